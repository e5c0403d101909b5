//! Light selection (shaders/lib/light_select.wgsl, graphs/pathtracer-lightselect.ron) on the GPU
//! (lavapipe in CI): each light is drawn as often as the probability the estimator divides by,
//! the probabilities sum to 1, and the images keep the all-lights images' means.

mod common;

use common::render::render;
use passgraph::render::channels::ChannelSelection;
use passgraph::render::session::{RenderSettings, Session};

fn settings(graph: &str, scene: &str, size: u32, seed: u32) -> RenderSettings {
    common::render::settings(graph, scene, size, seed, &[])
}

const SCENE: &str = "tests/data/light_select/scene.ron";

#[test]
fn each_light_is_drawn_as_often_as_its_probability_and_probabilities_sum_to_one() {
    // 256 x 256 invocations x 64 draws, half at each of the census's two points: 2^21 draws
    // per point.
    let session = render(
        &settings(
            "tests/fixtures/graphs/light_select_census.ron",
            SCENE,
            256,
            0,
        ),
        1,
    );
    let lights = session.scene().light_count as usize;
    assert_eq!(lights, 8);
    let counts: Vec<u32> = bytemuck::pod_collect_to_vec(&session.read_resource("counts").unwrap());
    let pmf: Vec<f32> = bytemuck::pod_collect_to_vec(&session.read_resource("pmf").unwrap());
    let draws = f64::from(1u32 << 21);
    for point in 0..2 {
        let range = point * lights..(point + 1) * lights;
        let p = &pmf[range.clone()];
        let n = &counts[range];
        let sum: f64 = p.iter().map(|&x| f64::from(x)).sum();
        assert!(
            (sum - 1.0).abs() < 1e-5,
            "point {point}: probabilities sum to {sum}"
        );
        assert_eq!(
            n.iter().map(|&c| f64::from(c)).sum::<f64>(),
            draws,
            "point {point}"
        );
        for (i, (&p, &n)) in p.iter().zip(n).enumerate() {
            let p = f64::from(p);
            let frequency = f64::from(n) / draws;
            if p == 0.0 {
                assert_eq!(n, 0, "point {point}, light {i}: probability 0 but drawn");
                continue;
            }
            // The census's lights all have p > 0.01 where drawn: at 2^21 draws the binomial
            // standard deviation is below 0.5 % of p, so 3 % is more than 6 of them (pbrt-v4's
            // light sampler tests use the same 3 %).
            assert!(
                p > 0.01,
                "point {point}, light {i}: p = {p}: the census needs p > 0.01"
            );
            assert!(
                (frequency - p).abs() <= 0.03 * p,
                "point {point}, light {i}: drawn {frequency:.5} of the time, probability {p:.5}"
            );
        }
    }
    // The tilted point must see some lights with probability exactly 0 (wholly below its
    // tangent plane), or the census would not test that case; the light facing away from the
    // floor is never drawn from the floor's centre.
    assert!(pmf[lights..2 * lights].contains(&0.0), "{pmf:?}");
    let up = session
        .scene()
        .lights
        .iter()
        .position(|l| glam::Vec3::from(l.e1).cross(glam::Vec3::from(l.e2)).y > 0.0)
        .expect("the census scene has a light facing up");
    assert_eq!(pmf[up], 0.0, "the light facing up: {pmf:?}");
}

/// Per-pixel difference of one channel between two sessions: its mean over pixels and
/// components, and that mean's standard error from the differences' spread (pixels are
/// independent samples, so the signal cancels and only the noise of both remains).
fn mean_difference(a: &Session, b: &Session, channel: &str) -> (f64, f64) {
    let selection = channel.parse::<ChannelSelection>().unwrap();
    let (x, y) = (a.image(&selection).unwrap(), b.image(&selection).unwrap());
    let d: Vec<f64> = x
        .pixels
        .iter()
        .flatten()
        .zip(y.pixels.iter().flatten())
        .map(|(&p, &q)| f64::from(p) - f64::from(q))
        .collect();
    let n = d.len() as f64;
    let mean = d.iter().sum::<f64>() / n;
    let var = d.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    // The three components of a pixel are correlated: count pixels, not components.
    (mean, (var / (n / 3.0)).sqrt())
}

fn assert_same_means(scene: &str, size: u32, frames: u32, channels: &[&str]) {
    let all = render(&settings("graphs/pathtracer.ron", scene, size, 1), frames);
    let selected = render(
        &settings("graphs/pathtracer-lightselect.ron", scene, size, 2),
        frames,
    );
    for &channel in channels {
        let (mean, se) = mean_difference(&selected, &all, channel);
        let level = {
            let img = all.image(&channel.parse().unwrap()).unwrap();
            img.pixels
                .iter()
                .flatten()
                .map(|&v| f64::from(v))
                .sum::<f64>()
                / (img.pixels.len() * 3) as f64
        };
        eprintln!("{scene} {channel}: mean {level:.5}, selected - all {mean:+.6} (se {se:.6})");
        // Unbiased: the mean difference is within 5 standard errors of 0, and the test can
        // tell: 5 standard errors are under 5 % of the channel's level, so a bias of 5 % fails.
        assert!(
            mean.abs() <= 5.0 * se,
            "{scene} {channel}: {mean} vs se {se}"
        );
        assert!(
            5.0 * se < 0.05 * level,
            "{scene} {channel}: se {se} vs level {level}"
        );
    }
}

#[test]
fn light_selection_keeps_the_means_with_eight_lights_of_different_power() {
    // The floor sees only the emitters, which reflect nothing: no indirect light to compare.
    assert_same_means(SCENE, 64, 64, &["direct"]);
}

#[test]
fn light_selection_keeps_the_means_in_the_cornell_box() {
    assert_same_means("scenes/cornell/scene.ron", 64, 128, &["direct", "indirect"]);
}
