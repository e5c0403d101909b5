// Test shader: lib/shading_point.wgsl's shading point at given hits, its shading normal before
// and after the material's normal or bump map (lib/surface_map.wgsl) and the map's shadowing
// of a direction written back for the CPU
// twin (src/scene/surface_map.rs) to check.
#include "lib/scene.wgsl"
#include "lib/sampling.wgsl"
#include "lib/bsdf.wgsl"
#include "lib/surface.wgsl"
#include "lib/shading.wgsl"
#include "lib/texture.wgsl"
#include "lib/shading_point.wgsl"

struct Query {
    dir: vec3<f32>,
    triangle: u32,
    bary: vec2<f32>,
    pad: vec2<u32>,
    // A light direction to shadow.
    w: vec3<f32>,
    pad1: u32,
}

struct Answer {
    ns: vec3<f32>,
    front: u32,
    n_smooth: vec3<f32>,
    shadowing: f32,
}

@group(0) @binding(0) var triangles: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(1) var shading: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(2) var textures: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(3) var materials: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(4) var<storage, read> queries: array<Query>;
@group(0) @binding(5) var<storage, read_write> answers: array<Answer>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if (i >= arrayLength(&queries)) {
        return;
    }
    let q = queries[i];
    let p = shading_point(q.triangle, q.bary.x, q.bary.y, q.dir);
    answers[i] = Answer(p.ns, select(0u, 1u, p.s.front), p.n_smooth,
                        surface_map_shadowing(p.n_smooth, p.ns, q.w));
}
