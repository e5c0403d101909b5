//! A raster pass's attachments: each bound to a graph texture and checked against the fragment
//! output it receives, and the draw's vertex count from an override the application provides.

use super::decl::{PassInstanceDecl, RasterDecl};
use super::error::GraphError;
use super::id::{IdVec, ResourceId};
use super::load::LoadedPass;
use super::plan::{PlannedRaster, PlannedResource, ResourceKind};
use super::provided::ProvidedSet;
use std::path::Path;

/// A raster pass's vertex count comes from an override the application provides.
pub(super) fn check_raster_count(
    pass: &LoadedPass,
    raster: &RasterDecl,
    provided: &ProvidedSet,
) -> Result<(), GraphError> {
    let error = |reason: String| GraphError::Raster {
        pass_file: pass.file.clone(),
        reason,
    };
    let known = || {
        provided
            .overrides()
            .iter()
            .filter(|o| o.ty == super::param::ParamType::U32)
            .map(|o| o.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    };
    match provided.get_override(&raster.triangles) {
        Some(o) if o.ty == super::param::ParamType::U32 => Ok(()),
        Some(o) => Err(error(format!(
            "triangles: '{}' is a {} the application provides, not a u32 count (counts: {})",
            raster.triangles,
            o.ty,
            known()
        ))),
        None => Err(error(format!(
            "triangles: '{}' is no count the application provides (counts: {})",
            raster.triangles,
            known()
        ))),
    }
}

/// Resolves a raster pass's attachments to graph textures and checks each against the
/// fragment output it receives.
pub(super) fn bind_attachments(
    graph_file: &Path,
    instance: &PassInstanceDecl,
    pass: &LoadedPass,
    raster: &RasterDecl,
    resources: &IdVec<ResourceId, PlannedResource>,
    [out_w, out_h]: [u32; 2],
) -> Result<PlannedRaster, GraphError> {
    let outputs = &pass.interface.outputs;
    let resolve = |name: &str, kind: &str| -> Result<(ResourceId, &PlannedResource), GraphError> {
        if pass.interface.bindings.iter().any(|b| b.name == name) {
            return Err(GraphError::Raster {
                pass_file: pass.file.clone(),
                reason: format!(
                    "'{name}' is both a {kind} and a binding of {}; rename one",
                    pass.shader.path.display()
                ),
            });
        }
        let Some(resource_name) = instance.bind.get(name) else {
            return Err(GraphError::Unbound {
                graph: graph_file.to_path_buf(),
                pass: instance.name.clone(),
                binding: name.to_string(),
                kind: kind.to_string(),
                shader: pass.file.clone(),
            });
        };
        let Some(id) = resources.position(|r| &r.name == resource_name) else {
            return Err(GraphError::UnknownResource {
                graph: graph_file.to_path_buf(),
                pass: instance.name.clone(),
                binding: name.to_string(),
                resource: resource_name.clone(),
                known: resources.iter().map(|r| r.name.clone()).collect(),
            });
        };
        Ok((id, &resources[id]))
    };
    let mismatch =
        |name: &str, resource: &PlannedResource, reason: String| GraphError::Attachment {
            graph: graph_file.to_path_buf(),
            pass: instance.name.clone(),
            attachment: name.to_string(),
            resource: resource.name.clone(),
            reason,
        };
    // Every attachment is a one-layer texture of the output's size: the viewport.
    let texture = |name: &str, resource: &PlannedResource| match resource.kind {
        ResourceKind::Texture {
            format,
            width,
            height,
            layers,
        } => {
            if layers != 1 {
                Err(mismatch(
                    name,
                    resource,
                    format!(
                        "'{}' has {layers} layers; an attachment has one",
                        resource.name
                    ),
                ))
            } else if (width, height) != (out_w, out_h) {
                Err(mismatch(
                    name,
                    resource,
                    format!(
                        "'{}' is {width}x{height} but the pass draws the output, {out_w}x{out_h}; give it size: Output",
                        resource.name
                    ),
                ))
            } else {
                Ok(format)
            }
        }
        _ => Err(mismatch(
            name,
            resource,
            format!("'{}' is not a texture the graph owns", resource.name),
        )),
    };
    let mut color = Vec::new();
    for (location, name) in raster.color.iter().enumerate() {
        let (id, resource) = resolve(name, "color attachment")?;
        let format = texture(name, resource)?;
        let Some(output) = outputs.iter().find(|o| o.location as usize == location) else {
            return Err(mismatch(
                name,
                resource,
                format!(
                    "it is colour attachment {location} but the fragment entry point '{}' has no @location({location}) output",
                    raster.fragment
                ),
            ));
        };
        if format.is_depth()
            || format.sample_kind() != output.sample
            || output.components < format.components()
        {
            return Err(mismatch(
                name,
                resource,
                format!(
                    "'{}' is {format:?} but fragment output {location} is {}",
                    resource.name, output.ty
                ),
            ));
        }
        color.push((name.clone(), id));
    }
    if let Some(extra) = outputs
        .iter()
        .find(|o| o.location as usize >= raster.color.len())
    {
        return Err(GraphError::Raster {
            pass_file: pass.file.clone(),
            reason: format!(
                "the fragment entry point '{}' writes @location({}) but `color` lists {} attachment(s); add one for it",
                raster.fragment,
                extra.location,
                raster.color.len()
            ),
        });
    }
    let depth = match &raster.depth {
        Some(name) => {
            let (id, resource) = resolve(name, "depth attachment")?;
            let format = texture(name, resource)?;
            if !format.is_depth() {
                return Err(mismatch(
                    name,
                    resource,
                    format!(
                        "'{}' is {format:?}; a depth attachment is Depth32Float",
                        resource.name
                    ),
                ));
            }
            Some((name.clone(), id))
        }
        None => None,
    };
    Ok(PlannedRaster {
        vertex: raster.vertex.clone(),
        fragment: raster.fragment.clone(),
        color,
        depth,
        load: raster.load,
        triangles: raster.triangles.clone(),
    })
}
