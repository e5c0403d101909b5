// The L0 and direct (L1) channels of one sample: emission seen at the primary hit (front
// faces only), and light reaching the primary hit straight from an emitter: next-event
// estimation there and, where the scene has non-Lambertian lobes or the surface is a mirror or
// glass, BSDF-sampled rays that hit an emitter, the two weighted by MIS (mis.wgsl). The
// including shader declares what nee.wgsl needs and includes it and primary.wgsl.

// A pass param: next-event estimates (and BSDF samples) per sample at the primary hit,
// averaged (splitting, as `bounces` for the indirect channel; sampler.wgsl's sample_split), so
// one sample's points on a light are consecutive points of one stratified sequence: a penumbra
// is integrated by a small net of shadow rays rather than one, for one more shadow ray each.
override light_samples: u32 = 1u;

struct DirectSample {
    l0: vec3<f32>,
    direct: vec3<f32>,
}

fn shade_direct(ray: Primary, source: SampleSource) -> DirectSample {
    if ray.triangle == NO_HIT {
        // A camera ray that leaves the scene sees the environment (L0), as in Mitsuba.
        return DirectSample(environment_seen(ray.dir), vec3<f32>(0.0));
    }
    let p = shading_point(ray.triangle, ray.u, ray.v, ray.dir);
    let wo = -ray.dir;
    var sum = vec3<f32>(0.0);
    if scene_max_depth >= 2u {
        for (var j = 0u; j < light_samples; j++) {
            let split = sample_split(source, light_samples, j);
            sum += direct_light(p, wo, split, DIM_DIRECT_SELECT, DIM_DIRECT_LIGHT);
            if samples_bsdf_for_light(p) {
                sum += bsdf_light(p, wo, split);
            }
        }
    }
    return DirectSample(p.emitted, sum / f32(light_samples));
}

// A BSDF sample from the primary hit p: the emission it meets, weighted. It takes the first
// bounce's sampler pairs (DIM_BOUNCE, DIM_BOUNCE_LOBE), so with as many light samples as
// bounces it is the indirect channel's first bounce, traced again: the direct and indirect
// channels then continue one path, as a path tracer's do. Two independent directions would
// each be unbiased, but they lose the anti-correlation of one path: where a glossy lobe sees
// an emitter in one part and a surface reflecting it in the other (a sphere over a glossy
// floor under the sky), one direction sees one or the other and the sum is nearly constant,
// two see both or neither; that doubled the variance there up to 80 times Mitsuba's
// (tests/data/conformance/README.md, roughconductor_beckmann).
fn bsdf_light(p: ShadingPoint, wo: vec3<f32>, source: SampleSource) -> vec3<f32> {
    let bs = point_sample(p, wo, sample_2d(source, DIM_BOUNCE), sample_1d(source, DIM_BOUNCE_LOBE));
    if all(bs.weight == vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    let origin = leaving(p.s, bs.wi);
    let hit = closest_hit(origin, bs.wi, 0.0, 3.0e38);
    if hit.triangle == NO_HIT {
        return bs.weight * environment_weighted(p.s.p, p.s.n, bs);
    }
    let q = shading_point(hit.triangle, hit.u, hit.v, bs.wi);
    return bs.weight * emission_weighted(p.s.p, p.s.n, bs, q);
}
