//! docs/writing-a-pass.md: the tutorial's files are what the doc shows, and the pass they add
//! runs through the built binary from a fresh folder, with no rebuild.

mod common;

use common::{copy_dir, root};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The tutorial's files, relative to docs/.
const FILES: [&str; 4] = [
    "writing-a-pass/shaders/false_colour.wgsl",
    "writing-a-pass/passes/false_colour.ron",
    "writing-a-pass/graphs/pathtracer-false-colour.ron",
    "writing-a-pass/tests/false-colour.ron",
];

/// The fenced block after each `<!-- include: PATH -->` line of the doc, by PATH.
fn included_blocks(doc: &str) -> Vec<(String, String)> {
    let mut blocks = Vec::new();
    let mut lines = doc.lines();
    while let Some(line) = lines.next() {
        let Some(path) = line
            .strip_prefix("<!-- include: ")
            .and_then(|l| l.strip_suffix(" -->"))
        else {
            continue;
        };
        let fence = lines.next().unwrap_or_default();
        assert!(
            fence.starts_with("```"),
            "{path}: no code block after the marker"
        );
        let mut body = String::new();
        for line in lines.by_ref() {
            if line == "```" {
                break;
            }
            body.push_str(line);
            body.push('\n');
        }
        blocks.push((path.to_string(), body));
    }
    blocks
}

#[test]
fn the_doc_shows_the_tutorial_files_verbatim() {
    let doc = std::fs::read_to_string(root().join("docs/writing-a-pass.md")).unwrap();
    let blocks = included_blocks(&doc);
    let paths: Vec<&str> = blocks.iter().map(|(p, _)| p.as_str()).collect();
    assert_eq!(
        paths, FILES,
        "the doc should include each file once, in order"
    );
    for (path, body) in &blocks {
        let file = std::fs::read_to_string(root().join("docs").join(path)).unwrap();
        assert!(
            *body == file,
            "docs/writing-a-pass.md and docs/{path} disagree"
        );
    }
}

fn passgraph(dir: &Path, args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_passgraph"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("the passgraph binary runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "passgraph {args:?}: {stderr}");
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn read_exr(path: PathBuf) -> Vec<[f32; 3]> {
    let img = image::open(&path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb32f();
    img.pixels().map(|p| p.0).collect()
}

/// The shader's ramp, on the CPU: blue, cyan, green, yellow, red at t = 0, 1/4, ..., 1.
fn ramp(t: f32) -> [f32; 3] {
    let stops = [
        [0.0, 0.0, 1.0],
        [0.0, 1.0, 1.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
        [1.0, 0.0, 0.0],
    ];
    let x = t.clamp(0.0, 1.0) * 4.0;
    let i = (x as usize).min(3);
    let f = x - i as f32;
    [0, 1, 2].map(|k| stops[i][k] + (stops[i + 1][k] - stops[i][k]) * f)
}

#[test]
fn the_tutorial_pass_runs_through_the_built_binary() {
    // A project folder as a user would have it after the tutorial: the shipped passes,
    // shaders, path tracer graph and Cornell box, plus the new files.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    copy_dir(&root().join("passes"), &d.join("passes"));
    copy_dir(&root().join("shaders"), &d.join("shaders"));
    copy_dir(&root().join("scenes/cornell"), &d.join("scenes/cornell"));
    std::fs::create_dir_all(d.join("graphs")).unwrap();
    std::fs::copy(
        root().join("graphs/pathtracer.ron"),
        d.join("graphs/pathtracer.ron"),
    )
    .unwrap();
    for file in FILES {
        let to = d.join(file.strip_prefix("writing-a-pass/").unwrap());
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(root().join("docs").join(file), to).unwrap();
    }
    let graph = "graphs/pathtracer-false-colour.ron";
    assert!(passgraph(d, &["check", graph]).contains(": ok (6 passes in 4 stages, 0 culled)"));
    let plan = passgraph(d, &["plan", graph]);
    assert!(plan.contains("  3: false_colour\n"), "{plan}");

    // Section 6: the graph tests print what the doc shows.
    let doc = std::fs::read_to_string(root().join("docs/writing-a-pass.md")).unwrap();
    let command = "$ passgraph test tests/false-colour.ron\n";
    let shown = &doc[doc.find(command).expect("the doc runs the tests") + command.len()..];
    let shown = &shown[..shown.find("```").unwrap()];
    assert_eq!(passgraph(d, &["test", "tests/false-colour.ron"]), shown);

    let scene = root().join("scenes/cornell/scene.ron");
    let render = |channel: &str, out: &str| {
        let args = [
            "--graph",
            graph,
            "--scene",
            scene.to_str().unwrap(),
            "--size",
            "32x32",
            "--frames",
            "4",
            "--channel",
            channel,
            "--out",
            out,
        ];
        passgraph(d, &args);
        read_exr(d.join(out))
    };
    let view = render("false_colour", "view.exr");
    // The same seed and frames: the same accumulation, read as its sum.
    let sum = render("sum", "sum.exr");
    // The graph sets lo = -1.5; hi is the pass's default, 1.
    let (lo, hi) = (-1.5f32, 1.0f32);
    let mut segments = [false; 4];
    for (v, s) in view.iter().zip(&sum) {
        let luminance = 0.2126 * s[0] + 0.7152 * s[1] + 0.0722 * s[2];
        let t = (luminance.max(1e-30).log10() - lo) / (hi - lo);
        segments[((t.clamp(0.0, 1.0) * 4.0) as usize).min(3)] = true;
        let expected = ramp(t);
        for k in 0..3 {
            // f32 log2 on the GPU against log10 here: a few ulps of the level, times the
            // ramp's slope of 4 / (hi - lo) = 1.6 per decade; 1e-4 is far above that and far
            // below any wrong colour (a quarter of the ramp is a whole unit).
            assert!(
                (v[k] - expected[k]).abs() < 1e-4,
                "luminance {luminance}: {v:?}, expected {expected:?}"
            );
        }
    }
    // The Cornell box spans enough decades that the check covers most of the ramp.
    assert!(
        segments.iter().filter(|&&s| s).count() >= 3,
        "segments {segments:?}"
    );
}
