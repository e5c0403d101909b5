//! The BSDF library's energy (src/bsdf, the CPU twin of shaders/lib/bsdf*.wgsl): white
//! furnace albedos from the samples' weights and from quadrature of eval.

mod bsdf_support;
mod common;

use bsdf_support::{Case, Rng, cases, grid, sampled_density};
use glam::Vec3;
use passgraph::bsdf::frame::basis;
use passgraph::material::dielectric::relative_eta;
use passgraph::material::metallic_roughness::table::SpecularAlbedoTable;
use passgraph::material::{eval, is_delta, pdf, sample};
use passgraph::scene::{
    Distribution, FRESNEL_NONE, MATERIAL_CONDUCTOR, MATERIAL_DIELECTRIC, MATERIAL_LAMBERT,
    MATERIAL_METALLIC_ROUGHNESS, MATERIAL_PHONG, MATERIAL_PLASTIC, MATERIAL_THIN_DIELECTRIC,
};

const SAMPLES: usize = 200_000;

/// Radiance transport scales the dielectric's transmitted samples by eta_ti^2 = 1 / eta^2
/// (eta relative to wo's side); this undoes it, leaving the fraction of energy transmitted.
fn undo_radiance_scaling(case: &Case, wi: Vec3) -> f64 {
    if case.bsdf.kind == MATERIAL_DIELECTRIC && wi.dot(case.n) < 0.0 {
        let eta = relative_eta(&case.bsdf, case.outside) as f64;
        eta * eta
    } else {
        1.0
    }
}

/// The albedo's Monte Carlo estimate from `SAMPLES` samples, all lobes and the non-delta
/// ones alone (both as means over all samples), and the standard errors of the two means.
struct Estimate {
    all: f64,
    all_se: f64,
    smooth: f64,
    smooth_se: f64,
}

fn estimate(case: &Case, seed: u64) -> Estimate {
    let mut rng = Rng::new(seed);
    let (mut s, mut s2, mut t, mut t2) = (0.0, 0.0, 0.0, 0.0);
    for _ in 0..SAMPLES {
        let u = rng.vec2();
        let smp = sample(&case.bsdf, case.n, case.outside, case.wo, u, rng.unit());
        let w = smp.weight.x as f64 * undo_radiance_scaling(case, smp.wi);
        s += w;
        s2 += w * w;
        if !smp.delta {
            t += w;
            t2 += w * w;
        }
    }
    let n = SAMPLES as f64;
    let se = |sum: f64, sum2: f64| ((sum2 / n - (sum / n).powi(2)).max(0.0) / (n - 1.0)).sqrt();
    Estimate {
        all: s / n,
        all_se: se(s, s2),
        smooth: t / n,
        smooth_se: se(t, t2),
    }
}

/// The integral of eval (f |cos|, radiance scaling undone) over the sphere, and an estimate of
/// its error; with `as_sampled`, of eval times the sampler's density over pdf
/// (`sampled_density`: 1 but for Beckmann's masking fit), what the mean weight estimates.
fn quadrature(case: &Case, as_sampled: bool) -> (f64, f64) {
    let frame = basis(case.n);
    let (cells, error) = grid().integrate(|local| {
        let wi = frame * local;
        let e = eval(&case.bsdf, case.n, case.outside, case.wo, wi).x as f64;
        let mut value = e * undo_radiance_scaling(case, wi);
        if as_sampled && e > 0.0 {
            let p = f64::from(pdf(&case.bsdf, case.n, case.outside, case.wo, wi));
            if p > 0.0 {
                value *= sampled_density(case, wi) / p;
            }
        }
        value
    });
    (cells.iter().sum(), error)
}

/// E(wo) - E_table(wo) of a metallic-roughness case's dielectric layer: what its base gets too
/// much (negative: too little), times 1 - metallic.
fn layer_table_excess_signed(case: &Case) -> f64 {
    let b = &case.bsdf;
    let mu = case.wo.dot(case.n);
    let r = b.alpha.sqrt();
    let table = SpecularAlbedoTable::shared();
    let difference =
        SpecularAlbedoTable::exact(f64::from(mu), f64::from(r)) - f64::from(table.albedo(mu, r));
    difference * f64::from(1.0 - b.ks.x)
}

/// The positive part of [`layer_table_excess_signed`]: energy the table can create.
fn layer_table_excess(case: &Case) -> f64 {
    layer_table_excess_signed(case).max(0.0)
}

/// The model loses no energy at all with white parameters (each sample's weight is 1): Lambert,
/// the smooth mirror, the smooth dielectric with its radiance scaling undone, and the thin
/// dielectric (R' + (1 - R') = 1).
fn conserves_exactly(case: &Case) -> bool {
    let b = &case.bsdf;
    // A complex-index conductor absorbs by physics (its Fresnel term is below 1).
    if b.kind == MATERIAL_CONDUCTOR && b.fresnel != FRESNEL_NONE {
        return false;
    }
    b.kind == MATERIAL_LAMBERT
        || b.kind == MATERIAL_THIN_DIELECTRIC
        || (b.alpha == 0.0 && (b.kind == MATERIAL_CONDUCTOR || b.kind == MATERIAL_DIELECTRIC))
}

/// Fails on a model that creates energy (a missing 1/pi or Jacobian, a Fresnel term applied
/// once too few), on a lossless model that loses energy, and on samples whose weights disagree
/// with eval (the quadrature of eval and the mean weight of the non-delta samples estimate the
/// same integral). Bounds: 5 standard errors of the mean (a false failure once in 1.7 million)
/// plus, for the quadrature, its own error (the adaptive rule's estimate, its accepted
/// differences between levels).
#[test]
fn white_furnace_albedo_is_at_most_one_and_one_where_energy_is_conserved() {
    let mut report = String::new();
    for (i, case) in cases(true).iter().enumerate() {
        let e = estimate(case, 1000 + i as u64);
        let mut line = format!("{}: albedo {:.5} +- {:.5}", case.name, e.all, e.all_se);
        // Rounding of f32 weights near 1 (eta_ti^2 eta^2 is not exactly 1 in f32). White
        // plastic conserves energy up to the fit of the internal diffuse Fresnel reflectance
        // (Egan and Hilgeman: 0.1% relative for eta 1 to 1.5, 0.15% of the albedo through
        // 1 / (1 - F_dr)); 2e-3 bounds it.
        let rounding = 1e-5;
        // Beckmann's masking is Mitsuba's rational fit of G1 (relative error below 0.35 %),
        // one factor per direction in eval: 7e-3 of the albedo.
        let fit = if case.bsdf.kind == MATERIAL_METALLIC_ROUGHNESS {
            layer_table_excess(case) + rounding
        } else if case.bsdf.distribution == Distribution::Beckmann && case.bsdf.alpha > 0.0 {
            7e-3
        } else if case.bsdf.kind == MATERIAL_PLASTIC {
            2e-3
        } else {
            rounding
        };
        // The seed's Phong keeps its normalisation (ns + 8) / (8 pi), an approximation that
        // reflects a few percent more than it receives near normal incidence (white, ns 10:
        // 1.037); only its samples' agreement with eval is checked.
        assert!(
            case.bsdf.kind == MATERIAL_PHONG || e.all <= 1.0 + 5.0 * e.all_se + fit,
            "{}: albedo {} exceeds 1 (standard error {})",
            case.name,
            e.all,
            e.all_se
        );
        if conserves_exactly(case) {
            assert!(
                (e.all - 1.0).abs() <= 5.0 * e.all_se + rounding,
                "{}: albedo {} should be 1",
                case.name,
                e.all
            );
        }
        if case.bsdf.kind == MATERIAL_METALLIC_ROUGHNESS && case.bsdf.ks.x == 0.0 {
            // The dielectric's base gets 1 - E_table(wo) and its layer reflects E(wo): the
            // albedo is 1 plus the table's under-estimate of E (the reference rule's error
            // is below 1e-5: 128 and 256 nodes agree to 8e-6 at the worst case).
            let expected = 1.0 + layer_table_excess_signed(case);
            assert!(
                (e.all - expected).abs() <= 5.0 * e.all_se + 2e-5,
                "{}: albedo {} should be {expected} (1 + the table's error)",
                case.name,
                e.all
            );
        }
        if case.bsdf.kind == MATERIAL_PLASTIC && case.bsdf.table.is_none() {
            assert!(
                (e.all - 1.0).abs() <= 5.0 * e.all_se + fit,
                "{}: albedo {} should be 1 within the fit's error",
                case.name,
                e.all
            );
        }
        if !is_delta(&case.bsdf) {
            let (q, q_error) = quadrature(case, false);
            let (q_sampled, q_sampled_error) = if case.bsdf.distribution == Distribution::Beckmann {
                quadrature(case, true)
            } else {
                (q, q_error)
            };
            line += &format!(", quadrature {q:.5} (+- {q_error:.1e})");
            assert!(
                case.bsdf.kind == MATERIAL_PHONG || q <= 1.0 + q_error + fit,
                "{}: quadrature albedo {q} exceeds 1",
                case.name
            );
            let (q, q_error) = (q_sampled, q_sampled_error);
            assert!(
                (q - e.smooth).abs() <= 5.0 * e.smooth_se + q_error + 1e-5,
                "{}: quadrature {q} (error {q_error}) against the samples' {} +- {}",
                case.name,
                e.smooth,
                e.smooth_se
            );
        }
        report += &line;
        report += "\n";
    }
    println!("{report}");
}

/// Mitsuba 3's white roughplastic albedos (tests/data/bsdf/mitsuba_furnace.txt: alpha, ior,
/// cos wo, the mean of 200 000 of its samples' weights and its standard error).
fn mitsuba_furnace() -> Vec<(Distribution, f32, f32, f32, f64, f64)> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/bsdf/mitsuba_furnace.txt");
    std::fs::read_to_string(path)
        .expect("the Mitsuba furnace table")
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|l| {
            let mut fields = l.split_whitespace();
            let d = fields.next().and_then(Distribution::from_mitsuba_name);
            let v: Vec<f64> = fields.map(|f| f.parse().expect("a number")).collect();
            let d = d.expect("ggx or beckmann");
            (d, v[0] as f32, v[1] as f32, v[2] as f32, v[3], v[4])
        })
        .collect()
}

/// Fails when rough plastic loses or gains energy Mitsuba 3's roughplastic does not (its
/// albedo is well below 1: the single-scattering GGX coat loses what its masking stops, more
/// as alpha grows). White (kd = ks = 1) rough plastic's albedo from our samples' weights
/// against Mitsuba's own, at each (alpha, ior, cos wo) Mitsuba's table holds. Bound: 5
/// standard errors of the difference of the two independent means (a false failure once in
/// 1.7 million), plus 1e-4 for the tables' f32 rounding and the f32 sampling's.
#[test]
fn white_rough_plastic_albedo_matches_mitsuba() {
    let mut report = String::new();
    let rows = mitsuba_furnace();
    assert!(rows.len() >= 36, "the whole table");
    for (i, &(distribution, alpha, ior, cos_o, albedo, se)) in rows.iter().enumerate() {
        let n = bsdf_support::tilted_normal();
        let case = Case {
            name: format!("rough plastic {distribution:?} alpha {alpha} ior {ior}, cos wo {cos_o}"),
            bsdf: bsdf_support::bsdf_with(
                distribution,
                MATERIAL_PLASTIC,
                Vec3::ONE,
                Vec3::ONE,
                0.0,
                alpha,
                ior,
                Vec3::ZERO,
            ),
            n,
            outside: true,
            wo: bsdf_support::incident(n, cos_o),
        };
        let e = estimate(&case, 5000 + i as u64);
        let bound = 5.0 * (e.all_se * e.all_se + se * se).sqrt() + 1e-4;
        report += &format!(
            "{}: albedo {:.5} +- {:.5}, Mitsuba {albedo:.5} +- {se:.5}\n",
            case.name, e.all, e.all_se
        );
        assert!(
            (e.all - albedo).abs() <= bound,
            "{}: albedo {} but Mitsuba's {albedo} (bound {bound})",
            case.name,
            e.all
        );
    }
    println!("{report}");
}
