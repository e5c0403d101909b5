//! Normal and bump maps in whole renders (the default graph on lavapipe in CI):
//! - against Mitsuba 3 (`normalmap`, `bumpmap`): the planes `scripts/make-surface-maps` writes
//!   (tests/data/surface_maps), lit at a grazing angle by a small emitter, 96x96 at max_depth
//!   3; over each quarter of the plane's pixels, the mean within 1 % per component and the RMSE
//!   at the noise floor (tests/common/reference.rs), the references two independent halves.
//!
//! No render-level analytic test: a constant normal map n' is not the plane with vertex normals
//! n', because the model (Mitsuba's) also multiplies by the terminator shadowing;
//! tests/surface_map_gpu.rs checks the perturbed normal and the shadowing themselves.

mod common;

use common::reference::{Halves, check_region};
use common::render::{image, render, settings};
use common::root;
use passgraph::scene::load_scene;
use passgraph::scene::regions::material_regions;
use std::path::Path;

const SIZE: u32 = 96;
const FRAMES: u32 = 256;
const CHANNELS: &str = "l0+direct+indirect";
const GRAPH: &str = "graphs/pathtracer.ron";

/// The plane's pixels in four regions: the quarters of the image it covers.
fn quarters(scene: &Path) -> Vec<(String, Vec<usize>)> {
    let regions = material_regions(
        &load_scene(scene).unwrap_or_else(|e| panic!("{e}")),
        SIZE,
        SIZE,
    );
    let plane = &regions["plane"];
    let half = SIZE as usize / 2;
    let mut out = Vec::new();
    for (name, top, left) in [
        ("top left", true, true),
        ("top right", true, false),
        ("bottom left", false, true),
        ("bottom right", false, false),
    ] {
        let pixels: Vec<usize> = plane
            .iter()
            .copied()
            .filter(|&i| {
                let (x, y) = (i % SIZE as usize, i / SIZE as usize);
                (y < half) == top && (x < half) == left
            })
            .collect();
        out.push((name.to_string(), pixels));
    }
    out
}

fn check_against_mitsuba(name: &str) {
    let scene = root().join(format!("tests/data/surface_maps/{name}.ron"));
    let a = image(
        &render(&settings(GRAPH, &scene, SIZE, 1, &[]), FRAMES),
        CHANNELS,
    );
    let b = image(
        &render(&settings(GRAPH, &scene, SIZE, 2, &[]), FRAMES),
        CHANNELS,
    );
    let halves = Halves::read(&format!("surface-{name}-96-depth3"));
    for (region, pixels) in quarters(&scene) {
        let noise = halves.noise(&pixels);
        check_region(
            &format!("{name} map, {region}"),
            &a,
            &b,
            &halves.mean,
            &pixels,
            noise,
            0.01,
        );
    }
}

#[test]
fn a_normal_mapped_plane_matches_mitsuba() {
    check_against_mitsuba("normal");
}

#[test]
fn a_bump_mapped_plane_matches_mitsuba() {
    check_against_mitsuba("bump");
}
