//! Every way setting up or running a plan on the GPU can fail, each naming the adapter, pass or
//! resource at fault.

use passgraph_graph::error::list;
use thiserror::Error;

/// What to tell a user whose machine exposes no adapter passgraph can use.
pub const NO_ADAPTER_HINT: &str = "no Vulkan adapter found (passgraph runs on Vulkan, Metal or DX12, not on wgpu's GL backend, whose translation of its shaders Mesa's GL rejects); install Mesa's software Vulkan driver (lavapipe): scripts/setup, or on Debian 12 apt-get install -t bookworm-backports mesa-vulkan-drivers (elsewhere apt-get install mesa-vulkan-drivers)";

#[derive(Debug, Error)]
pub enum GpuError {
    #[error("{}: {what}: {reason}", graph.display())]
    OverLimit {
        graph: std::path::PathBuf,
        /// The resource or pass at fault.
        what: String,
        reason: String,
    },

    #[error("{NO_ADAPTER_HINT}")]
    NoAdapter,

    #[error(
        "WGPU_BACKEND='{value}' names no backend passgraph runs on (vulkan, metal, dx12); wgpu's GL backend cannot run its shaders: unset WGPU_BACKEND or set it to vulkan"
    )]
    UnsupportedBackend { value: String },

    #[error(
        "no adapter's description contains '{filter}' (adapters: {}); GL adapters are never used",
        list(available)
    )]
    NoMatchingAdapter {
        filter: String,
        available: Vec<String>,
    },

    #[error("no adapter can present to the window (adapters: {})", list(available))]
    NoPresentingAdapter { available: Vec<String> },

    #[error("adapter '{adapter}' refused to create a device: {source}")]
    RequestDevice {
        adapter: String,
        source: wgpu::RequestDeviceError,
    },

    #[error(
        "pass '{pass}' binds the provided resource '{resource}', but no data was provided for it"
    )]
    MissingProvided { pass: String, resource: String },

    #[error("pass '{pass}' uses the scene override '{name}', but no value was provided for it")]
    MissingOverride { pass: String, name: String },

    #[error("no resource named '{name}' in the graph (resources: {})", list(known))]
    UnknownResource { name: String, known: Vec<String> },

    #[error("resource '{name}' has no GPU object: no kept pass uses it")]
    Unallocated { name: String },

    #[error("resource '{name}' is provided by the framework; {what}")]
    ProvidedNotGraphOwned { name: String, what: &'static str },

    #[error(
        "'{name}' is not a provided uniform (provided uniforms: {})",
        list(uniforms)
    )]
    NotAProvidedUniform { name: String, uniforms: Vec<String> },

    #[error("resource '{name}' holds {expected} bytes, but {got} bytes were given")]
    WrongSize {
        name: String,
        expected: u64,
        got: u64,
    },

    #[error("no kept pass named '{pass}' (passes: {})", list(known))]
    UnknownPass { pass: String, known: Vec<String> },

    #[error("pass '{pass}' has no params uniform")]
    NoParams { pass: String },

    #[error("pass '{pass}': the params uniform holds {expected} bytes, but {got} bytes were given")]
    WrongParamsSize {
        pass: String,
        expected: u64,
        got: u64,
    },

    #[error(
        "pass '{pass}' binding '{binding}': adapter '{adapter}' does not support {access} storage textures in {format}"
    )]
    UnsupportedStorageTexture {
        pass: String,
        binding: String,
        adapter: String,
        format: String,
        access: String,
    },

    #[error(
        "pass '{pass}' dispatches {workgroups:?} workgroups, but the device allows at most {max} per dimension"
    )]
    TooManyWorkgroups {
        pass: String,
        workgroups: [u32; 3],
        max: u32,
    },

    #[error("resource '{name}': cannot create its GPU object: {message}")]
    CreateResource { name: String, message: String },

    #[error("pass '{pass}': cannot create its pipeline or bind groups: {message}")]
    CreatePass { pass: String, message: String },

    #[error("the GPU rejected the frame: {message}")]
    Frame { message: String },

    #[error("resource '{name}': {message}")]
    Transfer { name: String, message: String },
}
