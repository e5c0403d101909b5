//! Classifying a bound global: the `params` uniform, buffers, textures and their formats.

use super::*;

/// Address spaces whose variables are bound by the pipeline rather than owned by the shader.
pub(super) fn is_resource(space: AddressSpace) -> bool {
    matches!(
        space,
        AddressSpace::Uniform
            | AddressSpace::Storage { .. }
            | AddressSpace::Handle
            | AddressSpace::Immediate
    )
}

pub(super) enum Reflected {
    /// The `params` uniform: its fields and size.
    Params(Vec<ParamField>, u32),
    Binding(BindingKind),
}

/// Classifies one bound global, or says why the framework cannot bind it.
pub(super) fn binding_kind(
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
pub(super) fn texture_kind(
    inner: &TypeInner,
    type_name: &dyn Fn() -> String,
) -> Result<BindingKind, String> {
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
            let format = TextureFormat::STORAGE
                .into_iter()
                .find(|f| f.wgsl_name() == wgsl)
                .ok_or_else(|| {
                    let supported: Vec<_> = TextureFormat::STORAGE
                        .iter()
                        .map(|f| f.wgsl_name())
                        .collect();
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
pub(super) enum Kind {
    Sampled(SampleKind),
    Storage(TextureFormat, Access),
}

/// Declared access of a storage buffer or texture (not what the code happens to do with it).
pub(super) fn map_access(access: StorageAccess) -> Access {
    match (
        access.contains(StorageAccess::LOAD),
        access.contains(StorageAccess::STORE),
    ) {
        (true, true) => Access::ReadWrite,
        (false, true) => Access::Write,
        _ => Access::Read,
    }
}
