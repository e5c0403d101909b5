//! passgraph's graph compiler: pure data, no GPU. RON declarations and shader reflection in,
//! a `Plan` of stages, barriers and resource allocations out. It knows no application: what an
//! application provides (scene buffers, override constants) comes in as a `ProvidedSet`.

// GraphError carries paths and names for its messages; it is built once, on the error path.
#![allow(clippy::result_large_err)]

mod attachments;
pub mod bind;
pub mod compile;
pub mod compose;
pub mod contract;
pub mod cull;
pub mod decl;
pub mod deps;
pub mod dot;
pub mod error;
pub mod format;
pub mod id;
pub mod interface;
pub mod lifetime;
pub mod load;
pub mod param;
pub mod plan;
pub mod plan_chart;
pub mod plan_text;
pub mod provided;
pub mod reflect;
pub mod ron_file;
pub mod schedule;
pub mod set_param;
pub mod shader_source;
pub mod shared_params;
pub mod text_file;
