//! A triangle soup with materials: what every mesh format loads into.

use super::texture::Texture;
use crate::material::Material;
use glam::{Vec2, Vec3};
use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;

/// One triangle in file order; `material` indexes [`Mesh::materials`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshTriangle {
    /// Counter-clockwise seen from the front (the emitting side).
    pub vertices: [Vec3; 3],
    pub material: u32,
    /// Per-corner shading normals (OBJ `vn`, unit length), when every corner has one.
    pub normals: Option<[Vec3; 3]>,
    /// Per-corner texture coordinates (OBJ `vt`), when every corner has them.
    pub uvs: Option<[Vec2; 3]>,
}

impl MeshTriangle {
    /// A triangle without shading normals or texture coordinates.
    pub fn flat(vertices: [Vec3; 3], material: u32) -> MeshTriangle {
        MeshTriangle {
            vertices,
            material,
            normals: None,
            uvs: None,
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    /// The file it came from, for messages.
    pub path: PathBuf,
    pub triangles: Vec<MeshTriangle>,
    pub materials: Vec<Material>,
    /// `material_names[i]` names `materials[i]` (the MTL name, or "default").
    pub material_names: Vec<String>,
    /// The images the materials' `map_*` indices refer to.
    pub textures: Vec<Texture>,
    /// Material `front` seen from behind (the side its triangles' winding faces away from) is
    /// material `back`: Mitsuba's one-sided models (black from behind) and `twosided` with two
    /// BSDFs. Every material not in the map shades both sides alike (passgraph's default).
    pub back_materials: BTreeMap<u32, u32>,
    /// Materials whose opacity (`opacity` < 1 or `map_d`) is Mitsuba's `mask`: at a hit the
    /// surface shades with probability opacity and otherwise is a null interaction (the path
    /// goes straight on, one segment longer, and shadow rays stop there). Every other
    /// material's opacity cuts its surface out (MTL `d`: rays pass at no depth).
    pub null_masks: BTreeSet<u32>,
    /// What loaded but will not render as written, each naming the file (and line): for the
    /// command line to print.
    pub warnings: Vec<String>,
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
                .map(|&vertices| MeshTriangle::flat(vertices, 0))
                .collect(),
            materials: vec![Material::DEFAULT],
            material_names: vec![DEFAULT_MATERIAL_NAME.to_string()],
            textures: Vec::new(),
            back_materials: BTreeMap::new(),
            null_masks: BTreeSet::new(),
            warnings: Vec::new(),
        }
    }
}

/// Whether a triangle's normal (the edges' cross product) overflows f32: the BVH then treats
/// it as degenerate and it is never hit (it "vanishes"), which a file should not do silently.
pub fn normal_overflows(t: &MeshTriangle) -> bool {
    let [a, b, c] = t.vertices;
    !(b - a).cross(c - a).length_squared().is_finite()
}

/// Splits a polygon into triangles `(v0, v[i], v[i + 1])`, as the references do.
pub fn fan_triangulate<T: Copy>(polygon: &[T]) -> impl Iterator<Item = [T; 3]> + '_ {
    fan_corners(polygon.len()).map(|c| c.map(|k| polygon[k]))
}

/// [`fan_triangulate`]'s triangles of a polygon of `count` corners, as corner indices.
pub fn fan_corners(count: usize) -> impl Iterator<Item = [usize; 3]> {
    (2..count).map(|i| [0, i - 1, i])
}
