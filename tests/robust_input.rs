//! Bad input found by hand (issue 11): each case once crashed, hung or gave a silently wrong
//! result; now `check` (or the command, before any rendering) rejects it with a message naming
//! the file and what is wrong, exit status 1 (2 for usage), and no panic.

mod common;

use common::{assert_mentions, copy_dir, root};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A private copy of the shipped graphs, passes, shaders and scenes that a test may edit.
struct Project {
    dir: tempfile::TempDir,
}

impl Project {
    fn new() -> Project {
        let dir = tempfile::tempdir().unwrap();
        for sub in ["graphs", "passes", "shaders", "scenes"] {
            copy_dir(&root().join(sub), &dir.path().join(sub));
        }
        Project { dir }
    }

    fn path(&self, rel: &str) -> PathBuf {
        self.dir.path().join(rel)
    }

    fn arg(&self, rel: &str) -> String {
        self.path(rel).to_str().unwrap().to_string()
    }

    /// Replaces the one occurrence of `from` in `rel`.
    fn edit(&self, rel: &str, from: &str, to: &str) -> &Project {
        let path = self.path(rel);
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text.matches(from).count(), 1, "{rel}: {from:?}");
        std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
        self
    }

    fn write(&self, rel: &str, text: &str) -> &Project {
        let path = self.path(rel);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, text).unwrap();
        self
    }
}

fn passgraph(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_passgraph"))
        .args(args)
        .output()
        .expect("the passgraph binary runs")
}

/// The arguments of a one-frame `render` of the copy `p` at `size`, with `input` (e.g.
/// `["--graph", path]`) and output `x.png` in the copy.
fn one_frame(p: &Project, input: [&str; 2], size: &str) -> Vec<String> {
    let mut args = vec!["render".to_string(), input[0].into(), p.arg(input[1])];
    for a in ["--frames", "1", "--size", size, "--out"] {
        args.push(a.into());
    }
    args.push(p.arg("x.png"));
    args
}

fn strs(args: &[String]) -> Vec<&str> {
    args.iter().map(String::as_str).collect()
}

/// Runs a command that must fail with `code`, a message on stderr mentioning `parts`, and no
/// panic; returns stderr.
fn fails(args: &[&str], code: i32, parts: &[&str]) -> String {
    let out = passgraph(args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(code), "{args:?}: {stderr}");
    assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    assert_mentions(&stderr, parts);
    stderr
}

const GRAPH: &str = "graphs/pathtracer.ron";

// 1. A result buffer smaller than five planes passed `check` and panicked in `render`.
#[test]
fn result_smaller_than_five_planes_is_rejected_by_check_and_render_without_panic() {
    for size in ["PerPixel(64)", "Bytes(16)"] {
        let p = Project::new();
        p.edit(
            GRAPH,
            r#""result": Buffer(size: PerPixel(80)"#,
            &format!(r#""result": Buffer(size: {size}"#),
        );
        let graph = p.arg(GRAPH);
        fails(
            &["check", &graph],
            1,
            &["pathtracer.ron", "'result'", "PerPixel(80)"],
        );
        fails(
            &strs(&one_frame(&p, ["--graph", GRAPH], "8x8")),
            1,
            &["pathtracer.ron", "'result'"],
        );
        assert!(!p.path("x.png").exists());
    }
}

// 4. What `render` reads back must exist: `dropped`, and each ray counter as an output.
#[test]
fn missing_dropped_buffer_or_unlisted_ray_counter_is_rejected_by_check() {
    // A graph with a result but no dropped-sample counter (the seed fixture).
    let seed = common::fixtures().join("graphs/seed.ron");
    fails(
        &["check", seed.to_str().unwrap()],
        1,
        &["seed.ron", "'dropped'", "not declared"],
    );
    // Declared and written, but not an output: its content is not kept for the read-back.
    let p = Project::new();
    p.edit(GRAPH, r#""result", "dropped", "#, r#""result", "#);
    fails(
        &["check", &p.arg(GRAPH)],
        1,
        &["pathtracer.ron", "'dropped'", "outputs"],
    );

    let p = Project::new();
    p.edit(GRAPH, r#", "rays_indirect"]"#, "]");
    fails(
        &["check", &p.arg(GRAPH)],
        1,
        &["pathtracer.ron", "'rays_indirect'", "ray_count", "outputs"],
    );
}

// 4. `rays` with fewer layers than intersect stores rendered a wrong image with exit 0.
#[test]
fn texture_with_fewer_layers_than_a_constant_layer_index_is_an_error() {
    for layers in [1, 2] {
        let p = Project::new();
        p.edit(GRAPH, "layers: 3", &format!("layers: {layers}"));
        fails(
            &["check", "--generic", &p.arg(GRAPH)],
            1,
            &[
                "pathtracer.ron",
                "pass 'intersect'",
                "'rays'",
                "layer 2",
                "layers: 3",
            ],
        );
    }
}

// 4. `direct` at Scaled(0.5) lit a quarter of the image.
#[test]
fn per_pixel_pass_writing_a_texture_smaller_than_the_output_is_an_error() {
    let p = Project::new();
    p.edit(
        GRAPH,
        r#""direct": Texture(format: Rgba32Float),"#,
        r#""direct": Texture(format: Rgba32Float, size: Scaled(0.5)),"#,
    );
    fails(
        &["check", "--generic", &p.arg(GRAPH)],
        1,
        &["pathtracer.ron", "pass 'direct'", "'direct'", "128x128"],
    );
}

// 4. An empty graph or one without outputs passed `check`.
#[test]
fn graph_without_passes_or_outputs_is_an_error() {
    let p = Project::new();
    p.write("graphs/empty.ron", "Graph(passes: [], outputs: [])");
    fails(
        &["check", "--generic", &p.arg("graphs/empty.ron")],
        1,
        &["empty.ron", "no passes"],
    );
    p.edit(
        GRAPH,
        r#"outputs: ["result", "dropped", "rays_intersect", "rays_ambient", "rays_direct", "rays_indirect"],"#,
        "outputs: [],",
    );
    fails(
        &["check", "--generic", &p.arg(GRAPH)],
        1,
        &["pathtracer.ron", "no outputs"],
    );
}

#[test]
fn every_shipped_graph_meets_the_render_contract() {
    for entry in std::fs::read_dir(root().join("graphs")).unwrap() {
        let path = entry.unwrap().path();
        if common::is_subgraph(&path) {
            // A subgraph (graphs/denoiser.ron) runs only where a graph includes it.
            let out = passgraph(&["check", path.to_str().unwrap()]);
            assert_eq!(out.status.code(), Some(1), "{}", path.display());
            assert!(String::from_utf8_lossy(&out.stderr).contains("is a subgraph"));
            continue;
        }
        let out = passgraph(&["check", path.to_str().unwrap()]);
        assert!(
            out.status.success(),
            "{}: {}",
            path.display(),
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

// 3. `bench --seconds NaN` (or inf) ran forever.
#[test]
fn bench_time_budget_that_is_not_finite_and_positive_is_a_usage_error() {
    for seconds in ["NaN", "inf", "-inf", "0", "-1"] {
        fails(
            &[
                "bench",
                "--reference",
                "r.exr",
                &format!("--seconds={seconds}"),
            ],
            2,
            &["--seconds"],
        );
    }
}

// 8. `--frames 0` wrote a black image; `bench --frames 0` rendered one frame.
#[test]
fn zero_frames_is_a_usage_error_for_render_and_bench() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    fails(
        &["render", "--frames", "0", "--out", out.to_str().unwrap()],
        2,
        &["--frames"],
    );
    fails(
        &["bench", "--reference", "r.exr", "--frames", "0"],
        2,
        &["--frames"],
    );
    assert!(!out.exists());
}

/// A render that must be refused before any frame: it asks for a million frames, which would
/// take hours, so a passing test shows the check came first; and nothing is written.
fn refused_before_rendering(extra: &[&str], code: i32, parts: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("never.png");
    let mut args = vec![
        "render",
        "--frames",
        "1000000",
        "--size",
        "16x16",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    fails(&args, code, parts);
    assert!(!out.exists());
}

// 8. `--out`, `--channel` and `--reference` were checked after all frames were rendered.
#[test]
fn bad_out_channel_or_reference_is_refused_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    let d = |rel: &str| dir.path().join(rel).to_str().unwrap().to_string();
    refused_before_rendering(&["--out", &d("x.bmp")], 2, &["x.bmp", ".png"]);
    refused_before_rendering(&["--out", &d("no/such/dir/x.png")], 2, &["no/such/dir"]);
    std::fs::create_dir(dir.path().join("a.png")).unwrap();
    refused_before_rendering(&["--out", &d("a.png")], 2, &["a.png", "directory"]);
    refused_before_rendering(&["--channel", "denoised"], 1, &["'denoised'"]);

    // A reference of another size, and a PNG (sRGB, clamped) given as the linear reference.
    let image = passgraph::render::image::RgbImage {
        width: 8,
        height: 8,
        pixels: vec![[0.5; 3]; 64],
    };
    image.write(&dir.path().join("small.exr")).unwrap();
    refused_before_rendering(
        &["--reference", &d("small.exr")],
        1,
        &["small.exr", "8x8", "16x16"],
    );
    let image = passgraph::render::image::RgbImage {
        width: 16,
        height: 16,
        pixels: vec![[0.5; 3]; 256],
    };
    image.write(&dir.path().join("ref.png")).unwrap();
    std::fs::copy(dir.path().join("ref.png"), dir.path().join("ref.exr")).unwrap();
    refused_before_rendering(&["--reference", &d("ref.png")], 1, &["ref.png", "OpenEXR"]);
    // Judged by content, not by name.
    refused_before_rendering(&["--reference", &d("ref.exr")], 1, &["ref.exr", "OpenEXR"]);
}

// 8. `--error-csv` without `--camera-path` was ignored.
#[test]
fn error_csv_without_camera_path_is_a_usage_error() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("e.csv");
    refused_before_rendering(
        &["--error-csv", csv.to_str().unwrap()],
        2,
        &["--camera-path"],
    );
    assert!(!csv.exists());
}

// 8. The same graph twice in `bench` overwrote its own CSV.
#[test]
fn bench_with_the_same_graph_twice_is_a_usage_error() {
    let dir = tempfile::tempdir().unwrap();
    let graph = root().join(GRAPH);
    let graph = graph.to_str().unwrap();
    let out = dir.path().join("bench");
    fails(
        &[
            "bench",
            "--reference",
            "r.exr",
            "--graph",
            graph,
            "--graph",
            graph,
            "--out",
            out.to_str().unwrap(),
        ],
        2,
        &["pathtracer", "once"],
    );
    assert!(!out.exists());
}

/// `passgraph-runtime-*` folders in `dir`.
fn runtime_dirs(dir: &Path) -> Vec<PathBuf> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("passgraph-runtime-"))
        })
        .collect()
}

fn without_session(tmp: &Path, args: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_passgraph"));
    c.args(args)
        .env("TMPDIR", tmp)
        .env_remove("XDG_RUNTIME_DIR");
    c
}

// 7. The private runtime folder was left in the temp folder on exit.
#[test]
fn runtime_folder_is_removed_on_success_error_and_usage_error() {
    let tmp = tempfile::tempdir().unwrap();
    let graph = root().join(GRAPH);
    for args in [
        vec!["check", graph.to_str().unwrap()],
        vec!["check", "no-such-graph.ron"],
        vec!["render", "--no-such-flag"],
        vec!["--help"],
    ] {
        let out = without_session(tmp.path(), &args).output().unwrap();
        assert!(!String::from_utf8_lossy(&out.stderr).contains("panicked"));
        assert_eq!(runtime_dirs(tmp.path()), Vec::<PathBuf>::new(), "{args:?}");
    }
}

// 7. SIGINT/SIGTERM left temporary files and the runtime folder behind.
#[cfg(unix)]
#[test]
fn sigterm_during_a_render_removes_the_runtime_folder_and_writes_nothing() {
    use std::io::BufRead;
    use std::os::unix::process::ExitStatusExt;
    let tmp = tempfile::tempdir().unwrap();
    let out_dir = tempfile::tempdir().unwrap();
    let out = out_dir.path().join("x.png");
    let mut child = without_session(
        tmp.path(),
        &[
            "render",
            "--frames",
            "1000000",
            "--size",
            "16x16",
            "--out",
            out.to_str().unwrap(),
        ],
    )
    .stderr(std::process::Stdio::piped())
    .spawn()
    .unwrap();
    // The render has started (and the runtime folder exists) once it names its adapter.
    let mut stderr = std::io::BufReader::new(child.stderr.take().unwrap());
    let mut line = String::new();
    while !line.contains("adapter:") {
        line.clear();
        assert!(stderr.read_line(&mut line).unwrap() > 0, "no adapter line");
    }
    assert_eq!(runtime_dirs(tmp.path()).len(), 1);
    let killed = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let status = child.wait().unwrap();
    assert_eq!(status.signal(), Some(15), "{status:?}");
    assert_eq!(runtime_dirs(tmp.path()), Vec::<PathBuf>::new());
    assert_eq!(std::fs::read_dir(out_dir.path()).unwrap().count(), 0);
}

/// Adds `fn big_expr` with `body` to the shipped ambient shader (through an include).
fn with_big_function(p: &Project, body: &str) {
    p.write(
        "shaders/lib/big.wgsl",
        &format!("fn big_expr() -> f32 {{\n    {body}\n}}\n"),
    );
    let ambient = std::fs::read_to_string(p.path("shaders/ambient.wgsl")).unwrap();
    p.write(
        "shaders/ambient.wgsl",
        &format!("#include \"lib/big.wgsl\"\n{ambient}"),
    );
}

// 2. A WGSL expression of 20,000 terms overflowed the stack (SIGABRT) in `check`.
#[test]
fn wgsl_expression_of_20000_terms_or_nesting_is_an_error_not_a_stack_overflow() {
    let terms = vec!["1.0"; 20_000].join(" + ");
    let p = Project::new();
    with_big_function(&p, &format!("return {terms};"));
    fails(
        &["check", &p.arg(GRAPH)],
        1,
        &["lib/big.wgsl:2:5", "operators"],
    );
    let p = Project::new();
    let nested = format!("return {}1.0{};", "(".repeat(20_000), ")".repeat(20_000));
    with_big_function(&p, &nested);
    fails(&["check", &p.arg(GRAPH)], 1, &["lib/big.wgsl:2:", "nested"]);
}

#[test]
fn long_expression_within_the_bound_is_parsed_on_a_large_stack() {
    // 16,000 terms overflow the 8 MiB of a main thread in naga's recursion.
    let p = Project::new();
    with_big_function(&p, &format!("return {};", vec!["1.0"; 16_000].join(" + ")));
    let out = passgraph(&["check", &p.arg(GRAPH)]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

// 2. 20,000 nested includes overflowed the stack in the include step.
#[test]
fn chain_of_20000_nested_includes_is_an_error_not_a_stack_overflow() {
    let p = Project::new();
    for i in 0..20_000 {
        p.write(
            &format!("shaders/chain/{i}.wgsl"),
            &format!("#include \"{}.wgsl\"\n", i + 1),
        );
    }
    p.write("shaders/chain/20000.wgsl", "fn chain_end() {}\n");
    let ambient = std::fs::read_to_string(p.path("shaders/ambient.wgsl")).unwrap();
    p.write(
        "shaders/ambient.wgsl",
        &format!("#include \"chain/0.wgsl\"\n{ambient}"),
    );
    fails(
        &["check", &p.arg(GRAPH)],
        1,
        &["chain/63.wgsl:1", "nested more than 64 deep"],
    );
}

// 6. A key given twice in a RON map silently kept the last value.
#[test]
fn duplicate_key_in_resources_bind_or_params_is_an_error_naming_key_and_line() {
    let p = Project::new();
    p.edit(
        GRAPH,
        r#""l0": Texture(format: Rgba32Float),"#,
        "\"l0\": Texture(format: Rgba32Float),\n        \"l0\": Texture(format: Rgba16Float),",
    );
    let line = std::fs::read_to_string(p.path(GRAPH))
        .unwrap()
        .lines()
        .position(|l| l.contains("Rgba16Float"))
        .unwrap()
        + 1;
    fails(
        &["check", &p.arg(GRAPH)],
        1,
        &[&format!("pathtracer.ron:{line}:"), "duplicate key \"l0\""],
    );

    let p = Project::new();
    p.edit(
        GRAPH,
        r#""ray_count": "rays_intersect","#,
        r#""ray_count": "rays_intersect", "ray_count": "rays_ambient","#,
    );
    fails(
        &["check", &p.arg(GRAPH)],
        1,
        &["pathtracer.ron:", "duplicate key \"ray_count\""],
    );

    let p = Project::new();
    let pass = std::fs::read_to_string(p.path("passes/ambient.ron")).unwrap();
    let param = pass
        .split("params: {")
        .nth(1)
        .and_then(|rest| rest.split('}').next())
        .expect("ambient.ron declares params")
        .trim()
        .trim_end_matches(',');
    p.write(
        "passes/ambient.ron",
        &pass.replacen(param, &format!("{param}, {param}"), 1),
    );
    let key = param.split('"').nth(1).unwrap();
    fails(
        &["check", &p.arg(GRAPH)],
        1,
        &["ambient.ron:", &format!("duplicate key \"{key}\"")],
    );
}

// 9. The Rust type name `PassInstanceDecl` leaked into RON errors.
#[test]
fn ron_errors_name_the_schema_not_rust_types() {
    let p = Project::new();
    p.edit(
        GRAPH,
        r#"(name: "intersect", pass: "intersect","#,
        r#"(pass: "intersect","#,
    );
    let stderr = fails(&["check", &p.arg(GRAPH)], 1, &["pathtracer.ron:", "name"]);
    assert!(!stderr.contains("Decl"), "{stderr}");
    let p = Project::new();
    p.edit(GRAPH, r#""l0": Texture("#, r#""l0": Textur("#);
    let stderr = fails(&["check", &p.arg(GRAPH)], 1, &["pathtracer.ron:", "Textur"]);
    assert!(!stderr.contains("Decl"), "{stderr}");
}

// 5. Sizes overflowed silently: PerPixel(4611686018427387905) became 1024 bytes, and `plan`
// printed wrapped sizes.
#[test]
fn sizes_past_2_to_the_64_bytes_are_errors_not_wrapped() {
    let p = Project::new();
    p.edit(
        GRAPH,
        r#""result": Buffer(size: PerPixel(80)"#,
        r#""result": Buffer(size: PerPixel(4611686018427387905)"#,
    );
    fails(
        &["check", &p.arg(GRAPH)],
        1,
        &[
            "pathtracer.ron",
            "'result'",
            "PerPixel(4611686018427387905)",
            "2^64",
        ],
    );
    let graph = root().join(GRAPH);
    fails(
        &[
            "plan",
            graph.to_str().unwrap(),
            "--size",
            "4294967295x4294967295",
        ],
        1,
        &["pathtracer.ron", "4294967295x4294967295", "2^64", "--size"],
    );
}

/// A render of the copy `p` that must stop before the first frame with `parts` in its message
/// (and not wgpu's raw "Validation Error").
fn over_limit(p: &Project, size: &str, parts: &[&str]) {
    let stderr = fails(&strs(&one_frame(p, ["--graph", GRAPH], size)), 1, parts);
    assert!(!stderr.contains("Validation Error"), "{stderr}");
    assert!(!p.path("x.png").exists());
}

// 5. Device limits ended in wgpu's raw validation text.
#[test]
fn device_limits_are_checked_before_creating_anything_naming_resource_limit_and_fix() {
    // Past the limits a graph whose passes all declare `footprint: Pixel` renders in tiles
    // (tests/tiles.rs); one that cannot be tiled still stops before creating anything.
    let p = Project::new();
    p.edit("passes/accumulate.ron", ", footprint: Pixel)", ")");
    over_limit(
        &p,
        "8192x8192",
        &[
            "pathtracer.ron",
            "resource '",
            "max_buffer_size",
            "--size",
            "pass 'accumulate'",
        ],
    );
    let p = Project::new();
    p.edit(GRAPH, "layers: 3", "layers: 100000");
    over_limit(
        &p,
        "8x8",
        &["resource 'rays'", "max_texture_array_layers", "layers"],
    );
    let p = Project::new();
    p.edit(
        "shaders/accumulate.wgsl",
        "@workgroup_size(8, 8)",
        "@workgroup_size(1024, 1024)",
    );
    over_limit(
        &p,
        "8x8",
        &[
            "pass 'accumulate'",
            "accumulate.wgsl",
            "max_compute_invocations_per_workgroup",
        ],
    );
}

// 5. `enable f16;` on a device without 16-bit floats ended in wgpu's raw validation text.
#[test]
fn enable_f16_renders_or_names_the_missing_feature() {
    let p = Project::new();
    let shader = std::fs::read_to_string(p.path("shaders/accumulate.wgsl")).unwrap();
    p.write("shaders/accumulate.wgsl", &format!("enable f16;\n{shader}"));
    let out = passgraph(&strs(&one_frame(&p, ["--graph", GRAPH], "8x8")));
    let stderr = String::from_utf8_lossy(&out.stderr);
    if !out.status.success() {
        assert_eq!(out.status.code(), Some(1), "{stderr}");
        assert_mentions(&stderr, &["pass 'accumulate'", "enable f16", "SHADER_F16"]);
        assert!(!stderr.contains("Validation Error"), "{stderr}");
    }
}

// 8. NaN and infinite params were accepted.
#[test]
fn non_finite_params_are_rejected_from_set_graph_and_pass_file() {
    for value in ["NaN", "inf", "-inf", "1e39"] {
        refused_before_rendering(
            &["--set", &format!("ambient.radius={value}")],
            1,
            &["ambient.radius", "finite"],
        );
    }
    let p = Project::new();
    p.edit(
        GRAPH,
        r#"(name: "ambient", pass: "ambient", bind: {"#,
        r#"(name: "ambient", pass: "ambient", params: { "ambient_color": Vec3(0.1, NaN, 0.1) }, bind: {"#,
    );
    fails(
        &["check", &p.arg(GRAPH)],
        1,
        &[
            "pathtracer.ron",
            "pass 'ambient'",
            "'ambient_color'",
            "finite",
        ],
    );
    let p = Project::new();
    p.edit("passes/ambient.ron", "F32(3.0e38)", "F32(inf)");
    fails(
        &["check", &p.arg(GRAPH)],
        1,
        &["ambient.ron", "'radius'", "finite"],
    );
}

#[test]
fn params_outside_their_declared_range_are_refused_naming_param_value_and_range() {
    let fused = concat!(env!("CARGO_MANIFEST_DIR"), "/graphs/pathtracer-fused.ron");
    for (set, range) in [
        ("path.samples_per_frame=0", "1 to 256"),
        ("path.light_samples=4294967295", "1 to 256"),
        ("path.bounces=0", "1 to 256"),
        ("path.sampler_kind=7", "0 to 1"),
    ] {
        refused_before_rendering(
            &["--graph", fused, "--set", set],
            1,
            &[set, "outside the param's range", range, "passes/path.ron"],
        );
    }
    refused_before_rendering(
        &["--set", "indirect.bounces=0"],
        1,
        &["indirect.bounces=0", "1 to 256", "passes/indirect.ron"],
    );
    refused_before_rendering(
        &["--set", "direct.light_samples=0"],
        1,
        &["direct.light_samples=0", "1 to 256"],
    );
    // In a graph file: the error names it and the pass file that declares the range.
    let p = Project::new();
    p.edit(
        GRAPH,
        r#"(name: "ambient", pass: "ambient", bind: {"#,
        r#"(name: "ambient", pass: "ambient", params: { "radius": F32(-1.0) }, bind: {"#,
    );
    fails(
        &["check", &p.arg(GRAPH)],
        1,
        &[
            "pathtracer.ron: pass 'ambient': param 'radius' is -1, outside its range 0 to",
            "passes/ambient.ron",
        ],
    );
    // A range that does not hold its own default, or names no param, is the pass file's error.
    let p = Project::new();
    p.edit(
        "passes/ambient.ron",
        "\"sampler_kind\": (0, 1)",
        "\"sampler_kind\": (2, 3)",
    );
    fails(
        &["check", &p.arg(GRAPH)],
        1,
        &["ambient.ron: `ranges`: 'sampler_kind': its default U32(1) lies outside (2, 3)"],
    );
    let p = Project::new();
    p.edit(
        "passes/ambient.ron",
        "\"sampler_kind\": (0, 1)",
        "\"sampler\": (0, 1)",
    );
    fails(
        &["check", &p.arg(GRAPH)],
        1,
        &["ambient.ron: `ranges`: 'sampler' is not a param of this pass"],
    );
}

const SCENE: &str = "scenes/cornell/scene.ron";
const OBJ: &str = "scenes/cornell/cornell.obj";

/// Loads a scene of the copy `p` through the library; the error's message.
fn scene_error(p: &Project, rel: &str) -> String {
    match passgraph::scene::load_scene(&p.path(rel)) {
        Ok(_) => panic!("{rel} should not load"),
        Err(e) => e.to_string(),
    }
}

// 8. Triangles with 1e19 coordinates vanished silently (dropped as degenerate: their normal
// overflows f32). They still are not rendered, but loading says so with the file and line.
#[test]
fn triangles_whose_normal_overflows_are_reported_with_file_and_line() {
    let p = Project::new();
    p.edit(
        OBJ,
        "usemtl white\nv 552.8 0.0 0.0\n",
        "usemtl white\nv 552.8 1e19 0.0\n",
    );
    let scene = passgraph::scene::load_scene(&p.path(SCENE)).unwrap();
    assert_eq!(scene.mesh.warnings.len(), 1, "{:?}", scene.mesh.warnings);
    assert_mentions(
        &scene.mesh.warnings[0],
        &["cornell.obj:7:", "1e19", "overflows", "not rendered"],
    );
    // Through the command line, before the frames.
    let out = passgraph(&strs(&one_frame(&p, ["--scene", SCENE], "8x8")));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert_mentions(&stderr, &["warning: ", "cornell.obj:7:", "not rendered"]);

    p.write(
        "scenes/cornell/tri.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
         property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
         0 0 0\n1e19 0 0\n0 -1e19 0\n3 0 1 2\n",
    );
    p.edit(SCENE, "cornell.obj", "tri.ply");
    let scene = passgraph::scene::load_scene(&p.path(SCENE)).unwrap();
    assert_mentions(
        &scene.mesh.warnings.join("\n"),
        &["tri.ply", "-1e19", "not rendered"],
    );
    // A shipped scene warns about nothing.
    let shipped = passgraph::scene::load_scene(&root().join(SCENE)).unwrap();
    assert!(shipped.mesh.warnings.is_empty());
}

// 9. PLY errors printed the parser's `ParseError { .. }` internals over several lines.
#[test]
fn ply_errors_are_one_human_line_without_parser_internals() {
    let p = Project::new();
    p.edit(SCENE, "cornell.obj", "bad.ply");
    for (body, parts) in [
        (
            "element vertex 1\nproperty flot x\nend_header\n0\n",
            vec!["bad.ply:4:", "'property flot x'", "float"],
        ),
        (
            "element vertex 1\nproperty float x\nend_header\nx\n",
            vec!["bad.ply:6:", "'x'", "number"],
        ),
    ] {
        p.write(
            "scenes/cornell/bad.ply",
            &format!("ply\nformat ascii 1.0\n{body}"),
        );
        let message = scene_error(&p, SCENE);
        assert_mentions(&message, &parts);
        assert!(!message.contains("ParseError"), "{message}");
        assert!(!message.contains('\n'), "{message}");
    }
}

// 9. A camera 1e30 from its target was called "the same point".
#[test]
fn far_camera_is_out_of_range_and_a_near_target_is_a_valid_camera() {
    let p = Project::new();
    p.edit(SCENE, "eye: (278, 273, -800)", "eye: (278, 273, -1e30)");
    let message = scene_error(&p, SCENE);
    assert_mentions(&message, &["scene.ron:5:", "eye", "1e30", "1e18"]);
    assert!(!message.contains("same point"), "{message}");
    // 1e-30 apart: the squared length underflows, but the direction is well defined.
    let v = glam::Vec3::new;
    let camera = passgraph::scene::CameraDesc::new(
        v(0.0, 0.0, 0.0),
        v(1e-30, 0.0, 0.0),
        v(0.0, 1.0, 0.0),
        40.0,
    )
    .unwrap();
    assert_eq!(camera.basis()[0], v(1.0, 0.0, 0.0));
}

// 9. An OBJ with CR-only line endings (old Mac) reported "no triangles".
#[test]
fn obj_and_mtl_with_cr_only_line_endings_load_like_lf() {
    let p = Project::new();
    let lf = passgraph::scene::load_scene(&p.path(SCENE)).unwrap();
    for file in [OBJ, "scenes/cornell/cornell.mtl"] {
        let text = std::fs::read_to_string(p.path(file)).unwrap();
        p.write(file, &text.replace('\n', "\r"));
    }
    let cr = passgraph::scene::load_scene(&p.path(SCENE)).unwrap();
    assert_eq!(cr.mesh, lf.mesh);
}

// 9. Non-UTF-8 files were reported without a line number.
#[test]
fn non_utf8_graph_shader_scene_or_mesh_names_the_line() {
    let corrupt = |p: &Project, rel: &str, line: usize| {
        let text = std::fs::read(p.path(rel)).unwrap();
        let at = text
            .iter()
            .enumerate()
            .filter(|&(_, &b)| b == b'\n')
            .nth(line - 2)
            .unwrap()
            .0
            + 1;
        let mut bytes = text.clone();
        bytes.insert(at, 0xff);
        std::fs::write(p.path(rel), bytes).unwrap();
    };
    let p = Project::new();
    corrupt(&p, GRAPH, 3);
    fails(
        &["check", &p.arg(GRAPH)],
        1,
        &["pathtracer.ron", "line 3", "UTF-8"],
    );
    let p = Project::new();
    corrupt(&p, "shaders/lib/rng.wgsl", 2);
    fails(
        &["check", &p.arg(GRAPH)],
        1,
        &["rng.wgsl", "line 2", "UTF-8"],
    );
    let p = Project::new();
    corrupt(&p, SCENE, 4);
    assert_mentions(&scene_error(&p, SCENE), &["scene.ron", "line 4", "UTF-8"]);
    let p = Project::new();
    corrupt(&p, OBJ, 9);
    assert_mentions(&scene_error(&p, SCENE), &["cornell.obj", "line 9", "UTF-8"]);
}

// 9. `view` without a display printed a path inside the cargo registry.
#[test]
fn view_without_a_display_says_so_without_a_source_path() {
    let out = Command::new(env!("CARGO_BIN_EXE_passgraph"))
        .args(["view", "--frames", "1", "--size", "8x8"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert_mentions(&stderr, &["no display", "Xvfb"]);
    assert!(
        !stderr.contains(".cargo") && !stderr.contains(".rs:"),
        "{stderr}"
    );
}

// 8. A bench variant's bad channel was found only after the variants before it had rendered.
#[test]
fn bench_checks_every_variant_before_rendering_any() {
    let dir = tempfile::tempdir().unwrap();
    let reference = dir.path().join("ref.exr");
    passgraph::render::image::RgbImage {
        width: 16,
        height: 16,
        pixels: vec![[0.5; 3]; 256],
    }
    .write(&reference)
    .unwrap();
    let graph = root().join(GRAPH);
    let graph = graph.to_str().unwrap();
    let out = dir.path().join("bench");
    fails(
        &[
            "bench",
            "--reference",
            reference.to_str().unwrap(),
            "--size",
            "16x16",
            "--frames",
            "1000000",
            "--graph",
            graph,
            "--graph",
            &format!("{graph}@nosuch"),
            "--out",
            out.to_str().unwrap(),
        ],
        1,
        &["'nosuch'"],
    );
    let written = std::fs::read_dir(&out).map_or(0, |d| d.count());
    assert_eq!(written, 0, "nothing is rendered or written");
}

// 8. A camera path's reference was read only when its segment came, after earlier frames.
#[test]
fn camera_path_reference_of_another_size_is_refused_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    passgraph::render::image::RgbImage {
        width: 8,
        height: 8,
        pixels: vec![[0.5; 3]; 64],
    }
    .write(&dir.path().join("small.exr"))
    .unwrap();
    let path = dir.path().join("path.ron");
    std::fs::write(
        &path,
        "CameraPath([(frames: 1000000), (frames: 1, reference: \"small.exr\")])",
    )
    .unwrap();
    let out = dir.path().join("x.png");
    fails(
        &[
            "render",
            "--camera-path",
            path.to_str().unwrap(),
            "--size",
            "16x16",
            "--out",
            out.to_str().unwrap(),
        ],
        1,
        &["small.exr", "8x8", "16x16"],
    );
    assert!(!out.exists());
}
