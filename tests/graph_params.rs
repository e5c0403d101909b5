//! Params written once: an `override`'s default lives in its WGSL (the pass file need not repeat
//! it, yet instances set it), a graph-level `shared_params` value reaches every instance whose
//! pass has the param, and `--set PARAM=VALUE` sets it on each of them.

mod common;

use common::{assert_mentions, root};
use passgraph::graph::param::ParamValue;
use passgraph::graph::set_param::set_param;
use passgraph::render::provided::path_tracer;
use passgraph::{GraphError, Plan, compile, compile_file, load_graph};
use std::path::PathBuf;

/// A graph file in a scratch folder that extends a shipped graph with `changes`.
fn variant(dir: &tempfile::TempDir, base: &str, changes: &str) -> PathBuf {
    let path = dir.path().join("variant.ron");
    let base = root().join("graphs").join(base);
    std::fs::write(
        &path,
        format!(
            "Graph(extends: {:?}, {changes})",
            base.display().to_string()
        ),
    )
    .unwrap();
    path
}

fn param(plan: &Plan, pass: &str, name: &str) -> Option<ParamValue> {
    plan.pass(pass)
        .unwrap_or_else(|| panic!("no pass {pass}"))
        .params
        .get(name)
        .cloned()
}

#[test]
fn an_overrides_wgsl_default_is_a_param_the_pass_file_need_not_list() {
    // passes/intersect.ron lists no params; shaders/lib/sampler.wgsl declares
    // `override sampler_kind: u32 = 1u;`.
    let text = std::fs::read_to_string(root().join("passes/intersect.ron")).unwrap();
    assert!(!text.contains("\"sampler_kind\": U32"), "{text}");
    let plan = compile_file(&root().join("graphs/pathtracer.ron"), [16, 16]).unwrap();
    assert_eq!(
        param(&plan, "intersect", "sampler_kind"),
        Some(ParamValue::U32(1))
    );
    assert!(
        plan.pass("intersect")
            .unwrap()
            .overrides
            .contains(&("sampler_kind".to_string(), 1.0))
    );

    let dir = tempfile::tempdir().unwrap();
    let set = variant(
        &dir,
        "pathtracer.ron",
        r#"params: { "intersect": { "sampler_kind": U32(0) } }"#,
    );
    let plan = compile_file(&set, [16, 16]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        param(&plan, "intersect", "sampler_kind"),
        Some(ParamValue::U32(0))
    );
    assert_eq!(
        param(&plan, "direct", "sampler_kind"),
        Some(ParamValue::U32(1))
    );

    // The pass file's range still holds a param whose default is in the WGSL.
    let out = variant(
        &dir,
        "pathtracer.ron",
        r#"params: { "intersect": { "sampler_kind": U32(7) } }"#,
    );
    let e = compile_file(&out, [16, 16]).unwrap_err();
    assert!(matches!(e, GraphError::ParamOutOfRange { .. }), "{e}");

    // What the application sets is not a param an instance may set.
    let provided = variant(
        &dir,
        "pathtracer.ron",
        r#"params: { "intersect": { "scene_max_depth": U32(4) } }"#,
    );
    let e = compile_file(&provided, [16, 16]).unwrap_err();
    assert!(matches!(e, GraphError::UnknownParam { .. }), "{e}");
    assert_mentions(&e.to_string(), &["scene_max_depth", "sampler_kind"]);
}

#[test]
fn a_shared_param_reaches_every_pass_that_has_it_and_an_instances_own_value_wins() {
    let dir = tempfile::tempdir().unwrap();
    let path = variant(
        &dir,
        "pathtracer.ron",
        r#"shared_params: { "sampler_kind": U32(0), "light_selection": Bool(true) },
           params: { "direct": { "sampler_kind": U32(1) } }"#,
    );
    let plan = compile_file(&path, [16, 16]).unwrap_or_else(|e| panic!("{e}"));
    for pass in ["intersect", "ambient", "indirect"] {
        assert_eq!(
            param(&plan, pass, "sampler_kind"),
            Some(ParamValue::U32(0)),
            "{pass}"
        );
    }
    assert_eq!(
        param(&plan, "direct", "sampler_kind"),
        Some(ParamValue::U32(1))
    );
    for pass in ["direct", "indirect"] {
        assert_eq!(
            param(&plan, pass, "light_selection"),
            Some(ParamValue::Bool(true))
        );
    }
    // Passes without the param are left alone.
    assert_eq!(param(&plan, "accumulate", "sampler_kind"), None);
    assert_eq!(param(&plan, "intersect", "light_selection"), None);
    // The plan names the file that set a shared value.
    assert_mentions(&plan.to_string(), &["sampler_kind from", "variant.ron"]);

    // A graph extending this one inherits its shared params and may change them.
    let child = dir.path().join("child.ron");
    std::fs::write(
        &child,
        r#"Graph(extends: "variant.ron", shared_params: { "sampler_kind": U32(1) })"#,
    )
    .unwrap();
    let plan = compile_file(&child, [16, 16]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        param(&plan, "ambient", "sampler_kind"),
        Some(ParamValue::U32(1))
    );
    assert_eq!(
        param(&plan, "indirect", "light_selection"),
        Some(ParamValue::Bool(true))
    );
}

#[test]
fn a_shared_param_no_pass_has_or_of_the_wrong_type_or_out_of_range_is_an_error_naming_its_file() {
    let dir = tempfile::tempdir().unwrap();
    let typo = variant(
        &dir,
        "pathtracer.ron",
        r#"shared_params: { "sampler_knd": U32(0) }"#,
    );
    let e = compile_file(&typo, [16, 16]).unwrap_err();
    assert!(matches!(e, GraphError::UnusedSharedParam { .. }), "{e}");
    assert_mentions(
        &e.to_string(),
        &["variant.ron", "'sampler_knd'", "intersect"],
    );

    let wrong = variant(
        &dir,
        "pathtracer.ron",
        r#"shared_params: { "sampler_kind": F32(0.0) }"#,
    );
    let e = compile_file(&wrong, [16, 16]).unwrap_err();
    assert!(matches!(e, GraphError::ParamType { .. }), "{e}");
    assert_mentions(&e.to_string(), &["variant.ron", "sampler_kind", "u32"]);

    let out = variant(
        &dir,
        "pathtracer.ron",
        r#"shared_params: { "sampler_kind": U32(2) }"#,
    );
    let e = compile_file(&out, [16, 16]).unwrap_err();
    assert!(matches!(e, GraphError::ParamOutOfRange { .. }), "{e}");
    assert_mentions(&e.to_string(), &["variant.ron", "sampler_kind"]);
}

#[test]
fn a_subgraph_may_not_set_shared_params_nor_be_included_with_them() {
    let dir = tempfile::tempdir().unwrap();
    let sub = dir.path().join("sub.ron");
    std::fs::write(
        &sub,
        format!(
            r#"Graph(extends: {:?}, shared_params: {{ "sampler_kind": U32(0) }})"#,
            root().join("graphs/denoiser.ron").display().to_string()
        ),
    )
    .unwrap();
    let e = load_graph(&sub).unwrap_err();
    assert_mentions(
        &e.to_string(),
        &["sub.ron", "shared_params", "sampler_kind"],
    );

    // A whole graph with shared params, included: its passes would not take them.
    let whole = variant(
        &dir,
        "pathtracer.ron",
        r#"shared_params: { "sampler_kind": U32(0) }"#,
    );
    let includer = dir.path().join("includer.ron");
    std::fs::write(
        &includer,
        format!(
            r#"Graph(extends: {:?}, include: [(file: {:?}, prefix: "other")])"#,
            root().join("graphs/pathtracer.ron").display().to_string(),
            whole.display().to_string()
        ),
    )
    .unwrap();
    let e = load_graph(&includer).unwrap_err();
    assert_mentions(
        &e.to_string(),
        &["includer.ron", "shared_params", "sampler_kind"],
    );
}

#[test]
fn set_without_an_instance_sets_the_param_on_every_pass_that_has_it() {
    let mut graph = load_graph(&root().join("graphs/pathtracer.ron")).unwrap();
    set_param(&mut graph, "sample_index_restarts=false", path_tracer()).unwrap();
    let plan = compile(&graph, [16, 16]).unwrap();
    for pass in ["intersect", "ambient", "direct", "indirect"] {
        assert_eq!(
            param(&plan, pass, "sample_index_restarts"),
            Some(ParamValue::Bool(false)),
            "{pass}"
        );
    }
    let e = set_param(&mut graph, "no_such_param=1", path_tracer()).unwrap_err();
    assert_mentions(
        &e.to_string(),
        &["no pass of the graph has a param 'no_such_param'"],
    );
    let e = set_param(&mut graph, "sampler_kind=5", path_tracer()).unwrap_err();
    assert_mentions(&e.to_string(), &["outside the param's range"]);
    // An instance's param the WGSL declares is settable one by one too.
    set_param(&mut graph, "direct.mis_strategy=2", path_tracer()).unwrap();
    let plan = compile(&graph, [16, 16]).unwrap();
    assert_eq!(
        param(&plan, "direct", "mis_strategy"),
        Some(ParamValue::U32(2))
    );
    assert_eq!(
        param(&plan, "indirect", "mis_strategy"),
        Some(ParamValue::U32(0))
    );
}
