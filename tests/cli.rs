//! The installed binary: exit codes, stdout and stderr for check, plan and dot.

mod common;

use common::{Scratch, fixtures};
use std::process::{Command, Output};

fn passgraph(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_passgraph"))
        .args(args)
        .output()
        .expect("the passgraph binary runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn plan_prints_the_three_stages_of_the_seed_graph() {
    let graph = fixtures().join("graphs/seed.ron");
    let out = passgraph(&["plan", graph.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    common::assert_mentions(
        &stdout,
        &[
            "0: intersect",
            "1: ambient, direct, indirect",
            "2: accumulate",
            "barriers:",
        ],
    );
}

#[test]
fn check_succeeds_on_every_fixture_and_project_graph() {
    let project = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs");
    // The fixtures are library graphs (census buffers, no `result`): the framework's rules only.
    let dirs = [(fixtures().join("graphs"), true), (project, false)];
    for (dir, generic) in &dirs {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if common::is_subgraph(&path) {
                // Its check is robust_input's every_shipped_graph_meets_the_render_contract.
                continue;
            }
            let mut args = vec!["check", path.to_str().unwrap()];
            if *generic {
                args.push("--generic");
            }
            let out = passgraph(&args);
            assert!(
                out.status.success(),
                "{}: {}",
                path.display(),
                text(&out.stderr)
            );
            assert!(text(&out.stdout).contains(": ok"));
        }
    }
}

#[test]
fn invalid_graph_exits_1_with_the_message_on_stderr_and_no_panic() {
    let s = Scratch::new();
    s.edit(
        "graphs/seed.ron",
        r#""out": "indirect""#,
        r#""out": "indirekt""#,
    );
    let graph = s.path("graphs/seed.ron");
    for command in ["check", "plan", "dot"] {
        let out = passgraph(&[command, graph.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(1), "{command}");
        let stderr = text(&out.stderr);
        assert!(stderr.starts_with("error: "), "{stderr}");
        assert!(stderr.contains("'indirekt'"), "{stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
        assert!(out.stdout.is_empty());
    }
}

#[test]
fn dot_writes_a_whole_file() {
    let s = Scratch::new();
    let out_file = s.path("seed.dot");
    let graph = fixtures().join("graphs/seed.ron");
    let out = passgraph(&[
        "dot",
        graph.to_str().unwrap(),
        "--out",
        out_file.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let dot = std::fs::read_to_string(out_file).unwrap();
    assert!(dot.starts_with("digraph") && dot.trim_end().ends_with('}'));
}

#[test]
fn dot_labels_render_in_graphviz_as_lines_not_as_a_literal_backslash_n() {
    // Graphviz itself draws the file (scripts/setup installs it): each node's name and its
    // graph file are lines of their own. Before, the labels held "\\n", drawn as "\n".
    let graph = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/pathtracer.ron");
    let out = passgraph(&["dot", graph.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let mut dot = Command::new("dot")
        .arg("-Tsvg")
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .expect("Graphviz's `dot` runs (scripts/setup installs the graphviz package)");
    use std::io::Write;
    dot.stdin.take().unwrap().write_all(&out.stdout).unwrap();
    let svg = dot.wait_with_output().unwrap();
    assert!(svg.status.success(), "{}", text(&svg.stderr));
    let svg = text(&svg.stdout);
    // The text of every <text> element: one drawn line each.
    let lines: Vec<&str> = svg
        .split("<text")
        .skip(1)
        .filter_map(|t| {
            t.split_once('>')
                .and_then(|(_, rest)| rest.split_once("</text>"))
        })
        .map(|(line, _)| line)
        .collect();
    assert!(
        lines.iter().all(|l| !l.contains("\\n")),
        "a label shows a literal \\n: {lines:?}"
    );
    for line in ["intersect", "direct", "accumulate"] {
        assert!(lines.contains(&line), "no drawn line '{line}' in {lines:?}");
    }
    assert!(
        lines.iter().any(|l| l.ends_with("graphs/pathtracer.ron")),
        "no drawn line with the graph file in {lines:?}"
    );
}

#[test]
fn bad_size_is_a_usage_error_not_a_panic() {
    let graph = fixtures().join("graphs/seed.ron");
    let out = passgraph(&["plan", graph.to_str().unwrap(), "--size", "0x12"]);
    assert!(!out.status.success());
    assert!(!text(&out.stderr).contains("panicked"));
}
