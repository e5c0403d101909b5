//! One kept pass made ready to dispatch: its pipeline, its params uniform and its bind groups,
//! all created once.

use super::context::GpuContext;
use super::convert::{binding_type, storage_feature, texture_format};
use super::error::GpuError;
use super::error_scope::capture_errors;
use super::provided_data::ProvidedData;
use super::resources::{BoundResource, GpuResources};
use super::specialise::{specialise, specialise_validated};
use passgraph_graph::decl::LoadOp;
use passgraph_graph::interface::BindingKind;
use passgraph_graph::plan::PlannedPass;
use std::borrow::Cow;
use std::collections::BTreeMap;
use wgpu::util::DeviceExt;

pub struct PreparedPass {
    pub name: String,
    pub pipeline: Pipeline,
    /// (group index, bind group); groups the shader does not use are absent.
    pub bind_groups: Vec<(u32, wgpu::BindGroup)>,
    /// The `params` uniform and its length in bytes.
    pub params: Option<(wgpu::Buffer, u64)>,
    pub workgroups: [u32; 3],
    /// An `Indirect` dispatch's buffer and the offset of its workgroup counts.
    pub indirect: Option<(wgpu::Buffer, u64)>,
    /// Why the pipeline was built from the WGSL as written instead of the module specialised
    /// to its override values (the same image; a slower pipeline to create); `None` when it
    /// was specialised.
    pub unspecialised: Option<String>,
}

/// A compute pass's pipeline, or a raster pass's with what its render pass needs.
pub enum Pipeline {
    Compute(wgpu::ComputePipeline),
    Render(RenderDraw),
}

pub struct RenderDraw {
    pub pipeline: wgpu::RenderPipeline,
    pub color: Vec<wgpu::TextureView>,
    pub depth: Option<wgpu::TextureView>,
    /// Whether the attachments are cleared (else loaded).
    pub clear: bool,
    pub vertices: u32,
}

/// What fills a binding slot: the planned binding at this index, or the params block.
#[derive(Clone, Copy)]
enum Slot {
    Binding(usize),
    Params,
}

impl PreparedPass {
    pub fn new(
        ctx: &GpuContext,
        pass: &PlannedPass,
        resources: &GpuResources,
        provided: &ProvidedData,
    ) -> Result<PreparedPass, GpuError> {
        check_storage_textures(ctx, pass)?;
        let max = ctx.device().limits().max_compute_workgroups_per_dimension;
        if pass.workgroups.iter().any(|&n| n > max) {
            return Err(GpuError::TooManyWorkgroups {
                pass: pass.name.clone(),
                workgroups: pass.workgroups,
                max,
            });
        }
        let constants = pass_constants(pass, provided)?;
        let draw = match &pass.raster {
            Some(raster) => {
                let count = provided.overrides.get(&raster.triangles).ok_or_else(|| {
                    GpuError::MissingOverride {
                        pass: pass.name.clone(),
                        name: raster.triangles.clone(),
                    }
                })?;
                // The compiler checked the override is a u32; 3 vertices per triangle.
                let vertices = (*count as u64).saturating_mul(3).min(u64::from(u32::MAX)) as u32;
                Some((raster, vertices))
            }
            None => None,
        };
        let created = capture_errors(ctx.device(), || {
            let bound: Vec<BoundResource> = pass
                .bindings
                .iter()
                .map(|b| resources.bind(b))
                .collect::<Result<_, _>>()?;
            let targets = match draw {
                Some((raster, vertices)) => Some(Targets {
                    color: raster
                        .color
                        .iter()
                        .map(|(_, id)| resources.attachment(*id))
                        .collect::<Result<_, _>>()?,
                    color_formats: raster
                        .color
                        .iter()
                        .map(|(_, id)| resources.format(*id))
                        .collect(),
                    depth: raster
                        .depth
                        .as_ref()
                        .map(|(_, id)| resources.attachment(*id))
                        .transpose()?,
                    vertices,
                }),
                None => None,
            };
            Ok(create(ctx.device(), pass, &bound, &constants, targets))
        });
        created.unwrap_or_else(|message| {
            Err(GpuError::CreatePass {
                pass: pass.name.clone(),
                message,
            })
        })
    }
}

/// The pipeline constants of `pass`: its params' overrides and the scene's values of the
/// provided overrides it declares.
pub fn pass_constants<'a>(
    pass: &'a PlannedPass,
    provided: &ProvidedData,
) -> Result<Vec<(&'a str, f64)>, GpuError> {
    let mut constants: Vec<(&str, f64)> = pass
        .overrides
        .iter()
        .map(|(name, value)| (name.as_str(), *value))
        .collect();
    for name in &pass.provided_overrides {
        let value = provided
            .overrides
            .get(name)
            .ok_or_else(|| GpuError::MissingOverride {
                pass: pass.name.clone(),
                name: name.clone(),
            })?;
        constants.push((name.as_str(), *value));
    }
    Ok(constants)
}

/// The module of `pass` specialised to `constants` ([`specialise`]): what its pipeline is
/// built from unless this fails.
pub fn specialise_pass(
    pass: &PlannedPass,
    constants: &[(&str, f64)],
) -> Result<naga::Module, String> {
    let entry = match pass.raster {
        Some(_) => None,
        None => Some((naga::ShaderStage::Compute, pass.entry.as_str())),
    };
    match pass.shader.validated() {
        Some(shader) => specialise_validated(shader, entry, constants),
        None => specialise(&pass.shader.code, entry, constants),
    }
}

/// A raster pass's attachments and vertex count.
struct Targets {
    color: Vec<wgpu::TextureView>,
    color_formats: Vec<Option<wgpu::TextureFormat>>,
    depth: Option<wgpu::TextureView>,
    vertices: u32,
}

/// Everything wgpu validates; the caller turns its errors into one naming the pass.
fn create(
    device: &wgpu::Device,
    pass: &PlannedPass,
    bound: &[BoundResource],
    constants: &[(&str, f64)],
    targets: Option<Targets>,
) -> PreparedPass {
    let label = Some(pass.name.as_str());
    let params = pass.params_uniform.as_ref().map(|p| {
        let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(&format!("{} params", pass.name)),
            contents: &p.bytes,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        (buffer, p.bytes.len() as u64)
    });

    let mut groups: BTreeMap<u32, Vec<(u32, Slot, wgpu::BindingType)>> = BTreeMap::new();
    for (i, b) in pass.bindings.iter().enumerate() {
        groups.entry(b.group).or_default().push((
            b.binding,
            Slot::Binding(i),
            binding_type(&b.kind),
        ));
    }
    if let Some(p) = &pass.params_uniform {
        let size = p.bytes.len() as u64;
        groups.entry(p.group).or_default().push((
            p.binding,
            Slot::Params,
            binding_type(&BindingKind::Uniform { size }),
        ));
    }

    let layouts: BTreeMap<u32, wgpu::BindGroupLayout> = groups
        .iter()
        .map(|(&group, slots)| {
            let entries: Vec<wgpu::BindGroupLayoutEntry> = slots
                .iter()
                .map(|(binding, _, ty)| wgpu::BindGroupLayoutEntry {
                    binding: *binding,
                    visibility: visibility(pass, ty),
                    ty: *ty,
                    count: None,
                })
                .collect();
            let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label,
                entries: &entries,
            });
            (group, layout)
        })
        .collect();
    // Unused group indices below the highest stay empty.
    let group_count = groups.keys().next_back().map_or(0, |&g| g + 1);
    let slots: Vec<Option<&wgpu::BindGroupLayout>> =
        (0..group_count).map(|g| layouts.get(&g)).collect();
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label,
        bind_group_layouts: &slots,
        immediate_size: 0,
    });

    // The module specialised to this pass's override values, or the WGSL as written (then wgpu
    // substitutes the values, and reports any error), and why.
    let (source, constants, unspecialised) = match specialise_pass(pass, constants) {
        Ok(module) => (wgpu::ShaderSource::Naga(Cow::Owned(module)), &[][..], None),
        Err(why) => (
            wgpu::ShaderSource::Wgsl(pass.shader.code.as_str().into()),
            constants,
            Some(why),
        ),
    };
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor { label, source });
    let pipeline = match (&pass.raster, targets) {
        (Some(raster), Some(targets)) => {
            let color_targets: Vec<Option<wgpu::ColorTargetState>> = targets
                .color_formats
                .iter()
                .map(|format| {
                    format.map(|format| wgpu::ColorTargetState {
                        format,
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    })
                })
                .collect();
            let options = || wgpu::PipelineCompilationOptions {
                constants,
                ..Default::default()
            };
            let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label,
                layout: Some(&pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some(&raster.vertex),
                    compilation_options: options(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: targets.depth.as_ref().map(|_| wgpu::DepthStencilState {
                    format: wgpu::TextureFormat::Depth32Float,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::Less),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(&raster.fragment),
                    compilation_options: options(),
                    targets: &color_targets,
                }),
                multiview_mask: None,
                cache: None,
            });
            Pipeline::Render(RenderDraw {
                pipeline,
                color: targets.color,
                depth: targets.depth,
                clear: raster.load == LoadOp::Clear,
                vertices: targets.vertices,
            })
        }
        _ => Pipeline::Compute(
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label,
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(&pass.entry),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants,
                    ..Default::default()
                },
                cache: None,
            }),
        ),
    };

    let mut bind_groups = Vec::with_capacity(layouts.len());
    for (group, layout) in &layouts {
        let entries: Vec<wgpu::BindGroupEntry> = groups[group]
            .iter()
            .filter_map(|&(binding, slot, _)| {
                let resource = match slot {
                    Slot::Binding(i) => bound[i].as_binding(),
                    Slot::Params => params.as_ref()?.0.as_entire_binding(),
                };
                Some(wgpu::BindGroupEntry { binding, resource })
            })
            .collect();
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label,
            layout,
            entries: &entries,
        });
        bind_groups.push((*group, bind_group));
    }

    // The compiler made the counts' buffer one of the pass's bindings.
    let indirect = pass.indirect.and_then(|(id, offset)| {
        let i = pass.bindings.iter().position(|b| b.resource == id)?;
        match &bound[i] {
            BoundResource::Buffer(buffer) => Some(((*buffer).clone(), offset)),
            BoundResource::View(_) => None,
        }
    });
    PreparedPass {
        name: pass.name.clone(),
        pipeline,
        bind_groups,
        params,
        workgroups: pass.workgroups,
        indirect,
        unspecialised,
    }
}

/// Compute passes bind for the compute stage; raster passes for both of theirs, except what
/// is written (a vertex shader may not write storage).
fn visibility(pass: &PlannedPass, ty: &wgpu::BindingType) -> wgpu::ShaderStages {
    if pass.raster.is_none() {
        return wgpu::ShaderStages::COMPUTE;
    }
    let writes = match ty {
        wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            ..
        } => !read_only,
        wgpu::BindingType::StorageTexture { access, .. } => {
            *access != wgpu::StorageTextureAccess::ReadOnly
        }
        _ => false,
    };
    if writes {
        wgpu::ShaderStages::FRAGMENT
    } else {
        wgpu::ShaderStages::VERTEX_FRAGMENT
    }
}

/// Storage textures beyond WebGPU's guarantees (e.g. `read_write` rgba32float) depend on the
/// adapter; saying so beats wgpu's generic layout error.
fn check_storage_textures(ctx: &GpuContext, pass: &PlannedPass) -> Result<(), GpuError> {
    for b in &pass.bindings {
        let BindingKind::StorageTexture { access, format, .. } = b.kind else {
            continue;
        };
        let features = ctx.format_features(texture_format(format));
        if !features.flags.contains(storage_feature(access)) {
            return Err(GpuError::UnsupportedStorageTexture {
                pass: pass.name.clone(),
                binding: b.name.clone(),
                adapter: ctx.adapter_info().name.clone(),
                format: format.to_string(),
                access: access.to_string(),
            });
        }
    }
    Ok(())
}
