//! The path tracer on the GPU (lavapipe in CI) against independent ground truth: the analytic
//! furnace and Mitsuba 3 references of the Cornell box. Every bound is derived from the
//! variance measured in the same run, never widened by hand.

mod common;

use common::render::{image as channel, render};
use common::root;
use passgraph::bench::metrics::{downsample_2x, image_error};
use passgraph::render::image::RgbImage;
use passgraph::render::session::{RenderSettings, Session};
use std::sync::OnceLock;

fn settings(scene: &str, size: u32, seed: u32, set: &[&str]) -> RenderSettings {
    common::render::settings("graphs/pathtracer.ron", scene, size, seed, set)
}

/// Mean over pixels and components, and the standard error of that mean from the spread of
/// the per-pixel means (valid when every pixel has the same expectation, as in the furnace).
fn mean_and_standard_error(img: &RgbImage) -> (f64, f64) {
    let values: Vec<f64> = img.pixels.iter().flatten().map(|&v| f64::from(v)).collect();
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    // Components of one pixel are identical in a grey furnace: count pixels, not components.
    (mean, (var / (n / 3.0)).sqrt())
}

#[test]
fn furnace_gives_le_times_one_rho_rho_squared() {
    let session = render(&settings("tests/data/furnace/scene.ron", 32, 1, &[]), 64);
    // L0 is deterministic: every primary ray sees an inward-emitting wall.
    let (l0, l0_se) = mean_and_standard_error(&channel(&session, "l0"));
    assert!(
        (l0 - 0.5).abs() < 1e-6 && l0_se < 1e-6,
        "L0 {l0} (se {l0_se})"
    );
    for (name, expected) in [("direct", 0.25), ("indirect", 0.125), ("sum", 0.875)] {
        let (mean, se) = mean_and_standard_error(&channel(&session, name));
        // Five standard errors: a false failure once in ~1.7 million runs; 1e-5 for f32
        // accumulation of 64 frames.
        let bound = 5.0 * se + 1e-5;
        assert!(
            (mean - expected).abs() < bound,
            "{name}: mean {mean}, expected {expected}, bound {bound} (se {se})"
        );
    }
    assert_eq!(session.dropped().unwrap(), 0);
    // Rays, as the passes count them: per pixel and frame 1 primary ray, 5 shadow rays from
    // the primary hit (the 6 emitting faces, each one parallelogram light, minus the one
    // coplanar with the hit, where cos = 0 casts nothing), and 1 bounce plus 5 shadow rays
    // from the second hit: 12.
    let expected = 12 * 32 * 32 * 64;
    let counted = session
        .rays_counted()
        .unwrap()
        .expect("the passes count rays");
    assert!(
        counted <= expected && counted as f64 >= 0.999 * expected as f64,
        "{counted} rays counted, {expected} expected"
    );
}

const CORNELL: &str = "scenes/cornell/scene.ron";
const CORNELL_FRAMES: u32 = 128;

/// Two independent 128² renders of the Cornell box, shared by the tests below.
fn cornell_pair() -> &'static (Session, Session) {
    static PAIR: OnceLock<(Session, Session)> = OnceLock::new();
    PAIR.get_or_init(|| {
        (
            render(&settings(CORNELL, 128, 1, &[]), CORNELL_FRAMES),
            render(&settings(CORNELL, 128, 2, &[]), CORNELL_FRAMES),
        )
    })
}

/// Checks a render against a reference: per-channel means within 1 %, and an MSE no larger
/// than the render's own noise (half the MSE between two independent renders), the
/// reference's noise floor (RMSE 1e-3, its README) and five standard errors of both MSEs.
fn check_against_reference(channels: &str, reference: RgbImage) {
    let (a, b) = cornell_pair();
    let a = channel(a, channels);
    let b = channel(b, channels);
    let ours = a.mean();
    let theirs = reference.mean();
    for k in 0..3 {
        let rel = (ours[k] - theirs[k]).abs() / theirs[k];
        assert!(
            rel < 0.01,
            "{channels}: component {k} mean {} vs reference {} ({:.2} %)",
            ours[k],
            theirs[k],
            rel * 100.0
        );
    }
    let vs_reference = image_error(&a, &reference).unwrap();
    let between = image_error(&a, &b).unwrap();
    let noise = between.mse() / 2.0;
    let floor = 1e-3f64.powi(2);
    let slack = 5.0 * (vs_reference.mse_standard_error + between.mse_standard_error / 2.0);
    let bound = noise + floor + slack;
    eprintln!(
        "{channels}: RMSE vs reference {:.5}, expected from noise {:.5}, bound {:.5}",
        vs_reference.rmse,
        (noise + floor).sqrt(),
        bound.sqrt()
    );
    assert!(
        vs_reference.mse() < bound,
        "{channels}: RMSE {} exceeds the noise bound {}",
        vs_reference.rmse,
        bound.sqrt()
    );
}

fn reference(name: &str) -> RgbImage {
    RgbImage::read_exr(&root().join("tests/data/references").join(name)).unwrap()
}

#[test]
fn cornell_box_matches_mitsuba_with_one_bounce() {
    check_against_reference("l0+direct+indirect", reference("cornell-128-depth3.exr"));
}

#[test]
fn cornell_box_direct_light_matches_mitsuba() {
    let reference = downsample_2x(&reference("cornell-256-depth2.exr"));
    check_against_reference("l0+direct", reference);
}

#[test]
fn cornell_red_wall_is_on_the_left_and_green_on_the_right() {
    let img = channel(&cornell_pair().0, "sum");
    let column_mean = |x0: u32, x1: u32| {
        let mut sum = [0.0f64; 3];
        for y in 32..96 {
            for x in x0..x1 {
                let p = img.pixels[(y * img.width + x) as usize];
                for k in 0..3 {
                    sum[k] += f64::from(p[k]);
                }
            }
        }
        sum
    };
    let left = column_mean(0, 8);
    let right = column_mean(120, 128);
    assert!(left[0] > 2.0 * left[1], "left wall is red: {left:?}");
    assert!(right[1] > 2.0 * right[0], "right wall is green: {right:?}");
}

#[test]
fn same_seed_gives_identical_bytes_and_another_seed_differs() {
    let s = |seed| {
        render(&settings(CORNELL, 32, seed, &[]), 4)
            .result()
            .unwrap()
    };
    let a = s(7);
    assert_eq!(
        bytemuck::cast_slice::<_, u8>(&a),
        bytemuck::cast_slice::<_, u8>(&s(7))
    );
    assert_ne!(
        bytemuck::cast_slice::<_, u8>(&a),
        bytemuck::cast_slice::<_, u8>(&s(8))
    );
}

#[test]
fn camera_inside_the_closed_tall_block_sees_no_light_at_all() {
    let session = render(
        &settings("tests/data/inside_block/scene.ron", 32, 3, &[]),
        16,
    );
    for c in ["l0", "direct", "indirect", "sum"] {
        let img = channel(&session, c);
        let max = img.pixels.iter().flatten().fold(0.0f32, |m, &v| m.max(v));
        assert_eq!(max, 0.0, "{c}: light leaked into the closed block");
    }
    // Every pixel still accumulated its samples.
    let result = session.result().unwrap();
    assert!(result.iter().all(|p| p[3] == 16.0));
}

#[test]
fn scene_without_emitters_is_black_and_casts_no_shadow_rays() {
    let session = render(&settings("tests/data/no_lights/scene.ron", 32, 4, &[]), 4);
    assert_eq!(session.scene().light_count, 0);
    assert!(session.scene().lights.is_empty());
    let img = channel(&session, "sum");
    assert!(img.pixels.iter().flatten().all(|&v| v == 0.0));
    // Only the primary rays remain: no shadow rays, no bounce.
    assert_eq!(session.rays_counted().unwrap(), Some(32 * 32 * 4));
}

#[test]
fn ambient_light_needs_no_emitter_and_is_kd_times_colour_when_unoccluded() {
    let s = settings(
        "tests/data/no_lights/scene.ron",
        32,
        5,
        &["ambient.ambient_color=1,1,1", "ambient.radius=1e-3"],
    );
    // With a tiny radius nothing occludes: ambient is exactly kd * colour at each hit.
    let session = render(&s, 2);
    let ambient = channel(&session, "ambient");
    let white_kd = [0.885809f32, 0.698859, 0.666422];
    let center = ambient.pixels[(16 * 32 + 16) as usize];
    for k in 0..3 {
        assert!((center[k] - white_kd[k]).abs() < 1e-6, "{center:?}");
    }
}

#[test]
fn settings_name_the_bad_instance_or_param() {
    for (set, expect) in [
        ("nope.radius=1", "no pass instance 'nope'"),
        ("ambient.size=1", "no param 'size'"),
        ("ambient.radius=far", "'far' is not an f32"),
    ] {
        let err = Session::new(&settings(CORNELL, 8, 0, &[set]))
            .err()
            .expect("should fail");
        assert!(err.to_string().contains(expect), "{err}");
    }
}

#[test]
fn accumulation_stops_at_max_frames_and_a_camera_move_restarts_it() {
    let mut s = settings(CORNELL, 8, 0, &[]);
    s.max_frames = 3;
    let mut session = render(&s, 3);
    assert!(
        !session.render_frame().unwrap(),
        "a fourth frame is not accumulated"
    );
    assert!(session.result().unwrap().iter().all(|p| p[3] == 3.0));
    let camera = session.scene_description().camera;
    session.set_camera(camera).unwrap();
    assert_eq!(session.accumulated(), 0);
    assert!(session.render_frame().unwrap());
    assert!(session.result().unwrap().iter().all(|p| p[3] == 1.0));
}
