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

/// The largest coordinate magnitude a vertex may have. The renderer works in f32 and multiplies
/// coordinate differences (edge cross products, squared distances): with |c| <= 1e18 those
/// stay below 1.2e37, within f32's 3.4e38; beyond, they overflow to infinity and the triangle
/// is lost as degenerate, so a file with such vertices is refused rather than rendered wrong.
pub const MAX_COORDINATE: f32 = 1e18;

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
