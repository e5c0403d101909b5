//! The compiled graph: what the GPU executor records and what graph tests assert on.

use super::compose::PassOrigin;
use super::decl::{Footprint, LoadOp};
use super::format::TextureFormat;
use super::id::{IdVec, KeptPass, ResourceId, Stage};
use super::interface::{Access, BindingKind};
use super::lifetime::Lifetime;
use super::param::ParamValue;
use super::provided::ProvidedKind;
use super::schedule::{Barrier, Usage};
use super::shader_source::ShaderSource;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// A resource's shape once the output size is known.
#[derive(Clone, Debug, PartialEq)]
pub enum ResourceKind {
    Texture {
        format: TextureFormat,
        width: u32,
        height: u32,
        layers: u32,
    },
    Buffer {
        size: u64,
    },
    /// Owned by the application (registered in a `ProvidedSet`), which sizes and fills it.
    Provided(ProvidedKind),
}

impl ResourceKind {
    /// Bytes the graph allocates for it; provided resources are the application's, not the graph's.
    pub fn bytes(&self) -> u64 {
        match *self {
            ResourceKind::Texture {
                format,
                width,
                height,
                layers,
            } => {
                // Saturating: compile rejects sizes past 2^64, so this never saturates there.
                u64::from(width)
                    .saturating_mul(u64::from(height))
                    .saturating_mul(u64::from(layers))
                    .saturating_mul(format.bytes_per_texel())
            }
            ResourceKind::Buffer { size } => size,
            ResourceKind::Provided(_) => 0,
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct PlannedResource {
    pub name: String,
    /// The graph file that declared it; `None` for provided resources.
    pub origin: Option<PathBuf>,
    pub kind: ResourceKind,
    pub persistent: bool,
    pub output: bool,
    /// Stages that use it; `None` when no kept pass does.
    pub lifetime: Option<Lifetime>,
    /// Index into `Plan::physical`; `None` for provided or unused resources.
    pub physical: Option<usize>,
}

/// One GPU object; several transient resources may share it.
#[derive(Clone, Debug, PartialEq)]
pub struct PhysicalResource {
    pub kind: ResourceKind,
    /// Every usage of every resource mapped onto it: the object's usage flags.
    pub usages: Vec<Usage>,
    pub users: Vec<ResourceId>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct PlannedBinding {
    /// The shader's variable name.
    pub name: String,
    pub group: u32,
    pub binding: u32,
    pub kind: BindingKind,
    pub resource: ResourceId,
}

/// The packed `params` uniform block of a pass instance.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamsUniform {
    pub group: u32,
    pub binding: u32,
    pub bytes: Vec<u8>,
}

/// A kept pass instance, ready to record.
#[derive(Clone, Debug)]
pub struct PlannedPass {
    pub name: String,
    /// The graph file that introduced the instance, and those that changed its params.
    pub origin: PassOrigin,
    pub pass_file: PathBuf,
    pub shader: ShaderSource,
    pub entry: String,
    pub stage: Stage,
    /// Workgroups per dispatch (unused when `indirect` is set).
    pub workgroups: [u32; 3],
    /// An `Indirect` dispatch: the buffer whose bytes at the offset hold the workgroup counts.
    pub indirect: Option<(ResourceId, u64)>,
    /// The entry point's `@workgroup_size`.
    pub workgroup_size: [u32; 3],
    /// Whether the shader uses subgroup operations (wgpu feature SUBGROUP).
    pub needs_subgroups: bool,
    pub bindings: Vec<PlannedBinding>,
    /// Every param with its final value (defaults overridden by the graph).
    pub params: BTreeMap<String, ParamValue>,
    pub params_uniform: Option<ParamsUniform>,
    /// Pipeline-overridable constants set from params.
    pub overrides: Vec<(String, f64)>,
    /// Pipeline-overridable constants the application provides (in `ProvidedData`).
    pub provided_overrides: Vec<String>,
    /// Each resource touched, with the union of its bindings' accesses.
    pub uses: Vec<(ResourceId, Access)>,
    /// For a raster pass: its draw (then `entry`, `workgroups` and `workgroup_size` are unused).
    pub raster: Option<PlannedRaster>,
    /// Which pixels one pixel's invocation depends on (the pass file's `footprint`).
    pub footprint: Footprint,
}

/// A raster pass's draw: entry points, attachments bound to graph textures, vertex count.
#[derive(Clone, Debug, PartialEq)]
pub struct PlannedRaster {
    pub vertex: String,
    pub fragment: String,
    /// Attachment `i` takes fragment output `@location(i)`: (shader-side name, resource).
    pub color: Vec<(String, ResourceId)>,
    pub depth: Option<(String, ResourceId)>,
    pub load: LoadOp,
    /// The provided override whose value is the triangle count (3 vertices each).
    pub triangles: String,
}

#[derive(Clone, Debug, PartialEq)]
pub struct CulledPass {
    pub name: String,
    /// The graph file that introduced the instance.
    pub origin: PathBuf,
    pub reason: String,
    pub uses: Vec<(ResourceId, Access)>,
}

/// A dependency between two kept passes, for display.
#[derive(Clone, Debug, PartialEq)]
pub struct PlannedEdge {
    pub from: KeptPass,
    pub to: KeptPass,
    pub resource: ResourceId,
    pub hazard: super::deps::Hazard,
}

#[derive(Clone, Debug)]
pub struct Plan {
    pub graph: PathBuf,
    /// Every graph file `graph` was composed from (extends, include), `graph` first.
    pub graph_files: Vec<PathBuf>,
    pub output_size: [u32; 2],
    pub resources: IdVec<ResourceId, PlannedResource>,
    pub physical: Vec<PhysicalResource>,
    /// Kept passes in program order.
    pub passes: IdVec<KeptPass, PlannedPass>,
    /// Indices into `passes`; every pass of a stage may run once the previous stage is done.
    pub stages: IdVec<Stage, Vec<KeptPass>>,
    pub barriers: Vec<Barrier>,
    pub edges: Vec<PlannedEdge>,
    pub culled: Vec<CulledPass>,
}

impl Plan {
    pub fn pass(&self, name: &str) -> Option<&PlannedPass> {
        self.passes.iter().find(|p| p.name == name)
    }

    pub fn resource_id(&self, name: &str) -> Option<ResourceId> {
        self.resources
            .iter()
            .position(|r| r.name == name)
            .map(ResourceId)
    }

    /// Pass names per stage, the shape tests and `plan` show.
    pub fn stage_names(&self) -> Vec<Vec<&str>> {
        self.stages
            .iter()
            .map(|s| s.iter().map(|&p| self.passes[p].name.as_str()).collect())
            .collect()
    }

    /// Bytes of graph-owned resources if each had its own object.
    pub fn bytes_without_reuse(&self) -> u64 {
        self.resources
            .iter()
            .filter(|r| r.physical.is_some())
            .map(|r| r.kind.bytes())
            .fold(0, u64::saturating_add)
    }

    /// Bytes actually allocated after transient reuse.
    pub fn bytes_allocated(&self) -> u64 {
        self.physical
            .iter()
            .map(|p| p.kind.bytes())
            .fold(0, u64::saturating_add)
    }
}
