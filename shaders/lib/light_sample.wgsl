// One sample of next-event estimation's light: a uniform point on an emissive triangle and the
// shadow ray to it. Shared by nee.wgsl and the acne census (tests/fixtures), so the census
// checks exactly the rays the passes cast. The including shader declares `triangles` and
// `lights`, and includes scene, rng, sampling and surface.

struct LightSample {
    // The shadow ray runs from the shading point's offset origin to `end` (t in (0, 1)).
    end: vec3<f32>,
    wi: vec3<f32>,
    d2: f32,
    cos_x: f32,
    cos_y: f32,
    area: f32,
}

// Draws two random numbers whatever the outcome, so streams stay aligned across passes.
fn sample_light(s: Surface, origin: vec3<f32>, i: u32, rng: ptr<function, u32>) -> LightSample {
    let light = scene_triangle(triangles, scene_light(lights, i));
    let u1 = rng_next(rng);
    let u2 = rng_next(rng);
    let q = sample_triangle(light.p0, light.p1, light.p2, u1, u2);
    let c = cross(light.p1 - light.p0, light.p2 - light.p0);
    let area = 0.5 * length(c);
    let nl = c / (2.0 * area);
    let to_light = q - origin;
    let d2 = dot(to_light, to_light);
    let wi = to_light * inverseSqrt(d2);
    // The shadow ray ends just short of the sample point moved off the light, to its front
    // (the side this point is on), by offset_ray's few hundred ulps: q is rounded by a few ulps
    // of its coordinates, which far from the origin (1e5) can put it behind the light's plane,
    // and the light would occlude itself.
    let end = offset_ray(q, nl);
    // Emission leaves the front face only: cos_y is taken against the front normal.
    return LightSample(end, wi, d2, dot(s.n, wi), -dot(nl, wi), area);
}
