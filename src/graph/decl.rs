//! The RON schema: what users write in `passes/*.ron` and `graphs/*.ron`.

use super::format::TextureFormat;
use super::param::ParamValue;
use serde::Deserialize;
use std::collections::BTreeMap;

/// `passes/<name>.ron`: a shader entry point, how to dispatch it, and its params with defaults.
#[derive(Clone, Debug, Deserialize)]
#[serde(rename = "Pass", deny_unknown_fields)]
pub struct PassDecl {
    /// Path of the WGSL file, relative to the `shaders/` directory beside `passes/`.
    pub shader: String,
    #[serde(default = "default_entry")]
    pub entry: String,
    #[serde(default)]
    pub dispatch: Dispatch,
    #[serde(default)]
    pub params: BTreeMap<String, ParamValue>,
}

fn default_entry() -> String {
    "main".to_string()
}

/// How many workgroups a pass launches.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
pub enum Dispatch {
    /// One invocation per output pixel: ceil(size / workgroup_size) workgroups.
    #[default]
    PerPixel,
    /// A fixed number of workgroups (x, y, z).
    Workgroups(u32, u32, u32),
}

/// `graphs/<name>.ron`: resources, pass instances in program order, and outputs.
#[derive(Clone, Debug, Deserialize)]
#[serde(rename = "Graph", deny_unknown_fields)]
pub struct GraphDecl {
    #[serde(default)]
    pub resources: BTreeMap<String, ResourceDecl>,
    pub passes: Vec<PassInstanceDecl>,
    pub outputs: Vec<String>,
}

/// A resource the graph owns. Persistent resources keep their content across frames.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum ResourceDecl {
    Texture {
        format: TextureFormat,
        #[serde(default)]
        size: TextureSize,
        #[serde(default = "one")]
        layers: u32,
        #[serde(default)]
        persistent: bool,
    },
    Buffer {
        size: BufferSize,
        #[serde(default)]
        persistent: bool,
    },
}

fn one() -> u32 {
    1
}

impl ResourceDecl {
    pub fn persistent(&self) -> bool {
        match self {
            ResourceDecl::Texture { persistent, .. } | ResourceDecl::Buffer { persistent, .. } => {
                *persistent
            }
        }
    }
}

/// A texture's size: the output's, a fraction of it, or absolute.
#[derive(Clone, Copy, Debug, Default, PartialEq, Deserialize)]
pub enum TextureSize {
    #[default]
    Output,
    /// The output size times this factor, rounded, at least 1 texel.
    Scaled(f32),
    Absolute(u32, u32),
}

/// A buffer's size: absolute, or so many bytes per output pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
pub enum BufferSize {
    Bytes(u64),
    PerPixel(u64),
}

/// One use of a pass in a graph.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PassInstanceDecl {
    /// Unique within the graph; several instances may share one `pass`.
    pub name: String,
    /// The pass file: `passes/<pass>.ron`.
    pub pass: String,
    /// Shader binding name -> resource name.
    #[serde(default)]
    pub bind: BTreeMap<String, String>,
    /// Overrides of the pass's param defaults.
    #[serde(default)]
    pub params: BTreeMap<String, ParamValue>,
}
