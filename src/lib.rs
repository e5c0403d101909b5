//! passgraph: a render-graph framework on wgpu whose passes are WGSL compute shaders declared in
//! RON. The `graph` module compiles graph files to a `Plan` without touching a GPU.

// GraphError carries paths and names for its messages; it is built once, on the error path.
#![allow(clippy::result_large_err)]

pub mod atomic_write;
pub mod bench;
pub mod gpu;
pub mod graph;
pub mod graphtest;
pub mod render;
pub mod scene;
pub mod text_file;
pub mod view;

pub use graph::compile::{compile, compile_file};
pub use graph::dot::to_dot;
pub use graph::error::GraphError;
pub use graph::load::{LoadedGraph, load_graph};
pub use graph::plan::Plan;
