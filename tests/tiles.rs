//! Big images (src/render/tiles.rs): a tiled render equals the whole render bit for bit, an
//! image over lavapipe's storage-binding limit renders in tiles, and graphs that read other
//! pixels are refused with the pass named.

mod common;

use common::render::{differing_pixels, settings};
use common::{Scratch, assert_mentions, root};
use passgraph::render::channels::ChannelSelection;
use passgraph::render::image::RgbImage;
use passgraph::render::tiles::ImageRender;
use std::process::{Command, Output};

/// The planes of the accumulation but the sum, added: a difference in any of them shows.
const ALL_PLANES: &str = "l0+direct+indirect+ambient";

/// `frames` frames of `graph` at 48x40 from sample `first` on, whole or in tiles; the image,
/// dropped samples, rays.
fn render(
    graph: &str,
    tile: Option<[u32; 2]>,
    first: u32,
    frames: u32,
) -> (RgbImage, u32, Option<u64>) {
    let s = passgraph::render::session::RenderSettings {
        size: [48, 40],
        max_frames: frames,
        ..settings(graph, "scenes/cornell/scene.ron", 48, 0, &[])
    };
    let channel: ChannelSelection = ALL_PLANES.parse().unwrap();
    let mut r =
        ImageRender::for_render(&s, &channel, tile, false).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(r.tiling().is_some(), tile.is_some(), "{graph}");
    r.start_at_sample(first);
    let tiles = r.tile_count() as u64;
    assert_eq!(r.steps_left(), u64::from(frames) * tiles);
    for _ in 0..u64::from(frames) * tiles {
        r.render_frame().unwrap();
    }
    assert_eq!(r.accumulated(), frames);
    (
        r.image(&channel).unwrap(),
        r.dropped().unwrap(),
        r.rays_counted().unwrap(),
    )
}

fn assert_bitwise_equal(graph: &str, tiles: &[[u32; 2]], first: u32) {
    let (whole, dropped, rays) = render(graph, None, first, 2);
    assert!(
        whole.mean().iter().all(|&m| m > 0.0),
        "{graph}: a black image proves nothing"
    );
    for &tile in tiles {
        let (tiled, tiled_dropped, tiled_rays) = render(graph, Some(tile), first, 2);
        let differing = differing_pixels(&whole, &tiled);
        assert_eq!(differing, 0, "{graph}, {tile:?} tiles: pixels differ");
        assert_eq!((tiled_dropped, tiled_rays), (dropped, rays), "{graph}");
    }
}

#[test]
fn tiles_equal_the_whole_image_bit_for_bit_with_the_default_graph() {
    // 16 divides 48 but not 40; 32x24 divides neither.
    assert_bitwise_equal("graphs/pathtracer.ron", &[[16, 16], [32, 24]], 0);
}

#[test]
fn a_sample_range_renders_alike_in_tiles() {
    // `--samples 5..7`: every tile starts at sample 5.
    assert_bitwise_equal("graphs/pathtracer.ron", &[[16, 16]], 5);
}

#[test]
fn tiles_equal_the_whole_image_bit_for_bit_with_the_fused_graphs() {
    assert_bitwise_equal("graphs/pathtracer-fused.ron", &[[32, 24]], 0);
    // Several samples per frame and bounces per sample.
    assert_bitwise_equal("graphs/pathtracer-fast.ron", &[[16, 16]], 0);
}

fn passgraph(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_passgraph"))
        .args(args)
        .output()
        .expect("the passgraph binary runs")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn full_hd_renders_in_tiles_on_lavapipe_and_reports_memory_per_pixel() {
    // Untiled, `result` alone (80 bytes per pixel, 158 MiB) is over lavapipe's 128 MiB
    // storage binding.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("hd.exr");
    let result = passgraph(&[
        "render",
        "--size",
        "1920x1080",
        "--frames",
        "2",
        "--out",
        out.to_str().unwrap(),
    ]);
    let err = stderr(&result);
    assert!(result.status.success(), "{err}");
    assert_mentions(
        &err,
        &[
            "272.0 GPU bytes per pixel",
            "per 1920x544 tile",
            "2 tiles of the 1920x1080 image",
        ],
    );
    let image = RgbImage::read_exr(&out).unwrap();
    assert_eq!([image.width, image.height], [1920, 1080]);
    // Both tiles (rows 0-543 and 544-1079) were rendered and put in place.
    let mean = |rows: std::ops::Range<usize>| {
        let pixels = &image.pixels[rows.start * 1920..rows.end * 1920];
        pixels.iter().map(|p| p[0] + p[1] + p[2]).sum::<f32>() / pixels.len() as f32
    };
    assert!(mean(0..544) > 0.01 && mean(544..1080) > 0.01);
}

#[test]
fn a_graph_that_reads_neighbours_is_not_tiled_and_the_error_names_the_pass() {
    let graph = root().join("graphs/pathtracer-denoise.ron");
    let graph = graph.to_str().unwrap();
    // Too big untiled: the error says why, which pass, and the largest untiled size.
    let result = passgraph(&["render", "--graph", graph, "--size", "1920x1080"]);
    assert_eq!(result.status.code(), Some(1));
    assert_mentions(
        &stderr(&result),
        &[
            "max_storage_buffer_binding_size",
            "cannot be rendered in tiles",
            "pass 'denoise/atrous1'",
            "footprint: Pixel",
            "renders untiled on this device is 1727x971",
        ],
    );
    // Asked for tiles.
    let result = passgraph(&[
        "render", "--graph", graph, "--size", "64x64", "--tile", "32x32",
    ]);
    assert_eq!(result.status.code(), Some(1));
    assert_mentions(
        &stderr(&result),
        &["cannot render in tiles", "pass 'denoise/atrous1'"],
    );
}

#[test]
fn a_tile_that_is_not_a_multiple_of_8_is_a_usage_error() {
    let result = passgraph(&["render", "--size", "64x64", "--tile", "20x16"]);
    assert_eq!(result.status.code(), Some(2));
    assert_mentions(&stderr(&result), &["tile 20x16", "multiple of 8"]);
    assert!(!stderr(&result).contains("panicked"));
}

#[test]
fn footprint_pixel_is_refused_where_it_cannot_hold() {
    let scratch = Scratch::new();
    scratch.write(
        "passes/counter.ron",
        "Pass(shader: \"counter.wgsl\", dispatch: Workgroups(1, 1, 1), footprint: Pixel)",
    );
    scratch.write(
        "shaders/counter.wgsl",
        "@group(0) @binding(0) var<storage, read_write> n: array<u32>;\n@compute @workgroup_size(1) fn main() { n[0] += 1u; }\n",
    );
    scratch.write(
        "graphs/counter.ron",
        "Graph(resources: { \"n\": Buffer(size: Bytes(4), persistent: true) }, passes: [(name: \"c\", pass: \"counter\", bind: { \"n\": \"n\" })], outputs: [\"n\"])",
    );
    let (_, message) = scratch.error("graphs/counter.ron");
    assert_mentions(&message, &["counter.ron", "footprint", "Workgroups"]);
}

#[test]
fn an_image_past_the_samplers_32_bit_pixel_index_is_an_error() {
    let result = passgraph(&["render", "--size", "70000x70000", "--frames", "1"]);
    assert_eq!(result.status.code(), Some(1));
    assert_mentions(&stderr(&result), &["70000x70000", "2^32 pixels"]);
}
