//! Plastic (`shaders/lib/bsdf_plastic.wgsl`): a diffuse base kd under a smooth dielectric coat of
//! index ior (outside 1) tinted ks, as Mitsuba 3's plastic with nonlinear false, two-sided.
//! Local frame: normal +z, wo.z >= 0.
//!
//! alpha is ignored: a rough plastic (Mitsuba's roughplastic) needs per-material tables (the
//! coat's transmittance over cos theta and its internal reflectance) that Material does not
//! carry yet, so every plastic is the smooth one.

use super::frame::sample_cosine;
use super::fresnel::{fresnel_dielectric, fresnel_diffuse_reflectance};
use super::{Bsdf, Sample};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// The probability of sampling the coat's delta reflection, from the reflectance at wo
/// (`f_i`): Mitsuba's weights, with the tints' means at this point.
pub fn specular_probability(b: &Bsdf, f_i: f32) -> f32 {
    let s_mean = (b.ks.x + b.ks.y + b.ks.z) / 3.0;
    let d_mean = (b.kd.x + b.kd.y + b.kd.z) / 3.0;
    // Black tints have no lobe to prefer.
    let w = if d_mean + s_mean > 0.0 {
        s_mean / (d_mean + s_mean)
    } else {
        0.5
    };
    let p_s = f_i * w;
    let p_d = (1.0 - f_i) * (1.0 - w);
    if p_s + p_d > 0.0 {
        p_s / (p_s + p_d)
    } else {
        1.0
    }
}

/// The base's light through the coat: kd / (1 - internal diffuse reflectance), the coat's
/// transmission both ways and the 1 / eta^2 of entering and leaving.
fn diffuse(b: &Bsdf, cos_o: f32, cos_i: f32) -> Vec3 {
    let eta = b.ior;
    let f_o = fresnel_dielectric(cos_o, eta).r;
    let f_i = fresnel_dielectric(cos_i, eta).r;
    let fdr_int = fresnel_diffuse_reflectance(1.0 / eta);
    let scale = (cos_i / PI) * (1.0 / (eta * eta)) * (1.0 - f_o) * (1.0 - f_i);
    b.kd / (1.0 - fdr_int) * scale
}

pub fn eval(b: &Bsdf, wo: Vec3, wi: Vec3) -> Vec3 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return Vec3::ZERO;
    }
    diffuse(b, wo.z, wi.z)
}

pub fn pdf(b: &Bsdf, wo: Vec3, wi: Vec3) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let f_o = fresnel_dielectric(wo.z, b.ior).r;
    (1.0 - specular_probability(b, f_o)) * (wi.z / PI)
}

/// `u_lobe` below the specular probability picks the coat's reflection (delta; pdf is that
/// probability), otherwise the base by the cosine.
pub fn sample(b: &Bsdf, wo: Vec3, u: Vec2, u_lobe: f32) -> Sample {
    if wo.z <= 0.0 {
        return Sample::failed(Vec3::Z);
    }
    let f_o = fresnel_dielectric(wo.z, b.ior).r;
    let p_s = specular_probability(b, f_o);
    if u_lobe < p_s {
        return Sample {
            wi: Vec3::new(-wo.x, -wo.y, wo.z),
            weight: b.ks * (f_o / p_s),
            pdf: p_s,
            delta: true,
        };
    }
    let wi = sample_cosine(Vec3::Z, u.x, u.y);
    let pdf = (1.0 - p_s) * (wi.z / PI);
    if wi.z <= 0.0 || pdf <= 0.0 {
        return Sample::failed(wi);
    }
    Sample {
        wi,
        weight: diffuse(b, wo.z, wi.z) / pdf,
        pdf,
        delta: false,
    }
}
