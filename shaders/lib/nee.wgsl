// Next-event estimation, shared by direct and indirect. The including shader declares
// `triangles`, `materials`, `lights` and `bvh`, and includes scene, rng, sampling, brdf, bvh
// and surface.

// Next-event estimation: one uniform point on every emissive triangle and a shadow ray to it.
// Returns the sum over lights of f * Le * cos_x * cos_y / d^2 * area.
fn direct_light(s: Surface, wo: vec3<f32>, rng: ptr<function, u32>) -> vec3<f32> {
    let m = materials[s.material];
    let origin = offset_ray(s.p, s.n);
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < scene_light_count; i++) {
        let light = triangles[lights[i]];
        let u1 = rng_next(rng);
        let u2 = rng_next(rng);
        let q = sample_triangle(light.p0, light.p1, light.p2, u1, u2);
        let c = cross(light.p1 - light.p0, light.p2 - light.p0);
        let area = 0.5 * length(c);
        let nl = c / (2.0 * area);
        let to_light = q - origin;
        let d2 = dot(to_light, to_light);
        let wi = to_light * inverseSqrt(d2);
        let cos_x = dot(s.n, wi);
        // Emission leaves the front face only.
        let cos_y = -dot(nl, wi);
        if cos_x <= 0.0 || cos_y <= 0.0 {
            continue;
        }
        // The shadow ray ends just short of the sample point moved off the light, to its front
        // (the side this point is on), by offset_ray's few hundred ulps: q is rounded by a few
        // ulps of its coordinates, which far from the origin (1e5) can put it behind the
        // light's plane, and the light would occlude itself.
        let end = offset_ray(q, nl);
        if any_hit(origin, end - origin, 0.0, 1.0 - 1e-4) {
            continue;
        }
        let le = materials[light.material].ke;
        sum += brdf(m, s.n, wo, wi) * le * (cos_x * cos_y / d2 * area);
    }
    return sum;
}
