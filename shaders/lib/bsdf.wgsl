// The BSDF library: one material's scattering at a shading point, dispatched on its kind by
// bsdf_eval, bsdf_pdf, bsdf_sample and bsdf_is_delta (material_models.wgsl, generated from the
// material registry, src/material/registry.rs: each model's WGSL is lib/material/NAME.wgsl). Each
// kind's code sits behind scene_has_kind, so a scene's shaders hold only its models.
//
// The including shader includes lib/scene.wgsl and lib/sampling.wgsl first and declares the
// scene.materials texel view as the global `materials` (rough plastic and metallic-roughness
// read their tables there); this file brings the shared maths and the models.
//
// Conventions: directions are world-space unit vectors, wo toward the viewer, wi toward the
// light; n is the shading normal turned to wo's side; `outside` says whether wo is on the
// surface's front side (only the dielectric reads it). eval is f |n.wi| of the non-delta lobes.
// A sample's weight is f |n.wi| / pdf (0 when the sample fails, its pdf then 0 too). A delta
// sample (delta true) has pdf = the probability of having chosen that delta lobe (1 for the
// smooth conductor, the lobe probability for smooth plastic, dielectric and thin dielectric);
// its weight already
// divides by it. The dielectric's transmission carries radiance transport's eta_ti^2.

#include "fresnel.wgsl"
#include "ggx.wgsl"
#include "erf.wgsl"
#include "beckmann.wgsl"
#include "microfacet.wgsl"
#include "material_models.wgsl"

// A material at one shading point, textures already applied.
struct Bsdf {
    kind: u32,
    kd: vec3<f32>,
    ks: vec3<f32>,
    ns: f32,
    // Microfacet alpha; 0: smooth (delta).
    alpha: f32,
    ior: f32,
    tf: vec3<f32>,
    // The texel index in `materials` of the rough plastic's tables, or NO_TABLE (every other
    // model, smooth plastic).
    table: u32,
    // The rough lobes' distribution (DISTRIBUTION_*: lib/microfacet.wgsl); the conductor's
    // Fresnel term (FRESNEL_NONE, FRESNEL_CONDUCTOR) and complex index eta + i k.
    distribution: u32,
    fresnel: u32,
    eta: vec3<f32>,
    k: vec3<f32>,
}

struct BsdfSample {
    wi: vec3<f32>,
    weight: vec3<f32>,
    pdf: f32,
    delta: bool,
    // The relative index of refraction across the sample, eta_t / eta_i: above 1 entering a
    // denser medium, 1 for a reflection (Mitsuba's BSDFSample3f::eta). A refraction's weight
    // carries radiance's 1 / eta^2; Russian roulette takes it back out (path_light.wgsl).
    eta: f32,
}

fn bsdf_from_material(m: Material) -> Bsdf {
    return Bsdf(m.kind, m.kd, m.ks, m.ns, m.alpha, m.ior, m.tf, m.table, m.distribution,
        m.fresnel, m.eta, m.k);
}

// The world-to-local rotation: local = v * frame (rows of the transpose are the axes).
fn bsdf_frame(n: vec3<f32>) -> mat3x3<f32> {
    return basis(n);
}
