//! The thin lens and the Gaussian pixel filter against Mitsuba 3 (`thinlens`, `gaussian` with
//! `sample_border`), on the Cornell box at 64x64, max_depth 3: the lens focused on the short
//! block (focus_distance 900, aperture_radius 80: the back wall blurs by about 2.7 pixels), and
//! the box's pinhole with Mitsuba's default Gaussian (stddev 0.5). Over the whole image (the lens
//! and the filter change every edge, which regions by material would leave out): the mean within
//! 1 % per component and the RMSE at the noise floor (tests/common/reference.rs: the render's own
//! noise from a second seed plus the reference's, from its two independent halves, plus five
//! standard errors). References: tests/data/references/README.md.

mod common;

use common::reference::check_region;
use common::render::{image, render, settings};
use common::root;
use passgraph::render::image::RgbImage;

const SIZE: u32 = 64;
const CAMERA: &str =
    "camera: Camera(eye: (278, 273, -800), target: (278, 273, 0), up: (0, 1, 0), fov_y: 39.3077),";

fn reference(name: &str) -> RgbImage {
    RgbImage::read_exr(&root().join("tests/data/references").join(name)).unwrap()
}

/// The Cornell box with its camera line replaced by `camera`, in a temporary directory.
fn cornell_with(camera: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    common::copy_dir(&root().join("scenes/cornell"), dir.path());
    let path = dir.path().join("scene.ron");
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains(CAMERA), "the Cornell scene's camera line");
    std::fs::write(&path, text.replace(CAMERA, camera)).unwrap();
    dir
}

fn check(what: &str, camera: &str, references: [&str; 2]) {
    let dir = cornell_with(camera);
    let scene = dir.path().join("scene.ron");
    let channels = "l0+direct+indirect";
    let graph = "graphs/pathtracer.ron";
    let frames = 256;
    let a = image(
        &render(&settings(graph, &scene, SIZE, 1, &[]), frames),
        channels,
    );
    let b = image(
        &render(&settings(graph, &scene, SIZE, 2, &[]), frames),
        channels,
    );
    let half_a = reference(references[0]);
    let half_b = reference(references[1]);
    let mut mean = half_a.clone();
    for (p, q) in mean.pixels.iter_mut().zip(&half_b.pixels) {
        for k in 0..3 {
            p[k] = 0.5 * (p[k] + q[k]);
        }
    }
    let pixels: Vec<usize> = (0..(SIZE * SIZE) as usize).collect();
    // A quarter of the halves' mean squared difference: the noise of their mean.
    let noise: f64 = pixels
        .iter()
        .flat_map(|&i| (0..3).map(move |k| (i, k)))
        .map(|(i, k)| (f64::from(half_a.pixels[i][k]) - f64::from(half_b.pixels[i][k])).powi(2))
        .sum::<f64>()
        / (3 * pixels.len()) as f64
        / 4.0;
    check_region(what, &a, &b, &mean, &pixels, noise, 0.01);
}

#[test]
fn thin_lens_defocus_matches_mitsuba() {
    check(
        "thin lens",
        "camera: Camera(eye: (278, 273, -800), target: (278, 273, 0), up: (0, 1, 0), fov_y: 39.3077, aperture_radius: 80, focus_distance: 900),",
        [
            "cornell-lens-64-depth3-a.exr",
            "cornell-lens-64-depth3-b.exr",
        ],
    );
}

#[test]
fn gaussian_filter_matches_mitsuba() {
    check(
        "Gaussian filter",
        &format!("{CAMERA}\n    filter: Gaussian(stddev: 0.5),"),
        [
            "cornell-gaussian-64-depth3-a.exr",
            "cornell-gaussian-64-depth3-b.exr",
        ],
    );
}
