// Next-event estimation, shared by direct and indirect. The including shader declares
// `triangles`, `materials`, `lights`, `light_power` and `bvh`, and includes scene, rng,
// sampling, brdf, bvh, surface, light_sample and light_select.

// A pass param: one light per shading point, chosen by light_select.wgsl, instead of all.
override light_selection: bool = false;

// Light reaching s from the emitters, toward wo.
fn direct_light(s: Surface, wo: vec3<f32>, rng: ptr<function, u32>) -> vec3<f32> {
    if light_selection {
        return selected_light(s, wo, rng);
    }
    return all_lights(s, wo, rng);
}

// f * Le * cos_x * cos_y / d^2 * area for one uniform point on light i, 0 if occluded.
fn light_contribution(s: Surface, m: Material, wo: vec3<f32>, origin: vec3<f32>, i: u32, rng: ptr<function, u32>) -> vec3<f32> {
    let l = sample_light(s, origin, i, rng);
    if l.cos_x <= 0.0 || l.cos_y <= 0.0 {
        return vec3<f32>(0.0);
    }
    if any_hit(origin, l.end - origin, 0.0, 1.0 - 1e-4) {
        return vec3<f32>(0.0);
    }
    let le = scene_material(materials, scene_triangle(triangles, scene_light(lights, i)).material).ke;
    return brdf(m, s.n, wo, l.wi) * le * (l.cos_x * l.cos_y / l.d2 * l.area);
}

// One light, drawn with probability pmf, and its contribution divided by pmf.
fn selected_light(s: Surface, wo: vec3<f32>, rng: ptr<function, u32>) -> vec3<f32> {
    let origin = offset_ray(s.p, s.n);
    let choice = select_light(origin, s.n, rng);
    if choice.index == LIGHT_NONE {
        return vec3<f32>(0.0);
    }
    let m = scene_material(materials, s.material);
    return light_contribution(s, m, wo, origin, choice.index, rng) / choice.pmf;
}

// One uniform point on every emissive triangle and a shadow ray to each.
fn all_lights(s: Surface, wo: vec3<f32>, rng: ptr<function, u32>) -> vec3<f32> {
    let m = scene_material(materials, s.material);
    let origin = offset_ray(s.p, s.n);
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < scene_light_count; i++) {
        sum += light_contribution(s, m, wo, origin, i, rng);
    }
    return sum;
}
