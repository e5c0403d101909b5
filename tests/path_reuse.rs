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
    let mut lit = 0;
    for b in 0..reuse[0].len() {
        let (r, r_se) = block_over_seeds(&reuse, b);
        let (f, f_se) = block_over_seeds(&fused, b);
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
    assert!(
        lit > 10,
        "only {lit} blocks have indirect light: the scene tests nothing"
    );
}

#[test]
fn a_scene_with_a_specular_lobe_shares_nothing_and_traces_the_pooled_bounces_itself() {
    // The Cornell box with glossy red and green walls: a bounce hit's light toward another
    // pixel would differ from its light toward the pixel that drew it, so nothing is shared,
    // and each pixel traces bounces * reuse_pixels bounces as the fused pass does.
    let dir = tempfile::tempdir().unwrap();
    let cornell = root().join("scenes/cornell");
    std::fs::copy(cornell.join("cornell.obj"), dir.path().join("cornell.obj")).unwrap();
    let mtl = std::fs::read_to_string(cornell.join("cornell.mtl")).unwrap();
    let glossy = mtl.replace(
        "Kd 0.570068 0.0430135 0.0443706\nKs 0 0 0",
        "Kd 0.570068 0.0430135 0.0443706\nKs 0.3 0.3 0.3\nNs 20",
    );
    assert_ne!(glossy, mtl, "the red wall's material was not found");
    std::fs::write(dir.path().join("cornell.mtl"), glossy).unwrap();
    std::fs::copy(cornell.join("scene.ron"), dir.path().join("scene.ron")).unwrap();
    let scene = dir.path().join("scene.ron");
    let reuse = render(
        &settings(
            REUSE,
            &scene,
            32,
            4,
            &["path.reuse_pixels=4", "path.bounces=2"],
        ),
        2,
    );
    let fused = render(
        &settings(
            "graphs/pathtracer-fast.ron",
            &scene,
            32,
            4,
            &["path.bounces=8", "path.coherent_bounces=false"],
        ),
        2,
    );
    let (a, b) = (channel(&reuse, "indirect"), channel(&fused, "indirect"));
    assert!(a.mean()[0] > 0.0, "the indirect channel is black");
    assert_eq!(a.pixels, b.pixels, "not the fused pass's 8 bounces");
}
