//! The executor on a real device (Mesa lavapipe on machines without a GPU): fixture graphs run
//! end to end and their outputs are read back.

use passgraph::gpu::{Executor, GpuContext, GpuError, ProvidedData};
use passgraph::graph::shader_source::ShaderSource;
use passgraph::{Plan, compile_file};
use std::path::Path;
use std::sync::OnceLock;

/// One device for all tests: creating one costs far more than any test here.
fn ctx() -> &'static GpuContext {
    static CTX: OnceLock<GpuContext> = OnceLock::new();
    CTX.get_or_init(|| GpuContext::new(None).unwrap_or_else(|e| panic!("{e}")))
}

fn plan(graph: &str, size: [u32; 2]) -> Plan {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/graphs")
        .join(graph);
    compile_file(&path, size).unwrap_or_else(|e| panic!("{graph} should compile: {e}"))
}

fn executor(plan: &Plan, provided: &ProvidedData) -> Executor {
    Executor::new(ctx(), plan, provided).unwrap_or_else(|e| panic!("executor: {e}"))
}

fn run_frames(executor: &mut Executor, frames: usize) {
    for _ in 0..frames {
        executor
            .run_frame(ctx())
            .unwrap_or_else(|e| panic!("frame: {e}"));
    }
}

fn read(executor: &Executor, name: &str) -> Vec<u8> {
    executor
        .read_resource(name)
        .unwrap_or_else(|e| panic!("reading {name}: {e}"))
}

fn f16_channels(bytes: &[u8]) -> Vec<f32> {
    bytes
        .chunks_exact(2)
        .map(|b| half::f16::from_le_bytes([b[0], b[1]]).to_f32())
        .collect()
}

fn f32_channels(bytes: &[u8]) -> Vec<f32> {
    bytemuck::pod_collect_to_vec(bytes)
}

/// Every channel of every texel equals `value`; on failure, says where.
fn assert_all(channels: &[f32], value: f32, what: &str) {
    if let Some((i, v)) = channels.iter().enumerate().find(|(_, v)| **v != value) {
        panic!(
            "{what}: channel {} of texel {} is {v}, expected {value}",
            i % 4,
            i / 4
        );
    }
}

#[test]
fn chain_output_is_the_fill_value_everywhere() {
    let plan = plan("chain.ron", [40, 24]);
    let mut executor = executor(&plan, &ProvidedData::default());
    run_frames(&mut executor, 1);
    let out = f16_channels(&read(&executor, "out"));
    assert_eq!(out.len(), 40 * 24 * 4);
    assert_all(&out, 1.0, "out");
}

#[test]
fn reuse_fixture_carries_the_fill_value_through_its_shared_texture() {
    let size = [32, 32];
    let plan = plan("reuse.ron", size);
    let physical = |name: &str| plan.resources[plan.resource_id(name).unwrap()].physical;
    assert!(physical("t1").is_some());
    assert_eq!(physical("t1"), physical("t3"));
    assert_eq!(physical("t1"), physical("t4"));

    let mut executor = executor(&plan, &ProvidedData::default());
    run_frames(&mut executor, 1);
    let out = f16_channels(&read(&executor, "out"));
    assert_eq!(out.len(), 32 * 32 * 4);
    // Only the quarter that went through the half-size texture carries data: c4 reads `half`
    // with full-size coordinates, and out-of-bounds loads return zero on robust devices.
    let (w, h) = (size[0] as usize, size[1] as usize);
    let covered: Vec<f32> = (0..h / 2)
        .flat_map(|y| out[(y * w) * 4..(y * w + w / 2) * 4].to_vec())
        .collect();
    assert_all(&covered, 1.0, "out, top-left quarter");
}

#[test]
fn full_size_chain_through_a_shared_texture_gives_the_fill_value_everywhere() {
    let plan = plan("gpu_reuse.ron", [24, 40]);
    let physical = |name: &str| plan.resources[plan.resource_id(name).unwrap()].physical;
    assert_eq!(physical("t1"), physical("t3"));
    let mut executor = executor(&plan, &ProvidedData::default());
    run_frames(&mut executor, 2);
    let out = f16_channels(&read(&executor, "out"));
    assert_eq!(out.len(), 24 * 40 * 4);
    assert_all(&out, 0.75, "out");
}

#[test]
fn graph_param_reaches_the_shader_and_set_params_replaces_it() {
    // culling.ron sets the fill pass's `value` to 0.25 (the pass default is 1.0).
    let plan = plan("culling.ron", [16, 16]);
    let mut executor = executor(&plan, &ProvidedData::default());
    run_frames(&mut executor, 1);
    assert_all(&f16_channels(&read(&executor, "out")), 0.25, "out");

    executor
        .set_params("fill", &0.5f32.to_le_bytes())
        .unwrap_or_else(|e| panic!("{e}"));
    run_frames(&mut executor, 1);
    assert_all(
        &f16_channels(&read(&executor, "out")),
        0.5,
        "out after set_params",
    );
}

#[test]
fn set_params_rejects_a_wrong_length_and_unknown_passes() {
    let plan = plan("culling.ron", [8, 8]);
    let mut executor = executor(&plan, &ProvidedData::default());
    let err = executor.set_params("fill", &[0u8; 8]).unwrap_err();
    assert!(matches!(err, GpuError::WrongParamsSize { .. }), "{err}");
    assert!(err.to_string().contains("'fill'"), "{err}");
    let err = executor.set_params("final", &[0u8; 4]).unwrap_err();
    assert!(matches!(err, GpuError::NoParams { .. }), "{err}");
    let err = executor.set_params("nope", &[0u8; 4]).unwrap_err();
    assert!(err.to_string().contains("'nope'"), "{err}");
}

#[test]
fn override_constant_reaches_the_pipeline() {
    // out = mix(current, history, HISTORY_WEIGHT) with current = 1; the graph sets the weight
    // to 0.75 (the shader's default is 0.9), and store_history copies out into history.
    let size = [16, 8];
    let plan = plan("history.ron", size);
    let mut executor = executor(&plan, &ProvidedData::default());
    let zeros = vec![0u8; 16 * 8 * 8];
    executor
        .write_resource("history", &zeros)
        .unwrap_or_else(|e| panic!("{e}"));
    run_frames(&mut executor, 1);
    assert_all(&f16_channels(&read(&executor, "out")), 0.25, "frame 1");
    // The persistent history now holds 0.25: 0.25 + 0.75 * 0.25.
    run_frames(&mut executor, 1);
    assert_all(&f16_channels(&read(&executor, "out")), 0.4375, "frame 2");
}

#[test]
fn persistent_buffer_keeps_its_content_across_frames() {
    let plan = plan("gpu_counter.ron", [8, 8]);
    let mut executor = executor(&plan, &ProvidedData::default());
    run_frames(&mut executor, 3);
    assert_eq!(read(&executor, "counter"), 3u32.to_le_bytes());
}

#[test]
fn read_write_rgba32float_storage_texture_accumulates_across_frames() {
    let plan = plan("gpu_accumulate.ron", [12, 10]);
    let result = Executor::new(ctx(), &plan, &ProvidedData::default());
    let mut executor = match result {
        Ok(executor) => executor,
        // WebGPU only guarantees read_write for r32 formats; lavapipe supports it here too.
        Err(GpuError::UnsupportedStorageTexture { .. })
            if !ctx().adapter_info().name.contains("llvmpipe") =>
        {
            return;
        }
        Err(e) => panic!("{e}"),
    };
    run_frames(&mut executor, 3);
    assert_all(&f32_channels(&read(&executor, "sum")), 3.0, "sum");
}

#[test]
fn write_then_read_round_trips_a_layered_texture_without_row_padding() {
    // 20 rgba32float texels are 320 bytes a row, which the copy pads to 512.
    let (w, h, layers) = (20, 12, 3);
    let plan = plan("seed.ron", [w, h]);
    let mut executor = executor(&plan, &seed_provided());
    let texels: Vec<f32> = (0..w * h * layers * 4).map(|i| i as f32).collect();
    let bytes: Vec<u8> = bytemuck::cast_slice(&texels).to_vec();
    executor
        .write_resource("rays", &bytes)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(f32_channels(&read(&executor, "rays")), texels);
}

#[test]
fn transfers_check_names_and_sizes() {
    let plan = plan("chain.ron", [8, 8]);
    let mut executor = executor(&plan, &ProvidedData::default());
    let err = executor.write_resource("out", &[0u8; 3]).unwrap_err();
    assert!(matches!(err, GpuError::WrongSize { .. }), "{err}");
    assert!(err.to_string().contains("'out'"), "{err}");
    let err = executor.read_resource("missing").unwrap_err();
    assert!(matches!(err, GpuError::UnknownResource { .. }), "{err}");
    assert!(err.to_string().contains("'missing'"), "{err}");
    let err = executor.read_resource("camera").unwrap_err();
    assert!(
        matches!(err, GpuError::ProvidedNotGraphOwned { .. }),
        "{err}"
    );
    let err = executor.update_uniform("scene.bvh", &[0u8; 4]).unwrap_err();
    assert!(matches!(err, GpuError::NotAProvidedUniform { .. }), "{err}");
    // A provided uniform this graph never binds is simply not needed.
    executor
        .update_uniform("frame", &[0u8; 16])
        .unwrap_or_else(|e| panic!("{e}"));
}

/// Everything seed.ron binds; `scene.lights` is empty, as for a scene without lights.
fn seed_provided() -> ProvidedData {
    let vec4s = |n: usize| vec![0u8; n * 16];
    // eye, forward, right, up: a zero forward would make every ray direction NaN.
    let camera: [f32; 16] = [
        0.0, 0.0, -1.0, 1.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0,
    ];
    ProvidedData::default()
        .with_buffer("scene.triangles", vec4s(3))
        .with_buffer("scene.materials", vec4s(1))
        .with_buffer("scene.lights", Vec::new())
        .with_buffer("scene.bvh", vec4s(2))
        .with_buffer("camera", bytemuck::cast_slice(&camera).to_vec())
        .with_buffer("frame", vec![0u8; 16])
}

#[test]
fn seed_graph_runs_with_an_empty_provided_buffer() {
    let (w, h) = (16, 16);
    let plan = plan("seed.ron", [w, h]);
    let mut executor = executor(&plan, &seed_provided());
    for index in 0..2u32 {
        let frame: Vec<u8> = [index, index, w, h]
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        executor
            .update_uniform("frame", &frame)
            .unwrap_or_else(|e| panic!("{e}"));
        run_frames(&mut executor, 1);
    }
    let result = f32_channels(&read(&executor, "result"));
    assert_eq!(result.len() as u32, w * h * 5 * 4);
    assert!(result.iter().all(|v| v.is_finite()));
}

#[test]
fn missing_provided_buffer_is_an_error_naming_it() {
    let plan = plan("seed.ron", [8, 8]);
    let mut provided = seed_provided();
    provided.buffers.remove("scene.lights");
    let err = Executor::new(ctx(), &plan, &provided)
        .err()
        .expect("an error");
    assert!(matches!(err, GpuError::MissingProvided { .. }), "{err}");
    let message = err.to_string();
    assert!(message.contains("'scene.lights'"), "{message}");
    assert!(message.contains("'direct'"), "{message}");
}

#[test]
fn scene_override_reaches_the_pipeline_and_is_required() {
    let plan = plan("gpu_scene_override.ron", [8, 8]);
    let err = Executor::new(ctx(), &plan, &ProvidedData::default())
        .err()
        .expect("an error");
    assert!(matches!(err, GpuError::MissingOverride { .. }), "{err}");
    assert!(err.to_string().contains("'scene_light_count'"), "{err}");

    let provided = ProvidedData::default().with_override("scene_light_count", 3.0);
    let mut executor = executor(&plan, &provided);
    run_frames(&mut executor, 1);
    assert_all(&f32_channels(&read(&executor, "out")), 3.0, "out");
}

#[test]
fn a_shader_wgpu_rejects_is_an_error_naming_the_pass() {
    let mut plan = plan("chain.ron", [8, 8]);
    let copy2 = plan.passes.iter_mut().find(|p| p.name == "copy2").unwrap();
    copy2.shader = ShaderSource::from_code(
        copy2.shader.path.clone(),
        "@compute @workgroup_size(1) fn main() { let x: u32 = 1.5; }".into(),
    );
    let err = Executor::new(ctx(), &plan, &ProvidedData::default())
        .err()
        .expect("an error");
    assert!(matches!(err, GpuError::CreatePass { .. }), "{err}");
    assert!(err.to_string().contains("'copy2'"), "{err}");
}

#[test]
fn stage_times_are_one_finite_non_negative_number_per_stage() {
    let plan = plan("chain.ron", [16, 16]);
    let mut executor = executor(&plan, &ProvidedData::default());
    if ctx().adapter_info().name.contains("llvmpipe") {
        assert!(
            ctx().timestamps_supported(),
            "lavapipe has timestamp queries"
        );
    }
    if !ctx().timestamps_supported() {
        assert_eq!(executor.last_stage_times_ms(), None);
        return;
    }
    assert_eq!(executor.last_stage_times_ms(), None, "before any frame");
    run_frames(&mut executor, 2);
    let times = executor.last_stage_times_ms().expect("stage times");
    assert_eq!(times.len(), plan.stages.len());
    assert!(
        times.iter().all(|t| t.is_finite() && *t >= 0.0),
        "{times:?}"
    );
    // lavapipe writes timestamps inside compute passes too: one time per kept pass.
    let frame = executor.last_frame_times().expect("frame times");
    let passes = frame.passes.expect("per-pass times on lavapipe");
    assert_eq!(passes.len(), plan.passes.len());
    assert!(
        passes.iter().all(|t| t.is_finite() && *t >= 0.0),
        "{passes:?}"
    );
}

#[test]
fn an_adapter_filter_matching_nothing_lists_the_adapters() {
    let err = GpuContext::new(Some("no such adapter 1234"))
        .err()
        .expect("an error");
    assert!(matches!(err, GpuError::NoMatchingAdapter { .. }), "{err}");
    let message = err.to_string();
    assert!(message.contains("'no such adapter 1234'"), "{message}");
    assert!(message.contains(&ctx().adapter_info().name), "{message}");
}

#[test]
fn texel_views_hold_a_provided_buffer_word_for_word_across_rows() {
    // 16,385 texels: more than one row on any device (rows are at most 16,384 texels wide on
    // lavapipe, 8,192 under WebGPU's defaults), with a partial last texel.
    let words: Vec<u32> = (0..4 * 16_385 - 3)
        .map(|i: u32| i.wrapping_mul(0x9e37_79b9))
        .collect();
    let max_row = ctx().device().limits().max_texture_dimension_2d;
    assert!(
        16_385 > max_row,
        "rows of {max_row} texels: the view fits one row"
    );
    let mut provided =
        ProvidedData::default().with_buffer("scene.triangles", bytemuck::cast_slice(&words));
    // scene.wgsl declares the scene overrides; their values do not matter here.
    for name in passgraph::render::provided::path_tracer()
        .overrides()
        .iter()
        .map(|o| o.name.as_str())
    {
        provided = provided.with_override(name, 0.0);
    }
    let plan = plan("gpu_texel_view.ron", [512, 512]);
    let mut executor = executor(&plan, &provided);
    run_frames(&mut executor, 1);
    let copies: Vec<u32> = bytemuck::cast_slice(&read(&executor, "copies")).to_vec();
    const WORDS: usize = 262_144;
    for (form, copy) in ["buffer", "storage texel view", "sampled texel view"]
        .iter()
        .zip(copies.chunks_exact(WORDS))
    {
        let mismatch = (0..words.len()).find(|&i| copy[i] != words[i]);
        assert_eq!(mismatch, None, "{form}: first differing word");
    }
}

#[test]
fn raster_pass_draws_with_depth_test_and_a_compute_pass_reads_it() {
    let plan = plan("raster.ron", [16, 8]);
    assert_eq!(plan.stage_names(), [["draw"], ["copy"]]);
    let err = Executor::new(ctx(), &plan, &ProvidedData::default())
        .err()
        .expect("an error");
    assert!(err.to_string().contains("'scene_triangle_count'"), "{err}");
    // Two triangles: the nearer, drawn first, must survive the farther one drawn over it.
    let provided = ProvidedData::default().with_override("scene_triangle_count", 2.0);
    let mut executor = executor(&plan, &provided);
    run_frames(&mut executor, 2);
    assert_all(&f16_channels(&read(&executor, "out")), 0.5, "out");
}

#[test]
fn indirect_dispatch_runs_the_workgroups_an_earlier_pass_wrote() {
    let plan = plan("gpu_indirect.ron", [8, 8]);
    let count = plan.passes.iter().find(|p| p.name == "count").unwrap();
    let args = plan
        .resources
        .iter()
        .position(|r| r.name == "args")
        .unwrap();
    assert_eq!(count.indirect.map(|(r, o)| (r.0, o)), Some((args, 16)));
    let mut executor = executor(&plan, &ProvidedData::default());
    run_frames(&mut executor, 2);
    assert_eq!(read(&executor, "counter"), 48u32.to_le_bytes());
}
