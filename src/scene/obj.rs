//! OBJ + MTL meshes through tobj.
//!
//! tobj reports errors without lines (and panics on a colour with fewer than three numbers), so
//! the text is checked line by line first: every problem found there names its file and line
//! (in pieces of about a megabyte on all cores, the first error in the file reported).
//! tobj then reads a normalised copy holding only what the renderer uses (positions, faces by
//! position index, objects, material libraries and `usemtl`), one line per original line, and
//! fan-triangulates the polygons. Texture coordinates and normals (`vt`, `vn`) are checked and
//! kept here, per face, and given to tobj's triangles afterwards (tobj pads a face without them
//! with another face's indices). The MTL keys tobj does not read (PBR `Pm`/`Pr`, `Tf`, texture
//! maps) are read here with their lines too; which keys make which material: [`material_from`].

use super::error::{Location, SceneError};
use super::mesh::{DEFAULT_MATERIAL_NAME, Mesh, MeshTriangle};
use super::texture::{Encoding, Texture};
use crate::bsdf::microfacet::Distribution;
use crate::material::conductor::presets::{CONDUCTOR_PRESETS, conductor_preset};
use crate::material::{
    FRESNEL_CONDUCTOR, MATERIAL_CONDUCTOR, MATERIAL_DIELECTRIC, MATERIAL_LAMBERT, MATERIAL_PHONG,
    MATERIAL_PLASTIC, MATERIAL_THIN_DIELECTRIC, Material, NO_TEXTURE, SURFACE_MAP_BUMP,
};
use glam::{Vec2, Vec3};
use rayon::prelude::*;
use std::collections::{HashMap, HashSet};
use std::io::Cursor;
use std::path::Path;

pub fn load_obj(path: &Path) -> Result<Mesh, SceneError> {
    let text = unix_line_endings(read(path)?);
    let checked = check_obj(path, &text, true)?;
    load_checked(path, checked)
}

/// [`load_obj`] without materials: `mtllib` and `usemtl` are skipped (every face gets the
/// default material), as Mitsuba's `obj` shape, whose BSDF comes from the scene, reads them.
pub fn load_obj_geometry(path: &Path) -> Result<Mesh, SceneError> {
    let text = unix_line_endings(read(path)?);
    let checked = check_obj(path, &text, false)?;
    load_checked(path, checked)
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
    /// What tobj reads, in pieces: the original lines reduced to what the renderer uses, and
    /// the faces on them.
    pieces: Vec<NormalizedPiece>,
    /// Material library text by the name `mtllib` gives (as tobj will ask for it).
    libraries: HashMap<String, String>,
    /// What the libraries say beyond tobj's keys, by material name (a later definition
    /// replaces an earlier one, as in tobj).
    extras: HashMap<String, MtlExtras>,
    textures: Textures,
    /// `vt` and `vn` in file order (what face corners index, 0-based).
    texcoords: Vec<Vec2>,
    normals: Vec<Vec3>,
    warnings: Vec<String>,
}

/// Consecutive lines of a checked OBJ file: the text tobj reads for them, one line per
/// original line, and every face of three or more corners on them, in file order (what tobj's
/// triangles come from). Kept apart rather than joined: joining a 1M-triangle file's pieces
/// cost a third of its check.
#[derive(Default)]
struct NormalizedPiece {
    text: String,
    faces: Vec<FaceCorners>,
    /// The faces' `vt` and `vn` indices, one face's after the other (a face's are
    /// `corners[face.attributes]`; one list for all faces rather than one per face: a million
    /// faces were a million allocations).
    corners: Vec<Corner>,
}

/// A face's line, its corner count, and where its corners' attributes are in
/// [`NormalizedPiece::corners`]: none when no corner has a `vt` or `vn` (most meshes), so
/// that such faces store nothing.
struct FaceCorners {
    line: usize,
    count: usize,
    attributes: Option<std::ops::Range<usize>>,
}

/// The pieces' texts read one after the other, as tobj reads a file.
struct PiecesReader<'a> {
    pieces: &'a [NormalizedPiece],
    piece: usize,
    at: usize,
}

impl std::io::Read for PiecesReader<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        use std::io::BufRead;
        let available = self.fill_buf()?;
        let n = available.len().min(buf.len());
        buf[..n].copy_from_slice(&available[..n]);
        self.consume(n);
        Ok(n)
    }
}

impl std::io::BufRead for PiecesReader<'_> {
    fn fill_buf(&mut self) -> std::io::Result<&[u8]> {
        while let Some(piece) = self.pieces.get(self.piece) {
            if self.at < piece.text.len() {
                return Ok(&piece.text.as_bytes()[self.at..]);
            }
            (self.piece, self.at) = (self.piece + 1, 0);
        }
        Ok(&[])
    }

    fn consume(&mut self, amount: usize) {
        self.at += amount;
    }
}

/// A face corner's `vt` and `vn` indices (0-based) where given.
type Corner = (Option<usize>, Option<usize>);

/// The first `N` pieces of a line's `parts` (words, or a face vertex's `/`-separated indices;
/// missing ones empty) and how many there are in all (which may be more than `N`): the checks
/// need a few pieces each, and collecting them into a vector allocated once per line.
fn first<'a, const N: usize>(parts: impl Iterator<Item = &'a str>) -> ([&'a str; N], usize) {
    let mut first = [""; N];
    let mut count = 0;
    for part in parts {
        if let Some(slot) = first.get_mut(count) {
            *slot = part;
        }
        count += 1;
    }
    (first, count)
}

/// The images the materials use, each decoded once per encoding.
#[derive(Default)]
struct Textures {
    list: Vec<Texture>,
    index: HashMap<(std::path::PathBuf, Encoding), u32>,
}

/// MTL values tobj leaves in `unknown_param` or that need checking with their lines.
#[derive(Clone, Debug, Default)]
struct MtlExtras {
    pm: Option<f32>,
    pr: Option<f32>,
    tf: Option<[f32; 3]>,
    ni: Option<f32>,
    d: Option<f32>,
    illum: Option<u8>,
    map_kd: Option<u32>,
    map_ks: Option<u32>,
    map_pr: Option<u32>,
    map_d: Option<u32>,
    surface_map: Option<SurfaceMap>,
    /// `distribution ggx|beckmann`: the rough lobes' microfacets (Mitsuba's `distribution`).
    distribution: Option<Distribution>,
    /// A conductor's complex index: `eta r g b` with `k r g b`, or `conductor NAME` (one of
    /// Mitsuba's `material` presets).
    conductor_ior: Option<(Vec3, Vec3)>,
    eta: Option<[f32; 3]>,
    k: Option<[f32; 3]>,
    /// `thin 1`: glass is a thin sheet (Mitsuba's `thindielectric`).
    thin: bool,
}

/// A material's normal map (`norm`) or bump map (`map_Bump`, `bump`) and where it was given.
#[derive(Clone, Debug)]
struct SurfaceMap {
    /// `Material::surface_map`: the texture index, `SURFACE_MAP_BUMP` set for a bump map.
    texture: u32,
    bump_scale: f32,
    keyword: String,
    at: Location,
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

/// The OBJ text is checked in pieces of whole lines, about this many bytes each, in parallel:
/// on one thread the check took 0.6 s of a 1M-triangle file's 2.4 s start-up.
const PIECE_BYTES: usize = 1 << 20;

/// The text cut after the first line end at or past every `size` bytes (bytes, not chars: a
/// cut follows a `\n`, so it is a char boundary whatever the text): pieces of whole lines.
fn pieces(text: &str, size: usize) -> Vec<&str> {
    let mut cuts = vec![0];
    let mut at = 0;
    while text.len() - at > size {
        match text.as_bytes()[at + size..]
            .iter()
            .position(|&b| b == b'\n')
        {
            Some(end) => at += size + end + 1,
            None => break,
        }
        cuts.push(at);
    }
    cuts.push(text.len());
    cuts.windows(2).map(|w| &text[w[0]..w[1]]).collect()
}

/// How many lines there are, and how many vertices, texture coordinates and normals they
/// define: what the faces after them may index.
#[derive(Clone, Copy, Default)]
struct Defined {
    lines: usize,
    vertices: usize,
    texcoords: usize,
    normals: usize,
}

impl Defined {
    fn of(text: &str) -> Defined {
        let mut defined = Defined::default();
        for line in text.lines() {
            defined.lines += 1;
            match split_keyword(line) {
                Some(("v", _)) => defined.vertices += 1,
                Some(("vt", _)) => defined.texcoords += 1,
                Some(("vn", _)) => defined.normals += 1,
                _ => {}
            }
        }
        defined
    }

    fn add(self, other: Defined) -> Defined {
        Defined {
            lines: self.lines + other.lines,
            vertices: self.vertices + other.vertices,
            texcoords: self.texcoords + other.texcoords,
            normals: self.normals + other.normals,
        }
    }
}

/// One piece checked: its text and faces, its texture coordinates and normals, its `mtllib`
/// and `usemtl` lines, and its first error.
#[derive(Default)]
struct CheckedPiece<'a> {
    normalized: NormalizedPiece,
    texcoords: Vec<Vec2>,
    normals: Vec<Vec3>,
    /// (line, keyword, rest), checked after the pieces in file order: a library is read once,
    /// and `usemtl` may name only what a library before it defines.
    materials: Vec<(usize, &'a str, &'a str)>,
    /// The piece's first error and its line; its lines after it are not checked.
    error: Option<(usize, SceneError)>,
}

/// Checks a piece's lines, `before` being what the lines before it define (counted, not
/// checked: a line before this piece that fails is an earlier error, reported instead).
fn check_piece<'a>(
    path: &Path,
    piece: &'a str,
    before: Defined,
    materials: bool,
) -> CheckedPiece<'a> {
    let mut checked = CheckedPiece::default();
    checked.normalized.text.reserve(piece.len());
    let mut vertices = before.vertices;
    for (index, line) in piece.lines().enumerate() {
        let number = before.lines + index + 1;
        if let Err(error) = check_line(
            path,
            number,
            line,
            materials,
            &mut vertices,
            before,
            &mut checked,
        ) {
            checked.error = Some((number, error));
            break;
        }
        checked.normalized.text.push('\n');
    }
    checked
}

/// One line of [`check_piece`].
fn check_line<'a>(
    path: &Path,
    number: usize,
    line: &'a str,
    materials: bool,
    vertices: &mut usize,
    before: Defined,
    checked: &mut CheckedPiece<'a>,
) -> Result<(), SceneError> {
    let Some((keyword, rest)) = split_keyword(line) else {
        return Ok(());
    };
    let normalized = &mut checked.normalized.text;
    match keyword {
        "v" => {
            let (words, count) = check_vertex(path, number, rest)?;
            *vertices += 1;
            // Drop vertex colours; keep x y z and an optional w, which tobj divides by.
            let kept = if count == 4 { 4 } else { 3 };
            normalized.push('v');
            for word in &words[..kept] {
                normalized.push(' ');
                normalized.push_str(word);
            }
        }
        "vt" => {
            // v defaults to 0; w is unused.
            let [u, v, _] = check_numbers(path, number, keyword, rest, 1..=3)?;
            checked.texcoords.push(Vec2::new(u, v));
        }
        "vn" => {
            checked.normals.push(Vec3::from(check_numbers(
                path,
                number,
                keyword,
                rest,
                3..=3,
            )?));
        }
        "f" => {
            let counts = [
                *vertices,
                before.texcoords + checked.texcoords.len(),
                before.normals + checked.normals.len(),
            ];
            let corners = &mut checked.normalized.corners;
            let (start, written) = (corners.len(), normalized.len());
            normalized.push('f');
            check_face(path, number, rest, counts, normalized, corners)?;
            let count = corners.len() - start;
            // Points and lines are not surfaces; tobj is told to ignore them anyway.
            if count >= 3 {
                let plain = corners[start..].iter().all(|&c| c == (None, None));
                if plain {
                    corners.truncate(start);
                }
                checked.normalized.faces.push(FaceCorners {
                    line: number,
                    count,
                    attributes: (!plain).then_some(start..start + count),
                });
            } else {
                corners.truncate(start);
                normalized.truncate(written);
            }
        }
        "o" | "g" => {
            normalized.push_str(keyword);
            normalized.push(' ');
            normalized.push_str(rest);
        }
        "mtllib" | "usemtl" if !materials => {}
        "mtllib" | "usemtl" => {
            checked.materials.push((number, keyword, rest));
            normalized.push_str(keyword);
            normalized.push(' ');
            normalized.push_str(rest);
        }
        // Lines, smoothing groups, comments: unused.
        _ => {}
    }
    Ok(())
}

/// Checks every line tobj would act on and builds the normalised text: the pieces in
/// parallel, then the material lines in file order, and the first error in the file reported.
fn check_obj(path: &Path, text: &str, materials: bool) -> Result<CheckedObj, SceneError> {
    check_obj_in_pieces(path, text, materials, PIECE_BYTES)
}

/// [`check_obj`] with pieces of about `piece_bytes`.
fn check_obj_in_pieces(
    path: &Path,
    text: &str,
    materials: bool,
    piece_bytes: usize,
) -> Result<CheckedObj, SceneError> {
    let pieces = pieces(text, piece_bytes);
    let defined: Vec<Defined> = pieces.par_iter().map(|p| Defined::of(p)).collect();
    let before: Vec<Defined> = defined
        .iter()
        .scan(Defined::default(), |sum, &d| {
            let before = *sum;
            *sum = sum.add(d);
            Some(before)
        })
        .collect();
    let mut checked: Vec<CheckedPiece> = pieces
        .par_iter()
        .zip(before)
        .map(|(&piece, before)| check_piece(path, piece, before, materials))
        .collect();
    let first_error = checked.iter().find_map(|c| c.error.as_ref().map(|e| e.0));

    let dir = path.parent().unwrap_or(Path::new(""));
    let mut libraries = HashMap::new();
    // Names defined by the libraries loaded so far: tobj resolves `usemtl` when it sees it.
    let mut defined: Vec<String> = Vec::new();
    let mut defined_set: HashSet<String> = HashSet::new();
    let mut extras = HashMap::new();
    let mut textures = Textures::default();
    let mut warnings = Vec::new();
    for &(number, keyword, rest) in checked.iter().flat_map(|c| &c.materials) {
        if first_error.is_some_and(|line| number > line) {
            break;
        }
        if keyword == "mtllib" {
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
                let checked = check_mtl(&mtl_path, &mtl_text, &mut textures, &mut warnings)?;
                for (name, extra) in checked {
                    if defined_set.insert(name.clone()) {
                        defined.push(name.clone());
                    }
                    extras.insert(name, extra);
                }
                libraries.insert(rest.to_string(), mtl_text);
            }
        } else {
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
        }
    }
    if let Some((_, error)) = checked.iter_mut().find_map(|c| c.error.take()) {
        return Err(error);
    }

    let mut texcoords = Vec::new();
    let mut normals = Vec::new();
    let pieces = checked
        .into_iter()
        .map(|piece| {
            texcoords.extend(piece.texcoords);
            normals.extend(piece.normals);
            piece.normalized
        })
        .collect();
    Ok(CheckedObj {
        pieces,
        libraries,
        extras,
        textures,
        texcoords,
        normals,
        warnings,
    })
}

/// A line's numbers after its keyword: a count in `counts` (at most 3), each finite; those not
/// given are 0.
fn check_numbers(
    path: &Path,
    line: usize,
    keyword: &str,
    rest: &str,
    counts: std::ops::RangeInclusive<usize>,
) -> Result<[f32; 3], SceneError> {
    let (words, count) = first::<3>(rest.split_whitespace());
    if !counts.contains(&count) {
        let expected = if counts.start() == counts.end() {
            format!("{}", counts.start())
        } else {
            format!("{} to {}", counts.start(), counts.end())
        };
        return Err(syntax(
            path,
            line,
            format!("{keyword} needs {expected} numbers; found {count}"),
        ));
    }
    let mut numbers = [0.0; 3];
    for (number, word) in numbers.iter_mut().zip(&words[..count]) {
        *number = match word.parse::<f32>() {
            Ok(v) if v.is_finite() => v,
            _ => {
                return Err(syntax(
                    path,
                    line,
                    format!("{keyword}: '{word}' is not a finite number"),
                ));
            }
        };
    }
    Ok(numbers)
}

/// `v x y z [w | r g b]`: numbers, w nonzero, and a finite position after dividing by w.
/// Returns the words and their count.
fn check_vertex<'a>(
    path: &Path,
    line: usize,
    rest: &'a str,
) -> Result<([&'a str; 6], usize), SceneError> {
    let (words, count) = first::<6>(rest.split_whitespace());
    if !matches!(count, 3 | 4 | 6) {
        return Err(syntax(
            path,
            line,
            format!("a vertex needs x y z, optionally w or r g b; found {count} numbers"),
        ));
    }
    let mut numbers = [0.0f32; 6];
    for (number, word) in numbers.iter_mut().zip(&words[..count]) {
        *number = word
            .parse()
            .map_err(|_| syntax(path, line, format!("'{word}' is not a number")))?;
    }
    let numbers = &numbers[..count];
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
    Ok((words, count))
}

/// `f v1[/vt/vn] v2 ...`: every index in range (1-based, or negative = relative) of what is
/// defined above (`counts`: vertices, texture coordinates, normals). Appends the position
/// indices as written (each after a space) to `normalized`, and each corner's `vt` and `vn`,
/// 0-based, to `corners`.
fn check_face(
    path: &Path,
    line: usize,
    rest: &str,
    counts: [usize; 3],
    normalized: &mut String,
    corners: &mut Vec<Corner>,
) -> Result<(), SceneError> {
    let mut vertices = 0;
    for word in rest.split_whitespace() {
        let (parts, count) = first::<3>(word.split('/'));
        if count > 3 {
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
        resolve_index(index, counts[0]).ok_or_else(|| SceneError::FaceIndexOutOfRange {
            at: Location::line(path, line),
            index,
            vertex_count: counts[0],
            valid: valid_range(counts[0], "vertices"),
        })?;
        normalized.push(' ');
        normalized.push_str(position);
        vertices += 1;
    }
    if vertices == 0 {
        return Err(syntax(path, line, "a face needs vertices"));
    }
    // Texture coordinate and normal indices after every position's: a face's positions are the
    // more fundamental error.
    for word in rest.split_whitespace() {
        let (parts, _) = first::<3>(word.split('/'));
        let optional = |slot: usize,
                        what: &str,
                        plural: &str|
         -> Result<Option<usize>, SceneError> {
            match parts[slot] {
                "" => Ok(None),
                text => {
                    let index: i64 = text.parse().map_err(|_| {
                        syntax(
                            path,
                            line,
                            format!("'{word}': '{text}' is not a {what} index"),
                        )
                    })?;
                    resolve_index(index, counts[slot]).map(Some).ok_or_else(|| {
                        syntax(
                            path,
                            line,
                            format!(
                                "face refers to {what} {index}, but {} {plural} are defined (valid: {})",
                                counts[slot],
                                valid_range(counts[slot], plural)
                            ),
                        )
                    })
                }
            }
        };
        let vt = optional(1, "texture coordinate", "texture coordinates")?;
        let vn = optional(2, "normal", "normals")?;
        corners.push((vt, vn));
    }
    Ok(())
}

/// An OBJ index (1-based, or negative = counted back from the last) as 0-based, if in range.
fn resolve_index(index: i64, count: usize) -> Option<usize> {
    let count = count as i64;
    let resolved = if index < 0 { count + index } else { index - 1 };
    (0..count).contains(&resolved).then_some(resolved as usize)
}

fn valid_range(count: usize, what: &str) -> String {
    if count == 0 {
        format!("none yet: faces may only use {what} defined above them")
    } else {
        format!("1..={count} or -{count}..=-1")
    }
}

/// Checks the lines of an MTL file that tobj parses (it panics on short colours) and that the
/// renderer needs in range, reads what tobj leaves unparsed, and loads the texture maps.
/// Returns the materials' names in order with those values.
fn check_mtl(
    path: &Path,
    text: &str,
    textures: &mut Textures,
    warnings: &mut Vec<String>,
) -> Result<Vec<(String, MtlExtras)>, SceneError> {
    let dir = path.parent().unwrap_or(Path::new(""));
    let mut materials: Vec<(String, MtlExtras)> = Vec::new();
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
        let in_unit_range = |value: f32| {
            if (0.0..=1.0).contains(&value) {
                Ok(value)
            } else {
                Err(syntax(
                    path,
                    number,
                    format!("{keyword} must be in [0, 1], found '{rest}'"),
                ))
            }
        };
        // Keys before the first `newmtl` belong to no material; tobj ignores them too.
        let current = materials.last_mut().map(|(_, extras)| extras);
        let set = |apply: &mut dyn FnMut(&mut MtlExtras)| {
            if let Some(extras) = current {
                apply(extras);
            }
        };
        match keyword {
            "newmtl" => {
                if rest.is_empty() {
                    return Err(syntax(path, number, "newmtl needs a material name"));
                }
                materials.push((rest.to_string(), MtlExtras::default()));
            }
            "Kd" | "Ks" | "Ke" => physical(&numbers(3)?)?,
            "Ka" => {
                numbers(3)?;
            }
            "Ns" => physical(&numbers(1)?)?,
            "Ni" => {
                let ni = numbers(1)?[0];
                if !(ni.is_finite() && ni > 0.0) {
                    return Err(syntax(
                        path,
                        number,
                        format!(
                            "Ni (index of refraction) must be positive and finite, found '{rest}'"
                        ),
                    ));
                }
                set(&mut |e| e.ni = Some(ni));
            }
            "d" => {
                let d = in_unit_range(numbers(1)?[0])?;
                set(&mut |e| e.d = Some(d));
            }
            "Pr" => {
                let pr = in_unit_range(numbers(1)?[0])?;
                set(&mut |e| e.pr = Some(pr));
            }
            "Pm" => {
                let pm = numbers(1)?[0];
                if !pm.is_finite() {
                    return Err(syntax(
                        path,
                        number,
                        format!("Pm must be finite, found '{rest}'"),
                    ));
                }
                if pm != 0.0 && pm != 1.0 {
                    warnings.push(format!(
                        "{}:{number}: Pm {pm} is neither 0 nor 1: rendered as {} (threshold 0.5)",
                        path.display(),
                        if pm >= 0.5 {
                            "a conductor (Pm 1)"
                        } else {
                            "plastic (Pm 0)"
                        }
                    ));
                }
                set(&mut |e| e.pm = Some(pm));
            }
            "Tf" => {
                // `Tf r g b`, or `Tf v` for a grey (the spectral and xyz forms are not read).
                let tf = match words.len() {
                    1 => [numbers(1)?[0]; 3],
                    _ => {
                        let v = numbers(3)?;
                        [v[0], v[1], v[2]]
                    }
                };
                physical(&tf)?;
                set(&mut |e| e.tf = Some(tf));
            }
            "illum" => {
                let Some(model) = words.first().and_then(|w| w.parse::<u8>().ok()) else {
                    return Err(syntax(path, number, "illum needs a model number (0-255)"));
                };
                set(&mut |e| e.illum = Some(model));
            }
            "map_Kd" | "map_Ks" | "map_Pr" | "map_d" => {
                let encoding = match keyword {
                    "map_Kd" | "map_Ks" => Encoding::Srgb,
                    _ => Encoding::Raw,
                };
                let texture = load_map(path, dir, number, keyword, rest, encoding, textures)?;
                set(&mut |e| match keyword {
                    "map_Kd" => e.map_kd = Some(texture),
                    "map_Ks" => e.map_ks = Some(texture),
                    "map_Pr" => e.map_pr = Some(texture),
                    _ => e.map_d = Some(texture),
                });
            }
            "norm" | "map_Bump" | "map_bump" | "bump" => {
                let map = surface_map(path, dir, number, keyword, rest, textures)?;
                let mut first = None;
                set(&mut |e| match &e.surface_map {
                    Some(earlier) => first = Some((earlier.keyword.clone(), earlier.at.line)),
                    None => e.surface_map = Some(map.clone()),
                });
                if let Some((earlier, line)) = first {
                    return Err(syntax(
                        path,
                        number,
                        format!(
                            "{keyword}: this material already has a {earlier} (line {}); give it a normal map or a bump map, not both",
                            line.unwrap_or(0)
                        ),
                    ));
                }
            }
            "distribution" => {
                let Some(distribution) = Distribution::from_mitsuba_name(rest) else {
                    return Err(syntax(
                        path,
                        number,
                        format!("distribution must be ggx or beckmann, found '{rest}'"),
                    ));
                };
                set(&mut |e| e.distribution = Some(distribution));
            }
            "eta" | "k" => {
                let v = numbers(3)?;
                physical(&v)?;
                let v = [v[0], v[1], v[2]];
                set(&mut |e| {
                    if keyword == "eta" {
                        e.eta = Some(v);
                    } else {
                        e.k = Some(v);
                    }
                });
            }
            "thin" => {
                let thin = match rest {
                    "0" => false,
                    "1" => true,
                    _ => {
                        return Err(syntax(
                            path,
                            number,
                            format!("thin must be 0 or 1 (a thin sheet of glass), found '{rest}'"),
                        ));
                    }
                };
                set(&mut |e| e.thin = thin);
            }
            "conductor" => {
                let Some((eta, k)) = conductor_preset(rest) else {
                    let names: Vec<&str> = CONDUCTOR_PRESETS.iter().map(|p| p.0).collect();
                    return Err(syntax(
                        path,
                        number,
                        format!(
                            "conductor needs one of Mitsuba's presets ({}), found '{rest}'",
                            names.join(", ")
                        ),
                    ));
                };
                set(&mut |e| e.conductor_ior = Some((eta, k)));
            }
            "map_Ka" | "map_Ns" | "map_ns" | "map_NS" | "map_Ke" | "map_Pm" | "map_Ps" | "disp"
            | "decal" | "refl" => {
                if rest.is_empty() {
                    return Err(syntax(path, number, format!("{keyword} needs a file name")));
                }
                warnings.push(format!(
                    "{}:{number}: {keyword} is not supported; ignored",
                    path.display()
                ));
            }
            _ => {}
        }
    }
    Ok(materials)
}

/// A `norm FILE` (tangent-space normal map) or `map_Bump [-bm s] FILE` / `bump [-bm s] FILE`
/// (height field, heights s x the texel's luminance: Mitsuba's `bumpmap` `scale` s) line. Both
/// images are read raw (a normal map's texel is 2 rgb - 1, not a colour).
fn surface_map(
    path: &Path,
    dir: &Path,
    line: usize,
    keyword: &str,
    rest: &str,
    textures: &mut Textures,
) -> Result<SurfaceMap, SceneError> {
    let bump = keyword != "norm";
    let (bump_scale, file) = match rest.strip_prefix("-bm") {
        Some(after) if bump && (after.is_empty() || after.starts_with(char::is_whitespace)) => {
            let after = after.trim_start();
            let (value, file) = after.split_once(char::is_whitespace).unwrap_or((after, ""));
            match value.parse::<f32>() {
                Ok(v) if v.is_finite() => (v, file.trim()),
                _ => {
                    return Err(syntax(
                        path,
                        line,
                        format!(
                            "{keyword}: -bm needs a finite number (the bump scale) before the file name, found '{value}'"
                        ),
                    ));
                }
            }
        }
        _ => (1.0, rest),
    };
    let texture = load_map(path, dir, line, keyword, file, Encoding::Raw, textures)?;
    if bump {
        let t = &textures.list[texture as usize];
        if t.width * t.height == 1 {
            return Err(syntax(
                path,
                line,
                format!(
                    "{keyword}: '{file}' is a single texel: a bump map's heights need at least two texels to have a slope"
                ),
            ));
        }
    }
    Ok(SurfaceMap {
        texture: if bump {
            texture | SURFACE_MAP_BUMP
        } else {
            texture
        },
        bump_scale,
        keyword: keyword.to_string(),
        at: Location::line(path, line),
    })
}

/// A `map_*` line's image, loaded once per file and encoding; its index in `textures`.
fn load_map(
    path: &Path,
    dir: &Path,
    line: usize,
    keyword: &str,
    rest: &str,
    encoding: Encoding,
    textures: &mut Textures,
) -> Result<u32, SceneError> {
    if rest.is_empty() {
        return Err(syntax(path, line, format!("{keyword} needs a file name")));
    }
    // Options (-s, -o, -bm, -clamp, ...) would change the lookup; reading them as part of the
    // file name, or skipping them, would render something else than the file asks for.
    if rest.starts_with('-') {
        let option = rest.split_whitespace().next().unwrap_or(rest);
        return Err(syntax(
            path,
            line,
            format!(
                "{keyword}: texture options such as '{option}' are not supported; give the file name alone"
            ),
        ));
    }
    // Like tobj, the rest of the line is the file name (it may contain spaces).
    let file = dir.join(rest);
    let key = (file.clone(), encoding);
    if let Some(&index) = textures.index.get(&key) {
        return Ok(index);
    }
    let texture = Texture::load(&file, encoding).map_err(|message| {
        // The OS's message without its "(os error N)" suffix.
        let message = match message.find(" (os error") {
            Some(at) => message[..at].to_string(),
            None => message,
        };
        syntax(
            path,
            line,
            format!("{keyword}: cannot read '{rest}': {message}"),
        )
    })?;
    let index = textures.list.len() as u32;
    textures.list.push(texture);
    textures.index.insert(key, index);
    Ok(index)
}

/// Loads the checked text through tobj and converts its models.
fn load_checked(path: &Path, checked: CheckedObj) -> Result<Mesh, SceneError> {
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
        &mut PiecesReader {
            pieces: &checked.pieces,
            piece: 0,
            at: 0,
        },
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
        warnings: checked.warnings,
        path: path.to_path_buf(),
        triangles: Vec::new(),
        materials: materials
            .iter()
            .map(|m| material_from(m, checked.extras.get(&m.name)))
            .collect(),
        material_names: materials.iter().map(|m| m.name.clone()).collect(),
        textures: checked.textures.list,
        back_materials: Default::default(),
        null_masks: Default::default(),
    };
    // tobj keeps the faces' order (its models follow the file) and fans each the same way.
    let mut corners = checked.pieces.iter().flat_map(|piece| {
        piece.faces.iter().flat_map(|face| {
            let corner = |k: usize| match &face.attributes {
                Some(at) => piece.corners[at.start + k],
                None => (None, None),
            };
            crate::scene::mesh::fan_corners(face.count).map(move |t| (face.line, t.map(corner)))
        })
    });
    let mut zero_normals: Vec<usize> = Vec::new();
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
        for indices in model.mesh.indices.chunks_exact(3) {
            let Some((line, triangle)) = corners.next() else {
                return Err(SceneError::Mesh {
                    path: path.to_path_buf(),
                    message: "tobj returned more triangles than the file has".to_string(),
                });
            };
            let uvs = match triangle.map(|(vt, _)| vt) {
                [Some(a), Some(b), Some(c)] => Some([
                    checked.texcoords[a],
                    checked.texcoords[b],
                    checked.texcoords[c],
                ]),
                _ => None,
            };
            if uvs.is_none() {
                check_surface_map_uvs(path, line, &mesh.material_names, material, &checked.extras)?;
            }
            let normals = match triangle.map(|(_, vn)| vn) {
                [Some(a), Some(b), Some(c)] => {
                    let n = [checked.normals[a], checked.normals[b], checked.normals[c]];
                    // A zero (or overflowing) normal has no direction to interpolate.
                    if n.iter().all(|n| n.length_squared().is_normal()) {
                        Some(n.map(Vec3::normalize))
                    } else {
                        if zero_normals.last() != Some(&line) {
                            zero_normals.push(line);
                        }
                        None
                    }
                }
                _ => None,
            };
            mesh.triangles.push(MeshTriangle {
                vertices: [
                    vertex(indices[0])?,
                    vertex(indices[1])?,
                    vertex(indices[2])?,
                ],
                material,
                normals,
                uvs,
            });
        }
    }
    if let Some(&first) = zero_normals.first() {
        mesh.warnings.push(format!(
            "{}:{first}: {} face{} a zero-length (or overflowing) normal (vn); shaded with the geometric normal",
            path.display(),
            zero_normals.len(),
            if zero_normals.len() == 1 {
                " has"
            } else {
                "s have"
            }
        ));
    }
    Ok(mesh)
}

/// A normal or bump map needs the tangent frame that texture coordinates give: an error at the
/// map's MTL line, naming the face without `vt`, when `material` has one.
fn check_surface_map_uvs(
    path: &Path,
    face_line: usize,
    names: &[String],
    material: u32,
    extras: &HashMap<String, MtlExtras>,
) -> Result<(), SceneError> {
    let Some(name) = names.get(material as usize) else {
        return Ok(());
    };
    match extras.get(name).and_then(|e| e.surface_map.as_ref()) {
        Some(map) => Err(SceneError::Syntax {
            at: map.at.clone(),
            message: format!(
                "{}: material '{name}' needs texture coordinates (vt) for its tangent frame, but the face at {}:{face_line} has none",
                map.keyword,
                path.display()
            ),
        }),
        None => Ok(()),
    }
}

/// GGX roughness r from `Pr`, or else from `Ns` as Blender's OBJ importer converts it
/// (r = 1 - sqrt(Ns / 1000)); 0 (smooth) when neither is given.
fn roughness(m: &tobj::Material, extras: &MtlExtras) -> f32 {
    match (extras.pr, m.shininess) {
        (Some(pr), _) => pr,
        (None, Some(ns)) => 1.0 - (ns.clamp(0.0, 1000.0) / 1000.0).sqrt(),
        (None, None) => 0.0,
    }
}

/// MTL values to the renderer's material. Missing values: Kd 0.8 (as for faces without a
/// material), Ks 0, Ns 0, Ke 0, Ni 1.5, Tf 1, d 1.
///
/// The kind: `illum` 4, 6 or 7, or a `Tf`: dielectric (glass), with `thin 1` a thin sheet
/// (smooth: `Pr` does not apply). Else `Pm` or `Pr` (the PBR
/// keys): a conductor when Pm >= 0.5 (Fresnel = Kd, or Kd times the complex-index Fresnel of
/// `eta`/`k` or of a `conductor NAME` preset), plastic otherwise (diffuse Kd, specular tint Ks,
/// 1 when absent). Else the seed's models: Phong when Ks > 0, Lambert otherwise. `distribution`
/// picks the rough models' microfacets (GGX when absent).
fn material_from(m: &tobj::Material, extras: Option<&MtlExtras>) -> Material {
    let extras = extras.cloned().unwrap_or_default();
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
    let kd = m.diffuse.unwrap_or(Material::DEFAULT.kd);
    let glass = matches!(extras.illum, Some(4 | 6 | 7)) || extras.tf.is_some();
    let pbr = extras.pm.is_some() || extras.pr.is_some();
    let r = roughness(m, &extras);
    let mut material = Material {
        kd,
        ns: m.shininess.unwrap_or(0.0),
        ks: m.specular.unwrap_or([0.0; 3]),
        ke: ke.unwrap_or([0.0; 3]),
        tf: extras.tf.unwrap_or([1.0; 3]),
        ior: extras.ni.unwrap_or(1.5),
        map_kd: extras.map_kd.unwrap_or(NO_TEXTURE),
        map_ks: extras.map_ks.unwrap_or(NO_TEXTURE),
        map_pr: extras.map_pr.unwrap_or(NO_TEXTURE),
        map_d: extras.map_d.unwrap_or(NO_TEXTURE),
        opacity: extras.d.unwrap_or(1.0),
        surface_map: extras
            .surface_map
            .as_ref()
            .map_or(NO_TEXTURE, |s| s.texture),
        bump_scale: extras.surface_map.as_ref().map_or(1.0, |s| s.bump_scale),
        ..Material::default()
    };
    if glass && extras.thin {
        // Mitsuba's thindielectric is smooth only.
        material.kind = MATERIAL_THIN_DIELECTRIC;
    } else if glass {
        material.kind = MATERIAL_DIELECTRIC;
        material.alpha = r * r;
    } else if pbr {
        material.alpha = r * r;
        if extras.pm.unwrap_or(0.0) >= 0.5 {
            material.kind = MATERIAL_CONDUCTOR;
            if let Some((eta, k)) = conductor_ior(&extras) {
                material.eta = eta.to_array();
                material.k = k.to_array();
                material.fresnel = FRESNEL_CONDUCTOR;
            }
        } else {
            material.kind = MATERIAL_PLASTIC;
            material.ks = m.specular.unwrap_or([1.0; 3]);
        }
    } else if material.ks.iter().any(|&c| c > 0.0) {
        material.kind = MATERIAL_PHONG;
    } else {
        material.kind = MATERIAL_LAMBERT;
    }
    material.distribution = extras.distribution.unwrap_or_default() as u32;
    material
}

/// A conductor's complex index from its MTL keys: `eta` and `k` (a missing one is Mitsuba's
/// default: eta 0, k 1), else the `conductor` preset's; `None` without any (Fresnel 1).
fn conductor_ior(extras: &MtlExtras) -> Option<(Vec3, Vec3)> {
    if extras.eta.is_some() || extras.k.is_some() {
        let eta = extras.eta.map_or(Vec3::ZERO, Vec3::from);
        let k = extras.k.map_or(Vec3::ONE, Vec3::from);
        return Some((eta, k));
    }
    extras.conductor_ior
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What a check gives, comparable: the text tobj reads, every face (line, corners'
    /// attributes), texture coordinates, normals; or the error's message.
    fn summary(checked: Result<CheckedObj, SceneError>) -> String {
        match checked {
            Err(e) => format!("error: {e}"),
            Ok(c) => {
                let text: String = c.pieces.iter().map(|p| p.text.as_str()).collect();
                let faces: Vec<String> = c
                    .pieces
                    .iter()
                    .flat_map(|p| {
                        p.faces.iter().map(move |f| {
                            let corners: Vec<Corner> = (0..f.count)
                                .map(|k| {
                                    f.attributes
                                        .as_ref()
                                        .map_or((None, None), |a| p.corners[a.start + k])
                                })
                                .collect();
                            format!("{} {:?}", f.line, corners)
                        })
                    })
                    .collect();
                format!(
                    "{text}|{faces:?}|{:?}|{:?}|{}",
                    c.texcoords,
                    c.normals,
                    c.libraries.len()
                )
            }
        }
    }

    /// Checked in pieces as small as one line each, a file gives what it gives whole: faces
    /// index vertices, coordinates and normals of earlier pieces (counted back too), `usemtl`
    /// names what an earlier piece's library defines, and the first error in the file is the
    /// one reported, whichever piece holds it and whether it is a material line's.
    #[test]
    fn pieces_of_any_size_check_as_the_whole_file() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("m.mtl"), "newmtl red\nKd 1 0 0\n").unwrap();
        let path = dir.path().join("mesh.obj");
        let good = "# é, a comment of two-byte chars\nmtllib m.mtl\nv 0 0 0\nv 1 0 0\n\nvt 0 0\n\
                    vn 0 0 1\nv 0 1 0 1\nusemtl red\nf 1/1/1 2/1/1 3/1/1\no ünïcode\nv 1 1 0\n\
                    f -1 -2 -3 -4\nf 1 2\ng two\nf 1//1 -3//-1 4//1\n";
        let whole = summary(check_obj_in_pieces(&path, good, true, usize::MAX));
        assert!(!whole.starts_with("error"), "{whole}");
        let broken = [
            // (the replaced line, its replacement)
            ("f 1/1/1 2/1/1 3/1/1", "f 1/1/1 2/1/1 9/1/1"),
            ("f -1 -2 -3 -4", "f -1 -2 -3 -5"),
            ("usemtl red", "usemtl blue"),
            ("v 1 1 0", "v 1 1 nan"),
            // A material error after a syntax error: the syntax error is the first.
            ("vn 0 0 1", "vn 0 0"),
        ];
        let mut texts = vec![(good.to_string(), whole)];
        for (from, to) in broken {
            let mut text = good.replace(from, to);
            if to == "vn 0 0" {
                text = text.replace("usemtl red", "usemtl blue");
            }
            let expected = summary(check_obj_in_pieces(&path, &text, true, usize::MAX));
            assert!(expected.starts_with("error"), "{to}: {expected}");
            texts.push((text, expected));
        }
        for (text, expected) in &texts {
            for size in [0, 1, 5, 20, 64, text.len() - 1] {
                let pieces = pieces(text, size);
                assert!(size > 40 || pieces.len() > 3, "{size}: {}", pieces.len());
                let got = summary(check_obj_in_pieces(&path, text, true, size));
                assert_eq!(&got, expected, "pieces of {size}");
            }
        }
    }
}
