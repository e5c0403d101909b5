@group(0) @binding(0) var src: texture_storage_2d<rgba32float, read>;
@group(0) @binding(1) var<uniform> grade: vec4<f32>;
@group(0) @binding(2) var dst: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let p = vec2<i32>(id.xy);
    if any(p >= vec2<i32>(textureDimensions(dst))) {
        return;
    }
    let c = textureLoad(src, p);
    textureStore(dst, p, vec4<f32>(c.rgb * grade.rgb, c.a));
}
