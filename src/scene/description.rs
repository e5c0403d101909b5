//! A scene as every loader makes it (RON scene files, OBJ, Mitsuba XML, glTF: src/scene/file.rs
//! dispatches), what the command line sets when one loads, and the depth limits they share.
//! The loaders depend on this, not on each other.

use super::camera::CameraDesc;
use super::emitters::Emitters;
use super::filter::PixelFilter;
use super::mesh::Mesh;
use std::path::PathBuf;

/// A loaded scene: the mesh with its materials and the camera.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The scene file.
    pub path: PathBuf,
    pub mesh: Mesh,
    pub camera: CameraDesc,
    /// The longest path in segments, as Mitsuba's `max_depth` (1: emitters seen directly,
    /// 2: direct light, 3: one bounce, ...); at least 1; [`MAX_MAX_DEPTH`] for unbounded
    /// (Mitsuba's -1), which needs `rr_depth`.
    pub max_depth: u32,
    /// Russian roulette from this BSDF sample of a path on (Mitsuba's `rr_depth`); none if
    /// `None` (the default, unlike Mitsuba's 5: the estimate is the same, the noise lower).
    pub rr_depth: Option<u32>,
    /// Point, spot and directional lights and the environment.
    pub emitters: Emitters,
    /// The pixel filter (Box unless the file names one).
    pub filter: PixelFilter,
}

/// What the command line sets when a scene loads.
#[derive(Clone, Debug, Default)]
pub struct SceneOptions {
    /// Mitsuba XML `NAME=VALUE` defines (`--define`, as `mitsuba -D`): they replace the
    /// file's `<default>`s.
    pub defines: Vec<(String, String)>,
    /// Replaces the file's `max_depth` (`--max-depth`).
    pub max_depth: Option<u32>,
    /// A glTF scene's camera by its name or its node's (`--camera`; default the first).
    pub camera: Option<String>,
}

/// A scene and what its file says about the render: a Mitsuba XML scene's film size and
/// sample count (the defaults of `--size` and `--frames`; none for RON scenes).
#[derive(Clone, Debug)]
pub struct LoadedScene {
    pub scene: Scene,
    pub film_size: Option<[u32; 2]>,
    pub sample_count: Option<u32>,
}

/// The largest `max_depth`: Mitsuba's is an `int`. It also stands for Mitsuba's -1, unbounded:
/// no path of 2^31 segments is ever traced.
pub const MAX_MAX_DEPTH: u32 = i32::MAX as u32;

/// A `max_depth` as written (scene file or command line): 1..=[`MAX_MAX_DEPTH`], or -1 for
/// unbounded (as Mitsuba), which is [`MAX_MAX_DEPTH`].
pub fn check_max_depth(depth: i64) -> Result<u32, String> {
    match u32::try_from(depth) {
        Ok(d) if (1..=MAX_MAX_DEPTH).contains(&d) => Ok(d),
        _ if depth == -1 => Ok(MAX_MAX_DEPTH),
        _ => Err(format!(
            "max_depth must be 1 (emitters seen directly) to {MAX_MAX_DEPTH}, or -1 for unbounded, found {depth}"
        )),
    }
}

/// An `rr_depth` as written: 1..=[`MAX_MAX_DEPTH`] (1: Russian roulette from the first BSDF
/// sample on).
pub fn check_rr_depth(depth: i64) -> Result<u32, String> {
    match u32::try_from(depth) {
        Ok(d) if (1..=MAX_MAX_DEPTH).contains(&d) => Ok(d),
        _ => Err(format!(
            "rr_depth must be 1 (Russian roulette from the first bounce on) to {MAX_MAX_DEPTH}, found {depth}"
        )),
    }
}

/// An unbounded depth needs Russian roulette to end its paths (in a closed scene nothing else
/// would).
pub fn check_depths(max_depth: u32, rr_depth: Option<u32>) -> Result<(), String> {
    if max_depth == MAX_MAX_DEPTH && rr_depth.is_none_or(|rr| rr >= MAX_MAX_DEPTH) {
        return Err(
            "max_depth -1 (unbounded) needs Russian roulette: give rr_depth (Mitsuba's default is 5)"
                .into(),
        );
    }
    Ok(())
}
