//! Dielectric (`shaders/lib/material/dielectric.wgsl`): a one-sided interface between outside
//! (index 1, where the geometric normal points) and inside (index ior), reflection untinted,
//! transmission tinted tf, in radiance transport (transmitted radiance scaled by eta_ti^2);
//! microfacet-rough (GGX or Beckmann, `distribution`) when alpha > 0 as Mitsuba 3's roughdielectric, a delta interface when alpha = 0 as
//! its dielectric. Local frame: normal +z on wo's side; `eta` is the index across the interface
//! relative to wo's side (ior outside, 1 / ior inside).

use crate::bsdf::fresnel::fresnel_dielectric;
use crate::bsdf::microfacet::{
    microfacet_alpha, microfacet_d, microfacet_g1, microfacet_pdf_visible,
    microfacet_sample_visible,
};
use crate::material::bsdf::{Bsdf, Sample, in_local_frame, sample_in_local_frame};
use crate::material::model::{Model, Space};
use glam::{Vec2, Vec3};

pub const KIND: u32 = 4;

pub const MODEL: Model = Model {
    name: "dielectric",
    kind: KIND,
    space: Space::Local,
    eval: |b, n, outside, wo, wi| in_local_frame(n, wo, wi, |wo, wi| eval(b, outside, wo, wi)),
    pdf: |b, n, outside, wo, wi| in_local_frame(n, wo, wi, |wo, wi| pdf(b, outside, wo, wi)),
    sample: |b, n, outside, wo, u, u_lobe| {
        sample_in_local_frame(n, wo, |wo| sample(b, outside, wo, u, u_lobe))
    },
    is_delta: |b| b.alpha == 0.0,
    microfacet: true,
    specular: |_| true,
    table: None,
};

pub fn relative_eta(b: &Bsdf, outside: bool) -> f32 {
    if outside { b.ior } else { 1.0 / b.ior }
}

/// The microfacet normal that takes wo to wi (reflected or refracted), on wo's side.
fn half(eta: f32, wo: Vec3, wi: Vec3) -> Vec3 {
    let is_reflection = wo.z * wi.z > 0.0;
    let m = (wo + wi * if is_reflection { 1.0 } else { eta }).normalize();
    if m.z < 0.0 { -m } else { m }
}

pub fn eval(b: &Bsdf, outside: bool, wo: Vec3, wi: Vec3) -> Vec3 {
    if b.alpha == 0.0 || wo.z == 0.0 {
        return Vec3::ZERO;
    }
    let a = microfacet_alpha(b.alpha);
    let eta = relative_eta(b, outside);
    let m = half(eta, wo, wi);
    let d = microfacet_d(b.distribution, a, m);
    let f = fresnel_dielectric(wo.dot(m), eta).r;
    let g = microfacet_g1(b.distribution, a, wo, m) * microfacet_g1(b.distribution, a, wi, m);
    if wo.z * wi.z > 0.0 {
        return Vec3::splat(f * d * g / (4.0 * wo.z.abs()));
    }
    // Radiance transport's 1 / eta^2 times the half-vector Jacobian's eta^2.
    let scale = 1.0 / (eta * eta);
    let denom = wo.dot(m) + eta * wi.dot(m);
    let t = (scale * (1.0 - f) * d * g * eta * eta * wo.dot(m) * wi.dot(m)
        / (wo.z * denom * denom))
        .abs();
    b.tf * t
}

pub fn pdf(b: &Bsdf, outside: bool, wo: Vec3, wi: Vec3) -> f32 {
    if b.alpha == 0.0 || wo.z == 0.0 {
        return 0.0;
    }
    let a = microfacet_alpha(b.alpha);
    let eta = relative_eta(b, outside);
    let is_reflection = wo.z * wi.z > 0.0;
    let m = half(eta, wo, wi);
    if wo.dot(m) * wo.z <= 0.0 || wi.dot(m) * wi.z <= 0.0 {
        return 0.0;
    }
    let denom = wo.dot(m) + eta * wi.dot(m);
    let dwh_dwi = if is_reflection {
        1.0 / (4.0 * wi.dot(m))
    } else {
        eta * eta * wi.dot(m) / (denom * denom)
    };
    let f = fresnel_dielectric(wo.dot(m), eta).r;
    let lobe = if is_reflection { f } else { 1.0 - f };
    microfacet_pdf_visible(b.distribution, a, wo, m) * lobe * dwh_dwi.abs()
}

/// Smooth: `u_lobe <= F` reflects, else refracts; delta, pdf = the chosen lobe's probability.
/// Rough: a visible normal, then the same choice by its F.
pub fn sample(b: &Bsdf, outside: bool, wo: Vec3, u: Vec2, u_lobe: f32) -> Sample {
    let eta = relative_eta(b, outside);
    if wo.z == 0.0 {
        return Sample::failed(Vec3::Z);
    }
    if b.alpha == 0.0 {
        let fr = fresnel_dielectric(wo.z, eta);
        if u_lobe <= fr.r {
            return Sample {
                wi: Vec3::new(-wo.x, -wo.y, wo.z),
                weight: Vec3::ONE,
                pdf: fr.r,
                delta: true,
            };
        }
        return Sample {
            wi: Vec3::new(-fr.eta_ti * wo.x, -fr.eta_ti * wo.y, fr.cos_t),
            weight: b.tf * (fr.eta_ti * fr.eta_ti),
            pdf: 1.0 - fr.r,
            delta: true,
        };
    }
    let a = microfacet_alpha(b.alpha);
    let m = microfacet_sample_visible(b.distribution, a, wo, u);
    let fr = fresnel_dielectric(wo.dot(m), eta);
    let (wi, weight) = if u_lobe <= fr.r {
        (2.0 * wo.dot(m) * m - wo, Vec3::ONE)
    } else {
        (
            m * (wo.dot(m) * fr.eta_ti + fr.cos_t) - wo * fr.eta_ti,
            b.tf * (fr.eta_ti * fr.eta_ti),
        )
    };
    // f cos / pdf = tint G1(wi, m), 0 when wi left for the wrong side: a failed sample.
    let g = microfacet_g1(b.distribution, a, wi, m);
    let pdf = pdf(b, outside, wo, wi);
    if g <= 0.0 || pdf <= 0.0 {
        return Sample::failed(wi);
    }
    Sample {
        wi,
        weight: weight * g,
        pdf,
        delta: false,
    }
}
