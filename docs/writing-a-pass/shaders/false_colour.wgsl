// False colour: the luminance of one plane of the path tracer's accumulation on a log scale,
// from blue (10^lo and darker) through cyan, green and yellow to red (10^hi and brighter).

struct Params {
    plane: u32,
    lo: f32,
    hi: f32,
}

@group(0) @binding(0) var<uniform> params: Params;
// Planes of width * height vec4 (mean RGB, sample count): L0, direct, indirect, ambient, sum.
@group(0) @binding(1) var<storage, read> result: array<vec4<f32>>;
@group(0) @binding(2) var out: texture_storage_2d<rgba32float, write>;

fn ramp(t: f32) -> vec3<f32> {
    let stops = array<vec3<f32>, 5>(
        vec3<f32>(0.0, 0.0, 1.0),
        vec3<f32>(0.0, 1.0, 1.0),
        vec3<f32>(0.0, 1.0, 0.0),
        vec3<f32>(1.0, 1.0, 0.0),
        vec3<f32>(1.0, 0.0, 0.0),
    );
    let x = clamp(t, 0.0, 1.0) * 4.0;
    let i = min(u32(x), 3u);
    return mix(stops[i], stops[i + 1u], x - f32(i));
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(out);
    if any(id.xy >= size) {
        return;
    }
    let rgb = result[params.plane * size.x * size.y + id.y * size.x + id.x].xyz;
    let luminance = dot(rgb, vec3<f32>(0.2126, 0.7152, 0.0722));
    // log10 from log2; the floor keeps black finite (it maps to blue).
    let level = log2(max(luminance, 1.0e-30)) * 0.30103;
    let t = (level - params.lo) / (params.hi - params.lo);
    textureStore(out, vec2<i32>(id.xy), vec4<f32>(ramp(t), 1.0));
}
