//! Point, spot (plain and projecting an image) and directional lights and an HDR environment
//! against Mitsuba 3, at 64x64, region by region (the pixels whose footprint sees one material,
//! and those that see only the environment): the mean within 1 % per component and the RMSE at
//! the noise floor (tests/common/reference.rs: this render's noise from a second seed, the
//! reference's from its two independent halves, plus five standard errors). The scenes come from
//! scripts/make-lights-scenes; the references from scripts/mitsuba-reference
//! (tests/data/references/README.md). Rendered with the default graph (graphs/pathtracer.ron)
//! on the GPU (lavapipe in CI).

mod common;

use common::reference::{Halves, check_region};
use common::render::{image, render, settings};
use common::root;
use passgraph::scene::load_scene;
use passgraph::scene::regions::{ENVIRONMENT_REGION, material_regions};

const SIZE: u32 = 64;

/// `scene` at `max_depth` (in a copy of its directory when the depth is not the file's).
fn check(scene: &str, reference_name: &str, depth: u32, frames: u32, regions: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let source = root().join(scene);
    common::copy_dir(source.parent().unwrap(), dir.path());
    let path = dir.path().join(source.file_name().unwrap());
    let text = std::fs::read_to_string(&path).unwrap();
    // Images are found relative to the scene file: keep them reachable.
    let text = text
        .replace(
            "file: \"../../environment/",
            &format!(
                "file: \"{}/",
                root().join("tests/data/environment").display()
            ),
        )
        .replace(
            "texture: \"../../textures/",
            &format!(
                "texture: \"{}/",
                root().join("tests/data/textures").display()
            ),
        );
    let end = text.rfind(')').unwrap();
    std::fs::write(
        &path,
        format!("{}    max_depth: {depth},\n)\n", &text[..end]),
    )
    .unwrap();
    let channels = "l0+direct+indirect";
    let graph = "graphs/pathtracer.ron";
    let a = image(
        &render(&settings(graph, &path, SIZE, 1, &[]), frames),
        channels,
    );
    let b = image(
        &render(&settings(graph, &path, SIZE, 2, &[]), frames),
        channels,
    );
    let halves = Halves::read(&format!("{reference_name}-64-depth{depth}"));
    let mean = &halves.mean;
    let all = material_regions(
        &load_scene(&path).unwrap_or_else(|e| panic!("{e}")),
        SIZE,
        SIZE,
    );
    for &name in regions {
        let pixels = all
            .get(name)
            .unwrap_or_else(|| panic!("{scene}: no region {name}"));
        let noise = halves.noise(pixels);
        // Pixels that see only the environment are one lookup per sample, nearly noiseless: what
        // is left is the f32 direction-to-texel arithmetic (atan2, acos), which on lavapipe
        // differs from Mitsuba's CPU by a few 1e-4 relative (measured: RMSE 2.3e-4 of the mean
        // at 64x64). Allow 5e-4 of the region's mean for it.
        let arithmetic = if name == ENVIRONMENT_REGION {
            let m = pixels
                .iter()
                .flat_map(|&i| mean.pixels[i])
                .map(f64::from)
                .sum::<f64>()
                / (3 * pixels.len()) as f64;
            (5e-4 * m).powi(2)
        } else {
            0.0
        };
        check_region(
            &format!("{reference_name} {name}, max_depth {depth}"),
            &a,
            &b,
            mean,
            pixels,
            noise + arithmetic,
            0.01,
        );
    }
}

const BLOCKS: &[&str] = &["floor", "wall", "red", "blue"];

#[test]
fn a_point_light_matches_mitsuba() {
    check(
        "tests/data/scenes/lights/point.ron",
        "lights-point",
        3,
        128,
        BLOCKS,
    );
}

#[test]
fn a_spot_light_matches_mitsuba() {
    check(
        "tests/data/scenes/lights/spot.ron",
        "lights-spot",
        3,
        128,
        BLOCKS,
    );
}

#[test]
fn a_spot_light_projecting_an_image_matches_mitsuba() {
    check(
        "tests/data/scenes/lights/spot-texture.ron",
        "lights-spot-texture",
        3,
        128,
        BLOCKS,
    );
}

#[test]
fn a_directional_light_matches_mitsuba() {
    check(
        "tests/data/scenes/lights/directional.ron",
        "lights-directional",
        3,
        128,
        BLOCKS,
    );
}

const SPHERES: &[&str] = &["ground", "white", "gold", "glass", ENVIRONMENT_REGION];

#[test]
fn an_hdri_lit_group_of_spheres_matches_mitsuba_at_max_depth_3() {
    check("tests/data/scenes/hdri/hdri.ron", "hdri", 3, 256, SPHERES);
}

#[test]
fn an_hdri_lit_group_of_spheres_matches_mitsuba_at_max_depth_8() {
    check("tests/data/scenes/hdri/hdri.ron", "hdri", 8, 256, SPHERES);
}
