//! The plan's memory on the GPU: one texture or buffer per physical object (transient
//! resources with disjoint lifetimes share one), one buffer and/or texel view per provided
//! resource the kept passes bind, and uploads to and readback from them by resource name.

use super::context::GpuContext;
use super::convert::{texture_format, view_dimension};
use super::error::GpuError;
use super::error_scope::capture_errors;
use super::provided_data::ProvidedData;
use super::readback::read_mapped;
use super::texels::create_texel_view;
use passgraph_graph::format::{TextureDim, TextureFormat};
use passgraph_graph::id::{IdVec, ResourceId};
use passgraph_graph::interface::BindingKind;
use passgraph_graph::plan::{
    PhysicalResource, Plan, PlannedBinding, PlannedResource, ResourceKind,
};
use passgraph_graph::provided::ProvidedKind;
use passgraph_graph::schedule::Usage;
use std::collections::BTreeMap;
use wgpu::util::DeviceExt;

pub enum GpuObject {
    Texture {
        texture: wgpu::Texture,
        format: TextureFormat,
        width: u32,
        height: u32,
        layers: u32,
    },
    Buffer {
        buffer: wgpu::Buffer,
    },
}

/// What one binding receives. Texture views are made per binding because the shader decides
/// the view dimension.
pub enum BoundResource<'a> {
    View(wgpu::TextureView),
    Buffer(&'a wgpu::Buffer),
}

impl BoundResource<'_> {
    pub fn as_binding(&self) -> wgpu::BindingResource<'_> {
        match self {
            BoundResource::View(view) => wgpu::BindingResource::TextureView(view),
            BoundResource::Buffer(buffer) => buffer.as_entire_binding(),
        }
    }
}

pub struct GpuResources {
    /// The plan's resources by id: names, shapes and physical objects.
    resources: IdVec<ResourceId, PlannedResource>,
    /// By index into `Plan::physical`.
    objects: Vec<GpuObject>,
    provided: BTreeMap<ResourceId, ProvidedObject>,
}

/// A provided resource in the forms its bindings ask for.
struct ProvidedObject {
    buffer: Option<wgpu::Buffer>,
    /// The bytes as `Rgba32Uint` texels, for texel-view bindings (see `texels`).
    texels: Option<wgpu::Texture>,
}

impl GpuResources {
    /// Creates every physical object of `plan` and uploads the provided buffers its kept
    /// passes bind. A provided resource in use without bytes in `data` is an error naming it
    /// and the first pass that binds it.
    pub fn new(
        ctx: &GpuContext,
        plan: &Plan,
        data: &ProvidedData,
    ) -> Result<GpuResources, GpuError> {
        let device = ctx.device();
        let mut objects = Vec::with_capacity(plan.physical.len());
        for physical in &plan.physical {
            let name = physical_name(plan, physical);
            let object = capture_errors(device, || create_object(device, &name, physical))
                .and_then(|object| {
                    object.ok_or_else(|| "the plan allocated a provided resource".to_string())
                })
                .map_err(|message| GpuError::CreateResource { name, message })?;
            objects.push(object);
        }
        let mut provided = BTreeMap::new();
        for (id, need) in provided_needs(plan) {
            let name = &plan.resources[id].name;
            let bytes = data
                .buffers
                .get(name)
                .ok_or_else(|| GpuError::MissingProvided {
                    pass: need.first_pass.clone(),
                    resource: name.clone(),
                })?;
            let create_error = |message| GpuError::CreateResource {
                name: name.clone(),
                message,
            };
            let buffer = need
                .as_buffer
                .then(|| capture_errors(device, || create_provided(device, name, &need, bytes)))
                .transpose()
                .map_err(create_error)?;
            let texels = need
                .as_texels
                .then(|| {
                    capture_errors(device, || {
                        create_texel_view(device, ctx.queue(), name, bytes)
                    })
                    .and_then(|texture| texture)
                })
                .transpose()
                .map_err(create_error)?;
            provided.insert(id, ProvidedObject { buffer, texels });
        }
        Ok(GpuResources {
            resources: plan.resources.clone(),
            objects,
            provided,
        })
    }

    /// The GPU object behind one of a pass's bindings.
    pub fn bind(&self, binding: &PlannedBinding) -> Result<BoundResource<'_>, GpuError> {
        let resource = &self.resources[binding.resource];
        if let Some(object) = self.provided.get(&binding.resource) {
            // provided_needs made every form a kept binding asks for.
            let missing = || GpuError::Unallocated {
                name: resource.name.clone(),
            };
            return Ok(if binding.kind.is_texture() {
                BoundResource::View(
                    object
                        .texels
                        .as_ref()
                        .ok_or_else(missing)?
                        .create_view(&Default::default()),
                )
            } else {
                BoundResource::Buffer(object.buffer.as_ref().ok_or_else(missing)?)
            });
        }
        let physical = resource.physical.ok_or_else(|| GpuError::Unallocated {
            name: resource.name.clone(),
        })?;
        Ok(match &self.objects[physical] {
            GpuObject::Buffer { buffer } => BoundResource::Buffer(buffer),
            GpuObject::Texture { texture, .. } => {
                let dim = match binding.kind {
                    BindingKind::StorageTexture { dim, .. }
                    | BindingKind::SampledTexture { dim, .. } => dim,
                    _ => TextureDim::D2,
                };
                BoundResource::View(texture.create_view(&wgpu::TextureViewDescriptor {
                    label: Some(&resource.name),
                    dimension: Some(view_dimension(dim)),
                    // A 2D view shows one layer; the plan only binds one-layer textures so.
                    array_layer_count: (dim == TextureDim::D2).then_some(1),
                    ..Default::default()
                }))
            }
        })
    }

    /// The wgpu format of a graph texture (`None` for anything else).
    pub fn format(&self, id: ResourceId) -> Option<wgpu::TextureFormat> {
        match self.resources[id].physical.map(|p| &self.objects[p]) {
            Some(GpuObject::Texture { format, .. }) => Some(texture_format(*format)),
            _ => None,
        }
    }

    /// A view of a raster pass's attachment (a one-layer texture the graph owns).
    pub fn attachment(&self, id: ResourceId) -> Result<wgpu::TextureView, GpuError> {
        let resource = &self.resources[id];
        let unallocated = || GpuError::Unallocated {
            name: resource.name.clone(),
        };
        match resource.physical.map(|p| &self.objects[p]) {
            Some(GpuObject::Texture { texture, .. }) => {
                Ok(texture.create_view(&wgpu::TextureViewDescriptor {
                    label: Some(&resource.name),
                    dimension: Some(wgpu::TextureViewDimension::D2),
                    array_layer_count: Some(1),
                    ..Default::default()
                }))
            }
            _ => Err(unallocated()),
        }
    }

    /// The buffer of a provided uniform; `Ok(None)` when no kept pass binds it, so nothing
    /// needs its bytes.
    pub fn provided_uniform(&self, name: &str) -> Result<Option<&wgpu::Buffer>, GpuError> {
        let id = self
            .resources
            .iter()
            .position(|r| r.name == name && r.kind == ResourceKind::Provided(ProvidedKind::Uniform))
            .map(ResourceId)
            .ok_or_else(|| GpuError::NotAProvidedUniform {
                name: name.to_string(),
                uniforms: self
                    .resources
                    .iter()
                    .filter(|r| r.kind == ResourceKind::Provided(ProvidedKind::Uniform))
                    .map(|r| r.name.clone())
                    .collect(),
            })?;
        Ok(self.provided.get(&id).and_then(|o| o.buffer.as_ref()))
    }

    /// Replaces the whole content of a graph-owned resource; `bytes` must be exactly its size
    /// (textures: layer-major, then row-major, tightly packed). Resources sharing an object
    /// with others see the bytes only until another of them is written.
    pub fn write(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        name: &str,
        bytes: &[u8],
    ) -> Result<(), GpuError> {
        let (resource, object) = self.graph_owned(name, "it cannot be written directly")?;
        check_size(resource, bytes)?;
        capture_errors(device, || match object {
            GpuObject::Texture {
                texture,
                format,
                width,
                height,
                layers,
            } => queue.write_texture(
                texture.as_image_copy(),
                bytes,
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(width * format.bytes_per_texel() as u32),
                    rows_per_image: Some(*height),
                },
                extent(*width, *height, *layers),
            ),
            GpuObject::Buffer { buffer } => write_padded(queue, buffer, bytes),
        })
        .map_err(|message| GpuError::Transfer {
            name: name.to_string(),
            message,
        })
    }

    /// The content of a graph-owned resource after all submitted work, blocking. Textures come
    /// back layer-major, then row-major, without row padding; buffers as their declared bytes.
    pub fn read(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        name: &str,
    ) -> Result<Vec<u8>, GpuError> {
        let (resource, object) = self.graph_owned(name, "it cannot be read back")?;
        let transfer = |message| GpuError::Transfer {
            name: name.to_string(),
            message,
        };
        let size = resource.kind.bytes();
        match object {
            GpuObject::Texture {
                texture,
                format,
                width,
                height,
                layers,
            } => {
                let row = u64::from(*width) * format.bytes_per_texel();
                let padded_row = align(row, u64::from(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT));
                let rows = u64::from(*height) * u64::from(*layers);
                let staging = capture_errors(device, || {
                    let staging = readback_buffer(device, name, padded_row * rows);
                    let mut encoder = device.create_command_encoder(&Default::default());
                    encoder.copy_texture_to_buffer(
                        texture.as_image_copy(),
                        wgpu::TexelCopyBufferInfo {
                            buffer: &staging,
                            layout: wgpu::TexelCopyBufferLayout {
                                offset: 0,
                                bytes_per_row: Some(padded_row as u32),
                                rows_per_image: Some(*height),
                            },
                        },
                        extent(*width, *height, *layers),
                    );
                    queue.submit([encoder.finish()]);
                    staging
                })
                .map_err(transfer)?;
                let padded = read_mapped(device, &staging, padded_row * rows).map_err(transfer)?;
                Ok(padded
                    .chunks_exact(padded_row as usize)
                    .flat_map(|r| &r[..row as usize])
                    .copied()
                    .collect())
            }
            GpuObject::Buffer { buffer } => {
                let staging = capture_errors(device, || {
                    let staging = readback_buffer(device, name, buffer.size());
                    let mut encoder = device.create_command_encoder(&Default::default());
                    encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, buffer.size());
                    queue.submit([encoder.finish()]);
                    staging
                })
                .map_err(transfer)?;
                read_mapped(device, &staging, size).map_err(transfer)
            }
        }
    }

    fn graph_owned(
        &self,
        name: &str,
        what_if_provided: &'static str,
    ) -> Result<(&PlannedResource, &GpuObject), GpuError> {
        let resource = self
            .resources
            .iter()
            .find(|r| r.name == name)
            .ok_or_else(|| GpuError::UnknownResource {
                name: name.to_string(),
                known: self.resources.iter().map(|r| r.name.clone()).collect(),
            })?;
        if let ResourceKind::Provided(_) = resource.kind {
            return Err(GpuError::ProvidedNotGraphOwned {
                name: name.to_string(),
                what: what_if_provided,
            });
        }
        let physical = resource.physical.ok_or_else(|| GpuError::Unallocated {
            name: name.to_string(),
        })?;
        Ok((resource, &self.objects[physical]))
    }
}

fn check_size(resource: &PlannedResource, bytes: &[u8]) -> Result<(), GpuError> {
    let expected = resource.kind.bytes();
    if bytes.len() as u64 != expected {
        return Err(GpuError::WrongSize {
            name: resource.name.clone(),
            expected,
            got: bytes.len() as u64,
        });
    }
    Ok(())
}

/// Labels a shared object by all its users, e.g. `t1+t3+t4`, so errors and debuggers show
/// every resource living in it.
fn physical_name(plan: &Plan, physical: &PhysicalResource) -> String {
    physical
        .users
        .iter()
        .map(|&r| plan.resources[r].name.as_str())
        .collect::<Vec<_>>()
        .join("+")
}

/// `None` for a provided kind, which the plan never allocates.
fn create_object(
    device: &wgpu::Device,
    name: &str,
    physical: &PhysicalResource,
) -> Option<GpuObject> {
    match physical.kind {
        ResourceKind::Texture {
            format,
            width,
            height,
            layers,
        } => {
            // Copies in and out serve uploads (tests, initialisation) and readback.
            let mut usage = wgpu::TextureUsages::COPY_SRC | wgpu::TextureUsages::COPY_DST;
            for u in &physical.usages {
                usage |= match u {
                    Usage::Sampled => wgpu::TextureUsages::TEXTURE_BINDING,
                    Usage::StorageRead | Usage::StorageWrite | Usage::StorageReadWrite => {
                        wgpu::TextureUsages::STORAGE_BINDING
                    }
                    Usage::ColorAttachment | Usage::DepthAttachment => {
                        wgpu::TextureUsages::RENDER_ATTACHMENT
                    }
                    Usage::Uniform | Usage::Indirect => wgpu::TextureUsages::empty(),
                };
            }
            let texture = device.create_texture(&wgpu::TextureDescriptor {
                label: Some(name),
                size: extent(width, height, layers),
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: texture_format(format),
                usage,
                view_formats: &[],
            });
            Some(GpuObject::Texture {
                texture,
                format,
                width,
                height,
                layers,
            })
        }
        ResourceKind::Buffer { size } => {
            let mut usage = wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
            for u in &physical.usages {
                usage |= match u {
                    Usage::Uniform => wgpu::BufferUsages::UNIFORM,
                    Usage::StorageRead | Usage::StorageWrite | Usage::StorageReadWrite => {
                        wgpu::BufferUsages::STORAGE
                    }
                    Usage::Indirect => wgpu::BufferUsages::INDIRECT,
                    Usage::Sampled | Usage::ColorAttachment | Usage::DepthAttachment => {
                        wgpu::BufferUsages::empty()
                    }
                };
            }
            let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(name),
                // Bindings and copies need 4-byte multiples; readback trims to `size`.
                size: align(size.max(4), 4),
                usage,
                mapped_at_creation: false,
            });
            Some(GpuObject::Buffer { buffer })
        }
        ResourceKind::Provided(_) => None,
    }
}

/// How the kept passes bind one provided resource.
struct ProvidedNeed {
    kind: ProvidedKind,
    /// The largest size a binding requires: the uniform struct, or a storage buffer's fixed
    /// part (one element of a runtime-sized array).
    min_size: u64,
    first_pass: String,
    /// Bound as a buffer (storage or uniform) by some pass.
    as_buffer: bool,
    /// Bound as a texel view (a storage or sampled `u32` texture) by some pass.
    as_texels: bool,
}

fn provided_needs(plan: &Plan) -> BTreeMap<ResourceId, ProvidedNeed> {
    let mut needs: BTreeMap<ResourceId, ProvidedNeed> = BTreeMap::new();
    for pass in &plan.passes {
        for b in &pass.bindings {
            let ResourceKind::Provided(kind) = plan.resources[b.resource].kind else {
                continue;
            };
            let min_size = match b.kind {
                BindingKind::Uniform { size } => size,
                BindingKind::Storage { min_size, .. } => min_size,
                _ => 0,
            };
            let need = needs.entry(b.resource).or_insert_with(|| ProvidedNeed {
                kind,
                min_size: 0,
                first_pass: pass.name.clone(),
                as_buffer: false,
                as_texels: false,
            });
            need.min_size = need.min_size.max(min_size);
            if b.kind.is_texture() {
                need.as_texels = true;
            } else {
                need.as_buffer = true;
            }
        }
    }
    needs
}

/// The scene's bytes, zero-padded so that even an empty buffer (a scene without lights) can
/// be bound: at least what the shaders require, and a 4-byte multiple.
fn create_provided(
    device: &wgpu::Device,
    name: &str,
    need: &ProvidedNeed,
    bytes: &[u8],
) -> wgpu::Buffer {
    let size = align((bytes.len() as u64).max(need.min_size).max(4), 4);
    let mut contents = bytes.to_vec();
    contents.resize(size as usize, 0);
    let usage = match need.kind {
        ProvidedKind::StorageBuffer => wgpu::BufferUsages::STORAGE,
        ProvidedKind::Uniform => wgpu::BufferUsages::UNIFORM,
    };
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(name),
        contents: &contents,
        usage: usage | wgpu::BufferUsages::COPY_DST,
    })
}

/// `queue.write_buffer` at offset 0 with the 4-byte multiple length it requires; buffers are
/// created with rounded-up sizes so the padding fits.
pub fn write_padded(queue: &wgpu::Queue, buffer: &wgpu::Buffer, bytes: &[u8]) {
    if bytes.len().is_multiple_of(4) {
        queue.write_buffer(buffer, 0, bytes);
    } else {
        let mut padded = bytes.to_vec();
        padded.resize(align(bytes.len() as u64, 4) as usize, 0);
        queue.write_buffer(buffer, 0, &padded);
    }
}

fn readback_buffer(device: &wgpu::Device, name: &str, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(&format!("{name} readback")),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

fn extent(width: u32, height: u32, layers: u32) -> wgpu::Extent3d {
    wgpu::Extent3d {
        width,
        height,
        depth_or_array_layers: layers,
    }
}

pub fn align(value: u64, to: u64) -> u64 {
    value.div_ceil(to) * to
}
