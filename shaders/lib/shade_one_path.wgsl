// The L0, direct and indirect channels of one sample with one light sample and one bounce per
// primary hit (light_samples = bounces = 1), tracing the primary hit's BSDF sample once: the
// direct channel's MIS half (shade_direct.wgsl's bsdf_light) and the indirect channel's first
// bounce (shade_indirect.wgsl's bounce_path) take the same sampler pairs, so the same
// direction, which shade_direct and shade_indirect trace once each. The same operations in
// the same order otherwise, so the same image bit for bit with one ray fewer per sample
// wherever the direct channel samples the BSDF (non-Lambertian lobes, an environment). The
// including shader includes what nee.wgsl needs, nee.wgsl and path_light.wgsl.

struct PathSample {
    l0: vec3<f32>,
    direct: vec3<f32>,
    indirect: vec3<f32>,
}

// What the primary hit p gives before its BSDF sample is traced: next-event estimation for the
// direct channel, the BSDF sample, its weight for the direct channel's MIS half (0 where that
// takes none) and for the indirect channel (Russian roulette's factor included; 0 where it
// has none), and whether the sample's ray is traced at all. The fused pass and the
// wavefront's camera pass both start a sample here.
struct PrimaryBounce {
    direct: vec3<f32>,
    bs: BsdfSample,
    direct_weight: vec3<f32>,
    weight: vec3<f32>,
    traced: bool,
}

fn primary_bounce(p: ShadingPoint, wo: vec3<f32>, source: SampleSource) -> PrimaryBounce {
    let none = vec3<f32>(0.0);
    var b = PrimaryBounce(none, BsdfSample(none, none, 0.0, false, 1.0), none, none, false);
    if scene_max_depth >= 2u {
        b.direct = direct_light(p, wo, source, DIM_DIRECT_SELECT, DIM_DIRECT_LIGHT);
    }
    let for_direct = scene_max_depth >= 2u && samples_bsdf_for_light(p);
    let for_indirect = scene_max_depth >= 3u && scene_light_count > 0u;
    if !for_direct && !for_indirect {
        return b;
    }
    b.bs = point_sample(p, wo, sample_2d(source, DIM_BOUNCE), sample_1d(source, DIM_BOUNCE_LOBE));
    if for_direct {
        b.direct_weight = b.bs.weight;
    }
    if for_indirect {
        b.weight = b.bs.weight * russian_roulette(1u, roulette_odds(b.bs.weight, b.bs), source);
    }
    b.traced = any(b.direct_weight != none) || any(b.weight != none);
    return b;
}

fn shade_one_path(ray: Primary, source: SampleSource) -> PathSample {
    let none = vec3<f32>(0.0);
    if ray.triangle == NO_HIT {
        return PathSample(environment_seen(ray.dir), none, none);
    }
    let p = shading_point(ray.triangle, ray.u, ray.v, ray.dir);
    let b = primary_bounce(p, -ray.dir, source);
    var direct = b.direct;
    if !b.traced {
        return PathSample(p.emitted, direct, none);
    }
    let hit = closest_hit(leaving(p.s, b.bs.wi), b.bs.wi, 0.0, 3.0e38);
    let for_direct = any(b.direct_weight != none);
    if hit.triangle == NO_HIT {
        if for_direct {
            direct += b.direct_weight * environment_weighted(p.s.p, p.s.n, b.bs);
        }
        return PathSample(p.emitted, direct, none);
    }
    let x = shading_point(hit.triangle, hit.u, hit.v, b.bs.wi);
    if for_direct {
        direct += b.direct_weight * emission_weighted(p.s.p, p.s.n, b.bs, x);
    }
    var indirect = none;
    if any(b.weight != none) {
        indirect = b.weight * path_light(x, b.bs.wi, source, roulette_odds(b.weight, b.bs));
    }
    return PathSample(p.emitted, direct, indirect);
}
