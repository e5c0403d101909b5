//! Thin dielectric (`shaders/lib/material/thin_dielectric.wgsl`): a sheet of index ior (outside 1)
//! too thin to see its two faces apart, as Mitsuba 3's thindielectric: light reflects with the
//! interreflected reflectance R' = R + T^2 R / (1 - R^2) = 2R / (1 + R) (R the Fresnel term at
//! the sheet's cosine, T = 1 - R) or passes straight through with 1 - R' tinted tf, without
//! refraction (a sheet shifts a ray, it does not turn it). Both lobes are delta and two-sided.
//! Local frame: normal +z on wo's side.

use crate::bsdf::fresnel::fresnel_dielectric;
use crate::material::bsdf::{Bsdf, Sample, sample_in_local_frame};
use crate::material::model::{Model, Space};
use crate::material::record::Material;
use glam::Vec3;

pub const KIND: u32 = 5;

/// Both lobes are delta: eval and pdf are 0.
pub const MODEL: Model = Model {
    name: "thin_dielectric",
    kind: KIND,
    space: Space::Local,
    eval: |_, _, _, _, _| Vec3::ZERO,
    pdf: |_, _, _, _, _| 0.0,
    sample: |b, n, _, wo, _, u_lobe| sample_in_local_frame(n, wo, |wo| sample(b, wo, u_lobe)),
    is_delta: |_| true,
    microfacet: false,
    specular: |_| true,
    table: None,
};

impl Material {
    /// A thin dielectric sheet (Mitsuba's `thindielectric`) of index `ior` relative to outside
    /// (Mitsuba's int_ior / ext_ior), its transmission tinted `specular_transmittance`.
    pub fn thin_dielectric(ior: f32, specular_transmittance: [f32; 3]) -> Material {
        Material {
            kind: KIND,
            ior,
            tf: specular_transmittance,
            ..Material::DEFAULT
        }
    }
}

/// The sheet's reflectance at `cos` (0..1): the first reflection and every one that escapes
/// after bouncing inside, R + T^2 R (1 + R^2 + R^4 + ...).
pub fn thin_reflectance(b: &Bsdf, cos: f32) -> f32 {
    let r = fresnel_dielectric(cos, b.ior).r;
    r * 2.0 / (1.0 + r)
}

/// `u_lobe < R'` reflects (weight 1), else passes through (weight tf; always at R' = 0, a
/// sheet of index 1: Mitsuba's null, src/scene/mitsuba_xml/bsdf.rs); the pdf is the chosen
/// lobe's probability.
pub fn sample(b: &Bsdf, wo: Vec3, u_lobe: f32) -> Sample {
    if wo.z <= 0.0 {
        return Sample::failed(Vec3::Z);
    }
    let r = thin_reflectance(b, wo.z);
    if u_lobe < r {
        return Sample {
            wi: Vec3::new(-wo.x, -wo.y, wo.z),
            weight: Vec3::ONE,
            pdf: r,
            delta: true,
        };
    }
    Sample {
        wi: -wo,
        weight: b.tf,
        pdf: 1.0 - r,
        delta: true,
    }
}
