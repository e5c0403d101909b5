// The L0 and direct (L1) channels of one sample: emission seen at the primary hit (front
// faces only) and next-event estimation there. The including shader declares what nee.wgsl
// needs and includes it and primary.wgsl.

// A pass param: next-event estimates per sample at the primary hit, averaged (splitting, as
// `bounces` for the indirect channel; sampler.wgsl's sample_split), so one sample's points on a
// light are consecutive points of one stratified sequence: a penumbra is integrated by a small net of
// shadow rays rather than one, for one more shadow ray each.
override light_samples: u32 = 1u;

struct DirectSample {
    l0: vec3<f32>,
    direct: vec3<f32>,
}

fn shade_direct(ray: Primary, source: SampleSource) -> DirectSample {
    if ray.triangle == NO_HIT {
        return DirectSample(vec3<f32>(0.0), vec3<f32>(0.0));
    }
    let s = surface_at(scene_triangle(triangles, ray.triangle), ray.u, ray.v, ray.dir);
    let emitted = select(vec3<f32>(0.0), scene_material_ke(materials, s.material), s.front);
    var sum = vec3<f32>(0.0);
    for (var j = 0u; j < light_samples; j++) {
        let light = sample_split(source, light_samples, j);
        sum += direct_light(s, -ray.dir, light, DIM_DIRECT_SELECT, DIM_DIRECT_LIGHT);
    }
    return DirectSample(emitted, sum / f32(light_samples));
}
