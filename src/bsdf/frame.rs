//! Directions around a normal, as `shaders/lib/sampling.wgsl` computes them.

use glam::{Mat3, Vec3};
use std::f32::consts::PI;

/// An orthonormal basis around unit `n` (n the third column), branch-free (Duff et al. 2017):
/// `basis` in sampling.wgsl.
pub fn basis(n: Vec3) -> Mat3 {
    let s = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    let t = Vec3::new(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    let bt = Vec3::new(b, s + n.y * n.y * a, -n.y);
    Mat3::from_cols(t, bt, n)
}

/// `v` in the frame's coordinates (WGSL `v * frame`).
pub fn to_local(frame: &Mat3, v: Vec3) -> Vec3 {
    Vec3::new(
        v.dot(frame.x_axis),
        v.dot(frame.y_axis),
        v.dot(frame.z_axis),
    )
}

/// A cosine-weighted direction around `n` (pdf cos / pi), Malley's method: `sample_cosine`.
pub fn sample_cosine(n: Vec3, u1: f32, u2: f32) -> Vec3 {
    let r = u1.sqrt();
    let phi = 2.0 * PI * u2;
    let local = Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u1).max(0.0).sqrt());
    (basis(n) * local).normalize()
}
