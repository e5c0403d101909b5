//! Path depth with Mitsuba's meaning (`max_depth` in the scene file): in the furnace (a closed
//! box whose walls all emit Le = 0.5 and reflect rho = 0.5), a path of k segments carries
//! Le rho^(k-1), so the channels are L0 = Le (k = 1), direct = Le rho (k = 2) and
//! indirect = Le (rho^2 + ... + rho^(max_depth - 1)): a geometric series that each depth must
//! end exactly where it should; with Russian roulette, unbounded too. Run on the GPU (lavapipe in CI) with the seed's separate passes
//! and the fused path pass.

mod common;

use common::render::{image, render, settings};
use common::root;
use passgraph::render::image::RgbImage;

const LE: f64 = 0.5;
const RHO: f64 = 0.5;

/// The furnace scene with `max_depth: depth`, in a temporary directory.
fn furnace(depth: u32) -> tempfile::TempDir {
    furnace_with(&format!("max_depth: {depth},"))
}

/// The furnace scene with `fields` (e.g. `max_depth: -1, rr_depth: 5,`) after its mesh.
fn furnace_with(fields: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let from = root().join("tests/data/furnace");
    for file in ["furnace.obj", "furnace.mtl"] {
        std::fs::copy(from.join(file), dir.path().join(file)).unwrap();
    }
    let scene = std::fs::read_to_string(from.join("scene.ron")).unwrap();
    let scene = scene.replace(
        "mesh: \"furnace.obj\",",
        &format!("mesh: \"furnace.obj\",\n    {fields}"),
    );
    assert!(
        scene.contains("max_depth"),
        "the furnace scene names its mesh"
    );
    std::fs::write(dir.path().join("scene.ron"), scene).unwrap();
    dir
}

/// Mean over pixels and components, and its standard error from the spread of the pixels
/// (every pixel of the furnace has the same expectation; components are equal: count pixels).
fn mean_and_standard_error(img: &RgbImage) -> (f64, f64) {
    let values: Vec<f64> = img.pixels.iter().flatten().map(|&v| f64::from(v)).collect();
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / (n / 3.0)).sqrt())
}

fn expected(depth: u32) -> [(&'static str, f64); 3] {
    let indirect: f64 = (3..=depth).map(|k| LE * RHO.powi(k as i32 - 1)).sum();
    [
        ("l0", if depth >= 1 { LE } else { 0.0 }),
        ("direct", if depth >= 2 { LE * RHO } else { 0.0 }),
        ("indirect", indirect),
    ]
}

fn check(graph: &str, depth: u32) {
    check_channels(
        graph,
        &furnace(depth),
        &format!("max_depth {depth}"),
        expected(depth),
    );
}

fn check_channels(
    graph: &str,
    dir: &tempfile::TempDir,
    what: &str,
    channels: [(&'static str, f64); 3],
) {
    let scene = dir.path().join("scene.ron");
    let session = render(&settings(graph, &scene, 32, 1, &[]), 32);
    let depth = what;
    for (channel, expected) in channels {
        let (mean, se) = mean_and_standard_error(&image(&session, channel));
        // Five standard errors (a false failure once in ~1.7 million), plus 1e-5 for f32
        // accumulation.
        let bound = 5.0 * se + 1e-5;
        assert!(
            (mean - expected).abs() < bound,
            "{graph}, {depth}, {channel}: mean {mean}, expected {expected}, bound {bound}"
        );
    }
}

#[test]
fn each_max_depth_ends_the_furnace_series_where_mitsuba_does() {
    for depth in [1, 2, 3, 4, 8] {
        check("graphs/pathtracer.ron", depth);
    }
}

#[test]
fn the_fused_pass_follows_max_depth_too() {
    for depth in [2, 5] {
        check("graphs/pathtracer-fused.ron", depth);
    }
}

/// Russian roulette (Mitsuba's rr_depth) ends paths at random and reweights the survivors: the
/// expectation stays the series' sum, to max_depth or, unbounded (-1), to its limit
/// Le rho^2 / (1 - rho) in the indirect channel.
#[test]
fn russian_roulette_keeps_the_furnace_series_unbiased_to_any_depth() {
    let unbounded = [
        ("l0", LE),
        ("direct", LE * RHO),
        ("indirect", LE * RHO * RHO / (1.0 - RHO)),
    ];
    for (graph, rr) in [
        ("graphs/pathtracer.ron", 1),
        ("graphs/pathtracer.ron", 5),
        ("graphs/pathtracer-fused.ron", 2),
    ] {
        let dir = furnace_with(&format!("max_depth: -1, rr_depth: {rr},"));
        check_channels(
            graph,
            &dir,
            &format!("max_depth -1, rr_depth {rr}"),
            unbounded,
        );
    }
    let dir = furnace_with("max_depth: 8, rr_depth: 2,");
    check_channels(
        "graphs/pathtracer.ron",
        &dir,
        "max_depth 8, rr_depth 2",
        expected(8),
    );
}

#[test]
fn cornell_box_at_max_depth_8_matches_mitsuba() {
    let dir = tempfile::tempdir().unwrap();
    common::copy_dir(&root().join("scenes/cornell"), dir.path());
    let path = dir.path().join("scene.ron");
    let scene = std::fs::read_to_string(&path).unwrap();
    std::fs::write(
        &path,
        scene.replace(
            "mesh: \"cornell.obj\",",
            "mesh: \"cornell.obj\",\n    max_depth: 8,",
        ),
    )
    .unwrap();
    let frames = 128;
    let a = render(
        &settings("graphs/pathtracer.ron", &path, 128, 1, &[]),
        frames,
    );
    let b = render(
        &settings("graphs/pathtracer.ron", &path, 128, 2, &[]),
        frames,
    );
    let reference =
        RgbImage::read_exr(&root().join("tests/data/references/cornell-128-depth8-mj.exr"))
            .unwrap();
    let all: Vec<usize> = (0..128 * 128).collect();
    let channels = "l0+direct+indirect";
    // The reference's noise floor: RMSE 1e-3 (tests/data/references/README.md).
    common::reference::check_region(
        "Cornell box, max_depth 8",
        &image(&a, channels),
        &image(&b, channels),
        &reference,
        &all,
        1e-6,
        0.01,
    );
}

/// A glass slab (index 1.5) filling the view in front of an emitting wall, Russian roulette
/// from the first BSDF sample on: each pixel's light comes through two refractions. A
/// refraction into the glass divides radiance by eta^2 = 2.25, and Mitsuba's odds multiply it
/// back (q = min(max(throughput) eta^2, 0.95)); without that factor a path entering the glass
/// survives with probability 1 / 2.25, the survivors weigh 2.25x, and the per-sample relative
/// variance, about 1 / (P(refract twice) q1 q2) - 1, rises from 1 / (0.92 0.95^2) - 1 = 0.20 to
/// 1 / (0.92 0.444 0.95) - 1 = 1.58 (P(refract) = 1 - F = 0.96 at each face). Measured over a
/// frame's pixels (every pixel sees the same light at near-normal incidence), against 0.5:
/// 4096 samples of a two-valued estimate estimate its relative variance to a few percent.
#[test]
fn russian_roulette_does_not_cut_paths_for_the_radiance_a_refraction_scales() {
    let dir = tempfile::tempdir().unwrap();
    let mut obj = String::from("mtllib slab.mtl\n");
    // The slab: a box from z = -1 to 1, faces wound outward.
    let (s, z0, z1) = (10.0, -1.0, 1.0);
    for z in [z0, z1] {
        for (x, y) in [(-s, -s), (s, -s), (s, s), (-s, s)] {
            obj += &format!("v {x} {y} {z}\n");
        }
    }
    obj += "usemtl glass\n";
    // Front (z = -1, normal -z), back (+z) and the four sides.
    for face in [
        [1, 4, 3, 2],
        [5, 6, 7, 8],
        [1, 2, 6, 5],
        [2, 3, 7, 6],
        [3, 4, 8, 7],
        [4, 1, 5, 8],
    ] {
        obj += &format!("f {} {} {} {}\n", face[0], face[1], face[2], face[3]);
    }
    // The wall at z = 3, emitting toward the camera (-z).
    for (x, y) in [(-20.0, -20.0), (20.0, -20.0), (20.0, 20.0), (-20.0, 20.0)] {
        obj += &format!("v {x} {y} 3\n");
    }
    obj += "usemtl wall\nf 9 12 11 10\n";
    std::fs::write(dir.path().join("slab.obj"), obj).unwrap();
    std::fs::write(
        dir.path().join("slab.mtl"),
        "newmtl glass\nillum 7\nNi 1.5\nTf 1 1 1\nnewmtl wall\nKd 0 0 0\nKe 1 1 1\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("scene.ron"),
        "Scene(mesh: \"slab.obj\", max_depth: 8, rr_depth: 1, camera: Camera(eye: (0, 0, -5), target: (0, 0, 0), up: (0, 1, 0), fov_y: 20))\n",
    )
    .unwrap();
    let scene = dir.path().join("scene.ron");
    for graph in [
        "graphs/pathtracer.ron",
        "graphs/pathtracer-fused.ron",
        "graphs/pathtracer-wavefront-merged.ron",
    ] {
        let session = render(&settings(graph, &scene, 64, 1, &[]), 1);
        let img = image(&session, "sum");
        let values: Vec<f64> = img.pixels.iter().map(|p| f64::from(p[0])).collect();
        let n = values.len() as f64;
        let mean = values.iter().sum::<f64>() / n;
        let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
        let relative = variance / (mean * mean);
        assert!(
            mean > 0.1,
            "{graph}: the wall seen through the slab is lit (mean {mean})"
        );
        assert!(
            relative < 0.5,
            "{graph}: per-sample relative variance {relative} (mean {mean}): roulette cuts paths inside the glass"
        );
    }
}
