//! Sampling of the BSDF library's models (src/bsdf, the CPU twin of shaders/lib/bsdf*.wgsl):
//! chi-square tests of the sampled directions against `pdf`, the weights against eval / pdf,
//! and the delta lobes' directions and probabilities.

mod bsdf_support;
mod common;

use bsdf_support::{Case, Rng, cases, chi2_p_value, rounding_tolerance};
use glam::Vec3;
use passgraph::bsdf::frame::{basis, to_local};
use passgraph::bsdf::fresnel::fresnel_dielectric;
use passgraph::material::dielectric::relative_eta;
use passgraph::material::thin_dielectric::thin_reflectance;
use passgraph::material::{Sample, eval, is_delta, pdf, sample};
use passgraph::scene::{MATERIAL_CONDUCTOR, MATERIAL_DIELECTRIC, MATERIAL_THIN_DIELECTRIC};

const SAMPLES: usize = 200_000;
fn draw(case: &Case, seed: u64) -> Vec<Sample> {
    let mut rng = Rng::new(seed);
    (0..SAMPLES)
        .map(|_| {
            let u = rng.vec2();
            sample(&case.bsdf, case.n, case.outside, case.wo, u, rng.unit())
        })
        .collect()
}

/// Fails on a sampler whose directions do not follow `pdf` (a wrong Jacobian, a lobe
/// probability missing from pdf, visible normals sampled from the wrong distribution, a pdf
/// that does not integrate to the sampler's success probability).
#[test]
fn sampled_directions_follow_pdf_by_chi_square() {
    let mut report = String::new();
    for (i, case) in cases(false).iter().enumerate() {
        if is_delta(&case.bsdf) {
            continue;
        }
        let p = chi2_p_value(case, &draw(case, 500 + i as u64));
        report += &format!("{}: p {p:.3e}\n", case.name);
        assert!(
            p > bsdf_support::P_THRESHOLD,
            "{}: chi-square p-value {p}",
            case.name
        );
    }
    println!("{report}");
}

/// Fails on a sample whose weight is not f |cos| / pdf of the same direction, or whose pdf is
/// not pdf's (the integrator divides by pdf for MIS and trusts the weight). Bound:
/// `rounding_tolerance` (tests/bsdf_support).
#[test]
fn sample_weight_is_eval_over_pdf() {
    // The largest relative difference, and the largest as a fraction of its tolerance.
    let (mut worst, mut worst_fraction) = (0.0f32, 0.0f32);
    for (i, case) in cases(false).iter().enumerate() {
        for s in draw(case, 900 + i as u64).iter().take(20_000) {
            if s.delta || s.pdf <= 0.0 {
                continue;
            }
            let e = eval(&case.bsdf, case.n, case.outside, case.wo, s.wi);
            let p = pdf(&case.bsdf, case.n, case.outside, case.wo, s.wi);
            let expected = e / p;
            let tol = rounding_tolerance(case, s.wi);
            let rel = ((s.weight - expected).abs() / expected.abs().max(Vec3::splat(1e-6)))
                .max_element()
                .max((s.pdf - p).abs() / p);
            worst = worst.max(rel);
            worst_fraction = worst_fraction.max(rel / tol);
            assert!(
                rel <= tol,
                "{}: weight {} pdf {} but eval / pdf {expected} pdf {p} at {}",
                case.name,
                s.weight,
                s.pdf,
                s.wi
            );
        }
    }
    println!("largest relative difference {worst:e}, {worst_fraction:.3} of its tolerance");
}

/// Fails on a delta lobe that leaves in the wrong direction or with the wrong probability: the
/// smooth mirror's reflection (weight kd), the smooth dielectric's choice between reflection
/// (probability F) and refraction by Snell's law (weight tf eta_ti^2, pdf 1 - F), the thin
/// dielectric's between reflection (2F / (1 + F)) and passing straight through (weight tf). The
/// frequency of reflections is binomial: within 5 standard deviations of F.
#[test]
fn delta_lobes_reflect_and_refract_with_fresnel_probability() {
    for (i, case) in cases(false).iter().enumerate() {
        if !is_delta(&case.bsdf) {
            continue;
        }
        let frame = basis(case.n);
        let wo = to_local(&frame, case.wo);
        let samples = draw(case, 300 + i as u64);
        let mut reflected = 0usize;
        for s in &samples {
            assert!(s.delta, "{}: a smooth model's sample is delta", case.name);
            let wi = to_local(&frame, s.wi);
            if wi.z > 0.0 {
                reflected += 1;
                let mirror = Vec3::new(-wo.x, -wo.y, wo.z);
                assert!((wi - mirror).length() < 1e-5, "{}: mirror {wi}", case.name);
            } else if case.bsdf.kind == MATERIAL_THIN_DIELECTRIC {
                // Straight through, tinted.
                assert!((wi + wo).length() < 1e-5, "{}: through {wi}", case.name);
                assert_eq!(s.weight, case.bsdf.tf, "{}", case.name);
            } else {
                let eta = relative_eta(&case.bsdf, case.outside);
                let sin_o = Vec3::new(wo.x, wo.y, 0.0);
                let sin_i = Vec3::new(wi.x, wi.y, 0.0);
                assert!(
                    (sin_i + sin_o / eta).length() < 1e-5,
                    "{}: Snell's law at {wi}",
                    case.name
                );
                let eta_ti = 1.0 / eta;
                let expected = case.bsdf.tf * (eta_ti * eta_ti);
                assert!((s.weight - expected).abs().max_element() < 1e-6);
            }
        }
        let f = if case.bsdf.kind == MATERIAL_CONDUCTOR {
            1.0
        } else if case.bsdf.kind == MATERIAL_THIN_DIELECTRIC {
            thin_reflectance(&case.bsdf, wo.z) as f64
        } else {
            assert_eq!(case.bsdf.kind, MATERIAL_DIELECTRIC);
            fresnel_dielectric(wo.z, relative_eta(&case.bsdf, case.outside)).r as f64
        };
        let n = samples.len() as f64;
        let sd = (f * (1.0 - f) / n).sqrt();
        let freq = reflected as f64 / n;
        assert!(
            (freq - f).abs() <= 5.0 * sd + 1e-9,
            "{}: reflected {freq}, F {f}",
            case.name
        );
    }
}
