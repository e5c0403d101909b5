//! A fragment entry point's outputs, for checking colour attachments.

use super::*;

/// The `@location` outputs of a fragment entry point (a value or a struct of them), sorted.
pub(super) fn fragment_outputs(
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
