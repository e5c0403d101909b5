//! Raster passes on the GPU (lavapipe in CI): graphs/pathtracer-raster.ron, whose raster pass
//! (shaders/visibility.wgsl) and conversion pass (shaders/vbuffer_rays.wgsl) replace intersect,
//! renders the expectation of graphs/pathtracer.ron, and its rasteriser sees the triangle
//! intersect's rays hit at every pixel centre but a few on edges.

mod common;

use common::render::{image as channel, render, root, settings};
use common::stats::{assert_unbiased, cornell_reference_mean, mean_over_seeds};
use passgraph::render::session::Session;
use std::path::{Path, PathBuf};

const CORNELL: &str = "scenes/cornell/scene.ron";
const RASTER: &str = "graphs/pathtracer-raster.ron";
const PATHTRACER: &str = "graphs/pathtracer.ron";

#[test]
fn raster_graph_has_the_expectation_of_the_path_tracer() {
    let (reference, slack) = cornell_reference_mean();
    let images = |graph: &str| -> Vec<_> {
        (0..16)
            .map(|seed| channel(&render(&settings(graph, CORNELL, 32, seed, &[]), 2), "sum"))
            .collect()
    };
    let raster = images(RASTER);
    let traced = images(PATHTRACER);
    assert_unbiased("Cornell box, raster graph", &raster, reference, slack);
    // Against the path tracer's own means: within 5 standard errors of the difference.
    let (a, se_a) = mean_over_seeds(&raster);
    let (b, se_b) = mean_over_seeds(&traced);
    for k in 0..3 {
        let bound = 5.0 * (se_a[k].powi(2) + se_b[k].powi(2)).sqrt();
        assert!(
            (a[k] - b[k]).abs() < bound,
            "component {k}: raster mean {} and path tracer mean {} differ by more than {bound}",
            a[k],
            b[k]
        );
    }
}

#[test]
fn raster_graph_counts_one_primary_ray_per_pixel_and_drops_nothing() {
    let session = render(&settings(RASTER, CORNELL, 32, 1, &[]), 3);
    assert_eq!(session.dropped().unwrap(), 0);
    let rays = session.read_resource("rays_intersect").unwrap();
    let count = u64::from_le_bytes(rays[..8].try_into().unwrap());
    assert_eq!(count, 3 * 32 * 32);
}

/// A graph extending `graph` that also reads back `output`, in `dir`.
fn with_output(dir: &Path, graph: &str, output: &str) -> PathBuf {
    let path = dir.join(format!("{output}.ron"));
    let text = format!(
        "Graph(extends: {:?}, outputs: [{output:?}])",
        root().join(graph).display().to_string()
    );
    std::fs::write(&path, text).unwrap();
    path
}

fn words(session: &Session, resource: &str) -> Vec<u32> {
    session
        .read_resource(resource)
        .unwrap()
        .chunks_exact(4)
        .map(|b| u32::from_le_bytes(b.try_into().unwrap()))
        .collect()
}

/// Pixels whose visible triangle differs between the rasteriser and intersect at pixel centres
/// (no jitter), and the pixels compared.
fn triangle_mismatches(size: u32) -> (Vec<(u32, u32, u32, u32)>, usize) {
    let dir = tempfile::tempdir().unwrap();
    let raster_graph = with_output(dir.path(), RASTER, "vbuffer");
    let traced_graph = with_output(dir.path(), PATHTRACER, "rays");
    let raster = render(
        &settings(
            &raster_graph,
            CORNELL,
            size,
            0,
            &[
                "visibility.pixel_jitter=false",
                "primary.pixel_jitter=false",
            ],
        ),
        1,
    );
    let traced = render(
        &settings(
            &traced_graph,
            CORNELL,
            size,
            0,
            &["intersect.pixel_jitter=false"],
        ),
        1,
    );
    let pixels = (size * size) as usize;
    // vbuffer: triangle + 1 (0: none), u, v, t per texel.
    let drawn: Vec<u32> = words(&raster, "vbuffer")
        .chunks_exact(4)
        .map(|t| t[0].wrapping_sub(1))
        .collect();
    // rays: three layers of rgba32float; the triangle's bits are layer 2's fourth component.
    let hit: Vec<u32> = words(&traced, "rays")[2 * 4 * pixels..]
        .chunks_exact(4)
        .map(|t| t[3])
        .collect();
    assert_eq!((drawn.len(), hit.len()), (pixels, pixels));
    let mismatches = (0..pixels)
        .filter(|&i| drawn[i] != hit[i])
        .map(|i| (i as u32 % size, i as u32 / size, drawn[i], hit[i]))
        .collect();
    (mismatches, pixels)
}

#[test]
fn rasteriser_sees_intersects_triangle_at_pixel_centres() {
    let (mismatches, pixels) = triangle_mismatches(128);
    // The two disagree only where a pixel centre lies on (within rounding of) an edge: the
    // rasteriser's fixed-point edge functions and tie rule against the watertight ray test.
    // The Cornell box's 32 triangles cross a 128x128 image in edges about 3,000 pixels long in
    // all; a centre within rounding (~1e-4 pixel) of one is rare. Each mismatch must be a
    // triangle seen by both (an edge between two), never geometry one of them misses.
    assert!(
        mismatches.len() <= pixels / 1000,
        "{} of {pixels} pixels differ: {:?}",
        mismatches.len(),
        &mismatches[..mismatches.len().min(20)]
    );
    for &(x, y, drawn, hit) in &mismatches {
        assert!(
            drawn != u32::MAX && hit != u32::MAX,
            "pixel ({x}, {y}): rasteriser {drawn:#x}, intersect {hit:#x}"
        );
    }
    println!(
        "{} mismatches of {pixels}: {mismatches:?}",
        mismatches.len()
    );
}

#[test]
fn raster_rays_match_intersects_at_pixel_centres() {
    // With the visible triangle agreeing, the conversion pass's t, u, v are intersect's own
    // (the same watertight test on the same ray), so the whole image is the path tracer's.
    let raster = render(
        &settings(
            RASTER,
            CORNELL,
            32,
            3,
            &[
                "visibility.pixel_jitter=false",
                "primary.pixel_jitter=false",
            ],
        ),
        2,
    );
    let traced = render(
        &settings(
            PATHTRACER,
            CORNELL,
            32,
            3,
            &["intersect.pixel_jitter=false"],
        ),
        2,
    );
    for c in ["l0", "direct", "indirect"] {
        let (a, b) = (channel(&raster, c), channel(&traced, c));
        assert_eq!(a.pixels, b.pixels, "{c} differs");
    }
}
