// Cut-outs from map_d textures, for lib/bvh.wgsl's bvh_stops: the opacity of texture `map`
// at triangle k's texture coordinates for barycentrics (u, v), the luminance of the raw
// (linear) image, as Mitsuba's mask reads its opacity bitmap.
//
// The includer includes lib/scene.wgsl first and binds scene.shading and scene.textures as
// `shading` and `textures` (texture_storage_2d<rgba32uint, read>), as lib/shading.wgsl and
// lib/texture.wgsl ask.
#include "shading.wgsl"
#include "texture.wgsl"

fn cutout_map_opacity(map: u32, k: u32, u: f32, v: f32) -> f32 {
    let uv = shading_uv(shading, k, u, v);
    return dot(texture_bilinear(textures, map, uv).rgb, TEXTURE_LUMINANCE);
}
