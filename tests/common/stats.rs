//! Test support: estimates over independent renders.

use passgraph::render::image::RgbImage;

/// The per-component image means of renders with different seeds (one estimate per seed), their
/// mean and the standard error of that mean from the spread between seeds: each seed
/// randomises the sampler afresh, so the renders are independent, identically distributed
/// estimates (for the Sobol sampler too: its scrambles are the randomisation).
pub fn mean_over_seeds(images: &[RgbImage]) -> ([f64; 3], [f64; 3]) {
    let n = images.len() as f64;
    let means: Vec<[f64; 3]> = images.iter().map(RgbImage::mean).collect();
    let mut mean = [0.0; 3];
    let mut se = [0.0; 3];
    for k in 0..3 {
        mean[k] = means.iter().map(|m| m[k]).sum::<f64>() / n;
        let var = means.iter().map(|m| (m[k] - mean[k]).powi(2)).sum::<f64>() / (n - 1.0);
        se[k] = (var / n).sqrt();
    }
    (mean, se)
}

/// Asserts that the mean over `images` (one per seed) matches `expected` in every component
/// within five standard errors (a false failure once in ~1.7 million runs) plus `slack`, the
/// uncertainty of `expected` itself.
pub fn assert_unbiased(what: &str, images: &[RgbImage], expected: [f64; 3], slack: f64) {
    let (mean, se) = mean_over_seeds(images);
    for k in 0..3 {
        let bound = 5.0 * se[k] + slack;
        assert!(
            (mean[k] - expected[k]).abs() < bound,
            "{what}, component {k}: mean {} expected {}, bound {bound}",
            mean[k],
            expected[k]
        );
    }
}

/// The mean of the 128x128 Mitsuba reference of the Cornell box (l0+direct+indirect) and its
/// uncertainty: the reference's per-pixel noise floor (RMSE 1e-3,
/// tests/data/references/README.md) over sqrt(128 * 128) pixels, rounded up to 1e-5. The image
/// mean does not depend on the resolution (box filter), so renders of any size compare with it.
pub fn cornell_reference_mean() -> ([f64; 3], f64) {
    let path = super::root().join("tests/data/references/cornell-128-depth3.exr");
    (RgbImage::read_exr(&path).unwrap().mean(), 1e-5)
}
