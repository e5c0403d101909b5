// One sample of next-event estimation's light: a uniform point on a light (a triangle or a
// parallelogram) and the shadow ray to it. Shared by nee.wgsl and the acne census
// (tests/fixtures), so the census checks exactly the rays the passes cast. The including
// shader includes scene, sampling and surface.

struct LightSample {
    // The shadow ray runs from the shading point's offset origin to `end` (t in (0, 1)).
    end: vec3<f32>,
    wi: vec3<f32>,
    d2: f32,
    cos_x: f32,
    cos_y: f32,
    area: f32,
}

// The point on `light` that the 2D sample u picks, uniformly by area.
fn sample_light(s: Surface, origin: vec3<f32>, light: Light, u: vec2<f32>) -> LightSample {
    let parallelogram = light.second != LIGHT_NO_TRIANGLE;
    // A parallelogram takes the square's points as they are.
    let ab = select(square_to_triangle(u), u, parallelogram);
    let q = light.p0 + ab.x * light.e1 + ab.y * light.e2;
    let c = cross(light.e1, light.e2);
    let twice = length(c);
    let area = select(0.5 * twice, twice, parallelogram);
    let nl = c / twice;
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
