// A wavefront level's first pass: the closest hit of every path queued for the level
// (lib/wavefront.wgsl), nothing else, so the traversal runs in lanes that all have a ray.
#include "lib/provided_scene.wgsl"
#include "lib/bvh.wgsl"
#include "lib/cutout_map.wgsl"
#include "lib/ray_count.wgsl"
#include "lib/wavefront.wgsl"
#include "lib/wavefront_trace.wgsl"

// A pass param: the level (0: the primary hit's bounce), its record's index in `levels_in`.
override level: u32 = 0u;

@group(0) @binding(0) var<storage, read_write> paths: array<WavefrontPath>;
@group(0) @binding(1) var<storage, read> queue_in: array<u32>;
@group(0) @binding(2) var<storage, read> levels_in: array<WavefrontLevel>;
@group(0) @binding(3) var<storage, read_write> ray_count: array<atomic<u32>, 2>;

@compute @workgroup_size(64)
fn main(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) local_index: u32,
) {
    let entry = wavefront_entry(group, groups, local_index);
    if entry < levels_in[level].count {
        let slot = queue_in[entry];
        var path = paths[slot];
        wavefront_trace(&path);
        paths[slot] = path;
    }
    count_rays(local_index);
}
