//! A triangle soup with materials: what every mesh format loads into.

use super::error::SceneError;
use super::gpu::Material;
use super::{obj, ply};
use glam::Vec3;
use std::path::{Path, PathBuf};

/// One triangle in file order; `material` indexes [`Mesh::materials`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshTriangle {
    /// Counter-clockwise seen from the front (the emitting side).
    pub vertices: [Vec3; 3],
    pub material: u32,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    /// The file it came from, for messages.
    pub path: PathBuf,
    pub triangles: Vec<MeshTriangle>,
    pub materials: Vec<Material>,
    /// `material_names[i]` names `materials[i]` (the MTL name, or "default").
    pub material_names: Vec<String>,
}

/// The name given to [`Material::DEFAULT`] when a mesh needs it.
pub const DEFAULT_MATERIAL_NAME: &str = "default";

impl Mesh {
    /// A mesh of `triangles` that all use [`Material::DEFAULT`] (for tests and generated
    /// geometry).
    pub fn from_triangles(path: impl Into<PathBuf>, triangles: &[[Vec3; 3]]) -> Mesh {
        Mesh {
            path: path.into(),
            triangles: triangles
                .iter()
                .map(|&vertices| MeshTriangle {
                    vertices,
                    material: 0,
                })
                .collect(),
            materials: vec![Material::DEFAULT],
            material_names: vec![DEFAULT_MATERIAL_NAME.to_string()],
        }
    }
}

/// Loads a `.obj` (with its MTL files) or `.ply` mesh, chosen by extension (any case).
///
/// Errors name the file and, where the format has lines, the line: a missing file, a
/// non-finite vertex, a face index out of range, an unknown material, a missing material
/// library, a mesh without triangles.
pub fn load_mesh(path: &Path) -> Result<Mesh, SceneError> {
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let mesh = match extension.as_deref() {
        Some("obj") => obj::load_obj(path)?,
        Some("ply") => ply::load_ply(path)?,
        _ => {
            return Err(SceneError::UnsupportedMeshFormat {
                path: path.to_path_buf(),
            });
        }
    };
    if mesh.triangles.is_empty() {
        return Err(SceneError::NoTriangles {
            path: path.to_path_buf(),
        });
    }
    Ok(mesh)
}

/// Splits a polygon into triangles `(v0, v[i], v[i + 1])`, as the references do.
pub fn fan_triangulate<T: Copy>(polygon: &[T]) -> impl Iterator<Item = [T; 3]> + '_ {
    (2..polygon.len()).map(move |i| [polygon[0], polygon[i - 1], polygon[i]])
}
