//! The BSDF library's CPU twin (src/bsdf) against Mitsuba 3 itself: eval and pdf at fixed
//! directions, from tests/data/bsdf/mitsuba_table.txt (written by scripts/bsdf-mitsuba-table
//! with Mitsuba 3.9.0, scalar_rgb: twosided + diffuse, twosided + roughconductor with
//! material none, twosided + plastic with nonlinear false, roughdielectric; all ggx with
//! sample_visible, ext_ior 1).

mod bsdf_support;

use glam::Vec3;
use passgraph::bsdf::{Bsdf, eval, pdf};
use std::path::Path;

struct Row {
    case: String,
    bsdf: Bsdf,
    wo: Vec3,
    wi: Vec3,
    eval: Vec3,
    pdf: f32,
}

fn rows() -> Vec<Row> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/bsdf/mitsuba_table.txt");
    let text = std::fs::read_to_string(&path).expect("the Mitsuba table");
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|line| {
            let mut fields = line.split_whitespace();
            let case = fields.next().expect("case").to_string();
            let v: Vec<f32> = fields.map(|f| f.parse().expect("a number")).collect();
            let v3 = |i: usize| Vec3::new(v[i], v[i + 1], v[i + 2]);
            Row {
                case,
                bsdf: Bsdf {
                    kind: v[0] as u32,
                    alpha: v[1],
                    ior: v[2],
                    kd: v3(3),
                    ks: v3(6),
                    ns: 0.0,
                    tf: v3(9),
                },
                wo: v3(12),
                wi: v3(15),
                eval: v3(18),
                pdf: v[21],
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
