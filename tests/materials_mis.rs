//! Multiple importance sampling is unbiased: light sampling alone, BSDF sampling alone and the
//! two combined by the power heuristic (the `mis_strategy` param, shaders/lib/mis.wgsl) give the
//! same direct and indirect light, block by block, within five standard errors of their
//! difference: on tests/data/mis_glossy (a rough gold floor under two area lights, whose glossy
//! reflections fill the view, so both strategies matter at every pixel) and on the materials
//! showcase (rough conductor, rough plastic, glass, a textured floor), and on a rough gold
//! sphere under an environment map and a point light (tests/data/mis_environment). Each strategy alone drops a different set of paths if a weight is wrong (a
//! missing pdf factor, a light pdf that ignores light selection, a delta lobe counted twice),
//! so any such error separates them. Run on the GPU (lavapipe in CI).

mod common;

use common::render::{image, render, settings};
use passgraph::render::image::RgbImage;

const SIZE: u32 = 32;
const BLOCKS: u32 = 4;
const SEEDS: u32 = 12;
const FRAMES: u32 = 16;

/// The mean of each of BLOCKS x BLOCKS blocks of an image (all three components).
fn block_means(img: &RgbImage) -> Vec<f64> {
    let side = (SIZE / BLOCKS) as usize;
    let mut sums = vec![0.0; (BLOCKS * BLOCKS) as usize];
    for (i, p) in img.pixels.iter().enumerate() {
        let (x, y) = (i % SIZE as usize, i / SIZE as usize);
        let block = (y / side) * BLOCKS as usize + x / side;
        sums[block] += p.iter().map(|&c| f64::from(c)).sum::<f64>();
    }
    sums.iter().map(|s| s / (3 * side * side) as f64).collect()
}

/// Per channel, per block: the mean over SEEDS independent estimates and the standard error of
/// that mean. The estimates are disjoint sample ranges of one session with the independent
/// sampler (PCG: every sample index draws independent numbers), so the shaders are compiled
/// once per strategy, not once per estimate (session set-up was most of this test's time).
fn estimate(scene: &str, graph: &str, strategy: u32, extra: &[&str]) -> Vec<Vec<(f64, f64)>> {
    let set = format!("path.mis_strategy={strategy}");
    let mut sets = vec![set.as_str(), "path.sampler_kind=0"];
    sets.extend_from_slice(extra);
    let mut session = render(&settings(graph, scene, SIZE, 0, &sets), 0);
    let mut per_seed: Vec<Vec<Vec<f64>>> = Vec::new();
    for seed in 0..SEEDS {
        session.start_at_sample(seed * FRAMES);
        for _ in 0..FRAMES {
            assert!(session.render_frame().unwrap());
        }
        per_seed.push(
            CHANNELS
                .iter()
                .map(|c| block_means(&image(&session, c)))
                .collect(),
        );
    }
    let n = f64::from(SEEDS);
    (0..CHANNELS.len())
        .map(|c| {
            (0..(BLOCKS * BLOCKS) as usize)
                .map(|b| {
                    let mean = per_seed.iter().map(|m| m[c][b]).sum::<f64>() / n;
                    let var = per_seed
                        .iter()
                        .map(|m| (m[c][b] - mean).powi(2))
                        .sum::<f64>()
                        / (n - 1.0);
                    (mean, (var / n).sqrt())
                })
                .collect()
        })
        .collect()
}

const CHANNELS: [&str; 2] = ["direct", "indirect"];

/// Asserts every block of every strategy agrees with the combination within five standard
/// errors of the difference (a false failure about once in 1.7 million per comparison; 48
/// comparisons per channel).
fn assert_strategies_agree(scene: &str, graph: &str, extra: &[&str]) {
    let both = estimate(scene, graph, 0, extra);
    for strategy in [1, 2] {
        let alone = estimate(scene, graph, strategy, extra);
        for (c, channel) in CHANNELS.iter().enumerate() {
            for (b, (a, m)) in alone[c].iter().zip(&both[c]).enumerate() {
                let bound = 5.0 * (a.1 * a.1 + m.1 * m.1).sqrt();
                assert!(
                    (a.0 - m.0).abs() <= bound,
                    "{scene} {graph} {channel} block {b}: strategy {strategy} gives {} (se {}), MIS {} (se {}), bound {bound}",
                    a.0,
                    a.1,
                    m.0,
                    m.1
                );
            }
        }
    }
}

const GLOSSY: &str = "tests/data/mis_glossy/scene.ron";
const FUSED: &str = "graphs/pathtracer-fused.ron";

#[test]
fn light_sampling_bsdf_sampling_and_mis_agree_on_glossy_reflections_of_lights() {
    assert_strategies_agree(GLOSSY, FUSED, &[]);
}

#[test]
fn the_strategies_agree_under_light_selection() {
    assert_strategies_agree(GLOSSY, FUSED, &["path.light_selection=true"]);
}

/// A rough gold sphere under an environment map and a point light (scripts/make-lights-scenes):
/// environment rays that miss the scene are weighted against the environment's own sampling.
const ENVIRONMENT: &str = "tests/data/mis_environment/scene.ron";

#[test]
fn the_strategies_agree_on_a_glossy_sphere_under_an_environment_map() {
    assert_strategies_agree(ENVIRONMENT, FUSED, &[]);
}

#[test]
fn the_strategies_agree_under_an_environment_map_with_light_selection() {
    assert_strategies_agree(ENVIRONMENT, FUSED, &["path.light_selection=true"]);
}

#[test]
fn the_strategies_agree_on_every_material_of_the_showcase() {
    assert_strategies_agree("scenes/materials/scene.ron", FUSED, &[]);
}
