//! What a pass's shader exposes, as reflected by naga: the contract the graph is checked against.

use super::format::{SampleKind, TextureDim, TextureFormat};
use super::param::{ParamType, ParamValue};
use std::fmt;

/// How a pass touches a resource, for hazard analysis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Access {
    Read,
    Write,
    ReadWrite,
}

impl Access {
    pub fn reads(self) -> bool {
        matches!(self, Access::Read | Access::ReadWrite)
    }
    pub fn writes(self) -> bool {
        matches!(self, Access::Write | Access::ReadWrite)
    }
}

impl fmt::Display for Access {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Access::Read => "read",
            Access::Write => "write",
            Access::ReadWrite => "read_write",
        })
    }
}

/// The kind of a shader binding: what resource it needs and how it uses it.
#[derive(Clone, Debug, PartialEq)]
pub enum BindingKind {
    /// `var<uniform>`; `size` is the struct's size in bytes.
    Uniform { size: u64 },
    /// `var<storage, read>` or `var<storage, read_write>`. `min_size` is the size of the
    /// fixed part (for a runtime-sized array: one element).
    Storage { access: Access, min_size: u64 },
    /// `texture_storage_2d[_array]<format, access>`.
    StorageTexture {
        access: Access,
        format: TextureFormat,
        dim: TextureDim,
    },
    /// `texture_2d[_array]<T>`, read with `textureLoad` or sampled.
    SampledTexture { sample: SampleKind, dim: TextureDim },
}

impl BindingKind {
    pub fn access(&self) -> Access {
        match self {
            BindingKind::Uniform { .. } | BindingKind::SampledTexture { .. } => Access::Read,
            BindingKind::Storage { access, .. } | BindingKind::StorageTexture { access, .. } => {
                *access
            }
        }
    }

    pub fn is_texture(&self) -> bool {
        matches!(
            self,
            BindingKind::StorageTexture { .. } | BindingKind::SampledTexture { .. }
        )
    }
}

impl fmt::Display for BindingKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BindingKind::Uniform { .. } => f.write_str("var<uniform>"),
            // A read_write buffer the shader only stores to (see reflect::written_only).
            BindingKind::Storage {
                access: Access::Write,
                ..
            } => f.write_str("var<storage, read_write> (stored to only)"),
            BindingKind::Storage { access, .. } => write!(f, "var<storage, {access}>"),
            BindingKind::StorageTexture {
                access,
                format,
                dim,
            } => {
                write!(f, "texture_storage_{dim}<{format}, {access}>")
            }
            BindingKind::SampledTexture { sample, dim } => write!(f, "texture_{dim}<{sample}>"),
        }
    }
}

/// One resource binding used by the entry point.
#[derive(Clone, Debug, PartialEq)]
pub struct ShaderBinding {
    /// The WGSL variable name: what the graph binds a resource to.
    pub name: String,
    pub group: u32,
    pub binding: u32,
    pub kind: BindingKind,
    /// For an arrayed texture: the highest layer the entry point loads or stores with a
    /// constant index (`textureStore(rays, pixel, 2, ...)`), which the bound texture must have.
    pub max_constant_layer: Option<u32>,
}

/// A field of the pass's `params` uniform block.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamField {
    pub name: String,
    pub ty: ParamType,
    /// Byte offset inside the uniform block.
    pub offset: u32,
}

/// The `var<uniform> params: T` block, filled by the framework from the pass's params.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamBlock {
    pub group: u32,
    pub binding: u32,
    /// Size of the uniform struct in bytes (WGSL layout).
    pub size: u32,
    pub fields: Vec<ParamField>,
}

/// A pipeline-overridable constant (`override NAME: T [= default];`).
#[derive(Clone, Debug, PartialEq)]
pub struct ShaderOverride {
    pub name: String,
    pub ty: ParamType,
    pub has_default: bool,
    /// The default's value when it is a literal (`= 4u`), for checking a pass file's param
    /// against it; `None` without a default or when it is an expression.
    pub default: Option<ParamValue>,
    /// Byte offset of the declaration in the shader's code (see `ShaderSource::locate`).
    pub offset: Option<usize>,
}

/// Everything the graph compiler needs to know about one pass's shader.
#[derive(Clone, Debug, PartialEq)]
pub struct ShaderInterface {
    pub entry: String,
    pub workgroup_size: [u32; 3],
    /// Whether the module uses subgroup operations, which not every device offers.
    pub needs_subgroups: bool,
    /// Bindings the entry point uses, except the params block, sorted by (group, binding).
    pub bindings: Vec<ShaderBinding>,
    /// The uniform variable named `params`, if the entry point uses one.
    pub params: Option<ParamBlock>,
    pub overrides: Vec<ShaderOverride>,
    /// A raster pass's fragment outputs by location; empty for a compute pass.
    pub outputs: Vec<FragmentOutput>,
}

/// One `@location(n)` output of a fragment entry point.
#[derive(Clone, Debug, PartialEq)]
pub struct FragmentOutput {
    pub location: u32,
    pub sample: SampleKind,
    pub components: u32,
    /// The WGSL type, for messages (`vec4<u32>`).
    pub ty: String,
}
