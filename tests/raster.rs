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

/// A pixel where the rasteriser and intersect see different triangles (`u32::MAX`: none), with
/// how far inside its triangle each one's point is: the smallest barycentric coordinate (0 on
/// an edge; `None` where that side sees nothing).
#[derive(Debug)]
struct Mismatch {
    pixel: (u32, u32),
    drawn: u32,
    hit: u32,
    drawn_edge: Option<f32>,
    hit_edge: Option<f32>,
}

fn smallest_barycentric(u: f32, v: f32) -> f32 {
    u.min(v).min(1.0 - u - v)
}

/// The mismatches between the rasteriser's and intersect's visible triangle at pixel centres
/// (no jitter) at `size`².
fn triangle_mismatches(size: u32) -> Vec<Mismatch> {
    let dir = tempfile::tempdir().unwrap();
    let raster_graph = with_output(dir.path(), RASTER, "vbuffer");
    let traced_graph = with_output(dir.path(), PATHTRACER, "rays");
    let no_jitter = [
        "visibility.pixel_jitter=false",
        "primary.pixel_jitter=false",
    ];
    let raster = render(&settings(&raster_graph, CORNELL, size, 0, &no_jitter), 1);
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
    let vbuffer = words(&raster, "vbuffer");
    // rays: three layers of rgba32float; layer 2 is t, u, v, triangle bits.
    let rays = words(&traced, "rays");
    assert_eq!((vbuffer.len(), rays.len()), (4 * pixels, 12 * pixels));
    let f = f32::from_bits;
    (0..pixels)
        .filter_map(|i| {
            let drawn = vbuffer[4 * i].wrapping_sub(1);
            let h = &rays[4 * (2 * pixels + i)..][..4];
            let hit = h[3];
            (drawn != hit).then(|| Mismatch {
                pixel: (i as u32 % size, i as u32 / size),
                drawn,
                hit,
                drawn_edge: (drawn != u32::MAX)
                    .then(|| smallest_barycentric(f(vbuffer[4 * i + 1]), f(vbuffer[4 * i + 2]))),
                hit_edge: (hit != u32::MAX).then(|| smallest_barycentric(f(h[1]), f(h[2]))),
            })
        })
        .collect()
}

#[test]
fn rasteriser_sees_intersects_triangle_at_pixel_centres() {
    // Two sizes: 128 puts the box's edges on round pixel positions, 97 anywhere.
    for size in [97, 128] {
        let mismatches = triangle_mismatches(size);
        let pixels = (size * size) as usize;
        // The two can disagree only where a pixel centre lies on an edge, within rounding: the
        // rasteriser's fixed-point edge functions (8 bits of sub-pixel precision) and tie rule
        // against the watertight ray test. So every triangle either side sees at a mismatch is
        // seen at its edge: its smallest barycentric coordinate within EDGE of 0 (a Cornell box
        // triangle spans tens of pixels here, so 1e-3 is a few hundredths of a pixel).
        const EDGE: f32 = 1e-3;
        for m in &mismatches {
            for edge in [m.drawn_edge, m.hit_edge].into_iter().flatten() {
                assert!(
                    edge.abs() < EDGE,
                    "{size}x{size}, pixel {:?}: the rasteriser sees triangle {:#x}, intersect {:#x}, not at an edge ({m:?})",
                    m.pixel,
                    m.drawn,
                    m.hit
                );
            }
        }
        // And such centres are rare: the box's 32 triangles have edges a few thousand pixels
        // long in all at this size, and a centre within a few hundredths of a pixel of one,
        // for at most a few of them, is far below one pixel per thousand.
        assert!(
            mismatches.len() <= pixels / 1000,
            "{size}x{size}: {} of {pixels} pixels differ: {mismatches:?}",
            mismatches.len()
        );
        println!(
            "{size}x{size}: {} of {pixels} differ: {mismatches:?}",
            mismatches.len()
        );
    }
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
