// The wavefront's last pass: each pixel's direct and indirect channels from its path record
// (lib/wavefront.wgsl), for accumulate.
#include "lib/provided_scene.wgsl"
#include "lib/wavefront.wgsl"

@group(0) @binding(0) var<storage, read> paths: array<WavefrontPath>;
@group(0) @binding(1) var direct: texture_storage_2d<rgba32float, write>;
@group(0) @binding(2) var indirect: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= frame.width || id.y >= frame.height {
        return;
    }
    let path = paths[wavefront_slot(id.xy)];
    textureStore(direct, vec2<i32>(id.xy), vec4<f32>(path.direct, 1.0));
    textureStore(indirect, vec2<i32>(id.xy), vec4<f32>(path.indirect, 1.0));
}
