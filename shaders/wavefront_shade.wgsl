// A wavefront level's second pass: shades the end of every path queued for the level
// (lib/wavefront_vertex.wgsl) and queues those that go on for the next level. With `finish`
// (the graph's last level), it traces and shades them on to their end instead, so a graph of
// any number of levels renders paths of any scene_max_depth whole.
#include "lib/provided_scene.wgsl"
#include "lib/rng.wgsl"
#include "lib/sampler.wgsl"
#include "lib/sampling.wgsl"
#include "lib/bsdf.wgsl"
#include "lib/mis.wgsl"
#include "lib/bvh.wgsl"
#include "lib/cutout_map.wgsl"
#include "lib/ray_count.wgsl"
#include "lib/primary.wgsl"
#include "lib/surface.wgsl"
#include "lib/shading.wgsl"
#include "lib/texture.wgsl"
#include "lib/shading_point.wgsl"
#include "lib/light_sample.wgsl"
#include "lib/light_select.wgsl"
#include "lib/nee.wgsl"
#include "lib/path_light.wgsl"
#include "lib/wavefront.wgsl"
#include "lib/wavefront_trace.wgsl"
#include "lib/wavefront_vertex.wgsl"

// Pass params: the level (its record is levels_in[level], the next level's
// levels_out[level + 1]); whether it is the graph's last; whether it traces its paths' rays
// itself (no extend pass before it: one dispatch per level instead of two).
override level: u32 = 0u;
override finish: bool = false;
override trace: bool = false;

@group(0) @binding(0) var<storage, read_write> paths: array<WavefrontPath>;
@group(0) @binding(1) var<storage, read> queue_in: array<u32>;
@group(0) @binding(2) var<storage, read_write> queue_out: array<u32>;
@group(0) @binding(3) var<storage, read> levels_in: array<WavefrontLevel>;
@group(0) @binding(5) var<storage, read_write> levels_out: array<WavefrontLevelCounter>;
@group(0) @binding(4) var<storage, read_write> ray_count: array<atomic<u32>, 2>;

fn shade(entry: u32) {
    if entry >= levels_in[level].count {
        return;
    }
    let slot = queue_in[entry];
    let source = sample_source(wavefront_pixel(slot), 1u, 0u);
    var path = paths[slot];
    if trace {
        wavefront_trace(&path);
    }
    var goes_on = wavefront_vertex(&path, source);
    if finish {
        while goes_on {
            wavefront_trace(&path);
            goes_on = wavefront_vertex(&path, source);
        }
    }
    paths[slot] = path;
    if goes_on {
        wavefront_queue(level + 1u, slot);
    }
}

@compute @workgroup_size(64)
fn main(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) local_index: u32,
) {
    shade(wavefront_entry(group, groups, local_index));
    count_rays(local_index);
}
