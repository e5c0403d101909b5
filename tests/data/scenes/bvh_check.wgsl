// Test shader: shaders/lib/bvh.wgsl used as its contract says. It casts one ray per invocation
// and writes the three queries' answers, so it also serves GPU-against-CPU checks.
#include "lib/scene.wgsl"
#include "lib/bvh.wgsl"
#include "lib/cutout_map_none.wgsl"

struct Query {
    origin: vec3<f32>,
    tmin: f32,
    dir: vec3<f32>,
    tmax: f32,
}

struct Answer {
    t: f32,
    u: f32,
    v: f32,
    triangle: u32,
    any: u32,
    shadow: u32,
    pad1: u32,
    pad2: u32,
}

@group(0) @binding(0) var triangles: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(1) var bvh: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(2) var<storage, read> queries: array<Query>;
@group(0) @binding(3) var<storage, read_write> answers: array<Answer>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if (i >= arrayLength(&queries)) {
        return;
    }
    let q = queries[i];
    let hit = closest_hit(q.origin, q.dir, q.tmin, q.tmax);
    let any = any_hit(q.origin, q.dir, q.tmin, q.tmax);
    let shadow = shadow_hit(q.origin, q.dir, q.tmin, q.tmax);
    answers[i] = Answer(hit.t, hit.u, hit.v, hit.triangle, select(0u, 1u, any), select(0u, 1u, shadow), 0u, 0u);
}
