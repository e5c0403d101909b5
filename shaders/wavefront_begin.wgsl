// The wavefront's queues start each frame empty (lib/wavefront.wgsl): no paths and no
// workgroups at every level of both record buffers.
#include "lib/provided_scene.wgsl"
#include "lib/wavefront.wgsl"

@group(0) @binding(0) var<storage, read_write> levels_0: array<WavefrontLevel>;
@group(0) @binding(1) var<storage, read_write> levels_1: array<WavefrontLevel>;

@compute @workgroup_size(64)
fn main(@builtin(local_invocation_index) i: u32) {
    let empty = WavefrontLevel(0u, 0u, 1u, 0u);
    for (var k = i; k < arrayLength(&levels_0); k += 64u) {
        levels_0[k] = empty;
    }
    for (var k = i; k < arrayLength(&levels_1); k += 64u) {
        levels_1[k] = empty;
    }
}
