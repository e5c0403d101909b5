//! One kept pass made ready to dispatch: its pipeline, its params uniform and its bind groups,
//! all created once.

use super::context::GpuContext;
use super::convert::{binding_type, storage_feature, texture_format};
use super::error::GpuError;
use super::error_scope::capture_errors;
use super::provided_data::ProvidedData;
use super::resources::{BoundResource, GpuResources};
use crate::graph::interface::BindingKind;
use crate::graph::plan::PlannedPass;
use std::collections::BTreeMap;
use wgpu::util::DeviceExt;

pub struct PreparedPass {
    pub name: String,
    pub pipeline: wgpu::ComputePipeline,
    /// (group index, bind group); groups the shader does not use are absent.
    pub bind_groups: Vec<(u32, wgpu::BindGroup)>,
    /// The `params` uniform and its length in bytes.
    pub params: Option<(wgpu::Buffer, u64)>,
    pub workgroups: [u32; 3],
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
        let created = capture_errors(ctx.device(), || {
            let bound: Vec<BoundResource> = pass
                .bindings
                .iter()
                .map(|b| resources.bind(b))
                .collect::<Result<_, _>>()?;
            Ok(create(ctx.device(), pass, &bound, &constants))
        });
        created.unwrap_or_else(|message| {
            Err(GpuError::CreatePass {
                pass: pass.name.clone(),
                message,
            })
        })
    }
}

/// Everything wgpu validates; the caller turns its errors into one naming the pass.
fn create(
    device: &wgpu::Device,
    pass: &PlannedPass,
    bound: &[BoundResource],
    constants: &[(&str, f64)],
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
                    visibility: wgpu::ShaderStages::COMPUTE,
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

    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label,
        source: wgpu::ShaderSource::Wgsl(pass.shader.code.as_str().into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label,
        layout: Some(&pipeline_layout),
        module: &module,
        entry_point: Some(&pass.entry),
        compilation_options: wgpu::PipelineCompilationOptions {
            constants,
            ..Default::default()
        },
        cache: None,
    });

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

    PreparedPass {
        name: pass.name.clone(),
        pipeline,
        bind_groups,
        params,
        workgroups: pass.workgroups,
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
