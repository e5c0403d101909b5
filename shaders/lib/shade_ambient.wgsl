// The ambient channel of one sample: one cosine-weighted ray from the primary hit; unoccluded
// within `radius`, the point receives kd * color. The including shader declares `triangles`,
// `materials`, `bvh` and `frame` and includes scene, rng, sampler, sampling, bvh, primary and
// surface.

fn shade_ambient(ray: Primary, source: SampleSource, color: vec3<f32>, radius: f32) -> vec3<f32> {
    // A black ambient colour (the physical default) casts no ray.
    if ray.triangle == NO_HIT || all(color == vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    let s = surface_at(scene_triangle(triangles, ray.triangle), ray.u, ray.v, ray.dir);
    let u = sample_2d(source, DIM_AMBIENT);
    let d = sample_cosine(s.n, u.x, u.y);
    if any_hit(ray_origin(s, s.n), d, 0.0, radius) {
        return vec3<f32>(0.0);
    }
    return scene_face_material(materials, s.material, s.front).kd * color;
}
