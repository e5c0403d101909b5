//! The wavefront graphs (graphs/pathtracer-wavefront.ron, shaders/lib/wavefront.wgsl, and
//! graphs/pathtracer-wavefront-merged.ron, one pass per level) against the fused pass with one bounce and one light sample per primary hit: the same estimator on
//! the same samples, so the same image but for the rounding of products taken in another
//! order (the wavefront multiplies a path's throughput before it meets the light, the fused
//! pass after). On the GPU (lavapipe in CI), on scenes that exercise each kind of vertex.

mod common;

use common::render::{image as channel, max_relative_difference, render, settings};
use passgraph::render::session::Session;

const WAVEFRONT: &str = "graphs/pathtracer-wavefront.ron";
const MERGED: &str = "graphs/pathtracer-wavefront-merged.ron";
const FUSED: &str = "graphs/pathtracer-fused.ron";
/// The fused pass's estimator that the wavefront's is.
const ONE_PATH: [&str; 2] = ["path.bounces=1", "path.light_samples=1"];

/// Renders `scene` with the fused pass and `wavefront` (`max_depth` replacing the scene's where given; `set`
/// params `P=V` set on the fused pass and on the wavefront's passes that have them) and
/// compares `channels` one by one, and the rays they traced.
fn check_graph(
    wavefront_graph: &str,
    scene: &str,
    size: u32,
    max_depth: Option<u32>,
    set: &[(&str, &[&str])],
    channels: &[&str],
) {
    let session = |graph: &str, sets: Vec<String>| -> Session {
        let sets: Vec<&str> = sets.iter().map(String::as_str).collect();
        let mut s = settings(graph, scene, size, 3, &sets);
        s.max_depth = max_depth;
        render(&s, 4)
    };
    let mut fused_sets: Vec<String> = ONE_PATH.iter().map(|s| s.to_string()).collect();
    let mut wavefront_sets = Vec::new();
    for (param, instances) in set {
        fused_sets.push(format!("path.{param}"));
        wavefront_sets.extend(instances.iter().map(|i| format!("{i}.{param}")));
    }
    let fused = session(FUSED, fused_sets);
    let wavefront = session(wavefront_graph, wavefront_sets);
    for c in channels {
        let (a, b) = (channel(&fused, c), channel(&wavefront, c));
        assert!(
            a.mean()[0] > 0.0,
            "{scene} {c} is black: the comparison would be empty"
        );
        // A dozen roundings of f32 products per vertex, over at most 8 vertices: a few 1e-6
        // at most; anything the estimators do differently moves pixels by whole percents.
        let d = max_relative_difference(&a, &b);
        assert!(d <= 1e-5, "{scene} {c}: the wavefront image differs by {d}");
    }
    assert_eq!(fused.dropped().unwrap(), 0);
    assert_eq!(wavefront.dropped().unwrap(), 0);
    // The same rays: both trace the primary hit's BSDF sample once for both channels.
    let rays = |s: &Session| s.rays_counted().unwrap().unwrap();
    let (f, w) = (rays(&fused), rays(&wavefront));
    assert_eq!(
        w, f,
        "{scene}: the wavefront's rays against the fused pass's"
    );
}

/// check_graph for graphs/pathtracer-wavefront.ron.
fn check(
    scene: &str,
    size: u32,
    max_depth: Option<u32>,
    set: &[(&str, &[&str])],
    channels: &[&str],
) {
    check_graph(WAVEFRONT, scene, size, max_depth, set, channels);
}

/// Every pass of the wavefront that shades with light sampling.
const SHADING: [&str; 8] = [
    "camera", "shade_0", "shade_1", "shade_2", "shade_3", "shade_4", "shade_5", "shade_6",
];

#[test]
fn wavefront_renders_the_fused_passes_samples_in_the_cornell_box_with_ambient_light() {
    check(
        "scenes/cornell/scene.ron",
        32,
        None,
        &[("ambient_color=0.2,0.2,0.2", &["camera"])],
        &["l0", "direct", "indirect", "ambient"],
    );
}

#[test]
fn wavefront_renders_the_fused_passes_samples_through_glass_gold_and_plastic_at_depth_8() {
    check(
        "scenes/materials/scene.ron",
        48,
        Some(8),
        &[],
        &["l0", "direct", "indirect"],
    );
}

#[test]
fn wavefront_renders_the_fused_passes_samples_under_an_environment_map_at_depth_8() {
    check(
        "tests/data/scenes/hdri/hdri.ron",
        32,
        Some(8),
        &[],
        &["l0", "direct", "indirect"],
    );
}

#[test]
fn wavefront_renders_the_fused_passes_samples_with_a_textured_spot_light() {
    check(
        "tests/data/scenes/lights/spot-texture.ron",
        32,
        Some(5),
        &[],
        &["direct", "indirect"],
    );
}

#[test]
fn wavefront_renders_the_fused_passes_samples_with_light_selection() {
    check(
        "scenes/cornell-many-lights/scene.ron",
        32,
        Some(4),
        &[("light_selection=true", &SHADING)],
        &["direct", "indirect"],
    );
}

/// Paths longer than the graph's levels: the last level follows them to their end.
#[test]
fn wavefront_last_level_finishes_paths_longer_than_the_graph() {
    check(
        "scenes/materials/scene.ron",
        32,
        Some(12),
        &[],
        &["indirect"],
    );
}

/// One pass per level, tracing its own rays: the same paths.
#[test]
fn merged_levels_render_the_fused_passes_samples_through_glass_gold_and_plastic() {
    check_graph(
        MERGED,
        "scenes/materials/scene.ron",
        32,
        Some(10),
        &[],
        &["l0", "direct", "indirect"],
    );
}
