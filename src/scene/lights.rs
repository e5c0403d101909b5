//! Which triangles emit light: next-event estimation samples exactly these.

use super::bvh::is_degenerate;
use super::gpu::{Material, Triangle};

/// Indices (into `triangles`) of the triangles whose material has some `Ke` > 0 and whose area
/// is nonzero: a zero-area emitter can never be sampled (its pdf would divide by zero).
pub fn emissive_triangles(triangles: &[Triangle], materials: &[Material]) -> Vec<u32> {
    triangles
        .iter()
        .enumerate()
        .filter(|(_, t)| {
            materials
                .get(t.material as usize)
                .is_some_and(Material::is_emissive)
                && !is_degenerate(&t.vertices())
        })
        .map(|(i, _)| i as u32)
        .collect()
}
