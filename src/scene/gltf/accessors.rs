//! Accessors read with every check a hostile file needs before the gltf crate's readers slice
//! and convert: the element type the attribute must have, a count of at least one, and the
//! byte range of every element inside its buffer view and buffer. Sparse accessors are not
//! read (no mesh attribute passgraph reads uses them in practice): an error says so.

use super::resources::view_bytes;
use gltf::accessor::{DataType, Dimensions};

/// What an accessor is, for messages: "accessor 3 (POSITION of mesh 'Cube' primitive 0)".
pub fn describe(accessor: &gltf::Accessor<'_>, role: &str) -> String {
    format!("accessor {} ({role})", accessor.index())
}

/// Checks that `accessor` has one of the `allowed` (data type, dimensions) pairs and that its
/// elements lie inside its view and buffer.
pub fn check(
    accessor: &gltf::Accessor<'_>,
    role: &str,
    allowed: &[(DataType, Dimensions)],
    buffers: &[Vec<u8>],
) -> Result<(), String> {
    let what = describe(accessor, role);
    let kind = (accessor.data_type(), accessor.dimensions());
    if !allowed.contains(&kind) {
        let names: Vec<String> = allowed
            .iter()
            .map(|(t, d)| format!("{d:?} of {t:?}"))
            .collect();
        return Err(format!(
            "{what} is {:?} of {:?}; expected {}",
            kind.1,
            kind.0,
            names.join(" or ")
        ));
    }
    if accessor.sparse().is_some() {
        return Err(format!("{what} is sparse, which passgraph does not read"));
    }
    if accessor.count() == 0 {
        return Err(format!("{what} has no elements"));
    }
    let Some(view) = accessor.view() else {
        return Err(format!(
            "{what} has no buffer view (all zeros), which passgraph does not read"
        ));
    };
    let bytes = view_bytes(&view, buffers)?;
    let size = accessor.size();
    let stride = view.stride().unwrap_or(size);
    if stride < size {
        return Err(format!(
            "{what}: buffer view {} has a byte stride of {stride}, less than an element's {size} bytes",
            view.index()
        ));
    }
    let end = (accessor.count() - 1)
        .checked_mul(stride)
        .and_then(|b| b.checked_add(accessor.offset()))
        .and_then(|b| b.checked_add(size));
    match end {
        Some(end) if end <= bytes.len() => Ok(()),
        _ => Err(format!(
            "{what}: {} elements of {size} bytes (stride {stride}) from byte {} run past the end of buffer view {} ({} bytes): accessor out of range",
            accessor.count(),
            accessor.offset(),
            view.index(),
            bytes.len()
        )),
    }
}

/// The first non-finite component of a list of vectors, as (element, value).
pub fn first_non_finite<const N: usize>(values: &[[f32; N]]) -> Option<(usize, f32)> {
    values
        .iter()
        .enumerate()
        .find_map(|(i, v)| v.iter().find(|c| !c.is_finite()).map(|&c| (i, c)))
}

/// Errors for the first non-finite value of an attribute.
pub fn check_finite<const N: usize>(
    values: &[[f32; N]],
    accessor: &gltf::Accessor<'_>,
    role: &str,
) -> Result<(), String> {
    match first_non_finite(values) {
        Some((i, c)) => Err(format!(
            "{}: element {i} has the non-finite value {c}; every value must be a finite number",
            describe(accessor, role)
        )),
        None => Ok(()),
    }
}
