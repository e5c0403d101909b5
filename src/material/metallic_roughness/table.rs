//! The specular albedo of glTF's dielectric layer (GGX, separable Smith, Schlick Fresnel with
//! f0 = 0.04) over cos theta and roughness, from which the metallic-roughness model weights its
//! diffuse base so the two layers share what arrives (mod.rs says why). One table
//! serves every material and every texel of a roughness texture: f0 is fixed by the
//! specification, so the albedo depends on the cosine and the roughness alone.
//!
//! E(mu, r) at mu = i / 63 (64 entries) and roughness r = j / 31 (32 rows; alpha = r^2), read
//! bilinearly; each row's cosine-weighted average 2 int E mu dmu taken exactly over that
//! piecewise-linear interpolant, so the base's albedo is 1 - E(wo) to rounding. Computed once
//! per process in f64 by a 64 x 64 Gauss-Legendre rule over the visible-normal sampler's unit
//! square (as plastic/tables.rs). On the GPU a table is [`TABLE_TEXELS`] texels of the materials
//! view: per row 16 texels of the 64 albedos, four per texel, then the average in a texel's x.

use crate::bsdf::ggx::{ggx_alpha, ggx_g1, ggx_sample_visible};
use crate::bsdf::quadrature::gauss_legendre;
use glam::{Vec2, Vec3};
use std::sync::OnceLock;

/// The dielectric's reflectance at normal incidence: an index of 1.5 (the specification's).
pub const DIELECTRIC_F0: f32 = 0.04;

/// Gauss-Legendre nodes a side for each entry: the integrand has a kink where the reflected
/// direction crosses the horizon, so the rule converges slowly near grazing (mu 0.05, roughness
/// 0.1: 32 nodes are 1.3e-4 from 256, 64 nodes 2e-5).
const TABLE_NODES: usize = 64;

/// Entries per row, over cos theta in [0, 1].
pub const COSINES: usize = 64;
/// Rows, over roughness in [0, 1].
pub const ROUGHNESSES: usize = 32;
/// Texels (4 f32) a row takes: the albedos, then the average.
pub const ROW_TEXELS: usize = COSINES / 4 + 1;
/// Texels the whole table takes in the materials view.
pub const TABLE_TEXELS: usize = ROUGHNESSES * ROW_TEXELS;

#[derive(Clone, Debug, PartialEq)]
pub struct SpecularAlbedoTable {
    albedo: Vec<[f32; COSINES]>,
    average: Vec<f32>,
}

/// Schlick's Fresnel term of the dielectric layer at `cos`.
fn schlick(cos: f64) -> f64 {
    let f0 = f64::from(DIELECTRIC_F0);
    f0 + (1.0 - f0) * (1.0 - cos.abs()).clamp(0.0, 1.0).powi(5)
}

/// The layer's albedo seen from cos theta = `mu`: the mean over visible normals m of
/// F(wo.m) G1(wi, m), wi the reflection of wo about m (the visible-normal sampler's weight).
fn albedo_at(mu: f64, roughness: f64, nodes: usize) -> f64 {
    if roughness == 0.0 {
        return schlick(mu);
    }
    let alpha = ggx_alpha((roughness * roughness) as f32);
    let wo = Vec3::new((1.0 - mu * mu).sqrt() as f32, 0.0, mu as f32);
    let (nodes, weights) = gauss_legendre(nodes);
    let mut sum = 0.0;
    for (x, wx) in nodes.iter().zip(&weights) {
        for (y, wy) in nodes.iter().zip(&weights) {
            let u = Vec2::new((0.5 * x + 0.5) as f32, (0.5 * y + 0.5) as f32);
            let m = ggx_sample_visible(alpha, wo, u);
            let wi = 2.0 * wo.dot(m) * m - wo;
            if wi.z > 0.0 {
                let g = f64::from(ggx_g1(alpha, wi, m));
                sum += schlick(f64::from(wo.dot(m))) * g * wx * wy * 0.25;
            }
        }
    }
    sum
}

/// 2 int_0^1 E(mu) mu dmu of the piecewise-linear interpolant of `row`.
fn cosine_average(row: &[f32; COSINES]) -> f64 {
    let h = 1.0 / (COSINES - 1) as f64;
    let mut sum = 0.0;
    for i in 0..COSINES - 1 {
        let (a, b) = (i as f64 * h, (i + 1) as f64 * h);
        let (ea, eb) = (f64::from(row[i]), f64::from(row[i + 1]));
        // int_a^b 2 mu (ea + (eb - ea) (mu - a) / h) dmu.
        let ramp = 2.0 / h * ((b.powi(3) - a.powi(3)) / 3.0 - a * (b * b - a * a) / 2.0);
        sum += ea * (b * b - a * a) + (eb - ea) * ramp;
    }
    sum
}

/// Linear interpolation's cell and weight for `x` in [0, 1] over `n` nodes.
fn cell(x: f32, n: usize) -> (usize, f32) {
    let t = x.clamp(0.0, 1.0) * (n - 1) as f32;
    let i = (t as usize).min(n - 2);
    (i, t - i as f32)
}

impl SpecularAlbedoTable {
    pub fn compute() -> SpecularAlbedoTable {
        use rayon::prelude::*;
        let albedo: Vec<[f32; COSINES]> = (0..ROUGHNESSES)
            .into_par_iter()
            .map(|j| {
                let r = j as f64 / (ROUGHNESSES - 1) as f64;
                let mut row = [0.0f32; COSINES];
                for (i, e) in row.iter_mut().enumerate() {
                    // Floored as plastic_tables.rs floors it: a direction in the plane has no
                    // visible normals.
                    let mu = (i as f64 / (COSINES - 1) as f64).max(1e-6);
                    *e = albedo_at(mu, r, TABLE_NODES) as f32;
                }
                row
            })
            .collect();
        let average = albedo
            .iter()
            .map(|row| cosine_average(row) as f32)
            .collect();
        SpecularAlbedoTable { albedo, average }
    }

    /// E(mu, roughness) by a finer rule than the table's (256 nodes a side), between the nodes
    /// too: what the bilinear [`Self::albedo`] approximates. Near grazing on smooth layers the
    /// two differ by up to 5e-3 (mu 0.044, roughness 0.09: E bends faster than 64 x 32 nodes
    /// follow); where the table under-estimates E the base gets that much too much.
    pub fn exact(mu: f64, roughness: f64) -> f64 {
        albedo_at(mu.max(1e-6), roughness, 256)
    }

    /// The table of this process, computed on first use (8 M visible-normal samples).
    pub fn shared() -> &'static SpecularAlbedoTable {
        static TABLE: OnceLock<SpecularAlbedoTable> = OnceLock::new();
        TABLE.get_or_init(SpecularAlbedoTable::compute)
    }

    /// E(cos, roughness), bilinear (the WGSL's order of operations).
    pub fn albedo(&self, cos: f32, roughness: f32) -> f32 {
        let (i, t) = cell(cos, COSINES);
        let (j, s) = cell(roughness, ROUGHNESSES);
        let lerp = |row: &[f32; COSINES]| row[i] + (row[i + 1] - row[i]) * t;
        let (e0, e1) = (lerp(&self.albedo[j]), lerp(&self.albedo[j + 1]));
        e0 + (e1 - e0) * s
    }

    /// The cosine-weighted average of E at `roughness`, linear between rows: the exact average
    /// of the bilinear interpolant.
    pub fn average(&self, roughness: f32) -> f32 {
        let (j, s) = cell(roughness, ROUGHNESSES);
        let (a0, a1) = (self.average[j], self.average[j + 1]);
        a0 + (a1 - a0) * s
    }

    /// The table as the materials view holds it.
    pub fn texels(&self) -> Vec<[f32; 4]> {
        let mut out = Vec::with_capacity(TABLE_TEXELS);
        for (row, average) in self.albedo.iter().zip(&self.average) {
            out.extend(row.chunks_exact(4).map(|c| [c[0], c[1], c[2], c[3]]));
            out.push([*average, 0.0, 0.0, 0.0]);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fails on a table whose rows do not start at the smooth layer (F itself) or whose
    /// albedo grows with roughness at normal incidence (masking only removes light).
    #[test]
    fn smooth_row_is_schlick_and_roughness_only_loses_light() {
        let t = SpecularAlbedoTable::shared();
        for i in 0..COSINES {
            let mu = (i as f64 / (COSINES - 1) as f64).max(1e-6);
            assert_eq!(t.albedo[0][i], schlick(mu) as f32);
        }
        for j in 1..ROUGHNESSES {
            assert!(t.albedo[j][COSINES - 1] <= t.albedo[j - 1][COSINES - 1] + 1e-6);
        }
        // The smooth average: f0 + (1 - f0) 2 int (1 - mu)^5 mu = f0 + (1 - f0) / 21, up to
        // the interpolant's error (h^2 / 8 times F'' <= 20, weighted by 2 mu: below 2e-3).
        let exact = DIELECTRIC_F0 + (1.0 - DIELECTRIC_F0) / 21.0;
        assert!((t.average[0] - exact).abs() < 2e-3, "{}", t.average[0]);
        assert!(t.average[0] >= exact, "a convex F's chords lie above it");
    }

    #[test]
    fn texels_hold_rows_in_order() {
        let t = SpecularAlbedoTable::shared();
        let texels = t.texels();
        assert_eq!(texels.len(), TABLE_TEXELS);
        assert_eq!(texels[ROW_TEXELS + 1][2], t.albedo[1][6]);
        assert_eq!(texels[2 * ROW_TEXELS - 1][0], t.average[1]);
    }
}
