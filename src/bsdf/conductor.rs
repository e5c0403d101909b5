//! Conductor (`shaders/lib/bsdf_conductor.wgsl`): a mirror tinted kd, GGX-rough when alpha > 0,
//! a delta mirror when alpha = 0, as Mitsuba 3's roughconductor / conductor with material none
//! and specular_reflectance kd, two-sided. Local frame: normal +z, wo.z >= 0.

use super::ggx::{ggx_alpha, ggx_d, ggx_g1, ggx_sample_visible};
use super::{Bsdf, Sample};
use glam::{Vec2, Vec3};

pub fn eval(b: &Bsdf, wo: Vec3, wi: Vec3) -> Vec3 {
    if b.alpha == 0.0 || wo.z <= 0.0 || wi.z <= 0.0 {
        return Vec3::ZERO;
    }
    let a = ggx_alpha(b.alpha);
    let m = (wo + wi).normalize();
    let d = ggx_d(a, m);
    let g = ggx_g1(a, wo, m) * ggx_g1(a, wi, m);
    b.kd * (d * g / (4.0 * wo.z))
}

pub fn pdf(b: &Bsdf, wo: Vec3, wi: Vec3) -> f32 {
    if b.alpha == 0.0 {
        return 0.0;
    }
    let m = (wo + wi).normalize();
    if wo.z <= 0.0 || wi.z <= 0.0 || wo.dot(m) <= 0.0 || wi.dot(m) <= 0.0 {
        return 0.0;
    }
    let a = ggx_alpha(b.alpha);
    // The visible-normal density times the reflection Jacobian 1 / (4 wi.m), wi.m = wo.m.
    ggx_d(a, m) * ggx_g1(a, wo, m) / (4.0 * wo.z)
}

pub fn sample(b: &Bsdf, wo: Vec3, u: Vec2) -> Sample {
    if wo.z <= 0.0 {
        return Sample::failed(Vec3::Z);
    }
    if b.alpha == 0.0 {
        // The delta lobe is chosen with probability 1.
        return Sample {
            wi: Vec3::new(-wo.x, -wo.y, wo.z),
            weight: b.kd,
            pdf: 1.0,
            delta: true,
        };
    }
    let a = ggx_alpha(b.alpha);
    let m = ggx_sample_visible(a, wo, u);
    let wi = 2.0 * wo.dot(m) * m - wo;
    let pdf = pdf(b, wo, wi);
    if pdf <= 0.0 {
        return Sample::failed(wi);
    }
    // f cos / pdf = kd G1(wi, m): D and G1(wo, m) cancel.
    Sample {
        wi,
        weight: b.kd * ggx_g1(a, wi, m),
        pdf,
        delta: false,
    }
}
