//! Mitsuba's `serialized` mesh format: meshes one after another, each a little-endian header
//! (format id 0x041C, version 3 or 4) and a zlib stream (flags; version 4: a NUL-terminated
//! name; vertex and triangle counts as u64; positions; then normals, texture coordinates and
//! colours as the flags say; u32 or u64 indices), and at the end of the file each mesh's offset
//! (u64 in version 4, u32 in version 3) and the mesh count (u32).

use super::shapes::{Geometry, Triangle};
use flate2::read::ZlibDecoder;
use glam::{DVec2, DVec3};
use std::io::Read;
use std::path::Path;

const FORMAT_ID: u16 = 0x041C;
const HAS_NORMALS: u32 = 0x0001;
const HAS_TEXCOORDS: u32 = 0x0002;
const HAS_TANGENTS: u32 = 0x0004;
const HAS_COLORS: u32 = 0x0008;
const FACE_NORMALS: u32 = 0x0010;
const SINGLE_PRECISION: u32 = 0x1000;
const DOUBLE_PRECISION: u32 = 0x2000;

/// A sequential reader over decompressed bytes; every read says what ran out.
struct Bytes<'a> {
    data: &'a [u8],
    at: usize,
}

impl Bytes<'_> {
    fn take(&mut self, n: usize, what: &str) -> Result<&[u8], String> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.data.len());
        let end = end.ok_or_else(|| format!("the mesh data ends inside its {what}"))?;
        let s = &self.data[self.at..end];
        self.at = end;
        Ok(s)
    }
    fn u32(&mut self, what: &str) -> Result<u32, String> {
        Ok(u32::from_le_bytes(
            self.take(4, what)?.try_into().unwrap_or_default(),
        ))
    }
    fn u64(&mut self, what: &str) -> Result<u64, String> {
        Ok(u64::from_le_bytes(
            self.take(8, what)?.try_into().unwrap_or_default(),
        ))
    }
    fn real(&mut self, double: bool, what: &str) -> Result<f64, String> {
        Ok(if double {
            f64::from_le_bytes(self.take(8, what)?.try_into().unwrap_or_default())
        } else {
            f64::from(f32::from_le_bytes(
                self.take(4, what)?.try_into().unwrap_or_default(),
            ))
        })
    }
}

/// Reads mesh `shape_index` of a serialized file. Returns the geometry and whether the file
/// asks for face normals (its flag 0x0010). The message is for the caller to place.
pub fn load_serialized(path: &Path, shape_index: usize) -> Result<(Geometry, bool), String> {
    let file = std::fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    if file.len() < 8 {
        return Err(format!(
            "{}: too short for a serialized file",
            path.display()
        ));
    }
    let count = u32::from_le_bytes(file[file.len() - 4..].try_into().unwrap_or_default()) as usize;
    let header = |at: usize| -> Option<(u16, u16)> {
        let h = file.get(at..at + 4)?;
        Some((
            u16::from_le_bytes([h[0], h[1]]),
            u16::from_le_bytes([h[2], h[3]]),
        ))
    };
    let (id, version) = header(0).ok_or("too short")?;
    if id != FORMAT_ID || !(version == 3 || version == 4) {
        return Err(format!(
            "{}: not a Mitsuba serialized mesh (header {id:#06x} version {version}; expected 0x041c, version 3 or 4)",
            path.display()
        ));
    }
    if shape_index >= count {
        return Err(format!(
            "{}: shape_index {shape_index} is out of range: the file has {count} mesh{}",
            path.display(),
            if count == 1 { "" } else { "es" }
        ));
    }
    let width = if version == 4 { 8 } else { 4 };
    let table = file
        .len()
        .checked_sub(4 + width * count)
        .ok_or("a truncated offset table")?;
    let entry = table + width * shape_index;
    let offset = if version == 4 {
        u64::from_le_bytes(file[entry..entry + 8].try_into().unwrap_or_default()) as usize
    } else {
        u32::from_le_bytes(file[entry..entry + 4].try_into().unwrap_or_default()) as usize
    };
    let (id, mesh_version) = header(offset).ok_or("a mesh offset beyond the file")?;
    if id != FORMAT_ID {
        return Err(format!(
            "{}: mesh {shape_index} at byte {offset} has no serialized header",
            path.display()
        ));
    }
    let mut data = Vec::new();
    ZlibDecoder::new(&file[offset + 4..table])
        .read_to_end(&mut data)
        .or_else(|e| {
            // The stream ends before the next mesh; trailing bytes are the next one's.
            if data.is_empty() {
                Err(e)
            } else {
                Ok(data.len())
            }
        })
        .map_err(|e| format!("{}: mesh {shape_index}: zlib: {e}", path.display()))?;
    let mut b = Bytes { data: &data, at: 0 };
    let flags = b.u32("flags")?;
    if mesh_version == 4 {
        while b.take(1, "name")?[0] != 0 {}
    }
    let vertex_count = b.u64("vertex count")? as usize;
    let triangle_count = b.u64("triangle count")? as usize;
    let double = flags & DOUBLE_PRECISION != 0;
    if double == (flags & SINGLE_PRECISION != 0) {
        return Err(format!(
            "{}: mesh {shape_index}: flags {flags:#x} give neither or both precisions",
            path.display()
        ));
    }
    let vec3s = |b: &mut Bytes, what: &str| -> Result<Vec<DVec3>, String> {
        (0..vertex_count)
            .map(|_| {
                Ok(DVec3::new(
                    b.real(double, what)?,
                    b.real(double, what)?,
                    b.real(double, what)?,
                ))
            })
            .collect()
    };
    let positions = vec3s(&mut b, "positions")?;
    let normals = if flags & HAS_NORMALS != 0 {
        Some(vec3s(&mut b, "normals")?)
    } else {
        None
    };
    let uvs: Option<Vec<DVec2>> = if flags & HAS_TEXCOORDS != 0 {
        Some(
            (0..vertex_count)
                .map(|_| Ok(DVec2::new(b.real(double, "uvs")?, b.real(double, "uvs")?)))
                .collect::<Result<_, String>>()?,
        )
    } else {
        None
    };
    if flags & HAS_TANGENTS != 0 {
        // Unused: passgraph derives tangents from the texture coordinates.
        b.take(vertex_count * 4 * if double { 8 } else { 4 }, "tangents")?;
    }
    if flags & HAS_COLORS != 0 {
        // Vertex colours are not used by the subset's BSDFs (Mitsuba reads them through the
        // `mesh_attribute` texture, which is not supported).
        b.take(vertex_count * 3 * if double { 8 } else { 4 }, "colours")?;
    }
    let wide = vertex_count > u32::MAX as usize;
    let mut triangles = Vec::with_capacity(triangle_count);
    for _ in 0..triangle_count {
        let mut ix = [0usize; 3];
        for i in &mut ix {
            *i = if wide {
                b.u64("indices")? as usize
            } else {
                b.u32("indices")? as usize
            };
            if *i >= vertex_count {
                return Err(format!(
                    "{}: mesh {shape_index}: index {i} out of range ({vertex_count} vertices)",
                    path.display()
                ));
            }
        }
        triangles.push(Triangle {
            p: ix.map(|i| positions[i]),
            n: normals.as_ref().map(|n| ix.map(|i| n[i])),
            uv: uvs.as_ref().map(|uv| ix.map(|i| uv[i])),
        });
    }
    Ok((Geometry { triangles }, flags & FACE_NORMALS != 0))
}
