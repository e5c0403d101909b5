//! Alpha cut-outs (MTL `d` < 1 and `map_d`), analytically: a black sheet of opacity 0.5 stops
//! half the rays that reach it, primary rays and shadow rays alike (shaders/lib/bvh.wgsl's
//! stochastic pass-through), and a checker-cut sheet (`map_d`) lets exactly its open cells
//! through. Run on the GPU (lavapipe in CI).

mod common;

use common::render::{image, render, settings};
use passgraph::render::image::RgbImage;

/// Writes `scene.ron`, `cutout.obj` and `cutout.mtl` into a temporary directory.
fn scene(obj: &str, mtl: &str, camera: &str) -> tempfile::TempDir {
    scene_with_map(obj, mtl, camera, None)
}

/// As [`scene`], with an 8-bit grey `alpha.png` for `map_d` (values raw, 0-255).
fn scene_with_map(
    obj: &str,
    mtl: &str,
    camera: &str,
    alpha: Option<image::GrayImage>,
) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    if let Some(alpha) = alpha {
        alpha.save(dir.path().join("alpha.png")).unwrap();
    }
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
const MAP_SHEET: &str = "newmtl sheet\nKd 0 0 0\nmap_d alpha.png\n";

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

/// The direct light on a floor (y = 0) lit by a light (y = 2, facing down) through a black
/// sheet (y = 1, material `sheet`, with texture coordinates) that covers the whole light as
/// seen from the floor; the camera between floor and sheet. `alpha.png` is a uniform grey of
/// 128/255, for a `map_d` sheet.
fn direct_under(sheet: &str) -> Vec<f64> {
    let obj = "mtllib cutout.mtl\n\
        vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
        usemtl floor\nv -10 0 -10\nv -10 0 10\nv 10 0 10\nv 10 0 -10\nf 1 2 3 4\n\
        usemtl sheet\nv -20 1 -20\nv -20 1 20\nv 20 1 20\nv 20 1 -20\nf 5/1 6/2 7/3 8/4\n\
        usemtl glow\nv -1 2 -1\nv 1 2 -1\nv 1 2 1\nv -1 2 1\nf 9 10 11 12\n";
    let camera = "Camera(eye: (0, 0.5, -1), target: (0, 0, 0.5), up: (0, 1, 0), fov_y: 60)";
    let mtl = format!("newmtl floor\nKd 0.5 0.5 0.5\n{sheet}newmtl glow\nKd 0 0 0\nKe 1 1 1\n");
    let grey = image::GrayImage::from_pixel(4, 4, image::Luma([128]));
    let dir = scene_with_map(obj, &mtl, camera, Some(grey));
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
}

/// Asserts that the direct light under a sheet is `fraction` of it under an open sheet (d 0),
/// pixel by pixel, within five standard errors of the differences' mean.
fn assert_transmits(under: &[f64], open: &[f64], fraction: f64, sheet: &str) {
    let difference: Vec<f64> = under
        .iter()
        .zip(open)
        .map(|(u, o)| u - fraction * o)
        .collect();
    let (mean, se) = mean_and_se(&difference);
    let (open_mean, _) = mean_and_se(open);
    assert!(
        open_mean > 0.01,
        "the open sheet should let light through: {open_mean}"
    );
    assert!(
        mean.abs() < 5.0 * se,
        "direct under {sheet} minus {fraction} of direct with d 0: {mean} (se {se}); open {open_mean}"
    );
}

#[test]
fn a_half_opaque_sheet_halves_the_direct_light_under_it() {
    // With d 0.5 the direct light is half what it is with d 0 (the sheet passes every ray).
    let half = direct_under(&SHEET.replace('D', "0.5"));
    let open = direct_under(&SHEET.replace('D', "0"));
    assert_transmits(&half, &open, 0.5, "d 0.5");
}

/// A 32x32 checker of four 16x16 cells: opaque (255) top left and bottom right, open (0) else.
fn checker() -> image::GrayImage {
    image::GrayImage::from_fn(32, 32, |x, y| {
        image::Luma([if (x < 16) == (y < 16) { 255 } else { 0 }])
    })
}

#[test]
fn a_checker_cut_sheet_transmits_half_and_exactly_its_open_cells() {
    // The camera at z = -1 looks at a black sheet (z = 0, half-size 0.6, a 2x2 checker map_d
    // over it) in front of an emitter (z = 1, Ke 1) that fills the view. The view (fov 60,
    // half-size tan 30 = 0.577 at the sheet) is centred on the checker's centre, so it sees
    // equal areas of opaque and open cells, and the bilinear blends at the cell borders are
    // symmetric: L0 = 0.5 on average. Away from the borders opacity is exactly 0 or 1, so
    // every sample there passes or stops: L0 is exactly 1 or 0. Both the ray-traced and the
    // rasterised primary visibility must see the same.
    let obj = "mtllib cutout.mtl\n\
        vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
        usemtl sheet\nv -0.6 -0.6 0\nv 0.6 -0.6 0\nv 0.6 0.6 0\nv -0.6 0.6 0\n\
        f 1/1 2/2 3/3 4/4\n\
        usemtl glow\nv -8 -8 1\nv -8 8 1\nv 8 8 1\nv 8 -8 1\nf 5 6 7 8\n";
    let mtl = format!("{MAP_SHEET}newmtl glow\nKd 0 0 0\nKe 1 1 1\n");
    let dir = scene_with_map(
        obj,
        &mtl,
        "Camera(eye: (0, 0, -1), target: (0, 0, 1), up: (0, 1, 0), fov_y: 60)",
        Some(checker()),
    );
    const SIZE: usize = 32;
    for graph in ["graphs/pathtracer.ron", "graphs/pathtracer-raster.ron"] {
        let session = render(
            &settings(graph, dir.path().join("scene.ron"), SIZE as u32, 1, &[]),
            16,
        );
        let l0 = image(&session, "l0");
        let (mean, se) = mean_and_se(&values(&l0));
        assert!(
            (mean - 0.5).abs() < 5.0 * se && se < 0.02,
            "{graph}: L0 {mean} (se {se}), expected 0.5"
        );
        // Pixel rows and columns more than 2 pixels (a pixel of jitter, the blend band of
        // 0.5 texel = 0.3 pixel) from the image's centre lines, which the cell borders
        // project to, see one cell only.
        let quadrant = |x: usize, y: usize| -> Option<(bool, bool)> {
            let away = |i: usize| (i as i64 * 2 + 1 - SIZE as i64).abs() > 4;
            (away(x) && away(y)).then_some((x < SIZE / 2, y < SIZE / 2))
        };
        let mut seen = std::collections::BTreeMap::new();
        for y in 0..SIZE {
            for x in 0..SIZE {
                let Some(q) = quadrant(x, y) else { continue };
                let v = l0.pixels[y * SIZE + x][0];
                assert!(
                    v == 0.0 || v == 1.0,
                    "{graph}: pixel ({x}, {y}) inside a cell has L0 {v}, not exactly 0 or 1"
                );
                let first = *seen.entry(q).or_insert(v);
                assert_eq!(
                    v, first,
                    "{graph}: pixel ({x}, {y}) differs from its quadrant"
                );
            }
        }
        // A checker: diagonal quadrants agree, neighbours differ.
        let at = |left: bool, top: bool| seen[&(left, top)];
        assert_eq!(at(true, true), at(false, false), "{graph}: {seen:?}");
        assert_eq!(at(false, true), at(true, false), "{graph}: {seen:?}");
        assert_ne!(at(true, true), at(false, true), "{graph}: {seen:?}");
    }
}

#[test]
fn a_grey_map_d_sheet_stops_its_raw_value_of_the_direct_light() {
    // As the constant-d test, with the sheet's opacity from a uniform grey map_d of 128/255,
    // read raw (not sRGB-decoded: that would be 0.216): the direct light under it is
    // 1 - 128/255 of the open sheet's.
    let grey = direct_under(MAP_SHEET);
    let open = direct_under(&SHEET.replace('D', "0"));
    let transmitted = 1.0 - 128.0 / 255.0;
    assert_transmits(&grey, &open, transmitted, "the grey map_d");
}
