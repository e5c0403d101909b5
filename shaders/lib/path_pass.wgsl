// What the two whole-sample passes (shaders/path.wgsl, shaders/path_reuse.wgsl) share: their
// params, their bindings (the same pass interface, so a graph swaps one for the other) and the
// write of the frame's channel means.

struct Params {
    ambient_color: vec3<f32>,
    radius: f32,
}

// A pass param: samples per pixel per frame.
override samples_per_frame: u32 = 1u;

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var l0: texture_storage_2d<rgba32float, write>;
@group(0) @binding(2) var direct: texture_storage_2d<rgba32float, write>;
@group(0) @binding(3) var indirect: texture_storage_2d<rgba32float, write>;
@group(0) @binding(4) var ambient: texture_storage_2d<rgba32float, write>;
@group(0) @binding(5) var<storage, read_write> ray_count: array<atomic<u32>, 2>;

// Writes the frame's channels: the sums of its samples_per_frame samples, as means.
fn store_channel_means(pixel: vec2<u32>, sum_l0: vec3<f32>, sum_direct: vec3<f32>, sum_indirect: vec3<f32>, sum_ambient: vec3<f32>) {
    let p = vec2<i32>(pixel);
    let scale = 1.0 / f32(samples_per_frame);
    textureStore(l0, p, vec4<f32>(sum_l0 * scale, 1.0));
    textureStore(direct, p, vec4<f32>(sum_direct * scale, 1.0));
    textureStore(indirect, p, vec4<f32>(sum_indirect * scale, 1.0));
    textureStore(ambient, p, vec4<f32>(sum_ambient * scale, 1.0));
}
