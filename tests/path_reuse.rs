//! Path reuse (graphs/pathtracer-reuse.ron, shaders/path_reuse.wgsl): the dispatch over tiles,
//! the device feature it needs, the degenerate group of one pixel against the fused pass, and
//! the expectation on the furnace and, region by region, on the Cornell box (lavapipe in CI).

mod common;

use common::render::{image as channel, render, settings};
use common::stats::{assert_unbiased, cornell_reference_mean, mean_over_seeds};
use common::{Scratch, assert_mentions, root};
use passgraph::bench::metrics::downsample_2x;
use passgraph::gpu::limits::check_limits;
use passgraph::render::image::RgbImage;

const CORNELL: &str = "scenes/cornell/scene.ron";
const REUSE: &str = "graphs/pathtracer-reuse.ron";

#[test]
fn one_workgroup_of_64_runs_per_8x8_tile_and_only_with_subgroups() {
    let plan = passgraph::compile_file(&root().join(REUSE), [100, 37]).unwrap();
    let path = plan.passes.iter().find(|p| p.name == "path").unwrap();
    assert_eq!(path.workgroup_size, [64, 1, 1]);
    assert_eq!(path.workgroups, [13, 5, 1]);
    assert!(path.needs_subgroups);
    let limits = wgpu::Limits::default();
    let error = check_limits(&plan, &limits, wgpu::Features::empty())
        .expect_err("a device without subgroups cannot run it");
    assert_mentions(
        &error.to_string(),
        &["pass 'path'", "path_reuse.wgsl", "SUBGROUP"],
    );
    check_limits(&plan, &limits, wgpu::Features::SUBGROUP).unwrap();
    // The fused pass needs nothing of the kind.
    let fast = passgraph::compile_file(&root().join("graphs/pathtracer-fast.ron"), [100, 37]);
    assert!(fast.unwrap().passes.iter().all(|p| !p.needs_subgroups));
}

#[test]
fn a_tile_that_is_not_one_invocation_per_pixel_is_an_error_naming_the_pass() {
    let scratch = Scratch::new();
    scratch.edit(
        "passes/fill.ron",
        r#"Pass(shader: "fill.wgsl","#,
        r#"Pass(shader: "fill.wgsl", dispatch: PerTile(8, 8),"#,
    );
    let (_, message) = scratch.error("graphs/chain.ron");
    assert_mentions(
        &message,
        &[
            "chain.ron",
            "pass 'fill'",
            "fill.wgsl",
            "PerTile(8, 8)",
            "64",
            "256",
        ],
    );
}

#[test]
fn a_group_of_one_pixel_renders_the_fused_pass_samples() {
    // With nothing shared the estimate is path.wgsl's: the same bounces and light samples
    // (the fast graph's 2), weighted brdf * pi (the cosines cancel up to rounding), summed in
    // index order.
    let reuse = render(
        &settings(
            REUSE,
            CORNELL,
            32,
            3,
            &[
                "path.reuse_pixels=1",
                "path.bounces=3",
                "path.light_samples=2",
            ],
        ),
        2,
    );
    let fused = render(
        &settings(
            "graphs/pathtracer-fast.ron",
            CORNELL,
            32,
            3,
            &["path.bounces=3", "path.coherent_bounces=false"],
        ),
        2,
    );
    for c in ["l0", "direct", "indirect"] {
        let (a, b) = (channel(&reuse, c), channel(&fused, c));
        assert!(a.mean()[0] > 0.0, "{c} is black");
        let d = a
            .pixels
            .iter()
            .flatten()
            .zip(b.pixels.iter().flatten())
            .map(|(&x, &y)| (x - y).abs() / x.abs().max(y.abs()).max(1.0))
            .fold(0.0, f32::max);
        assert!(d <= 1e-5, "{c}: the images differ by {d}");
    }
}

#[test]
fn shared_bounces_keep_the_expectation_on_the_furnace() {
    // Furnace: Le (1 + rho + rho^2) with Le = 0.5, rho = 0.5. Every wall is a hull face, so
    // every connection is visible and every member's density counts.
    let images: Vec<_> = (1..=8)
        .map(|seed| {
            render(
                &settings(REUSE, "tests/data/furnace/scene.ron", 16, seed, &[]),
                4,
            )
        })
        .collect();
    for (name, expected) in [("indirect", 0.125), ("sum", 0.875)] {
        let channel: Vec<_> = images.iter().map(|s| channel(s, name)).collect();
        assert_unbiased(&format!("furnace {name}"), &channel, [expected; 3], 1e-6);
    }
}

/// The mean of each `bw` x `bh` block of `image`.
fn block_means(image: &RgbImage, bw: usize, bh: usize) -> Vec<[f64; 3]> {
    let (w, h) = (image.width as usize, image.height as usize);
    let mut out = vec![[0.0; 3]; (w / bw) * (h / bh)];
    for y in 0..h {
        for x in 0..w {
            let p = image.pixels[y * w + x];
            let o = &mut out[(y / bh) * (w / bw) + x / bw];
            for k in 0..3 {
                o[k] += f64::from(p[k]) / (bw * bh) as f64;
            }
        }
    }
    out
}

/// Block `b`'s mean over seeds and its standard error: `runs` holds each seed's block means.
fn block_over_seeds(runs: &[Vec<[f64; 3]>], b: usize) -> ([f64; 3], [f64; 3]) {
    let per_seed: Vec<RgbImage> = runs
        .iter()
        .map(|blocks| RgbImage {
            width: 1,
            height: 1,
            pixels: vec![blocks[b].map(|v| v as f32)],
        })
        .collect();
    mean_over_seeds(&per_seed)
}

/// Asserts that each block's mean over seeds agrees between the reuse graph's `reuse` and the
/// fused pass's `fused` (each seed's block means) within 5 standard errors of the difference,
/// the two standard errors (from the spread between seeds) combined; returns how many blocks
/// the fused pass lights (mean above 1e-3).
fn assert_blocks_agree(reuse: &[Vec<[f64; 3]>], fused: &[Vec<[f64; 3]>]) -> usize {
    let mut lit = 0;
    for b in 0..reuse[0].len() {
        let (r, r_se) = block_over_seeds(reuse, b);
        let (f, f_se) = block_over_seeds(fused, b);
        lit += usize::from(f[0] > 1e-3);
        for k in 0..3 {
            let bound = 5.0 * (r_se[k].powi(2) + f_se[k].powi(2)).sqrt() + 1e-6;
            assert!(
                (r[k] - f[k]).abs() < bound,
                "block {b}, component {k}: reuse {} fused {}, bound {bound}",
                r[k],
                f[k]
            );
        }
    }
    lit
}

#[test]
fn shared_bounces_keep_the_expectation_in_every_region_of_the_cornell_box() {
    // A bias from reuse would be local (a connection's visibility, a side of a wall), so the
    // image is compared region by region: 16 blocks of 8x8 pixels at 32x32, each block's mean
    // over 16 seeds within 5 standard errors (from the spread between seeds) of the Mitsuba
    // reference's block, plus the reference's own noise (RMSE 1e-3 per 128x128 pixel, over the
    // 32x32 of them in a block: 3e-5; 1e-4 taken). The whole image's mean is checked too.
    let reference = {
        let full = RgbImage::read_exr(&root().join("tests/data/references/cornell-128-depth3.exr"))
            .unwrap();
        downsample_2x(&downsample_2x(&full))
    };
    let expected = block_means(&reference, 8, 8);
    let images: Vec<RgbImage> = (1..=16)
        .map(|seed| {
            let session = render(&settings(REUSE, CORNELL, 32, seed, &[]), 4);
            channel(&session, "l0+direct+indirect")
        })
        .collect();
    let (mean, slack) = cornell_reference_mean();
    assert_unbiased("Cornell box, reuse", &images, mean, slack);
    let blocks: Vec<Vec<[f64; 3]>> = images.iter().map(|i| block_means(i, 8, 8)).collect();
    for (b, want) in expected.iter().enumerate() {
        let (got, se) = block_over_seeds(&blocks, b);
        for k in 0..3 {
            let bound = 5.0 * se[k] + 1e-4;
            assert!(
                (got[k] - want[k]).abs() < bound,
                "block {b}, component {k}: mean {} reference {}, bound {bound}",
                got[k],
                want[k]
            );
        }
    }
}

#[test]
fn a_shared_bounce_reaches_only_the_pixels_that_see_it() {
    // A thin wall seen almost edge-on (tests/data/reuse_wall): groups of pixels straddle it,
    // and the lit left half's bounce hits face the right half's primary hits through the wall.
    // Joined without visibility they would light the right half, which no light reaches in two
    // bounces. Block by block (2x8 pixels, narrow across the wall's image), the reuse graph's
    // mean over 16 seeds must match the fused pass's (itself checked against Mitsuba
    // elsewhere) within 5 standard errors of the difference, the two graphs' standard errors
    // (from the spread between seeds) combined. With the visibility rays left out, the block
    // that straddles the wall fails by 6 of them.
    let scene = "tests/data/reuse_wall/scene.ron";
    let blocks = |graph: &str| -> Vec<Vec<[f64; 3]>> {
        (1..=16)
            .map(|seed| {
                let session = render(&settings(graph, scene, 32, seed, &[]), 8);
                block_means(&channel(&session, "indirect"), 2, 8)
            })
            .collect()
    };
    let (reuse, fused) = (blocks(REUSE), blocks("graphs/pathtracer-fast.ron"));
    let lit = assert_blocks_agree(&reuse, &fused);
    assert!(
        lit > 10,
        "only {lit} blocks have indirect light: the scene tests nothing"
    );
}

/// A copy of the Cornell box in a temporary folder with its mesh and material library rewritten
/// by `obj` and `mtl` (which must change something).
fn cornell_with(
    obj: impl Fn(&str) -> String,
    mtl: impl Fn(&str) -> String,
) -> (tempfile::TempDir, std::path::PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let cornell = root().join("scenes/cornell");
    let mut changed = false;
    for (name, edit) in [
        ("cornell.obj", &obj as &dyn Fn(&str) -> String),
        ("cornell.mtl", &mtl),
    ] {
        let text = std::fs::read_to_string(cornell.join(name)).unwrap();
        let edited = edit(&text);
        changed |= edited != text;
        std::fs::write(dir.path().join(name), edited).unwrap();
    }
    assert!(changed, "the Cornell box was not changed");
    std::fs::copy(cornell.join("scene.ron"), dir.path().join("scene.ron")).unwrap();
    let scene = dir.path().join("scene.ron");
    (dir, scene)
}

/// The Cornell box with its material library rewritten by `edit`.
fn cornell_with_materials(
    edit: impl Fn(&str) -> String,
) -> (tempfile::TempDir, std::path::PathBuf) {
    cornell_with(str::to_string, edit)
}

/// The indirect channels of the reuse graph (groups of 4, 2 bounces each; sharing decided per
/// sample when `per_pixel`) and of the fused pass with the 8 bounces a group pools, seed 4, 2
/// frames at 32x32.
fn reuse_and_pooled_indirect(scene: &std::path::Path, per_pixel: bool) -> (RgbImage, RgbImage) {
    let sharing = format!("path.per_pixel_sharing={per_pixel}");
    let reuse = render(
        &settings(
            REUSE,
            scene,
            32,
            4,
            &["path.reuse_pixels=4", "path.bounces=2", &sharing],
        ),
        2,
    );
    let fused = render(
        &settings(
            "graphs/pathtracer-fast.ron",
            scene,
            32,
            4,
            &["path.bounces=8", "path.coherent_bounces=false"],
        ),
        2,
    );
    (channel(&reuse, "indirect"), channel(&fused, "indirect"))
}

#[test]
fn a_pixel_whose_every_lobe_is_delta_traces_the_pooled_bounces_itself() {
    // Sharing per sample, every wall a smooth mirror and the light black but for its emission:
    // no primary hit has a lobe another pixel's bounce could reach, so each pixel traces the 8
    // bounces its group would have pooled, and its estimate is the fused pass's, bit for bit. (The light's
    // pixels share, but a black Lambertian reflects nothing, there as in the fused pass.)
    let (_dir, scene) = cornell_with_materials(|mtl| {
        mtl.replace("Ks 0 0 0\n", "Ks 0 0 0\nPm 1\nPr 0\n").replace(
            "Kd 0.885809 0.698859 0.666422\nKs 0 0 0\nPm 1\nPr 0\nKe",
            "Kd 0 0 0\nKs 0 0 0\nKe",
        )
    });
    let (reuse, fused) = reuse_and_pooled_indirect(&scene, true);
    assert!(reuse.mean()[0] > 0.0, "the indirect channel is black");
    assert_eq!(reuse.pixels, fused.pixels, "not the fused pass's 8 bounces");
}

/// The Cornell box with a glossy (Phong) red wall.
fn cornell_with_a_glossy_wall() -> (tempfile::TempDir, std::path::PathBuf) {
    cornell_with_materials(|mtl| {
        mtl.replace(
            "Kd 0.570068 0.0430135 0.0443706\nKs 0 0 0",
            "Kd 0.570068 0.0430135 0.0443706\nKs 0.3 0.3 0.3\nNs 20",
        )
    })
}

#[test]
fn a_scene_with_a_specular_lobe_shares_nothing_and_traces_the_pooled_bounces_itself() {
    // A bounce hit on the glossy wall reflects other light toward another pixel than toward
    // the one that drew it; by default nothing is shared then (per sample it costs more than
    // it saves: shaders/path_reuse.wgsl), and each pixel traces bounces * reuse_pixels bounces
    // as the fused pass does.
    let (_dir, scene) = cornell_with_a_glossy_wall();
    let (reuse, fused) = reuse_and_pooled_indirect(&scene, false);
    assert!(reuse.mean()[0] > 0.0, "the indirect channel is black");
    assert_eq!(reuse.pixels, fused.pixels, "not the fused pass's 8 bounces");
}

#[test]
fn the_diffuse_pixels_of_a_scene_with_a_glossy_lobe_share_their_bounces() {
    // Sharing per sample on the Cornell box with a glossy red wall: its pixels' bounce hits are
    // shared wherever they land on the Lambertian walls, and the other walls' pixels receive
    // those, so (almost) no pixel is the fused pass's with the pooled bounces. The expectation
    // is checked with glossy and delta lobes on scenes/materials below.
    let (_dir, scene) = cornell_with_a_glossy_wall();
    let (reuse, fused) = reuse_and_pooled_indirect(&scene, true);
    let lit = fused.pixels.iter().filter(|p| p[0] > 0.0).count();
    let same = reuse
        .pixels
        .iter()
        .zip(&fused.pixels)
        .filter(|(a, b)| a[0] > 0.0 && a == b)
        .count();
    assert!(lit > 900, "only {lit} of 1024 pixels have indirect light");
    assert!(
        same * 20 < lit,
        "{same} of {lit} lit pixels are the fused pass's: they do not share"
    );
}

#[test]
fn shared_bounces_keep_the_expectation_among_glossy_glass_and_textured_surfaces() {
    // Sharing per sample on scenes/materials: rough gold (a glossy lobe that shares its draws), rough plastic (a
    // glossy coat over a diffuse base), smooth glass (every lobe delta: traced alone), a
    // textured floor and spheres with shading normals. At 8x8 pixels a group of 8 spans half
    // the image's width, its primary hits far apart. Pixel by pixel, the reuse graph's mean over 16
    // seeds (16 frames each) must match the fused pass's within 5 standard
    // errors of the difference, the two graphs' standard errors (from the spread between
    // seeds) combined. Weighing glossy primary hits by cosine densities (as if Lambertian)
    // shifts pixels by 15 of them.
    let scene = "scenes/materials/scene.ron";
    let blocks = |graph: &str, set: &[&str]| -> Vec<Vec<[f64; 3]>> {
        (1..=16)
            .map(|seed| {
                let session = render(&settings(graph, scene, 8, seed, set), 16);
                block_means(&channel(&session, "indirect"), 1, 1)
            })
            .collect()
    };
    let reuse = blocks(REUSE, &["path.per_pixel_sharing=true"]);
    let fused = blocks("graphs/pathtracer-fast.ron", &[]);
    let lit = assert_blocks_agree(&reuse, &fused);
    assert!(lit > 48, "only {lit} of 64 pixels have indirect light");
}

#[test]
fn a_normal_mapped_primary_hit_weighs_shared_hits_by_its_mapped_normal() {
    // The Cornell box with its back wall normal-mapped (tests/data/surface_maps/stripes.png:
    // four bands tilted about 30 degrees toward +u, +v, -u, -v): a Lambertian scene, so every
    // pixel shares, and a back-wall pixel must weigh the group's hits by the cosine to its
    // mapped normal, as the fused pass does (a band tilted toward the red wall gathers more of
    // its light). Block by block (4x4 pixels at 32x32), the reuse graph's mean over 16 seeds
    // must match the fused pass's within 5 standard errors of the difference. Weighed by the
    // geometric normal instead, as the pass did before 2026-12-04, a block on the wall is 6.5 %
    // too bright, 7 standard errors off.
    let (dir, scene) = cornell_with(
        |obj| {
            let mapped = obj
                .replace(
                    "o back_wall\nusemtl white\n",
                    "o back_wall\nusemtl mapped\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n",
                )
                .replace("f 9 10 11 12", "f 9/1 10/2 11/3 12/4");
            assert_eq!(
                mapped.matches("mapped").count() + mapped.matches("9/1").count(),
                2,
                "the back wall was not found"
            );
            mapped
        },
        |mtl| format!("{mtl}\nnewmtl mapped\nKd 0.885809 0.698859 0.666422\nnorm stripes.png\n"),
    );
    std::fs::copy(
        root().join("tests/data/surface_maps/stripes.png"),
        dir.path().join("stripes.png"),
    )
    .unwrap();
    let blocks = |graph: &str| -> Vec<Vec<[f64; 3]>> {
        (1..=16)
            .map(|seed| {
                let session = render(&settings(graph, &scene, 32, seed, &[]), 8);
                block_means(&channel(&session, "indirect"), 4, 4)
            })
            .collect()
    };
    let (reuse, fused) = (blocks(REUSE), blocks("graphs/pathtracer-fast.ron"));
    assert_blocks_agree(&reuse, &fused);
}
