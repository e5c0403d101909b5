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
