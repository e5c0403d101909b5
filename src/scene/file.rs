//! The scene file (RON): which mesh to load, relative to the scene file, the camera and,
//! optionally, the longest path (Mitsuba's `max_depth`, default 3).
//!
//! ```ron
//! Scene(
//!     mesh: "cornell.obj",
//!     camera: Camera(eye: (278, 273, -800), target: (278, 273, 0), up: (0, 1, 0), fov_y: 39.3077),
//!     max_depth: 8,
//! )
//! ```

use super::camera::{CameraDesc, CameraError};
use super::error::{Location, SceneError};
use super::gpu::DEFAULT_MAX_DEPTH;
use super::mesh::{Mesh, load_mesh};
use glam::Vec3;
use serde::Deserialize;
use serde::de::{self, Deserializer, Visitor};
use std::fmt;
use std::path::{Path, PathBuf};

/// A loaded scene: the mesh with its materials and the camera.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The scene file.
    pub path: PathBuf,
    pub mesh: Mesh,
    pub camera: CameraDesc,
    /// The longest path in segments, as Mitsuba's `max_depth` (1: emitters seen directly,
    /// 2: direct light, 3: one bounce, ...); at least 1.
    pub max_depth: u32,
}

/// The built-in default scene, relative to the crate root.
pub const DEFAULT_SCENE: &str = "scenes/cornell/scene.ron";

/// The scene file as written.
#[derive(Debug, Deserialize)]
#[serde(rename = "Scene", deny_unknown_fields)]
struct SceneFile {
    mesh: PathBuf,
    camera: CameraFile,
    #[serde(default = "default_max_depth")]
    max_depth: i64,
}

fn default_max_depth() -> i64 {
    i64::from(DEFAULT_MAX_DEPTH)
}

#[derive(Debug, Deserialize)]
#[serde(rename = "Camera", deny_unknown_fields)]
struct CameraFile {
    eye: (Number, Number, Number),
    target: (Number, Number, Number),
    up: (Number, Number, Number),
    /// Vertical field of view in degrees.
    fov_y: Number,
}

/// An f32 that may be written as an integer (`278` as well as `278.0`).
#[derive(Clone, Copy, Debug)]
struct Number(f32);

impl<'de> Deserialize<'de> for Number {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Number, D::Error> {
        struct NumberVisitor;
        impl Visitor<'_> for NumberVisitor {
            type Value = Number;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Number, E> {
                Ok(Number(v as f32))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Number, E> {
                Ok(Number(v as f32))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Number, E> {
                Ok(Number(v as f32))
            }
            fn visit_i128<E: de::Error>(self, v: i128) -> Result<Number, E> {
                Ok(Number(v as f32))
            }
            fn visit_u128<E: de::Error>(self, v: u128) -> Result<Number, E> {
                Ok(Number(v as f32))
            }
        }
        deserializer.deserialize_any(NumberVisitor)
    }
}

fn vec3((x, y, z): (Number, Number, Number)) -> Vec3 {
    Vec3::new(x.0, y.0, z.0)
}

/// Reads a scene file and the mesh it names (and that mesh's materials).
///
/// Errors: the file cannot be read; RON syntax or schema (file:line:col); an invalid camera
/// (eye at target, up parallel to the view, fov outside (0, 180)); any mesh error (see
/// [`load_mesh`]).
pub fn load_scene(path: &Path) -> Result<Scene, SceneError> {
    let text = crate::text_file::read_utf8(path).map_err(|source| SceneError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let file: SceneFile = ron::from_str(&text).map_err(|e| SceneError::Ron {
        path: path.to_path_buf(),
        line: e.span.start.line,
        col: e.span.start.col,
        message: e.code.to_string(),
    })?;
    // Checked before the mesh: it is cheap, and its error is about this file.
    let camera = CameraDesc::new(
        vec3(file.camera.eye),
        vec3(file.camera.target),
        vec3(file.camera.up),
        file.camera.fov_y.0,
    )
    .map_err(|source| {
        let field = match source {
            CameraError::FieldOfView(_) => "fov_y",
            CameraError::EyeAtTarget => "target",
            CameraError::UpParallelToForward => "up",
            CameraError::NonFinite => "camera",
            CameraError::OutOfRange { what, .. } => what,
        };
        SceneError::Camera {
            at: Location {
                path: path.to_path_buf(),
                line: field_line(&text, field),
                item: None,
            },
            source,
        }
    })?;
    let max_depth = check_max_depth(file.max_depth).map_err(|message| SceneError::Syntax {
        at: Location {
            path: path.to_path_buf(),
            line: field_line(&text, "max_depth"),
            item: None,
        },
        message,
    })?;
    let dir = path.parent().unwrap_or(Path::new(""));
    let mesh = load_mesh(&dir.join(&file.mesh))?;
    Ok(Scene {
        path: path.to_path_buf(),
        mesh,
        camera,
        max_depth,
    })
}

/// The largest `max_depth`: Mitsuba's is an `int`.
pub const MAX_MAX_DEPTH: u32 = i32::MAX as u32;

/// A `max_depth` as written (scene file or command line): 1..=[`MAX_MAX_DEPTH`].
pub fn check_max_depth(depth: i64) -> Result<u32, String> {
    match u32::try_from(depth) {
        Ok(d) if (1..=MAX_MAX_DEPTH).contains(&d) => Ok(d),
        _ => Err(format!(
            "max_depth must be 1 (emitters seen directly) to {MAX_MAX_DEPTH}, found {depth}"
        )),
    }
}

/// The line of the first `field:` in RON text (serde keeps no positions once parsed). Comments
/// are not skipped: this only points a message at a likely line.
fn field_line(text: &str, field: &str) -> Option<usize> {
    let is_ident = |c: char| c.is_alphanumeric() || c == '_';
    text.match_indices(field)
        .find(|&(at, _)| {
            let before_ok = !text[..at].chars().next_back().is_some_and(is_ident);
            let after = text[at + field.len()..].trim_start();
            before_ok && after.starts_with(':')
        })
        .map(|(at, _)| text[..at].matches('\n').count() + 1)
}
