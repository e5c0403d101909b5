// Generated from the material registry (src/material/registry.rs) by src/material/wgsl.rs:
// do not edit. `cargo test --lib material::wgsl` rewrites it when the registry changes.

// Each model's functions (lib/material/NAME.wgsl: src/material/model.rs lists them) and
// the dispatch on a material's kind; lib/bsdf.wgsl includes this file and states the
// conventions.

#include "material/lambert.wgsl"
#include "material/phong.wgsl"
#include "material/conductor.wgsl"
#include "material/plastic.wgsl"
#include "material/dielectric.wgsl"
#include "material/thin_dielectric.wgsl"
#include "material/metallic_roughness.wgsl"

fn bsdf_eval(b: Bsdf, n: vec3<f32>, outside: bool, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if scene_has_kind(MATERIAL_LAMBERT) && b.kind == MATERIAL_LAMBERT {
        return lambert_eval(b, n, outside, wo, wi);
    }
    if scene_has_kind(MATERIAL_PHONG) && b.kind == MATERIAL_PHONG {
        return phong_eval(b, n, outside, wo, wi);
    }
    let frame = bsdf_frame(n);
    if scene_has_kind(MATERIAL_CONDUCTOR) && b.kind == MATERIAL_CONDUCTOR {
        return conductor_eval(b, outside, wo * frame, wi * frame);
    }
    if scene_has_kind(MATERIAL_PLASTIC) && b.kind == MATERIAL_PLASTIC {
        return plastic_eval(b, outside, wo * frame, wi * frame);
    }
    if scene_has_kind(MATERIAL_DIELECTRIC) && b.kind == MATERIAL_DIELECTRIC {
        return dielectric_eval(b, outside, wo * frame, wi * frame);
    }
    if scene_has_kind(MATERIAL_THIN_DIELECTRIC) && b.kind == MATERIAL_THIN_DIELECTRIC {
        return thin_dielectric_eval(b, outside, wo * frame, wi * frame);
    }
    if scene_has_kind(MATERIAL_METALLIC_ROUGHNESS) && b.kind == MATERIAL_METALLIC_ROUGHNESS {
        return metallic_roughness_eval(b, outside, wo * frame, wi * frame);
    }
    return vec3<f32>(0.0);
}

fn bsdf_pdf(b: Bsdf, n: vec3<f32>, outside: bool, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if scene_has_kind(MATERIAL_LAMBERT) && b.kind == MATERIAL_LAMBERT {
        return lambert_pdf(b, n, outside, wo, wi);
    }
    if scene_has_kind(MATERIAL_PHONG) && b.kind == MATERIAL_PHONG {
        return phong_pdf(b, n, outside, wo, wi);
    }
    let frame = bsdf_frame(n);
    if scene_has_kind(MATERIAL_CONDUCTOR) && b.kind == MATERIAL_CONDUCTOR {
        return conductor_pdf(b, outside, wo * frame, wi * frame);
    }
    if scene_has_kind(MATERIAL_PLASTIC) && b.kind == MATERIAL_PLASTIC {
        return plastic_pdf(b, outside, wo * frame, wi * frame);
    }
    if scene_has_kind(MATERIAL_DIELECTRIC) && b.kind == MATERIAL_DIELECTRIC {
        return dielectric_pdf(b, outside, wo * frame, wi * frame);
    }
    if scene_has_kind(MATERIAL_THIN_DIELECTRIC) && b.kind == MATERIAL_THIN_DIELECTRIC {
        return thin_dielectric_pdf(b, outside, wo * frame, wi * frame);
    }
    if scene_has_kind(MATERIAL_METALLIC_ROUGHNESS) && b.kind == MATERIAL_METALLIC_ROUGHNESS {
        return metallic_roughness_pdf(b, outside, wo * frame, wi * frame);
    }
    return 0.0;
}

// u picks the direction within a lobe, u_lobe the lobe.
fn bsdf_sample(b: Bsdf, n: vec3<f32>, outside: bool, wo: vec3<f32>, u: vec2<f32>, u_lobe: f32)
    -> BsdfSample {
    if scene_has_kind(MATERIAL_LAMBERT) && b.kind == MATERIAL_LAMBERT {
        return lambert_sample(b, n, outside, wo, u, u_lobe);
    }
    if scene_has_kind(MATERIAL_PHONG) && b.kind == MATERIAL_PHONG {
        return phong_sample(b, n, outside, wo, u, u_lobe);
    }
    var s = BsdfSample(n, vec3<f32>(0.0), 0.0, false, 1.0);
    let frame = bsdf_frame(n);
    if scene_has_kind(MATERIAL_CONDUCTOR) && b.kind == MATERIAL_CONDUCTOR {
        s = conductor_sample(b, outside, wo * frame, u, u_lobe);
    } else if scene_has_kind(MATERIAL_PLASTIC) && b.kind == MATERIAL_PLASTIC {
        s = plastic_sample(b, outside, wo * frame, u, u_lobe);
    } else if scene_has_kind(MATERIAL_DIELECTRIC) && b.kind == MATERIAL_DIELECTRIC {
        s = dielectric_sample(b, outside, wo * frame, u, u_lobe);
    } else if scene_has_kind(MATERIAL_THIN_DIELECTRIC) && b.kind == MATERIAL_THIN_DIELECTRIC {
        s = thin_dielectric_sample(b, outside, wo * frame, u, u_lobe);
    } else if scene_has_kind(MATERIAL_METALLIC_ROUGHNESS) && b.kind == MATERIAL_METALLIC_ROUGHNESS {
        s = metallic_roughness_sample(b, outside, wo * frame, u, u_lobe);
    } else {
        return s;
    }
    s.wi = frame * s.wi;
    return s;
}

// True when every lobe is delta: light sampling cannot contribute, so the shadow ray can
// be skipped.
fn bsdf_is_delta(b: Bsdf) -> bool {
    if scene_has_kind(MATERIAL_LAMBERT) && b.kind == MATERIAL_LAMBERT {
        return lambert_is_delta(b);
    }
    if scene_has_kind(MATERIAL_PHONG) && b.kind == MATERIAL_PHONG {
        return phong_is_delta(b);
    }
    if scene_has_kind(MATERIAL_CONDUCTOR) && b.kind == MATERIAL_CONDUCTOR {
        return conductor_is_delta(b);
    }
    if scene_has_kind(MATERIAL_PLASTIC) && b.kind == MATERIAL_PLASTIC {
        return plastic_is_delta(b);
    }
    if scene_has_kind(MATERIAL_DIELECTRIC) && b.kind == MATERIAL_DIELECTRIC {
        return dielectric_is_delta(b);
    }
    if scene_has_kind(MATERIAL_THIN_DIELECTRIC) && b.kind == MATERIAL_THIN_DIELECTRIC {
        return thin_dielectric_is_delta(b);
    }
    if scene_has_kind(MATERIAL_METALLIC_ROUGHNESS) && b.kind == MATERIAL_METALLIC_ROUGHNESS {
        return metallic_roughness_is_delta(b);
    }
    return false;
}
