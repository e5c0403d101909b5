// Next-event estimation, shared by direct and indirect. The including shader declares
// `triangles`, `materials`, `lights` and `bvh`, and includes scene, rng, sampling, brdf, bvh,
// surface and light_sample.

// One uniform point on every emissive triangle and a shadow ray to it.
// Returns the sum over lights of f * Le * cos_x * cos_y / d^2 * area.
fn direct_light(s: Surface, wo: vec3<f32>, rng: ptr<function, u32>) -> vec3<f32> {
    let m = scene_material(materials, s.material);
    let origin = offset_ray(s.p, s.n);
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < scene_light_count; i++) {
        let l = sample_light(s, origin, i, rng);
        if l.cos_x <= 0.0 || l.cos_y <= 0.0 {
            continue;
        }
        if any_hit(origin, l.end - origin, 0.0, 1.0 - 1e-4) {
            continue;
        }
        let le = scene_material(materials, scene_triangle(triangles, scene_light(lights, i)).material).ke;
        sum += brdf(m, s.n, wo, l.wi) * le * (l.cos_x * l.cos_y / l.d2 * l.area);
    }
    return sum;
}
