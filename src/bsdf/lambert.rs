//! Lambert (`shaders/lib/bsdf_lambert.wgsl`): f = kd / pi, two-sided (Mitsuba 3's twosided +
//! diffuse). World space; n faces wo.

use super::frame::sample_cosine;
use super::{Bsdf, Sample};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

pub fn eval(b: &Bsdf, n: Vec3, wo: Vec3, wi: Vec3) -> Vec3 {
    let cos_o = n.dot(wo);
    let cos_i = n.dot(wi);
    if cos_o <= 0.0 || cos_i <= 0.0 {
        return Vec3::ZERO;
    }
    b.kd * (cos_i / PI)
}

pub fn pdf(n: Vec3, wo: Vec3, wi: Vec3) -> f32 {
    let cos_o = n.dot(wo);
    let cos_i = n.dot(wi);
    if cos_o <= 0.0 || cos_i <= 0.0 {
        return 0.0;
    }
    cos_i / PI
}

pub fn sample(b: &Bsdf, n: Vec3, wo: Vec3, u: Vec2) -> Sample {
    let wi = sample_cosine(n, u.x, u.y);
    let pdf = pdf(n, wo, wi);
    if pdf <= 0.0 {
        return Sample::failed(wi);
    }
    // f cos / pdf: the cosines and pi cancel.
    Sample {
        wi,
        weight: b.kd,
        pdf,
        delta: false,
    }
}
