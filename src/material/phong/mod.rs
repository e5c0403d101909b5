//! The seed's normalised Blinn-Phong (`shaders/lib/material/phong.wgsl`), f = kd / pi + ks (ns + 8) / (8 pi)
//! max(0, n.h)^ns, sampled by the cosine. No Mitsuba twin.

use crate::bsdf::frame::sample_cosine;
use crate::material::bsdf::{Bsdf, Sample};
use crate::material::lambert;
use crate::material::model::{Model, Space};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

pub const KIND: u32 = 1;

pub const MODEL: Model = Model {
    name: "phong",
    kind: KIND,
    space: Space::World,
    eval: |b, n, _, wo, wi| eval(b, n, wo, wi),
    pdf: |_, n, _, wo, wi| lambert::pdf(n, wo, wi),
    sample: |b, n, _, wo, u, _| sample(b, n, wo, u),
    is_delta: |_| false,
    microfacet: false,
    specular: |m| m.ks.iter().any(|&c| c > 0.0),
    table: None,
};

pub fn eval(b: &Bsdf, n: Vec3, wo: Vec3, wi: Vec3) -> Vec3 {
    let cos_o = n.dot(wo);
    let cos_i = n.dot(wi);
    if cos_o <= 0.0 || cos_i <= 0.0 {
        return Vec3::ZERO;
    }
    let h = (wo + wi).normalize();
    let lobe = (b.ns + 8.0) / (8.0 * PI) * n.dot(h).max(0.0).powf(b.ns);
    (b.kd * (1.0 / PI) + b.ks * lobe) * cos_i
}

pub fn sample(b: &Bsdf, n: Vec3, wo: Vec3, u: Vec2) -> Sample {
    let wi = sample_cosine(n, u.x, u.y);
    let pdf = lambert::pdf(n, wo, wi);
    if pdf <= 0.0 {
        return Sample::failed(wi);
    }
    Sample {
        wi,
        weight: eval(b, n, wo, wi) / pdf,
        pdf,
        delta: false,
    }
}
