//! passgraph's executor: running a compiled `Plan` (passgraph-graph) on wgpu: a headless
//! device, the plan's resources, and an executor that records one compute pass per stage each
//! frame.

#![allow(clippy::result_large_err)]

pub mod context;
mod convert;
pub mod error;
mod error_scope;
pub mod executor;
pub mod limits;
mod pass;
pub mod provided_data;
pub mod readback;
mod resources;
pub mod specialise;
pub mod texels;
mod timing;

pub use context::GpuContext;
pub use error::GpuError;
pub use executor::Executor;
pub use pass::{pass_constants, specialise_pass};
pub use provided_data::ProvidedData;
pub use timing::FrameTimes;
