// The indirect channel of one sample: every path of 3 to scene_max_depth segments, from
// `bounces` BSDF-sampled bounces at the primary hit (path_light.wgsl follows each). Emission
// met by the first bounce is not added: L1 counts it. The including shader declares what
// nee.wgsl needs and includes it, primary.wgsl and path_light.wgsl.

// A pass param: bounces per sample from the one primary hit, averaged (splitting). Where the
// indirect light is the image's noise, more of them cost less than more whole samples: the
// primary ray and its direct light are shared. Bounce j of sample i takes sample index
// i * bounces + j of its sampler pairs, so one sample's bounces are consecutive points of one
// stratified sequence.
override bounces: u32 = 1u;

// A pass param: trace each batch of a sample's bounces in the order of their azimuth around the
// normal rather than in index order. The same bounces, summed in another order (so the same
// image up to f32 rounding), but neighbouring pixels, which run side by side in SIMD lanes, then
// trace rays into the same wedge of directions at the same time: a lane waits less for its
// slowest neighbour, and nearby rays visit the same nodes. With 8 bounces per sample it takes
// 0.83x the CPU time on the Cornell box, 0.79x on the bunny (docs/benchmark-history.md).
override coherent_bounces: bool = true;

// Bounces ordered together. Each aligned batch of 2^k consecutive Sobol points is a (0,k,2)-net,
// so its points fall one in each 1/2^k slab of azimuth: after ordering, bounce j of every lane
// lies in slab j. Eight keeps the two small private arrays cheap.
const BOUNCE_BATCH: u32 = 8u;

fn shade_indirect(ray: Primary, source: SampleSource) -> vec3<f32> {
    // Without lights there is nothing to find past the first bounce: no bounce ray at all.
    if ray.triangle == NO_HIT || scene_light_count == 0u || scene_max_depth < 3u {
        return vec3<f32>(0.0);
    }
    let p = shading_point(ray.triangle, ray.u, ray.v, ray.dir);
    var sum = vec3<f32>(0.0);
    for (var first = 0u; first < bounces; first += BOUNCE_BATCH) {
        let n = min(BOUNCE_BATCH, bounces - first);
        // The batch's samples, and the order to trace them in (order[j]: the j-th to trace).
        var u: array<vec2<f32>, BOUNCE_BATCH>;
        var order: array<u32, BOUNCE_BATCH>;
        for (var t = 0u; t < n; t++) {
            u[t] = sample_2d(sample_split(source, bounces, first + t), DIM_BOUNCE);
            order[t] = t;
        }
        if coherent_bounces {
            // Rank by azimuth (the cosine lobe's angle is 2 pi u.y), ties by index.
            for (var t = 0u; t < n; t++) {
                var rank = 0u;
                for (var r = 0u; r < n; r++) {
                    rank += select(0u, 1u, u[r].y < u[t].y || (u[r].y == u[t].y && r < t));
                }
                order[rank] = t;
            }
        }
        for (var j = 0u; j < n; j++) {
            let t = order[j];
            sum += bounce_path(p, -ray.dir, sample_split(source, bounces, first + t), u[t]);
        }
    }
    return sum / f32(bounces);
}
