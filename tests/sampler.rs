//! The samplers of shaders/lib/sampler.wgsl on the GPU (lavapipe in CI): the Sobol sampler's
//! stratification at every aligned power-of-two block of samples, its decorrelation across
//! dimension pairs and pixels, and both samplers' images unbiased on the furnace (analytic) and
//! the Cornell box (Mitsuba 3), measured over seeds.

mod common;

use common::render::{image as channel, render, settings};
use common::stats::{assert_unbiased, cornell_reference_mean};

const SAMPLES: usize = 256;
const DIMS: usize = 4;
const SIZE: u32 = 16;

/// census[pixel][dim][index], from tests/fixtures/shaders/sampler_census.wgsl.
fn census(seed: u32, sampler_kind: u32) -> Vec<[f32; 2]> {
    let set = format!("census.sampler_kind={sampler_kind}");
    let session = render(
        &settings(
            "tests/fixtures/graphs/sampler_census.ron",
            "scenes/cornell/scene.ron",
            SIZE,
            seed,
            &[&set],
        ),
        1,
    );
    let samples: Vec<[f32; 2]> =
        bytemuck::pod_collect_to_vec(&session.read_resource("samples").unwrap());
    assert_eq!(samples.len(), (SIZE * SIZE) as usize * DIMS * SAMPLES);
    samples
}

fn series(samples: &[[f32; 2]], pixel: usize, dim: usize) -> &[[f32; 2]] {
    let start = (pixel * DIMS + dim) * SAMPLES;
    &samples[start..start + SAMPLES]
}

/// Whether `points` (2^k of them) put exactly one point in every elementary interval of area
/// 2^-k: 2^a by 2^(k-a) cells for every a in 0..=k.
fn is_0_k_2_net(points: &[[f32; 2]]) -> Result<(), String> {
    let k = points.len().trailing_zeros();
    assert_eq!(points.len(), 1 << k);
    for a in 0..=k {
        let (nx, ny) = (1usize << a, 1usize << (k - a));
        let mut cells = vec![0u32; nx * ny];
        for p in points {
            let (cx, cy) = ((p[0] * nx as f32) as usize, (p[1] * ny as f32) as usize);
            cells[cy * nx + cx] += 1;
        }
        if let Some(i) = cells.iter().position(|&c| c != 1) {
            return Err(format!(
                "{nx}x{ny} cells: cell {i} holds {} points",
                cells[i]
            ));
        }
    }
    Ok(())
}

#[test]
fn sobol_samples_lie_in_the_unit_square_and_every_aligned_power_of_two_block_is_a_net() {
    let samples = census(3, 1);
    assert!(
        samples.iter().flatten().all(|&v| (0.0..1.0).contains(&v)),
        "a sample outside [0, 1)"
    );
    // Any frame can be the last: every prefix of N samples is a union of aligned blocks of
    // 2^k samples (the binary digits of N), so each block must be a (0,k,2)-net.
    for pixel in 0..(SIZE * SIZE) as usize {
        for dim in 0..DIMS {
            let s = series(&samples, pixel, dim);
            for k in 0..=8 {
                for (b, block) in s.chunks(1 << k).enumerate() {
                    is_0_k_2_net(block).unwrap_or_else(|e| {
                        panic!(
                            "pixel {pixel}, pair {dim}, samples {}..{}: {e}",
                            b << k,
                            (b + 1) << k
                        )
                    });
                }
            }
        }
    }
}

/// The correlation of two equally long series, and the bound five standard errors put on it
/// if they were independent (1/sqrt(n) each).
fn correlation(x: &[f64], y: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (a, b) in x.iter().zip(y) {
        sxy += (a - mx) * (b - my);
        sxx += (a - mx) * (a - mx);
        syy += (b - my) * (b - my);
    }
    (sxy / (sxx * syy).sqrt(), 5.0 / n.sqrt())
}

#[test]
fn sobol_pairs_and_neighbouring_pixels_are_decorrelated() {
    let samples = census(5, 1);
    let pixels = (SIZE * SIZE) as usize;
    let column = |dim: usize, coord: usize, shift: usize| -> Vec<f64> {
        (0..pixels)
            .flat_map(|p| {
                series(&samples, (p + shift) % pixels, dim)
                    .iter()
                    .map(move |s| f64::from(s[coord]))
            })
            .collect()
    };
    // Sample i of pair A against sample i of pair B in the same pixel: a padded sampler
    // shuffles each pair's sequence on its own, or the pairs would be the same points.
    for (a, b) in [(0, 1), (0, 2), (1, 3), (2, 3)] {
        for (ca, cb) in [(0, 0), (1, 1), (0, 1)] {
            let (r, bound) = correlation(&column(a, ca, 0), &column(b, cb, 0));
            assert!(
                r.abs() < bound,
                "pairs {a}.{ca} and {b}.{cb}: correlation {r:.4} (bound {bound:.4})"
            );
        }
    }
    // The same pair in the next pixel: each pixel is scrambled on its own.
    for coord in 0..2 {
        let (r, bound) = correlation(&column(0, coord, 0), &column(0, coord, 1));
        assert!(
            r.abs() < bound,
            "neighbouring pixels, coordinate {coord}: correlation {r:.4} (bound {bound:.4})"
        );
    }
}

#[test]
fn independent_sampler_is_uniform_and_uncorrelated() {
    let samples = census(7, 0);
    let values: Vec<f64> = samples.iter().flatten().map(|&v| f64::from(v)).collect();
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
    // Uniform on [0, 1): mean 1/2 (standard error sqrt(1/12 / n)), variance 1/12 (standard
    // error sqrt(1/180 / n): the fourth central moment is 1/80, 1/80 - 1/144 = 1/180).
    assert!(
        (mean - 0.5).abs() < 5.0 * (1.0 / 12.0 / n).sqrt(),
        "mean {mean}"
    );
    assert!(
        (var - 1.0 / 12.0).abs() < 5.0 * (1.0 / 180.0 / n).sqrt(),
        "variance {var}"
    );
    let x: Vec<f64> = samples.iter().map(|s| f64::from(s[0])).collect();
    let y: Vec<f64> = samples.iter().map(|s| f64::from(s[1])).collect();
    let (r, bound) = correlation(&x, &y);
    assert!(r.abs() < bound, "x and y: correlation {r} (bound {bound})");
    // Consecutive samples of one series.
    let (r, bound) = correlation(&x[..x.len() - 1], &x[1..]);
    assert!(
        r.abs() < bound,
        "consecutive samples: correlation {r} (bound {bound})"
    );
}

const SAMPLER_SETS: [[&str; 4]; 2] = [
    [
        "intersect.sampler_kind=0",
        "ambient.sampler_kind=0",
        "direct.sampler_kind=0",
        "indirect.sampler_kind=0",
    ],
    [
        "intersect.sampler_kind=1",
        "ambient.sampler_kind=1",
        "direct.sampler_kind=1",
        "indirect.sampler_kind=1",
    ],
];

#[test]
fn both_samplers_are_unbiased_on_the_furnace() {
    for set in SAMPLER_SETS {
        let renders: Vec<_> = (1..=8)
            .map(|seed| {
                render(
                    &settings(
                        "graphs/pathtracer.ron",
                        "tests/data/furnace/scene.ron",
                        16,
                        seed,
                        &set,
                    ),
                    8,
                )
            })
            .collect();
        for (name, expected) in [("direct", 0.25), ("indirect", 0.125), ("sum", 0.875)] {
            let images: Vec<_> = renders.iter().map(|s| channel(s, name)).collect();
            // 1e-6 for f32 sums.
            assert_unbiased(&format!("{set:?} {name}"), &images, [expected; 3], 1e-6);
        }
    }
}

#[test]
fn both_samplers_are_unbiased_on_the_cornell_box() {
    let (expected, slack) = cornell_reference_mean();
    for set in SAMPLER_SETS {
        let images: Vec<_> = (1..=8)
            .map(|seed| {
                let s = render(
                    &settings(
                        "graphs/pathtracer.ron",
                        "scenes/cornell/scene.ron",
                        32,
                        seed,
                        &set,
                    ),
                    8,
                );
                channel(&s, "l0+direct+indirect")
            })
            .collect();
        assert_unbiased(&format!("{set:?}"), &images, expected, slack);
    }
}
