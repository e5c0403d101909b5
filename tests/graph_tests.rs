//! `passgraph test`: the shipped graph tests (tests/graphs/*.ron) pass; on a deliberately broken
//! copy they fail naming the case, the expectation and the measured value; a malformed test
//! file is an error naming its file and line, never a panic.

mod common;

use common::{assert_mentions, copy_dir, root};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn passgraph(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_passgraph"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("the passgraph binary runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn test_files(dir: &Path) -> Vec<String> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir.join("tests/graphs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    files
        .iter()
        .map(|p| p.strip_prefix(dir).unwrap().to_string_lossy().into_owned())
        .collect()
}

#[test]
fn the_shipped_graph_tests_pass() {
    let files = test_files(root());
    let mut args = vec!["test"];
    args.extend(files.iter().map(String::as_str));
    let out = passgraph(root(), &args);
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{stdout}{}", text(&out.stderr));
    let cases = stdout.lines().filter(|l| l.starts_with("ok    ")).count();
    assert!(
        stdout.ends_with(&format!("{cases} cases: {cases} passed, 0 failed\n")),
        "{stdout}"
    );
    // Every shipped graph has cases.
    for graph in std::fs::read_dir(root().join("graphs")).unwrap() {
        let graph = graph.unwrap().path();
        let name = graph.file_name().unwrap().to_str().unwrap();
        if common::is_subgraph(&graph) {
            continue;
        }
        assert!(
            files.iter().any(|f| f.ends_with(name)),
            "no tests/graphs/{name}"
        );
    }
}

#[test]
fn every_shipped_test_file_reads_and_its_graphs_compile_without_rendering() {
    for file in test_files(root()) {
        let cases = passgraph::graphtest::run::check_file(&root().join(&file))
            .unwrap_or_else(|e| panic!("{file}: {e}"));
        assert!(cases > 0, "{file}");
    }
}

/// A project copy with what tests/graphs/pathtracer.ron reads.
fn project() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for sub in [
        "graphs",
        "passes",
        "shaders",
        "scenes/cornell",
        "tests/graphs",
    ] {
        copy_dir(&root().join(sub), &d.join(sub));
    }
    let reference = "tests/data/references/cornell-128-depth3.exr";
    std::fs::create_dir_all(d.join("tests/data/references")).unwrap();
    std::fs::copy(root().join(reference), d.join(reference)).unwrap();
    dir
}

fn edit(path: &Path, from: &str, to: &str) {
    let text = std::fs::read_to_string(path).unwrap();
    assert_eq!(
        text.matches(from).count(),
        1,
        "{from:?} in {}",
        path.display()
    );
    std::fs::write(path, text.replacen(from, to, 1)).unwrap();
}

#[test]
fn a_broken_graph_fails_naming_the_case_the_expectation_and_the_measured_value() {
    let dir = project();
    let d = dir.path();
    // Accumulate reads the indirect texture as the direct one: it compiles, but the image
    // loses direct light and counts indirect twice, and the plan loses a barrier.
    edit(
        &d.join("graphs/pathtracer.ron"),
        r#""l0": "l0", "direct": "direct", "indirect": "indirect","#,
        r#""l0": "l0", "direct": "indirect", "indirect": "indirect","#,
    );
    let out = passgraph(d, &["test", "tests/graphs/pathtracer.ron"]);
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    assert_mentions(&text(&out.stderr), &["cases failed"]);
    let line = |case: &str| {
        stdout
            .lines()
            .find(|l| l.contains(&format!(" {case}")))
            .unwrap_or_else(|| panic!("no line for {case}:\n{stdout}"))
            .to_string()
    };
    assert_mentions(
        &line("shape"),
        &[
            "FAIL  tests/graphs/pathtracer.ron:17 shape: Barriers: measured 4 barriers",
            "expected 5",
        ],
    );
    let failed = line("cornell-unbiased");
    assert!(failed.starts_with("FAIL  tests/graphs/pathtracer.ron:27 cornell-unbiased: "));
    assert_mentions(
        &failed,
        &[
            "Mean(l0+direct+indirect): r: measured 0.",
            "standard errors (allowed 6)",
            "Rmse(l0+direct+indirect): measured RMSE ",
            "expected below 9.1000e-2",
        ],
    );
    // What held is not reported as failed.
    assert!(!failed.contains("NoDroppedSamples"), "{failed}");
    assert!(line("unread-pass-is-culled").starts_with("ok    "));
    assert!(
        stdout.ends_with("4 cases: 1 passed, 3 failed\n"),
        "{stdout}"
    );
}

#[test]
fn a_wrong_plan_expectation_fails_with_the_measured_plan() {
    let dir = project();
    let d = dir.path();
    let file = d.join("tests/graphs/pathtracer.ron");
    edit(&file, "Barriers(5)", "Barriers(6)");
    edit(
        &file,
        r#"Culled(["spare_ambient"])"#,
        r#"Culled(["spare_ambient", "ambient"])"#,
    );
    let out = passgraph(d, &["test", "tests/graphs/pathtracer.ron"]);
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    assert_mentions(
        &stdout,
        &[
            "FAIL  tests/graphs/pathtracer.ron:17 shape: Barriers: measured 5 barriers (rays before stage 1, ",
            "expected 6",
            "unread-pass-is-culled: Culled: measured culled [spare_ambient], expected [ambient, spare_ambient]",
        ],
    );
}

/// Writes a test file into a project copy and runs it; it must be an error, not a failure.
fn bad_file(body: &str) -> String {
    let dir = project();
    let d = dir.path();
    std::fs::write(d.join("tests/graphs/bad.ron"), body).unwrap();
    // A plan-only case in another file, to show the other files still run.
    let good = case(&format!("{GRAPH}\n            expect: [Culled([])],"));
    std::fs::write(d.join("tests/graphs/good.ron"), good).unwrap();
    let out = passgraph(
        d,
        &["test", "tests/graphs/bad.ron", "tests/graphs/good.ron"],
    );
    let stdout = text(&out.stdout);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stdout}{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    // The other file still runs.
    assert!(
        stdout.ends_with("1 cases: 1 passed, 0 failed; 1 test file(s) with errors\n"),
        "{stdout}"
    );
    stdout
        .lines()
        .find(|l| l.starts_with("error "))
        .unwrap_or_else(|| panic!("no error line:\n{stdout}"))
        .to_string()
}

fn case(fields: &str) -> String {
    format!("GraphTests(\n    cases: [\n        (\n{fields}\n        ),\n    ],\n)\n")
}

const GRAPH: &str = r#"            name: "c",
            graph: "../../graphs/pathtracer.ron","#;

#[test]
fn a_malformed_test_file_is_an_error_naming_its_file_and_line() {
    for (body, parts) in [
        // RON syntax: the parser's line and column.
        (
            case(&format!("{GRAPH}\n            expect: [Culled([]]\n")),
            &["tests/graphs/bad.ron:6:"][..],
        ),
        // An unknown expectation.
        (
            case(&format!("{GRAPH}\n            expect: [Cullled([])],")),
            &["tests/graphs/bad.ron:6:", "Cullled"],
        ),
        // A graph file that does not exist.
        (
            case(
                "            name: \"c\",\n            graph: \"nope.ron\",\n            expect: [Culled([])],",
            ),
            &[
                "tests/graphs/bad.ron:5:",
                "case 'c'",
                "nope.ron",
                "no such file",
            ],
        ),
        (
            case("            name: \"c\",\n            expect: [Culled([])],"),
            &["tests/graphs/bad.ron:4:", "either `graph"],
        ),
        // Frames without a scene.
        (
            case(&format!("{GRAPH}\n            expect: [NoDroppedSamples],")),
            &["tests/graphs/bad.ron:4:", "needs a `scene`"],
        ),
        (
            case(&format!(
                "{GRAPH}\n            scene: \"../../scenes/cornell/scene.ron\",\n            expect: [\n                AllFinite(channel: \"l0+bogus\"),\n            ],"
            )),
            &[
                "tests/graphs/bad.ron:8:",
                "AllFinite(l0+bogus)",
                "unknown channel 'bogus'",
            ],
        ),
        // A mean needs a spread between seeds.
        (
            case(&format!(
                "{GRAPH}\n            scene: \"../../scenes/cornell/scene.ron\",\n            expect: [\n                Mean(channel: \"sum\", value: (1, 1, 1), within: 5),\n            ],"
            )),
            &["tests/graphs/bad.ron:8:", "Mean(sum)", "at least 2"],
        ),
        // A reference that is not the case's size times a power of 2.
        (
            case(&format!(
                "{GRAPH}\n            scene: \"../../scenes/cornell/scene.ron\",\n            size: (48, 48),\n            expect: [\n                Rmse(channel: \"sum\", reference: \"../data/references/cornell-128-depth3.exr\", below: 1),\n            ],"
            )),
            &["tests/graphs/bad.ron:9:", "128x128", "48x48"],
        ),
        (
            case(&format!(
                "{GRAPH}\n            scene: \"../../scenes/cornell/scene.ron\",\n            expect: [\n                Rmse(channel: \"sum\", reference: \"../data/references/cornell-128-depth3.exr\", below: -1),\n            ],"
            )),
            &["tests/graphs/bad.ron:8:", "below must be a positive number"],
        ),
        (
            "GraphTests(cases: [])".to_string(),
            &["tests/graphs/bad.ron: no cases"],
        ),
        // A mistyped frame count that would render for days.
        (
            case(&format!(
                "{GRAPH}\n            scene: \"../../scenes/cornell/scene.ron\",\n            frames: 4294967295,\n            expect: [NoDroppedSamples],"
            )),
            &[
                "tests/graphs/bad.ron:7:",
                "4294967295 frames x 1 seeds x 32x32 pixels",
                "more than max_samples (67108864)",
            ],
        ),
    ] {
        let line = bad_file(&body);
        assert_mentions(&line, parts);
    }
}

#[test]
fn a_bad_change_written_inline_fails_its_case_naming_the_test_file_and_line() {
    let dir = project();
    let d = dir.path();
    let body = case(
        r#"            name: "inline",
            changes: Graph(
                extends: "../../graphs/pathtracer.ron",
                remove_passes: ["intersekt"],
            ),
            expect: [Culled([])],"#,
    );
    std::fs::write(d.join("tests/graphs/inline.ron"), body).unwrap();
    let out = passgraph(d, &["test", "tests/graphs/inline.ron"]);
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    assert_mentions(
        &stdout,
        &[
            "FAIL  tests/graphs/inline.ron:4 inline: graph: does not load: tests/graphs/inline.ron:7: remove_passes: no pass 'intersekt'",
            "1 cases: 0 passed, 1 failed",
        ],
    );
}

#[test]
fn no_test_file_is_a_usage_error() {
    let out = passgraph(root(), &["test"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn the_largest_seed_count_is_checked_without_listing_the_seeds() {
    // Found by the fuzzer: `seeds: 4294967295` made the reader allocate a list of four billion
    // seeds (16 GiB) before any rendering; a count is kept as a count.
    let project = project();
    let file = project.path().join("tests/graphs/pathtracer.ron");
    let text = std::fs::read_to_string(&file).unwrap();
    let first = text.find("seeds: 16,").expect("a case with 16 seeds");
    let edited = format!(
        "{}seeds: 4294967295,{}",
        &text[..first],
        &text[first + "seeds: 16,".len()..]
    );
    std::fs::write(&file, edited).unwrap();
    // Refused as too much work (max_samples), from the counts alone.
    let e = passgraph::graphtest::run::check_file(&file).unwrap_err();
    assert!(
        e.contains("4294967295 seeds") && e.contains("max_samples"),
        "{e}"
    );
}
