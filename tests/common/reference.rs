//! Renders against a Mitsuba 3 reference over a region of pixels: the region's mean per
//! component within a relative tolerance, and its mean squared error no larger than the
//! render's own noise, the reference's noise and five standard errors of both estimates.

use passgraph::render::image::RgbImage;

/// Mean and standard error of the mean of `values`.
fn mean_and_se(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
    (mean, (var / n).sqrt())
}

/// Squared differences of two images over `pixels`, every component.
fn squared_differences(x: &RgbImage, y: &RgbImage, pixels: &[usize]) -> Vec<f64> {
    pixels
        .iter()
        .flat_map(|&i| (0..3).map(move |k| f64::from(x.pixels[i][k]) - f64::from(y.pixels[i][k])))
        .map(|d| d * d)
        .collect()
}

/// What [`check_region`] measured, for a test's message or a note.
#[derive(Debug)]
pub struct RegionError {
    pub mean: [f64; 3],
    pub reference_mean: [f64; 3],
    pub rmse: f64,
    pub noise_rmse: f64,
    pub bound_rmse: f64,
}

/// Checks `a` (a render; `b` an independent one with another seed) against `reference` over
/// `pixels`. `reference_noise`: the reference's own mean squared error per component (its
/// noise floor). Each component's mean must lie within `mean_tolerance` (relative) of the
/// reference's, or, where the region is too noisy for that to be a test of bias at this sample
/// count, within five standard errors of the difference of the two means (pixels are
/// independent: the standard error is the per-pixel noise over the pixel count). The bound on
/// the MSE is a's noise (half the MSE between a and b) plus the reference's noise plus five
/// standard errors of both MSE estimates.
pub fn check_region(
    what: &str,
    a: &RgbImage,
    b: &RgbImage,
    reference: &RgbImage,
    pixels: &[usize],
    reference_noise: f64,
    mean_tolerance: f64,
) -> RegionError {
    assert!(!pixels.is_empty(), "{what}: no pixels");
    let mut mean = [0.0; 3];
    let mut reference_mean = [0.0; 3];
    for k in 0..3 {
        let ours: Vec<f64> = pixels.iter().map(|&i| f64::from(a.pixels[i][k])).collect();
        let theirs: Vec<f64> = pixels
            .iter()
            .map(|&i| f64::from(reference.pixels[i][k]))
            .collect();
        mean[k] = mean_and_se(&ours).0;
        reference_mean[k] = mean_and_se(&theirs).0;
    }
    let (vs_reference, vs_reference_se) = mean_and_se(&squared_differences(a, reference, pixels));
    let (between, between_se) = mean_and_se(&squared_differences(a, b, pixels));
    let noise = between / 2.0 + reference_noise;
    let bound = noise + 5.0 * (vs_reference_se + between_se / 2.0);
    let error = RegionError {
        mean,
        reference_mean,
        rmse: vs_reference.sqrt(),
        noise_rmse: noise.sqrt(),
        bound_rmse: bound.sqrt(),
    };
    eprintln!(
        "{what}: {} pixels, mean {:.5?} vs {:.5?} (standard error {:.2e}), RMSE {:.5} (noise {:.5}, bound {:.5})",
        pixels.len(),
        error.mean,
        error.reference_mean,
        (noise / pixels.len() as f64).sqrt(),
        error.rmse,
        error.noise_rmse,
        error.bound_rmse
    );
    let mean_se = (noise / pixels.len() as f64).sqrt();
    for k in 0..3 {
        let difference = (mean[k] - reference_mean[k]).abs();
        let tolerance = (mean_tolerance * reference_mean[k]).max(5.0 * mean_se);
        assert!(
            difference < tolerance,
            "{what}: component {k} mean {} vs reference {} ({:.2} %; tolerance {:.2} %: the larger of {:.2} % and five standard errors)",
            mean[k],
            reference_mean[k],
            100.0 * difference / reference_mean[k],
            100.0 * tolerance / reference_mean[k],
            100.0 * mean_tolerance
        );
    }
    assert!(
        vs_reference < bound,
        "{what}: RMSE {} against the reference exceeds the noise bound {} (noise alone {})",
        error.rmse,
        error.bound_rmse,
        error.noise_rmse
    );
    error
}

/// A reference made as two independent halves (Mitsuba renders with different seeds,
/// `tests/data/references/NAME-a.exr` and `-b.exr`): their mean is the reference, and a quarter
/// of their mean squared difference over a region its own noise.
pub struct Halves {
    pub a: RgbImage,
    pub b: RgbImage,
    pub mean: RgbImage,
}

impl Halves {
    /// Reads `tests/data/references/{name}-a.exr` and `-b.exr`.
    pub fn read(name: &str) -> Halves {
        let dir = super::root().join("tests/data/references");
        let read = |h: &str| RgbImage::read_exr(&dir.join(format!("{name}-{h}.exr"))).unwrap();
        let (a, b) = (read("a"), read("b"));
        let mut mean = a.clone();
        for (p, q) in mean.pixels.iter_mut().zip(&b.pixels) {
            for k in 0..3 {
                p[k] = 0.5 * (p[k] + q[k]);
            }
        }
        Halves { a, b, mean }
    }

    /// The mean's own mean squared error per component over `pixels`.
    pub fn noise(&self, pixels: &[usize]) -> f64 {
        squared_differences(&self.a, &self.b, pixels)
            .iter()
            .sum::<f64>()
            / (3 * pixels.len()) as f64
            / 4.0
    }
}
