//! The scene file (RON): which mesh to load, relative to the scene file, the camera and,
//! optionally, the longest path (Mitsuba's `max_depth`, default 3) and the pixel filter
//! (default `Box`).
//!
//! ```ron
//! Scene(
//!     mesh: "cornell.obj",
//!     camera: Camera(eye: (278, 273, -800), target: (278, 273, 0), up: (0, 1, 0), fov_y: 39.3077),
//!     max_depth: 8,
//! )
//! ```
//!
//! The camera is `Camera(eye, target, up, fov_y: F)` (the vertical field of view), or
//! `Camera(eye, target, up, fov: F, fov_axis: X | Y | Diagonal | Smaller | Larger)` (Mitsuba's
//! `fov` / `fov_axis`; the axis defaults to X as Mitsuba's), either with
//! `aperture_radius: R, focus_distance: D` for a thin lens (both or neither), or
//! `Orthographic(eye, target, up, width: W)`: parallel rays from a rectangle W world units wide
//! around the eye. `filter: Box | Gaussian(stddev: S) | Tent(radius: R)` (in pixels).

use super::camera::{CameraDesc, CameraError, FovAxis, Lens, Projection};
use super::error::{Location, SceneError};
use super::filter::PixelFilter;
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
    /// The pixel filter (Box unless the file names one).
    pub filter: PixelFilter,
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
    #[serde(default)]
    filter: FilterFile,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
enum FilterFile {
    #[default]
    Box,
    Gaussian {
        stddev: Number,
    },
    Tent {
        radius: Number,
    },
}

impl FilterFile {
    fn filter(&self) -> PixelFilter {
        match *self {
            FilterFile::Box => PixelFilter::Box,
            FilterFile::Gaussian { stddev } => PixelFilter::Gaussian { stddev: stddev.0 },
            FilterFile::Tent { radius } => PixelFilter::Tent { radius: radius.0 },
        }
    }
}

fn default_max_depth() -> i64 {
    i64::from(DEFAULT_MAX_DEPTH)
}

/// `Camera(...)` (perspective, optionally a thin lens) or `Orthographic(...)`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
enum CameraFile {
    Camera {
        eye: (Number, Number, Number),
        target: (Number, Number, Number),
        up: (Number, Number, Number),
        /// Vertical field of view in degrees.
        #[serde(default, deserialize_with = "some_number")]
        fov_y: Option<Number>,
        /// Field of view in degrees along `fov_axis`.
        #[serde(default, deserialize_with = "some_number")]
        fov: Option<Number>,
        #[serde(default, deserialize_with = "some_axis")]
        fov_axis: Option<FovAxisFile>,
        #[serde(default, deserialize_with = "some_number")]
        aperture_radius: Option<Number>,
        #[serde(default, deserialize_with = "some_number")]
        focus_distance: Option<Number>,
    },
    Orthographic {
        eye: (Number, Number, Number),
        target: (Number, Number, Number),
        up: (Number, Number, Number),
        /// The image's horizontal extent in world units.
        width: Number,
    },
}

#[derive(Clone, Copy, Debug, Deserialize)]
enum FovAxisFile {
    X,
    Y,
    Diagonal,
    Smaller,
    Larger,
}

/// An optional field written as a plain number (`fov: 40`, not `fov: Some(40)`).
fn some_number<'de, D: Deserializer<'de>>(deserializer: D) -> Result<Option<Number>, D::Error> {
    Number::deserialize(deserializer).map(Some)
}

/// `fov_axis: X`, not `fov_axis: Some(X)`.
fn some_axis<'de, D: Deserializer<'de>>(deserializer: D) -> Result<Option<FovAxisFile>, D::Error> {
    FovAxisFile::deserialize(deserializer).map(Some)
}

impl CameraFile {
    /// The camera, or the error and the field it is about.
    fn camera(&self) -> Result<CameraDesc, (CameraError, &'static str)> {
        match *self {
            CameraFile::Camera {
                eye,
                target,
                up,
                fov_y,
                fov,
                fov_axis,
                aperture_radius,
                focus_distance,
            } => {
                let (fov_degrees, fov_axis) = match (fov_y, fov, fov_axis) {
                    (Some(_), Some(_), _) => return Err((CameraError::FovTwice, "fov")),
                    (None, None, _) => return Err((CameraError::FovMissing, "camera")),
                    (Some(_), None, Some(_)) => {
                        return Err((CameraError::FovAxisWithoutFov, "fov_axis"));
                    }
                    (Some(f), None, None) => {
                        // fov_y keeps its own message and the pinhole's exact arithmetic.
                        if !(f.0 > 0.0 && f.0 < 180.0) {
                            return Err((CameraError::FieldOfView(f.0), "fov_y"));
                        }
                        (f.0, FovAxis::Y)
                    }
                    (None, Some(f), axis) => (f.0, axis.map_or(FovAxis::X, FovAxisFile::axis)),
                };
                let lens = match (aperture_radius, focus_distance) {
                    (None, None) => None,
                    (Some(_), None) => {
                        return Err((CameraError::ApertureWithoutFocus, "aperture_radius"));
                    }
                    (None, Some(_)) => {
                        return Err((CameraError::FocusWithoutAperture, "focus_distance"));
                    }
                    (Some(r), Some(d)) => Some(Lens {
                        aperture_radius: r.0,
                        focus_distance: d.0,
                    }),
                };
                let projection = Projection::Perspective {
                    fov_degrees,
                    fov_axis,
                    lens,
                };
                CameraDesc::with_projection(vec3(eye), vec3(target), vec3(up), projection).map_err(
                    |e| {
                        let field = camera_error_field(&e);
                        (e, field)
                    },
                )
            }
            CameraFile::Orthographic {
                eye,
                target,
                up,
                width,
            } => CameraDesc::with_projection(
                vec3(eye),
                vec3(target),
                vec3(up),
                Projection::Orthographic { width: width.0 },
            )
            .map_err(|e| {
                let field = camera_error_field(&e);
                (e, field)
            }),
        }
    }
}

impl FovAxisFile {
    fn axis(self) -> FovAxis {
        match self {
            FovAxisFile::X => FovAxis::X,
            FovAxisFile::Y => FovAxis::Y,
            FovAxisFile::Diagonal => FovAxis::Diagonal,
            FovAxisFile::Smaller => FovAxis::Smaller,
            FovAxisFile::Larger => FovAxis::Larger,
        }
    }
}

/// The scene-file field a camera error is about (the line it points to).
fn camera_error_field(e: &CameraError) -> &'static str {
    match e {
        CameraError::FieldOfView(_) | CameraError::FovOfOrthographic => "fov_y",
        CameraError::Fov(_) | CameraError::FovTwice => "fov",
        CameraError::FovAxisWithoutFov => "fov_axis",
        CameraError::EyeAtTarget => "target",
        CameraError::UpParallelToForward => "up",
        CameraError::NonFinite | CameraError::FovMissing => "camera",
        CameraError::OutOfRange { what, .. } => what,
        CameraError::ApertureRadius(_) | CameraError::ApertureWithoutFocus => "aperture_radius",
        CameraError::FocusDistance(_) | CameraError::FocusWithoutAperture => "focus_distance",
        CameraError::OrthographicWidth(_) | CameraError::WidthOutOfRange { .. } => "width",
    }
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
/// (eye at target, up parallel to the view, fov outside (0, 180), a lens or orthographic width
/// that is not a finite number > 0, half a lens); an invalid filter size; any mesh error (see
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
    let camera = file
        .camera
        .camera()
        .map_err(|(source, field)| SceneError::Camera {
            at: Location {
                path: path.to_path_buf(),
                line: field_line(&text, field),
                item: None,
            },
            source,
        })?;
    let filter = file
        .filter
        .filter()
        .check()
        .map_err(|message| SceneError::Syntax {
            at: Location {
                path: path.to_path_buf(),
                line: field_line(&text, "filter"),
                item: None,
            },
            message,
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
        filter,
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
