//! Checking one pass instance against its shader: params, bindings, resource compatibility.

use super::attachments::{bind_attachments, check_raster_count};
use super::compose::PassOrigin;
use super::decl::{Dispatch, LoadOp, PassInstanceDecl};
use super::error::GraphError;
use super::format::{SampleKind, TextureDim, TextureFormat};
use super::id::{IdVec, ResourceId};
use super::interface::{Access, BindingKind, ShaderBinding};
use super::load::LoadedPass;
use super::param::ParamValue;
use super::plan::{ParamsUniform, PlannedBinding, PlannedRaster, PlannedResource, ResourceKind};
use super::provided::{ProvidedKind, ProvidedSet};
use super::schedule::Usage;
use std::collections::BTreeMap;
use std::path::Path;

/// A pass instance with its bindings resolved to resources.
#[derive(Clone, Debug)]
pub struct BoundPass {
    pub bindings: Vec<PlannedBinding>,
    pub params: BTreeMap<String, ParamValue>,
    pub params_uniform: Option<ParamsUniform>,
    pub overrides: Vec<(String, f64)>,
    /// Overrides the application sets (see [`ProvidedSet::overrides`]).
    pub provided_overrides: Vec<String>,
    pub workgroups: [u32; 3],
    /// One entry per resource, accesses merged over its bindings.
    pub uses: Vec<(ResourceId, Access)>,
    pub usages: Vec<(ResourceId, Usage)>,
    pub raster: Option<PlannedRaster>,
    /// For an `Indirect` dispatch: the buffer holding the workgroup counts and their offset.
    pub indirect: Option<(ResourceId, u64)>,
}

/// Checks that a pass file's params match its shader: every `params` field and every
/// `override` without default is a declared param of the same type, and every param is used.
pub fn check_pass_params(pass: &LoadedPass, provided: &ProvidedSet) -> Result<(), GraphError> {
    let declared = &pass.decl.params;
    let params = pass.params(provided);
    let shader = &pass.shader.path;
    if let Some((name, value)) = declared.iter().find(|(_, v)| !v.is_finite()) {
        return Err(GraphError::NonFiniteParam {
            file: pass.file.clone(),
            pass: pass
                .file
                .file_stem()
                .map_or(String::new(), |s| s.to_string_lossy().into()),
            param: name.clone(),
            value: format!("{value:?}"),
        });
    }
    for (name, &(min, max)) in &pass.decl.ranges {
        let bad = |reason: String| GraphError::BadParamRange {
            file: pass.file.clone(),
            reason,
        };
        let Some(default) = params.get(name) else {
            return Err(bad(format!("'{name}' is not a param of this pass")));
        };
        if default.scalar().is_none() {
            return Err(bad(format!(
                "'{name}' is a {}; only f32, u32 and i32 params have ranges",
                default.ty()
            )));
        }
        if !(min.is_finite() && max.is_finite() && min <= max) {
            return Err(bad(format!(
                "'{name}': ({min}, {max}) is not a range (finite, min <= max)"
            )));
        }
        if !default.within((min, max)) {
            return Err(bad(format!(
                "'{name}': its default {default:?} lies outside ({min}, {max})"
            )));
        }
    }
    let wrong_type = |param: &str, expected: String, found: &ParamValue| GraphError::ParamType {
        file: pass.file.clone(),
        pass: pass
            .file
            .file_stem()
            .map_or(String::new(), |s| s.to_string_lossy().into()),
        param: param.to_string(),
        expected,
        found: found.ty().to_string(),
        expected_where: format!("the shader {}", shader.display()),
    };
    for field in pass.interface.params.iter().flat_map(|b| &b.fields) {
        let Some(value) = declared.get(&field.name) else {
            return Err(GraphError::UndeclaredUniformField {
                pass_file: pass.file.clone(),
                shader: shader.clone(),
                field: field.name.clone(),
            });
        };
        if value.ty() != field.ty {
            return Err(wrong_type(&field.name, field.ty.to_string(), value));
        }
    }
    for o in &pass.interface.overrides {
        if let Some(p) = provided.get_override(&o.name) {
            if p.ty != o.ty {
                return Err(GraphError::UnsupportedBinding {
                    shader: shader.clone(),
                    binding: o.name.clone(),
                    reason: format!(
                        "`override {}` is set by the framework ({}) and must have type {}",
                        o.name, p.what, p.ty
                    ),
                });
            }
            if declared.contains_key(&o.name) {
                return Err(GraphError::UnsupportedBinding {
                    shader: pass.file.clone(),
                    binding: o.name.clone(),
                    reason:
                        "the framework sets this override from the scene; remove it from params"
                            .into(),
                });
            }
            continue;
        }
        match declared.get(&o.name) {
            Some(value) if value.ty() != o.ty => {
                return Err(wrong_type(&o.name, o.ty.to_string(), value));
            }
            Some(value) if o.default.as_ref().is_some_and(|d| d != value) => {
                let (file, line, _) = pass.shader.locate(o.offset.unwrap_or(0));
                return Err(GraphError::OverrideDefaultDisagrees {
                    pass_file: pass.file.clone(),
                    shader: file,
                    line,
                    name: o.name.clone(),
                    ron: format!("{value:?}"),
                    wgsl: o
                        .default
                        .as_ref()
                        .map_or(String::new(), |d| d.wgsl_literal()),
                });
            }
            None if !o.has_default => {
                return Err(GraphError::OverrideWithoutValue {
                    pass_file: pass.file.clone(),
                    shader: shader.clone(),
                    name: o.name.clone(),
                });
            }
            _ => {}
        }
    }
    if let Some(raster) = &pass.decl.raster {
        check_raster_count(pass, raster, provided)?;
    }
    let field_names: Vec<&str> = pass
        .interface
        .params
        .iter()
        .flat_map(|b| &b.fields)
        .map(|f| f.name.as_str())
        .collect();
    for name in declared.keys() {
        let is_override = pass.interface.overrides.iter().any(|o| &o.name == name);
        if !is_override && !field_names.contains(&name.as_str()) {
            return Err(GraphError::UnusedParam {
                pass_file: pass.file.clone(),
                shader: shader.clone(),
                param: name.clone(),
            });
        }
    }
    Ok(())
}

/// Resolves one instance: param overrides, each shader binding to a compatible resource.
pub fn bind_instance(
    origin: &PassOrigin,
    instance: &PassInstanceDecl,
    pass: &LoadedPass,
    resources: &IdVec<ResourceId, PlannedResource>,
    output_size: [u32; 2],
    provided: &ProvidedSet,
) -> Result<BoundPass, GraphError> {
    let graph_file = origin.file.as_path();
    let params = resolve_params(origin, instance, pass, provided)?;
    let shader = &pass.interface;
    let mut bindings = Vec::new();
    for b in &shader.bindings {
        let by_name = || provided.bound_by_name(&b.name).map(|p| &p.name);
        let Some(resource_name) = instance.bind.get(&b.name).or_else(by_name) else {
            return Err(GraphError::Unbound {
                graph: graph_file.to_path_buf(),
                pass: instance.name.clone(),
                binding: b.name.clone(),
                kind: b.kind.to_string(),
                shader: pass.shader.path.clone(),
            });
        };
        let found = resources.iter().position(|r| &r.name == resource_name);
        let Some(id) = found.map(ResourceId) else {
            return Err(GraphError::UnknownResource {
                graph: graph_file.to_path_buf(),
                pass: instance.name.clone(),
                binding: b.name.clone(),
                resource: resource_name.clone(),
                known: resources.iter().map(|r| r.name.clone()).collect(),
            });
        };
        if let Err(reason) = compatible(&b.kind, &resources[id], provided) {
            return Err(GraphError::BindingMismatch {
                graph: graph_file.to_path_buf(),
                pass: instance.name.clone(),
                binding: b.name.clone(),
                resource: resource_name.clone(),
                reason,
            });
        }
        check_bounds(
            graph_file,
            instance,
            &pass.decl.dispatch,
            b,
            &resources[id],
            output_size,
        )?;
        bindings.push(PlannedBinding {
            name: b.name.clone(),
            group: b.group,
            binding: b.binding,
            kind: b.kind.clone(),
            resource: id,
        });
    }
    let raster = match &pass.decl.raster {
        Some(r) => Some(bind_attachments(
            graph_file,
            instance,
            pass,
            r,
            resources,
            output_size,
        )?),
        None => None,
    };
    let attachments: Vec<&(String, ResourceId)> = raster
        .iter()
        .flat_map(|r| r.color.iter().chain(&r.depth))
        .collect();
    if let Some(extra) = instance.bind.keys().find(|k| {
        !shader.bindings.iter().any(|b| &b.name == *k) && !attachments.iter().any(|a| &a.0 == *k)
    }) {
        return Err(GraphError::NoSuchBinding {
            graph: graph_file.to_path_buf(),
            pass: instance.name.clone(),
            binding: extra.clone(),
            shader: pass.shader.path.clone(),
            available: shader.bindings.iter().map(|b| b.name.clone()).collect(),
        });
    }
    let (mut uses, mut usages) = merge_uses(graph_file, &instance.name, &bindings, resources)?;
    if let Some(r) = &raster {
        let access = match r.load {
            LoadOp::Clear => Access::Write,
            LoadOp::Load => Access::ReadWrite,
        };
        let color = r.color.iter().map(|a| (a, Usage::ColorAttachment));
        let depth = r.depth.iter().map(|a| (a, Usage::DepthAttachment));
        for ((name, id), usage) in color.chain(depth) {
            if let Some(other) = bindings.iter().find(|b| b.resource == *id) {
                return Err(GraphError::ConflictingUsage {
                    graph: graph_file.to_path_buf(),
                    pass: instance.name.clone(),
                    resource: resources[*id].name.clone(),
                    bindings: vec![other.name.clone(), name.clone()],
                });
            }
            if uses.iter().any(|(u, _)| u == id) {
                return Err(GraphError::ConflictingUsage {
                    graph: graph_file.to_path_buf(),
                    pass: instance.name.clone(),
                    resource: resources[*id].name.clone(),
                    bindings: attachments
                        .iter()
                        .filter(|a| a.1 == *id)
                        .map(|a| a.0.clone())
                        .collect(),
                });
            }
            uses.push((*id, access));
            usages.push((*id, usage));
        }
        uses.sort();
    }
    let params_uniform = shader.params.as_ref().map(|block| {
        let mut bytes = vec![0u8; block.size as usize];
        for f in &block.fields {
            let value = params[&f.name].to_le_bytes();
            let at = f.offset as usize;
            bytes[at..at + value.len()].copy_from_slice(&value);
        }
        ParamsUniform {
            group: block.group,
            binding: block.binding,
            bytes,
        }
    });
    let overrides = shader
        .overrides
        .iter()
        .filter_map(|o| Some((o.name.clone(), params.get(&o.name)?.as_override()?)))
        .collect();
    let provided_overrides = shader
        .overrides
        .iter()
        .filter(|o| provided.get_override(&o.name).is_some())
        .map(|o| o.name.clone())
        .collect();
    let indirect = match &pass.decl.dispatch {
        Dispatch::Indirect {
            binding,
            index,
            stride,
        } if raster.is_none() => {
            let record = (binding.as_str(), index.as_deref(), *stride);
            let id = bind_indirect(
                graph_file, instance, pass, &bindings, resources, &params, record,
            )?;
            usages.push((id.0, Usage::Indirect));
            Some(id)
        }
        _ => None,
    };
    let workgroups = match pass.decl.dispatch {
        _ if raster.is_some() => [1, 1, 1],
        // Read from the buffer when the pass runs.
        Dispatch::Indirect { .. } => [0, 0, 0],
        Dispatch::PerPixel => {
            let [wx, wy, _] = shader.workgroup_size;
            [
                output_size[0].div_ceil(wx.max(1)),
                output_size[1].div_ceil(wy.max(1)),
                1,
            ]
        }
        Dispatch::Workgroups(x, y, z) => [x, y, z],
        Dispatch::PerTile(tw, th) => {
            let invocations = shader.workgroup_size.iter().product::<u32>();
            if tw == 0 || th == 0 || u64::from(invocations) != u64::from(tw) * u64::from(th) {
                return Err(GraphError::Dispatch {
                    graph: graph_file.to_path_buf(),
                    pass: instance.name.clone(),
                    shader: pass.shader.path.clone(),
                    reason: format!(
                        "dispatch PerTile({tw}, {th}) needs one invocation per pixel of the tile, {} in all, but the shader's workgroup has {invocations} ({:?})",
                        u64::from(tw) * u64::from(th),
                        shader.workgroup_size
                    ),
                });
            }
            [output_size[0].div_ceil(tw), output_size[1].div_ceil(th), 1]
        }
    };
    Ok(BoundPass {
        bindings,
        params,
        params_uniform,
        overrides,
        provided_overrides,
        workgroups,
        uses,
        usages,
        raster,
        indirect,
    })
}

/// Resolves an `Indirect` dispatch's record: the binding it names must be a read-only storage
/// buffer of the graph's (WebGPU forbids a buffer written in the same dispatch that reads its
/// counts), and the record at `stride` times the index param must lie inside it.
fn bind_indirect(
    graph_file: &Path,
    instance: &PassInstanceDecl,
    pass: &LoadedPass,
    bindings: &[PlannedBinding],
    resources: &IdVec<ResourceId, PlannedResource>,
    params: &BTreeMap<String, ParamValue>,
    (binding, index, stride): (&str, Option<&str>, u64),
) -> Result<(ResourceId, u64), GraphError> {
    let error = |reason: String| GraphError::Dispatch {
        graph: graph_file.to_path_buf(),
        pass: instance.name.clone(),
        shader: pass.shader.path.clone(),
        reason,
    };
    let Some(b) = bindings.iter().find(|b| b.name == binding) else {
        return Err(error(format!(
            "dispatch Indirect reads its workgroup counts through binding '{binding}', which the shader does not use (it uses: {})",
            bindings
                .iter()
                .map(|b| b.name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        )));
    };
    if !matches!(
        b.kind,
        BindingKind::Storage {
            access: Access::Read,
            ..
        }
    ) {
        return Err(error(format!(
            "dispatch Indirect reads its workgroup counts through binding '{binding}', which is {}; it must be `var<storage, read>` (a buffer the same dispatch writes cannot hold its counts)",
            b.kind
        )));
    }
    let resource = &resources[b.resource];
    let ResourceKind::Buffer { size } = resource.kind else {
        return Err(error(format!(
            "dispatch Indirect reads its workgroup counts from '{}', which is not a buffer of the graph",
            resource.name
        )));
    };
    let record = match index {
        None => 0,
        Some(name) => match params.get(name) {
            Some(ParamValue::U32(i)) => u64::from(*i),
            Some(other) => {
                return Err(error(format!(
                    "dispatch Indirect takes its record index from param '{name}', which is a {}, not a u32",
                    other.ty()
                )));
            }
            None => {
                return Err(error(format!(
                    "dispatch Indirect takes its record index from param '{name}', which the pass does not have"
                )));
            }
        },
    };
    let offset = record.saturating_mul(stride);
    if stride % 4 != 0 || offset.saturating_add(12) > size {
        return Err(error(format!(
            "dispatch Indirect reads 12 bytes at offset {offset} (record {record}, stride {stride}) of '{}', which has {size} bytes{}",
            resource.name,
            if stride % 4 != 0 {
                "; the stride must be a multiple of 4"
            } else {
                ""
            }
        )));
    }
    Ok((b.resource, offset))
}

/// What reflection can prove goes out of bounds: a constant layer index beyond the texture's
/// layers, or a per-pixel pass writing a texture smaller than the output it is dispatched over
/// (the pixels past its edge are dropped: part of the image would never be written).
fn check_bounds(
    graph_file: &Path,
    instance: &PassInstanceDecl,
    dispatch: &Dispatch,
    b: &ShaderBinding,
    resource: &PlannedResource,
    [out_w, out_h]: [u32; 2],
) -> Result<(), GraphError> {
    let ResourceKind::Texture {
        width,
        height,
        layers,
        ..
    } = resource.kind
    else {
        return Ok(());
    };
    let error = |reason: String| GraphError::OutOfBounds {
        graph: graph_file.to_path_buf(),
        pass: instance.name.clone(),
        binding: b.name.clone(),
        resource: resource.name.clone(),
        reason,
    };
    if let Some(layer) = b.max_constant_layer {
        if layer >= layers {
            return Err(error(format!(
                "the shader uses layer {layer}, but '{}' has {layers} layer{}; declare it with layers: {}",
                resource.name,
                if layers == 1 { "" } else { "s" },
                u64::from(layer) + 1
            )));
        }
    }
    if matches!(dispatch, Dispatch::PerPixel | Dispatch::PerTile(..))
        && b.kind.access().writes()
        && (width < out_w || height < out_h)
    {
        return Err(error(format!(
            "the pass runs once per output pixel ({out_w}x{out_h}) and writes '{}', which is only {width}x{height}: the pixels beyond it would be lost; give it size: Output",
            resource.name
        )));
    }
    Ok(())
}

fn resolve_params(
    origin: &PassOrigin,
    instance: &PassInstanceDecl,
    pass: &LoadedPass,
    provided: &ProvidedSet,
) -> Result<BTreeMap<String, ParamValue>, GraphError> {
    let mut params = pass.params(provided);
    let known: Vec<String> = params.keys().cloned().collect();
    for (name, value) in &instance.params {
        let graph_file = origin.param_file(name);
        if !value.is_finite() {
            return Err(GraphError::NonFiniteParam {
                file: graph_file.to_path_buf(),
                pass: instance.name.clone(),
                param: name.clone(),
                value: format!("{value:?}"),
            });
        }
        let Some(default) = params.get_mut(name) else {
            return Err(GraphError::UnknownParam {
                graph: graph_file.to_path_buf(),
                pass: instance.name.clone(),
                pass_file: pass.file.clone(),
                param: name.clone(),
                known: known.clone(),
            });
        };
        if default.ty() != value.ty() {
            return Err(GraphError::ParamType {
                file: graph_file.to_path_buf(),
                pass: instance.name.clone(),
                param: name.clone(),
                expected: default.ty().to_string(),
                found: value.ty().to_string(),
                expected_where: pass.file.display().to_string(),
            });
        }
        if let Some(&(min, max)) = pass.decl.ranges.get(name)
            && !value.within((min, max))
        {
            return Err(GraphError::ParamOutOfRange {
                file: graph_file.to_path_buf(),
                pass: instance.name.clone(),
                pass_file: pass.file.clone(),
                param: name.clone(),
                value: value
                    .scalar()
                    .map_or(format!("{value:?}"), |v| v.to_string()),
                min,
                max,
            });
        }
        *default = value.clone();
    }
    Ok(params)
}

/// Whether a shader binding can use a resource; `Err` says why not.
fn compatible(
    kind: &BindingKind,
    resource: &PlannedResource,
    provided: &ProvidedSet,
) -> Result<(), String> {
    let name = &resource.name;
    let readers = provided.texel_reader_file().map_or(String::new(), |f| {
        format!(" (as the readers in {f} take it)")
    });
    match (&resource.kind, kind) {
        (ResourceKind::Provided(p), _) => match (p, kind) {
            (ProvidedKind::Uniform, BindingKind::Uniform { .. }) => Ok(()),
            (
                ProvidedKind::StorageBuffer,
                BindingKind::Storage {
                    access: Access::Read,
                    ..
                },
            ) => Ok(()),
            // A texel view: the same bytes as 16-byte texels (gpu/texels.rs).
            (
                ProvidedKind::StorageBuffer,
                BindingKind::SampledTexture {
                    sample: SampleKind::Uint,
                    dim: TextureDim::D2,
                }
                | BindingKind::StorageTexture {
                    access: Access::Read,
                    format: TextureFormat::Rgba32Uint,
                    dim: TextureDim::D2,
                },
            ) => Ok(()),
            (ProvidedKind::StorageBuffer, BindingKind::Storage { .. }) => Err(format!(
                "'{name}' is provided by the framework and read-only; declare the binding var<storage, read>"
            )),
            (ProvidedKind::Uniform, _) => Err(format!(
                "'{name}' is a uniform block provided by the framework; declare the binding var<uniform>, not {kind}"
            )),
            (ProvidedKind::StorageBuffer, _) => Err(format!(
                "'{name}' is a storage buffer provided by the framework; declare the binding var<storage, read> or, for its bytes as 16-byte texels, texture_storage_2d<rgba32uint, read>{readers} or texture_2d<u32>; not {kind}"
            )),
        },
        (ResourceKind::Buffer { .. }, BindingKind::StorageTexture { .. })
        | (ResourceKind::Buffer { .. }, BindingKind::SampledTexture { .. }) => Err(format!(
            "the shader declares {kind}, a texture, but '{name}' is a buffer"
        )),
        (ResourceKind::Texture { .. }, BindingKind::Uniform { .. })
        | (ResourceKind::Texture { .. }, BindingKind::Storage { .. }) => Err(format!(
            "the shader declares {kind}, a buffer, but '{name}' is a texture"
        )),
        (ResourceKind::Buffer { size }, BindingKind::Uniform { size: need })
        | (ResourceKind::Buffer { size }, BindingKind::Storage { min_size: need, .. }) => {
            if size < need {
                Err(format!(
                    "'{name}' is {size} bytes but the shader's {kind} needs at least {need}"
                ))
            } else {
                Ok(())
            }
        }
        (ResourceKind::Texture { format, .. }, _) if format.is_depth() => Err(format!(
            "'{name}' is {format:?}, which a raster pass uses as its depth attachment only; it cannot be bound to {kind}"
        )),
        (
            ResourceKind::Texture { format, layers, .. },
            BindingKind::StorageTexture {
                format: want, dim, ..
            },
        ) => {
            if format != want {
                return Err(format!(
                    "the shader declares {kind} but '{name}' has format {format}"
                ));
            }
            check_dim(*dim, *layers, name, kind)
        }
        (
            ResourceKind::Texture { format, layers, .. },
            BindingKind::SampledTexture { sample, dim },
        ) => {
            if format.sample_kind() != *sample {
                return Err(format!(
                    "the shader declares {kind} but '{name}' has format {format}, which reads as {}",
                    format.sample_kind()
                ));
            }
            check_dim(*dim, *layers, name, kind)
        }
    }
}

fn check_dim(dim: TextureDim, layers: u32, name: &str, kind: &BindingKind) -> Result<(), String> {
    if dim == TextureDim::D2 && layers != 1 {
        Err(format!(
            "the shader declares {kind} (one layer) but '{name}' has {layers} layers; declare a 2d_array binding"
        ))
    } else {
        Ok(())
    }
}

/// Merges bindings per resource. A resource bound twice must only be read: a write through one
/// binding with another binding of the same resource is a data race within the dispatch.
#[allow(clippy::type_complexity)]
fn merge_uses(
    graph_file: &Path,
    pass: &str,
    bindings: &[PlannedBinding],
    resources: &IdVec<ResourceId, PlannedResource>,
) -> Result<(Vec<(ResourceId, Access)>, Vec<(ResourceId, Usage)>), GraphError> {
    let mut by_resource: BTreeMap<ResourceId, Vec<&PlannedBinding>> = BTreeMap::new();
    for b in bindings {
        by_resource.entry(b.resource).or_default().push(b);
    }
    let mut uses = Vec::new();
    let mut usages = Vec::new();
    for (r, bs) in by_resource {
        let writes = bs.iter().any(|b| b.kind.access().writes());
        if writes && bs.len() > 1 {
            return Err(GraphError::ConflictingUsage {
                graph: graph_file.to_path_buf(),
                pass: pass.to_string(),
                resource: resources[r].name.clone(),
                bindings: bs.iter().map(|b| b.name.clone()).collect(),
            });
        }
        let access = bs[0].kind.access();
        uses.push((r, access));
        for b in bs {
            let u = Usage::of(&b.kind);
            if !usages.contains(&(r, u)) {
                usages.push((r, u));
            }
        }
    }
    Ok((uses, usages))
}
