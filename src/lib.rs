//! passgraph: a render-graph framework on wgpu whose passes are WGSL compute shaders declared in
//! RON, and its first application, a progressive path tracer. The layers are crates: `graph`
//! (passgraph-graph) compiles graph files to a `Plan` without touching a GPU, `gpu`
//! (passgraph-gpu) runs a plan on wgpu; this crate is the path tracer (scene, render, bench,
//! view) and re-exports both under their old paths.

// GraphError carries paths and names for its messages; it is built once, on the error path.
#![allow(clippy::result_large_err)]

pub mod atomic_write;
pub mod bench;
pub mod bsdf;
pub mod builtin;
pub mod graphtest;
pub mod material;
pub mod render;
pub mod scene;
pub mod view;

pub use passgraph_gpu as gpu;
pub use passgraph_graph as graph;
pub use passgraph_graph::text_file;

pub use graph::dot::to_dot;
pub use graph::error::GraphError;
pub use graph::load::{LoadedGraph, load_graph};
pub use graph::plan::Plan;

use std::path::Path;

/// Loads and compiles a graph file for the path tracer: its passes may bind what
/// [`render::provided::path_tracer`] provides. Another application passes its own set to
/// [`graph::compile::compile_file`].
pub fn compile_file(path: &Path, output_size: [u32; 2]) -> Result<Plan, GraphError> {
    graph::compile::compile_file(path, output_size, render::provided::path_tracer())
}

/// Compiles a loaded graph for the path tracer (see [`compile_file`]).
pub fn compile(graph: &LoadedGraph, output_size: [u32; 2]) -> Result<Plan, GraphError> {
    graph::compile::compile(graph, output_size, render::provided::path_tracer())
}
