//! The fused graph (graphs/pathtracer-fused.ron, shaders/path.wgsl) against the seed's separate
//! passes, its samples per frame, and the indirect channel's splitting (`bounces`), on the GPU
//! (lavapipe in CI).

mod common;

use common::render::{image as channel, max_relative_difference, render, settings};
use common::stats::{assert_unbiased, cornell_reference_mean};

const CORNELL: &str = "scenes/cornell/scene.ron";

#[test]
fn fused_pass_renders_the_separate_passes_samples_in_every_channel() {
    // A grey ambient light, so that the ambient channel casts rays too.
    let separate = render(
        &settings(
            "graphs/pathtracer.ron",
            CORNELL,
            32,
            5,
            &["ambient.ambient_color=0.2,0.2,0.2"],
        ),
        4,
    );
    let fused = render(
        &settings(
            "graphs/pathtracer-fused.ron",
            CORNELL,
            32,
            5,
            &["path.ambient_color=0.2,0.2,0.2"],
        ),
        4,
    );
    for c in ["l0", "direct", "indirect", "ambient"] {
        let (a, b) = (channel(&separate, c), channel(&fused, c));
        assert!(
            a.mean()[0] > 0.0,
            "{c} is black: the comparison would be empty"
        );
        // The same functions on the same samples: the primary ray the lighting passes read from
        // the ray texture is the one the fused pass keeps in registers, bit for bit.
        let d = max_relative_difference(&a, &b);
        assert!(d <= 1e-6, "{c}: the fused image differs by {d}");
    }
    assert_eq!(separate.dropped().unwrap(), 0);
    assert_eq!(fused.dropped().unwrap(), 0);
}

#[test]
fn four_samples_per_frame_give_the_image_of_four_times_the_frames() {
    let one = render(
        &settings("graphs/pathtracer-fused.ron", CORNELL, 32, 2, &[]),
        8,
    );
    let four = render(
        &settings(
            "graphs/pathtracer-fused.ron",
            CORNELL,
            32,
            2,
            &["path.samples_per_frame=4"],
        ),
        2,
    );
    let (a, b) = (channel(&one, "sum"), channel(&four, "sum"));
    // The same 8 samples per pixel, averaged in another order: f32 rounding only.
    let d = max_relative_difference(&a, &b);
    assert!(d <= 1e-5, "the images differ by {d}");
    // Each frame counts once however many samples it holds.
    assert!(four.result().unwrap().iter().all(|p| p[3] == 2.0));
}

#[test]
fn split_light_samples_keep_the_expectation_and_the_fused_pass_takes_the_same_ones() {
    // The Cornell box against its reference's mean. (Not the furnace: next to its edges and
    // corners a point samples the adjacent wall by area with weights up to 1/r^2, a heavy
    // tail that makes the spread between a few seeds no measure of the error.)
    let (expected, slack) = cornell_reference_mean();
    let images: Vec<_> = (1..=8)
        .map(|seed| {
            let set = ["path.light_samples=3"];
            let s = settings("graphs/pathtracer-fused.ron", CORNELL, 32, seed, &set);
            channel(&render(&s, 4), "l0+direct+indirect")
        })
        .collect();
    assert_unbiased("Cornell box, 3 light samples", &images, expected, slack);
    // The separate direct pass and the fused pass average the same three estimates.
    let separate = render(
        &settings(
            "graphs/pathtracer.ron",
            CORNELL,
            32,
            5,
            &["direct.light_samples=3"],
        ),
        2,
    );
    let fused = render(
        &settings(
            "graphs/pathtracer-fused.ron",
            CORNELL,
            32,
            5,
            &["path.light_samples=3"],
        ),
        2,
    );
    let (a, b) = (channel(&separate, "direct"), channel(&fused, "direct"));
    let d = max_relative_difference(&a, &b);
    assert!(d <= 1e-6, "the fused direct channel differs by {d}");
    let one = channel(
        &render(&settings("graphs/pathtracer.ron", CORNELL, 32, 5, &[]), 2),
        "direct",
    );
    assert_ne!(a.pixels, one.pixels, "light_samples=3 changed nothing");
}

#[test]
fn split_bounces_keep_the_expectation_on_the_furnace_and_the_cornell_box() {
    let renders = |graph: &str, scene: &str, size: u32, set: &[&str]| -> Vec<_> {
        (1..=8)
            .map(|seed| render(&settings(graph, scene, size, seed, set), 4))
            .collect()
    };
    // Furnace: Le (1 + rho + rho^2) with Le = 0.5, rho = 0.5, every channel exactly known.
    let furnace = renders(
        "graphs/pathtracer-fused.ron",
        "tests/data/furnace/scene.ron",
        16,
        &["path.bounces=4"],
    );
    for (name, expected) in [("indirect", 0.125), ("sum", 0.875)] {
        let images: Vec<_> = furnace.iter().map(|s| channel(s, name)).collect();
        // 1e-6 for f32 sums.
        assert_unbiased(&format!("furnace {name}"), &images, [expected; 3], 1e-6);
    }
    let (expected, slack) = cornell_reference_mean();
    let images: Vec<_> = renders("graphs/pathtracer-fast.ron", CORNELL, 32, &[])
        .iter()
        .map(|s| channel(s, "l0+direct+indirect"))
        .collect();
    assert_unbiased("Cornell box, 8 bounces", &images, expected, slack);
}

#[test]
fn coherent_bounce_order_sums_the_same_bounces_as_index_order() {
    // 11 bounces: a whole batch of 8 and a partial one of 3; both graphs' lighting passes.
    for (graph, pass) in [
        ("graphs/pathtracer.ron", "indirect"),
        ("graphs/pathtracer-fused.ron", "path"),
    ] {
        let bounces = format!("{pass}.bounces=11");
        let image = |coherent: bool| {
            let order = format!("{pass}.coherent_bounces={coherent}");
            let session = render(&settings(graph, CORNELL, 32, 3, &[&bounces, &order]), 2);
            channel(&session, "indirect")
        };
        let (ordered, indexed) = (image(true), image(false));
        assert!(
            ordered.mean()[0] > 0.0,
            "{graph}: the indirect channel is black"
        );
        // The same 11 terms per sample, added in another order: f32 rounding only.
        let d = max_relative_difference(&ordered, &indexed);
        assert!(d <= 1e-5, "{graph}: the images differ by {d}");
        assert_ne!(
            ordered.pixels, indexed.pixels,
            "{graph}: not one pixel changed: is the order param applied?"
        );
    }
}

/// With one light sample and one bounce, the direct channel's MIS half and the indirect
/// channel's first bounce are one BSDF sample (the same sampler pairs): the fused pass traces
/// it once (shaders/lib/shade_one_path.wgsl) where the separate passes trace it twice, and
/// renders the same image.
#[test]
fn fused_pass_traces_the_primary_hits_bsdf_sample_once_for_both_channels() {
    let run = |graph: &str| {
        let mut s = settings(graph, "scenes/materials/scene.ron", 32, 4, &[]);
        s.max_depth = Some(8);
        render(&s, 4)
    };
    let separate = run("graphs/pathtracer.ron");
    let fused = run("graphs/pathtracer-fused.ron");
    for c in ["l0", "direct", "indirect"] {
        let (a, b) = (channel(&separate, c), channel(&fused, c));
        assert!(a.mean()[0] > 0.0, "{c} is black");
        let d = max_relative_difference(&a, &b);
        assert!(d <= 1e-6, "{c}: the fused image differs by {d}");
    }
    let rays = |s: &passgraph::render::session::Session| s.rays_counted().unwrap().unwrap();
    let (s, f) = (rays(&separate), rays(&fused));
    // The gold, plastic and glass fill many of the 32x32 pixels: hundreds of rays a frame.
    assert!(
        f + 4 * 100 <= s,
        "the fused pass traced {f} rays, the separate passes {s}"
    );
}
