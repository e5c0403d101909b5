// What shading needs at a ray's hit: the surface (geometric side and offsets), the shading
// normal, the BSDF with textures applied, the emitted radiance toward the ray and the light the
// triangle belongs to. The including shader declares `triangles`, `materials`, `shading` and
// `textures` (scene.shading, scene.textures) and includes scene, surface, shading, texture
// and bsdf.

struct ShadingPoint {
    s: Surface,
    // The shading normal (interpolated vertex normals, or the geometric one), on the ray's side.
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
    let ns = shading_normal(shading, triangle, u, v, s.n);
    var m = scene_material(materials, s.material);
    if scene_has_textures {
        m = material_at(m, textures, shading_uv(shading, triangle, u, v));
    }
    return ShadingPoint(s, ns, bsdf_from_material(m), select(vec3<f32>(0.0), m.ke, s.front), t.light);
}

// The origin of a ray leaving s toward wi: moved off the surface to wi's side (transmitted
// rays leave from the other side).
fn leaving(s: Surface, wi: vec3<f32>) -> vec3<f32> {
    return offset_ray(s.p, select(-s.n, s.n, dot(s.n, wi) >= 0.0));
}
