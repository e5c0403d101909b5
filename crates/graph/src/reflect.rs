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
use naga::valid::{Capabilities, ValidationError, ValidationFlags, Validator};
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

/// Every storage format a graph resource can have, found by WGSL name.
const SUPPORTED_FORMATS: [TextureFormat; 17] = {
    use TextureFormat::*;
    [
        Rgba8Unorm,
        Rgba8Snorm,
        Rgba8Uint,
        Rgba8Sint,
        Bgra8Unorm,
        Rgba16Uint,
        Rgba16Sint,
        Rgba16Float,
        R32Uint,
        R32Sint,
        R32Float,
        Rg32Uint,
        Rg32Sint,
        Rg32Float,
        Rgba32Uint,
        Rgba32Sint,
        Rgba32Float,
    ]
};

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

/// Rejects a statement with more than [`MAX_OPERATORS_PER_STATEMENT`] binary operators, or
/// brackets nested deeper than [`MAX_NESTING`], with the file and line. Counts operator
/// characters between `;`, `{` and `}`, outside comments: an over-estimate (`<=` counts
/// twice), which is fine for a bound this loose.
fn check_expression_size(source: &ShaderSource) -> Result<(), GraphError> {
    let code = source.code.as_bytes();
    let mut start = 0;
    let mut operators = 0;
    let mut depth = 0usize;
    let mut i = 0;
    let error = |at: usize, message: String| {
        let (file, line, col) = source.locate(at);
        GraphError::Wgsl {
            file,
            line,
            col,
            message,
        }
    };
    while i < code.len() {
        match code[i] {
            b'/' if code.get(i + 1) == Some(&b'/') => {
                while i < code.len() && code[i] != b'\n' {
                    i += 1;
                }
                continue;
            }
            b'/' if code.get(i + 1) == Some(&b'*') => {
                i += 2;
                while i < code.len() && !(code[i] == b'*' && code.get(i + 1) == Some(&b'/')) {
                    i += 1;
                }
                i += 2;
                continue;
            }
            b';' | b'{' | b'}' => {
                start = i + 1;
                operators = 0;
            }
            _ => {}
        }
        match code[i] {
            b'(' | b'[' | b'{' => {
                depth += 1;
                if depth > MAX_NESTING {
                    return Err(error(
                        i,
                        format!(
                            "brackets and blocks nested more than {MAX_NESTING} deep; use intermediate `let`s or functions"
                        ),
                    ));
                }
            }
            b')' | b']' | b'}' => depth = depth.saturating_sub(1),
            b'+' | b'-' | b'*' | b'/' | b'%' | b'&' | b'|' | b'^' | b'<' | b'>' | b'=' | b'!' => {
                operators += 1;
                if operators > MAX_OPERATORS_PER_STATEMENT {
                    let at = start
                        + (code[start..]
                            .iter()
                            .take_while(|c| c.is_ascii_whitespace())
                            .count());
                    return Err(error(
                        at,
                        format!(
                            "this statement chains more than {MAX_OPERATORS_PER_STATEMENT} operators; split it into several statements"
                        ),
                    ));
                }
            }
            _ => {}
        }
        i += 1;
    }
    Ok(())
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
                kind,
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

/// The `@location` outputs of a fragment entry point (a value or a struct of them), sorted.
fn fragment_outputs(
    module: &Module,
    entry: &naga::EntryPoint,
) -> Result<Vec<FragmentOutput>, String> {
    let Some(result) = &entry.function.result else {
        return Ok(Vec::new());
    };
    let mut members = Vec::new();
    match (&result.binding, &module.types[result.ty].inner) {
        (Some(binding), _) => members.push((binding.clone(), result.ty)),
        (
            None,
            TypeInner::Struct {
                members: fields, ..
            },
        ) => {
            for f in fields {
                if let Some(binding) = &f.binding {
                    members.push((binding.clone(), f.ty));
                }
            }
        }
        (None, _) => {}
    }
    let mut outputs = Vec::new();
    for (binding, ty) in members {
        let naga::Binding::Location { location, .. } = binding else {
            continue;
        };
        let (scalar, components) = match module.types[ty].inner {
            TypeInner::Scalar(scalar) => (scalar, 1),
            TypeInner::Vector { size, scalar } => (scalar, size as u32),
            _ => {
                return Err(format!(
                    "@location({location}) has type {}; use a scalar or vector",
                    module.to_ctx().type_to_string(ty)
                ));
            }
        };
        let sample = match scalar.kind {
            ScalarKind::Uint => SampleKind::Uint,
            ScalarKind::Sint => SampleKind::Sint,
            _ => SampleKind::Float,
        };
        outputs.push(FragmentOutput {
            location,
            sample,
            components,
            ty: module.to_ctx().type_to_string(ty),
        });
    }
    outputs.sort_by_key(|o| o.location);
    Ok(outputs)
}

/// The highest constant layer index each global texture is loaded or stored with, in `entry`
/// and every function it calls.
fn constant_layers(
    module: &Module,
    entry: &naga::Function,
) -> HashMap<Handle<naga::GlobalVariable>, u32> {
    use naga::{Expression, Statement};
    let mut highest = HashMap::new();
    let mut seen = HashSet::new();
    let mut pending = vec![entry];
    while let Some(function) = pending.pop() {
        let exprs = &function.expressions;
        let mut note = |image: Handle<Expression>, index: Option<Handle<Expression>>| {
            let Expression::GlobalVariable(global) = exprs[image] else {
                return;
            };
            let Some(layer) = index.and_then(|i| constant_u32(module, exprs, i)) else {
                return;
            };
            let slot = highest.entry(global).or_insert(layer);
            *slot = (*slot).max(layer);
        };
        for (_, e) in exprs.iter() {
            if let Expression::ImageLoad {
                image, array_index, ..
            } = *e
            {
                note(image, array_index);
            }
        }
        // Statements nest (if, loop, switch); walk them with an explicit stack.
        let mut blocks = vec![&function.body];
        while let Some(block) = blocks.pop() {
            for statement in block.iter() {
                match statement {
                    Statement::ImageStore {
                        image, array_index, ..
                    } => note(*image, *array_index),
                    Statement::Call { function, .. } if seen.insert(*function) => {
                        pending.push(&module.functions[*function]);
                    }
                    Statement::Block(b) => blocks.push(b),
                    Statement::If { accept, reject, .. } => {
                        blocks.push(accept);
                        blocks.push(reject);
                    }
                    Statement::Loop {
                        body, continuing, ..
                    } => {
                        blocks.push(body);
                        blocks.push(continuing);
                    }
                    Statement::Switch { cases, .. } => blocks.extend(cases.iter().map(|c| &c.body)),
                    _ => {}
                }
            }
        }
    }
    highest
}

/// The value of a constant integer expression (a literal or a named `const`), if it is one.
fn constant_u32(
    module: &Module,
    exprs: &naga::Arena<naga::Expression>,
    e: Handle<naga::Expression>,
) -> Option<u32> {
    use naga::{Expression, Literal};
    let literal = |e: &Expression| match *e {
        Expression::Literal(l) => Some(l),
        _ => None,
    };
    let value = match exprs[e] {
        Expression::Constant(c) => literal(&module.global_expressions[module.constants[c].init])?,
        ref other => literal(other)?,
    };
    match value {
        Literal::U32(v) => Some(v),
        Literal::I32(v) => u32::try_from(v).ok(),
        Literal::AbstractInt(v) => u32::try_from(v).ok(),
        _ => None,
    }
}

/// Address spaces whose variables are bound by the pipeline rather than owned by the shader.
fn is_resource(space: AddressSpace) -> bool {
    matches!(
        space,
        AddressSpace::Uniform
            | AddressSpace::Storage { .. }
            | AddressSpace::Handle
            | AddressSpace::Immediate
    )
}

enum Reflected {
    /// The `params` uniform: its fields and size.
    Params(Vec<ParamField>, u32),
    Binding(BindingKind),
}

/// Classifies one bound global, or says why the framework cannot bind it.
fn binding_kind(
    module: &Module,
    space: AddressSpace,
    ty: Handle<Type>,
    name: &str,
) -> Result<Reflected, String> {
    let inner = &module.types[ty].inner;
    let type_name = || module.to_ctx().type_to_string(ty);
    if let TypeInner::BindingArray { .. } = inner {
        return Err(format!(
            "binding arrays ({}) are not supported: bind each resource separately",
            type_name()
        ));
    }
    let size = || {
        inner
            .try_size(module.to_ctx())
            .ok_or_else(|| format!("type {} is too large", type_name()))
    };
    match space {
        AddressSpace::Uniform if name == PARAMS_NAME => {
            let TypeInner::Struct { members, span } = inner else {
                return Err(format!(
                    "the `{PARAMS_NAME}` uniform must be a struct of params, not {}",
                    type_name()
                ));
            };
            let fields = members
                .iter()
                .map(|member| {
                    let field = member.name.clone().unwrap_or_default();
                    let ty =
                        uniform_field_type(&module.types[member.ty].inner).ok_or_else(|| {
                            format!(
                                "field '{field}' has type {}, which is not a param type \
                             (use f32, u32, i32, vec2<f32>, vec3<f32> or vec4<f32>)",
                                module.to_ctx().type_to_string(member.ty)
                            )
                        })?;
                    Ok(ParamField {
                        name: field,
                        ty,
                        offset: member.offset,
                    })
                })
                .collect::<Result<_, String>>()?;
            Ok(Reflected::Params(fields, *span))
        }
        AddressSpace::Uniform => Ok(Reflected::Binding(BindingKind::Uniform {
            size: u64::from(size()?),
        })),
        AddressSpace::Storage { access } => Ok(Reflected::Binding(BindingKind::Storage {
            access: map_access(access),
            // For a runtime-sized array naga counts one element: the least a buffer must hold.
            min_size: u64::from(size()?),
        })),
        AddressSpace::Handle => texture_kind(inner, &type_name).map(Reflected::Binding),
        _ => Err(format!(
            "variables in the {space:?} address space are not supported as bindings"
        )),
    }
}

/// Classifies a handle-space global: only 2D sampled and storage textures are supported.
fn texture_kind(inner: &TypeInner, type_name: &dyn Fn() -> String) -> Result<BindingKind, String> {
    let (dim, arrayed, class) = match *inner {
        TypeInner::Image {
            dim,
            arrayed,
            class,
        } => (dim, arrayed, class),
        TypeInner::Sampler { .. } => {
            return Err("samplers are not supported: read textures with textureLoad".to_string());
        }
        TypeInner::AccelerationStructure { .. } => {
            return Err("acceleration structures are not supported".to_string());
        }
        _ => {
            return Err(format!(
                "type {} is not supported as a binding",
                type_name()
            ));
        }
    };
    let kind = match class {
        ImageClass::Depth { .. } => {
            return Err(format!(
                "depth textures ({}) are not supported: use texture_2d<f32>",
                type_name()
            ));
        }
        ImageClass::Sampled { multi: true, .. } => {
            return Err(format!(
                "multisampled textures ({}) are not supported",
                type_name()
            ));
        }
        ImageClass::External => {
            return Err("external textures are not supported".to_string());
        }
        ImageClass::Storage { access, .. } if access.contains(StorageAccess::ATOMIC) => {
            return Err(format!(
                "atomic storage textures ({}) are not supported",
                type_name()
            ));
        }
        ImageClass::Sampled { kind, multi: false } => Kind::Sampled(match kind {
            ScalarKind::Float => SampleKind::Float,
            ScalarKind::Uint => SampleKind::Uint,
            ScalarKind::Sint => SampleKind::Sint,
            ScalarKind::Bool | ScalarKind::AbstractInt | ScalarKind::AbstractFloat => {
                return Err(format!("texture type {} is not supported", type_name()));
            }
        }),
        ImageClass::Storage { format, access } => {
            let wgsl = format.to_wgsl();
            let format = SUPPORTED_FORMATS
                .into_iter()
                .find(|f| f.wgsl_name() == wgsl)
                .ok_or_else(|| {
                    let supported: Vec<_> =
                        SUPPORTED_FORMATS.iter().map(|f| f.wgsl_name()).collect();
                    format!(
                        "storage texture format {wgsl} is not supported (supported: {})",
                        supported.join(", ")
                    )
                })?;
            Kind::Storage(format, map_access(access))
        }
    };
    let dim = match (dim, arrayed) {
        (ImageDimension::D2, false) => TextureDim::D2,
        (ImageDimension::D2, true) => TextureDim::D2Array,
        (other, _) => {
            return Err(format!(
                "{} textures ({}) are not supported: only 2d and 2d_array textures can be bound",
                other.to_wgsl(),
                type_name()
            ));
        }
    };
    Ok(match kind {
        Kind::Sampled(sample) => BindingKind::SampledTexture { sample, dim },
        Kind::Storage(format, access) => BindingKind::StorageTexture {
            access,
            format,
            dim,
        },
    })
}

/// A texture binding before its dimension is checked.
enum Kind {
    Sampled(SampleKind),
    Storage(TextureFormat, Access),
}

/// Declared access of a storage buffer or texture (not what the code happens to do with it).
fn map_access(access: StorageAccess) -> Access {
    match (
        access.contains(StorageAccess::LOAD),
        access.contains(StorageAccess::STORE),
    ) {
        (true, true) => Access::ReadWrite,
        (false, true) => Access::Write,
        _ => Access::Read,
    }
}

fn uniform_field_type(inner: &TypeInner) -> Option<ParamType> {
    match *inner {
        TypeInner::Scalar(Scalar::F32) => Some(ParamType::F32),
        TypeInner::Scalar(Scalar::U32) => Some(ParamType::U32),
        TypeInner::Scalar(Scalar::I32) => Some(ParamType::I32),
        TypeInner::Vector {
            size,
            scalar: Scalar::F32,
        } => Some(match size {
            VectorSize::Bi => ParamType::Vec2,
            VectorSize::Tri => ParamType::Vec3,
            VectorSize::Quad => ParamType::Vec4,
        }),
        _ => None,
    }
}

/// A literal override default as a param value (the override types: bool, f32, u32, i32).
fn literal_value(literal: naga::Literal) -> Option<ParamValue> {
    match literal {
        naga::Literal::Bool(b) => Some(ParamValue::Bool(b)),
        naga::Literal::F32(f) => Some(ParamValue::F32(f)),
        naga::Literal::U32(u) => Some(ParamValue::U32(u)),
        naga::Literal::I32(i) => Some(ParamValue::I32(i)),
        _ => None,
    }
}

fn override_type(inner: &TypeInner) -> Option<ParamType> {
    match *inner {
        TypeInner::Scalar(Scalar::BOOL) => Some(ParamType::Bool),
        TypeInner::Scalar(Scalar::F32) => Some(ParamType::F32),
        TypeInner::Scalar(Scalar::U32) => Some(ParamType::U32),
        TypeInner::Scalar(Scalar::I32) => Some(ParamType::I32),
        _ => None,
    }
}

/// Where an error without a usable span is reported.
fn start_of_main(source: &ShaderSource) -> (PathBuf, usize, usize) {
    (source.path.clone(), 1, 1)
}

fn wgsl_error(location: (PathBuf, usize, usize), message: String) -> GraphError {
    let (file, line, col) = location;
    GraphError::Wgsl {
        file,
        line,
        col,
        message,
    }
}

/// Whether a span label says something the message does not.
fn adds_information(message: &str, label: &str) -> bool {
    let label = label.trim();
    !label.is_empty() && label != "see msg" && !message.contains(label)
}

fn parse_error(source: &ShaderSource, error: &naga::front::wgsl::ParseError) -> GraphError {
    let mut labels = error
        .labels()
        .filter_map(|(span, label)| Some((span.to_range()?, label)));
    let primary = labels.next();
    let mut message = error.message().to_string();
    if let Some((_, label)) = &primary {
        if adds_information(&message, label) {
            message.push_str(&format!(" ({})", label.trim()));
        }
    }
    // Secondary labels point elsewhere, possibly into another file (e.g. the previous
    // definition in an included library), so they carry their own location.
    for (range, label) in labels {
        if adds_information(&message, label) {
            let (file, line, col) = source.locate(range.start);
            message.push_str(&format!(
                "; {} at {}:{line}:{col}",
                label.trim(),
                file.display()
            ));
        }
    }
    for note in error.notes() {
        message.push_str(&format!("; note: {note}"));
    }
    let location = primary.map_or_else(
        || start_of_main(source),
        |(range, _)| source.locate(range.start),
    );
    wgsl_error(location, message)
}

fn validation_error(source: &ShaderSource, error: &naga::WithSpan<ValidationError>) -> GraphError {
    // The top-level message only names the function or global; the cause says what is wrong.
    let mut message = error.to_string();
    let mut cause = error.source();
    while let Some(inner) = cause {
        message.push_str(&format!(": {inner}"));
        cause = inner.source();
    }
    // naga lists the enclosing item's span (a whole function) before the offending
    // expression's, so the first span that contains no other is the precise one.
    let spans: Vec<(Range<usize>, &str)> = error
        .spans()
        .filter_map(|(span, label)| Some((span.to_range()?, label.as_str())))
        .collect();
    let innermost = spans.iter().find(|(outer, _)| {
        !spans.iter().any(|(inner, _)| {
            inner != outer && outer.start <= inner.start && inner.end <= outer.end
        })
    });
    let location = match innermost {
        Some((range, label)) => {
            // Labels naming naga's IR ("naga::ir::Function [0]") mean nothing to users.
            if !label.starts_with("naga::") && adds_information(&message, label) {
                message.push_str(&format!(" ({})", label.trim()));
            }
            source.locate(range.start)
        }
        None => start_of_main(source),
    };
    wgsl_error(location, message)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fs;
    use std::path::Path;

    fn reflect_code(code: &str, entry: &str) -> Result<ShaderInterface, GraphError> {
        reflect(
            &ShaderSource::from_code("test.wgsl".into(), code.to_string()),
            entry,
        )
    }

    fn interface(code: &str) -> ShaderInterface {
        match reflect_code(code, "main") {
            Ok(interface) => interface,
            Err(e) => panic!("reflect failed: {e}"),
        }
    }

    fn single_binding(code: &str) -> BindingKind {
        let interface = interface(code);
        assert_eq!(interface.bindings.len(), 1, "{:?}", interface.bindings);
        interface.bindings[0].kind.clone()
    }

    fn unsupported_reason(code: &str) -> (String, String) {
        match reflect_code(code, "main") {
            Err(GraphError::UnsupportedBinding {
                binding, reason, ..
            }) => (binding, reason),
            other => panic!("expected UnsupportedBinding, got {other:?}"),
        }
    }

    fn wgsl_error_at(result: Result<ShaderInterface, GraphError>) -> (PathBuf, usize, usize) {
        match result {
            Err(GraphError::Wgsl {
                file, line, col, ..
            }) => (file, line, col),
            other => panic!("expected Wgsl error, got {other:?}"),
        }
    }

    fn project(files: &[(&str, &str)]) -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        for (path, content) in files {
            let path = dir.path().join(path);
            fs::create_dir_all(path.parent().unwrap()).unwrap();
            fs::write(path, content).unwrap();
        }
        dir
    }

    fn same_file(a: &Path, b: &Path) -> bool {
        a.canonicalize().unwrap() == b.canonicalize().unwrap()
    }

    #[test]
    fn storage_buffer_access_follows_declaration() {
        let read = single_binding(
            "@group(0) @binding(0) var<storage, read> buf: array<u32>;
             @compute @workgroup_size(1) fn main() { _ = buf[0]; }",
        );
        assert_eq!(
            read,
            BindingKind::Storage {
                access: Access::Read,
                min_size: 4
            }
        );
        // Declared read_write but only read: the declaration decides, as the pipeline layout does.
        let read_write = single_binding(
            "@group(0) @binding(0) var<storage, read_write> buf: array<u32>;
             @compute @workgroup_size(1) fn main() { _ = buf[0]; }",
        );
        assert_eq!(read_write.access(), Access::ReadWrite);
    }

    #[test]
    fn storage_min_size_counts_struct_with_one_runtime_element() {
        let kind = single_binding(
            "struct Particles { count: u32, items: array<vec4<f32>> }
             @group(0) @binding(0) var<storage, read_write> particles: Particles;
             @compute @workgroup_size(64) fn main() { particles.count = 1u; }",
        );
        // count at 0, items aligned to 16, one 16-byte element.
        assert_eq!(
            kind,
            BindingKind::Storage {
                access: Access::ReadWrite,
                min_size: 32
            }
        );
    }

    #[test]
    fn storage_min_size_of_bare_runtime_array_is_one_stride() {
        let kind = single_binding(
            "@group(0) @binding(0) var<storage, read> v: array<vec3<f32>>;
             @compute @workgroup_size(1) fn main() { _ = v[0]; }",
        );
        assert_eq!(
            kind,
            BindingKind::Storage {
                access: Access::Read,
                min_size: 16
            }
        );
    }

    #[test]
    fn uniform_other_than_params_is_a_sized_binding() {
        let kind = single_binding(
            "struct Eye { view: mat4x4<f32>, pos: vec3<f32> }
             @group(0) @binding(0) var<uniform> eye: Eye;
             @compute @workgroup_size(1) fn main() { _ = eye.pos; }",
        );
        assert_eq!(kind, BindingKind::Uniform { size: 80 });
    }

    #[test]
    fn storage_texture_access_format_and_dim() {
        let interface = interface(
            "@group(0) @binding(0) var w: texture_storage_2d<rgba16float, write>;
             @group(0) @binding(1) var r: texture_storage_2d_array<r32float, read>;
             @group(0) @binding(2) var rw: texture_storage_2d<rgba8unorm, read_write>;
             @compute @workgroup_size(8, 8) fn main() {
                 let x = textureLoad(r, vec2(0, 0), 0);
                 textureStore(rw, vec2(0, 0), textureLoad(rw, vec2(0, 0)));
                 textureStore(w, vec2(0, 0), x);
             }",
        );
        let kinds: Vec<_> = interface.bindings.iter().map(|b| b.kind.clone()).collect();
        assert_eq!(
            kinds,
            [
                BindingKind::StorageTexture {
                    access: Access::Write,
                    format: TextureFormat::Rgba16Float,
                    dim: TextureDim::D2
                },
                BindingKind::StorageTexture {
                    access: Access::Read,
                    format: TextureFormat::R32Float,
                    dim: TextureDim::D2Array
                },
                BindingKind::StorageTexture {
                    access: Access::ReadWrite,
                    format: TextureFormat::Rgba8Unorm,
                    dim: TextureDim::D2
                },
            ]
        );
        assert_eq!(interface.workgroup_size, [8, 8, 1]);
    }

    #[test]
    fn every_supported_storage_format_maps_to_the_same_texture_format() {
        for format in SUPPORTED_FORMATS {
            let kind = single_binding(&format!(
                "@group(0) @binding(0) var t: texture_storage_2d<{}, write>;
                 @compute @workgroup_size(1) fn main() {{ _ = textureDimensions(t); }}",
                format.wgsl_name()
            ));
            assert_eq!(
                kind,
                BindingKind::StorageTexture {
                    access: Access::Write,
                    format,
                    dim: TextureDim::D2
                }
            );
        }
    }

    #[test]
    fn unsupported_storage_format_is_named() {
        let (binding, reason) = unsupported_reason(
            "@group(0) @binding(0) var t: texture_storage_2d<r16unorm, write>;
             @compute @workgroup_size(1) fn main() { _ = textureDimensions(t); }",
        );
        assert_eq!(binding, "t");
        assert!(reason.contains("r16unorm"), "{reason}");
    }

    #[test]
    fn sampled_texture_kind_and_dim() {
        let interface = interface(
            "@group(0) @binding(0) var a: texture_2d<f32>;
             @group(0) @binding(1) var b: texture_2d<u32>;
             @group(1) @binding(0) var c: texture_2d_array<i32>;
             @compute @workgroup_size(1) fn main() {
                 _ = textureLoad(a, vec2(0, 0), 0);
                 _ = textureLoad(b, vec2(0, 0), 0);
                 _ = textureLoad(c, vec2(0, 0), 0, 0);
             }",
        );
        let kinds: Vec<_> = interface.bindings.iter().map(|b| b.kind.clone()).collect();
        assert_eq!(
            kinds,
            [
                BindingKind::SampledTexture {
                    sample: SampleKind::Float,
                    dim: TextureDim::D2
                },
                BindingKind::SampledTexture {
                    sample: SampleKind::Uint,
                    dim: TextureDim::D2
                },
                BindingKind::SampledTexture {
                    sample: SampleKind::Sint,
                    dim: TextureDim::D2Array
                },
            ]
        );
    }

    #[test]
    fn bindings_are_sorted_by_group_then_binding() {
        let interface = interface(
            "@group(1) @binding(0) var<storage, read> d: array<u32>;
             @group(0) @binding(3) var<storage, read> c: array<u32>;
             @group(0) @binding(1) var<storage, read> b: array<u32>;
             @compute @workgroup_size(1) fn main() { _ = b[0]; _ = c[0]; _ = d[0]; }",
        );
        let slots: Vec<_> = interface
            .bindings
            .iter()
            .map(|b| (b.name.as_str(), b.group, b.binding))
            .collect();
        assert_eq!(slots, [("b", 0, 1), ("c", 0, 3), ("d", 1, 0)]);
    }

    #[test]
    fn params_block_fields_offsets_and_size() {
        let interface = interface(
            "struct Params { a: f32, b: vec3<f32>, c: u32, d: i32, e: vec2<f32>, f: vec4<f32> }
             @group(0) @binding(2) var<uniform> params: Params;
             @compute @workgroup_size(1) fn main() { _ = params.a; }",
        );
        let block = interface.params.expect("params block");
        assert_eq!((block.group, block.binding), (0, 2));
        let fields: Vec<_> = block
            .fields
            .iter()
            .map(|f| (f.name.as_str(), f.ty, f.offset))
            .collect();
        assert_eq!(
            fields,
            [
                ("a", ParamType::F32, 0),
                ("b", ParamType::Vec3, 16),
                ("c", ParamType::U32, 28),
                ("d", ParamType::I32, 32),
                ("e", ParamType::Vec2, 40),
                ("f", ParamType::Vec4, 48),
            ]
        );
        assert_eq!(block.size, 64);
        // The params block is not an ordinary binding.
        assert!(interface.bindings.is_empty());
    }

    #[test]
    fn params_field_of_unsupported_type_is_named() {
        let (binding, reason) = unsupported_reason(
            "struct Params { scale: f32, m: mat4x4<f32> }
             @group(0) @binding(0) var<uniform> params: Params;
             @compute @workgroup_size(1) fn main() { _ = params.scale; }",
        );
        assert_eq!(binding, "params");
        assert!(
            reason.contains("'m'") && reason.contains("mat4x4<f32>"),
            "{reason}"
        );
    }

    #[test]
    fn params_uniform_that_is_not_a_struct_is_rejected() {
        let (binding, reason) = unsupported_reason(
            "@group(0) @binding(0) var<uniform> params: vec4<f32>;
             @compute @workgroup_size(1) fn main() { _ = params.x; }",
        );
        assert_eq!(binding, "params");
        assert!(reason.contains("struct"), "{reason}");
    }

    #[test]
    fn unused_globals_are_not_bindings() {
        let interface = interface(
            "struct Params { a: f32 }
             @group(0) @binding(0) var<uniform> params: Params;
             @group(0) @binding(1) var<storage, read> unused: array<u32>;
             @group(0) @binding(2) var<storage, read_write> used: array<u32>;
             @group(0) @binding(3) var s: sampler;
             fn helper() { used[0] = 1u; }
             @compute @workgroup_size(1) fn main() { helper(); }",
        );
        let names: Vec<_> = interface.bindings.iter().map(|b| b.name.as_str()).collect();
        // `used` is reached through a helper function; an unused sampler is no error either.
        assert_eq!(names, ["used"]);
        assert_eq!(interface.params, None);
    }

    #[test]
    fn each_entry_point_gets_only_its_own_bindings() {
        let code = "@group(0) @binding(0) var<storage, read> input: array<f32>;
             @group(0) @binding(1) var<storage, read_write> a: array<f32>;
             @group(0) @binding(2) var<storage, read_write> b: array<f32>;
             @compute @workgroup_size(64) fn first() { a[0] = input[0]; }
             @compute @workgroup_size(8, 8) fn second() { b[0] = input[0]; }";
        let names = |entry: &str| {
            let interface = reflect_code(code, entry).unwrap();
            let names: Vec<_> = interface.bindings.into_iter().map(|b| b.name).collect();
            (names, interface.workgroup_size, interface.entry)
        };
        assert_eq!(
            names("first"),
            (vec!["input".into(), "a".into()], [64, 1, 1], "first".into())
        );
        assert_eq!(
            names("second"),
            (vec!["input".into(), "b".into()], [8, 8, 1], "second".into())
        );
    }

    #[test]
    fn missing_entry_point_lists_compute_entry_points_only() {
        let result = reflect_code(
            "@compute @workgroup_size(1) fn a() {}
             @compute @workgroup_size(1) fn b() {}
             @fragment fn fs() -> @location(0) vec4<f32> { return vec4(1.0); }",
            "fs",
        );
        match result {
            Err(GraphError::NoEntryPoint {
                entry, available, ..
            }) => {
                assert_eq!(entry, "fs");
                assert_eq!(available, ["a", "b"]);
            }
            other => panic!("expected NoEntryPoint, got {other:?}"),
        }
    }

    #[test]
    fn unsupported_binding_types_are_rejected_with_reason() {
        let cases = [
            ("var s: sampler;", "_ = s;", "sampler"),
            (
                "var d: texture_depth_2d;",
                "_ = textureDimensions(d);",
                "depth",
            ),
            (
                "var m: texture_multisampled_2d<f32>;",
                "_ = textureDimensions(m);",
                "multisampled",
            ),
            ("var t: texture_3d<f32>;", "_ = textureDimensions(t);", "3d"),
            ("var t: texture_1d<f32>;", "_ = textureDimensions(t);", "1d"),
            (
                "var t: texture_cube<f32>;",
                "_ = textureDimensions(t);",
                "cube",
            ),
            (
                "var t: texture_storage_3d<rgba8unorm, write>;",
                "_ = textureDimensions(t);",
                "3d",
            ),
        ];
        for (decl, use_, expected) in cases {
            let code = format!(
                "@group(0) @binding(0) {decl}\n@compute @workgroup_size(1) fn main() {{ {use_} }}"
            );
            let (_, reason) = unsupported_reason(&code);
            assert!(reason.contains(expected), "{decl}: {reason}");
        }
    }

    #[test]
    fn binding_arrays_are_rejected_with_reason() {
        let (binding, reason) = unsupported_reason(
            "enable wgpu_binding_array;
             @group(0) @binding(0) var ts: binding_array<texture_2d<f32>, 4>;
             @compute @workgroup_size(1) fn main() { _ = textureLoad(ts[0], vec2(0, 0), 0); }",
        );
        assert_eq!(binding, "ts");
        assert!(reason.contains("binding arrays"), "{reason}");
    }

    #[test]
    fn overrides_with_types_and_defaults() {
        let interface = interface(
            "override enabled: bool = true;
             override scale: f32;
             override count: u32 = 4u;
             override offset: i32 = -1;
             @compute @workgroup_size(1) fn main() { _ = scale; }",
        );
        let overrides: Vec<_> = interface
            .overrides
            .iter()
            .map(|o| (o.name.as_str(), o.ty, o.has_default))
            .collect();
        assert_eq!(
            overrides,
            [
                ("enabled", ParamType::Bool, true),
                ("scale", ParamType::F32, false),
                ("count", ParamType::U32, true),
                ("offset", ParamType::I32, true),
            ]
        );
    }

    #[test]
    fn override_with_id_is_rejected_because_it_cannot_be_set_by_name() {
        let (binding, reason) = unsupported_reason(
            "@id(3) override scale: f32 = 1.0;
             @compute @workgroup_size(1) fn main() { _ = scale; }",
        );
        assert_eq!(binding, "scale");
        assert!(reason.contains("@id(3)"), "{reason}");
    }

    #[test]
    fn override_sized_workgroup_is_rejected() {
        let (binding, _) = unsupported_reason(
            "override size: u32 = 64u;
             @compute @workgroup_size(size) fn main() {}",
        );
        assert_eq!(binding, "@workgroup_size");
    }

    #[test]
    fn const_sized_workgroup_is_accepted() {
        let interface = interface(
            "const SIZE = 16u;
             @compute @workgroup_size(SIZE, SIZE / 2u) fn main() {}",
        );
        assert_eq!(interface.workgroup_size, [16, 8, 1]);
    }

    #[test]
    fn parse_error_in_included_lib_reports_lib_file_and_line() {
        let dir = project(&[
            (
                "shaders/lib/rng.wgsl",
                "// rng\nfn rng(seed: u32) -> u32 {\n    let x = seed * 747796405u\n    return x;\n}\n",
            ),
            (
                "shaders/passes/noise.wgsl",
                "// noise\n#include \"lib/rng.wgsl\"\n@compute @workgroup_size(1) fn main() {}\n",
            ),
        ]);
        let root = dir.path().join("shaders");
        let source = ShaderSource::load(&root.join("passes/noise.wgsl"), &root).unwrap();
        let (file, line, col) = wgsl_error_at(reflect(&source, "main"));
        assert!(same_file(&file, &root.join("lib/rng.wgsl")), "{file:?}");
        // naga points at the token after the missing `;`.
        assert_eq!((line, col), (4, 5));
    }

    #[test]
    fn parse_error_after_include_reports_main_file_own_line() {
        let dir = project(&[
            (
                "shaders/lib/rng.wgsl",
                "fn rng(seed: u32) -> u32 {\n    return seed * 747796405u;\n}\n",
            ),
            (
                "shaders/noise.wgsl",
                "#include \"lib/rng.wgsl\"\n\n@compute @workgroup_size(1) fn main() {\n    let x: u32 = rng(1u) +;\n}\n",
            ),
        ]);
        let root = dir.path().join("shaders");
        let main = root.join("noise.wgsl");
        let source = ShaderSource::load(&main, &root).unwrap();
        let (file, line, _) = wgsl_error_at(reflect(&source, "main"));
        assert_eq!(file, main);
        assert_eq!(line, 4);
    }

    #[test]
    fn parse_error_message_keeps_informative_labels() {
        let result = reflect_code(
            "fn f() {}\nfn f() {}\n@compute @workgroup_size(1) fn main() {}",
            "main",
        );
        match result {
            Err(GraphError::Wgsl {
                line, col, message, ..
            }) => {
                assert_eq!((line, col), (2, 4));
                // The previous definition is elsewhere, so the message says where.
                assert!(message.contains("test.wgsl:1:4"), "{message}");
            }
            other => panic!("expected Wgsl error, got {other:?}"),
        }
    }

    #[test]
    fn validation_error_points_at_offending_expression_not_enclosing_function() {
        let result = reflect_code(
            "@group(0) @binding(0) var<storage, read> b: array<f32>;\n\
             fn helper(i: u32) {\n\
             \x20   b[i] = 1.0;\n\
             }\n\
             @compute @workgroup_size(1) fn main() { helper(0u); }",
            "main",
        );
        match result {
            Err(GraphError::Wgsl {
                file,
                line,
                col,
                message,
            }) => {
                assert_eq!(file, PathBuf::from("test.wgsl"));
                assert_eq!((line, col), (3, 5));
                // The cause, not just "Function 'helper' is invalid".
                assert!(message.contains("store"), "{message}");
            }
            other => panic!("expected Wgsl error, got {other:?}"),
        }
    }

    #[test]
    fn validation_error_in_included_lib_reports_lib_file() {
        let dir = project(&[
            (
                "shaders/lib/layout.wgsl",
                "// layout\n@group(0) @binding(0) var<uniform> weights: array<f32, 4>;\n",
            ),
            (
                "shaders/p.wgsl",
                "#include \"lib/layout.wgsl\"\n@compute @workgroup_size(1) fn main() { _ = weights[0]; }\n",
            ),
        ]);
        let root = dir.path().join("shaders");
        let source = ShaderSource::load(&root.join("p.wgsl"), &root).unwrap();
        let (file, line, _) = wgsl_error_at(reflect(&source, "main"));
        assert!(same_file(&file, &root.join("lib/layout.wgsl")), "{file:?}");
        assert_eq!(line, 2);
    }

    #[test]
    fn validation_error_without_span_points_at_start_of_main_file() {
        // f64 needs a native feature; naga reports the type without a span.
        let location = wgsl_error_at(reflect_code(
            "\n@compute @workgroup_size(1) fn main() { var x: f64 = 1.0lf; }",
            "main",
        ));
        assert_eq!(location, (PathBuf::from("test.wgsl"), 1, 1));
    }

    #[test]
    fn core_wgsl_builtins_needing_capabilities_validate() {
        // pack2x16float is core WGSL but needs SHADER_FLOAT16_IN_FLOAT32 in naga.
        interface("@compute @workgroup_size(1) fn main() { _ = pack2x16float(vec2(1.0)); }");
    }

    #[test]
    fn raster_entry_points_union_their_bindings_and_list_fragment_outputs() {
        let code = "@group(0) @binding(0) var<uniform> scale: vec4<f32>;
             @group(0) @binding(1) var tex: texture_2d<u32>;
             @group(0) @binding(2) var<storage, read> unused: array<u32>;
             struct Out { @location(1) id: vec2<u32>, @location(0) colour: vec4<f32>,
                          @builtin(frag_depth) depth: f32 }
             @vertex fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
                 return scale * f32(i);
             }
             @fragment fn fs() -> Out {
                 return Out(textureLoad(tex, vec2(0, 0), 0).xy, vec4(1.0), 0.5);
             }
             @compute @workgroup_size(1) fn main() { _ = unused[0]; }";
        let source = ShaderSource::from_code("test.wgsl".into(), code.to_string());
        let interface = reflect_raster(&source, "vs", "fs").unwrap();
        let names: Vec<_> = interface.bindings.iter().map(|b| b.name.as_str()).collect();
        assert_eq!(names, ["scale", "tex"]);
        let outputs: Vec<_> = interface
            .outputs
            .iter()
            .map(|o| (o.location, o.sample, o.components, o.ty.as_str()))
            .collect();
        assert_eq!(
            outputs,
            [
                (0, SampleKind::Float, 4, "vec4<f32>"),
                (1, SampleKind::Uint, 2, "vec2<u32>"),
            ]
        );
        // Entry points are found by stage: a compute entry point is no vertex shader, and the
        // message says which stage was looked for.
        let e = reflect_raster(&source, "main", "fs").unwrap_err();
        assert!(matches!(e, GraphError::NoEntryPoint { .. }));
        let e = e.in_pass_file(Path::new("passes/gbuffer.ron")).to_string();
        assert!(
            e.starts_with("passes/gbuffer.ron: pass's shader ")
                && e.contains("no vertex entry point 'main'"),
            "{e}"
        );
    }
}
