//! Alpha cut-outs (MTL `d` < 1), analytically: a black sheet of opacity 0.5 stops half the rays
//! that reach it, primary rays and shadow rays alike (shaders/lib/bvh.wgsl's stochastic
//! pass-through). Run on the GPU (lavapipe in CI).

mod common;

use common::render::{image, render, settings};
use passgraph::render::image::RgbImage;

/// Writes `scene.ron`, `cutout.obj` and `cutout.mtl` into a temporary directory.
fn scene(obj: &str, mtl: &str, camera: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("cutout.obj"), obj).unwrap();
    std::fs::write(dir.path().join("cutout.mtl"), mtl).unwrap();
    std::fs::write(
        dir.path().join("scene.ron"),
        format!("Scene(mesh: \"cutout.obj\", camera: {camera})"),
    )
    .unwrap();
    dir
}

/// Mean over pixels and components of `values`, and its standard error from their spread.
fn mean_and_se(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

fn values(img: &RgbImage) -> Vec<f64> {
    img.pixels.iter().map(|p| f64::from(p[0])).collect()
}

const SHEET: &str = "newmtl sheet\nKd 0 0 0\nd D\n";

#[test]
fn an_emitter_behind_a_half_opaque_sheet_is_seen_half_the_time() {
    // The camera at z = -1 looks at a black sheet (z = 0, d 0.5) in front of an emitter
    // (z = 1, Ke 1, facing the camera) that fills the view: L0 = 0.5 in every pixel.
    let obj = "mtllib cutout.mtl\n\
        usemtl sheet\nv -4 -4 0\nv 4 -4 0\nv 4 4 0\nv -4 4 0\nf 1 2 3 4\n\
        usemtl glow\nv -8 -8 1\nv -8 8 1\nv 8 8 1\nv 8 -8 1\nf 5 6 7 8\n";
    let mtl = format!(
        "{}newmtl glow\nKd 0 0 0\nKe 1 1 1\n",
        SHEET.replace('D', "0.5")
    );
    let dir = scene(
        obj,
        &mtl,
        "Camera(eye: (0, 0, -1), target: (0, 0, 1), up: (0, 1, 0), fov_y: 60)",
    );
    let session = render(
        &settings(
            "graphs/pathtracer.ron",
            dir.path().join("scene.ron"),
            32,
            1,
            &[],
        ),
        16,
    );
    let (mean, se) = mean_and_se(&values(&image(&session, "l0")));
    // Five standard errors: a false failure once in ~1.7 million runs.
    assert!(
        (mean - 0.5).abs() < 5.0 * se,
        "L0 {mean} (se {se}), expected 0.5"
    );
    assert!(
        se > 0.0 && se < 0.02,
        "se {se}: the sheet should pass and stop rays"
    );
}

#[test]
fn a_half_opaque_sheet_halves_the_direct_light_under_it() {
    // A floor (y = 0) lit by a light (y = 2, facing down) through a black sheet (y = 1) that
    // covers the whole light as seen from the floor; the camera between floor and sheet. With
    // d 0.5 the direct light is half what it is with d 0 (the sheet passes every ray).
    let obj = "mtllib cutout.mtl\n\
        usemtl floor\nv -10 0 -10\nv -10 0 10\nv 10 0 10\nv 10 0 -10\nf 1 2 3 4\n\
        usemtl sheet\nv -20 1 -20\nv -20 1 20\nv 20 1 20\nv 20 1 -20\nf 5 6 7 8\n\
        usemtl glow\nv -1 2 -1\nv 1 2 -1\nv 1 2 1\nv -1 2 1\nf 9 10 11 12\n";
    let camera = "Camera(eye: (0, 0.5, -1), target: (0, 0, 0.5), up: (0, 1, 0), fov_y: 60)";
    let direct = |d: &str| {
        let mtl = format!(
            "newmtl floor\nKd 0.5 0.5 0.5\n{}newmtl glow\nKd 0 0 0\nKe 1 1 1\n",
            SHEET.replace('D', d)
        );
        let dir = scene(obj, &mtl, camera);
        let session = render(
            &settings(
                "graphs/pathtracer.ron",
                dir.path().join("scene.ron"),
                32,
                1,
                &[],
            ),
            32,
        );
        values(&image(&session, "direct"))
    };
    let half = direct("0.5");
    let open = direct("0");
    let difference: Vec<f64> = half.iter().zip(&open).map(|(h, o)| h - 0.5 * o).collect();
    let (mean, se) = mean_and_se(&difference);
    let (open_mean, _) = mean_and_se(&open);
    assert!(
        open_mean > 0.01,
        "the open sheet should let light through: {open_mean}"
    );
    assert!(
        mean.abs() < 5.0 * se,
        "direct with d 0.5 minus half of direct with d 0: {mean} (se {se}); open {open_mean}"
    );
}
