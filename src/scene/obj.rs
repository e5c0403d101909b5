//! OBJ + MTL meshes through tobj.
//!
//! tobj reports errors without lines (and panics on a colour with fewer than three numbers), so
//! the text is checked line by line first: every problem found there names its file and line.
//! tobj then reads a normalised copy holding only what the renderer uses (positions, faces by
//! position index, objects, material libraries and `usemtl`), one line per original line, and
//! fan-triangulates the polygons.

use super::error::{Location, SceneError};
use super::gpu::{MATERIAL_LAMBERT, MATERIAL_PHONG, Material};
use super::mesh::{DEFAULT_MATERIAL_NAME, Mesh, MeshTriangle};
use glam::Vec3;
use std::collections::{HashMap, HashSet};
use std::io::Cursor;
use std::path::Path;

pub fn load_obj(path: &Path) -> Result<Mesh, SceneError> {
    let text = unix_line_endings(read(path)?);
    let checked = check_obj(path, &text)?;
    load_checked(path, &checked)
}

/// Old Mac files end lines with a lone CR, which `str::lines` does not split on (the whole file
/// would be one line, and no face would be found); CRLF and CR both become LF.
fn unix_line_endings(text: String) -> String {
    if text.contains('\r') {
        text.replace("\r\n", "\n").replace('\r', "\n")
    } else {
        text
    }
}

fn read(path: &Path) -> Result<String, SceneError> {
    crate::text_file::read_utf8(path).map_err(|source| SceneError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// An OBJ file that passed [`check_obj`].
struct CheckedObj {
    /// What tobj reads: the original lines reduced to what the renderer uses.
    normalized: String,
    /// Material library text by the name `mtllib` gives (as tobj will ask for it).
    libraries: HashMap<String, String>,
}

/// The first word of a line and the rest, trimmed.
fn split_keyword(line: &str) -> Option<(&str, &str)> {
    let line = line.trim();
    if line.is_empty() {
        return None;
    }
    match line.split_once(char::is_whitespace) {
        Some((keyword, rest)) => Some((keyword, rest.trim())),
        None => Some((line, "")),
    }
}

fn syntax(path: &Path, line: usize, message: impl Into<String>) -> SceneError {
    SceneError::Syntax {
        at: Location::line(path, line),
        message: message.into(),
    }
}

/// Checks every line tobj would act on and builds the normalised text.
fn check_obj(path: &Path, text: &str) -> Result<CheckedObj, SceneError> {
    let dir = path.parent().unwrap_or(Path::new(""));
    let mut normalized = String::with_capacity(text.len());
    let mut libraries = HashMap::new();
    // Names defined by the libraries loaded so far: tobj resolves `usemtl` when it sees it.
    let mut defined: Vec<String> = Vec::new();
    let mut defined_set: HashSet<String> = HashSet::new();
    let mut vertex_count: usize = 0;

    for (index, line) in text.lines().enumerate() {
        let number = index + 1;
        let Some((keyword, rest)) = split_keyword(line) else {
            normalized.push('\n');
            continue;
        };
        match keyword {
            "v" => {
                check_vertex(path, number, rest)?;
                vertex_count += 1;
                // Drop vertex colours; keep x y z and an optional w, which tobj divides by.
                let words: Vec<&str> = rest.split_whitespace().collect();
                let kept = if words.len() == 4 { 4 } else { 3 };
                normalized.push_str("v ");
                normalized.push_str(&words[..kept].join(" "));
            }
            "f" => {
                let indices = check_face(path, number, rest, vertex_count)?;
                // Points and lines are not surfaces; tobj is told to ignore them anyway.
                if indices.len() >= 3 {
                    normalized.push_str("f ");
                    normalized.push_str(&indices.join(" "));
                }
            }
            "o" | "g" => {
                normalized.push_str(keyword);
                normalized.push(' ');
                normalized.push_str(rest);
            }
            "mtllib" => {
                if rest.is_empty() {
                    return Err(syntax(path, number, "mtllib needs a file name"));
                }
                // Like tobj, the rest of the line is one file name (it may contain spaces).
                let mtl_path = dir.join(rest);
                if !libraries.contains_key(rest) {
                    let mtl_text = crate::text_file::read_utf8(&mtl_path).map_err(|source| {
                        if source.kind() == std::io::ErrorKind::NotFound {
                            SceneError::MissingMaterialLibrary {
                                at: Location::line(path, number),
                                mtl: mtl_path.clone(),
                            }
                        } else {
                            SceneError::Io {
                                path: mtl_path.clone(),
                                source,
                            }
                        }
                    })?;
                    let mtl_text = unix_line_endings(mtl_text);
                    for name in check_mtl(&mtl_path, &mtl_text)? {
                        if defined_set.insert(name.clone()) {
                            defined.push(name);
                        }
                    }
                    libraries.insert(rest.to_string(), mtl_text);
                }
                normalized.push_str("mtllib ");
                normalized.push_str(rest);
            }
            "usemtl" => {
                if rest.is_empty() {
                    return Err(syntax(path, number, "usemtl needs a material name"));
                }
                if !defined_set.contains(rest) {
                    return Err(SceneError::UnknownMaterial {
                        at: Location::line(path, number),
                        name: rest.to_string(),
                        defined,
                    });
                }
                normalized.push_str("usemtl ");
                normalized.push_str(rest);
            }
            // Texture coordinates, normals, lines, smoothing groups, comments: unused.
            _ => {}
        }
        normalized.push('\n');
    }
    Ok(CheckedObj {
        normalized,
        libraries,
    })
}

/// `v x y z [w | r g b]`: numbers, w nonzero, and a finite position after dividing by w.
fn check_vertex(path: &Path, line: usize, rest: &str) -> Result<(), SceneError> {
    let words: Vec<&str> = rest.split_whitespace().collect();
    if !matches!(words.len(), 3 | 4 | 6) {
        return Err(syntax(
            path,
            line,
            format!(
                "a vertex needs x y z, optionally w or r g b; found {} numbers",
                words.len()
            ),
        ));
    }
    let mut numbers = Vec::with_capacity(words.len());
    for word in &words {
        let value: f32 = word
            .parse()
            .map_err(|_| syntax(path, line, format!("'{word}' is not a number")))?;
        numbers.push(value);
    }
    let mut position = [numbers[0], numbers[1], numbers[2]];
    if let [_, _, _, w] = numbers[..] {
        if w == 0.0 {
            return Err(syntax(path, line, "vertex weight w is 0"));
        }
        // As tobj does, in f32.
        for c in &mut position {
            *c /= w;
        }
    }
    if let Some(i) = position.iter().position(|c| !c.is_finite()) {
        let value = if numbers.len() == 4 {
            format!("{} after dividing by w = {}", position[i], numbers[3])
        } else {
            words[i].to_string()
        };
        return Err(SceneError::NonFiniteVertex {
            at: Location::line(path, line),
            value,
        });
    }
    Ok(())
}

/// `f v1[/vt/vn] v2 ...`: every position index in range (1-based, or negative = relative).
/// Returns the position indices as written.
fn check_face<'a>(
    path: &Path,
    line: usize,
    rest: &'a str,
    vertex_count: usize,
) -> Result<Vec<&'a str>, SceneError> {
    let mut indices = Vec::new();
    for word in rest.split_whitespace() {
        let parts: Vec<&str> = word.split('/').collect();
        if parts.len() > 3 {
            return Err(syntax(
                path,
                line,
                format!("'{word}' is not a face vertex (expected v, v/vt, v//vn or v/vt/vn)"),
            ));
        }
        let position = parts[0];
        let index: i64 = position.parse().map_err(|_| {
            syntax(
                path,
                line,
                format!("'{word}' does not start with a vertex index"),
            )
        })?;
        let count = vertex_count as i64;
        let valid = if index < 0 {
            count + index >= 0
        } else {
            index >= 1 && index <= count
        };
        if !valid {
            return Err(SceneError::FaceIndexOutOfRange {
                at: Location::line(path, line),
                index,
                vertex_count,
                valid: if vertex_count == 0 {
                    "none yet: faces may only use vertices defined above them".to_string()
                } else {
                    format!("1..={vertex_count} or -{vertex_count}..=-1")
                },
            });
        }
        indices.push(position);
    }
    if indices.is_empty() {
        return Err(syntax(path, line, "a face needs vertices"));
    }
    Ok(indices)
}

/// Checks the lines of an MTL file that tobj parses (it panics on short colours) and that the
/// renderer needs finite and non-negative. Returns the material names in order.
fn check_mtl(path: &Path, text: &str) -> Result<Vec<String>, SceneError> {
    let mut names = Vec::new();
    for (index, line) in text.lines().enumerate() {
        let number = index + 1;
        let Some((keyword, rest)) = split_keyword(line) else {
            continue;
        };
        let words: Vec<&str> = rest.split_whitespace().collect();
        let numbers = |count: usize| -> Result<Vec<f32>, SceneError> {
            let parsed: Option<Vec<f32>> = words
                .iter()
                .take(count)
                .map(|w| w.parse::<f32>().ok())
                .collect();
            match parsed {
                Some(values) if values.len() == count => Ok(values),
                _ => Err(syntax(
                    path,
                    number,
                    match count {
                        1 => format!("{keyword} needs a number, found '{rest}'"),
                        _ => format!("{keyword} needs {count} numbers, found '{rest}'"),
                    },
                )),
            }
        };
        let physical = |values: &[f32]| {
            if values.iter().all(|v| v.is_finite() && *v >= 0.0) {
                Ok(())
            } else {
                Err(syntax(
                    path,
                    number,
                    format!("{keyword} must be finite and non-negative, found '{rest}'"),
                ))
            }
        };
        match keyword {
            "newmtl" => {
                if rest.is_empty() {
                    return Err(syntax(path, number, "newmtl needs a material name"));
                }
                names.push(rest.to_string());
            }
            "Kd" | "Ks" | "Ke" => physical(&numbers(3)?)?,
            "Ka" => {
                numbers(3)?;
            }
            "Ns" => physical(&numbers(1)?)?,
            "Ni" | "d" => {
                numbers(1)?;
            }
            "illum" if words.first().and_then(|w| w.parse::<u8>().ok()).is_none() => {
                return Err(syntax(path, number, "illum needs a model number (0-255)"));
            }
            "map_Ka" | "map_Kd" | "map_Ks" | "map_Bump" | "map_bump" | "map_Ns" | "map_ns"
            | "map_NS" | "bump" | "map_d"
                if rest.is_empty() =>
            {
                return Err(syntax(path, number, format!("{keyword} needs a file name")));
            }
            _ => {}
        }
    }
    Ok(names)
}

/// Loads the checked text through tobj and converts its models.
fn load_checked(path: &Path, checked: &CheckedObj) -> Result<Mesh, SceneError> {
    let options = tobj::LoadOptions {
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
        ..tobj::LoadOptions::default()
    };
    let tobj_error = |error: tobj::LoadError| SceneError::Mesh {
        path: path.to_path_buf(),
        message: error.to_string(),
    };
    let (models, materials) = tobj::load_obj_buf(
        &mut Cursor::new(checked.normalized.as_bytes()),
        &options,
        |name| match name.to_str().and_then(|n| checked.libraries.get(n)) {
            Some(text) => tobj::load_mtl_buf(&mut Cursor::new(text.as_bytes())),
            None => Err(tobj::LoadError::OpenFileFailed),
        },
    )
    .map_err(tobj_error)?;
    // No library (or none with materials) comes back as an error: then there are no materials.
    let materials = materials.unwrap_or_default();

    let mut mesh = Mesh {
        warnings: Vec::new(),
        path: path.to_path_buf(),
        triangles: Vec::new(),
        materials: materials.iter().map(convert_material).collect(),
        material_names: materials.iter().map(|m| m.name.clone()).collect(),
    };
    let mut default_material = None;
    for model in &models {
        let material = match model.mesh.material_id {
            Some(id) if id < mesh.materials.len() => id as u32,
            _ => *default_material.get_or_insert_with(|| {
                mesh.materials.push(Material::DEFAULT);
                mesh.material_names.push(DEFAULT_MATERIAL_NAME.to_string());
                (mesh.materials.len() - 1) as u32
            }),
        };
        let positions = &model.mesh.positions;
        let vertex = |i: u32| -> Result<Vec3, SceneError> {
            let i = i as usize * 3;
            match positions.get(i..i + 3) {
                Some(p) => Ok(Vec3::new(p[0], p[1], p[2])),
                None => Err(SceneError::Mesh {
                    path: path.to_path_buf(),
                    message: "tobj returned a vertex index out of range".to_string(),
                }),
            }
        };
        for corners in model.mesh.indices.chunks_exact(3) {
            mesh.triangles.push(MeshTriangle {
                vertices: [
                    vertex(corners[0])?,
                    vertex(corners[1])?,
                    vertex(corners[2])?,
                ],
                material,
            });
        }
    }
    Ok(mesh)
}

/// MTL values to the renderer's material. Missing values: Kd 0.8 (as for faces without a
/// material), Ks 0, Ns 0, Ke 0.
fn convert_material(m: &tobj::Material) -> Material {
    // tobj 4 parses Ke itself; older versions left it among the unknown parameters.
    let ke = m.emissive.or_else(|| {
        let values: Vec<f32> = m
            .unknown_param
            .get("Ke")?
            .split_whitespace()
            .map(|w| w.parse().ok())
            .collect::<Option<_>>()?;
        values.get(..3).map(|v| [v[0], v[1], v[2]])
    });
    let ks = m.specular.unwrap_or([0.0; 3]);
    Material {
        kd: m.diffuse.unwrap_or(Material::DEFAULT.kd),
        ns: m.shininess.unwrap_or(0.0),
        ks,
        kind: if ks.iter().any(|&c| c > 0.0) {
            MATERIAL_PHONG
        } else {
            MATERIAL_LAMBERT
        },
        ke: ke.unwrap_or([0.0; 3]),
        ..Material::default()
    }
}
