//! The materials showcase (scenes/materials: a rough gold conductor, a rough blue plastic, a
//! smooth glass sphere, a checker-textured floor and the Cornell box's Lambertian walls)
//! against Mitsuba 3 at 128x128, at max_depth 3 and 8, material by material: over the pixels
//! whose whole footprint sees one material, the mean within 1 % per component and the RMSE at
//! the noise floor (tests/common/reference.rs: the render's own noise from a second seed plus
//! the reference's, from its two independent halves, plus five standard errors). Rendered with
//! the default graph (graphs/pathtracer.ron, the seed's separate passes) on the GPU (lavapipe
//! in CI).

mod common;

use common::reference::check_region;
use common::render::{image, render, settings};
use common::root;
use passgraph::render::image::RgbImage;
use passgraph::scene::load_scene;
use passgraph::scene::regions::material_regions;

const SIZE: u32 = 128;

fn reference(name: &str) -> RgbImage {
    RgbImage::read_exr(&root().join("tests/data/references").join(name)).unwrap()
}

/// The scene at `max_depth`, in a temporary directory beside copies of its files.
fn scene_at_depth(depth: u32) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    common::copy_dir(&root().join("scenes/materials"), dir.path());
    let path = dir.path().join("scene.ron");
    let text = std::fs::read_to_string(&path).unwrap();
    let edited = text.replace(
        "mesh: \"materials.obj\",",
        &format!("mesh: \"materials.obj\",\n    max_depth: {depth},"),
    );
    assert_ne!(text, edited, "the scene names its mesh");
    std::fs::write(&path, edited).unwrap();
    dir
}

fn check_depth(depth: u32, frames: u32) {
    let dir = scene_at_depth(depth);
    let scene = dir.path().join("scene.ron");
    let channels = "l0+direct+indirect";
    let graph = "graphs/pathtracer.ron";
    let a = image(
        &render(&settings(graph, &scene, SIZE, 1, &[]), frames),
        channels,
    );
    let b = image(
        &render(&settings(graph, &scene, SIZE, 2, &[]), frames),
        channels,
    );
    // Two independent halves of the reference (different seeds): their mean is the reference,
    // and a quarter of their mean squared difference its own noise.
    let half_a = reference(&format!("materials-128-depth{depth}-a.exr"));
    let half_b = reference(&format!("materials-128-depth{depth}-b.exr"));
    let mut mean = half_a.clone();
    for (p, q) in mean.pixels.iter_mut().zip(&half_b.pixels) {
        for k in 0..3 {
            p[k] = 0.5 * (p[k] + q[k]);
        }
    }
    let regions = material_regions(
        &load_scene(&scene).unwrap_or_else(|e| panic!("{e}")),
        SIZE,
        SIZE,
    );
    for name in [
        "gold",
        "blue_plastic",
        "glass",
        "checker_floor",
        "white",
        "red",
        "green",
    ] {
        let pixels = &regions[name];
        let noise: f64 = pixels
            .iter()
            .flat_map(|&i| (0..3).map(move |k| (i, k)))
            .map(|(i, k)| (f64::from(half_a.pixels[i][k]) - f64::from(half_b.pixels[i][k])).powi(2))
            .sum::<f64>()
            / (3 * pixels.len()) as f64
            / 4.0;
        check_region(
            &format!("{name}, max_depth {depth}"),
            &a,
            &b,
            &mean,
            pixels,
            noise,
            0.01,
        );
    }
}

#[test]
fn every_material_matches_mitsuba_at_max_depth_3() {
    check_depth(3, 256);
}

#[test]
fn every_material_matches_mitsuba_at_max_depth_8() {
    check_depth(8, 256);
}
