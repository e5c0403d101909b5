//! The scene file (RON): which mesh to load, relative to the scene file, the camera and,
//! optionally, the longest path (Mitsuba's `max_depth`, default 3; -1 for unbounded), Russian
//! roulette (Mitsuba's `rr_depth`, default none) and the pixel filter (default `Box`).
//!
//! ```ron
//! Scene(
//!     mesh: "cornell.obj",
//!     camera: Camera(eye: (278, 273, -800), target: (278, 273, 0), up: (0, 1, 0), fov_y: 39.3077),
//!     max_depth: 8,
//!     // Optional: lights besides the emissive triangles, and the environment.
//!     lights: [
//!         Point(position: (278, 500, 279), intensity: (4e4, 4e4, 4e4)),
//!         Spot(position: (278, 540, 279), target: (278, 0, 279), intensity: (1e5, 1e5, 1e5),
//!              cutoff_angle: 20, beam_width: 15),
//!         Directional(direction: (0, -1, 0.2), irradiance: (3, 3, 3)),
//!     ],
//!     environment: Environment(file: "sky.exr", scale: 1, to_world: [Rotate(axis: (0, 1, 0), angle: 90)]),
//!     // or: environment: Environment(color: (0.5, 0.5, 0.5)),
//! )
//! ```
//!
//! The mesh may be a glTF file (`.gltf`, `.glb`): its materials and punctual lights come with
//! it (the lights after this file's), and its first camera when this file names none.
//!
//! The camera is `Camera(eye, target, up, fov_y: F)` (the vertical field of view), or
//! `Camera(eye, target, up, fov: F, fov_axis: X | Y | Diagonal | Smaller | Larger)` (Mitsuba's
//! `fov` / `fov_axis`; the axis defaults to X as Mitsuba's), either with
//! `aperture_radius: R, focus_distance: D` for a thin lens (both or neither), or
//! `Orthographic(eye, target, up, width: W)`: parallel rays from a rectangle W world units wide
//! around the eye. `filter: Box | Gaussian(stddev: S) | Tent(radius: R)` (in pixels).

use super::camera::MAX_COORDINATE;
use super::camera::{CameraDesc, CameraError, FovAxis, Lens, Projection};
pub use super::description::{
    LoadedScene, MAX_MAX_DEPTH, Scene, SceneOptions, check_depths, check_max_depth, check_rr_depth,
};
use super::emitters::{AnalyticLight, Emitters};
use super::environment::{Environment, EnvironmentMap};
use super::environment_image::load_environment_image;
use super::error::{Location, SceneError};
use super::filter::PixelFilter;
use super::gpu_layout::DEFAULT_MAX_DEPTH;
use super::mesh_file::load_mesh;
use super::texture::{Encoding, Texture};
use glam::{Mat3, Vec3};
use serde::Deserialize;
use serde::de::{self, Deserializer, Visitor};
use std::fmt;
use std::path::{Path, PathBuf};

/// The built-in default scene, relative to the crate root.
pub const DEFAULT_SCENE: &str = "scenes/cornell/scene.ron";

/// The scene file as written.
#[derive(Debug, Deserialize)]
#[serde(rename = "Scene", deny_unknown_fields)]
struct SceneFile {
    mesh: PathBuf,
    /// Optional only for a glTF mesh, whose first camera it then takes.
    #[serde(default)]
    camera: Option<CameraFile>,
    #[serde(default = "default_max_depth")]
    max_depth: i64,
    #[serde(default)]
    rr_depth: Option<i64>,
    #[serde(default)]
    lights: Vec<LightFile>,
    #[serde(default)]
    environment: Option<EnvironmentFile>,
    #[serde(default)]
    filter: FilterFile,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
enum LightFile {
    Point {
        position: (Number, Number, Number),
        intensity: (Number, Number, Number),
    },
    Spot {
        position: (Number, Number, Number),
        target: (Number, Number, Number),
        intensity: (Number, Number, Number),
        /// Degrees; Mitsuba's default 20.
        cutoff_angle: Option<Number>,
        /// Degrees; Mitsuba's default 3/4 of the cutoff angle.
        beam_width: Option<Number>,
        /// The lookat frame's up (not along the axis), orienting `texture`; default +y, or +x
        /// for an axis within 26 degrees of y.
        up: Option<(Number, Number, Number)>,
        /// An image (PNG, JPEG; sRGB) projected over the cone, as Mitsuba's spot `texture`.
        texture: Option<PathBuf>,
    },
    Directional {
        direction: (Number, Number, Number),
        irradiance: (Number, Number, Number),
    },
}

#[derive(Debug, Deserialize)]
#[serde(rename = "Environment", deny_unknown_fields)]
struct EnvironmentFile {
    file: Option<PathBuf>,
    color: Option<(Number, Number, Number)>,
    scale: Option<Number>,
    #[serde(default)]
    to_world: Vec<TransformFile>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
enum TransformFile {
    /// A right-handed rotation by `angle` degrees about `axis`, as Mitsuba's `rotate`.
    Rotate {
        axis: (Number, Number, Number),
        angle: Number,
    },
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

/// Whether a scene path is a Mitsuba XML scene (by its extension, any case).
pub fn is_mitsuba_xml(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("xml"))
}

/// Loads a RON scene or (`.xml`) a Mitsuba 3 scene with `options` applied.
pub fn load_scene_with(path: &Path, options: &SceneOptions) -> Result<LoadedScene, SceneError> {
    let loaded = load_scene_unchecked(path, options)?;
    if options.max_depth.is_some() {
        check_depths(loaded.scene.max_depth, loaded.scene.rr_depth).map_err(|message| {
            SceneError::Syntax {
                at: Location {
                    path: path.to_path_buf(),
                    line: None,
                    item: None,
                },
                message: format!("--max-depth: {message}"),
            }
        })?;
    }
    Ok(loaded)
}

fn load_scene_unchecked(path: &Path, options: &SceneOptions) -> Result<LoadedScene, SceneError> {
    if is_mitsuba_xml(path) {
        let built = super::mitsuba_xml::load_mitsuba_xml(path, options)?;
        return Ok(LoadedScene {
            scene: built.scene,
            film_size: Some(built.film_size),
            sample_count: Some(built.sample_count),
        });
    }
    let only = |what: &str, kind: &str| SceneError::Syntax {
        at: Location {
            path: path.to_path_buf(),
            line: None,
            item: None,
        },
        message: format!("{what} applies to {kind} scenes only"),
    };
    if super::gltf::is_gltf(path) {
        if !options.defines.is_empty() {
            return Err(only("--define", "Mitsuba XML"));
        }
        let mut scene = super::gltf::load_gltf(path, options.camera.as_deref())?;
        if let Some(d) = options.max_depth {
            scene.max_depth = d;
        }
        return Ok(LoadedScene {
            scene,
            film_size: None,
            sample_count: None,
        });
    }
    if options.camera.is_some() {
        return Err(only("--camera", "glTF"));
    }
    if !options.defines.is_empty() {
        return Err(SceneError::Syntax {
            at: Location {
                path: path.to_path_buf(),
                line: None,
                item: None,
            },
            message: "--define applies to Mitsuba XML scenes only".into(),
        });
    }
    let mut scene = load_ron_scene(path)?;
    if let Some(d) = options.max_depth {
        scene.max_depth = d;
    }
    Ok(LoadedScene {
        scene,
        film_size: None,
        sample_count: None,
    })
}

/// Reads a scene file: RON, or a Mitsuba 3 XML scene (`.xml`, see
/// [`super::mitsuba_xml`]) without defines.
pub fn load_scene(path: &Path) -> Result<Scene, SceneError> {
    load_scene_with(path, &SceneOptions::default()).map(|l| l.scene)
}

/// Reads a RON scene file and the mesh it names (and that mesh's materials).
///
/// Errors: the file cannot be read; RON syntax or schema (file:line:col); an invalid camera
/// (eye at target, up parallel to the view, fov outside (0, 180), a lens or orthographic width
/// that is not a finite number > 0, half a lens); an invalid filter size; any mesh error (see
/// [`load_mesh`]).
fn load_ron_scene(path: &Path) -> Result<Scene, SceneError> {
    let text = crate::text_file::read_utf8(path).map_err(|source| SceneError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    // Optional fields are written bare (`environment: Environment(...)`), not as `Some(...)`.
    let options =
        ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    let file: SceneFile = options.from_str(&text).map_err(|e| SceneError::Ron {
        path: path.to_path_buf(),
        line: e.span.start.line,
        col: e.span.start.col,
        message: e.code.to_string(),
    })?;
    let dir = path.parent().unwrap_or(Path::new(""));
    let mesh_path = dir.join(&file.mesh);
    let gltf = super::gltf::is_gltf(&mesh_path);
    // Checked before the mesh: it is cheap, and its error is about this file.
    let camera = file
        .camera
        .as_ref()
        .map(|c| {
            c.camera().map_err(|(source, field)| SceneError::Camera {
                at: Location {
                    path: path.to_path_buf(),
                    line: field_line(&text, field),
                    item: None,
                },
                source,
            })
        })
        .transpose()?;
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
    let rr_depth = file
        .rr_depth
        .map(check_rr_depth)
        .transpose()
        .and_then(|rr| check_depths(max_depth, rr).map(|()| rr))
        .map_err(|message| SceneError::Syntax {
            at: Location {
                path: path.to_path_buf(),
                line: field_line(&text, "rr_depth").or(field_line(&text, "max_depth")),
                item: None,
            },
            message,
        })?;
    let at = |field: &str| Location {
        path: path.to_path_buf(),
        line: field_line(&text, field),
        item: None,
    };
    let mut lights = file
        .lights
        .iter()
        .enumerate()
        .map(|(k, light)| {
            analytic_light(light, dir).map_err(|message| SceneError::Syntax {
                at: Location {
                    line: nth_variant_line(&text, "lights", k).or(field_line(&text, "lights")),
                    ..at("lights")
                },
                message: format!("lights[{k}]: {message}"),
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let environment = file
        .environment
        .as_ref()
        .map(|e| {
            environment(e, dir).map_err(|message| SceneError::Syntax {
                at: at("environment"),
                message,
            })
        })
        .transpose()?;
    // A glTF mesh brings its materials and its lights (KHR_lights_punctual), and its camera
    // where this file names none; the environment, depths and filter are this file's.
    let (mesh, camera) = match (gltf, camera) {
        (true, camera) => {
            let scene = super::gltf::load_gltf(&mesh_path, None)?;
            lights.extend(scene.emitters.lights);
            (scene.mesh, camera.unwrap_or(scene.camera))
        }
        (false, Some(camera)) => (load_mesh(&mesh_path)?, camera),
        (false, None) => {
            return Err(SceneError::Syntax {
                at: at("mesh"),
                message: "missing field `camera` (only a glTF mesh brings its own)".into(),
            });
        }
    };
    Ok(Scene {
        path: path.to_path_buf(),
        mesh,
        camera,
        max_depth,
        rr_depth,
        emitters: Emitters {
            lights,
            environment,
        },
        filter,
    })
}

/// A finite point; `what` names it in the message.
fn finite_point(p: (Number, Number, Number), what: &str) -> Result<Vec3, String> {
    let v = vec3(p);
    if !v.is_finite() {
        return Err(format!("{what} {v} must be finite"));
    }
    if v.abs().max_element() > MAX_COORDINATE {
        return Err(format!(
            "{what} {v} lies beyond ±{MAX_COORDINATE:e}, where the renderer's f32 arithmetic overflows"
        ));
    }
    Ok(v)
}

/// A colour: finite, not negative.
fn colour(c: (Number, Number, Number), what: &str) -> Result<Vec3, String> {
    let v = vec3(c);
    if !v.is_finite() || v.min_element() < 0.0 {
        return Err(format!(
            "{what} {v} must be finite and not negative in every channel"
        ));
    }
    Ok(v)
}

/// The up a spot's frame takes when the file gives none: any not along the axis (the
/// exporter writes it, so Mitsuba's frame is the same).
pub fn default_spot_up(axis: Vec3) -> Vec3 {
    if axis.y.abs() < 0.9 { Vec3::Y } else { Vec3::X }
}

fn analytic_light(light: &LightFile, dir: &Path) -> Result<AnalyticLight, String> {
    Ok(match *light {
        LightFile::Point {
            position,
            intensity,
        } => AnalyticLight::Point {
            position: finite_point(position, "position")?,
            intensity: colour(intensity, "intensity")?,
        },
        LightFile::Spot {
            position,
            target,
            intensity,
            cutoff_angle,
            beam_width,
            up,
            ref texture,
        } => {
            let position = finite_point(position, "position")?;
            let target = finite_point(target, "target")?;
            if (target - position).length() <= 0.0 || !(target - position).length().is_finite() {
                return Err("a spot's target must differ from its position".into());
            }
            let cutoff = cutoff_angle.map_or(20.0, |n| n.0);
            if !(cutoff > 0.0 && cutoff <= 90.0) {
                return Err(format!(
                    "cutoff_angle is {cutoff} degrees; it must be in (0, 90]"
                ));
            }
            let beam = beam_width.map_or(0.75 * cutoff, |n| n.0);
            if !(beam > 0.0 && beam <= cutoff) {
                return Err(format!(
                    "beam_width is {beam} degrees; it must be in (0, cutoff_angle = {cutoff}]"
                ));
            }
            let axis = (target - position).normalize();
            let up = match up {
                None => default_spot_up(axis),
                Some(u) => {
                    let u = finite_point(u, "up")?;
                    if u.cross(axis).length() <= 1e-6 * u.length() {
                        return Err(format!(
                            "up {u} is zero or along the spot's axis {axis}; it must not be"
                        ));
                    }
                    u
                }
            };
            let texture = texture
                .as_ref()
                .map(|file| {
                    let path = dir.join(file);
                    Texture::load(&path, Encoding::Srgb)
                        .map_err(|e| format!("texture {}: {e}", path.display()))
                })
                .transpose()?;
            AnalyticLight::Spot {
                position,
                target,
                up,
                intensity: colour(intensity, "intensity")?,
                cutoff_angle: cutoff,
                beam_width: beam,
                texture,
            }
        }
        LightFile::Directional {
            direction,
            irradiance,
        } => {
            let d = finite_point(direction, "direction")?;
            let unit = d
                .try_normalize()
                .ok_or_else(|| format!("direction {d} must be a nonzero vector"))?;
            AnalyticLight::Directional {
                direction: unit,
                irradiance: colour(irradiance, "irradiance")?,
            }
        }
    })
}

fn environment(e: &EnvironmentFile, dir: &Path) -> Result<Environment, String> {
    let scale = e.scale.map_or(1.0, |n| n.0);
    if !(scale.is_finite() && scale >= 0.0) {
        return Err(format!(
            "environment scale is {scale}; it must be finite and not negative"
        ));
    }
    let mut to_world = Mat3::IDENTITY;
    for t in &e.to_world {
        let TransformFile::Rotate { axis, angle } = *t;
        let axis = finite_point(axis, "rotation axis")?
            .try_normalize()
            .ok_or("a rotation axis must be a nonzero vector")?;
        if !angle.0.is_finite() {
            return Err(format!("rotation angle {} must be finite", angle.0));
        }
        // Each rotation applies after the ones before it, as in Mitsuba's <transform>.
        to_world = Mat3::from_axis_angle(axis, angle.0.to_radians()) * to_world;
    }
    match (&e.file, e.color) {
        (Some(_), Some(_)) => Err("an environment has a file or a color, not both".into()),
        (None, None) => {
            Err("an environment needs a file (an .exr or .hdr image) or a color".into())
        }
        (None, Some(c)) => {
            if !e.to_world.is_empty() {
                return Err(
                    "a uniform environment (color) has no orientation: drop to_world".into(),
                );
            }
            Ok(Environment::Constant {
                radiance: colour(c, "color")? * scale,
            })
        }
        (Some(file), None) => {
            let path = dir.join(file);
            let image = load_environment_image(&path)?;
            Ok(Environment::Map(EnvironmentMap::new(
                path, image, scale, to_world,
            )))
        }
    }
}

/// The line of the k-th entry (a `Name(`) of the list field `field`, if the text shows it.
fn nth_variant_line(text: &str, field: &str, k: usize) -> Option<usize> {
    let start = field_line(text, field)?;
    let offset: usize = text.lines().take(start - 1).map(|l| l.len() + 1).sum();
    let rest = &text[offset..];
    let list = &rest[rest.find('[')? + 1..];
    let mut depth = 0usize;
    let mut seen = 0usize;
    for (at, c) in list.char_indices() {
        match c {
            '(' => {
                if depth == 0 {
                    if seen == k {
                        let absolute = offset + (rest.len() - list.len()) + at;
                        return Some(text[..absolute].matches('\n').count() + 1);
                    }
                    seen += 1;
                }
                depth += 1;
            }
            ')' => depth = depth.saturating_sub(1),
            ']' if depth == 0 => return None,
            _ => {}
        }
    }
    None
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
