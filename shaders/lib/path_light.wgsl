// The paths that continue a bounce: at each vertex past the primary hit, next-event estimation
// and a BSDF sample that hits an emitter end paths one segment longer (weighted against each
// other by MIS, nee.wgsl), and the BSDF sample goes on while scene_max_depth allows. The
// including shader declares what nee.wgsl needs and includes it.

// Russian roulette after the k-th BSDF sample of a path, as Mitsuba's path integrator: from
// the scene_rr_depth-th on, the path goes on with probability q = min(max(odds), 0.95) and its
// throughput is divided by q, so the estimate stays unbiased. `odds`: the path's throughput
// times the squared relative index of its refractions so far (roulette_odds), as Mitsuba's:
// a refraction into glass divides radiance by eta^2, and without the factor back every path
// inside glass would be cut at 1 / eta^2 the rate (on scenes/materials at max_depth 8, 2x the
// variance instead of Mitsuba's 1.3x: docs/benchmark-history.md). The factor the throughput
// takes: 0 (the path ends) or 1 / q.
fn russian_roulette(k: u32, odds: vec3<f32>, source: SampleSource) -> f32 {
    if scene_rr_depth == 0xffffffffu || k < scene_rr_depth {
        return 1.0;
    }
    let q = min(max(odds.x, max(odds.y, odds.z)), 0.95);
    if sample_1d(source, path_dim(k + 1u, PATH_DIM_RR)) >= q {
        return 0.0;
    }
    return 1.0 / q;
}

// Russian roulette's odds for a throughput that took the BSDF sample bs last (of a path whose
// earlier refractions' factor is already in it).
fn roulette_odds(throughput: vec3<f32>, bs: BsdfSample) -> vec3<f32> {
    return throughput * (bs.eta * bs.eta);
}

// One bounce from the primary hit p in the direction the BSDF sample u picks, and the light
// of every path of 3 to scene_max_depth segments that continues it.
fn bounce_path(p: ShadingPoint, wo: vec3<f32>, source: SampleSource, u: vec2<f32>) -> vec3<f32> {
    let bs = point_sample(p, wo, u, sample_1d(source, DIM_BOUNCE_LOBE));
    if all(bs.weight == vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    let weight = bs.weight * russian_roulette(1u, roulette_odds(bs.weight, bs), source);
    if all(weight == vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    let hit = closest_hit(leaving(p.s, bs.wi), bs.wi, 0.0, 3.0e38);
    if hit.triangle == NO_HIT {
        return vec3<f32>(0.0);
    }
    let x = shading_point(hit.triangle, hit.u, hit.v, bs.wi);
    return weight * path_light(x, bs.wi, source, roulette_odds(weight, bs));
}

// The light leaving the first bounce's hit x back along -dir (x ends a path's second segment)
// by every path of 3 to scene_max_depth segments through it, emission at x itself excluded.
// `prefix`: Russian roulette's odds for the path up to x (its throughput times the squared
// relative index of its refractions: roulette_odds).
fn path_light(first: ShadingPoint, first_dir: vec3<f32>, source: SampleSource, prefix: vec3<f32>) -> vec3<f32> {
    // Paths of 3 segments that end with a light sample from the first bounce's hit: the seed's
    // whole indirect channel. Peeled off the loop below: with max_depth 3 and light sampling
    // alone (a Lambertian scene) nothing else is traced, and straight-line code is 4 % faster
    // on lavapipe than one pass through the loop (docs/benchmark-history.md).
    var sum = direct_light(first, -first_dir, source, DIM_BOUNCE_SELECT, DIM_BOUNCE_LIGHT);
    if scene_max_depth == 3u && !samples_bsdf_for_light(first) {
        return sum;
    }
    var x = first;
    var dir = first_dir;
    var throughput = vec3<f32>(1.0);
    // The squared relative index of the refractions past x.
    var eta2 = 1.0;
    for (var depth = 3u; depth <= scene_max_depth; depth++) {
        // Paths of `depth` segments end at a light seen from x: sampled on the light (done
        // above for depth 3)...
        let wo = -dir;
        if depth > 3u {
            sum += throughput * direct_light(x, wo, source, path_dim(depth, PATH_DIM_SELECT), path_dim(depth, PATH_DIM_LIGHT));
        }
        // ... or met by a BSDF sample, which also goes on to longer paths.
        if depth == scene_max_depth && !samples_bsdf_for_light(x) {
            break;
        }
        let u = sample_2d(source, path_dim(depth, PATH_DIM_BSDF));
        let next = point_sample(x, wo, u, sample_1d(source, path_dim(depth, PATH_DIM_LOBE)));
        if all(next.weight == vec3<f32>(0.0)) {
            break;
        }
        throughput *= next.weight;
        eta2 *= next.eta * next.eta;
        // The BSDF sample at x is the path's (depth - 1)-th.
        throughput *= russian_roulette(depth - 1u, prefix * throughput * eta2, source);
        if all(throughput == vec3<f32>(0.0)) {
            break;
        }
        let origin = leaving(x.s, next.wi);
        let hit = closest_hit(origin, next.wi, 0.0, 3.0e38);
        if hit.triangle == NO_HIT {
            // The path of `depth` segments ends in the environment.
            sum += throughput * environment_weighted(x.s.p, x.s.n, next);
            break;
        }
        let y = shading_point(hit.triangle, hit.u, hit.v, next.wi);
        sum += throughput * emission_weighted(x.s.p, x.s.n, next, y);
        x = y;
        dir = next.wi;
    }
    return sum;
}
