//! The environment: radiance arriving from infinitely far away, either uniform (Mitsuba 3's
//! `constant`) or an equirectangular image (`envmap`), and the piecewise-constant 2D
//! distribution next-event estimation samples it by. `shaders/lib/emitters.wgsl` is the GPU
//! twin of [`EnvironmentMap::eval`], [`EnvironmentMap::sample`] and [`EnvironmentMap::pdf`].
//!
//! The image is looked up as Mitsuba's envmap does: a local direction v maps to
//! u = atan2(v.x, -v.z) / 2pi, t = acos(v.y) / pi; columns are texel-centred (u shifted by half a
//! texel, wrapping around) and rows vertex-centred (row 0 at t = 0, the last row at t = 1), and
//! the radiance is bilinear between the four texels around (u W, t (H - 1)). So the image is
//! W x (H - 1) bilinear patches, and the distribution has one cell per patch, with weight
//! mean(corner luminances) x sin(theta at the patch's centre): positive wherever the patch's
//! radiance is (texels are not negative), so every direction that carries light can be drawn.
//! Inside a cell the point is uniform in (u, t), so the solid-angle density is
//! P(cell) W (H - 1) / (2 pi^2 sin theta).

use super::environment_image::EnvironmentImage;
use super::texture::LUMINANCE;
use glam::{Mat3, Vec2, Vec3};
use std::f32::consts::PI;
use std::path::PathBuf;

/// The environment as a scene describes it.
#[derive(Clone, Debug, PartialEq)]
pub enum Environment {
    /// Uniform radiance from every direction (Mitsuba's `constant`).
    Constant {
        radiance: Vec3,
    },
    Map(EnvironmentMap),
}

/// An equirectangular environment image, scaled, and its orientation.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentMap {
    /// The image file (for the Mitsuba exporter and messages).
    pub path: PathBuf,
    pub image: EnvironmentImage,
    /// Multiplies every texel (Mitsuba's `scale`).
    pub scale: f32,
    /// Local (image) directions to world directions: a rotation (Mitsuba's `to_world`).
    pub to_world: Mat3,
    pub distribution: EnvironmentDistribution,
}

/// The sampling tables: `marginal` is the CDF over the H - 1 rows of cells (H entries, from 0
/// to 1), `conditional` row j's CDF over its W cells (W + 1 entries each). A cell's probability
/// is the product of its two CDF steps, as f32 differences: exactly what sampling draws it with.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentDistribution {
    pub width: u32,
    pub height: u32,
    pub marginal: Vec<f32>,
    pub conditional: Vec<f32>,
    /// The image's mean radiance luminance over the sphere (scale applied): what light
    /// selection weighs the environment by.
    pub mean_luminance: f32,
}

fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::from(LUMINANCE))
}

/// A CDF (first entry 0, last 1) of non-negative weights, in f64 then rounded; all zero: uniform.
fn cdf(weights: &[f64]) -> Vec<f32> {
    let total: f64 = weights.iter().sum();
    let n = weights.len() as f64;
    let mut sum = 0.0;
    let mut out = Vec::with_capacity(weights.len() + 1);
    out.push(0.0);
    for (k, w) in weights.iter().enumerate() {
        sum += w;
        out.push(if total > 0.0 {
            (sum / total) as f32
        } else {
            ((k + 1) as f64 / n) as f32
        });
    }
    *out.last_mut().expect("not empty") = 1.0;
    out
}

/// The index k with cdf[k] <= x < cdf[k + 1] (cells of zero width are never returned for
/// x < 1), and x's place inside that step, in [0, 1).
fn invert(cdf: &[f32], x: f32) -> (usize, f32) {
    // The last k with cdf[k] <= x, among the n = len - 1 steps.
    let n = cdf.len() - 1;
    let k = cdf[1..n].partition_point(|&c| c <= x);
    let step = cdf[k + 1] - cdf[k];
    let within = if step > 0.0 {
        ((x - cdf[k]) / step).clamp(0.0, 1.0 - f32::EPSILON / 2.0)
    } else {
        0.0
    };
    (k, within)
}

impl EnvironmentDistribution {
    pub fn build(image: &EnvironmentImage, scale: f32) -> EnvironmentDistribution {
        let (w, h) = (image.width as usize, image.height as usize);
        let lum: Vec<f64> = image
            .texels
            .iter()
            .map(|&t| f64::from(luminance(Vec3::from(t) * scale)))
            .collect();
        let at = |i: usize, j: usize| lum[j * w + i % w];
        let rows = h - 1;
        let mut conditional = Vec::with_capacity(rows * (w + 1));
        let mut row_weights = Vec::with_capacity(rows);
        let mut integral = 0.0f64;
        for j in 0..rows {
            let sin = ((j as f64 + 0.5) * std::f64::consts::PI / rows as f64).sin();
            let cells: Vec<f64> = (0..w)
                .map(|i| 0.25 * (at(i, j) + at(i + 1, j) + at(i, j + 1) + at(i + 1, j + 1)) * sin)
                .collect();
            let row: f64 = cells.iter().sum();
            integral += row;
            row_weights.push(row);
            conditional.extend(cdf(&cells));
        }
        // The integral of luminance over the sphere is about sum(cell) * (2 pi / W) (pi / (H - 1)).
        let sphere =
            integral * 2.0 * std::f64::consts::PI * std::f64::consts::PI / (w as f64 * rows as f64);
        EnvironmentDistribution {
            width: w as u32,
            height: h as u32,
            marginal: cdf(&row_weights),
            conditional,
            mean_luminance: (sphere / (4.0 * std::f64::consts::PI)) as f32,
        }
    }

    fn cell_probability(&self, i: usize, j: usize) -> f32 {
        let w = self.width as usize;
        let row = &self.conditional[j * (w + 1)..(j + 1) * (w + 1)];
        (self.marginal[j + 1] - self.marginal[j]) * (row[i + 1] - row[i])
    }

    /// The table as `scene.light_power` holds it after the lights' weights: the marginal CDF,
    /// then each row's conditional CDF.
    pub fn gpu_table(&self) -> Vec<f32> {
        let mut out = self.marginal.clone();
        out.extend_from_slice(&self.conditional);
        out
    }
}

/// The direction of image coordinates (u, t) in [0, 1]^2 (u before the half-texel shift), and
/// sin theta.
fn direction(u: f32, t: f32) -> (Vec3, f32) {
    let (sin_theta, cos_theta) = (t * PI).sin_cos();
    let (sin_phi, cos_phi) = (u * 2.0 * PI).sin_cos();
    (
        Vec3::new(sin_phi * sin_theta, cos_theta, -cos_phi * sin_theta),
        sin_theta,
    )
}

impl EnvironmentMap {
    pub fn new(
        path: PathBuf,
        image: EnvironmentImage,
        scale: f32,
        to_world: Mat3,
    ) -> EnvironmentMap {
        let distribution = EnvironmentDistribution::build(&image, scale);
        EnvironmentMap {
            path,
            image,
            scale,
            to_world,
            distribution,
        }
    }

    /// Radiance arriving along the world direction -d (seen looking along d).
    pub fn eval(&self, d: Vec3) -> Vec3 {
        self.image.eval(self.to_world.transpose() * d) * self.scale
    }

    /// A world direction drawn from the 2D sample u, and its solid-angle density (0: none).
    pub fn sample(&self, u: Vec2) -> (Vec3, f32) {
        let dist = &self.distribution;
        let (w, rows) = (dist.width as usize, dist.height as usize - 1);
        let (j, fy) = invert(&dist.marginal, u.y);
        let row = &dist.conditional[j * (w + 1)..(j + 1) * (w + 1)];
        let (i, fx) = invert(row, u.x);
        let shifted = (i as f32 + fx) / w as f32 + 0.5 / w as f32;
        let t = (j as f32 + fy) / rows as f32;
        let (v, sin_theta) = direction(shifted, t);
        if sin_theta <= 0.0 {
            return (Vec3::Y, 0.0);
        }
        let p = dist.cell_probability(i, j);
        let pdf = p * (w * rows) as f32 / (2.0 * PI * PI * sin_theta);
        (self.to_world * v, pdf)
    }

    /// The density [`EnvironmentMap::sample`] draws the world direction d with.
    pub fn pdf(&self, d: Vec3) -> f32 {
        let dist = &self.distribution;
        let (w, rows) = (dist.width as usize, dist.height as usize - 1);
        let v = self.to_world.transpose() * d;
        let mut u = v.x.atan2(-v.z) / (2.0 * PI) - 0.5 / w as f32;
        u -= u.floor();
        let t = v.y.clamp(-1.0, 1.0).acos() / PI;
        let i = ((u * w as f32) as usize).min(w - 1);
        let j = ((t * rows as f32) as usize).min(rows - 1);
        let sin_theta = (v.x * v.x + v.z * v.z).sqrt();
        if sin_theta <= 0.0 {
            return 0.0;
        }
        dist.cell_probability(i, j) * (w * rows) as f32 / (2.0 * PI * PI * sin_theta)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(w: u32, h: u32, f: impl Fn(u32, u32) -> [f32; 3]) -> EnvironmentImage {
        let texels = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .map(|(x, y)| f(x, y));
        EnvironmentImage::from_texels(w, h, texels.collect()).unwrap()
    }

    fn map(img: EnvironmentImage) -> EnvironmentMap {
        EnvironmentMap::new(PathBuf::new(), img, 1.0, Mat3::IDENTITY)
    }

    #[test]
    fn cell_probabilities_sum_to_one() {
        let m = map(image(7, 5, |x, y| [(x * y) as f32, 1.0, 0.0]));
        let d = &m.distribution;
        let sum: f32 = (0..4)
            .flat_map(|j| (0..7).map(move |i| (i, j)))
            .map(|(i, j)| d.cell_probability(i, j))
            .sum();
        assert!((sum - 1.0).abs() < 1e-5, "{sum}");
    }

    #[test]
    fn samples_carry_the_density_pdf_gives_them() {
        let m = map(image(8, 6, |x, y| [1.0 + (x + 3 * y) as f32, 0.5, 2.0]));
        for k in 0..500 {
            let u = Vec2::new(
                (k as f32 * 0.618_034).fract(),
                (k as f32 * 0.754_878).fract(),
            );
            let (d, pdf) = m.sample(u);
            assert!((d.length() - 1.0).abs() < 1e-5);
            let back = m.pdf(d);
            assert!(
                (back - pdf).abs() <= 1e-3 * pdf,
                "sample {k}: pdf {pdf}, pdf(d) {back}"
            );
        }
    }

    #[test]
    fn a_black_image_has_zero_mean_and_stays_sampleable() {
        let m = map(image(4, 3, |_, _| [0.0; 3]));
        assert_eq!(m.distribution.mean_luminance, 0.0);
        let (_, pdf) = m.sample(Vec2::new(0.3, 0.6));
        assert!(pdf > 0.0 && pdf.is_finite());
    }

    #[test]
    fn mean_luminance_of_a_uniform_image_is_its_luminance() {
        let m = map(image(64, 33, |_, _| [1.0, 1.0, 1.0]));
        let mean = m.distribution.mean_luminance;
        // The midpoint rule over sin theta: within 0.1 % at 32 rows.
        assert!((mean - 1.0).abs() < 1e-3, "{mean}");
    }

    /// Pearson's chi-square of `sample`'s directions against `pdf`, on a 16 x 8 grid of equal
    /// solid angle (azimuth x cos theta), the expected count of each bin integrated from the
    /// pdf on a 48 x 48 sub-grid (fine enough for the sun cells' edges). Bins expecting fewer than 5 samples are pooled. The threshold
    /// is the chi-square quantile at p = 1e-6 (Wilson-Hilferty): a correct sampler fails once
    /// in a million runs, a density off by a few percent anywhere fails at once.
    #[test]
    fn chi_square_of_the_sampled_directions_against_the_pdf() {
        // A dim sky with a bright small sun, under a rotation: what the sampler is for.
        let img = image(32, 17, |x, y| {
            let sun = if (10..12).contains(&x) && (5..7).contains(&y) {
                400.0
            } else {
                0.0
            };
            [
                0.2 + 0.05 * y as f32 + sun,
                0.3 + sun,
                0.5 + 0.01 * x as f32 + sun,
            ]
        });
        let rotation = Mat3::from_axis_angle(Vec3::new(1.0, 2.0, 0.5).normalize(), 0.7);
        let m = EnvironmentMap::new(PathBuf::new(), img, 1.0, rotation);
        let (nphi, ncos, sub) = (16usize, 8usize, 48usize);
        let bin = |d: Vec3| {
            let phi = d.z.atan2(d.x).rem_euclid(2.0 * PI);
            let i = ((phi / (2.0 * PI) * nphi as f32) as usize).min(nphi - 1);
            let j = (((d.y + 1.0) / 2.0 * ncos as f32) as usize).min(ncos - 1);
            j * nphi + i
        };
        let n = 400_000usize;
        let mut observed = vec![0f64; nphi * ncos];
        let mut state = 0x853c_49e6_748f_ea9bu64;
        let mut next = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((state >> 40) as f32) / (1u64 << 24) as f32
        };
        for _ in 0..n {
            let (d, pdf) = m.sample(Vec2::new(next(), next()));
            assert!(pdf > 0.0);
            observed[bin(d)] += 1.0;
        }
        let mut expected = vec![0f64; nphi * ncos];
        let cell = 4.0 * std::f64::consts::PI / (nphi * ncos * sub * sub) as f64;
        for j in 0..ncos * sub {
            let z = -1.0 + (j as f32 + 0.5) * 2.0 / (ncos * sub) as f32;
            let r = (1.0 - z * z).sqrt();
            for i in 0..nphi * sub {
                let phi = (i as f32 + 0.5) * 2.0 * PI / (nphi * sub) as f32;
                let d = Vec3::new(r * phi.cos(), z, r * phi.sin());
                expected[bin(d)] += f64::from(m.pdf(d)) * cell * n as f64;
            }
        }
        let (mut chi2, mut dof, mut pool_o, mut pool_e) = (0.0, 0usize, 0.0, 0.0);
        for (o, e) in observed.iter().zip(&expected) {
            if *e < 5.0 {
                pool_o += o;
                pool_e += e;
            } else {
                chi2 += (o - e).powi(2) / e;
                dof += 1;
            }
        }
        if pool_e > 0.0 {
            chi2 += (pool_o - pool_e).powi(2) / pool_e.max(1e-9);
            dof += 1;
        }
        let k = (dof - 1) as f64;
        let z = 4.753_424; // the standard normal's 1 - 1e-6 quantile
        let threshold = k * (1.0 - 2.0 / (9.0 * k) + z * (2.0 / (9.0 * k)).sqrt()).powi(3);
        assert!(
            chi2 < threshold,
            "chi-square {chi2} over {k} dof, threshold {threshold}"
        );
    }
}
