// The BSDF library: one material's scattering at a shading point, dispatched on its kind.
// Each kind's code sits behind scene_has_kind, so a scene's shaders hold only its models.
//
// The including shader includes lib/scene.wgsl and lib/sampling.wgsl first and declares the
// scene.materials texel view as the global `materials` (rough plastic reads its tables there:
// bsdf_plastic.wgsl); this file brings the models' own files.
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
#include "bsdf_lambert.wgsl"
#include "bsdf_phong.wgsl"
#include "bsdf_conductor.wgsl"
#include "bsdf_plastic.wgsl"
#include "bsdf_dielectric.wgsl"
#include "bsdf_thin_dielectric.wgsl"
#include "bsdf_metallic_roughness.wgsl"

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
}

fn bsdf_from_material(m: Material) -> Bsdf {
    return Bsdf(m.kind, m.kd, m.ks, m.ns, m.alpha, m.ior, m.tf, m.table, m.distribution,
        m.fresnel, m.eta, m.k);
}

// The world-to-local rotation: local = v * frame (rows of the transpose are the axes).
fn bsdf_frame(n: vec3<f32>) -> mat3x3<f32> {
    return basis(n);
}

fn bsdf_eval(b: Bsdf, n: vec3<f32>, outside: bool, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if scene_has_kind(MATERIAL_LAMBERT) && b.kind == MATERIAL_LAMBERT {
        return lambert_eval(b, n, wo, wi);
    }
    if scene_has_kind(MATERIAL_PHONG) && b.kind == MATERIAL_PHONG {
        return phong_eval(b, n, wo, wi);
    }
    let frame = bsdf_frame(n);
    if scene_has_kind(MATERIAL_CONDUCTOR) && b.kind == MATERIAL_CONDUCTOR {
        return conductor_eval(b, wo * frame, wi * frame);
    }
    if scene_has_kind(MATERIAL_PLASTIC) && b.kind == MATERIAL_PLASTIC {
        return plastic_eval(b, wo * frame, wi * frame);
    }
    if scene_has_kind(MATERIAL_DIELECTRIC) && b.kind == MATERIAL_DIELECTRIC {
        return dielectric_eval(b, outside, wo * frame, wi * frame);
    }
    if scene_has_kind(MATERIAL_METALLIC_ROUGHNESS) && b.kind == MATERIAL_METALLIC_ROUGHNESS {
        return metallic_roughness_eval(b, wo * frame, wi * frame);
    }
    return vec3<f32>(0.0);
}

fn bsdf_pdf(b: Bsdf, n: vec3<f32>, outside: bool, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if scene_has_kind(MATERIAL_LAMBERT) && b.kind == MATERIAL_LAMBERT {
        return lambert_pdf(n, wo, wi);
    }
    if scene_has_kind(MATERIAL_PHONG) && b.kind == MATERIAL_PHONG {
        return lambert_pdf(n, wo, wi);
    }
    let frame = bsdf_frame(n);
    if scene_has_kind(MATERIAL_CONDUCTOR) && b.kind == MATERIAL_CONDUCTOR {
        return conductor_pdf(b, wo * frame, wi * frame);
    }
    if scene_has_kind(MATERIAL_PLASTIC) && b.kind == MATERIAL_PLASTIC {
        return plastic_pdf(b, wo * frame, wi * frame);
    }
    if scene_has_kind(MATERIAL_DIELECTRIC) && b.kind == MATERIAL_DIELECTRIC {
        return dielectric_pdf(b, outside, wo * frame, wi * frame);
    }
    if scene_has_kind(MATERIAL_METALLIC_ROUGHNESS) && b.kind == MATERIAL_METALLIC_ROUGHNESS {
        return metallic_roughness_pdf(b, wo * frame, wi * frame);
    }
    return 0.0;
}

// u picks the direction within a lobe, u_lobe the lobe (plastic, dielectric, metallic-roughness).
fn bsdf_sample(b: Bsdf, n: vec3<f32>, outside: bool, wo: vec3<f32>, u: vec2<f32>, u_lobe: f32)
    -> BsdfSample {
    if scene_has_kind(MATERIAL_LAMBERT) && b.kind == MATERIAL_LAMBERT {
        return lambert_sample(b, n, wo, u);
    }
    if scene_has_kind(MATERIAL_PHONG) && b.kind == MATERIAL_PHONG {
        return phong_sample(b, n, wo, u);
    }
    let frame = bsdf_frame(n);
    var s = BsdfSample(n, vec3<f32>(0.0), 0.0, false);
    if scene_has_kind(MATERIAL_CONDUCTOR) && b.kind == MATERIAL_CONDUCTOR {
        s = conductor_sample(b, wo * frame, u);
    } else if scene_has_kind(MATERIAL_PLASTIC) && b.kind == MATERIAL_PLASTIC {
        s = plastic_sample(b, wo * frame, u, u_lobe);
    } else if scene_has_kind(MATERIAL_DIELECTRIC) && b.kind == MATERIAL_DIELECTRIC {
        s = dielectric_sample(b, outside, wo * frame, u, u_lobe);
    } else if scene_has_kind(MATERIAL_THIN_DIELECTRIC) && b.kind == MATERIAL_THIN_DIELECTRIC {
        s = thin_dielectric_sample(b, wo * frame, u_lobe);
    } else if scene_has_kind(MATERIAL_METALLIC_ROUGHNESS)
        && b.kind == MATERIAL_METALLIC_ROUGHNESS {
        s = metallic_roughness_sample(b, wo * frame, u, u_lobe);
    } else {
        return s;
    }
    s.wi = frame * s.wi;
    return s;
}

// True when every lobe is delta (smooth conductor, smooth dielectric, thin dielectric): light
// sampling cannot contribute, so the shadow ray can be skipped.
fn bsdf_is_delta(b: Bsdf) -> bool {
    return (b.alpha == 0.0
        && ((scene_has_kind(MATERIAL_CONDUCTOR) && b.kind == MATERIAL_CONDUCTOR)
            || (scene_has_kind(MATERIAL_DIELECTRIC) && b.kind == MATERIAL_DIELECTRIC)))
        || (scene_has_kind(MATERIAL_THIN_DIELECTRIC) && b.kind == MATERIAL_THIN_DIELECTRIC);
}
