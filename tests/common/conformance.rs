//! Mitsuba 3's render test (`src/render/tests/test_renders.py`), for the conformance scenes in
//! `tests/data/conformance/`: a per-pixel z-test of a test image's mean against a Mitsuba
//! reference, with the reference's per-sample variance image.
//!
//! **The test, as Mitsuba does it** (test_renders.py, functions `z_test` and `test_render`;
//! `bitmap_extract`, `read_rgb_bmp_to_xyz`):
//! - images are compared in CIE XYZ: the reference (mean) and the variance are stored as linear
//!   RGB and converted to XYZ with Mitsuba's `Bitmap.convert` (the matrix [`RGB_TO_XYZ`]), the
//!   test image likewise; the variance image is the XYZ variance of single samples
//!   (`moment` integrator: E[x²] − E[x]² per channel), stored through the inverse matrix, so
//!   the conversion gives it back;
//! - the variance is clamped from below, `max(var, 1e-4)` ([`VARIANCE_FLOOR`]);
//! - z = |test − reference| · sqrt(N / var) per pixel and channel, N the test image's samples
//!   per pixel (Mitsuba renders at a budget of 2·10⁶ samples per image, N = 2·10⁶ // pixels, 868
//!   at 48x48; [`budget_spp`]), and the two-sided p-value p = 2 (1 − Φ(z)) = erfc(z / √2);
//! - Šidák: a value passes when p > α = 1 − (1 − 0.01)^(1/P), P the pixel count (not the 3P
//!   values), so that P independent tests at α have a family-wise level of 0.01
//!   ([`SIGNIFICANCE`], [`sidak_alpha`]); at 48x48, α = 4.36·10⁻⁶, i.e. |z| < z* = 4.593;
//! - the scene passes when the passing values, divided by 3, are at least 99.75 % of the
//!   pixels ([`PASS_FRACTION`]): at most 17 of the 6912 values of a 48x48 image may fail.
//!
//! Here p is computed in f64 (`libm::erfc`), Mitsuba's in f32 (`dr.erf`): near z* its 1 − Φ
//! is quantised to about 3 % of α, which moves z* by less than 0.01. A non-finite test value
//! fails, as it does there (NaN > α is false).
//!
//! **What the test can see.** Under the null hypothesis (an unbiased renderer, N large enough
//! for the central limit theorem) test − reference is normal with variance σ²/N + σ²/N_ref, so
//! z is |normal| with standard deviation sqrt(1 + N/N_ref): 1.013 for N = 868 against the
//! 32768-spp references here. The expected number of values beyond z* is then
//! 3P · 2(1 − Φ(z*/1.013)) ≈ 0.04, against 17 allowed: a correct Gaussian renderer essentially
//! never fails, and the 0.25 % allowance is what absorbs what is not Gaussian — heavy-tailed
//! pixels (rare bright paths, at N = 868 far from normal) and references whose variance is
//! underestimated for the same reason. A bias b in one value is found (with probability
//! one half or more) when |b| > z* · sqrt(max(σ², 10⁻⁴) / N), and the scene fails when that
//! holds for more than 17 values (six pixels in all three channels, or 18 in one). Hence:
//! - a relative error ε is seen only where the per-sample relative standard deviation σ/μ is
//!   below ε·sqrt(N)/z*: 0.19 for ε = 3 % at N = 868. Path-traced diffuse pixels are far
//!   noisier (σ/μ of 1 and more); the pixels that see it are those with little noise:
//!   directly visible emitters and backgrounds, delta lights' direct light, smooth specular
//!   reflections of those. Every conformance scene has some, so that each can see a 3 %
//!   error (tests/conformance_ztest.rs checks that it does);
//! - the floor on the variance bounds the resolution: a bias below z* · 0.01 / sqrt(N)
//!   (1.6·10⁻³ at N = 868) is never seen, even in a noiseless pixel;
//! - the test's power grows as sqrt(N): halving the samples raises every threshold by 1.41.
//!   The reference's sample count N_ref does not enter the threshold; it sets the false
//!   failure rate (through sqrt(1 + N/N_ref) and through the noise of the variance estimate).
//!
//! Test images are expected to be made with independent samples, as Mitsuba's `independent`
//! sampler: a renderer with stratified or quasi-random samples has a smaller variance than
//! the reference's per-sample one, which leaves the thresholds (and so the power against a
//! bias) as they are and makes false failures rarer still.

use super::root;
use passgraph::render::image::RgbImage;
use std::fmt::Write as _;
use std::path::PathBuf;

/// Mitsuba's `significance_level`.
pub const SIGNIFICANCE: f64 = 0.01;
/// Mitsuba's `np.maximum(reference_var, 1e-4)`.
pub const VARIANCE_FLOOR: f64 = 1e-4;
/// Mitsuba's `np.count_nonzero(success) / 3 >= 0.9975 * pixel_count`.
pub const PASS_FRACTION: f64 = 0.9975;
/// Mitsuba's `sample_budget = int(2e6)` samples per image.
pub const SAMPLE_BUDGET: u64 = 2_000_000;

/// Linear sRGB (Rec. 709 primaries, D65) to CIE XYZ, rows X, Y, Z: Mitsuba 3.9.0's
/// `Bitmap.convert(PixelFormat.XYZ, ...)` of RGB images, the conversion `read_rgb_bmp_to_xyz`
/// applies (measured by converting the unit vectors with pip Mitsuba 3.9.0; the same numbers
/// as its `srgb_to_xyz`, which `moment` uses on each sample).
pub const RGB_TO_XYZ: [[f64; 3]; 3] = [
    [0.412453, 0.357580, 0.180423],
    [0.212671, 0.715160, 0.072169],
    [0.019334, 0.119193, 0.950227],
];

/// The conformance scenes and their references.
pub fn dir() -> PathBuf {
    root().join("tests/data/conformance")
}

/// Every scene, by feature name (`<feature>.xml`), sorted.
pub fn features() -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir())
        .unwrap()
        .filter_map(|e| {
            let name = e.unwrap().file_name().into_string().unwrap();
            name.strip_suffix(".xml").map(str::to_string)
        })
        .collect();
    names.sort();
    names
}

/// Mitsuba's spp for an image of `pixels` pixels: `sample_budget // pixel_count`.
pub fn budget_spp(pixels: usize) -> u32 {
    (SAMPLE_BUDGET / pixels as u64) as u32
}

/// The scene's test budget: its sampler's `sample_count`, the spp its test image was rendered
/// with and the passgraph side renders, chosen to fit the suite's time
/// (tests/data/conformance/README.md). Read from `references.csv`, which
/// scripts/mitsuba-conformance writes from the scene as Mitsuba loads it.
pub fn scene_spp(feature: &str) -> u32 {
    let path = dir().join("references.csv");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (name, spp) = (column("feature"), column("test_spp"));
    lines
        .map(|l| l.split(',').collect::<Vec<_>>())
        .find(|row| row[name] == feature)
        .unwrap_or_else(|| panic!("{}: no row for {feature}", path.display()))[spp]
        .parse()
        .unwrap()
}

pub fn rgb_to_xyz(rgb: [f32; 3]) -> [f64; 3] {
    RGB_TO_XYZ.map(|row| (0..3).map(|k| row[k] * f64::from(rgb[k])).sum())
}

/// Šidák's per-test level for `pixels` tests with a family-wise level of [`SIGNIFICANCE`]
/// (through log1p and expm1: 1 − 0.99^(1/P) loses digits in plain powers).
pub fn sidak_alpha(pixels: usize) -> f64 {
    -((-SIGNIFICANCE).ln_1p() / pixels as f64).exp_m1()
}

/// Two-sided p-value of a standard normal statistic.
pub fn p_value(z: f64) -> f64 {
    libm::erfc(z / std::f64::consts::SQRT_2)
}

/// A reference in XYZ: mean and per-sample variance per pixel, rows top to bottom.
pub struct Reference {
    pub feature: String,
    pub width: u32,
    pub height: u32,
    pub mean: Vec<[f64; 3]>,
    pub variance: Vec<[f64; 3]>,
}

/// `tests/data/conformance/<feature>.<kind>.exr` (`ref`, `var`, `test`, `swapped`).
pub fn read(feature: &str, kind: &str) -> RgbImage {
    let path = dir().join(format!("{feature}.{kind}.exr"));
    RgbImage::read_exr(&path).unwrap_or_else(|e| panic!("{e}"))
}

impl Reference {
    pub fn read(feature: &str) -> Reference {
        let mean = read(feature, "ref");
        let variance = read(feature, "var");
        assert_eq!(
            (mean.width, mean.height),
            (variance.width, variance.height),
            "{feature}: reference and variance sizes differ"
        );
        Reference {
            feature: feature.to_string(),
            width: mean.width,
            height: mean.height,
            mean: mean.pixels.iter().map(|&p| rgb_to_xyz(p)).collect(),
            variance: variance.pixels.iter().map(|&p| rgb_to_xyz(p)).collect(),
        }
    }
}

/// What the z-test measured.
#[derive(Debug)]
pub struct ZTest {
    pub feature: String,
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub alpha: f64,
    /// Per pixel, how many of its three values failed (p ≤ α or not finite).
    pub failed: Vec<u8>,
    pub failed_values: usize,
    /// Passing values / 3 / pixels: Mitsuba's criterion is `pass_fraction >= 0.9975`.
    pub pass_fraction: f64,
    pub min_p: f64,
    pub passed: bool,
}

impl ZTest {
    /// The values that may fail before the scene does (17 at 48x48).
    pub fn allowed_failures(&self) -> usize {
        let values = 3 * self.failed.len();
        values - (3.0 * PASS_FRACTION * self.failed.len() as f64).ceil() as usize
    }

    pub fn summary(&self) -> String {
        format!(
            "{}: {} at {} spp: pass fraction {:.4} ({} of {} values failed, {} allowed; \
             α {:.3e}, min p {:.3e})",
            self.feature,
            if self.passed { "pass" } else { "FAIL" },
            self.spp,
            self.pass_fraction,
            self.failed_values,
            3 * self.failed.len(),
            self.allowed_failures(),
            self.alpha,
            self.min_p
        )
    }

    /// The image with each pixel as `.` (passed), or the number of its failed values.
    pub fn failure_map(&self) -> String {
        let mut map = String::new();
        for y in 0..self.height as usize {
            for x in 0..self.width as usize {
                let n = self.failed[y * self.width as usize + x];
                map.push(if n == 0 { '.' } else { char::from(b'0' + n) });
            }
            map.push('\n');
        }
        map
    }
}

/// Mitsuba's z-test of `image` (linear RGB, `spp` samples per pixel) against `reference`.
pub fn z_test(reference: &Reference, image: &RgbImage, spp: u32) -> ZTest {
    assert_eq!(
        (image.width, image.height),
        (reference.width, reference.height),
        "{}: the image is {}x{}, the reference {}x{}",
        reference.feature,
        image.width,
        image.height,
        reference.width,
        reference.height
    );
    let pixels = image.pixels.len();
    let alpha = sidak_alpha(pixels);
    let mut failed = vec![0u8; pixels];
    let mut min_p = 1.0f64;
    for (i, &rgb) in image.pixels.iter().enumerate() {
        let (mean, variance) = (reference.mean[i], reference.variance[i]);
        for (k, value) in rgb_to_xyz(rgb).into_iter().enumerate() {
            let var = variance[k].max(VARIANCE_FLOOR);
            let z = (value - mean[k]).abs() * (f64::from(spp) / var).sqrt();
            let p = p_value(z);
            if p.is_finite() {
                min_p = min_p.min(p);
            }
            // As Mitsuba's `p_value > alpha`: a NaN fails.
            if p.is_nan() || p <= alpha {
                failed[i] += 1;
            }
        }
    }
    let failed_values: usize = failed.iter().map(|&n| usize::from(n)).sum();
    let pass_fraction = (3 * pixels - failed_values) as f64 / 3.0 / pixels as f64;
    ZTest {
        feature: reference.feature.clone(),
        width: image.width,
        height: image.height,
        spp,
        alpha,
        failed,
        failed_values,
        pass_fraction,
        min_p,
        passed: pass_fraction >= PASS_FRACTION,
    }
}

/// Writes what Mitsuba's test writes on a failure, to look at: the image, the reference and
/// an error image (0.02 × the image, failed pixels white), as linear RGB EXR in `dir`.
pub fn write_diagnostics(test: &ZTest, image: &RgbImage, dir: &std::path::Path) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    let prefix = dir.join(&test.feature);
    let with = |suffix: &str| PathBuf::from(format!("{}-{suffix}.exr", prefix.display()));
    image.write(&with("image")).unwrap();
    read(&test.feature, "ref").write(&with("ref")).unwrap();
    let mut error = image.clone();
    for (p, &n) in error.pixels.iter_mut().zip(&test.failed) {
        *p = if n > 0 { [1.0; 3] } else { p.map(|v| 0.02 * v) };
    }
    error.write(&with("error")).unwrap();
    with("error")
}

/// The passgraph side's check: `image`, rendered from `tests/data/conformance/<feature>.xml`
/// with `spp` samples per pixel, must pass Mitsuba's z-test against the scene's reference. On
/// a failure the message carries the pass fraction, a map of the failed pixels and the
/// diagnostic images' paths.
pub fn check_scene(feature: &str, image: &RgbImage, spp: u32) -> ZTest {
    let reference = Reference::read(feature);
    let test = z_test(&reference, image, spp);
    eprintln!("{}", test.summary());
    if !test.passed {
        let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("conformance");
        let error = write_diagnostics(&test, image, &out);
        let mut message = test.summary();
        let _ = write!(
            message,
            "\nfailed values per pixel (. none):\n{}error image: {}",
            test.failure_map(),
            error.display()
        );
        panic!("{message}");
    }
    test
}
