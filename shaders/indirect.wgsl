// Indirect: one cosine-weighted bounce from the primary hit, then next-event estimation at the
// second hit (lib/shade_indirect.wgsl).
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
#include "lib/ray_texture.wgsl"
#include "lib/surface.wgsl"
#include "lib/shading.wgsl"
#include "lib/texture.wgsl"
#include "lib/shading_point.wgsl"
#include "lib/light_sample.wgsl"
#include "lib/light_select.wgsl"
#include "lib/nee.wgsl"
#include "lib/path_light.wgsl"
#include "lib/shade_indirect.wgsl"

@group(0) @binding(0) var rays: texture_storage_2d_array<rgba32float, read>;
@group(0) @binding(1) var out: texture_storage_2d<rgba32float, write>;
@group(0) @binding(2) var<storage, read_write> ray_count: array<atomic<u32>, 2>;

fn shade(id: vec3<u32>) {
    let pixel = vec2<i32>(id.xy);
    if any(id.xy >= textureDimensions(out)) {
        return;
    }
    let value = shade_indirect(load_primary(pixel), sample_source(id.xy, 1u, 0u));
    textureStore(out, pixel, vec4<f32>(value, 1.0));
}

@compute @workgroup_size(8, 8)
fn main(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(local_invocation_index) local_index: u32,
) {
    shade(id);
    count_rays(local_index);
}
