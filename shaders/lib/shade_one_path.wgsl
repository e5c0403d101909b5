// The L0, direct and indirect channels of one sample with one light sample and one bounce per
// primary hit (light_samples = bounces = 1), tracing the primary hit's BSDF sample once: the
// direct channel's MIS half (shade_direct.wgsl's bsdf_light) and the indirect channel's first
// bounce (shade_indirect.wgsl's bounce_path) take the same sampler pairs, so the same
// direction, which shade_direct and shade_indirect trace once each. The same operations in
// the same order otherwise, so the same image bit for bit with one ray fewer per sample
// wherever the direct channel samples the BSDF (non-Lambertian lobes, an environment). The
// including shader includes shade_direct.wgsl and path_light.wgsl.

struct PathSample {
    l0: vec3<f32>,
    direct: vec3<f32>,
    indirect: vec3<f32>,
}

fn shade_one_path(ray: Primary, source: SampleSource) -> PathSample {
    let none = vec3<f32>(0.0);
    if ray.triangle == NO_HIT {
        return PathSample(environment_seen(ray.dir), none, none);
    }
    let p = shading_point(ray.triangle, ray.u, ray.v, ray.dir);
    let wo = -ray.dir;
    var direct = none;
    if scene_max_depth >= 2u {
        direct = direct_light(p, wo, source, DIM_DIRECT_SELECT, DIM_DIRECT_LIGHT);
    }
    let for_direct = scene_max_depth >= 2u && samples_bsdf_for_light(p);
    let for_indirect = scene_max_depth >= 3u && scene_light_count > 0u;
    if !for_direct && !for_indirect {
        return PathSample(p.emitted, direct, none);
    }
    let bs = point_sample(p, wo, sample_2d(source, DIM_BOUNCE), sample_1d(source, DIM_BOUNCE_LOBE));
    var weight = none;
    if for_indirect {
        weight = bs.weight * russian_roulette(1u, bs.weight, source);
    }
    if all(bs.weight == none) || (!for_direct && all(weight == none)) {
        return PathSample(p.emitted, direct, none);
    }
    let origin = leaving(p.s, bs.wi);
    let hit = closest_hit(origin, bs.wi, 0.0, 3.0e38);
    if hit.triangle == NO_HIT {
        if for_direct {
            direct += bs.weight * environment_weighted(p.s.p, p.s.n, bs);
        }
        return PathSample(p.emitted, direct, none);
    }
    let x = shading_point(hit.triangle, hit.u, hit.v, bs.wi);
    if for_direct {
        direct += bs.weight * emission_weighted(p.s.p, p.s.n, bs, x);
    }
    var indirect = none;
    if any(weight != none) {
        indirect = weight * path_light(x, bs.wi, source, weight);
    }
    return PathSample(p.emitted, direct, indirect);
}
