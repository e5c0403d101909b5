//! Reads a pass's shader interface with naga: which resources its entry point binds, its
//! `params` uniform layout, its overrides and its workgroup size.

use super::error::GraphError;
use super::format::{SampleKind, TextureDim, TextureFormat};
use super::interface::{
    Access, BindingKind, FragmentOutput, ParamBlock, ParamField, ShaderBinding, ShaderInterface,
    ShaderOverride,
};
use super::param::{ParamType, ParamValue};
use super::shader_source::{ShaderSource, ValidShader};
use naga::common::wgsl::{ToWgsl, TypeContext};
use naga::valid::{Capabilities, GlobalUse, ValidationError, ValidationFlags, Validator};
use naga::{
    AddressSpace, Handle, ImageClass, ImageDimension, Module, Scalar, ScalarKind, ShaderStage,
    StorageAccess, Type, TypeInner, VectorSize,
};
use std::collections::{HashMap, HashSet};
use std::error::Error as _;
use std::ops::Range;
use std::path::PathBuf;

/// The uniform variable the framework fills from the pass's params.
const PARAMS_NAME: &str = "params";

mod binding;
mod diagnostics;
mod fragment;
mod layers;
mod types;

use binding::*;
use diagnostics::*;
use fragment::*;
use layers::*;
use types::*;

/// What naga may accept. Reflection should not reject shaders the device would run (wgpu
/// validates again when the pipeline is created), and should leave unsupported bindings to this
/// module's own, clearer errors.
/// The framework's capability policy: what a shader may use. Reflection validates under it,
/// and so does specialisation (passgraph-gpu), so a shader is judged by one rule.
pub fn capabilities() -> Capabilities {
    // Core WebGPU: what wgpu grants a device with full downlevel support and no optional
    // features (`pack2x16float` and `quantizeToF16` need SHADER_FLOAT16_IN_FLOAT32).
    Capabilities::default()
        | Capabilities::SHADER_FLOAT16_IN_FLOAT32
        // Optional WebGPU features that common native adapters have ("shader-f16" still needs
        // `enable f16;`, "subgroups").
        | Capabilities::SHADER_FLOAT16
        | Capabilities::SUBGROUP
        // Binding types the framework rejects anyway: accepting them here lets `reflect` name
        // the binding and say why, instead of naga reporting a missing capability.
        | Capabilities::IMMEDIATES
        | Capabilities::STORAGE_TEXTURE_16BIT_NORM_FORMATS
        | Capabilities::TEXTURE_ATOMIC
        | Capabilities::TEXTURE_AND_SAMPLER_BINDING_ARRAY
        | Capabilities::BUFFER_BINDING_ARRAY
        | Capabilities::STORAGE_BUFFER_BINDING_ARRAY
        | Capabilities::STORAGE_TEXTURE_BINDING_ARRAY
}

/// Parses and validates the joined source, finds the compute entry point `entry`, and returns
/// its interface.
pub fn reflect(source: &ShaderSource, entry: &str) -> Result<ShaderInterface, GraphError> {
    reflect_entries(source, &[(ShaderStage::Compute, entry)])
}

/// A raster pass's interface: the bindings its vertex and fragment entry points use (the
/// union), and the fragment outputs.
pub fn reflect_raster(
    source: &ShaderSource,
    vertex: &str,
    fragment: &str,
) -> Result<ShaderInterface, GraphError> {
    reflect_entries(
        source,
        &[
            (ShaderStage::Vertex, vertex),
            (ShaderStage::Fragment, fragment),
        ],
    )
}

fn reflect_entries(
    source: &ShaderSource,
    entries: &[(ShaderStage, &str)],
) -> Result<ShaderInterface, GraphError> {
    check_expression_size(source)?;
    // naga's parser, lowering and validator recurse once per operand of a left-nested
    // expression chain; the stack they need grows with it, and a main thread's 8 MiB overflow
    // (an abort, not an error) near 10,000 operands. The check above bounds the chains, and a
    // thread with a large stack (memory is committed only as it is touched) gives them room.
    let reflected = std::thread::scope(|scope| {
        std::thread::Builder::new()
            .name("naga".into())
            .stack_size(NAGA_STACK_BYTES)
            .spawn_scoped(scope, || reflect_module(source, entries))
            .map(|thread| thread.join())
    });
    match reflected {
        Ok(Ok(result)) => result,
        // A panic inside naga: report it as the shader's error rather than abort the check.
        Ok(Err(_)) => Err(GraphError::Wgsl {
            file: source.path.clone(),
            line: 1,
            col: 1,
            message: "the WGSL front end failed on this shader (internal error)".into(),
        }),
        // No thread could be started: parse here.
        Err(_) => reflect_module(source, entries),
    }
}

/// The stack of the thread naga runs on.
pub const NAGA_STACK_BYTES: usize = 256 << 20;

/// The most operators one statement may chain (`a + b + ...`): far more than hand-written
/// code has, and far within what naga parses on `NAGA_STACK_BYTES` (100,000 took 3 s).
pub const MAX_OPERATORS_PER_STATEMENT: usize = 16_384;

/// The deepest nesting of `(`, `[` and `{` together. naga stops at about 200 levels with an
/// internal error that has no position; this bound comes first and says where.
pub const MAX_NESTING: usize = 64;

/// A `read_write` storage buffer the entry points only store to (no load, no atomic) is
/// written, not read: WGSL has no write-only buffers, and counting it as read would make its
/// first writer in a frame read what nothing wrote (an error, or a needless persistent
/// resource). Storage textures keep their declared access, which their layout must match.
fn written_only(kind: BindingKind, read: impl Fn() -> bool) -> BindingKind {
    match kind {
        BindingKind::Storage {
            access: Access::ReadWrite,
            min_size,
        } if !read() => BindingKind::Storage {
            access: Access::Write,
            min_size,
        },
        other => other,
    }
}

fn reflect_module(
    source: &ShaderSource,
    entries: &[(ShaderStage, &str)],
) -> Result<ShaderInterface, GraphError> {
    let module =
        naga::front::wgsl::parse_str(&source.code).map_err(|error| parse_error(source, &error))?;
    let info = Validator::new(ValidationFlags::all(), capabilities())
        .validate(&module)
        .map_err(|error| validation_error(source, &error))?;

    let unsupported = |binding: &str, reason: String| GraphError::UnsupportedBinding {
        shader: source.path.clone(),
        binding: binding.to_string(),
        reason,
    };

    let mut found = Vec::new();
    for &(stage, entry) in entries {
        let Some((index, entry_point)) = module
            .entry_points
            .iter()
            .enumerate()
            .find(|(_, ep)| ep.stage == stage && ep.name == entry)
        else {
            return Err(GraphError::NoEntryPoint {
                pass_file: None,
                shader: source.path.clone(),
                stage: format!("{stage:?}").to_lowercase(),
                entry: entry.to_string(),
                available: module
                    .entry_points
                    .iter()
                    .filter(|ep| ep.stage == stage)
                    .map(|ep| ep.name.clone())
                    .collect(),
            });
        };
        // The framework computes dispatch sizes from the workgroup size before any override
        // is set.
        if entry_point.workgroup_size_overrides.is_some() {
            return Err(unsupported(
                "@workgroup_size",
                format!(
                    "entry point '{entry}' sizes its workgroup with an override; \
                     use constant expressions in @workgroup_size"
                ),
            ));
        }
        found.push((index, entry_point));
    }
    let compute = found
        .iter()
        .find(|(_, ep)| ep.stage == ShaderStage::Compute)
        .map(|(_, ep)| ep);
    let outputs = match found
        .iter()
        .find(|(_, ep)| ep.stage == ShaderStage::Fragment)
    {
        Some((_, ep)) => fragment_outputs(&module, ep)
            .map_err(|reason| unsupported(&format!("{} (fragment output)", ep.name), reason))?,
        None => Vec::new(),
    };

    let mut layers: HashMap<Handle<naga::GlobalVariable>, u32> = HashMap::new();
    for (_, ep) in &found {
        for (global, layer) in constant_layers(&module, &ep.function) {
            let slot = layers.entry(global).or_insert(layer);
            *slot = (*slot).max(layer);
        }
    }
    let mut bindings = Vec::new();
    let mut params = None;
    for (handle, var) in module.global_variables.iter() {
        // A file may hold several entry points; only what these touch is their interface.
        let used = found
            .iter()
            .any(|&(index, _)| !info.get_entry_point(index)[handle].is_empty());
        if !used || !is_resource(var.space) {
            continue;
        }
        let name = var.name.clone().unwrap_or_else(|| format!("{handle:?}"));
        let Some(slot) = var.binding else {
            if var.space == AddressSpace::Immediate {
                return Err(unsupported(
                    &name,
                    "immediates (push constants) are not supported: put the values in the \
                     `params` uniform"
                        .to_string(),
                ));
            }
            return Err(unsupported(&name, "has no @group/@binding".to_string()));
        };
        match binding_kind(&module, var.space, var.ty, &name) {
            Ok(Reflected::Params(fields, size)) => {
                params = Some(ParamBlock {
                    group: slot.group,
                    binding: slot.binding,
                    size,
                    fields,
                });
            }
            Ok(Reflected::Binding(kind)) => bindings.push(ShaderBinding {
                name,
                group: slot.group,
                binding: slot.binding,
                kind: written_only(kind, || {
                    found.iter().any(|&(index, _)| {
                        info.get_entry_point(index)[handle].contains(GlobalUse::READ)
                    })
                }),
                max_constant_layer: layers.get(&handle).copied(),
            }),
            Err(reason) => return Err(unsupported(&name, reason)),
        }
    }
    bindings.sort_by_key(|b| (b.group, b.binding));

    let mut overrides = Vec::new();
    for (handle, item) in module.overrides.iter() {
        let Some(name) = &item.name else { continue };
        // Pipelines set overrides by name, but WebGPU keys an `@id` override by its number.
        if let Some(id) = item.id {
            return Err(unsupported(
                name,
                format!(
                    "override has @id({id}); remove the @id: the framework sets overrides by name"
                ),
            ));
        }
        let ty = override_type(&module.types[item.ty].inner).ok_or_else(|| {
            unsupported(
                name,
                format!(
                    "override type {} is not supported (use bool, f32, u32 or i32)",
                    module.to_ctx().type_to_string(item.ty)
                ),
            )
        })?;
        let default = item
            .init
            .and_then(|init| match module.global_expressions[init] {
                naga::Expression::Literal(literal) => literal_value(literal),
                _ => None,
            });
        let span = module.overrides.get_span(handle);
        overrides.push(ShaderOverride {
            name: name.clone(),
            ty,
            has_default: item.init.is_some(),
            default,
            offset: span
                .is_defined()
                .then(|| span.to_range().map_or(0, |r| r.start)),
        });
    }

    // What needs subgroups is what fails to validate without them.
    let without_subgroups = capabilities()
        - (Capabilities::SUBGROUP
            | Capabilities::SUBGROUP_BARRIER
            | Capabilities::SUBGROUP_VERTEX_STAGE);
    let needs_subgroups = Validator::new(ValidationFlags::all(), without_subgroups)
        .validate(&module)
        .is_err();

    let interface = ShaderInterface {
        entry: entries
            .first()
            .map_or(String::new(), |(_, e)| e.to_string()),
        workgroup_size: compute.map_or([1, 1, 1], |ep| ep.workgroup_size),
        needs_subgroups,
        bindings,
        params,
        overrides,
        outputs,
    };
    source.keep_validated(ValidShader { module, info });
    Ok(interface)
}

#[cfg(test)]
mod tests;
