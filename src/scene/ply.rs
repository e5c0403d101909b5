//! PLY meshes (ASCII and binary) through ply-rs-bw: vertex `x y z`, face `vertex_indices` (or
//! `vertex_index`) polygons fan-triangulated, one default material.
//!
//! An ASCII PLY has one element per line, so errors found after parsing still name their line;
//! a binary one names the element ("face 12") instead.

use super::error::{Location, SceneError};
use super::mesh::{DEFAULT_MATERIAL_NAME, Mesh, MeshTriangle, fan_triangulate};
use crate::material::Material;
use glam::Vec3;
use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{DefaultElement, Encoding, Header, Property};
use std::io::BufReader;
use std::path::Path;

pub fn load_ply(path: &Path) -> Result<Mesh, SceneError> {
    load(path, false)
}

/// [`load_ply`] keeping the vertices' normals (`nx ny nz`) and texture coordinates (`u v`,
/// `s t` or `texture_u texture_v`, as written) where every vertex has them: the Mitsuba XML
/// loader's `ply` shape, whose meshes shade with them as Mitsuba does.
pub fn load_ply_with_attributes(path: &Path) -> Result<Mesh, SceneError> {
    load(path, true)
}

fn load(path: &Path, attributes: bool) -> Result<Mesh, SceneError> {
    let file = std::fs::File::open(path).map_err(|source| SceneError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let parser = Parser::<DefaultElement>::new();
    let mut reader = Reader::new(BufReader::new(file));
    let header = parser
        .read_header(&mut reader)
        .map_err(|e| parse_error(path, e, true))?;
    let ascii = header.encoding == Encoding::Ascii;
    let places = ElementPlaces {
        path,
        header: &header,
        first_payload_line: reader.line(),
        ascii,
    };
    let payload = parser
        .read_payload(&mut reader, &header)
        .map_err(|e| parse_error(path, e, ascii))?;

    let empty = Vec::new();
    let vertices = payload.get("vertex").unwrap_or(&empty);
    let mut positions = Vec::with_capacity(vertices.len());
    for (i, vertex) in vertices.iter().enumerate() {
        let mut p = [0.0f32; 3];
        for (c, name) in p.iter_mut().zip(["x", "y", "z"]) {
            *c = vertex
                .get(name)
                .and_then(Property::to_f32_lossy)
                .ok_or_else(|| SceneError::Syntax {
                    at: places.locate("vertex", i),
                    message: format!("vertex has no numeric '{name}' property"),
                })?;
        }
        if let Some(bad) = p.iter().find(|c| !c.is_finite()) {
            return Err(SceneError::NonFiniteVertex {
                at: places.locate("vertex", i),
                value: bad.to_string(),
            });
        }
        positions.push(Vec3::from(p));
    }
    let read3 = |names: [&str; 3]| -> Option<Vec<Vec3>> {
        vertices
            .iter()
            .map(|v| {
                let c = |n: &str| v.get(n).and_then(Property::to_f32_lossy);
                Some(Vec3::new(c(names[0])?, c(names[1])?, c(names[2])?))
            })
            .collect()
    };
    let read2 = |names: [&str; 2]| -> Option<Vec<glam::Vec2>> {
        vertices
            .iter()
            .map(|v| {
                let c = |n: &str| v.get(n).and_then(Property::to_f32_lossy);
                Some(glam::Vec2::new(c(names[0])?, c(names[1])?))
            })
            .collect()
    };
    let (normals, uvs) = if attributes && !vertices.is_empty() {
        (
            read3(["nx", "ny", "nz"]),
            read2(["u", "v"])
                .or_else(|| read2(["s", "t"]))
                .or_else(|| read2(["texture_u", "texture_v"])),
        )
    } else {
        (None, None)
    };

    let faces = payload.get("face").unwrap_or(&empty);
    let mut triangles = Vec::with_capacity(faces.len());
    for (i, face) in faces.iter().enumerate() {
        let list = face
            .get("vertex_indices")
            .or_else(|| face.get("vertex_index"))
            .ok_or_else(|| SceneError::Syntax {
                at: places.locate("face", i),
                message: "face has no 'vertex_indices' (or 'vertex_index') list".to_string(),
            })?;
        let indices = list.to_u32_list().ok_or_else(|| SceneError::Syntax {
            at: places.locate("face", i),
            message: "face vertex indices must be non-negative integers".to_string(),
        })?;
        let mut corners = Vec::with_capacity(indices.len());
        let mut corner_indices = Vec::with_capacity(indices.len());
        for &index in &indices {
            let vertex =
                positions
                    .get(index as usize)
                    .ok_or_else(|| SceneError::FaceIndexOutOfRange {
                        at: places.locate("face", i),
                        index: i64::from(index),
                        vertex_count: positions.len(),
                        valid: match positions.len() {
                            0 => "none".to_string(),
                            n => format!("0..={}", n - 1),
                        },
                    })?;
            corners.push(*vertex);
            corner_indices.push(index as usize);
        }
        triangles.extend(fan_triangulate(&corner_indices).map(|ix| {
            MeshTriangle {
                vertices: ix.map(|i| positions[i]),
                material: 0,
                normals: normals
                    .as_ref()
                    .map(|n| ix.map(|i| n[i].normalize_or(Vec3::Z))),
                uvs: uvs.as_ref().map(|uv| ix.map(|i| uv[i])),
            }
        }));
        let _ = &corners;
    }

    Ok(Mesh {
        warnings: Vec::new(),
        path: path.to_path_buf(),
        triangles,
        materials: vec![Material::DEFAULT],
        material_names: vec![DEFAULT_MATERIAL_NAME.to_string()],
        textures: Vec::new(),
        back_materials: Default::default(),
        null_masks: Default::default(),
    })
}

/// ply-rs-bw counts binary elements as lines; only an ASCII (or header) line is worth naming.
fn parse_error(path: &Path, error: ply_rs_bw::parser::ParseError, has_lines: bool) -> SceneError {
    let message = error.to_string();
    // The library's message starts with "Line N: " when it knows the line; ours says it.
    let message = match error.line() {
        Some(line) => message
            .strip_prefix(&format!("Line {line}: "))
            .unwrap_or(&message)
            .to_string(),
        None => message,
    };
    let message = human_message(&message);
    SceneError::Syntax {
        at: Location {
            path: path.to_path_buf(),
            line: error.line().filter(|_| has_lines),
            item: None,
        },
        message,
    }
}

/// ply-rs-bw's messages nest its grammar's errors, with Rust `Debug` output, over several
/// lines ("Couldn't parse line.\n\tString: '...'\n\tError: ParseError { location: LineCol
/// {..}, expected: ExpectedSet {..} }"). Keeps what a user needs on one line: what failed,
/// the text, the column and, for header keywords, what was expected.
fn human_message(raw: &str) -> String {
    let mut out = raw
        .lines()
        .next()
        .unwrap_or("")
        .trim()
        .trim_end_matches('.')
        .to_string();
    if let Some(text) = raw
        .split("String: '")
        .nth(1)
        .and_then(|rest| rest.split('\'').next())
    {
        out += &format!(": '{}'", text.trim());
    }
    // Columns: "error at 1:5:" (a grammar error) or "column: 10" (its Debug form).
    let column = raw
        .split("error at ")
        .nth(1)
        .and_then(|rest| rest.split(':').nth(1))
        .or_else(|| {
            raw.split("column: ")
                .nth(1)
                .and_then(|r| r.split(',').next())
        })
        .and_then(|c| c.trim().parse::<usize>().ok());
    if let Some(column) = column {
        out += &format!(" at column {column}");
    }
    if let Some(set) = raw
        .split("expected: {")
        .nth(1)
        .and_then(|r| r.split('}').next())
    {
        let words: Vec<String> = set
            .split(", ")
            .map(|w| w.trim_matches(|c| c == '"' || c == '\\').to_string())
            .filter(|w| w.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') && !w.is_empty())
            .collect();
        if !words.is_empty() {
            out += &format!(" (expected one of: {})", words.join(", "));
        }
    } else if raw.contains("'0'..='9'") {
        out += " (expected a number)";
    }
    out
}

/// Where element `i` of an element kind sits in the file.
struct ElementPlaces<'a> {
    path: &'a Path,
    header: &'a Header,
    first_payload_line: usize,
    ascii: bool,
}

impl ElementPlaces<'_> {
    fn locate(&self, element: &str, i: usize) -> Location {
        if !self.ascii {
            return Location::item(self.path, format!("{element} {i}"));
        }
        // Elements follow one another in header order, one per line.
        let before: usize = self
            .header
            .elements
            .values()
            .take_while(|e| e.name != element)
            .map(|e| e.count)
            .sum();
        Location::line(self.path, self.first_payload_line + before + i)
    }
}
