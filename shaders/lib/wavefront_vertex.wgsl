// What a wavefront path does at the end of a segment (lib/wavefront.wgsl): path_light.wgsl's
// loop body, one vertex at a time, and the queue the paths that go on join. The including
// shader includes what path_light.wgsl needs, path_light.wgsl itself (Russian roulette) and
// wavefront.wgsl, and declares `levels_out` (array<WavefrontLevelCounter>) and `queue_out`
// (array<u32>), both read_write.

// Queues record `slot` for `level`, and grows the level's dispatch to cover it.
fn wavefront_queue(level: u32, slot: u32) {
    let entry = atomicAdd(&levels_out[level].count, 1u);
    queue_out[entry] = slot;
    if entry % 64u == 0u {
        let group = entry / 64u;
        atomicMax(&levels_out[level].x, min(group + 1u, WAVEFRONT_MAX_GROUPS));
        atomicMax(&levels_out[level].y, group / WAVEFRONT_MAX_GROUPS + 1u);
    }
}

// The ray leaving vertex p along the BSDF sample bs, as the path's segment `segment`.
fn wavefront_continue(path: ptr<function, WavefrontPath>, p: ShadingPoint, bs: BsdfSample, segment: u32) {
    (*path).origin = leaving(p.s, bs.wi);
    (*path).dir = bs.wi;
    (*path).pdf = bs.pdf;
    (*path).flags = select(0u, WAVEFRONT_DELTA, bs.delta) | (segment << WAVEFRONT_SEGMENT_SHIFT);
    (*path).from_p = p.s.p;
    (*path).from_n = p.s.n;
}

// Shades the end of the path's segment (its hit in the record): the emission or environment
// the segment meets, next-event estimation there and the BSDF sample that goes on. Returns
// whether the path goes on, its next ray then in the record.
fn wavefront_vertex(path: ptr<function, WavefrontPath>, source: SampleSource) -> bool {
    let segment = (*path).flags >> WAVEFRONT_SEGMENT_SHIFT;
    let bs = BsdfSample((*path).dir, vec3<f32>(0.0), (*path).pdf, ((*path).flags & WAVEFRONT_DELTA) != 0u, 1.0);
    let throughput = (*path).throughput;
    let direct_weight = (*path).direct_weight;
    // The first bounce's light is the direct channel's (emission met by the first bounce: L1);
    // past it, the indirect channel's.
    let met_weight = select(throughput, direct_weight, segment == 2u);
    if (*path).triangle == BVH_NO_HIT {
        if any(met_weight != vec3<f32>(0.0)) {
            let met = met_weight * environment_weighted((*path).from_p, (*path).from_n, bs);
            if segment == 2u {
                (*path).direct += met;
            } else {
                (*path).indirect += met;
            }
        }
        return false;
    }
    let x = shading_point((*path).triangle, (*path).hit_u, (*path).hit_v, bs.wi);
    if any(met_weight != vec3<f32>(0.0)) {
        let met = met_weight * emission_weighted((*path).from_p, (*path).from_n, bs, x);
        if segment == 2u {
            (*path).direct += met;
        } else {
            (*path).indirect += met;
        }
    }
    // Paths of segment + 1 segments: one ending with a light sample from x, one with the BSDF
    // sample, which also goes on.
    let depth = segment + 1u;
    if all(throughput == vec3<f32>(0.0)) || depth > scene_max_depth {
        return false;
    }
    let wo = -bs.wi;
    let dim_select = select(path_dim(depth, PATH_DIM_SELECT), DIM_BOUNCE_SELECT, segment == 2u);
    let dim_light = select(path_dim(depth, PATH_DIM_LIGHT), DIM_BOUNCE_LIGHT, segment == 2u);
    (*path).indirect += throughput * direct_light(x, wo, source, dim_select, dim_light);
    if depth == scene_max_depth && !samples_bsdf_for_light(x) {
        return false;
    }
    let u = sample_2d(source, path_dim(depth, PATH_DIM_BSDF));
    let next = point_sample(x, wo, u, sample_1d(source, path_dim(depth, PATH_DIM_LOBE)));
    if all(next.weight == vec3<f32>(0.0)) {
        return false;
    }
    var t = throughput * next.weight;
    let eta2 = (*path).eta2 * next.eta * next.eta;
    // The BSDF sample at x is the path's segment-th (the primary hit's was the first).
    t *= russian_roulette(segment, t * eta2, source);
    if all(t == vec3<f32>(0.0)) {
        return false;
    }
    (*path).throughput = t;
    (*path).eta2 = eta2;
    (*path).direct_weight = vec3<f32>(0.0);
    wavefront_continue(path, x, next, depth);
    return true;
}
