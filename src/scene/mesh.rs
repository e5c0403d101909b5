//! A triangle soup with materials: what every mesh format loads into.

use super::error::SceneError;
use super::gpu::Material;
use super::texture::Texture;
use super::{obj, ply};
use glam::{Vec2, Vec3};
pub(crate) use obj::load_obj_geometry;
pub(crate) use ply::load_ply_with_attributes;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

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

/// The largest coordinate magnitude a camera point may have. The renderer works in f32 and
/// multiplies coordinate differences (cross products, squared distances): with |c| <= 1e18
/// those stay below 1.2e37, within f32's 3.4e38.
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

/// A warning for triangles whose normal overflows, naming the file and, for an OBJ, the line
/// of the vertex farthest out.
fn overflow_warning(mesh: &Mesh) -> Option<String> {
    let overflowing: Vec<&MeshTriangle> = mesh
        .triangles
        .iter()
        .filter(|t| normal_overflows(t))
        .collect();
    let far = overflowing
        .iter()
        .flat_map(|t| t.vertices)
        .max_by(|p, q| p.abs().max_element().total_cmp(&q.abs().max_element()))?;
    let line = obj_vertex_line(&mesh.path, far);
    Some(format!(
        "{}{}: {} triangle{} so large that {} normal overflows f32 (a vertex at ({:e}, {:e}, {:e})); {} not rendered: scale the mesh down",
        mesh.path.display(),
        line.map_or(String::new(), |l| format!(":{l}")),
        overflowing.len(),
        if overflowing.len() == 1 {
            " is"
        } else {
            "s are"
        },
        if overflowing.len() == 1 {
            "its"
        } else {
            "their"
        },
        far.x,
        far.y,
        far.z,
        if overflowing.len() == 1 {
            "it is"
        } else {
            "they are"
        },
    ))
}

/// The line of an OBJ `v` statement with this position (after dividing by w), if any.
fn obj_vertex_line(path: &Path, p: Vec3) -> Option<usize> {
    let is_obj = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("obj"));
    if !is_obj {
        return None;
    }
    let text = crate::text_file::read_utf8(path).ok()?;
    // Lines as the OBJ loader counts them: CRLF and CR end lines too.
    let text = text.replace("\r\n", "\n").replace('\r', "\n");
    text.lines().enumerate().find_map(|(i, line)| {
        let rest = line.trim().strip_prefix("v ")?;
        let v: Vec<f32> = rest
            .split_whitespace()
            .map(str::parse)
            .collect::<Result<_, _>>()
            .ok()?;
        let w = if v.len() == 4 { v[3] } else { 1.0 };
        let q = Vec3::new(*v.first()? / w, *v.get(1)? / w, *v.get(2)? / w);
        (q == p).then_some(i + 1)
    })
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
    let mut mesh = match extension.as_deref() {
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
    mesh.warnings.extend(overflow_warning(&mesh));
    Ok(mesh)
}

/// Splits a polygon into triangles `(v0, v[i], v[i + 1])`, as the references do.
pub fn fan_triangulate<T: Copy>(polygon: &[T]) -> impl Iterator<Item = [T; 3]> + '_ {
    (2..polygon.len()).map(move |i| [polygon[0], polygon[i - 1], polygon[i]])
}
