// Next-event estimation, shared by direct and indirect. The including shader declares
// `triangles`, `materials`, `lights`, `light_power`, `bvh` and `frame`, and includes scene, rng,
// sampler, sampling, brdf, bvh, surface, light_sample and light_select.

// A pass param: one light per shading point, chosen by light_select.wgsl, instead of all.
override light_selection: bool = false;

// Light reaching s from the emitters, toward wo. `dim_select` and `dim_light` are the sampler
// pairs (sampler.wgsl) of the light choice and of the point on the light.
fn direct_light(s: Surface, wo: vec3<f32>, source: SampleSource, dim_select: u32, dim_light: u32) -> vec3<f32> {
    if light_selection {
        return selected_light(s, wo, source, dim_select, dim_light);
    }
    return all_lights(s, wo, source, dim_light);
}

// f * Le * (cos_x * cos_y / d^2 * area, or cos_x * S) for the point u picks on light i
// (light_sample.wgsl), 0 if occluded.
fn light_contribution(s: Surface, m: Material, wo: vec3<f32>, origin: vec3<f32>, i: u32, u: vec2<f32>) -> vec3<f32> {
    let light = scene_light(lights, i);
    let l = sample_light(s, origin, light, u);
    if l.cos_x <= 0.0 || l.cos_y <= 0.0 {
        return vec3<f32>(0.0);
    }
    if shadow_hit(origin, l.end - origin, 0.0, 1.0 - 1e-4) {
        return vec3<f32>(0.0);
    }
    let le = scene_material_ke(materials, light.material);
    return brdf(m, s.n, wo, l.wi) * le * l.geometry;
}

// One light, drawn with probability pmf, and its contribution divided by pmf.
fn selected_light(s: Surface, wo: vec3<f32>, source: SampleSource, dim_select: u32, dim_light: u32) -> vec3<f32> {
    let origin = offset_ray(s.p, s.n);
    let choice = select_light(origin, s.n, sample_1d(source, dim_select));
    if choice.index == LIGHT_NONE {
        return vec3<f32>(0.0);
    }
    let m = scene_material(materials, s.material);
    return light_contribution(s, m, wo, origin, choice.index, sample_2d(source, dim_light)) / choice.pmf;
}

// One point on every light and a shadow ray to each; light i takes its point from
// its own sampler pair.
fn all_lights(s: Surface, wo: vec3<f32>, source: SampleSource, dim_light: u32) -> vec3<f32> {
    let m = scene_material(materials, s.material);
    let origin = offset_ray(s.p, s.n);
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < scene_light_count; i++) {
        let u = sample_2d(source, dim_light + SAMPLER_LIGHT_STRIDE * i);
        sum += light_contribution(s, m, wo, origin, i, u);
    }
    return sum;
}
