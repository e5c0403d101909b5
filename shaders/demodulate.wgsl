// Demodulate: the denoiser's input, one plane of the accumulation (`plane`: 4 is the sum of
// L0, direct, indirect, ambient; see accumulate.wgsl) divided by the albedo guide. w carries
// the pixel's sample count, from which the à-trous passes scale their colour tolerance.
#include "lib/demodulation.wgsl"

struct Params {
    plane: u32,
}

@group(0) @binding(0) var<uniform> params: Params;
// Planes of width * height vec4: mean RGB and sample count.
@group(0) @binding(1) var<storage, read> result: array<vec4<f32>>;
@group(0) @binding(2) var albedo: texture_storage_2d<rgba32float, read>;
@group(0) @binding(3) var out: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(out);
    if any(id.xy >= size) {
        return;
    }
    let pixel = vec2<i32>(id.xy);
    let raw = result[params.plane * size.x * size.y + id.y * size.x + id.x];
    let a = demodulation_albedo(textureLoad(albedo, pixel).xyz);
    textureStore(out, pixel, vec4<f32>(raw.xyz / a, raw.w));
}
