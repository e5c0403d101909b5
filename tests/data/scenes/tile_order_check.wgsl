// Test shader: which workgroup shades each pixel under shaders/lib/tile_order.wgsl, dispatched
// as an image pass is (8x8 workgroups over the frame). tests/tile_order.rs checks that every
// pixel is shaded once, by the workgroup src/render/tile_order.rs says.
#include "lib/scene.wgsl"
#include "lib/tile_order.wgsl"

struct Answer {
    // How many invocations shaded the pixel.
    count: atomic<u32>,
    // The linear index of the (last) workgroup that did.
    group: atomic<u32>,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read_write> answers: array<Answer>;

@compute @workgroup_size(8, 8)
fn main(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_id) local: vec3<u32>,
) {
    let id = scattered_pixel(group, groups, local, frame);
    if id.x >= frame.width || id.y >= frame.height {
        return;
    }
    let i = id.y * frame.width + id.x;
    atomicAdd(&answers[i].count, 1u);
    atomicStore(&answers[i].group, group.y * groups.x + group.x);
}
