//! Composition (crates/graph/src/compose.rs): the shipped variants, written as differences from their
//! base, flatten to exactly the full files they replaced (kept in tests/data/graphs-flat/), and
//! every bad `extends`, `include` or change is an error naming the file that made it.

mod common;

use common::{Scratch, assert_mentions, root};
use passgraph::GraphError;
use passgraph::graph::compose::flatten;
use passgraph::graph::decl::GraphDecl;
use passgraph::graph::load::load_graph;
use passgraph::graph::shared_params::with_shared_params;
use std::collections::BTreeSet;
use std::path::Path;

/// The flattened shipped graph against the full file it replaced: same passes in the same
/// order (names, pass files, bindings, params), same resources, same outputs (a set: their
/// order means nothing). `rename` maps an old name to its new one (a subgraph's prefix).
fn assert_equivalent(graph: &str, rename: &dyn Fn(&str) -> String) {
    let new = {
        // Graph-level params reach the instances whose passes have them, as compile applies them.
        let loaded = load_graph(&root().join("graphs").join(graph))
            .unwrap_or_else(|e| panic!("{graph}: {e}"));
        let mut decl = loaded.decl.clone();
        decl.passes = with_shared_params(&loaded, passgraph::render::provided::path_tracer())
            .unwrap_or_else(|e| panic!("{graph}: {e}"))
            .into_iter()
            .map(|(_, instance)| instance)
            .collect();
        decl
    };
    let old: GraphDecl = {
        let path = root().join("tests/data/graphs-flat").join(graph);
        let mut old = flatten(&path).unwrap().decl;
        for p in &mut old.passes {
            p.name = rename(&p.name);
            p.bind = p.bind.iter().map(|(b, r)| (b.clone(), rename(r))).collect();
        }
        old.resources = old
            .resources
            .into_iter()
            .map(|(n, r)| (rename(&n), r))
            .collect();
        old.outputs = old.outputs.iter().map(|o| rename(o)).collect();
        old
    };
    assert!(new.inputs.is_empty() && old.inputs.is_empty());
    let names = |d: &GraphDecl| d.passes.iter().map(|p| p.name.clone()).collect::<Vec<_>>();
    assert_eq!(names(&new), names(&old), "{graph}: pass order");
    for (n, o) in new.passes.iter().zip(&old.passes) {
        assert_eq!(n, o, "{graph}: pass '{}'", n.name);
    }
    assert_eq!(new.resources, old.resources, "{graph}: resources");
    let set = |d: &GraphDecl| d.outputs.iter().cloned().collect::<BTreeSet<_>>();
    assert_eq!(set(&new), set(&old), "{graph}: outputs");
    assert_eq!(
        new.outputs.len(),
        set(&new).len(),
        "{graph}: repeated output"
    );
}

#[test]
fn every_shipped_variant_flattens_to_the_full_graph_it_replaced() {
    let same = |n: &str| n.to_string();
    for graph in [
        "pathtracer.ron",
        "pathtracer-lightselect.ron",
        "pathtracer-fused.ron",
        "pathtracer-fast.ron",
        "pathtracer-reproject.ron",
    ] {
        assert_equivalent(graph, &same);
    }
    // The denoiser's own passes and resources now sit under the include's prefix; its input
    // resources and its renamed output keep their names.
    let denoiser = [
        "gbuffer",
        "demodulate",
        "atrous1",
        "atrous2",
        "atrous3",
        "atrous4",
        "atrous5",
        "remodulate",
        "guide_normal",
        "guide_position",
        "guide_albedo",
        "atrous_a",
        "atrous_b",
    ];
    assert_equivalent("pathtracer-denoise.ron", &|n: &str| {
        if denoiser.contains(&n) {
            format!("denoise/{n}")
        } else {
            n.to_string()
        }
    });
}

#[test]
fn every_shipped_variant_is_a_short_file_of_differences() {
    for graph in [
        "pathtracer-lightselect.ron",
        "pathtracer-fused.ron",
        "pathtracer-fast.ron",
        "pathtracer-reproject.ron",
        "pathtracer-denoise.ron",
    ] {
        let text = std::fs::read_to_string(root().join("graphs").join(graph)).unwrap();
        assert!(text.contains("extends:"), "{graph} should extend its base");
        assert!(
            !text.contains("name: \"accumulate\""),
            "{graph} should not repeat accumulate"
        );
    }
}

#[test]
fn plan_and_dot_name_the_file_each_pass_and_resource_came_from() {
    // Relative paths, as a user types them (tests run in the repository).
    let plan =
        passgraph::compile_file(Path::new("graphs/pathtracer-lightselect.ron"), [32, 32]).unwrap();
    let text = plan.to_string();
    assert_mentions(
        &text,
        &[
            "composed of graphs/pathtracer-lightselect.ron, graphs/pathtracer.ron",
            "light_selection from graphs/pathtracer-lightselect.ron",
        ],
    );
    let line = |name: &str| {
        text.lines()
            .find(|l| l.trim_start().starts_with(&format!("{name} ")))
            .unwrap_or_else(|| panic!("no line for {name}:\n{text}"))
            .to_string()
    };
    assert_mentions(&line("intersect"), &["from graphs/pathtracer.ron"]);
    assert!(!line("intersect").contains("lightselect"), "{text}");
    assert_mentions(&line("rays"), &["(from graphs/pathtracer.ron)"]);

    let plan =
        passgraph::compile_file(Path::new("graphs/pathtracer-denoise.ron"), [32, 32]).unwrap();
    let dot = passgraph::to_dot(&plan);
    assert_mentions(
        &dot,
        &[
            "denoise/atrous1\\ngraphs/denoiser.ron",
            "accumulate\\ngraphs/pathtracer.ron",
        ],
    );
    // DOT's line break is `\n`; an escaped backslash before it (`\\n`) shows as a literal
    // "\n" in every node.
    assert!(!dot.contains("\\\\n"), "{dot}");
    assert!(plan.pass("denoise/remodulate").is_some());
}

/// A scratch project: the fixtures' passes and shaders beside graphs written by the test.
fn project(files: &[(&str, &str)]) -> Scratch {
    let s = Scratch::new();
    for (name, text) in files {
        s.write(name, text);
    }
    s
}

const BASE: &str = "graphs/base.ron";

fn with_base(child: &str) -> Scratch {
    let base = std::fs::read_to_string(common::fixtures().join("graphs/seed.ron")).unwrap();
    project(&[(BASE, &base), ("graphs/child.ron", child)])
}

fn compose_error(s: &Scratch, graph: &str) -> (Option<usize>, String) {
    let (e, msg) = s.error(graph);
    let GraphError::Compose { line, .. } = e else {
        panic!("expected a composition error, got: {msg}")
    };
    (line, msg)
}

#[test]
fn a_change_to_a_pass_that_does_not_exist_names_the_file_line_and_the_passes() {
    for (key, text) in [
        ("remove_passes", r#"remove_passes: ["intersekt"],"#),
        (
            "replace_passes",
            r#"replace_passes: [(name: "intersekt", pass: "intersect")],"#,
        ),
        (
            "params",
            r#"params: { "intersekt": { "sampler_kind": U32(0) } },"#,
        ),
    ] {
        let s = with_base(&format!(
            "Graph(\n    extends: \"base.ron\",\n    {text}\n)\n"
        ));
        let (line, msg) = compose_error(&s, "graphs/child.ron");
        assert_eq!(line, Some(3), "{key}: {msg}");
        assert_mentions(&msg, &["child.ron:3", "'intersekt'", "'intersect'", key]);
    }
}

#[test]
fn unknown_resources_and_outputs_in_a_change_are_errors() {
    for (text, parts) in [
        (
            r#"remove_resources: ["nope"]"#,
            &["remove_resources", "'nope'"][..],
        ),
        (
            r#"replace_resources: { "nope": Buffer(size: Bytes(4)) }"#,
            &["replace_resources", "'nope'"],
        ),
        (r#"remove_outputs: ["nope"]"#, &["remove_outputs", "'nope'"]),
        (
            r#"resources: { "rays": Buffer(size: Bytes(4)) }"#,
            &[
                "'rays' is already declared (from",
                "base.ron",
                "replace_resources",
            ],
        ),
        (
            r#"passes: [(name: "intersect", pass: "intersect")]"#,
            &["'intersect' already exists (from", "base.ron"],
        ),
        (
            r#"passes: [(name: "late", pass: "intersect", before: "nope")]"#,
            &["'late' goes before 'nope'"],
        ),
        (
            r#"remove_resources: ["rays"]"#,
            &["'rays' is still bound by pass", "base.ron"],
        ),
    ] {
        let s = with_base(&format!(
            "Graph(\n    extends: \"base.ron\",\n    {text},\n)\n"
        ));
        let (_, msg) = compose_error(&s, "graphs/child.ron");
        assert_mentions(&msg, &["child.ron:3"]);
        assert_mentions(&msg, parts);
    }
}

#[test]
fn a_cycle_of_extends_or_includes_is_an_error_that_shows_the_cycle() {
    let s = project(&[
        ("graphs/a.ron", "Graph(extends: \"b.ron\")"),
        ("graphs/b.ron", "Graph(\n  extends: \"a.ron\",\n)"),
    ]);
    let (line, msg) = compose_error(&s, "graphs/a.ron");
    assert_eq!(line, Some(2), "{msg}");
    assert_mentions(
        &msg,
        &["b.ron:2", "cycle", "a.ron -> ", "b.ron -> ", "a.ron"],
    );

    let s = project(&[(
        "graphs/self.ron",
        "Graph(include: [(file: \"self.ron\")], outputs: [])",
    )]);
    let (_, msg) = compose_error(&s, "graphs/self.ron");
    assert_mentions(&msg, &["self.ron:1", "include \"self.ron\" makes a cycle"]);
}

#[test]
fn a_chain_of_20000_extends_or_5000_includes_is_an_error_not_a_stack_overflow() {
    let extends: Vec<(String, String)> = (0..20_000)
        .map(|i| {
            (
                format!("graphs/e{i}.ron"),
                format!("Graph(extends: \"e{}.ron\")", i + 1),
            )
        })
        .collect();
    let includes: Vec<(String, String)> = (0..5_000)
        .map(|i| {
            (
                format!("graphs/i{i}.ron"),
                format!("Graph(include: [(file: \"i{}.ron\")], outputs: [])", i + 1),
            )
        })
        .collect();
    let files: Vec<(&str, &str)> = extends
        .iter()
        .chain(&includes)
        .map(|(n, t)| (n.as_str(), t.as_str()))
        .collect();
    let s = project(&files);
    let (_, msg) = compose_error(&s, "graphs/e0.ron");
    assert_mentions(
        &msg,
        &[
            "e63.ron:1",
            "extends \"e64.ron\"",
            "more than 64 deep",
            "e0.ron",
        ],
    );
    let (_, msg) = compose_error(&s, "graphs/i0.ron");
    assert_mentions(
        &msg,
        &["i63.ron:1", "include \"i64.ron\"", "more than 64 deep"],
    );
}

#[test]
fn a_missing_base_names_the_file_that_extends_it() {
    let s = with_base("Graph(\n  extends: \"bsae.ron\",\n)");
    let (line, msg) = compose_error(&s, "graphs/child.ron");
    assert_eq!(line, Some(2));
    assert_mentions(&msg, &["child.ron:2", "bsae.ron", "no such graph file"]);
}

#[test]
fn a_compile_error_names_the_file_that_introduced_the_bad_element() {
    // A binding added by the child: the child is named, not the base.
    let s = with_base(
        "Graph(extends: \"base.ron\", passes: [(name: \"extra\", pass: \"intersect\", bind: {
            \"camera\": \"camera\", \"triangles\": \"scene.triangles\", \"bvh\": \"scene.bvh\",
            \"rays\": \"rayz\", \"seeds\": \"seeds\" })])",
    );
    let (e, msg) = s.error("graphs/child.ron");
    assert!(matches!(e, GraphError::UnknownResource { .. }), "{msg}");
    assert_mentions(&msg, &["child.ron", "'extra'", "'rayz'"]);
    // A param set by the child on a base pass, of the wrong type: the child is named.
    let s = with_base(
        "Graph(extends: \"base.ron\", params: { \"ambient\": { \"ambient_color\": F32(1.0) } })",
    );
    let (e, msg) = s.error("graphs/child.ron");
    assert!(matches!(e, GraphError::ParamType { .. }), "{msg}");
    assert_mentions(&msg, &["child.ron", "'ambient'", "'ambient_color'"]);
    // A bad binding in the base: the base is named even when compiling the child.
    let s = with_base("Graph(extends: \"base.ron\")");
    s.edit(
        BASE,
        r#""rays": "rays", "seeds": "seeds", "l0""#,
        r#""rays": "rayz", "seeds": "seeds", "l0""#,
    );
    let (_, msg) = s.error("graphs/child.ron");
    assert_mentions(&msg, &["base.ron", "'rayz'"]);
    assert!(!msg.contains("child.ron"), "{msg}");
}

#[test]
fn a_subgraph_needs_its_inputs_bound_and_cannot_run_alone() {
    let denoiser = root().join("graphs/denoiser.ron");
    let (e, msg) = match passgraph::compile_file(&denoiser, [16, 16]) {
        Ok(_) => panic!("a subgraph compiled alone"),
        Err(e) => {
            let m = e.to_string();
            (e, m)
        }
    };
    assert!(matches!(e, GraphError::Subgraph { .. }), "{msg}");
    assert_mentions(&msg, &["denoiser.ron", "'result'", "'rays'", "include"]);

    let s = Scratch::new();
    s.write(
        "graphs/sub.ron",
        "Graph(inputs: [\"src\"], resources: { \"tmp\": Buffer(size: Bytes(4)) }, passes: [], outputs: [\"tmp\"])",
    );
    for (include, parts) in [
        ("(file: \"sub.ron\")", &["input 'src' is not bound"][..]),
        (
            "(file: \"sub.ron\", inputs: { \"src\": \"nope\" })",
            &["'src' -> 'nope'", "neither a resource"],
        ),
        (
            "(file: \"sub.ron\", inputs: { \"src\": \"rays\", \"x\": \"rays\" })",
            &["no input 'x'"],
        ),
        (
            "(file: \"sub.ron\", inputs: { \"src\": \"rays\" }, outputs: { \"y\": \"z\" })",
            &["no output 'y'"],
        ),
        (
            "(file: \"sub.ron\", prefix: \"a.b\", inputs: { \"src\": \"rays\" })",
            &["prefix 'a.b'"],
        ),
    ] {
        s.write(
            "graphs/child.ron",
            &format!("Graph(\n  extends: \"base.ron\",\n  include: [{include}],\n)"),
        );
        s.write(
            BASE,
            &std::fs::read_to_string(common::fixtures().join("graphs/seed.ron")).unwrap(),
        );
        let (line, msg) = compose_error(&s, "graphs/child.ron");
        assert_eq!(line, Some(3), "{msg}");
        assert_mentions(&msg, &["child.ron:3", "include \"sub.ron\""]);
        assert_mentions(&msg, parts);
    }
}

#[test]
fn an_included_subgraph_keeps_its_names_apart_under_its_prefix() {
    let s = Scratch::new();
    s.write(
        "graphs/sub.ron",
        std::fs::read_to_string(root().join("graphs/denoiser.ron"))
            .unwrap()
            .as_str(),
    );
    // Two copies of one subgraph side by side: the prefixes keep them apart.
    s.write(
        "graphs/two.ron",
        "Graph(extends: \"seed.ron\", include: [
            (file: \"sub.ron\", prefix: \"one\", inputs: { \"result\": \"result\", \"rays\": \"rays\" }),
            (file: \"sub.ron\", prefix: \"two\", inputs: { \"result\": \"result\", \"rays\": \"rays\" }),
        ])",
    );
    let flat = flatten(&s.path("graphs/two.ron")).unwrap();
    for prefix in ["one", "two"] {
        assert!(
            flat.decl
                .resources
                .contains_key(&format!("{prefix}/denoised"))
        );
        assert!(flat.decl.outputs.contains(&format!("{prefix}/denoised")));
        let remodulate = flat
            .decl
            .passes
            .iter()
            .find(|p| p.name == format!("{prefix}/remodulate"))
            .unwrap();
        assert_eq!(remodulate.bind["result"], "result");
        assert_eq!(remodulate.bind["out"], format!("{prefix}/denoised"));
        assert_eq!(remodulate.bind["filtered"], format!("{prefix}/atrous_b"));
        assert_eq!(
            flat.origins.passes[&format!("{prefix}/remodulate")].file,
            s.path("graphs/sub.ron")
        );
    }
    assert_eq!(flat.files.len(), 4, "{:?}", flat.files);
}
