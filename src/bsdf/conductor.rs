//! Conductor (`shaders/lib/bsdf_conductor.wgsl`): a mirror tinted kd, microfacet-rough when
//! alpha > 0, a delta mirror when alpha = 0, as Mitsuba 3's roughconductor / conductor,
//! two-sided: with `fresnel` FRESNEL_NONE its material none (Fresnel 1) with
//! specular_reflectance kd, with FRESNEL_CONDUCTOR kd times the Fresnel term of the complex index
//! eta + i k. Local frame: normal +z, wo.z >= 0.

use super::fresnel::fresnel_conductor;
use super::microfacet::{microfacet_alpha, microfacet_d, microfacet_g1, microfacet_sample_visible};
use super::{Bsdf, Sample};
use crate::scene::gpu_layout::FRESNEL_CONDUCTOR;
use glam::{Vec2, Vec3};

/// The reflectance at cos(wo, m) = `cos_i`: kd, times the complex-index Fresnel term when the
/// material has one (kd alone is the tinted mirror, unchanged bit for bit).
fn reflectance(b: &Bsdf, cos_i: f32) -> Vec3 {
    if b.fresnel == FRESNEL_CONDUCTOR {
        return b.kd * fresnel_conductor(cos_i, b.eta, b.k);
    }
    b.kd
}

pub fn eval(b: &Bsdf, wo: Vec3, wi: Vec3) -> Vec3 {
    if b.alpha == 0.0 || wo.z <= 0.0 || wi.z <= 0.0 {
        return Vec3::ZERO;
    }
    let a = microfacet_alpha(b.alpha);
    let m = (wo + wi).normalize();
    let d = microfacet_d(b.distribution, a, m);
    let g = microfacet_g1(b.distribution, a, wo, m) * microfacet_g1(b.distribution, a, wi, m);
    reflectance(b, wo.dot(m)) * (d * g / (4.0 * wo.z))
}

pub fn pdf(b: &Bsdf, wo: Vec3, wi: Vec3) -> f32 {
    if b.alpha == 0.0 {
        return 0.0;
    }
    let m = (wo + wi).normalize();
    if wo.z <= 0.0 || wi.z <= 0.0 || wo.dot(m) <= 0.0 || wi.dot(m) <= 0.0 {
        return 0.0;
    }
    let a = microfacet_alpha(b.alpha);
    // The visible-normal density times the reflection Jacobian 1 / (4 wi.m), wi.m = wo.m.
    microfacet_d(b.distribution, a, m) * microfacet_g1(b.distribution, a, wo, m) / (4.0 * wo.z)
}

pub fn sample(b: &Bsdf, wo: Vec3, u: Vec2) -> Sample {
    if wo.z <= 0.0 {
        return Sample::failed(Vec3::Z);
    }
    if b.alpha == 0.0 {
        // The delta lobe is chosen with probability 1.
        return Sample {
            wi: Vec3::new(-wo.x, -wo.y, wo.z),
            weight: reflectance(b, wo.z),
            pdf: 1.0,
            delta: true,
        };
    }
    let a = microfacet_alpha(b.alpha);
    let m = microfacet_sample_visible(b.distribution, a, wo, u);
    let wi = 2.0 * wo.dot(m) * m - wo;
    let pdf = pdf(b, wo, wi);
    if pdf <= 0.0 {
        return Sample::failed(wi);
    }
    // f cos / pdf = F kd G1(wi, m): D and G1(wo, m) cancel.
    Sample {
        wi,
        weight: reflectance(b, wo.dot(m)) * microfacet_g1(b.distribution, a, wi, m),
        pdf,
        delta: false,
    }
}
