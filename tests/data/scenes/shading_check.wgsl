// Test shader: lib/shading.wgsl and lib/texture.wgsl used as their contracts say, one query per
// invocation, every accessor's answer written back for the CPU to check.
#include "lib/scene.wgsl"
#include "lib/shading.wgsl"
#include "lib/texture.wgsl"

struct Query {
    n_geometric: vec3<f32>,
    triangle: u32,
    bary: vec2<f32>,
    uv: vec2<f32>,
    texture: u32,
    material: u32,
    pad0: u32,
    pad1: u32,
}

struct Answer {
    normal: vec3<f32>,
    pad0: f32,
    uv: vec2<f32>,
    pad1: vec2<f32>,
    texel: vec4<f32>,
    kd: vec3<f32>,
    alpha: f32,
    ks: vec3<f32>,
    opacity: f32,
}

@group(0) @binding(0) var shading: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(1) var textures: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(2) var materials: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(3) var<storage, read> queries: array<Query>;
@group(0) @binding(4) var<storage, read_write> answers: array<Answer>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if (i >= arrayLength(&queries)) {
        return;
    }
    let q = queries[i];
    let n = shading_normal(shading, q.triangle, q.bary.x, q.bary.y, q.n_geometric);
    let uv = shading_uv(shading, q.triangle, q.bary.x, q.bary.y);
    let texel = texture_bilinear(textures, q.texture, q.uv);
    let m = material_at(scene_material(materials, q.material), textures, q.uv);
    answers[i] = Answer(n, 0.0, uv, vec2<f32>(0.0), texel, m.kd, m.alpha, m.ks, m.opacity);
}
