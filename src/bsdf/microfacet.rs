//! The rough models' microfacet distribution chosen per material (`shaders/lib/microfacet.wgsl`):
//! GGX ([`super::ggx`]) or Beckmann ([`super::beckmann`]) by `Bsdf::distribution`, alpha
//! floored as Mitsuba floors both. Local frame, normal +z.

use super::beckmann::{beckmann_d, beckmann_g1, beckmann_pdf_visible, beckmann_sample_visible};
use super::ggx::{ggx_d, ggx_g1, ggx_pdf_visible, ggx_sample_visible};
use crate::scene::gpu_layout::Distribution;
use glam::{Vec2, Vec3};

/// Mitsuba's floor on alpha (its MicrofacetDistribution's, whatever the type).
pub fn microfacet_alpha(alpha: f32) -> f32 {
    alpha.max(1e-4)
}

pub fn microfacet_d(distribution: Distribution, alpha: f32, m: Vec3) -> f32 {
    match distribution {
        Distribution::Ggx => ggx_d(alpha, m),
        Distribution::Beckmann => beckmann_d(alpha, m),
    }
}

pub fn microfacet_g1(distribution: Distribution, alpha: f32, v: Vec3, m: Vec3) -> f32 {
    match distribution {
        Distribution::Ggx => ggx_g1(alpha, v, m),
        Distribution::Beckmann => beckmann_g1(alpha, v, m),
    }
}

pub fn microfacet_sample_visible(
    distribution: Distribution,
    alpha: f32,
    wi: Vec3,
    u: Vec2,
) -> Vec3 {
    match distribution {
        Distribution::Ggx => ggx_sample_visible(alpha, wi, u),
        Distribution::Beckmann => beckmann_sample_visible(alpha, wi, u),
    }
}

pub fn microfacet_pdf_visible(distribution: Distribution, alpha: f32, wi: Vec3, m: Vec3) -> f32 {
    match distribution {
        Distribution::Ggx => ggx_pdf_visible(alpha, wi, m),
        Distribution::Beckmann => beckmann_pdf_visible(alpha, wi, m),
    }
}
