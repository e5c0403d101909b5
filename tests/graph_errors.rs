//! Every way a graph can be wrong gets a typed error whose message names the file, the pass and
//! the binding at fault. Each test breaks one thing in a private copy of the seed fixture.

mod common;

use common::{Scratch, assert_mentions};
use passgraph::GraphError;

const SEED: &str = "graphs/seed.ron";

#[test]
fn ron_syntax_error_reports_file_line_and_column() {
    let s = Scratch::new();
    s.edit(
        SEED,
        r#""rays": Texture(format: Rgba32Float, size: Output, layers: 3),"#,
        r#""rays": Texture(format: Rgba32Float, size: Output, layers: 3)"#,
    );
    let (e, msg) = s.error(SEED);
    let GraphError::Ron { line, col, .. } = e else {
        panic!("{msg}")
    };
    assert_eq!(line, 5, "{msg}");
    assert!(col > 1, "{msg}");
    assert_mentions(&msg, &["seed.ron:5:"]);
}

#[test]
fn misspelt_field_is_a_ron_error_with_its_position() {
    let s = Scratch::new();
    s.edit(SEED, "layers: 3", "layer: 3");
    let (e, msg) = s.error(SEED);
    assert!(matches!(e, GraphError::Ron { line: 4, .. }), "{msg}");
    assert_mentions(&msg, &["layer"]);
}

#[test]
fn unknown_pass_names_the_instance_and_where_it_looked() {
    let s = Scratch::new();
    s.edit(SEED, r#"pass: "indirect""#, r#"pass: "indirekt""#);
    let (e, msg) = s.error(SEED);
    assert!(matches!(e, GraphError::UnknownPass { .. }), "{msg}");
    assert_mentions(
        &msg,
        &[
            "seed.ron",
            "pass 'indirect'",
            "'indirekt'",
            "passes/indirekt.ron",
        ],
    );
}

#[test]
fn unknown_resource_names_pass_binding_and_resource() {
    let s = Scratch::new();
    s.edit(SEED, r#""out": "indirect""#, r#""out": "indirekt""#);
    let (e, msg) = s.error(SEED);
    assert!(matches!(e, GraphError::UnknownResource { .. }), "{msg}");
    assert_mentions(
        &msg,
        &["seed.ron", "pass 'indirect'", "'out'", "'indirekt'"],
    );
}

#[test]
fn unknown_param_names_the_pass_file_and_lists_params() {
    let s = Scratch::new();
    s.edit(
        SEED,
        r#"params: { "ambient_color""#,
        r#"params: { "ambient_colour""#,
    );
    let (e, msg) = s.error(SEED);
    assert!(matches!(e, GraphError::UnknownParam { .. }), "{msg}");
    assert_mentions(
        &msg,
        &[
            "seed.ron",
            "pass 'ambient'",
            "'ambient_colour'",
            "ambient.ron",
            "'ambient_color'",
        ],
    );
}

#[test]
fn param_of_the_wrong_type_says_what_was_expected() {
    let s = Scratch::new();
    s.edit(SEED, "Vec3(0.1, 0.1, 0.1)", "F32(0.1)");
    let (e, msg) = s.error(SEED);
    assert!(matches!(e, GraphError::ParamType { .. }), "{msg}");
    assert_mentions(
        &msg,
        &[
            "seed.ron",
            "pass 'ambient'",
            "'ambient_color'",
            "F32",
            "Vec3",
        ],
    );
}

#[test]
fn pass_default_of_the_wrong_type_for_the_shader_is_an_error() {
    let s = Scratch::new();
    s.edit(
        "passes/ambient.ron",
        r#""radius": F32(1e30)"#,
        r#""radius": U32(7)"#,
    );
    let (e, msg) = s.error(SEED);
    assert!(matches!(e, GraphError::ParamType { .. }), "{msg}");
    assert_mentions(
        &msg,
        &["ambient.ron", "'radius'", "U32", "F32", "ambient.wgsl"],
    );
}

#[test]
fn shader_binding_left_unbound_names_it_and_its_kind() {
    let s = Scratch::new();
    s.edit(
        SEED,
        r#""rays": "rays", "seeds": "seeds",
        }),"#,
        r#""seeds": "seeds",
        }),"#,
    );
    let (e, msg) = s.error(SEED);
    assert!(matches!(e, GraphError::Unbound { .. }), "{msg}");
    assert_mentions(
        &msg,
        &[
            "seed.ron",
            "pass 'intersect'",
            "'rays'",
            "texture_storage_2d_array<rgba32float, write>",
            "intersect.wgsl",
        ],
    );
}

#[test]
fn bound_name_the_shader_lacks_lists_the_real_bindings() {
    let s = Scratch::new();
    s.edit(
        SEED,
        r#""ambient": "ambient", "result": "result","#,
        r#""ambient": "ambient", "result": "result", "history": "result","#,
    );
    let (e, msg) = s.error(SEED);
    assert!(matches!(e, GraphError::NoSuchBinding { .. }), "{msg}");
    assert_mentions(
        &msg,
        &[
            "seed.ron",
            "pass 'accumulate'",
            "'history'",
            "accumulate.wgsl",
            "'frame'",
        ],
    );
}

#[test]
fn storage_format_mismatch_names_both_formats() {
    let s = Scratch::new();
    s.edit(
        SEED,
        r#""seeds": Texture(format: R32Uint"#,
        r#""seeds": Texture(format: R32Float"#,
    );
    let (e, msg) = s.error(SEED);
    assert!(matches!(e, GraphError::BindingMismatch { .. }), "{msg}");
    assert_mentions(
        &msg,
        &[
            "seed.ron",
            "pass 'intersect'",
            "'seeds'",
            "r32uint",
            "r32float",
        ],
    );
}

#[test]
fn layered_texture_bound_to_a_2d_binding_is_a_dimension_error() {
    let s = Scratch::new();
    s.edit(
        SEED,
        r#""l0": "l0", "out": "direct""#,
        r#""l0": "rays", "out": "direct""#,
    );
    let (e, msg) = s.error(SEED);
    assert!(matches!(e, GraphError::BindingMismatch { .. }), "{msg}");
    assert_mentions(
        &msg,
        &["pass 'direct'", "'l0'", "'rays'", "3 layers", "2d_array"],
    );
}

#[test]
fn buffer_bound_to_a_texture_binding_is_a_kind_error() {
    let s = Scratch::new();
    s.edit(
        SEED,
        r#""l0": "l0", "out": "direct""#,
        r#""l0": "result", "out": "direct""#,
    );
    let (_, msg) = s.error(SEED);
    assert_mentions(&msg, &["pass 'direct'", "'l0'", "'result'", "is a buffer"]);
}

#[test]
fn buffer_smaller_than_the_shader_needs_is_an_error() {
    let s = Scratch::new();
    s.edit(
        SEED,
        "Buffer(size: PerPixel(80), persistent: true)",
        "Buffer(size: Bytes(8), persistent: true)",
    );
    let (_, msg) = s.error(SEED);
    assert_mentions(
        &msg,
        &["pass 'accumulate'", "'result'", "8 bytes", "at least 16"],
    );
}

#[test]
fn integer_texture_read_as_float_is_a_sample_type_error() {
    let s = Scratch::new();
    s.edit(
        SEED,
        r#""frame": "frame", "l0": "l0""#,
        r#""frame": "frame", "l0": "seeds""#,
    );
    let (_, msg) = s.error(SEED);
    assert_mentions(
        &msg,
        &["pass 'accumulate'", "'l0'", "'seeds'", "r32uint", "u32"],
    );
}

#[test]
fn writing_a_provided_resource_is_an_error() {
    let s = Scratch::new();
    s.edit(
        "shaders/intersect.wgsl",
        "var<storage, read> bvh",
        "var<storage, read_write> bvh",
    );
    let (_, msg) = s.error(SEED);
    assert_mentions(
        &msg,
        &["pass 'intersect'", "'bvh'", "'scene.bvh'", "read-only"],
    );
}

#[test]
fn declaring_a_provided_name_is_an_error() {
    let s = Scratch::new();
    s.edit(
        SEED,
        r#""l0": Texture(format: Rgba32Float),"#,
        r#""l0": Texture(format: Rgba32Float), "camera": Buffer(size: Bytes(64)),"#,
    );
    let (e, msg) = s.error(SEED);
    assert!(matches!(e, GraphError::InvalidResource { .. }), "{msg}");
    assert_mentions(&msg, &["'camera'", "provided by the framework"]);
}

#[test]
fn one_resource_written_through_two_bindings_is_a_conflict() {
    let s = Scratch::new();
    s.edit(
        SEED,
        r#""l0": "l0", "out": "direct""#,
        r#""l0": "direct", "out": "direct""#,
    );
    let (e, msg) = s.error(SEED);
    assert!(matches!(e, GraphError::ConflictingUsage { .. }), "{msg}");
    assert_mentions(&msg, &["pass 'direct'", "'direct'", "'l0'", "'out'"]);
}

#[test]
fn transient_read_before_any_write_suggests_persistence() {
    let s = Scratch::new();
    s.edit(
        SEED,
        r#""seeds": Texture(format: R32Uint, size: Output, persistent: true)"#,
        r#""seeds": Texture(format: R32Uint, size: Output)"#,
    );
    let (e, msg) = s.error(SEED);
    assert!(
        matches!(
            e,
            GraphError::ReadBeforeWrite {
                later_writer: None,
                ..
            }
        ),
        "{msg}"
    );
    assert_mentions(
        &msg,
        &[
            "seed.ron",
            "pass 'intersect'",
            "'seeds'",
            "persistent: true",
        ],
    );
}

#[test]
fn reader_listed_before_its_writer_is_told_to_reorder() {
    let s = Scratch::new();
    s.write(
        "graphs/order.ron",
        r#"Graph(
        resources: { "a": Texture(format: Rgba16Float), "out": Texture(format: Rgba16Float) },
        passes: [
            (name: "consume", pass: "copy", bind: { "src": "a", "dst": "out" }),
            (name: "produce", pass: "fill", bind: { "dst": "a" }),
        ],
        outputs: ["out"],
    )"#,
    );
    let (e, msg) = s.error("graphs/order.ron");
    assert!(matches!(e, GraphError::ReadBeforeWrite { .. }), "{msg}");
    assert_mentions(
        &msg,
        &[
            "pass 'consume'",
            "'a'",
            "'src'",
            "'produce' writes it later",
            "list 'produce' before 'consume'",
        ],
    );
}

#[test]
fn mutual_data_dependence_reports_the_cycle_in_order() {
    let s = Scratch::new();
    s.write(
        "graphs/cycle.ron",
        r#"Graph(
        resources: {
            "x": Texture(format: Rgba16Float), "y": Texture(format: Rgba16Float),
            "z": Texture(format: Rgba16Float),
        },
        passes: [
            (name: "a", pass: "copy", bind: { "src": "x", "dst": "y" }),
            (name: "b", pass: "copy", bind: { "src": "y", "dst": "z" }),
            (name: "c", pass: "copy", bind: { "src": "z", "dst": "x" }),
        ],
        outputs: ["x"],
    )"#,
    );
    let (e, msg) = s.error("graphs/cycle.ron");
    let GraphError::Cycle { passes, via, .. } = e else {
        panic!("{msg}")
    };
    assert_eq!(passes, ["a", "b", "c"]);
    assert_eq!(via, ["y", "z", "x"]);
    assert_mentions(
        &msg,
        &[
            "cycle.ron",
            "cycle detected: 'a' -[y]-> 'b' -[z]-> 'c' -[x]-> 'a'",
        ],
    );
}

#[test]
fn output_nobody_writes_is_an_error() {
    let s = Scratch::new();
    s.edit(SEED, r#""l0": Texture(format: Rgba32Float),"#,
        r#""l0": Texture(format: Rgba32Float), "spare": Texture(format: Rgba32Float, persistent: true),"#);
    s.edit(
        SEED,
        r#"outputs: ["result"]"#,
        r#"outputs: ["result", "spare"]"#,
    );
    let (e, msg) = s.error(SEED);
    assert!(matches!(e, GraphError::OutputNotWritten { .. }), "{msg}");
    assert_mentions(&msg, &["seed.ron", "no pass writes output 'spare'"]);
}

#[test]
fn output_that_is_not_a_resource_is_an_error() {
    let s = Scratch::new();
    s.edit(SEED, r#"outputs: ["result"]"#, r#"outputs: ["reslut"]"#);
    let (e, msg) = s.error(SEED);
    assert!(matches!(e, GraphError::UnknownOutput { .. }), "{msg}");
    assert_mentions(&msg, &["'reslut'", "'result'"]);
}

#[test]
fn duplicate_pass_names_are_rejected() {
    let s = Scratch::new();
    s.edit(SEED, r#"(name: "indirect""#, r#"(name: "direct""#);
    let (e, msg) = s.error(SEED);
    assert!(matches!(e, GraphError::DuplicatePassName { .. }), "{msg}");
    assert_mentions(&msg, &["seed.ron", "'direct'"]);
}

#[test]
fn missing_shader_file_names_the_pass_file_and_the_path() {
    let s = Scratch::new();
    s.edit("passes/direct.ron", "direct.wgsl", "direkt.wgsl");
    let (e, msg) = s.error(SEED);
    assert!(matches!(e, GraphError::MissingShader { .. }), "{msg}");
    assert_mentions(&msg, &["passes/direct.ron", "shaders/direkt.wgsl"]);
}

#[test]
fn missing_graph_file_is_an_io_error_naming_it() {
    let s = Scratch::new();
    let (e, msg) = s.error("graphs/nope.ron");
    assert!(matches!(e, GraphError::Io { .. }), "{msg}");
    assert_mentions(&msg, &["graphs/nope.ron"]);
}

#[test]
fn wgsl_parse_error_in_a_library_file_points_into_that_file() {
    let s = Scratch::new();
    s.edit(
        "shaders/lib/common.wgsl",
        "    let s = state * 747796405u + 2891336453u;",
        "    let s = state * 747796405u + ;",
    );
    let (e, msg) = s.error(SEED);
    let GraphError::Wgsl { file, line, .. } = e else {
        panic!("{msg}")
    };
    assert!(file.ends_with("shaders/lib/common.wgsl"), "{msg}");
    assert_eq!(line, 18, "{msg}");
}

#[test]
fn wgsl_parse_error_after_an_include_keeps_the_main_file_line() {
    let s = Scratch::new();
    s.edit(
        "shaders/direct.wgsl",
        "    let hit = textureLoad(rays, p, 2);",
        "    let hit = textureLoad(rays, p, 2)",
    );
    let (e, msg) = s.error(SEED);
    let GraphError::Wgsl { file, line, .. } = e else {
        panic!("{msg}")
    };
    assert!(file.ends_with("shaders/direct.wgsl"), "{msg}");
    // The missing semicolon is reported where the next statement starts.
    assert!(line == 16 || line == 17, "{msg}");
}

#[test]
fn wgsl_validation_error_points_at_the_original_line() {
    let s = Scratch::new();
    s.edit("shaders/indirect.wgsl", "    textureStore(out, p, vec4<f32>(light * dir * u, 1.0));",
        "    textureStore(out, p, vec4<f32>(light * dir * u, 1.0));\n    triangles[0] = vec4<f32>(0.0);");
    let (e, msg) = s.error(SEED);
    let GraphError::Wgsl { file, line, .. } = e else {
        panic!("{msg}")
    };
    assert!(file.ends_with("shaders/indirect.wgsl"), "{msg}");
    assert_eq!(line, 19, "{msg}");
}

#[test]
fn missing_include_names_the_including_line() {
    let s = Scratch::new();
    s.edit(
        "shaders/ambient.wgsl",
        "#include \"lib/common.wgsl\"",
        "#include \"lib/comon.wgsl\"",
    );
    let (e, msg) = s.error(SEED);
    let GraphError::Include { line, .. } = e else {
        panic!("{msg}")
    };
    assert_eq!(line, 2);
    assert_mentions(&msg, &["shaders/ambient.wgsl:2", "lib/comon.wgsl"]);
}

#[test]
fn missing_entry_point_lists_the_compute_entry_points() {
    let s = Scratch::new();
    s.edit(
        "passes/direct.ron",
        r#"Pass(shader: "direct.wgsl")"#,
        r#"Pass(shader: "direct.wgsl", entry: "trace")"#,
    );
    let (e, msg) = s.error(SEED);
    assert!(matches!(e, GraphError::NoEntryPoint { .. }), "{msg}");
    assert_mentions(&msg, &["direct.wgsl", "'trace'", "'main'"]);
}

#[test]
fn uniform_field_without_a_declared_param_is_an_error() {
    let s = Scratch::new();
    s.edit("passes/ambient.ron", "        \"radius\": F32(1e30),\n", "");
    let (e, msg) = s.error(SEED);
    assert!(
        matches!(e, GraphError::UndeclaredUniformField { .. }),
        "{msg}"
    );
    assert_mentions(&msg, &["passes/ambient.ron", "'radius'", "ambient.wgsl"]);
}

#[test]
fn declared_param_the_shader_never_uses_is_an_error() {
    let s = Scratch::new();
    s.edit(
        "passes/direct.ron",
        r#"Pass(shader: "direct.wgsl")"#,
        r#"Pass(shader: "direct.wgsl", params: { "gain": F32(2.0) })"#,
    );
    let (e, msg) = s.error(SEED);
    assert!(matches!(e, GraphError::UnusedParam { .. }), "{msg}");
    assert_mentions(&msg, &["passes/direct.ron", "'gain'", "direct.wgsl"]);
}

#[test]
fn override_without_default_or_param_is_an_error() {
    let s = Scratch::new();
    s.edit(
        "shaders/temporal.wgsl",
        "override HISTORY_WEIGHT: f32 = 0.9;",
        "override HISTORY_WEIGHT: f32;\noverride SHARPNESS: f32;",
    );
    s.edit(
        "shaders/temporal.wgsl",
        "HISTORY_WEIGHT));",
        "HISTORY_WEIGHT * SHARPNESS));",
    );
    let (e, msg) = s.error("graphs/history.ron");
    assert!(
        matches!(e, GraphError::OverrideWithoutValue { .. }),
        "{msg}"
    );
    assert_mentions(&msg, &["temporal.wgsl", "SHARPNESS", "passes/temporal.ron"]);
}

#[test]
fn a_pass_files_default_that_disagrees_with_its_overrides_default_is_an_error_naming_both() {
    let s = Scratch::new();
    s.edit(
        "shaders/temporal.wgsl",
        "override HISTORY_WEIGHT: f32 = 0.9;",
        "override HISTORY_WEIGHT: f32 = 0.8;",
    );
    let (e, msg) = s.error("graphs/history.ron");
    assert!(
        matches!(e, GraphError::OverrideDefaultDisagrees { .. }),
        "{msg}"
    );
    assert_mentions(
        &msg,
        &[
            "passes/temporal.ron",
            "'HISTORY_WEIGHT' defaults to F32(0.9)",
            "temporal.wgsl:2",
            "defaults to 0.8",
        ],
    );
}

#[test]
fn invalid_resource_declarations_are_rejected() {
    for (from, to, why) in [
        ("layers: 3", "layers: 0", "layers"),
        (
            "size: Output, layers: 3",
            "size: Absolute(0, 4), layers: 3",
            "zero side",
        ),
        (
            "size: Output, layers: 3",
            "size: Scaled(-1.0), layers: 3",
            "positive",
        ),
        ("PerPixel(80)", "Bytes(6)", "multiple of 4"),
    ] {
        let s = Scratch::new();
        s.edit(SEED, from, to);
        let (e, msg) = s.error(SEED);
        assert!(matches!(e, GraphError::InvalidResource { .. }), "{msg}");
        assert_mentions(&msg, &["seed.ron", why]);
    }
}

#[test]
fn scene_override_of_the_wrong_type_is_an_error() {
    let s = Scratch::new();
    s.edit(
        "shaders/direct.wgsl",
        "@compute @workgroup_size(8, 8)",
        "override scene_light_count: f32;\n\n@compute @workgroup_size(8, 8)",
    );
    s.edit(
        "shaders/direct.wgsl",
        "light * u, 1.0)",
        "light * u * scene_light_count, 1.0)",
    );
    let (_, msg) = s.error(SEED);
    assert_mentions(
        &msg,
        &[
            "direct.wgsl",
            "scene_light_count",
            "set by the framework",
            "U32",
        ],
    );
}

#[test]
fn provided_buffer_bound_to_a_float_texture_names_the_texel_view_forms() {
    let s = Scratch::new();
    s.edit(
        "shaders/intersect.wgsl",
        "var<storage, read> bvh: array<vec4<f32>>",
        "var bvh: texture_2d<f32>",
    );
    s.edit(
        "shaders/intersect.wgsl",
        "bvh[0].x",
        "textureLoad(bvh, vec2<u32>(0u), 0).x",
    );
    let (_, msg) = s.error(SEED);
    assert_mentions(
        &msg,
        &[
            "pass 'intersect'",
            "'bvh'",
            "'scene.bvh'",
            "texture_2d<u32>",
            "16-byte texels",
        ],
    );
}

const RASTER: &str = "graphs/raster.ron";

#[test]
fn raster_attachment_format_is_checked_against_the_fragment_output() {
    let s = Scratch::new();
    s.edit(
        "passes/raster_fill.ron",
        r#"fragment: "fs_main""#,
        r#"fragment: "fs_uint""#,
    );
    let (e, msg) = s.error(RASTER);
    assert!(matches!(e, GraphError::Attachment { .. }), "{msg}");
    assert_mentions(
        &msg,
        &[
            "raster.ron",
            "pass 'draw'",
            "attachment 'color'",
            "'drawn' is Rgba16Float but fragment output 0 is vec4<u32>",
        ],
    );
}

#[test]
fn raster_depth_attachment_must_be_depth32float() {
    let s = Scratch::new();
    s.edit(
        RASTER,
        r#""depth": Texture(format: Depth32Float)"#,
        r#""depth": Texture(format: R32Float)"#,
    );
    let (e, msg) = s.error(RASTER);
    assert!(matches!(e, GraphError::Attachment { .. }), "{msg}");
    assert_mentions(
        &msg,
        &[
            "pass 'draw'",
            "attachment 'depth'",
            "R32Float",
            "Depth32Float",
        ],
    );
}

#[test]
fn depth_texture_cannot_be_a_shader_binding() {
    let s = Scratch::new();
    s.edit(RASTER, r#""src": "drawn""#, r#""src": "depth""#);
    let (e, msg) = s.error(RASTER);
    assert!(matches!(e, GraphError::BindingMismatch { .. }), "{msg}");
    assert_mentions(&msg, &["pass 'copy'", "'src'", "depth attachment only"]);
}

#[test]
fn raster_attachment_of_another_size_is_rejected() {
    let s = Scratch::new();
    s.edit(
        RASTER,
        r#""drawn": Texture(format: Rgba16Float)"#,
        r#""drawn": Texture(format: Rgba16Float, size: Scaled(0.5))"#,
    );
    let (e, msg) = s.error(RASTER);
    assert!(matches!(e, GraphError::Attachment { .. }), "{msg}");
    assert_mentions(&msg, &["attachment 'color'", "128x128", "size: Output"]);
}

#[test]
fn unbound_raster_attachment_names_it() {
    let s = Scratch::new();
    s.edit(RASTER, r#", "depth": "depth""#, "");
    let (e, msg) = s.error(RASTER);
    assert!(matches!(e, GraphError::Unbound { .. }), "{msg}");
    assert_mentions(&msg, &["pass 'draw'", "'depth'", "depth attachment"]);
}

#[test]
fn raster_triangle_count_must_be_provided() {
    let s = Scratch::new();
    s.edit(
        "passes/raster_fill.ron",
        r#"triangles: "scene_triangle_count""#,
        r#"triangles: "scene_triangles""#,
    );
    let (e, msg) = s.error(RASTER);
    assert!(matches!(e, GraphError::Raster { .. }), "{msg}");
    assert_mentions(
        &msg,
        &[
            "raster_fill.ron",
            "'scene_triangles'",
            "scene_triangle_count",
        ],
    );
}

#[test]
fn raster_entry_points_are_looked_up_by_stage() {
    let s = Scratch::new();
    s.edit(
        "passes/raster_fill.ron",
        r#"vertex: "vs_main""#,
        r#"vertex: "fs_main""#,
    );
    let (e, msg) = s.error(RASTER);
    let GraphError::NoEntryPoint { available, .. } = &e else {
        panic!("{msg}")
    };
    assert_eq!(available, &["vs_main"], "{msg}");
}

#[test]
fn fragment_output_without_attachment_is_an_error() {
    let s = Scratch::new();
    s.edit(
        "passes/raster_fill.ron",
        r#"color: ["color"],"#,
        r#"color: [],"#,
    );
    s.edit(RASTER, r#""color": "drawn", "#, "");
    let (e, msg) = s.error(RASTER);
    assert!(matches!(e, GraphError::Raster { .. }), "{msg}");
    assert_mentions(&msg, &["fs_main", "@location(0)"]);
}

#[test]
fn loaded_attachment_is_read_so_it_needs_an_earlier_write_and_the_error_names_the_attachment() {
    // `load: Load` reads what the attachment held: a transient texture nobody wrote.
    let s = Scratch::new();
    s.edit(
        "passes/raster_fill.ron",
        r#"depth: "depth","#,
        r#"depth: "depth", load: Load,"#,
    );
    let (e, msg) = s.error(RASTER);
    assert!(matches!(e, GraphError::ReadBeforeWrite { .. }), "{msg}");
    // Before: "reads 'depth' (binding '')": an attachment is not a binding.
    assert_mentions(
        &msg,
        &["pass 'draw'", "'depth'", "attachment 'depth'", "load: Load"],
    );
    assert!(!msg.contains("binding ''"), "{msg}");
}

#[test]
fn loaded_attachment_of_a_persistent_texture_compiles_as_read_write() {
    let s = Scratch::new();
    s.edit(
        "passes/raster_fill.ron",
        r#"depth: "depth","#,
        r#"depth: "depth", load: Load,"#,
    );
    s.edit(
        RASTER,
        r#""drawn": Texture(format: Rgba16Float)"#,
        r#""drawn": Texture(format: Rgba16Float, persistent: true)"#,
    );
    s.edit(
        RASTER,
        r#""depth": Texture(format: Depth32Float)"#,
        r#""depth": Texture(format: Depth32Float, persistent: true)"#,
    );
    let plan = s.compile(RASTER).unwrap_or_else(|e| panic!("{e}"));
    let draw = plan.pass("draw").unwrap();
    let drawn = plan.resource_id("drawn").unwrap();
    assert!(
        draw.uses
            .iter()
            .any(|&(r, a)| r == drawn && a == passgraph::graph::interface::Access::ReadWrite),
        "{:?}",
        draw.uses
    );
}

const INDIRECT: &str = "graphs/gpu_indirect.ron";

#[test]
fn indirect_dispatch_record_past_the_buffer_names_the_offset_and_the_buffer() {
    let s = Scratch::new();
    s.edit(INDIRECT, r#""record": U32(1)"#, r#""record": U32(2)"#);
    let (e, msg) = s.error(INDIRECT);
    assert!(matches!(e, GraphError::Dispatch { .. }), "{msg}");
    assert_mentions(&msg, &["pass 'count'", "offset 32", "'args'", "32 bytes"]);
}

#[test]
fn indirect_dispatch_through_a_written_binding_is_an_error() {
    let s = Scratch::new();
    s.edit(
        "shaders/gpu_count_invocations.wgsl",
        "var<storage, read> args",
        "var<storage, read_write> args",
    );
    let (e, msg) = s.error(INDIRECT);
    assert!(matches!(e, GraphError::Dispatch { .. }), "{msg}");
    assert_mentions(&msg, &["pass 'count'", "'args'", "var<storage, read>"]);
}

#[test]
fn indirect_dispatch_naming_an_absent_binding_or_param_is_an_error() {
    let s = Scratch::new();
    s.edit(
        "passes/gpu_count_invocations.ron",
        r#"binding: "args""#,
        r#"binding: "argz""#,
    );
    let (e, msg) = s.error(INDIRECT);
    assert!(matches!(e, GraphError::Dispatch { .. }), "{msg}");
    assert_mentions(&msg, &["pass 'count'", "'argz'", "args, counter"]);

    let s = Scratch::new();
    s.edit(
        "passes/gpu_count_invocations.ron",
        r#"index: "record""#,
        r#"index: "level""#,
    );
    let (e, msg) = s.error(INDIRECT);
    assert!(matches!(e, GraphError::Dispatch { .. }), "{msg}");
    assert_mentions(&msg, &["pass 'count'", "param 'level'"]);
}

#[test]
fn indirect_dispatch_cannot_declare_a_pixel_footprint() {
    let s = Scratch::new();
    s.edit(
        "passes/gpu_count_invocations.ron",
        "Pass(shader:",
        "Pass(footprint: Pixel, shader:",
    );
    let (e, msg) = s.error(INDIRECT);
    assert!(matches!(e, GraphError::Footprint { .. }), "{msg}");
    assert_mentions(&msg, &["gpu_count_invocations.ron", "Indirect"]);
}
