//! The isotropic GGX microfacet distribution (`shaders/lib/ggx.wgsl`), as Mitsuba 3's
//! MicrofacetDistribution with type ggx and sample_visible true. Local frame, normal +z.

use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// Mitsuba's floor on alpha.
pub fn ggx_alpha(alpha: f32) -> f32 {
    alpha.max(1e-4)
}

/// D(m).
pub fn ggx_d(alpha: f32, m: Vec3) -> f32 {
    let a2 = alpha * alpha;
    let t = (m.x * m.x) / a2 + (m.y * m.y) / a2 + m.z * m.z;
    let d = 1.0 / (PI * a2 * t * t);
    // A tiny D times cos would underflow downstream terms.
    if d * m.z > 1e-20 { d } else { 0.0 }
}

/// Smith's masking G1(v, m); 0 when v sees m's back.
pub fn ggx_g1(alpha: f32, v: Vec3, m: Vec3) -> f32 {
    let xy = alpha * alpha * (v.x * v.x + v.y * v.y);
    let tan2 = xy / (v.z * v.z);
    let mut g = 2.0 / (1.0 + (1.0 + tan2).sqrt());
    if xy == 0.0 {
        g = 1.0;
    }
    if v.dot(m) * v.z <= 0.0 {
        g = 0.0;
    }
    g
}

/// A normal from the distribution of normals visible from `wi` (wi.z > 0), Heitz 2018; its
/// density is [`ggx_pdf_visible`].
pub fn ggx_sample_visible(alpha: f32, wi: Vec3, u: Vec2) -> Vec3 {
    let vh = Vec3::new(alpha * wi.x, alpha * wi.y, wi.z).normalize();
    let lensq = vh.x * vh.x + vh.y * vh.y;
    // Below 1e-12 (|xy| < 1e-6) wi's azimuth is rounding noise: a fixed tangent makes the same u
    // give the same direction on every device.
    let mut t1 = Vec3::X;
    if lensq > 1e-12 {
        t1 = Vec3::new(-vh.y, vh.x, 0.0) / lensq.sqrt();
    }
    let t2 = vh.cross(t1);
    let r = u.x.sqrt();
    let phi = 2.0 * PI * u.y;
    let p1 = r * phi.cos();
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * (r * phi.sin());
    let nh = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * vh;
    Vec3::new(alpha * nh.x, alpha * nh.y, nh.z.max(0.0)).normalize()
}

/// Density of [`ggx_sample_visible`]: D(m) G1(wi, m) |wi.m| / wi.z.
pub fn ggx_pdf_visible(alpha: f32, wi: Vec3, m: Vec3) -> f32 {
    ggx_d(alpha, m) * ggx_g1(alpha, wi, m) * wi.dot(m).abs() / wi.z
}
