//! Conductor (`shaders/lib/material/conductor.wgsl`): a mirror tinted kd, microfacet-rough when
//! alpha > 0, a delta mirror when alpha = 0, as Mitsuba 3's roughconductor / conductor,
//! two-sided: with `fresnel` FRESNEL_NONE its material none (Fresnel 1) with
//! specular_reflectance kd, with FRESNEL_CONDUCTOR kd times the Fresnel term of the complex index
//! eta + i k. Local frame: normal +z, wo.z >= 0.

pub mod presets;

use crate::bsdf::fresnel::fresnel_conductor;
use crate::bsdf::microfacet::{
    Distribution, microfacet_alpha, microfacet_d, microfacet_g1, microfacet_sample_visible,
};
use crate::material::bsdf::{Bsdf, Sample, in_local_frame, sample_in_local_frame};
use crate::material::model::{Model, Space};
use crate::material::record::{FRESNEL_CONDUCTOR, Material};
use glam::{Vec2, Vec3};

pub const KIND: u32 = 2;

pub const MODEL: Model = Model {
    name: "conductor",
    kind: KIND,
    space: Space::Local,
    eval: |b, n, _, wo, wi| in_local_frame(n, wo, wi, |wo, wi| eval(b, wo, wi)),
    pdf: |b, n, _, wo, wi| in_local_frame(n, wo, wi, |wo, wi| pdf(b, wo, wi)),
    sample: |b, n, _, wo, u, _| sample_in_local_frame(n, wo, |wo| sample(b, wo, u)),
    is_delta: |b| b.alpha == 0.0,
    microfacet: true,
    specular: |_| true,
    table: None,
};

impl Material {
    /// A conductor (Mitsuba's `conductor` / `roughconductor`): roughness `alpha` (0: smooth),
    /// `specular_reflectance` the tint kd, and `ior` its complex index (eta, k) per RGB channel
    /// ([`presets::conductor_preset`] has Mitsuba's named ones), or
    /// `None` for Mitsuba's material none (Fresnel 1).
    pub fn conductor(
        specular_reflectance: [f32; 3],
        alpha: f32,
        distribution: Distribution,
        ior: Option<(Vec3, Vec3)>,
    ) -> Material {
        let mut m = Material {
            kind: KIND,
            kd: specular_reflectance,
            alpha,
            distribution: distribution as u32,
            ..Material::DEFAULT
        };
        if let Some((eta, k)) = ior {
            m.eta = eta.to_array();
            m.k = k.to_array();
            m.fresnel = FRESNEL_CONDUCTOR;
        }
        m
    }

    /// Whether this is a conductor with a complex-index Fresnel term (the
    /// `scene_has_conductor_fresnel` override).
    pub fn uses_conductor_fresnel(&self) -> bool {
        self.kind == KIND && self.fresnel == FRESNEL_CONDUCTOR
    }
}

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
