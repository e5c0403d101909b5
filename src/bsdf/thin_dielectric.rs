//! Thin dielectric (`shaders/lib/bsdf_thin_dielectric.wgsl`): a sheet of index ior (outside 1)
//! too thin to see its two faces apart, as Mitsuba 3's thindielectric: light reflects with the
//! interreflected reflectance R' = R + T^2 R / (1 - R^2) = 2R / (1 + R) (R the Fresnel term at
//! the sheet's cosine, T = 1 - R) or passes straight through with 1 - R' tinted tf, without
//! refraction (a sheet shifts a ray, it does not turn it). Both lobes are delta and two-sided.
//! Local frame: normal +z on wo's side.

use super::Bsdf;
use super::Sample;
use super::fresnel::fresnel_dielectric;
use glam::Vec3;

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
