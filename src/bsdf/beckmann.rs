//! The isotropic Beckmann microfacet distribution (`shaders/lib/beckmann.wgsl`), as Mitsuba 3's
//! MicrofacetDistribution with type beckmann and sample_visible true: alpha is the RMS slope,
//! used as given (floored at 1e-4 as Mitsuba floors it: `microfacet_alpha`), Smith's masking by
//! Mitsuba's rational approximation, visible normals by Jakob 2014's numerical inversion.
//! Local frame, normal +z.

use super::erf::{erf, erfinv};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// 1 / sqrt(pi).
const INV_SQRT_PI: f32 = 0.564_189_6;

/// D(m) = exp(-tan^2 / alpha^2) / (pi alpha^2 cos^4); 0 for m below the horizon.
pub fn beckmann_d(alpha: f32, m: Vec3) -> f32 {
    if m.z <= 0.0 {
        return 0.0;
    }
    let cos2 = m.z * m.z;
    let xy = (m.x / alpha) * (m.x / alpha) + (m.y / alpha) * (m.y / alpha);
    let d = (-xy / cos2).exp() / (PI * alpha * alpha * cos2 * cos2);
    // A tiny D times cos would underflow downstream terms (Mitsuba's cut).
    if d * m.z > 1e-20 { d } else { 0.0 }
}

/// Smith's masking G1(v, m) by Mitsuba's rational fit in a = 1 / (alpha tan theta_v) (its
/// stated relative error below 0.35 %, exact 1 from a = 1.6); 0 when v sees m's back.
pub fn beckmann_g1(alpha: f32, v: Vec3, m: Vec3) -> f32 {
    let xy = alpha * alpha * (v.x * v.x + v.y * v.y);
    let mut g = 1.0;
    if xy > 0.0 {
        let a = (v.z * v.z / xy).sqrt();
        if a < 1.6 {
            g = (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a);
        }
    }
    if v.dot(m) * v.z <= 0.0 {
        g = 0.0;
    }
    g
}

/// Slopes from the visible slopes of the alpha = 1 distribution seen at cos_theta_i (Jakob
/// 2014: the x slope by three Newton steps on its CDF in the erf domain from an analytic first
/// guess, the y slope by inverting the Gaussian's CDF), as Mitsuba's sample_visible_11.
fn sample_visible_11(cos_theta_i: f32, u: Vec2) -> Vec2 {
    let sin_theta_i = (1.0 - cos_theta_i * cos_theta_i).max(0.0).sqrt();
    let tan_theta_i = sin_theta_i / cos_theta_i;
    // At normal incidence cot is infinite; 1e7 keeps every term finite and exact in f32
    // (erf(1e7) = 1, exp(-1e14) = 0) on every device.
    let cot_theta_i = cos_theta_i / sin_theta_i.max(1e-7);
    let maxval = erf(cot_theta_i);
    let u = u.clamp(Vec2::splat(1e-6), Vec2::splat(1.0 - 1e-6));
    let mut x = maxval - (maxval + 1.0) * erf((-u.x.ln()).sqrt());
    let target =
        u.x * (1.0 + maxval + INV_SQRT_PI * tan_theta_i * (-cot_theta_i * cot_theta_i).exp());
    for _ in 0..3 {
        let slope = erfinv(x);
        let value = 1.0 + x + INV_SQRT_PI * tan_theta_i * (-slope * slope).exp() - target;
        let derivative = 1.0 - slope * tan_theta_i;
        x -= value / derivative;
    }
    Vec2::new(erfinv(x), erfinv(2.0 * u.y - 1.0))
}

/// A normal from the distribution of normals visible from `wi` (wi.z > 0): stretch wi by
/// alpha, sample the alpha = 1 slopes, rotate them to wi's azimuth and unstretch; its density
/// is [`beckmann_pdf_visible`] (up to the masking fit, see [`beckmann_g1`]).
pub fn beckmann_sample_visible(alpha: f32, wi: Vec3, u: Vec2) -> Vec3 {
    let wi_p = Vec3::new(alpha * wi.x, alpha * wi.y, wi.z).normalize();
    let lensq = wi_p.x * wi_p.x + wi_p.y * wi_p.y;
    // Below 1e-12 (|xy| < 1e-6) wi's azimuth is rounding noise: a fixed one makes the same u
    // give the same direction on every device.
    let (mut cos_phi, mut sin_phi) = (1.0, 0.0);
    if lensq > 1e-12 {
        let inv = 1.0 / lensq.sqrt();
        cos_phi = wi_p.x * inv;
        sin_phi = wi_p.y * inv;
    }
    let s = sample_visible_11(wi_p.z, u);
    let slope_x = (cos_phi * s.x - sin_phi * s.y) * alpha;
    let slope_y = (sin_phi * s.x + cos_phi * s.y) * alpha;
    Vec3::new(-slope_x, -slope_y, 1.0).normalize()
}

/// Density of the visible normals: D(m) G1(wi, m) |wi.m| / wi.z.
pub fn beckmann_pdf_visible(alpha: f32, wi: Vec3, m: Vec3) -> f32 {
    beckmann_d(alpha, m) * beckmann_g1(alpha, wi, m) * wi.dot(m).abs() / wi.z
}
