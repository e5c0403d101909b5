//! Reciprocity of the BSDF library's models (src/bsdf, the CPU twin of shaders/lib/bsdf*.wgsl):
//! f(wo, wi) = f(wi, wo), f = eval / |n.wi|. All five models are reciprocal as Mitsuba 3 writes
//! them: Lambert and Phong (n.h is symmetric), GGX reflection (D G / (4 cos cos) and F at
//! wi.m = wo.m), plastic ((1 - F(wo)) (1 - F(wi)) is symmetric), and rough plastic as Mitsuba 3's
//! roughplastic writes it (its specular lobe is GGX reflection; its diffuse lobe is
//! t(cos_o) t(cos_i) kd / (pi eta^2 (1 - internal reflectance)), symmetric in the two
//! directions, the same table read at each). The dielectric's transmission
//! in radiance transport obeys the generalised form f(wo, wi) / eta_wo^2 = f(wi, wo) / eta_wi^2,
//! eta the absolute index on each direction's side.

mod bsdf_support;
mod common;

use bsdf_support::{Rng, materials, tilted_normal};
use glam::Vec3;
use passgraph::material::{Bsdf, eval};
use passgraph::scene::MATERIAL_DIELECTRIC;

/// f(wo, wi): eval without its cosine.
fn f(b: &Bsdf, n: Vec3, outside: bool, wo: Vec3, wi: Vec3) -> f32 {
    eval(b, n, outside, wo, wi).x / n.dot(wi).abs()
}

/// Fails on a model whose eval is not symmetric where the physics is (a cosine divided by the
/// wrong direction's, a Fresnel term of only one side, a transmission missing its eta^2). Bound:
/// f32 evaluation of the same expression in two orders; the GGX D at alpha 0.01 amplifies the
/// half vector's rounding (a few ulps) by up to 4 m_xy^2 / alpha^2 ~ 1e2 near the peak, so
/// 1e-4 relative (about 800 ulps) with a 1e-6 absolute floor for values near zero. Transmission
/// adds the Fresnel term's conditioning near the critical angle: from the dense side, (1 - F)
/// goes as cos_t = sqrt(1 - eta^2 sin^2), whose f32 rounding (a few epsilon absolute in cos_t^2)
/// is a relative error of about 1e-6 / cos_t^2, cos_t = |w.m| of the direction on the thin side.
#[test]
fn eval_is_reciprocal_with_the_dielectric_eta_squared() {
    let n = tilted_normal();
    let mut rng = Rng::new(7);
    // The largest relative asymmetry of reflections, and of transmissions against their bound.
    let (mut worst, mut worst_t) = (0.0f32, 0.0f32);
    for (name, b, outside) in materials(false) {
        for _ in 0..5000 {
            let mut wo = rng.sphere();
            let mut wi = rng.sphere();
            if wo.dot(n) < 0.0 {
                wo = -wo;
            }
            let transmits = b.kind == MATERIAL_DIELECTRIC && wi.dot(n) < 0.0;
            if !transmits && wi.dot(n) < 0.0 {
                wi = -wi;
            }
            let forward = f(&b, n, outside, wo, wi);
            let mut bound = 1e-4;
            let (backward, scale) = if transmits {
                let eta = if outside { b.ior } else { 1.0 / b.ior };
                let m = (wo + eta * wi).normalize();
                let thin_side = if outside { wo } else { wi };
                bound += 1e-6 / thin_side.dot(m).powi(2);
                // Seen from wi's side: the normal turned to it, the other side of the surface.
                let (ior_o, ior_i) = if outside { (1.0, b.ior) } else { (b.ior, 1.0) };
                let back = f(&b, -n, !outside, wi, wo);
                (back, (ior_o * ior_o) / (ior_i * ior_i))
            } else {
                (f(&b, n, outside, wi, wo), 1.0)
            };
            let expected = backward * scale;
            let diff = (forward - expected).abs();
            let bound = bound * forward.abs().max(expected.abs()) + 1e-6;
            if transmits {
                worst_t = worst_t.max(diff / bound);
            } else {
                worst = worst.max(diff / (forward.abs().max(expected.abs()) + 1e-6));
            }
            assert!(
                diff <= bound,
                "{name}: f(wo, wi) {forward} vs f(wi, wo) {backward} x {scale} at wo {wo} wi {wi}"
            );
        }
    }
    println!(
        "reflection: largest relative asymmetry {worst:e}; transmission: {worst_t:.3} of the bound"
    );
}
