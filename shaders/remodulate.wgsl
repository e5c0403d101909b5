// Remodulate: the filtered (demodulated) image times the albedo guide, blended with the raw
// accumulation by a weight that falls linearly from 1 at the first frame to 0 at `fade_frames`
// samples (0: never fade). The filter's bias does not shrink as frames accumulate while the
// noise does, so past some frame count the raw image is the better estimate; from
// `fade_frames` on the output is exactly the raw plane.
#include "lib/demodulation.wgsl"

struct Params {
    // The accumulation plane demodulate read (keep the two equal).
    plane: u32,
    fade_frames: u32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> result: array<vec4<f32>>;
@group(0) @binding(2) var filtered: texture_storage_2d<rgba32float, read>;
@group(0) @binding(3) var albedo: texture_storage_2d<rgba32float, read>;
@group(0) @binding(4) var out: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(out);
    if any(id.xy >= size) {
        return;
    }
    let pixel = vec2<i32>(id.xy);
    let raw = result[params.plane * size.x * size.y + id.y * size.x + id.x];
    let a = demodulation_albedo(textureLoad(albedo, pixel).xyz);
    let denoised = textureLoad(filtered, pixel).xyz * a;
    var weight = 1.0;
    if params.fade_frames > 0u {
        weight = clamp(1.0 - raw.w / f32(params.fade_frames), 0.0, 1.0);
    }
    // select, not mix: past the fade the output is the raw value bit for bit.
    let rgb = select(mix(raw.xyz, denoised, weight), raw.xyz, weight <= 0.0);
    textureStore(out, pixel, vec4<f32>(rgb, raw.w));
}
