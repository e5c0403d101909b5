// Test shader: shaders/lib/light_sample.wgsl's estimate of the projected solid angle of a
// light, cos_x over the pdf (`geometry`), over 2^16 independent uniform samples per query point:
// its mean and mean square. tests/light_sample.rs compares the mean with the closed form.
#include "lib/scene.wgsl"
#include "lib/rng.wgsl"
#include "lib/sampling.wgsl"
#include "lib/surface.wgsl"
#include "lib/light_sample.wgsl"

struct Query {
    origin: vec3<f32>,
    pad0: f32,
    normal: vec3<f32>,
    pad1: f32,
}

struct Answer {
    mean: f32,
    mean_square: f32,
    // The solid angle spherical_rectangle computes (which branch sample_light takes).
    solid_angle: f32,
    // Samples with cos_x or cos_y <= 0 (none for a light wholly in front of the point).
    rejected: u32,
}

@group(0) @binding(0) var<uniform> light: Light;
@group(0) @binding(1) var<storage, read> queries: array<Query>;
@group(0) @binding(2) var<storage, read_write> answers: array<Answer>;

const GRID: u32 = 256u;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&queries) {
        return;
    }
    let q = queries[i];
    let s = Surface(q.origin, q.normal, true, 0u, 0.0);
    var sum = 0.0;
    var sum_square = 0.0;
    var rejected = 0u;
    var state = pcg_hash(i + 1u);
    for (var a = 0u; a < GRID; a++) {
        var row = 0.0;
        var row_square = 0.0;
        for (var b = 0u; b < GRID; b++) {
            let u = vec2<f32>(rng_next(&state), rng_next(&state));
            let l = sample_light(s, q.origin, light, u);
            if l.cos_x <= 0.0 || l.cos_y <= 0.0 {
                rejected += 1u;
            } else {
                row += l.geometry;
                row_square += l.geometry * l.geometry;
            }
        }
        sum += row;
        sum_square += row_square;
    }
    let r = spherical_rectangle(q.origin, light.p0, light.e1, light.e2);
    let n = f32(GRID * GRID);
    answers[i] = Answer(sum / n, sum_square / n, r.solid_angle, rejected);
}
