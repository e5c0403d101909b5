//! Normal and bump maps in whole renders (the default graph on lavapipe in CI):
//! - against Mitsuba 3 (`normalmap`, `bumpmap`): the planes `scripts/make-surface-maps` writes
//!   (tests/data/surface_maps), lit at a grazing angle by a small emitter, 96x96 at max_depth
//!   3; over each quarter of the plane's pixels, the mean within 1 % per component and the RMSE
//!   at the noise floor (tests/common/reference.rs), the references two independent halves;
//! - analytic: a normal map of one constant tilt n' renders as the same plane with vertex
//!   normals n' (a plane whose shading normal is n').

mod common;

use common::reference::check_region;
use common::render::{image, render, settings};
use common::root;
use glam::Vec3;
use passgraph::render::image::RgbImage;
use passgraph::scene::load_scene;
use passgraph::scene::regions::material_regions;
use std::path::Path;

const SIZE: u32 = 96;
const FRAMES: u32 = 256;
const CHANNELS: &str = "l0+direct+indirect";
const GRAPH: &str = "graphs/pathtracer.ron";

fn reference(name: &str) -> RgbImage {
    RgbImage::read_exr(&root().join("tests/data/references").join(name)).unwrap()
}

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
    // Two independent halves of the reference (different seeds): their mean is the reference,
    // and a quarter of their mean squared difference its own noise.
    let half_a = reference(&format!("surface-{name}-96-depth3-a.exr"));
    let half_b = reference(&format!("surface-{name}-96-depth3-b.exr"));
    let mut mean = half_a.clone();
    for (p, q) in mean.pixels.iter_mut().zip(&half_b.pixels) {
        for k in 0..3 {
            p[k] = 0.5 * (p[k] + q[k]);
        }
    }
    for (region, pixels) in quarters(&scene) {
        let noise: f64 = pixels
            .iter()
            .flat_map(|&i| (0..3).map(move |k| (i, k)))
            .map(|(i, k)| (f64::from(half_a.pixels[i][k]) - f64::from(half_b.pixels[i][k])).powi(2))
            .sum::<f64>()
            / (3 * pixels.len()) as f64
            / 4.0;
        check_region(
            &format!("{name} map, {region}"),
            &a,
            &b,
            &mean,
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

/// A 2 x 2 8-bit RGB PNG of one colour.
fn constant_png(rgb: [u8; 3]) -> Vec<u8> {
    let image = image::RgbImage::from_pixel(2, 2, image::Rgb(rgb));
    let mut bytes = Vec::new();
    image
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .unwrap();
    bytes
}

#[test]
fn a_constant_normal_map_is_a_plane_with_that_shading_normal() {
    let dir = tempfile::tempdir().unwrap();
    common::copy_dir(&root().join("tests/data/surface_maps"), dir.path());
    // Tilted toward -s and +t (s along +u = +x, t = n x s along +v = -z on this plane): toward
    // the light's side, so the tilt brightens the plane.
    let rgb = [70u8, 190, 220];
    std::fs::write(dir.path().join("tilt.png"), constant_png(rgb)).unwrap();
    let mapped = dir.path().join("normal.mtl");
    let text = std::fs::read_to_string(&mapped).unwrap();
    std::fs::write(&mapped, text.replace("norm stripes.png", "norm tilt.png")).unwrap();
    // n' in world space: 2 rgb - 1 in (s, t, n) = (+x, -z, +y), normalised.
    let local = Vec3::from(rgb.map(|c| 2.0 * f32::from(c) / 255.0 - 1.0)).normalize();
    let n = Vec3::X * local.x - Vec3::Z * local.y + Vec3::Y * local.z;
    // The same plane without the map, every corner's vertex normal n'.
    let obj = dir.path().join("normal.obj");
    let text = std::fs::read_to_string(&obj).unwrap();
    let text = text
        .replace(
            "mtllib normal.mtl",
            &format!("mtllib flat.mtl\nvn {} {} {}", n.x, n.y, n.z),
        )
        .replace("f 1/1 2/2 3/3 4/4", "f 1/1/1 2/2/1 3/3/1 4/4/1");
    std::fs::write(dir.path().join("flat.obj"), text).unwrap();
    std::fs::write(
        dir.path().join("flat.mtl"),
        std::fs::read_to_string(&mapped)
            .unwrap()
            .replace("norm tilt.png\n", ""),
    )
    .unwrap();
    let scene = dir.path().join("normal.ron");
    let flat = dir.path().join("flat.ron");
    std::fs::write(
        &flat,
        std::fs::read_to_string(&scene)
            .unwrap()
            .replace("normal.obj", "flat.obj"),
    )
    .unwrap();

    // Same seed, same samples: the two differ only by the roundings of two ways to n'.
    let frames = 16;
    let a = image(
        &render(&settings(GRAPH, &scene, 64, 7, &[]), frames),
        CHANNELS,
    );
    let b = image(
        &render(&settings(GRAPH, &flat, 64, 7, &[]), frames),
        CHANNELS,
    );
    let untilted = {
        let plain = dir.path().join("plain.ron");
        let mtl = dir.path().join("normal.mtl");
        let text = std::fs::read_to_string(&mtl).unwrap();
        std::fs::write(&mtl, text.replace("norm tilt.png\n", "")).unwrap();
        std::fs::write(&plain, std::fs::read_to_string(&scene).unwrap()).unwrap();
        image(
            &render(&settings(GRAPH, &plain, 64, 7, &[]), frames),
            CHANNELS,
        )
    };
    let (mut largest, mut total, mut changed) = (0.0f64, 0.0f64, 0.0f64);
    for ((p, q), r) in a.pixels.iter().zip(&b.pixels).zip(&untilted.pixels) {
        for k in 0..3 {
            let d = f64::from((p[k] - q[k]).abs());
            largest = largest.max(d / f64::from(q[k]).max(1e-3));
            total += f64::from(q[k]);
            changed += f64::from((q[k] - r[k]).abs());
        }
    }
    eprintln!(
        "largest relative difference {largest:.2e}; the tilt changes the image by {:.1} % (mean absolute)",
        100.0 * changed / total
    );
    // The tilt matters (so the comparison tests something) ...
    assert!(
        changed / total > 0.2,
        "the tilt changed the image by {changed} of {total}"
    );
    // ... and the map reproduces it to the roundings of n' (a few ulps in a cosine).
    assert!(largest < 1e-4, "largest relative difference {largest}");
}
