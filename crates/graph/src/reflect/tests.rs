//! Reflection of shaders written for each case: bindings, params, overrides, errors.

use super::*;
use std::fs;
use std::path::Path;

fn reflect_code(code: &str, entry: &str) -> Result<ShaderInterface, GraphError> {
    reflect(
        &ShaderSource::from_code("test.wgsl".into(), code.to_string()),
        entry,
    )
}

fn interface(code: &str) -> ShaderInterface {
    match reflect_code(code, "main") {
        Ok(interface) => interface,
        Err(e) => panic!("reflect failed: {e}"),
    }
}

fn single_binding(code: &str) -> BindingKind {
    let interface = interface(code);
    assert_eq!(interface.bindings.len(), 1, "{:?}", interface.bindings);
    interface.bindings[0].kind.clone()
}

fn unsupported_reason(code: &str) -> (String, String) {
    match reflect_code(code, "main") {
        Err(GraphError::UnsupportedBinding {
            binding, reason, ..
        }) => (binding, reason),
        other => panic!("expected UnsupportedBinding, got {other:?}"),
    }
}

fn wgsl_error_at(result: Result<ShaderInterface, GraphError>) -> (PathBuf, usize, usize) {
    match result {
        Err(GraphError::Wgsl {
            file, line, col, ..
        }) => (file, line, col),
        other => panic!("expected Wgsl error, got {other:?}"),
    }
}

fn project(files: &[(&str, &str)]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for (path, content) in files {
        let path = dir.path().join(path);
        fs::create_dir_all(path.parent().unwrap()).unwrap();
        fs::write(path, content).unwrap();
    }
    dir
}

fn same_file(a: &Path, b: &Path) -> bool {
    a.canonicalize().unwrap() == b.canonicalize().unwrap()
}

#[test]
fn storage_buffer_access_follows_declaration() {
    let read = single_binding(
        "@group(0) @binding(0) var<storage, read> buf: array<u32>;
         @compute @workgroup_size(1) fn main() { _ = buf[0]; }",
    );
    assert_eq!(
        read,
        BindingKind::Storage {
            access: Access::Read,
            min_size: 4
        }
    );
    // Declared read_write but only read: the declaration decides, as the pipeline layout does.
    let read_write = single_binding(
        "@group(0) @binding(0) var<storage, read_write> buf: array<u32>;
         @compute @workgroup_size(1) fn main() { _ = buf[0]; }",
    );
    assert_eq!(read_write.access(), Access::ReadWrite);
}

#[test]
fn storage_min_size_counts_struct_with_one_runtime_element() {
    let kind = single_binding(
        "struct Particles { count: u32, items: array<vec4<f32>> }
         @group(0) @binding(0) var<storage, read_write> particles: Particles;
         @compute @workgroup_size(64) fn main() { particles.count = 1u; }",
    );
    // count at 0, items aligned to 16, one 16-byte element; only stored to, so written.
    assert_eq!(
        kind,
        BindingKind::Storage {
            access: Access::Write,
            min_size: 32
        }
    );
}

#[test]
fn read_write_buffer_the_shader_only_stores_to_is_written_not_read() {
    let access = |body: &str| {
        single_binding(&format!(
            "@group(0) @binding(0) var<storage, read_write> buf: array<atomic<u32>>;
             @compute @workgroup_size(1) fn main() {{ {body} }}"
        ))
        .access()
    };
    // An atomic store is a store; any other atomic reads and writes.
    assert_eq!(access("atomicStore(&buf[0], 1u);"), Access::Write);
    assert_eq!(access("atomicAdd(&buf[0], 1u);"), Access::ReadWrite);
    let plain = |body: &str| {
        single_binding(&format!(
            "@group(0) @binding(0) var<storage, read_write> buf: array<u32>;
             @compute @workgroup_size(1) fn main() {{ {body} }}"
        ))
        .access()
    };
    assert_eq!(plain("buf[0] = 1u;"), Access::Write);
    // Its length is no read of its contents.
    assert_eq!(plain("buf[arrayLength(&buf) - 1u] = 1u;"), Access::Write);
    assert_eq!(plain("buf[0] = buf[1];"), Access::ReadWrite);
    assert_eq!(plain("buf[buf[0]] = 1u;"), Access::ReadWrite);
    // A storage texture keeps its declaration, which its bind group layout must match.
    let texture = single_binding(
        "@group(0) @binding(0) var t: texture_storage_2d<r32float, read_write>;
         @compute @workgroup_size(1) fn main() { textureStore(t, vec2<i32>(0), vec4<f32>(1.0)); }",
    );
    assert_eq!(texture.access(), Access::ReadWrite);
}

#[test]
fn storage_min_size_of_bare_runtime_array_is_one_stride() {
    let kind = single_binding(
        "@group(0) @binding(0) var<storage, read> v: array<vec3<f32>>;
         @compute @workgroup_size(1) fn main() { _ = v[0]; }",
    );
    assert_eq!(
        kind,
        BindingKind::Storage {
            access: Access::Read,
            min_size: 16
        }
    );
}

#[test]
fn uniform_other_than_params_is_a_sized_binding() {
    let kind = single_binding(
        "struct Eye { view: mat4x4<f32>, pos: vec3<f32> }
         @group(0) @binding(0) var<uniform> eye: Eye;
         @compute @workgroup_size(1) fn main() { _ = eye.pos; }",
    );
    assert_eq!(kind, BindingKind::Uniform { size: 80 });
}

#[test]
fn storage_texture_access_format_and_dim() {
    let interface = interface(
        "@group(0) @binding(0) var w: texture_storage_2d<rgba16float, write>;
         @group(0) @binding(1) var r: texture_storage_2d_array<r32float, read>;
         @group(0) @binding(2) var rw: texture_storage_2d<rgba8unorm, read_write>;
         @compute @workgroup_size(8, 8) fn main() {
             let x = textureLoad(r, vec2(0, 0), 0);
             textureStore(rw, vec2(0, 0), textureLoad(rw, vec2(0, 0)));
             textureStore(w, vec2(0, 0), x);
         }",
    );
    let kinds: Vec<_> = interface.bindings.iter().map(|b| b.kind.clone()).collect();
    assert_eq!(
        kinds,
        [
            BindingKind::StorageTexture {
                access: Access::Write,
                format: TextureFormat::Rgba16Float,
                dim: TextureDim::D2
            },
            BindingKind::StorageTexture {
                access: Access::Read,
                format: TextureFormat::R32Float,
                dim: TextureDim::D2Array
            },
            BindingKind::StorageTexture {
                access: Access::ReadWrite,
                format: TextureFormat::Rgba8Unorm,
                dim: TextureDim::D2
            },
        ]
    );
    assert_eq!(interface.workgroup_size, [8, 8, 1]);
}

#[test]
fn every_supported_storage_format_maps_to_the_same_texture_format() {
    for format in TextureFormat::STORAGE {
        let kind = single_binding(&format!(
            "@group(0) @binding(0) var t: texture_storage_2d<{}, write>;
             @compute @workgroup_size(1) fn main() {{ _ = textureDimensions(t); }}",
            format.wgsl_name()
        ));
        assert_eq!(
            kind,
            BindingKind::StorageTexture {
                access: Access::Write,
                format,
                dim: TextureDim::D2
            }
        );
    }
}

#[test]
fn unsupported_storage_format_is_named() {
    let (binding, reason) = unsupported_reason(
        "@group(0) @binding(0) var t: texture_storage_2d<r16unorm, write>;
         @compute @workgroup_size(1) fn main() { _ = textureDimensions(t); }",
    );
    assert_eq!(binding, "t");
    assert!(reason.contains("r16unorm"), "{reason}");
}

#[test]
fn sampled_texture_kind_and_dim() {
    let interface = interface(
        "@group(0) @binding(0) var a: texture_2d<f32>;
         @group(0) @binding(1) var b: texture_2d<u32>;
         @group(1) @binding(0) var c: texture_2d_array<i32>;
         @compute @workgroup_size(1) fn main() {
             _ = textureLoad(a, vec2(0, 0), 0);
             _ = textureLoad(b, vec2(0, 0), 0);
             _ = textureLoad(c, vec2(0, 0), 0, 0);
         }",
    );
    let kinds: Vec<_> = interface.bindings.iter().map(|b| b.kind.clone()).collect();
    assert_eq!(
        kinds,
        [
            BindingKind::SampledTexture {
                sample: SampleKind::Float,
                dim: TextureDim::D2
            },
            BindingKind::SampledTexture {
                sample: SampleKind::Uint,
                dim: TextureDim::D2
            },
            BindingKind::SampledTexture {
                sample: SampleKind::Sint,
                dim: TextureDim::D2Array
            },
        ]
    );
}

#[test]
fn bindings_are_sorted_by_group_then_binding() {
    let interface = interface(
        "@group(1) @binding(0) var<storage, read> d: array<u32>;
         @group(0) @binding(3) var<storage, read> c: array<u32>;
         @group(0) @binding(1) var<storage, read> b: array<u32>;
         @compute @workgroup_size(1) fn main() { _ = b[0]; _ = c[0]; _ = d[0]; }",
    );
    let slots: Vec<_> = interface
        .bindings
        .iter()
        .map(|b| (b.name.as_str(), b.group, b.binding))
        .collect();
    assert_eq!(slots, [("b", 0, 1), ("c", 0, 3), ("d", 1, 0)]);
}

#[test]
fn params_block_fields_offsets_and_size() {
    let interface = interface(
        "struct Params { a: f32, b: vec3<f32>, c: u32, d: i32, e: vec2<f32>, f: vec4<f32> }
         @group(0) @binding(2) var<uniform> params: Params;
         @compute @workgroup_size(1) fn main() { _ = params.a; }",
    );
    let block = interface.params.expect("params block");
    assert_eq!((block.group, block.binding), (0, 2));
    let fields: Vec<_> = block
        .fields
        .iter()
        .map(|f| (f.name.as_str(), f.ty, f.offset))
        .collect();
    assert_eq!(
        fields,
        [
            ("a", ParamType::F32, 0),
            ("b", ParamType::Vec3, 16),
            ("c", ParamType::U32, 28),
            ("d", ParamType::I32, 32),
            ("e", ParamType::Vec2, 40),
            ("f", ParamType::Vec4, 48),
        ]
    );
    assert_eq!(block.size, 64);
    // The params block is not an ordinary binding.
    assert!(interface.bindings.is_empty());
}

#[test]
fn params_field_of_unsupported_type_is_named() {
    let (binding, reason) = unsupported_reason(
        "struct Params { scale: f32, m: mat4x4<f32> }
         @group(0) @binding(0) var<uniform> params: Params;
         @compute @workgroup_size(1) fn main() { _ = params.scale; }",
    );
    assert_eq!(binding, "params");
    assert!(
        reason.contains("'m'") && reason.contains("mat4x4<f32>"),
        "{reason}"
    );
}

#[test]
fn params_uniform_that_is_not_a_struct_is_rejected() {
    let (binding, reason) = unsupported_reason(
        "@group(0) @binding(0) var<uniform> params: vec4<f32>;
         @compute @workgroup_size(1) fn main() { _ = params.x; }",
    );
    assert_eq!(binding, "params");
    assert!(reason.contains("struct"), "{reason}");
}

#[test]
fn unused_globals_are_not_bindings() {
    let interface = interface(
        "struct Params { a: f32 }
         @group(0) @binding(0) var<uniform> params: Params;
         @group(0) @binding(1) var<storage, read> unused: array<u32>;
         @group(0) @binding(2) var<storage, read_write> used: array<u32>;
         @group(0) @binding(3) var s: sampler;
         fn helper() { used[0] = 1u; }
         @compute @workgroup_size(1) fn main() { helper(); }",
    );
    let names: Vec<_> = interface.bindings.iter().map(|b| b.name.as_str()).collect();
    // `used` is reached through a helper function; an unused sampler is no error either.
    assert_eq!(names, ["used"]);
    assert_eq!(interface.params, None);
}

#[test]
fn each_entry_point_gets_only_its_own_bindings() {
    let code = "@group(0) @binding(0) var<storage, read> input: array<f32>;
         @group(0) @binding(1) var<storage, read_write> a: array<f32>;
         @group(0) @binding(2) var<storage, read_write> b: array<f32>;
         @compute @workgroup_size(64) fn first() { a[0] = input[0]; }
         @compute @workgroup_size(8, 8) fn second() { b[0] = input[0]; }";
    let names = |entry: &str| {
        let interface = reflect_code(code, entry).unwrap();
        let names: Vec<_> = interface.bindings.into_iter().map(|b| b.name).collect();
        (names, interface.workgroup_size, interface.entry)
    };
    assert_eq!(
        names("first"),
        (vec!["input".into(), "a".into()], [64, 1, 1], "first".into())
    );
    assert_eq!(
        names("second"),
        (vec!["input".into(), "b".into()], [8, 8, 1], "second".into())
    );
}

#[test]
fn missing_entry_point_lists_compute_entry_points_only() {
    let result = reflect_code(
        "@compute @workgroup_size(1) fn a() {}
         @compute @workgroup_size(1) fn b() {}
         @fragment fn fs() -> @location(0) vec4<f32> { return vec4(1.0); }",
        "fs",
    );
    match result {
        Err(GraphError::NoEntryPoint {
            entry, available, ..
        }) => {
            assert_eq!(entry, "fs");
            assert_eq!(available, ["a", "b"]);
        }
        other => panic!("expected NoEntryPoint, got {other:?}"),
    }
}

#[test]
fn unsupported_binding_types_are_rejected_with_reason() {
    let cases = [
        ("var s: sampler;", "_ = s;", "sampler"),
        (
            "var d: texture_depth_2d;",
            "_ = textureDimensions(d);",
            "depth",
        ),
        (
            "var m: texture_multisampled_2d<f32>;",
            "_ = textureDimensions(m);",
            "multisampled",
        ),
        ("var t: texture_3d<f32>;", "_ = textureDimensions(t);", "3d"),
        ("var t: texture_1d<f32>;", "_ = textureDimensions(t);", "1d"),
        (
            "var t: texture_cube<f32>;",
            "_ = textureDimensions(t);",
            "cube",
        ),
        (
            "var t: texture_storage_3d<rgba8unorm, write>;",
            "_ = textureDimensions(t);",
            "3d",
        ),
    ];
    for (decl, use_, expected) in cases {
        let code = format!(
            "@group(0) @binding(0) {decl}\n@compute @workgroup_size(1) fn main() {{ {use_} }}"
        );
        let (_, reason) = unsupported_reason(&code);
        assert!(reason.contains(expected), "{decl}: {reason}");
    }
}

#[test]
fn binding_arrays_are_rejected_with_reason() {
    let (binding, reason) = unsupported_reason(
        "enable wgpu_binding_array;
         @group(0) @binding(0) var ts: binding_array<texture_2d<f32>, 4>;
         @compute @workgroup_size(1) fn main() { _ = textureLoad(ts[0], vec2(0, 0), 0); }",
    );
    assert_eq!(binding, "ts");
    assert!(reason.contains("binding arrays"), "{reason}");
}

#[test]
fn overrides_with_types_and_defaults() {
    let interface = interface(
        "override enabled: bool = true;
         override scale: f32;
         override count: u32 = 4u;
         override offset: i32 = -1;
         @compute @workgroup_size(1) fn main() { _ = scale; }",
    );
    let overrides: Vec<_> = interface
        .overrides
        .iter()
        .map(|o| (o.name.as_str(), o.ty, o.has_default))
        .collect();
    assert_eq!(
        overrides,
        [
            ("enabled", ParamType::Bool, true),
            ("scale", ParamType::F32, false),
            ("count", ParamType::U32, true),
            ("offset", ParamType::I32, true),
        ]
    );
}

#[test]
fn override_with_id_is_rejected_because_it_cannot_be_set_by_name() {
    let (binding, reason) = unsupported_reason(
        "@id(3) override scale: f32 = 1.0;
         @compute @workgroup_size(1) fn main() { _ = scale; }",
    );
    assert_eq!(binding, "scale");
    assert!(reason.contains("@id(3)"), "{reason}");
}

#[test]
fn override_sized_workgroup_is_rejected() {
    let (binding, _) = unsupported_reason(
        "override size: u32 = 64u;
         @compute @workgroup_size(size) fn main() {}",
    );
    assert_eq!(binding, "@workgroup_size");
}

#[test]
fn const_sized_workgroup_is_accepted() {
    let interface = interface(
        "const SIZE = 16u;
         @compute @workgroup_size(SIZE, SIZE / 2u) fn main() {}",
    );
    assert_eq!(interface.workgroup_size, [16, 8, 1]);
}

#[test]
fn parse_error_in_included_lib_reports_lib_file_and_line() {
    let dir = project(&[
        (
            "shaders/lib/rng.wgsl",
            "// rng\nfn rng(seed: u32) -> u32 {\n    let x = seed * 747796405u\n    return x;\n}\n",
        ),
        (
            "shaders/passes/noise.wgsl",
            "// noise\n#include \"lib/rng.wgsl\"\n@compute @workgroup_size(1) fn main() {}\n",
        ),
    ]);
    let root = dir.path().join("shaders");
    let source = ShaderSource::load(&root.join("passes/noise.wgsl"), &root).unwrap();
    let (file, line, col) = wgsl_error_at(reflect(&source, "main"));
    assert!(same_file(&file, &root.join("lib/rng.wgsl")), "{file:?}");
    // naga points at the token after the missing `;`.
    assert_eq!((line, col), (4, 5));
}

#[test]
fn parse_error_after_include_reports_main_file_own_line() {
    let dir = project(&[
        (
            "shaders/lib/rng.wgsl",
            "fn rng(seed: u32) -> u32 {\n    return seed * 747796405u;\n}\n",
        ),
        (
            "shaders/noise.wgsl",
            "#include \"lib/rng.wgsl\"\n\n@compute @workgroup_size(1) fn main() {\n    let x: u32 = rng(1u) +;\n}\n",
        ),
    ]);
    let root = dir.path().join("shaders");
    let main = root.join("noise.wgsl");
    let source = ShaderSource::load(&main, &root).unwrap();
    let (file, line, _) = wgsl_error_at(reflect(&source, "main"));
    assert_eq!(file, main);
    assert_eq!(line, 4);
}

#[test]
fn parse_error_message_keeps_informative_labels() {
    let result = reflect_code(
        "fn f() {}\nfn f() {}\n@compute @workgroup_size(1) fn main() {}",
        "main",
    );
    match result {
        Err(GraphError::Wgsl {
            line, col, message, ..
        }) => {
            assert_eq!((line, col), (2, 4));
            // The previous definition is elsewhere, so the message says where.
            assert!(message.contains("test.wgsl:1:4"), "{message}");
        }
        other => panic!("expected Wgsl error, got {other:?}"),
    }
}

#[test]
fn validation_error_points_at_offending_expression_not_enclosing_function() {
    let result = reflect_code(
        "@group(0) @binding(0) var<storage, read> b: array<f32>;\n\
         fn helper(i: u32) {\n\
         \x20   b[i] = 1.0;\n\
         }\n\
         @compute @workgroup_size(1) fn main() { helper(0u); }",
        "main",
    );
    match result {
        Err(GraphError::Wgsl {
            file,
            line,
            col,
            message,
        }) => {
            assert_eq!(file, PathBuf::from("test.wgsl"));
            assert_eq!((line, col), (3, 5));
            // The cause, not just "Function 'helper' is invalid".
            assert!(message.contains("store"), "{message}");
        }
        other => panic!("expected Wgsl error, got {other:?}"),
    }
}

#[test]
fn validation_error_in_included_lib_reports_lib_file() {
    let dir = project(&[
        (
            "shaders/lib/layout.wgsl",
            "// layout\n@group(0) @binding(0) var<uniform> weights: array<f32, 4>;\n",
        ),
        (
            "shaders/p.wgsl",
            "#include \"lib/layout.wgsl\"\n@compute @workgroup_size(1) fn main() { _ = weights[0]; }\n",
        ),
    ]);
    let root = dir.path().join("shaders");
    let source = ShaderSource::load(&root.join("p.wgsl"), &root).unwrap();
    let (file, line, _) = wgsl_error_at(reflect(&source, "main"));
    assert!(same_file(&file, &root.join("lib/layout.wgsl")), "{file:?}");
    assert_eq!(line, 2);
}

#[test]
fn validation_error_without_span_points_at_start_of_main_file() {
    // f64 needs a native feature; naga reports the type without a span.
    let location = wgsl_error_at(reflect_code(
        "\n@compute @workgroup_size(1) fn main() { var x: f64 = 1.0lf; }",
        "main",
    ));
    assert_eq!(location, (PathBuf::from("test.wgsl"), 1, 1));
}

#[test]
fn core_wgsl_builtins_needing_capabilities_validate() {
    // pack2x16float is core WGSL but needs SHADER_FLOAT16_IN_FLOAT32 in naga.
    interface("@compute @workgroup_size(1) fn main() { _ = pack2x16float(vec2(1.0)); }");
}

#[test]
fn raster_entry_points_union_their_bindings_and_list_fragment_outputs() {
    let code = "@group(0) @binding(0) var<uniform> scale: vec4<f32>;
         @group(0) @binding(1) var tex: texture_2d<u32>;
         @group(0) @binding(2) var<storage, read> unused: array<u32>;
         struct Out { @location(1) id: vec2<u32>, @location(0) colour: vec4<f32>,
                      @builtin(frag_depth) depth: f32 }
         @vertex fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
             return scale * f32(i);
         }
         @fragment fn fs() -> Out {
             return Out(textureLoad(tex, vec2(0, 0), 0).xy, vec4(1.0), 0.5);
         }
         @compute @workgroup_size(1) fn main() { _ = unused[0]; }";
    let source = ShaderSource::from_code("test.wgsl".into(), code.to_string());
    let interface = reflect_raster(&source, "vs", "fs").unwrap();
    let names: Vec<_> = interface.bindings.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(names, ["scale", "tex"]);
    let outputs: Vec<_> = interface
        .outputs
        .iter()
        .map(|o| (o.location, o.sample, o.components, o.ty.as_str()))
        .collect();
    assert_eq!(
        outputs,
        [
            (0, SampleKind::Float, 4, "vec4<f32>"),
            (1, SampleKind::Uint, 2, "vec2<u32>"),
        ]
    );
    // Entry points are found by stage: a compute entry point is no vertex shader, and the
    // message says which stage was looked for.
    let e = reflect_raster(&source, "main", "fs").unwrap_err();
    assert!(matches!(e, GraphError::NoEntryPoint { .. }));
    let e = e.in_pass_file(Path::new("passes/gbuffer.ron")).to_string();
    assert!(
        e.starts_with("passes/gbuffer.ron: pass's shader ")
            && e.contains("no vertex entry point 'main'"),
        "{e}"
    );
}
