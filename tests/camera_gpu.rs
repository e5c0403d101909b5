//! Cameras and pixel filters on the GPU (lavapipe in CI), against analytic expectations. A large
//! emitter (radiance 1) fills the left half of the view, its edge on the plane x = 0, which the
//! camera (eye at the origin, looking along -z, right = +x) sees at the image's middle column
//! boundary: each column's value is then the probability that a sample of it lands on the
//! emitter, and every row of a column is an independent estimate of it (its own sampler
//! scramble), so the spread over rows gives its standard error.
//!
//! - filters: with the pinhole that probability is the filter's CDF across the edge;
//! - thin lens: with the edge on the focus plane the image stays sharp; in front of it, blurred
//!   by the circle of confusion (below);
//! - orthographic: quads at two depths cover exactly the pixels their world size says.

mod common;

use common::render::{image, render};
use common::root;
use passgraph::render::image::RgbImage;
use passgraph::render::session::RenderSettings;
use passgraph::scene::PixelFilter;
use std::path::Path;

const MTL: &str = "newmtl light\nKd 0 0 0\nKe 1 1 1\n";

/// An emitter over x in [x0, x1], y in [y0, y1] at depth z (facing +z, toward the camera).
fn quad(obj: &mut String, first: usize, [x0, x1, y0, y1]: [f32; 4], z: f32) {
    use std::fmt::Write;
    for (x, y) in [(x0, y0), (x1, y0), (x1, y1), (x0, y1)] {
        let _ = writeln!(obj, "v {x} {y} {z}");
    }
    let _ = writeln!(obj, "f {} {} {} {}", first, first + 1, first + 2, first + 3);
}

/// A scene directory with `quads` and the scene file's `camera` and `extra` fields.
fn scene(quads: &[([f32; 4], f32)], camera: &str, extra: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let mut obj = String::from("mtllib scene.mtl\nusemtl light\n");
    for (i, &(rect, z)) in quads.iter().enumerate() {
        quad(&mut obj, 4 * i + 1, rect, z);
    }
    std::fs::write(dir.path().join("scene.obj"), obj).unwrap();
    std::fs::write(dir.path().join("scene.mtl"), MTL).unwrap();
    std::fs::write(
        dir.path().join("scene.ron"),
        format!(
            "Scene(\n    mesh: \"scene.obj\",\n    camera: {camera},\n    max_depth: 1,\n{extra})\n"
        ),
    )
    .unwrap();
    dir
}

/// The left-half emitter at depth `z`, wide enough that no blur here reaches its other edges.
fn half_plane(z: f32) -> Vec<([f32; 4], f32)> {
    vec![([-1000.0, 0.0, -1000.0, 1000.0], z)]
}

fn render_l0(graph: &str, scene: &Path, size: [u32; 2], frames: u32) -> RgbImage {
    render_l0_set(graph, scene, size, frames, &[])
}

/// As [`render_l0`], with graph params set (`INSTANCE.PARAM=VALUE`).
fn render_l0_set(graph: &str, scene: &Path, size: [u32; 2], frames: u32, set: &[&str]) -> RgbImage {
    let s = RenderSettings {
        size,
        seed: 7,
        set: set.iter().map(|s| s.to_string()).collect(),
        ..RenderSettings::new(root().join(graph), scene)
    };
    image(&render(&s, frames), "l0")
}

/// Each column's mean over rows (red) and the standard error of that mean.
fn column_means(img: &RgbImage) -> Vec<(f64, f64)> {
    (0..img.width as usize)
        .map(|x| {
            let v: Vec<f64> = (0..img.height as usize)
                .map(|y| f64::from(img.pixels[y * img.width as usize + x][0]))
                .collect();
            let n = v.len() as f64;
            let mean = v.iter().sum::<f64>() / n;
            let var = v.iter().map(|a| (a - mean).powi(2)).sum::<f64>() / (n - 1.0);
            (mean, (var / n).sqrt())
        })
        .collect()
}

/// Asserts each column's mean is its expectation within five standard errors (and a rounding
/// floor, for columns every sample agrees on).
fn assert_columns(what: &str, img: &RgbImage, expected: impl Fn(usize) -> f64) {
    for (x, (mean, se)) in column_means(img).into_iter().enumerate() {
        let e = expected(x);
        let tolerance = (5.0 * se).max(1e-4);
        assert!(
            (mean - e).abs() <= tolerance,
            "{what}: column {x}: mean {mean:.5} vs expected {e:.5} (5 SE {:.5})",
            5.0 * se
        );
    }
}

const RASTER: &str = "graphs/pathtracer-raster.ron";
const W: u32 = 16;
const H: u32 = 64;
const FRAMES: u32 = 64;
/// fov 90 along x: the edge plane at depth 10 is 20 units wide, 0.8 pixels per unit at W = 16.
const CAMERA: &str =
    "Camera(eye: (0, 0, 0), target: (0, 0, -1), up: (0, 1, 0), fov: 90, fov_axis: X";

/// The filter's CDF across the edge: column x's centre lies x + 0.5 - W/2 pixels right of it.
fn filter_edge(filter: PixelFilter, extra: &str, graph: &str) {
    let dir = scene(&half_plane(-10.0), &format!("{CAMERA})"), extra);
    let img = render_l0(graph, &dir.path().join("scene.ron"), [W, H], FRAMES);
    assert_columns(&format!("{filter:?} with {graph}"), &img, |x| {
        let offset = x as f64 + 0.5 - f64::from(W / 2);
        filter.cdf(-offset)
    });
}

#[test]
fn gaussian_filter_blurs_an_edge_by_its_cdf() {
    let filter = PixelFilter::Gaussian { stddev: 0.5 };
    for graph in ["graphs/pathtracer.ron", "graphs/pathtracer-fast.ron"] {
        filter_edge(filter, "    filter: Gaussian(stddev: 0.5),\n", graph);
    }
    let wide = PixelFilter::Gaussian { stddev: 1.2 };
    filter_edge(
        wide,
        "    filter: Gaussian(stddev: 1.2),\n",
        "graphs/pathtracer.ron",
    );
}

#[test]
fn tent_filter_blurs_an_edge_by_its_cdf() {
    let filter = PixelFilter::Tent { radius: 1.5 };
    for graph in ["graphs/pathtracer.ron", "graphs/pathtracer-fast.ron"] {
        filter_edge(filter, "    filter: Tent(radius: 1.5),\n", graph);
    }
}

#[test]
fn box_filter_keeps_the_edge_in_its_pixel() {
    filter_edge(PixelFilter::Box, "", "graphs/pathtracer.ron");
}

/// The x-marginal CDF of the uniform unit disk: the fraction of the disk left of x = t.
fn disk_cdf(t: f64) -> f64 {
    let t = t.clamp(-1.0, 1.0);
    0.5 + (t * (1.0 - t * t).sqrt() + t.asin()) / std::f64::consts::PI
}

#[test]
fn thin_lens_keeps_the_focus_plane_sharp_and_blurs_by_the_circle_of_confusion() {
    // Focused on the edge's plane: every ray of a film point meets it where the pinhole ray
    // does, so the columns are 1 or 0 as the pinhole's are, however large the aperture.
    let sharp = scene(
        &half_plane(-10.0),
        &format!("{CAMERA}, aperture_radius: 3, focus_distance: 10)"),
        "",
    );
    // The raster graph traces a lens camera's rays instead of rasterising them.
    for graph in [
        "graphs/pathtracer.ron",
        "graphs/pathtracer-fast.ron",
        RASTER,
    ] {
        let img = render_l0(graph, &sharp.path().join("scene.ron"), [W, H], 16);
        assert_columns(&format!("focused, {graph}"), &img, |x| {
            if x < (W / 2) as usize { 1.0 } else { 0.0 }
        });
    }
    // Focused at D = 5, the edge at depth z = 10: the ray from lens point a through the focus
    // point D d of film direction d (d . forward = 1) meets depth z at z d + a (1 - z / D), so a
    // film point sees a disk of radius R |1 - z / D| = R on the edge plane: R * 0.8 pixels.
    // Column x then sees the emitter with probability ∫_0^1 F((W/2 - x - u) / b) du, F the
    // disk's x-marginal CDF, b = 0.8 R, u the box filter's uniform offset.
    let radius = 5.0;
    let b = 0.8 * radius;
    let blurred = scene(
        &half_plane(-10.0),
        &format!("{CAMERA}, aperture_radius: {radius}, focus_distance: 5)"),
        "",
    );
    for graph in ["graphs/pathtracer.ron", "graphs/pathtracer-fast.ron"] {
        let img = render_l0(graph, &blurred.path().join("scene.ron"), [W, H], FRAMES);
        assert_columns(&format!("defocused, {graph}"), &img, |x| {
            let n = 4000;
            (0..n)
                .map(|i| {
                    let u = (i as f64 + 0.5) / n as f64;
                    disk_cdf((f64::from(W / 2) - x as f64 - u) / b)
                })
                .sum::<f64>()
                / n as f64
        });
    }
    // The raster graph shares one film offset per frame across the image, so its rows are
    // independent only at the pixel centre (jitter off): there column x sees the emitter with
    // probability F((W/2 - x - 1/2) / b), drawn from each pixel's own lens samples.
    let jitter_off = [
        "visibility.pixel_jitter=false",
        "primary.pixel_jitter=false",
    ];
    let img = render_l0_set(
        RASTER,
        &blurred.path().join("scene.ron"),
        [W, H],
        FRAMES,
        &jitter_off,
    );
    assert_columns("defocused, raster", &img, |x| {
        disk_cdf((f64::from(W / 2) - x as f64 - 0.5) / b)
    });
}

#[test]
fn orthographic_quads_cover_their_world_size_at_any_depth() {
    // Width 4 over 32 pixels: 8 pixels per unit. A quad x in [-1, 1], y in [0.5, 1.5] at depth
    // 100 and one x in [0, 1.5], y in [-1.5, -0.5] at depth 1000 (a perspective camera would
    // shrink the far one tenfold): columns 8..24 by rows 4..12, and columns 16..28 by rows
    // 20..28.
    let dir = scene(
        &[
            ([-1.0, 1.0, 0.5, 1.5], -100.0),
            ([0.0, 1.5, -1.5, -0.5], -1000.0),
        ],
        "Orthographic(eye: (0, 0, 0), target: (0, 0, -1), up: (0, 1, 0), width: 4)",
        "",
    );
    for graph in [
        "graphs/pathtracer.ron",
        "graphs/pathtracer-fast.ron",
        RASTER,
    ] {
        let img = render_l0(graph, &dir.path().join("scene.ron"), [32, 32], 16);
        for y in 0..32 {
            for x in 0..32 {
                let inside = ((8..24).contains(&x) && (4..12).contains(&y))
                    || ((16..28).contains(&x) && (20..28).contains(&y));
                let v = img.pixels[y * 32 + x][0];
                let expected = if inside { 1.0 } else { 0.0 };
                assert!(
                    (v - expected).abs() < 1e-3,
                    "{graph}: pixel ({x}, {y}) is {v}, expected {expected}"
                );
            }
        }
    }
}

#[test]
fn raster_graph_jitters_the_frame_by_the_filter() {
    // One film offset per frame for the whole image (lib/frame_jitter.wgsl): every pixel of a
    // column sees the emitter in the same frames, so a column's mean is the fraction of F
    // frames whose offset lands on it, a Bernoulli mean with standard error sqrt(p (1 - p) / F)
    // (an upper bound: the frames' offsets are stratified).
    let filter = PixelFilter::Gaussian { stddev: 0.5 };
    let dir = scene(
        &half_plane(-10.0),
        &format!("{CAMERA})"),
        "    filter: Gaussian(stddev: 0.5),\n",
    );
    let frames = 512;
    let img = render_l0(RASTER, &dir.path().join("scene.ron"), [W, 8], frames);
    for (x, (mean, _)) in column_means(&img).into_iter().enumerate() {
        let p = filter.cdf(-(x as f64 + 0.5 - f64::from(W / 2)));
        let se = (p * (1.0 - p) / f64::from(frames)).sqrt();
        assert!(
            (mean - p).abs() <= (5.0 * se).max(1e-4),
            "raster, column {x}: mean {mean:.5} vs expected {p:.5} (5 SE {:.5})",
            5.0 * se
        );
    }
}

#[test]
fn the_reprojection_graph_refuses_a_lens_or_orthographic_camera() {
    for camera in [
        format!("{CAMERA}, aperture_radius: 1, focus_distance: 10)"),
        "Orthographic(eye: (0, 0, 0), target: (0, 0, -1), up: (0, 1, 0), width: 4)".to_string(),
    ] {
        let dir = scene(&half_plane(-10.0), &camera, "");
        let s = RenderSettings {
            size: [16, 16],
            ..RenderSettings::new(
                root().join("graphs/pathtracer-reproject.ron"),
                dir.path().join("scene.ron"),
            )
        };
        let message = match passgraph::render::session::Session::new(&s) {
            Ok(_) => panic!("{camera}: the reprojection graph should refuse it"),
            Err(e) => e.to_string(),
        };
        assert!(
            message.contains("scene.ron") && message.contains("camera_previous"),
            "{message}"
        );
    }
}
