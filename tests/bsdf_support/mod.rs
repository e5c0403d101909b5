//! Support for the tests/bsdf_*.rs suites: a seeded random source, the materials and
//! incidences every suite runs over, spherical grids, and the chi-square test.
#![allow(dead_code)]

pub mod chi2;

use chi2::chi2_test;
use glam::Vec3;
use passgraph::bsdf::frame::{basis, to_local};
use passgraph::material::conductor::presets::conductor_preset;
use passgraph::material::dielectric::relative_eta;
use passgraph::material::plastic::specular_probability;
use passgraph::material::plastic::tables::PlasticTable;
use passgraph::material::{Bsdf, Sample, pdf};
use passgraph::scene::{
    Distribution, FRESNEL_CONDUCTOR, FRESNEL_NONE, MATERIAL_CONDUCTOR, MATERIAL_DIELECTRIC,
    MATERIAL_LAMBERT, MATERIAL_METALLIC_ROUGHNESS, MATERIAL_PHONG, MATERIAL_PLASTIC,
    MATERIAL_THIN_DIELECTRIC,
};

// The seeded random source is the shared test one (tests/common/geometry.rs).
#[allow(unused_imports)]
pub use crate::common::geometry::Rng;

/// A material seen from one direction: the inputs of eval / pdf / sample but wi.
#[derive(Clone, Debug)]
pub struct Case {
    pub name: String,
    pub bsdf: Bsdf,
    /// The shading normal, turned to wo's side.
    pub n: Vec3,
    pub outside: bool,
    pub wo: Vec3,
}

/// A normal off the axes, so the tests go through `basis` as a renderer does.
pub fn tilted_normal() -> Vec3 {
    Vec3::new(0.3, -0.5, 0.8).normalize()
}

/// The direction at cos(theta) = `cos_o` from `n`, azimuth 0.7 rad in n's frame.
pub fn incident(n: Vec3, cos_o: f32) -> Vec3 {
    let s = (1.0 - cos_o * cos_o).max(0.0).sqrt();
    (basis(n) * Vec3::new(s * 0.7f32.cos(), s * 0.7f32.sin(), cos_o)).normalize()
}

/// A material's Bsdf (GGX); a rough plastic gets its tables as scene loading computes them.
pub fn bsdf(kind: u32, kd: Vec3, ks: Vec3, ns: f32, alpha: f32, ior: f32, tf: Vec3) -> Bsdf {
    bsdf_with(Distribution::Ggx, kind, kd, ks, ns, alpha, ior, tf)
}

/// As [`bsdf`], with the rough lobes' microfacets from `distribution`.
#[allow(clippy::too_many_arguments)]
pub fn bsdf_with(
    distribution: Distribution,
    kind: u32,
    kd: Vec3,
    ks: Vec3,
    ns: f32,
    alpha: f32,
    ior: f32,
    tf: Vec3,
) -> Bsdf {
    let rough_plastic = kind == MATERIAL_PLASTIC && alpha > 0.0;
    Bsdf {
        kind,
        kd,
        ks,
        ns,
        alpha,
        ior,
        tf,
        table: rough_plastic.then(|| PlasticTable::compute(distribution, alpha, ior)),
        distribution,
        fresnel: FRESNEL_NONE,
        eta: Vec3::ZERO,
        k: Vec3::ONE,
    }
}

/// A conductor of Mitsuba's named complex index `preset` (its Fresnel term times kd).
pub fn named_conductor(preset: &str, kd: Vec3, alpha: f32, distribution: Distribution) -> Bsdf {
    let (eta, k) = conductor_preset(preset).expect("a Mitsuba preset");
    Bsdf {
        fresnel: FRESNEL_CONDUCTOR,
        eta,
        k,
        ..bsdf_with(
            distribution,
            MATERIAL_CONDUCTOR,
            kd,
            Vec3::ZERO,
            0.0,
            alpha,
            1.0,
            Vec3::ZERO,
        )
    }
}

/// The roughness values every rough model runs with: near-smooth, medium, rough.
pub const ROUGHNESS: [f32; 3] = [0.01, 0.3, 1.0];
/// Incidences: normal, oblique, grazing.
pub const INCIDENCE: [f32; 3] = [1.0, 0.5, 0.05];

/// The materials of the suites: tinted (`white` false) or white (all reflectances 1, the
/// furnace's), each kind at each roughness (0 for the delta variants), the dielectric from both
/// sides.
pub fn materials(white: bool) -> Vec<(String, Bsdf, bool)> {
    let pick = |tinted: Vec3| if white { Vec3::ONE } else { tinted };
    let kd = pick(Vec3::new(0.7, 0.5, 0.3));
    let ks = pick(Vec3::new(0.9, 0.8, 0.6));
    let tf = pick(Vec3::new(0.95, 0.9, 0.8));
    let mut out = vec![(
        "lambert".to_string(),
        bsdf(MATERIAL_LAMBERT, kd, Vec3::ZERO, 0.0, 0.0, 1.0, Vec3::ZERO),
        true,
    )];
    for ns in [10.0, 200.0] {
        // Phong with kd + ks = 1 as the seed's scenes keep it.
        let b = bsdf(
            MATERIAL_PHONG,
            Vec3::splat(0.5),
            Vec3::splat(0.5),
            ns,
            0.0,
            1.0,
            Vec3::ZERO,
        );
        out.push((format!("phong ns {ns}"), b, true));
    }
    for alpha in [0.0, ROUGHNESS[0], ROUGHNESS[1], ROUGHNESS[2]] {
        let b = bsdf(
            MATERIAL_CONDUCTOR,
            kd,
            Vec3::ZERO,
            0.0,
            alpha,
            1.0,
            Vec3::ZERO,
        );
        out.push((format!("conductor alpha {alpha}"), b, true));
    }
    let b = bsdf(MATERIAL_PLASTIC, kd, ks, 0.0, 0.0, 1.5, Vec3::ZERO);
    out.push(("plastic".to_string(), b, true));
    // Rough plastic (Mitsuba 3's roughplastic) at each roughness, and water's index once.
    for (alpha, ior) in [
        (ROUGHNESS[0], 1.5),
        (ROUGHNESS[1], 1.5),
        (ROUGHNESS[2], 1.5),
        (0.1, 1.33),
    ] {
        let b = bsdf(MATERIAL_PLASTIC, kd, ks, 0.0, alpha, ior, Vec3::ZERO);
        out.push((format!("rough plastic alpha {alpha} ior {ior}"), b, true));
    }
    for alpha in [0.0, ROUGHNESS[0], ROUGHNESS[1], ROUGHNESS[2]] {
        for outside in [true, false] {
            let b = bsdf(
                MATERIAL_DIELECTRIC,
                Vec3::ZERO,
                Vec3::ZERO,
                0.0,
                alpha,
                1.5,
                tf,
            );
            let side = if outside { "outside" } else { "inside" };
            out.push((format!("dielectric alpha {alpha} {side}"), b, outside));
        }
    }
    // Beckmann (Mitsuba's default distribution) for each rough model, and complex-index
    // conductors (gold; white runs keep its Fresnel term, which is below 1 by physics).
    let beckmann = Distribution::Beckmann;
    for alpha in ROUGHNESS {
        let b = bsdf_with(
            beckmann,
            MATERIAL_CONDUCTOR,
            kd,
            Vec3::ZERO,
            0.0,
            alpha,
            1.0,
            tf,
        );
        out.push((format!("beckmann conductor alpha {alpha}"), b, true));
    }
    for (alpha, ior) in [
        (ROUGHNESS[0], 1.5),
        (ROUGHNESS[1], 1.5),
        (ROUGHNESS[2], 1.33),
    ] {
        let b = bsdf_with(
            beckmann,
            MATERIAL_PLASTIC,
            kd,
            ks,
            0.0,
            alpha,
            ior,
            Vec3::ZERO,
        );
        out.push((
            format!("beckmann rough plastic alpha {alpha} ior {ior}"),
            b,
            true,
        ));
    }
    for alpha in ROUGHNESS {
        for outside in [true, false] {
            let b = bsdf_with(
                beckmann,
                MATERIAL_DIELECTRIC,
                Vec3::ZERO,
                Vec3::ZERO,
                0.0,
                alpha,
                1.5,
                tf,
            );
            let side = if outside { "outside" } else { "inside" };
            out.push((
                format!("beckmann dielectric alpha {alpha} {side}"),
                b,
                outside,
            ));
        }
    }
    for (alpha, distribution) in [
        (0.0, Distribution::Ggx),
        (ROUGHNESS[1], Distribution::Ggx),
        (ROUGHNESS[1], beckmann),
    ] {
        let b = named_conductor("Au", kd, alpha, distribution);
        out.push((
            format!("Au conductor alpha {alpha} {distribution:?}"),
            b,
            true,
        ));
    }
    for ior in [1.5, 1.33] {
        let b = bsdf(
            MATERIAL_THIN_DIELECTRIC,
            Vec3::ZERO,
            Vec3::ZERO,
            0.0,
            0.0,
            ior,
            tf,
        );
        out.push((format!("thin dielectric ior {ior}"), b, true));
    }
    // glTF's metallic-roughness (ks.x = metallic): the dielectric, half metal and the metal,
    // smooth (alpha 0: a delta mirror over the base) and at each roughness.
    for metallic in [0.0, 0.5, 1.0] {
        for alpha in [0.0, ROUGHNESS[0], ROUGHNESS[1], ROUGHNESS[2]] {
            let b = bsdf(
                MATERIAL_METALLIC_ROUGHNESS,
                kd,
                Vec3::new(metallic, 0.0, 0.0),
                0.0,
                alpha,
                1.5,
                Vec3::ZERO,
            );
            out.push((
                format!("metallic-roughness metallic {metallic} alpha {alpha}"),
                b,
                true,
            ));
        }
    }
    out
}

/// erf in f64: its Maclaurin series up to |x| = 3 (cancellation costs at most e^9 ~ 1e4 of the
/// 1e-16), the continued fraction of erfc beyond (60 terms: converged far below 1e-16 there).
pub fn erf_f64(x: f64) -> f64 {
    use std::f64::consts::PI;
    let a = x.abs();
    let y = if a <= 3.0 {
        let (mut term, mut sum) = (a, a);
        for n in 1..120 {
            term *= -a * a / n as f64;
            sum += term / (2 * n + 1) as f64;
        }
        sum * 2.0 / PI.sqrt()
    } else {
        // erfc(a) = e^(-a^2) / sqrt(pi) / (a + (1/2) / (a + 1 / (a + (3/2) / (a + ...)))).
        let mut f = a;
        for k in (1..60).rev() {
            f = a + (k as f64 / 2.0) / f;
        }
        1.0 - (-a * a).exp() / PI.sqrt() / f
    };
    if x < 0.0 { -y } else { y }
}

/// How much more often than `pdf` says the Beckmann visible-normal sampler picks a normal seen
/// from `wo_local` (local frame): it draws normals in proportion to D(m) <wo, m> exactly, whose
/// normalisation is Smith's exact G1 = 1 / (1 + Lambda), Lambda(a) = (erf(a) - 1) / 2 +
/// e^(-a^2) / (2 a sqrt(pi)), a = 1 / (alpha tan theta), while Mitsuba's pdf (and so ours)
/// divides by its rational fit of G1 instead (relative error below 0.35 %). 1 for GGX, whose
/// G1 is exact.
pub fn visible_normal_bias(b: &Bsdf, wo_local: Vec3) -> f64 {
    if b.distribution != Distribution::Beckmann {
        return 1.0;
    }
    let alpha = f64::from(b.alpha.max(1e-4));
    let (x, y, z) = (wo_local.x as f64, wo_local.y as f64, wo_local.z as f64);
    let xy = alpha * alpha * (x * x + y * y);
    if xy == 0.0 {
        return 1.0;
    }
    let a = (z * z / xy).sqrt();
    let lambda =
        (erf_f64(a) - 1.0) / 2.0 + (-a * a).exp() / (2.0 * a * std::f64::consts::PI.sqrt());
    let exact = 1.0 / (1.0 + lambda);
    let fit = if a >= 1.6 {
        1.0
    } else {
        (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a)
    };
    exact / fit
}

/// The density the sampler actually draws wi from: `pdf` with its visible-normal lobe scaled by
/// [`visible_normal_bias`] (the whole pdf for the conductor and dielectric, the coat's
/// reflection for rough plastic); `pdf` itself for every GGX and smooth model.
pub fn sampled_density(case: &Case, wi: Vec3) -> f64 {
    let b = &case.bsdf;
    let p = f64::from(pdf(b, case.n, case.outside, case.wo, wi));
    let frame = basis(case.n);
    let wo_local = to_local(&frame, case.wo);
    let bias = visible_normal_bias(b, wo_local);
    if bias == 1.0 || b.alpha == 0.0 {
        return p;
    }
    match (b.kind, &b.table) {
        (MATERIAL_PLASTIC, Some(t)) => {
            // The coat's reflection alone: the conductor's pdf of the same microfacets.
            let coat = Bsdf {
                kind: MATERIAL_CONDUCTOR,
                ..*b
            };
            let specular = f64::from(pdf(&coat, case.n, true, case.wo, wi));
            let p_s = f64::from(specular_probability(
                b,
                1.0 - t.transmittance_at(wo_local.z),
            ));
            p + p_s * specular * (bias - 1.0)
        }
        _ => p * bias,
    }
}

/// Every material at every incidence.
pub fn cases(white: bool) -> Vec<Case> {
    let n = tilted_normal();
    let mut out = Vec::new();
    for (name, b, outside) in materials(white) {
        for cos_o in INCIDENCE {
            out.push(Case {
                name: format!("{name}, cos wo {cos_o}"),
                bsdf: b,
                n,
                outside,
                wo: incident(n, cos_o),
            });
        }
    }
    out
}

/// A grid of cells equal in theta and phi around n (theta rather than cos theta keeps a
/// near-smooth lobe around the normal resolvable), each cell integrated adaptively.
pub struct SphereGrid {
    pub rows: usize,
    pub cols: usize,
}

/// A 4 x 4 midpoint rule on [t0, t1] x [p0, p1] in (theta, phi), with the sin theta Jacobian.
fn midpoint(f: &impl Fn(Vec3) -> f64, t0: f64, t1: f64, p0: f64, p1: f64) -> f64 {
    const K: usize = 4;
    let (st, sp) = ((t1 - t0) / K as f64, (p1 - p0) / K as f64);
    let mut sum = 0.0;
    for i in 0..K {
        let theta = t0 + (i as f64 + 0.5) * st;
        let (sin_t, cos_t) = theta.sin_cos();
        for j in 0..K {
            let phi = p0 + (j as f64 + 0.5) * sp;
            let d = Vec3::new(
                (sin_t * phi.cos()) as f32,
                (sin_t * phi.sin()) as f32,
                cos_t as f32,
            );
            sum += f(d) * sin_t;
        }
    }
    sum * st * sp
}

/// The integral over a rectangle whose 4 x 4 estimate is `coarse`: the four quarters' sum,
/// recursing into them until it agrees with `coarse` within 1e-4 relative or `abs` (halved at
/// each level). Adds the accepted difference, an estimate of the error, to `error`.
#[allow(clippy::too_many_arguments)]
fn adaptive(
    f: &impl Fn(Vec3) -> f64,
    t0: f64,
    t1: f64,
    p0: f64,
    p1: f64,
    coarse: f64,
    abs: f64,
    depth: u32,
    error: &mut f64,
) -> f64 {
    let (tm, pm) = (0.5 * (t0 + t1), 0.5 * (p0 + p1));
    let quarters = [
        (t0, tm, p0, pm),
        (t0, tm, pm, p1),
        (tm, t1, p0, pm),
        (tm, t1, pm, p1),
    ];
    let parts = quarters.map(|(a, b, c, d)| midpoint(f, a, b, c, d));
    let fine: f64 = parts.iter().sum();
    let diff = (fine - coarse).abs();
    if diff <= abs.max(1e-4 * fine.abs()) || depth == 0 {
        *error += diff;
        return fine;
    }
    quarters
        .iter()
        .zip(parts)
        .map(|(&(a, b, c, d), part)| adaptive(f, a, b, c, d, part, abs * 0.5, depth - 1, error))
        .sum()
}

impl SphereGrid {
    /// The cell of a direction given in n's local frame.
    pub fn cell(&self, local: Vec3) -> usize {
        let theta = local.z.clamp(-1.0, 1.0).acos() as f64;
        let mut phi = (local.y as f64).atan2(local.x as f64);
        if phi < 0.0 {
            phi += 2.0 * std::f64::consts::PI;
        }
        let r = ((theta / std::f64::consts::PI) * self.rows as f64) as usize;
        let c = ((phi / (2.0 * std::f64::consts::PI)) * self.cols as f64) as usize;
        r.min(self.rows - 1) * self.cols + c.min(self.cols - 1)
    }

    /// The integral of `f` (over local directions) on each cell, and an estimate of the total
    /// error: adaptive subdivision to 1e-4 relative or 1e-9 absolute per cell, 12 levels deep
    /// at most (cells of 1e-5 rad, far below the 1e-3 rad of the narrowest lobe tested).
    pub fn integrate(&self, f: impl Fn(Vec3) -> f64) -> (Vec<f64>, f64) {
        use std::f64::consts::PI;
        let (dt, dp) = (PI / self.rows as f64, 2.0 * PI / self.cols as f64);
        let mut error = 0.0;
        let mut out = Vec::with_capacity(self.rows * self.cols);
        for r in 0..self.rows {
            for c in 0..self.cols {
                let (t0, p0) = (r as f64 * dt, c as f64 * dp);
                let coarse = midpoint(&f, t0, t0 + dt, p0, p0 + dp);
                out.push(adaptive(
                    &f,
                    t0,
                    t0 + dt,
                    p0,
                    p0 + dp,
                    coarse,
                    1e-9,
                    12,
                    &mut error,
                ));
            }
        }
        (out, error)
    }
}

/// The grid the suites histogram and integrate on.
pub fn grid() -> SphereGrid {
    SphereGrid {
        rows: 64,
        cols: 128,
    }
}

/// A fixed seed per case and a p-value threshold of 1e-3, as Mitsuba 3's and pbrt's chi-square
/// tests use: a correct sampler fails one case in a thousand seeds.
pub const P_THRESHOLD: f64 = 1e-3;

/// The chi-square p-value of `samples` (drawn for `case`) against the twin's pdf (as the
/// sampler draws it: [`sampled_density`]). One extra cell holds the samples not histogrammed
/// (failed or delta), expecting 1 - integral of the density.
pub fn chi2_p_value(case: &Case, samples: &[Sample]) -> f64 {
    let grid = grid();
    let frame = basis(case.n);
    let mut observed = vec![0.0; grid.rows * grid.cols + 1];
    for s in samples {
        if s.delta || s.pdf <= 0.0 {
            observed[grid.rows * grid.cols] += 1.0;
        } else {
            observed[grid.cell(to_local(&frame, s.wi))] += 1.0;
        }
    }
    let n = samples.len() as f64;
    let (cells, error) = grid.integrate(|local| sampled_density(case, frame * local));
    let mut expected: Vec<f64> = cells.iter().map(|p| p * n).collect();
    let histogrammed: f64 = expected.iter().sum();
    // The unhistogrammed cell's expectation, n (1 - integral), is known only to the
    // quadrature's error, n x `error` samples: ~10 for a narrow lobe whose mass sits in two
    // cells integrated to 1e-4 relative (a near-smooth Beckmann lobe at grazing, which loses
    // ~1e-4 of its samples below the horizon). Within that the statistic takes the value
    // closest to what was observed; a larger departure still counts, less that margin.
    let unhistogrammed = (n - histogrammed).max(0.0);
    let observed_rest = observed[grid.rows * grid.cols];
    let margin = n * error;
    let gap = observed_rest - unhistogrammed;
    expected.push(unhistogrammed + gap.clamp(-margin, margin));
    chi2_test(&observed, &expected).p_value
}

/// The relative tolerance between two f32 evaluations of the same quantity at `wi` from inputs
/// a few epsilon apart (as a sample made it and as it reads back through the world frame, or as
/// the GPU and the CPU compute it): 2e-5 (a few hundred ulps of
/// differently ordered expressions), plus for GGX models the D's amplification of the half
/// vector's rounding. A direction is rounded by about 4 epsilon (two rotations), the half vector
/// m = (wo + eta' wi) / |wo + eta' wi| by 4 epsilon eta' / |wo + eta' wi| (large at grazing,
/// where |wo + wi| = 2 wo.m is small), and |d ln D / dm| <= 2 / alpha near the peak, 4 / m.z
/// in the tail toward the horizon (D ~ alpha^2 cos^4 theta_m there); the Jacobian's
/// 1 / (w.m), w.m about |wo + eta' wi| / 2, turns m's error into 8 epsilon eta' / |h|^2; a
/// dielectric's F near the critical angle adds 1e-6 / |cos_t^2| (cos_t^2 = 1 - (1 - (wo.m)^2) /
/// eta^2, whose rounding F's square root amplifies; bsdf_reciprocity.rs). Cosines and G1 near
/// the horizon carry the direction's rounding as 4 epsilon / |cos| relative, and a microfacet
/// seen edge-on m's rounding as 2 / |wo.m| + 1 / |wi.m| (see the code). Beckmann's D changes
/// faster in its tail than GGX's (below).
pub fn rounding_tolerance(case: &Case, wi: Vec3) -> f32 {
    let b = &case.bsdf;
    let grazing =
        4.0 * f32::EPSILON * (1.0 / wi.dot(case.n).abs() + 1.0 / case.wo.dot(case.n).abs());
    if b.kind == MATERIAL_PHONG {
        // pow(n.h, ns) multiplies n.h's relative error by ns (and pow's own, exp2 of ns log2).
        return 2e-5 + grazing + b.ns * 8.0 * f32::EPSILON;
    }
    let rough_plastic = b.kind == MATERIAL_PLASTIC && b.table.is_some();
    if !(b.kind == MATERIAL_CONDUCTOR
        || b.kind == MATERIAL_DIELECTRIC
        || b.kind == MATERIAL_METALLIC_ROUGHNESS
        || rough_plastic)
        || b.alpha == 0.0
    {
        return 2e-5 + grazing;
    }
    let transmits = wi.dot(case.n) < 0.0;
    let eta = if transmits {
        relative_eta(b, case.outside)
    } else {
        1.0
    };
    let h = case.wo + eta * wi;
    let m_z = (h.dot(case.n) / h.length()).abs();
    let alpha = b.alpha.max(1e-4);
    // Beckmann's D = exp(-tan^2 / alpha^2) / (pi alpha^2 cos^4) changes as
    // 2 tan / (alpha^2 cos^2) + 4 tan per radian, unbounded in the tail (where D is tiny).
    let d_log_d = if b.distribution == Distribution::Beckmann {
        let tan_m = (1.0 - m_z * m_z).max(0.0).sqrt() / m_z;
        2.0 * tan_m / (alpha * alpha * m_z * m_z) + 4.0 / m_z
    } else {
        2.0 / alpha + 4.0 / m_z
    };
    let jacobian = 8.0 * f32::EPSILON * eta / h.length_squared();
    let across = relative_eta(b, case.outside);
    let c = case.wo.dot(h) / h.length();
    let cos_t_sqr = 1.0 - (1.0 - c * c) / (across * across);
    let fresnel = if b.kind == MATERIAL_DIELECTRIC {
        (1e-6 / cos_t_sqr.abs()).min(1.0)
    } else {
        0.0
    };
    // The microfacet seen nearly edge-on from wo or wi: eval and pdf carry |wo.m| and |wi.m|
    // (the visible-normal density, the Jacobian) and 1 - F(wo.m), which near grazing is
    // linear in wo.m, so m's rounding is 2 / |wo.m| + 1 / |wi.m| of it, relative.
    let m = h / h.length();
    let facing = 2.0 / case.wo.dot(m).abs() + 1.0 / wi.dot(m).abs();
    let m_rounding = 4.0 * f32::EPSILON * eta / h.length();
    2e-5 + grazing + jacobian + fresnel + (d_log_d + facing) * m_rounding
}
