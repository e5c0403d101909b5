// The L0 and direct (L1) channels of one sample: emission seen at the primary hit (front
// faces only) and next-event estimation there. The including shader declares what nee.wgsl
// needs and includes it and primary.wgsl.

struct DirectSample {
    l0: vec3<f32>,
    direct: vec3<f32>,
}

fn shade_direct(ray: Primary, source: SampleSource) -> DirectSample {
    if ray.triangle == NO_HIT {
        return DirectSample(vec3<f32>(0.0), vec3<f32>(0.0));
    }
    let s = surface_at(scene_triangle(triangles, ray.triangle), ray.u, ray.v, ray.dir);
    let emitted = select(vec3<f32>(0.0), scene_material(materials, s.material).ke, s.front);
    return DirectSample(emitted, direct_light(s, -ray.dir, source, DIM_DIRECT_SELECT, DIM_DIRECT_LIGHT));
}
