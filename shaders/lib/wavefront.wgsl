// The wavefront path tracer's path state (graphs/pathtracer-wavefront.ron): where a path stands
// between its passes, one record per pixel (one path per pixel per frame), and the queues of
// the paths still going. Each level of the graph traces one segment of every queued path
// (wavefront_extend.wgsl) and shades its end (wavefront_shade.wgsl), appending the paths that go
// on to the next level's queue, so every pass runs only live paths, side by side in SIMD lanes,
// where the fused pass (path.wgsl) keeps a lane idle once its own path has ended.
//
// The estimator is path.wgsl's with one bounce and one light sample per primary hit
// (shade_direct.wgsl, shade_indirect.wgsl, path_light.wgsl): the same samples, dimension for
// dimension, so the same expectation. One ray fewer: path.wgsl traces the primary hit's BSDF
// sample twice, once for the direct channel's MIS half and once as the indirect channel's first
// bounce (the same direction); here the one ray serves both.
//
// Queues: level L's paths are `count` record indices in a queue buffer, and the level's
// passes are dispatched indirectly over them: one invocation per queued path, 64 to a
// workgroup, so a level runs its live paths only and CPU threads or GPU cores share them
// evenly. Levels alternate between two queue buffers and two buffers of level records (the
// record a pass is dispatched from must not be written in the same dispatch).

// A level's record: the workgroups to dispatch (x, y, z) and the paths queued.
struct WavefrontLevel {
    x: u32,
    y: u32,
    z: u32,
    count: u32,
}

struct WavefrontLevelCounter {
    x: atomic<u32>,
    y: atomic<u32>,
    z: atomic<u32>,
    count: atomic<u32>,
}

// WebGPU's least maximum of workgroups per dimension: a queue of more paths spills into y.
const WAVEFRONT_MAX_GROUPS: u32 = 65535u;

struct WavefrontPath {
    // The ray to trace next (origin, direction), the density of the sample that chose the
    // direction and whether it was delta (for MIS where the ray ends).
    origin: vec3<f32>,
    pdf: f32,
    dir: vec3<f32>,
    // WAVEFRONT_* bits, and the segment the ray is (2: the primary hit's bounce) above them.
    flags: u32,
    // The indirect channel's path throughput up to the ray (Russian roulette's factors
    // included); 0 for a ray traced only for the direct channel.
    throughput: vec3<f32>,
    // The hit of the ray: its triangle (BVH_NO_HIT on a miss), written by the extend pass.
    triangle: u32,
    // The direct channel's weight for the emission the primary hit's BSDF sample meets (its
    // MIS half, shade_direct.wgsl's bsdf_light); 0 past the first bounce.
    direct_weight: vec3<f32>,
    hit_t: f32,
    // The vertex the ray left: its point and geometric normal (light sampling's density there).
    from_p: vec3<f32>,
    hit_u: f32,
    from_n: vec3<f32>,
    hit_v: f32,
    // The channels' sums so far: direct (next-event estimation at the primary hit, then the
    // BSDF half) and indirect.
    direct: vec3<f32>,
    // The squared relative index of the path's refractions so far (Russian roulette's odds:
    // path_light.wgsl).
    eta2: f32,
    indirect: vec3<f32>,
}

const WAVEFRONT_DELTA: u32 = 1u;
const WAVEFRONT_SEGMENT_SHIFT: u32 = 8u;

// The record of this frame's pixel (tile-local).
fn wavefront_slot(pixel: vec2<u32>) -> u32 {
    return pixel.y * frame.width + pixel.x;
}

fn wavefront_pixel(slot: u32) -> vec2<u32> {
    return vec2<u32>(slot % frame.width, slot / frame.width);
}

// The queue entry of an invocation of a level's indirect dispatch (workgroups of 64).
fn wavefront_entry(group: vec3<u32>, groups: vec3<u32>, local_index: u32) -> u32 {
    return (group.y * groups.x + group.x) * 64u + local_index;
}
