// Accumulate: per-pixel running mean m += (x - m) / (n + 1) of L0, direct, indirect, ambient
// and their sum, in f32. A sample with a non-finite channel is dropped for the whole pixel and
// counted; each layer's w holds the pixel's own sample count, so a drop never skews the mean.
// The mean is compensated: `compensation` holds the rounding error of each update (the low
// part of mean + compensation), so the error stays near half an ulp instead of growing like
// sqrt(n) ulps (tests/robust_accumulate.rs; src/render/accumulate.rs mirrors this arithmetic).
#include "lib/provided_view.wgsl"

// A pass param: false where a reprojection pass prepares the history (per pixel).
override restart_on_reset: bool = true;

@group(0) @binding(0) var l0: texture_storage_2d<rgba32float, read>;
@group(0) @binding(1) var direct: texture_storage_2d<rgba32float, read>;
@group(0) @binding(2) var indirect: texture_storage_2d<rgba32float, read>;
@group(0) @binding(3) var ambient: texture_storage_2d<rgba32float, read>;
// Five planes of width * height: L0, direct, indirect, ambient, sum.
@group(0) @binding(4) var<storage, read_write> result: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read_write> dropped: atomic<u32>;
// Same layout as `result`: the rounding error carried by each mean (xyz; w unused).
@group(0) @binding(6) var<storage, read_write> compensation: array<vec4<f32>>;

struct Mean {
    mean: vec3<f32>,
    compensation: vec3<f32>,
}

// Returns v, hidden from the compiler's algebra: `zero` is 0 at run time but unknown when the
// shader is compiled. WGSL lets a compiler treat float arithmetic as exact, and Mesa's (lavapipe)
// then folds (m + d) - m to d, which turns the compensation below into 0.
fn opaque(v: vec3<f32>, zero: u32) -> vec3<f32> {
    return bitcast<vec3<f32>>(bitcast<vec3<u32>>(v) | vec3<u32>(zero));
}

// One step of the running mean of n samples (mean + compensation) with sample x: the increment
// d, the exact rounding error of mean + d (Knuth's TwoSum), then the sum renormalised so that
// the stored mean is the f32 nearest to mean + compensation (Fast2Sum).
fn mean_step(m: vec3<f32>, c: vec3<f32>, x: vec3<f32>, n: f32) -> Mean {
    // n counts samples, so it is never negative.
    let zero = select(0u, 1u, n < 0.0);
    let d = ((x - m) - c) / (n + 1.0);
    let s = opaque(m + d, zero);
    let b = opaque(s - m, zero);
    let e = (m - (s - b)) + (d - b);
    let t = c + e;
    let mean = opaque(s + t, zero);
    return Mean(mean, t - (mean - s));
}

// WGSL may assume floats are finite, so test the exponent bits instead of x != x.
fn finite(v: vec3<f32>) -> bool {
    let e = bitcast<vec3<u32>>(v) & vec3<u32>(0x7f800000u);
    return all(e != vec3<u32>(0x7f800000u));
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= frame.width || id.y >= frame.height {
        return;
    }
    let pixel = vec2<i32>(id.xy);
    let samples = array<vec3<f32>, 4>(
        textureLoad(l0, pixel).xyz,
        textureLoad(direct, pixel).xyz,
        textureLoad(indirect, pixel).xyz,
        textureLoad(ambient, pixel).xyz,
    );
    let sum = samples[0] + samples[1] + samples[2] + samples[3];
    let plane = frame.width * frame.height;
    let i = id.y * frame.width + id.x;
    if !(finite(samples[0]) && finite(samples[1]) && finite(samples[2]) && finite(samples[3]) && finite(sum)) {
        atomicAdd(&dropped, 1u);
        if frame.accumulated == 0u && restart_on_reset {
            // A restart still forgets the old history, with zero samples for this pixel.
            for (var c = 0u; c < 5u; c++) {
                result[c * plane + i] = vec4<f32>(0.0);
                compensation[c * plane + i] = vec4<f32>(0.0);
            }
        }
        return;
    }
    for (var c = 0u; c < 5u; c++) {
        let x = select(samples[min(c, 3u)], sum, c == 4u);
        let m = result[c * plane + i];
        // A restart ignores whatever the buffers held, unless a reprojection pass already
        // decided, per pixel, what history survives (restart_on_reset false).
        let restart = frame.accumulated == 0u && restart_on_reset;
        let n = select(m.w, 0.0, restart);
        let mean = select(m.xyz, vec3<f32>(0.0), restart);
        let error = select(compensation[c * plane + i].xyz, vec3<f32>(0.0), restart);
        let next = mean_step(mean, error, x, n);
        result[c * plane + i] = vec4<f32>(next.mean, n + 1.0);
        compensation[c * plane + i] = vec4<f32>(next.compensation, 0.0);
    }
}
