//! Compiling a loaded graph to a `Plan`: validation, dependencies, culling, stages, barriers,
//! lifetimes and reuse. No GPU involved.

use super::bind::{BoundPass, bind_instance, check_pass_params};
use super::compose::check_include_targets;
use super::cull::{ResourceFacts, cull_reason};
use super::decl::{BufferSize, GraphDecl, ResourceDecl, TextureSize};
use super::deps::{DependencyError, PassUse};
use super::error::GraphError;
use super::format::TextureFormat;
use super::id::{Id, IdVec, KeptPass, PassIndex, ResourceId, Stage};
use super::lifetime::{LogicalResource, Role, allocate, lifetimes};
use super::load::{LoadedGraph, load_graph};
use super::plan::{
    CulledPass, PhysicalResource, Plan, PlannedEdge, PlannedPass, PlannedResource, ResourceKind,
};
use super::provided::ProvidedSet;
use super::schedule::{Schedule, schedule};
use super::shared_params::with_shared_params;
use std::collections::BTreeSet;
use std::path::Path;

/// Loads and compiles a graph file for an output of `output_size` pixels, its passes binding
/// what `provided` registers as well as the graph's own resources.
pub fn compile_file(
    path: &Path,
    output_size: [u32; 2],
    provided: &ProvidedSet,
) -> Result<Plan, GraphError> {
    compile(&load_graph(path)?, output_size, provided)
}

pub fn compile(
    graph: &LoadedGraph,
    output_size: [u32; 2],
    provided: &ProvidedSet,
) -> Result<Plan, GraphError> {
    let file = graph.file.as_path();
    let decl = &graph.decl;
    // Loading could not tell these apart from typos; the set can.
    check_include_targets(&graph.include_targets, provided)?;
    if !decl.inputs.is_empty() {
        return Err(GraphError::Subgraph {
            graph: file.to_path_buf(),
            inputs: decl.inputs.clone(),
        });
    }
    check_unique_names(file, decl)?;
    check_not_empty(file, decl)?;
    for pass in graph.passes.values() {
        check_pass_params(pass, provided)?;
    }
    let mut resources = resolve_resources(graph, output_size, provided)?;
    let outputs = resolve_outputs(graph, &mut resources)?;

    let instances = with_shared_params(graph, provided)?;
    let bound = instances
        .iter()
        .map(|(origin, instance)| {
            let pass = &graph.passes[&instance.pass];
            bind_instance(origin, instance, pass, &resources, output_size, provided)
        })
        .collect::<Result<IdVec<PassIndex, BoundPass>, _>>()?;

    let is_persistent = |r: ResourceId| resources[r].persistent;
    let uses: IdVec<PassIndex, Vec<PassUse>> = bound.iter().map(pass_uses).collect();
    let usages: IdVec<PassIndex, _> = bound.iter().map(|b| b.usages.clone()).collect();
    let schedule = schedule(&uses, &usages, is_persistent, &outputs).map_err(|e| {
        let name = |p: PassIndex| decl.passes[p].name.clone();
        let res = |r: ResourceId| resources[r].name.clone();
        match e {
            DependencyError::ReadBeforeWrite {
                pass,
                resource,
                later_writer,
            } => GraphError::ReadBeforeWrite {
                graph: graph.pass_origin(&decl.passes[pass].name).file,
                pass: name(pass),
                through: reading_binding(&bound[pass], resource),
                resource: res(resource),
                later_writer: later_writer.map(name),
            },
            DependencyError::Cycle { passes, via } => GraphError::Cycle {
                graph: file.to_path_buf(),
                passes: passes.into_iter().map(name).collect(),
                via: via.into_iter().map(res).collect(),
            },
        }
    })?;
    if let Some(&r) = outputs
        .iter()
        .find(|r| !schedule.all.final_writer.contains_key(r))
    {
        return Err(GraphError::OutputNotWritten {
            graph: graph.output_origin(&resources[r].name).to_path_buf(),
            output: resources[r].name.clone(),
        });
    }
    let Schedule {
        all,
        alive,
        kept,
        deps,
        levels,
        stages,
        barriers,
        ..
    } = schedule;

    if graph.keep_used_textures {
        // Outputs only decide what is kept; the kept passes are settled, so marking more
        // outputs now changes lifetimes and aliasing, nothing else.
        for &p in kept.iter() {
            for &(r, _) in &bound[p].uses {
                if is_colour_texture(&resources[r].kind) {
                    resources[r].output = true;
                }
            }
        }
    }
    let roles: Vec<Role> = resources
        .iter()
        .map(|r| Role {
            persistent: r.persistent,
            output: r.output,
        })
        .collect();
    let used_in = kept
        .iter()
        .zip(&levels)
        .flat_map(|(&p, &stage)| bound[p].uses.iter().map(move |&(r, _)| (r, stage)));
    let last_stage = Stage(stages.len().saturating_sub(1));
    for (r, lifetime) in resources
        .iter_mut()
        .zip(lifetimes(&roles, used_in, last_stage))
    {
        r.lifetime = lifetime;
    }
    let physical = allocate_physical(&mut resources, &kept, &bound);

    let edges = deps
        .graph
        .edge_indices()
        .filter_map(|e| {
            let (from, to) = deps.graph.edge_endpoints(e)?;
            let d = deps.graph[e];
            Some(PlannedEdge {
                from: KeptPass(from.index()),
                to: KeptPass(to.index()),
                resource: d.resource,
                hazard: d.hazard,
            })
        })
        .collect();
    let culled = PassIndex::all(bound.len())
        .filter(|&p| !alive[p])
        .map(|p| CulledPass {
            name: decl.passes[p].name.clone(),
            origin: graph.pass_origin(&decl.passes[p].name).file,
            reason: cull_reason(
                p,
                &uses,
                &all,
                |q| &decl.passes[q].name,
                |r| ResourceFacts {
                    name: &resources[r].name,
                    persistent: resources[r].persistent,
                },
            ),
            uses: bound[p].uses.clone(),
        })
        .collect();
    let passes = kept
        .iter()
        .zip(&levels)
        .map(|(&p, &stage)| {
            let instance = &decl.passes[p];
            let pass = &graph.passes[&instance.pass];
            let b = &bound[p];
            PlannedPass {
                name: instance.name.clone(),
                origin: instances[p].0.clone(),
                pass_file: pass.file.clone(),
                shader: pass.shader.clone(),
                entry: pass.decl.entry.clone(),
                stage,
                workgroups: b.workgroups,
                indirect: b.indirect,
                workgroup_size: pass.interface.workgroup_size,
                needs_subgroups: pass.interface.needs_subgroups,
                bindings: b.bindings.clone(),
                params: b.params.clone(),
                params_uniform: b.params_uniform.clone(),
                overrides: b.overrides.clone(),
                provided_overrides: b.provided_overrides.clone(),
                uses: b.uses.clone(),
                raster: b.raster.clone(),
                footprint: pass.decl.footprint,
            }
        })
        .collect();
    Ok(Plan {
        graph: file.to_path_buf(),
        graph_files: graph.graph_files.clone(),
        output_size,
        resources,
        physical,
        passes,
        stages,
        barriers,
        edges,
        culled,
    })
}

fn pass_uses(b: &BoundPass) -> Vec<PassUse> {
    b.uses
        .iter()
        .map(|&(resource, access)| PassUse { resource, access })
        .collect()
}

fn check_unique_names(file: &Path, decl: &GraphDecl) -> Result<(), GraphError> {
    let mut seen = BTreeSet::new();
    for p in &decl.passes {
        if !seen.insert(p.name.as_str()) {
            return Err(GraphError::DuplicatePassName {
                graph: file.to_path_buf(),
                name: p.name.clone(),
            });
        }
    }
    Ok(())
}

/// A graph without passes or outputs would compile to a plan that does nothing.
fn check_not_empty(file: &Path, decl: &GraphDecl) -> Result<(), GraphError> {
    let reason = if decl.passes.is_empty() {
        "the graph has no passes; list at least one in `passes`"
    } else if decl.outputs.is_empty() {
        "the graph has no outputs, so every pass would be culled; list what the host reads back in `outputs`"
    } else {
        return Ok(());
    };
    Err(GraphError::EmptyGraph {
        graph: file.to_path_buf(),
        reason: reason.to_string(),
    })
}

/// A texture of the graph's own that can be read back (depth attachments cannot).
fn is_colour_texture(kind: &ResourceKind) -> bool {
    matches!(kind, ResourceKind::Texture { format, .. } if *format != TextureFormat::Depth32Float)
}

/// Declared resources (sized for this output) followed by every provided resource.
fn resolve_resources(
    graph: &LoadedGraph,
    [width, height]: [u32; 2],
    provided: &ProvidedSet,
) -> Result<IdVec<ResourceId, PlannedResource>, GraphError> {
    let decl = &graph.decl;
    let invalid = |name: &str, reason: String| GraphError::InvalidResource {
        graph: graph.resource_origin(name).to_path_buf(),
        resource: name.to_string(),
        reason,
    };
    let mut out = Vec::new();
    for (name, r) in &decl.resources {
        if provided.get(name).is_some() {
            return Err(invalid(
                name,
                "this name is provided by the framework; bind it without declaring it".into(),
            ));
        }
        let kind = match *r {
            ResourceDecl::Texture {
                format,
                size,
                layers,
                ..
            } => {
                if layers == 0 {
                    return Err(invalid(name, "layers must be at least 1".into()));
                }
                let (w, h) = match size {
                    TextureSize::Output => (width, height),
                    TextureSize::Scaled(s) if s.is_finite() && s > 0.0 => (
                        ((width as f32 * s).round() as u32).max(1),
                        ((height as f32 * s).round() as u32).max(1),
                    ),
                    TextureSize::Scaled(s) => {
                        return Err(invalid(name, format!("Scaled({s}) must be positive")));
                    }
                    TextureSize::Absolute(w, h) if w > 0 && h > 0 => (w, h),
                    TextureSize::Absolute(w, h) => {
                        return Err(invalid(name, format!("Absolute({w}, {h}) has a zero side")));
                    }
                };
                let bytes = u64::from(w)
                    .checked_mul(u64::from(h))
                    .and_then(|t| t.checked_mul(u64::from(layers)))
                    .and_then(|t| t.checked_mul(format.bytes_per_texel()));
                if bytes.is_none() {
                    return Err(invalid(
                        name,
                        format!(
                            "{w}x{h} texels x {layers} layers of {format} is more than 2^64 bytes; use a smaller --size or fewer layers"
                        ),
                    ));
                }
                ResourceKind::Texture {
                    format,
                    width: w,
                    height: h,
                    layers,
                }
            }
            ResourceDecl::Buffer { size, .. } => {
                let bytes = match size {
                    BufferSize::Bytes(b) => b,
                    BufferSize::PerPixel(b) => b
                        .checked_mul(u64::from(width))
                        .and_then(|t| t.checked_mul(u64::from(height)))
                        .ok_or_else(|| {
                            invalid(
                                name,
                                format!(
                                    "PerPixel({b}) at {width}x{height} is more than 2^64 bytes; use a smaller --size or fewer bytes per pixel"
                                ),
                            )
                        })?,
                };
                if bytes == 0 || bytes % 4 != 0 {
                    return Err(invalid(
                        name,
                        format!("buffer size {bytes} must be a positive multiple of 4 bytes"),
                    ));
                }
                ResourceKind::Buffer { size: bytes }
            }
        };
        out.push(PlannedResource {
            name: name.clone(),
            origin: Some(graph.resource_origin(name).to_path_buf()),
            kind,
            persistent: r.persistent(),
            output: false,
            lifetime: None,
            physical: None,
        });
    }
    out.extend(provided.resources().iter().map(|p| PlannedResource {
        name: p.name.clone(),
        origin: None,
        kind: ResourceKind::Provided(p.kind),
        // Provided content exists before the frame, like a persistent resource's.
        persistent: true,
        output: false,
        lifetime: None,
        physical: None,
    }));
    Ok(out.into())
}

fn resolve_outputs(
    graph: &LoadedGraph,
    resources: &mut IdVec<ResourceId, PlannedResource>,
) -> Result<Vec<ResourceId>, GraphError> {
    let decl = &graph.decl;
    let mut ids = Vec::new();
    for output in &decl.outputs {
        let found = resources
            .iter()
            .position(|r| &r.name == output && !matches!(r.kind, ResourceKind::Provided(_)));
        let Some(id) = found.map(ResourceId) else {
            return Err(GraphError::UnknownOutput {
                graph: graph.output_origin(output).to_path_buf(),
                output: output.clone(),
                known: decl.resources.keys().cloned().collect(),
            });
        };
        resources[id].output = true;
        ids.push(id);
    }
    Ok(ids)
}

fn allocate_physical(
    resources: &mut IdVec<ResourceId, PlannedResource>,
    kept: &[PassIndex],
    bound: &IdVec<PassIndex, BoundPass>,
) -> Vec<PhysicalResource> {
    let graph_owned = |r: &PlannedResource| !matches!(r.kind, ResourceKind::Provided(_));
    let logical: Vec<LogicalResource<ResourceKind>> = resources
        .iter()
        .map(|r| LogicalResource {
            descriptor: r.kind.clone(),
            lifetime: r.lifetime.filter(|_| graph_owned(r)),
            shareable: !r.persistent && !r.output,
        })
        .collect();
    let allocation = allocate(&logical);
    let mut physical: Vec<PhysicalResource> = allocation
        .physical
        .into_iter()
        .map(|kind| PhysicalResource {
            kind,
            usages: Vec::new(),
            users: Vec::new(),
        })
        .collect();
    for (r, slot) in ResourceId::all(resources.len()).zip(&allocation.physical_of) {
        resources[r].physical = *slot;
        if let Some(s) = *slot {
            physical[s].users.push(r);
        }
    }
    for &p in kept {
        for &(r, usage) in &bound[p].usages {
            if let Some(s) = resources[r].physical {
                if !physical[s].usages.contains(&usage) {
                    physical[s].usages.push(usage);
                    physical[s].usages.sort();
                }
            }
        }
    }
    physical
}

/// What a pass reads a resource through: a shader binding, or a raster attachment, which has
/// no binding (its `load: Load` reads it).
fn reading_binding(pass: &BoundPass, resource: ResourceId) -> String {
    if let Some(b) = pass.bindings.iter().find(|b| b.resource == resource) {
        return format!("binding '{}'", b.name);
    }
    let raster = pass.raster.as_ref();
    let attachment = raster.and_then(|r| {
        r.color
            .iter()
            .chain(r.depth.iter())
            .find(|(_, id)| *id == resource)
    });
    attachment.map_or_else(
        || "a use the plan does not name".to_string(),
        |(name, _)| format!("attachment '{name}', whose load: Load reads it"),
    )
}
