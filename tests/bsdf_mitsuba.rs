//! The BSDF library's CPU twin (src/bsdf) against Mitsuba 3 itself: eval and pdf at fixed
//! directions, from tests/data/bsdf/mitsuba_table.txt (written by scripts/bsdf-mitsuba-table
//! with Mitsuba 3.9.0, scalar_rgb: twosided + diffuse, twosided + roughconductor with
//! material none, with material Au and with RGB eta and k, twosided + plastic and roughplastic
//! with nonlinear false, roughdielectric; ggx and beckmann, sample_visible, ext_ior 1).

mod bsdf_support;
mod common;

use bsdf_support::bsdf_with;
use glam::Vec3;
use passgraph::material::{Bsdf, eval, pdf};
use passgraph::scene::{Distribution, FRESNEL_CONDUCTOR, MATERIAL_CONDUCTOR};
use std::cell::RefCell;
use std::collections::HashMap;
use std::path::Path;

struct Row {
    case: String,
    bsdf: Bsdf,
    wo: Vec3,
    wi: Vec3,
    eval: Vec3,
    pdf: f32,
}

/// A distribution by Mitsuba's name for it.
fn distribution(name: &str) -> Distribution {
    Distribution::from_mitsuba_name(name).expect("ggx or beckmann")
}

/// The row's Bsdf, a rough plastic's tables computed once per case; a conductor whose (eta, k)
/// is not Mitsuba's material none (0, 1) gets the complex-index Fresnel term.
#[allow(clippy::too_many_arguments)]
fn cached(
    kind: u32,
    distribution: Distribution,
    alpha: f32,
    ior: f32,
    kd: Vec3,
    ks: Vec3,
    tf: Vec3,
    (eta, k): (Vec3, Vec3),
) -> Bsdf {
    thread_local! {
        static TABLES: RefCell<HashMap<(u32, Distribution, u32, u32), Bsdf>> =
            RefCell::new(HashMap::new());
    }
    let base = TABLES.with(|t| {
        *t.borrow_mut()
            .entry((kind, distribution, alpha.to_bits(), ior.to_bits()))
            .or_insert_with(|| bsdf_with(distribution, kind, kd, ks, 0.0, alpha, ior, tf))
    });
    let mut b = Bsdf { kd, ks, tf, ..base };
    if kind == MATERIAL_CONDUCTOR && (eta != Vec3::ZERO || k != Vec3::ONE) {
        b.fresnel = FRESNEL_CONDUCTOR;
        b.eta = eta;
        b.k = k;
    }
    b
}

fn rows() -> Vec<Row> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/bsdf/mitsuba_table.txt");
    let text = std::fs::read_to_string(&path).expect("the Mitsuba table");
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|line| {
            let mut fields = line.split_whitespace();
            let case = fields.next().expect("case").to_string();
            let kind: u32 = fields.next().expect("kind").parse().expect("a kind");
            let distribution = distribution(fields.next().expect("distribution"));
            let v: Vec<f32> = fields.map(|f| f.parse().expect("a number")).collect();
            let v3 = |i: usize| Vec3::new(v[i], v[i + 1], v[i + 2]);
            Row {
                case,
                bsdf: cached(
                    kind,
                    distribution,
                    v[0],
                    v[1],
                    v3(2),
                    v3(5),
                    v3(8),
                    (v3(11), v3(14)),
                ),
                wo: v3(17),
                wi: v3(20),
                eval: v3(23),
                pdf: v[26],
            }
        })
        .collect()
}

/// Fails when a model's formula departs from the Mitsuba 3 plugin it matches (a Fresnel term,
/// a Jacobian, a lobe probability, the radiance scaling, the sides a model answers on). The
/// table's directions are in the local frame, so the twin sees them unrotated (n = +z, or -z
/// with outside false for the dielectric seen from inside). Bound: both compute in f32 with
/// equivalent expressions in different orders; relative 1e-4 (the GGX D's amplification of
/// rounding at alpha 0.01, see bsdf_reciprocity.rs) with a 1e-6 absolute floor.
#[test]
fn eval_and_pdf_match_mitsuba_3() {
    let rows = rows();
    assert!(rows.len() > 300, "the whole table");
    let mut nonzero = 0;
    let mut worst = 0.0f32;
    for r in &rows {
        let outside = r.wo.z > 0.0;
        let n = if outside { Vec3::Z } else { -Vec3::Z };
        let e = eval(&r.bsdf, n, outside, r.wo, r.wi);
        let p = pdf(&r.bsdf, n, outside, r.wo, r.wi);
        let mut close = |a: f32, b: f32| {
            let rel = (a - b).abs() / (a.abs().max(b.abs()) + 1e-6);
            worst = worst.max(rel);
            (a - b).abs() <= 1e-4 * a.abs().max(b.abs()) + 1e-6
        };
        for k in 0..3 {
            assert!(
                close(e[k], r.eval[k]),
                "{}: eval {e} but Mitsuba {} at wo {} wi {}",
                r.case,
                r.eval,
                r.wo,
                r.wi
            );
        }
        assert!(
            close(p, r.pdf),
            "{}: pdf {p} but Mitsuba {} at wo {} wi {}",
            r.case,
            r.pdf,
            r.wo,
            r.wi
        );
        if r.eval.x > 1e-4 {
            nonzero += 1;
        }
    }
    // The table is only a check where Mitsuba's values are not all zero.
    assert!(nonzero > 150, "{nonzero} rows with a lobe");
    println!(
        "{} rows, {nonzero} non-zero, largest relative difference {worst:e}",
        rows.len()
    );
}

/// Fails when the rough plastic's tables (src/bsdf/plastic_tables.rs) depart from Mitsuba 3's
/// roughplastic's: a quadrature rule, a sampler mapping, a Fresnel argument or the internal
/// reflectance's average differing. Mitsuba does not expose the tables, so its diffuse lobe
/// alone (tests/data/bsdf/mitsuba_plastic_tables.txt: kd 1, wo on the normal, wi at each table
/// cosine i / 63) gives them: cos / (pi eta^2) t(1) t(cos) / (1 - internal reflectance), so each
/// entry relative to t(1), and t(1)^2 / (1 - R). (t alone also sets the lobe probability, which
/// the table's pdf rows check at other cosines.) Bound: Mitsuba integrates in f32, up to 128^2
/// terms summed in order (rounding about 128 x 6e-8 = 8e-6 relative) and reads the table in
/// f32; ours is f64 rounded to f32: 1e-5 relative (measured: 4e-6).
#[test]
fn rough_plastic_tables_match_mitsuba_3() {
    use passgraph::material::plastic::tables::PlasticTable;
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/bsdf/mitsuba_plastic_tables.txt");
    let text = std::fs::read_to_string(&path).expect("the Mitsuba tables");
    let mut tables: HashMap<(Distribution, u32, u32), PlasticTable> = HashMap::new();
    let mut worst = 0.0f64;
    let mut count = 0;
    for line in text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
    {
        let mut fields = line.split_whitespace();
        let d = distribution(fields.next().expect("distribution"));
        let v: Vec<f64> = fields.map(|f| f.parse().expect("a number")).collect();
        let (alpha, ior, cos, mitsuba) = (v[0] as f32, v[1] as f32, v[2], v[3]);
        let t = tables
            .entry((d, alpha.to_bits(), ior.to_bits()))
            .or_insert_with(|| PlasticTable::compute(d, alpha, ior));
        let eta = f64::from(ior);
        let ours = cos / (std::f64::consts::PI * eta * eta)
            * f64::from(t.transmittance_at(1.0))
            * f64::from(t.transmittance_at(cos as f32))
            / (1.0 - f64::from(t.internal_reflectance));
        let rel = (ours - mitsuba).abs() / mitsuba.abs();
        worst = worst.max(rel);
        count += 1;
        assert!(
            rel <= 1e-5,
            "alpha {alpha} ior {ior} cos {cos}: ours {ours} but Mitsuba {mitsuba} ({rel:e})"
        );
    }
    assert!(count >= 12 * 63, "the whole table");
    println!("{count} table values, largest relative difference {worst:e}");
}

/// Fails when the thin dielectric departs from Mitsuba 3's thindielectric
/// (tests/data/bsdf/mitsuba_thin.txt: its sample at u_lobe 0, the reflection, and 1 - 1e-6, the
/// transmission, from four incidences at two indices): the interreflected reflectance 2R / (1 +
/// R) as the reflection's probability, the straight-through direction, the tint on the
/// transmission alone. Bound: the same f32 expressions in another order, 1e-5 relative.
#[test]
fn thin_dielectric_samples_match_mitsuba_3() {
    use passgraph::material::sample;
    use passgraph::scene::MATERIAL_THIN_DIELECTRIC;
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/bsdf/mitsuba_thin.txt");
    let text = std::fs::read_to_string(&path).expect("the Mitsuba thin table");
    let mut count = 0;
    for line in text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
    {
        let v: Vec<f32> = line
            .split_whitespace()
            .map(|f| f.parse().expect("a number"))
            .collect();
        let v3 = |i: usize| Vec3::new(v[i], v[i + 1], v[i + 2]);
        let (ior, u_lobe, wo) = (v[0], v[2], v3(3));
        let tf = Vec3::new(0.95, 0.9, 0.8);
        let b = bsdf_with(
            Distribution::Ggx,
            MATERIAL_THIN_DIELECTRIC,
            Vec3::ZERO,
            Vec3::ZERO,
            0.0,
            0.0,
            ior,
            tf,
        );
        let s = sample(&b, Vec3::Z, true, wo, glam::Vec2::splat(0.5), u_lobe);
        let close = |a: f32, b: f32| (a - b).abs() <= 1e-5 * a.abs().max(b.abs()) + 1e-7;
        assert!(s.delta, "a delta lobe");
        assert!(
            (s.wi - v3(6)).length() < 1e-6,
            "ior {ior}: wi {} but Mitsuba {}",
            s.wi,
            v3(6)
        );
        for k in 0..3 {
            assert!(
                close(s.weight[k], v[9 + k]),
                "ior {ior}: weight {} but Mitsuba {}",
                s.weight,
                v3(9)
            );
        }
        assert!(
            close(s.pdf, v[12]),
            "ior {ior} wo {wo}: pdf {} but Mitsuba {}",
            s.pdf,
            v[12]
        );
        count += 1;
    }
    assert_eq!(count, 16, "the whole table");
}
