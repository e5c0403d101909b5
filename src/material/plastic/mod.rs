//! Plastic (`shaders/lib/material/plastic.wgsl`): a diffuse base kd under a dielectric coat of
//! index ior (outside 1) tinted ks, as Mitsuba 3's plastic (smooth: no table) and roughplastic
//! (GGX or Beckmann by `distribution`, alpha > 0, with the coat's tables: tables.rs), both with nonlinear
//! false, two-sided. Local frame: normal +z, wo.z >= 0.

pub mod tables;

use crate::bsdf::frame::sample_cosine;
use crate::bsdf::fresnel::{fresnel_dielectric, fresnel_diffuse_reflectance};
use crate::bsdf::microfacet::{
    Distribution, microfacet_alpha, microfacet_d, microfacet_g1, microfacet_sample_visible,
};
use crate::material::bsdf::{Bsdf, Sample, in_local_frame, sample_in_local_frame};
use crate::material::model::{Model, Space, Table};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;
use tables::PlasticTable;

pub const KIND: u32 = 3;

/// The rough coat's table is Mitsuba's per-material one; materials with equal
/// (distribution, alpha, ior) share it.
pub const MODEL: Model = Model {
    name: "plastic",
    kind: KIND,
    space: Space::Local,
    eval: |b, n, _, wo, wi| in_local_frame(n, wo, wi, |wo, wi| eval(b, wo, wi)),
    pdf: |b, n, _, wo, wi| in_local_frame(n, wo, wi, |wo, wi| pdf(b, wo, wi)),
    sample: |b, n, _, wo, u, u_lobe| sample_in_local_frame(n, wo, |wo| sample(b, wo, u, u_lobe)),
    is_delta: |_| false,
    microfacet: true,
    specular: |_| true,
    table: Some(Table {
        key: |m| (m.alpha > 0.0).then(|| [m.distribution, m.alpha.to_bits(), m.ior.to_bits()]),
        texels: |m| {
            let distribution = Distribution::from_u32(m.distribution);
            PlasticTable::compute(distribution, m.alpha, m.ior)
                .texels()
                .to_vec()
        },
    }),
};

/// The probability of sampling the coat's reflection, from the fraction of light at wo the coat
/// reflects (`f_i`: F for the smooth coat, 1 - transmittance for the rough one): Mitsuba's
/// weights, with the tints' means at this point.
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
    if let Some(t) = &b.table {
        return rough_eval(b, t, wo, wi);
    }
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return Vec3::ZERO;
    }
    diffuse(b, wo.z, wi.z)
}

pub fn pdf(b: &Bsdf, wo: Vec3, wi: Vec3) -> f32 {
    if let Some(t) = &b.table {
        return rough_pdf(b, t, wo, wi);
    }
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let f_o = fresnel_dielectric(wo.z, b.ior).r;
    (1.0 - specular_probability(b, f_o)) * (wi.z / PI)
}

/// `u_lobe` below the specular probability picks the coat's reflection (delta; pdf is that
/// probability), otherwise the base by the cosine.
pub fn sample(b: &Bsdf, wo: Vec3, u: Vec2, u_lobe: f32) -> Sample {
    if let Some(t) = &b.table {
        return rough_sample(b, t, wo, u, u_lobe);
    }
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

/// The rough coat's diffuse part: kd / (1 - internal reflectance), the coat's transmittance
/// both ways (from the table), the 1 / eta^2 of entering and leaving, and the cosine.
fn rough_diffuse(b: &Bsdf, t: &PlasticTable, cos_o: f32, cos_i: f32) -> Vec3 {
    let t_o = t.transmittance_at(cos_o);
    let t_i = t.transmittance_at(cos_i);
    let scale = (1.0 / PI) * (1.0 / (b.ior * b.ior)) * cos_i * t_o * t_i;
    b.kd / (1.0 - t.internal_reflectance) * scale
}

/// The rough coat's specular part: ks F D G / (4 cos_o) (f times cos_i).
fn rough_specular(b: &Bsdf, wo: Vec3, wi: Vec3) -> Vec3 {
    let a = microfacet_alpha(b.alpha);
    let m = (wo + wi).normalize();
    let d = microfacet_d(b.distribution, a, m);
    let f = fresnel_dielectric(wo.dot(m), b.ior).r;
    let g = microfacet_g1(b.distribution, a, wo, m) * microfacet_g1(b.distribution, a, wi, m);
    b.ks * (f * d * g / (4.0 * wo.z))
}

fn rough_eval(b: &Bsdf, t: &PlasticTable, wo: Vec3, wi: Vec3) -> Vec3 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return Vec3::ZERO;
    }
    rough_specular(b, wo, wi) + rough_diffuse(b, t, wo.z, wi.z)
}

fn rough_pdf(b: &Bsdf, t: &PlasticTable, wo: Vec3, wi: Vec3) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let p_s = specular_probability(b, 1.0 - t.transmittance_at(wo.z));
    let a = microfacet_alpha(b.alpha);
    let m = (wo + wi).normalize();
    // The visible-normal density times the reflection Jacobian 1 / (4 wo.m).
    let specular =
        microfacet_d(b.distribution, a, m) * microfacet_g1(b.distribution, a, wo, m) / (4.0 * wo.z);
    p_s * specular + (1.0 - p_s) * (wi.z / PI)
}

/// `u_lobe` below the specular probability reflects wo about a visible microfacet normal, otherwise
/// the base is sampled by the cosine; either way the pdf is the mixture's.
fn rough_sample(b: &Bsdf, t: &PlasticTable, wo: Vec3, u: Vec2, u_lobe: f32) -> Sample {
    if wo.z <= 0.0 {
        return Sample::failed(Vec3::Z);
    }
    let p_s = specular_probability(b, 1.0 - t.transmittance_at(wo.z));
    let wi = if u_lobe < p_s {
        let m = microfacet_sample_visible(b.distribution, microfacet_alpha(b.alpha), wo, u);
        2.0 * wo.dot(m) * m - wo
    } else {
        sample_cosine(Vec3::Z, u.x, u.y)
    };
    let pdf = rough_pdf(b, t, wo, wi);
    if wi.z <= 0.0 || pdf <= 0.0 {
        return Sample::failed(wi);
    }
    Sample {
        wi,
        weight: rough_eval(b, t, wo, wi) / pdf,
        pdf,
        delta: false,
    }
}
