//! The materials showcase (scenes/materials: a rough gold conductor, a rough blue plastic, a
//! smooth glass sphere, a checker-textured floor and the Cornell box's Lambertian walls)
//! against Mitsuba 3 at 128x128, at max_depth 3 and 8, material by material: over the pixels
//! whose whole footprint sees one material, the mean within 1 % per component and the RMSE at
//! the noise floor (tests/common/reference.rs: the render's own noise from a second seed plus
//! the reference's, from its two independent halves, plus five standard errors). Rendered with
//! the default graph (graphs/pathtracer.ron, the seed's separate passes) on the GPU (lavapipe
//! in CI).

mod common;

use common::reference::{Halves, check_region};
use common::render::{image, render, settings};
use common::root;
use passgraph::scene::load_scene;
use passgraph::scene::regions::material_regions;

const SIZE: u32 = 128;

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
    let halves = Halves::read(&format!("materials-128-depth{depth}"));
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
        let noise = halves.noise(pixels);
        check_region(
            &format!("{name}, max_depth {depth}"),
            &a,
            &b,
            &halves.mean,
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
