//! Loading a mesh file by its extension (OBJ with its MTL files, PLY), and the checks every
//! format gets: at least one triangle, a warning for triangles too large for f32.

use super::error::SceneError;
use super::mesh::{Mesh, MeshTriangle, normal_overflows};
use super::{obj, ply};
use glam::Vec3;
use std::path::Path;

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
