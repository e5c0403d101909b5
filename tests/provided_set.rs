//! The compiler takes its provided resources from the application: a mock application (a
//! mesh viewer, no GPU) registers its own names, and the path tracer's mean nothing to it.

mod common;

use common::assert_mentions;
use passgraph::GraphError;
use passgraph::graph::compile::compile_file;
use passgraph::graph::param::ParamType;
use passgraph::graph::plan::ResourceKind;
use passgraph::graph::provided::{ProvidedKind, ProvidedSet};
use std::path::PathBuf;

/// A pass that reads the viewer's `mesh`, `clock` and `mesh_count` into its own output.
const SHADER: &str = "override mesh_count: u32;
@group(0) @binding(0) var<storage, read> mesh: array<vec4<f32>>;
@group(0) @binding(1) var<uniform> clock: vec4<f32>;
@group(0) @binding(2) var dst: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    textureStore(dst, vec2<i32>(id.xy), mesh[id.x % mesh_count] * clock.x);
}
";

fn viewer() -> ProvidedSet {
    ProvidedSet::new()
        .resource("mesh", ProvidedKind::StorageBuffer, "vertex positions")
        .resource("clock", ProvidedKind::Uniform, "seconds since start")
        .override_constant("mesh_count", ParamType::U32, "number of vertices")
}

struct Project {
    dir: tempfile::TempDir,
}

impl Project {
    /// A graph binding `mesh` and `clock` (or `mesh_as` in their place) plus `extra_resources`.
    fn new(mesh_as: &str, extra_resources: &str) -> Project {
        let dir = tempfile::tempdir().unwrap();
        let write = |rel: &str, text: &str| {
            let path = dir.path().join(rel);
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(path, text).unwrap();
        };
        write("shaders/scale.wgsl", SHADER);
        write("passes/scale.ron", "Pass(shader: \"scale.wgsl\")");
        write(
            "graphs/viewer.ron",
            &format!(
                "Graph(
    resources: {{ \"out\": Texture(format: Rgba32Float), {extra_resources} }},
    passes: [
        (name: \"scale\", pass: \"scale\", bind: {{ \"mesh\": \"{mesh_as}\", \"clock\": \"clock\", \"dst\": \"out\" }}),
    ],
    outputs: [\"out\"],
)"
            ),
        );
        Project { dir }
    }

    fn graph(&self) -> PathBuf {
        self.dir.path().join("graphs/viewer.ron")
    }

    fn error(&self, provided: &ProvidedSet) -> String {
        match compile_file(&self.graph(), [16, 16], provided) {
            Ok(_) => panic!("the graph should not compile"),
            Err(e) => e.to_string(),
        }
    }
}

#[test]
fn an_application_compiles_a_graph_that_binds_its_own_provided_names() {
    let plan = compile_file(&Project::new("mesh", "").graph(), [16, 16], &viewer())
        .unwrap_or_else(|e| panic!("{e}"));
    let kind = |name: &str| {
        plan.resources
            .iter()
            .find(|r| r.name == name)
            .map(|r| r.kind.clone())
    };
    assert_eq!(
        kind("mesh"),
        Some(ResourceKind::Provided(ProvidedKind::StorageBuffer))
    );
    assert_eq!(
        kind("clock"),
        Some(ResourceKind::Provided(ProvidedKind::Uniform))
    );
    // Nothing the path tracer provides is in this application's plan.
    assert_eq!(kind("camera"), None);
    let pass = plan.pass("scale").unwrap();
    assert_eq!(pass.provided_overrides, vec!["mesh_count".to_string()]);
    assert!(pass.overrides.is_empty());
}

#[test]
fn a_name_the_application_does_not_register_is_an_unknown_resource() {
    let project = Project::new("camera", "");
    let msg = project.error(&viewer());
    assert_mentions(&msg, &["'camera'", "neither declared", "nor provided"]);
    let without_mesh = ProvidedSet::new()
        .resource("clock", ProvidedKind::Uniform, "")
        .override_constant("mesh_count", ParamType::U32, "");
    let msg = Project::new("mesh", "").error(&without_mesh);
    assert_mentions(&msg, &["'mesh'", "nor provided"]);
}

#[test]
fn the_path_tracers_set_does_not_provide_the_viewers_names() {
    // The first of them the compiler meets is the override, checked with the pass's params.
    let err = passgraph::compile_file(&Project::new("mesh", "").graph(), [16, 16]).unwrap_err();
    assert!(
        matches!(err, GraphError::OverrideWithoutValue { .. }),
        "{err}"
    );
    assert_mentions(&err.to_string(), &["mesh_count"]);
}

#[test]
fn an_override_the_application_sets_needs_no_param_but_one_it_does_not_does() {
    let msg = Project::new("mesh", "").error(
        &ProvidedSet::new()
            .resource("mesh", ProvidedKind::StorageBuffer, "")
            .resource("clock", ProvidedKind::Uniform, ""),
    );
    assert_mentions(&msg, &["mesh_count"]);
}

#[test]
fn declaring_a_provided_name_is_an_error() {
    let msg = Project::new("mesh", "\"clock\": Buffer(size: Bytes(16)),").error(&viewer());
    assert_mentions(
        &msg,
        &[
            "'clock'",
            "provided by the framework",
            "without declaring it",
        ],
    );
}

#[test]
fn an_include_input_may_be_bound_to_a_name_the_application_provides() {
    let project = Project::new("mesh", "");
    let write = |rel: &str, text: &str| std::fs::write(project.dir.path().join(rel), text).unwrap();
    write(
        "graphs/scaler.ron",
        "Graph(
    inputs: [\"vertices\"],
    resources: { \"scaled\": Texture(format: Rgba32Float) },
    passes: [
        (name: \"scale\", pass: \"scale\", bind: { \"mesh\": \"vertices\", \"clock\": \"clock\", \"dst\": \"scaled\" }),
    ],
    outputs: [\"scaled\"],
)",
    );
    write(
        "graphs/top.ron",
        "Graph(
    include: [(file: \"scaler.ron\", inputs: { \"vertices\": \"mesh\" }, outputs: { \"scaled\": \"scaled\" })],
)",
    );
    let top = project.dir.path().join("graphs/top.ron");
    let plan = compile_file(&top, [16, 16], &viewer()).unwrap_or_else(|e| panic!("{e}"));
    assert!(plan.pass("scaler/scale").is_some());
    let err = compile_file(&top, [16, 16], &ProvidedSet::new()).unwrap_err();
    assert!(matches!(err, GraphError::Compose { .. }), "{err}");
    assert_mentions(
        &err.to_string(),
        &[
            "top.ron:2",
            "'vertices' -> 'mesh'",
            "neither a resource of this graph nor provided",
        ],
    );
}

/// The viewer's graph with the instance's `bind` given whole.
fn graph_binding(project: &Project, bind: &str, extra_resources: &str) -> PathBuf {
    let path = project.dir.path().join("graphs/by_name.ron");
    std::fs::write(
        &path,
        format!(
            "Graph(
    resources: {{ \"out\": Texture(format: Rgba32Float), {extra_resources} }},
    passes: [(name: \"scale\", pass: \"scale\", bind: {{ {bind} }})],
    outputs: [\"out\"],
)"
        ),
    )
    .unwrap();
    path
}

#[test]
fn a_variable_the_application_binds_by_name_needs_no_bind_entry_and_an_instance_entry_wins() {
    let project = Project::new("mesh", "");
    let by_name = viewer()
        .bind_by_name("mesh", "mesh")
        .bind_by_name("clock", "clock");
    let resource_of = |plan: &passgraph::graph::plan::Plan, binding: &str| {
        let pass = plan.pass("scale").unwrap();
        let b = pass.bindings.iter().find(|b| b.name == binding).unwrap();
        plan.resources[b.resource].name.clone()
    };
    let plan = compile_file(
        &graph_binding(&project, "\"dst\": \"out\"", ""),
        [16, 16],
        &by_name,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(resource_of(&plan, "mesh"), "mesh");
    assert_eq!(resource_of(&plan, "clock"), "clock");

    // The instance's own entry binds the variable to one of the graph's buffers instead.
    let plan = compile_file(
        &graph_binding(
            &project,
            "\"dst\": \"out\", \"mesh\": \"my_mesh\"",
            "\"my_mesh\": Buffer(size: Bytes(64), persistent: true),",
        ),
        [16, 16],
        &by_name,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(resource_of(&plan, "mesh"), "my_mesh");
    assert_eq!(resource_of(&plan, "clock"), "clock");

    // Without bind_by_name the same graph leaves `mesh` unbound, and the error says so.
    let err = compile_file(
        &graph_binding(&project, "\"dst\": \"out\"", ""),
        [16, 16],
        &viewer(),
    )
    .unwrap_err();
    assert!(matches!(err, GraphError::Unbound { .. }), "{err}");
    assert_mentions(&err.to_string(), &["'mesh'", "unbound", "by_name.ron"]);
}
