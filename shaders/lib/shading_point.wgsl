// What shading needs at a ray's hit: the surface (geometric side and offsets), the shading
// normal, the BSDF with textures applied, the emitted radiance toward the ray and the light the
// triangle belongs to. The including shader declares `triangles` and `materials` and includes
// scene, surface and bsdf.

struct ShadingPoint {
    s: Surface,
    // The shading normal on the ray's side (the geometric one until vertex normals exist).
    ns: vec3<f32>,
    b: Bsdf,
    // Ke on the front face, 0 on the back (emission is one-sided).
    emitted: vec3<f32>,
    // The light the triangle is part of, or NO_LIGHT.
    light: u32,
}

// The hit at barycentrics (u, v) of `triangle` by a ray along dir.
fn shading_point(triangle: u32, u: f32, v: f32, dir: vec3<f32>) -> ShadingPoint {
    let t = scene_triangle(triangles, triangle);
    let s = surface_at(t, u, v, dir);
    let m = scene_material(materials, s.material);
    return ShadingPoint(s, s.n, bsdf_from_material(m), select(vec3<f32>(0.0), m.ke, s.front), t.light);
}

// The origin of a ray leaving s toward wi: moved off the surface to wi's side (transmitted
// rays leave from the other side).
fn leaving(s: Surface, wi: vec3<f32>) -> vec3<f32> {
    return offset_ray(s.p, select(-s.n, s.n, dot(s.n, wi) >= 0.0));
}
