// The indirect channel of one sample: cosine-weighted bounces from the primary hit, then
// next-event estimation at each bounce's hit with that point's BRDF. Emission met by a bounce
// is not added: L1 counts it. The including shader declares what nee.wgsl needs and includes
// it and primary.wgsl.

// A pass param: bounces per sample from the one primary hit, averaged (splitting). Where the
// indirect light is the image's noise, more of them cost less than more whole samples: the
// primary ray and its direct light are shared. Bounce j of sample i takes sample index
// i * bounces + j of its sampler pairs, so one sample's bounces are consecutive points of one
// stratified sequence.
override bounces: u32 = 1u;

fn shade_indirect(ray: Primary, source: SampleSource) -> vec3<f32> {
    // Without lights there is nothing to find at the second hit: no bounce ray at all.
    if ray.triangle == NO_HIT || scene_light_count == 0u {
        return vec3<f32>(0.0);
    }
    let s = surface_at(scene_triangle(triangles, ray.triangle), ray.u, ray.v, ray.dir);
    let m = scene_material(materials, s.material);
    var sum = vec3<f32>(0.0);
    for (var j = 0u; j < bounces; j++) {
        let bounce = SampleSource(source.pixel, source.index * bounces + j, source.seed);
        let u = sample_2d(bounce, DIM_BOUNCE);
        let d = sample_cosine(s.n, u.x, u.y);
        let second = closest_hit(offset_ray(s.p, s.n), d, 0.0, 3.0e38);
        if second.triangle != NO_HIT {
            let s2 = surface_at(scene_triangle(triangles, second.triangle), second.u, second.v, d);
            // f * cos / pdf with pdf = cos / pi.
            let weight = brdf(m, s.n, -ray.dir, d) * PI;
            sum += weight * direct_light(s2, -d, bounce, DIM_BOUNCE_SELECT, DIM_BOUNCE_LIGHT);
        }
    }
    return sum / f32(bounces);
}
