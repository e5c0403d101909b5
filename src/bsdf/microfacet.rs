//! The rough models' microfacet distribution chosen per material (`shaders/lib/microfacet.wgsl`):
//! GGX ([`super::ggx`]) or Beckmann ([`super::beckmann`]) by `Bsdf::distribution`, alpha
//! floored as Mitsuba floors both. Local frame, normal +z.

use super::beckmann::{beckmann_d, beckmann_g1, beckmann_pdf_visible, beckmann_sample_visible};
use super::ggx::{ggx_d, ggx_g1, ggx_pdf_visible, ggx_sample_visible};
use glam::{Vec2, Vec3};

/// The microfacet normal distribution of a rough model (`Material::distribution`), as Mitsuba
/// 3's `distribution` parameter; alpha means the same for both (Mitsuba uses it unmapped: the
/// RMS slope for Beckmann).
#[repr(u32)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Distribution {
    /// GGX (Trowbridge-Reitz): passgraph's default.
    #[default]
    Ggx = 0,
    /// Beckmann: Mitsuba's default.
    Beckmann = 1,
}

impl Distribution {
    /// The distribution of a `Material::distribution` value; unknown values read as GGX, as
    /// the shaders treat them.
    pub fn from_u32(value: u32) -> Distribution {
        if value == Distribution::Beckmann as u32 {
            Distribution::Beckmann
        } else {
            Distribution::Ggx
        }
    }

    /// Mitsuba's name for it (`<string name="distribution" value="...">`).
    pub fn mitsuba_name(self) -> &'static str {
        match self {
            Distribution::Ggx => "ggx",
            Distribution::Beckmann => "beckmann",
        }
    }

    /// The distribution Mitsuba names `name` (case-insensitive, as Mitsuba reads it).
    pub fn from_mitsuba_name(name: &str) -> Option<Distribution> {
        match name.to_ascii_lowercase().as_str() {
            "ggx" => Some(Distribution::Ggx),
            "beckmann" => Some(Distribution::Beckmann),
            _ => None,
        }
    }
}

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
