//! The framework stands alone: the second renderer (examples/postprocess: a raster pass, then a
//! blur and a grade in compute), built on passgraph-graph and passgraph-gpu only, draws what its
//! application provides, pixel for pixel as a CPU model of the same three steps says.
//! Runs on any adapter wgpu finds (lavapipe in CI).

#[path = "../examples/postprocess/renderer.rs"]
mod renderer;

use passgraph_gpu::GpuContext;

const A: [f32; 3] = [0.2, 0.4, 0.8];
const B: [f32; 3] = [0.9, 0.3, 0.1];
const GAIN: [f32; 3] = [1.0, 0.9, 0.8];

/// The CPU model: triangle 0 fills the image with A, triangle 1 the left half with B; a 3x3
/// box with clamped edges; times the gain.
fn expected(size: [u32; 2], triangles: u32) -> Vec<[f32; 3]> {
    let [w, h] = size.map(|v| v as i32);
    // Pixel centres x + 0.5 left of the middle are covered by triangle 1.
    let drawn = |x: i32| -> [f32; 3] {
        let x = x.clamp(0, w - 1);
        if triangles >= 2 && 2 * x + 1 < w {
            B
        } else {
            A
        }
    };
    let mut out = Vec::new();
    for _y in 0..h {
        for x in 0..w {
            let mut sum = [0.0f32; 3];
            for _dy in -1..=1 {
                for dx in -1..=1 {
                    let c = drawn(x + dx);
                    for k in 0..3 {
                        sum[k] += c[k];
                    }
                }
            }
            out.push([0, 1, 2].map(|k| sum[k] / 9.0 * GAIN[k]));
        }
    }
    out
}

fn assert_matches(size: [u32; 2], triangles: u32) {
    let ctx = GpuContext::new(None).unwrap_or_else(|e| panic!("{e}"));
    let got = renderer::render(&ctx, size, triangles, GAIN).unwrap_or_else(|e| panic!("{e}"));
    let want = expected(size, triangles);
    assert_eq!(got.len(), want.len());
    for (i, (g, w)) in got.iter().zip(&want).enumerate() {
        for k in 0..3 {
            // The GPU may sum the nine texels in another order: a few ulps.
            assert!(
                (g[k] - w[k]).abs() <= 4.0 * f32::EPSILON,
                "{triangles} triangles, pixel ({}, {}), channel {k}: {} against {}",
                i as u32 % size[0],
                i as u32 / size[0],
                g[k],
                w[k]
            );
        }
        assert_eq!(g[3], 1.0);
    }
}

#[test]
fn the_raster_blur_grade_chain_draws_what_the_application_provides_pixel_for_pixel() {
    assert_matches([32, 24], 2);
    // The application's override decides the triangles: one leaves the whole image A.
    assert_matches([16, 8], 1);
}

#[test]
fn its_plan_orders_draw_blur_grade_and_knows_only_the_applications_names() {
    let plan = renderer::compile([32, 24]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        plan.stage_names(),
        [vec!["draw"], vec!["blur"], vec!["grade"]]
    );
    // A copy of the example binding the path tracer's `camera`: not this application's name.
    let dir = tempfile::tempdir().unwrap();
    let example = renderer::graph_path();
    let example = example.parent().unwrap().parent().unwrap();
    for sub in ["graphs", "passes", "shaders"] {
        std::fs::create_dir_all(dir.path().join(sub)).unwrap();
        for entry in std::fs::read_dir(example.join(sub)).unwrap() {
            let entry = entry.unwrap();
            let text = std::fs::read_to_string(entry.path())
                .unwrap()
                .replace("\"grade\": \"grade\"", "\"grade\": \"camera\"");
            std::fs::write(dir.path().join(sub).join(entry.file_name()), text).unwrap();
        }
    }
    let e = passgraph_graph::compile::compile_file(
        &dir.path().join("graphs/postprocess.ron"),
        [32, 24],
        &renderer::provided_set(),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("'camera'"), "{e}");
}
