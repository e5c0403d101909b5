//! The second renderer, on the framework crates alone (passgraph-graph and passgraph-gpu): the
//! application registers what it provides, compiles its graph against that, hands the executor
//! the data, runs a frame and reads the output back.

use passgraph_gpu::{Executor, GpuContext, ProvidedData};
use passgraph_graph::compile::compile_file;
use passgraph_graph::param::ParamType;
use passgraph_graph::plan::Plan;
use passgraph_graph::provided::{ProvidedKind, ProvidedSet};
use std::path::{Path, PathBuf};

/// What this application provides to its graphs.
pub fn provided_set() -> ProvidedSet {
    ProvidedSet::new()
        .override_constant(
            "triangle_count",
            ParamType::U32,
            "triangles the draw pass draws",
        )
        .resource(
            "grade",
            ProvidedKind::Uniform,
            "rgb gain of the grade pass (vec4, w unused)",
        )
}

/// The graph file shipped beside this file.
pub fn graph_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/postprocess/graphs/postprocess.ron")
}

pub fn compile(size: [u32; 2]) -> Result<Plan, String> {
    compile_file(&graph_path(), size, &provided_set()).map_err(|e| e.to_string())
}

/// One frame of `size` with `triangles` drawn and graded by `gain`: the output's RGBA texels,
/// row by row.
pub fn render(
    ctx: &GpuContext,
    size: [u32; 2],
    triangles: u32,
    gain: [f32; 3],
) -> Result<Vec<[f32; 4]>, String> {
    let plan = compile(size)?;
    let grade: Vec<u8> = [gain[0], gain[1], gain[2], 0.0]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let data = ProvidedData::default()
        .with_buffer("grade", grade)
        .with_override("triangle_count", f64::from(triangles));
    let mut executor = Executor::new(ctx, &plan, &data).map_err(|e| e.to_string())?;
    executor.run_frame(ctx).map_err(|e| e.to_string())?;
    let bytes = executor
        .read_resource("graded")
        .map_err(|e| e.to_string())?;
    Ok(bytes
        .chunks_exact(16)
        .map(|t| {
            let f =
                |i: usize| f32::from_le_bytes([t[4 * i], t[4 * i + 1], t[4 * i + 2], t[4 * i + 3]]);
            [f(0), f(1), f(2), f(3)]
        })
        .collect())
}
