// Test shader: the BSDF library (shaders/lib/bsdf.wgsl) used as its contract says. Each
// invocation evaluates one query's eval and pdf at (wo, wi) and draws one sample with its u, so
// tests compare the GPU with the CPU twin and histogram GPU-drawn directions.
#include "lib/scene.wgsl"
#include "lib/sampling.wgsl"
#include "lib/bsdf.wgsl"

struct Query {
    // kd and the kind (its bits).
    kd_kind: vec4<f32>,
    ks_ns: vec4<f32>,
    tf_ior: vec4<f32>,
    n_alpha: vec4<f32>,
    // wo and outside (1 or 0).
    wo_outside: vec4<f32>,
    wi: vec4<f32>,
    // u.xy, u_lobe, and the rough plastic's table index in `materials` (its bits).
    u: vec4<f32>,
    // The conductor's eta and the microfacet distribution (its bits), its k and Fresnel term
    // (its bits).
    eta_distribution: vec4<f32>,
    k_fresnel: vec4<f32>,
}

struct Answer {
    eval_pdf: vec4<f32>,
    // The sample's wi and delta (1 or 0).
    wi_delta: vec4<f32>,
    weight_pdf: vec4<f32>,
    // eval and pdf at the sample's wi.
    at_sample: vec4<f32>,
}

@group(0) @binding(0) var<storage, read> queries: array<Query>;
@group(0) @binding(1) var<storage, read_write> answers: array<Answer>;
// Rough plastic's tables, as scene.materials holds them after the materials.
@group(0) @binding(2) var materials: texture_storage_2d<rgba32uint, read>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&queries) {
        return;
    }
    let q = queries[i];
    let b = Bsdf(bitcast<u32>(q.kd_kind.w), q.kd_kind.xyz, q.ks_ns.xyz, q.ks_ns.w, q.n_alpha.w,
        q.tf_ior.w, q.tf_ior.xyz, bitcast<u32>(q.u.w), bitcast<u32>(q.eta_distribution.w),
        bitcast<u32>(q.k_fresnel.w), q.eta_distribution.xyz, q.k_fresnel.xyz);
    let n = q.n_alpha.xyz;
    let outside = q.wo_outside.w != 0.0;
    let wo = q.wo_outside.xyz;
    let e = bsdf_eval(b, n, outside, wo, q.wi.xyz);
    let p = bsdf_pdf(b, n, outside, wo, q.wi.xyz);
    let s = bsdf_sample(b, n, outside, wo, q.u.xy, q.u.z);
    let es = bsdf_eval(b, n, outside, wo, s.wi);
    let ps = bsdf_pdf(b, n, outside, wo, s.wi);
    answers[i] = Answer(vec4<f32>(e, p), vec4<f32>(s.wi, select(0.0, 1.0, s.delta)),
        vec4<f32>(s.weight, s.pdf), vec4<f32>(es, ps));
}
