//! The options shared by several commands, and the parsers of option values.

use std::path::PathBuf;

/// Built-in defaults, so `cargo run --release` alone renders the Cornell box.
pub(crate) const DEFAULT_GRAPH: &str =
    concat!(env!("CARGO_MANIFEST_DIR"), "/graphs/pathtracer.ron");

pub(crate) const DEFAULT_SCENE: &str =
    concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/cornell/scene.ron");

#[derive(clap::Args)]
pub(crate) struct GraphArgs {
    /// The graph file, e.g. graphs/pathtracer.ron.
    pub(crate) graph: PathBuf,
    /// Output size the plan is made for, WxH.
    #[arg(long, default_value = "256x256", value_parser = parse_size)]
    pub(crate) size: [u32; 2],
}

/// The scene and what replaces parts of it: shared by `render`, `view` and `bench`.
#[derive(clap::Args)]
pub(crate) struct SceneArgs {
    /// The scene file: RON naming a mesh and a camera, or a Mitsuba 3 scene (.xml).
    #[arg(long = "scene", id = "scene", value_name = "SCENE", default_value = DEFAULT_SCENE)]
    pub(crate) path: PathBuf,
    /// A Mitsuba XML scene's parameter, as `mitsuba -D`: replaces its <default name="NAME">.
    #[arg(short = 'D', long = "define", value_name = "NAME=VALUE", value_parser = parse_define)]
    pub(crate) define: Vec<(String, String)>,
    /// A glTF scene's camera, by its name or its node's (default: the first).
    #[arg(long, value_name = "NAME")]
    pub(crate) camera: Option<String>,
    /// Longest path in segments, as Mitsuba's max_depth (replaces the scene file's; default 3).
    #[arg(long, value_parser = parse_max_depth)]
    pub(crate) max_depth: Option<u32>,
}

#[derive(clap::Args)]
pub(crate) struct ViewArgs {
    #[arg(long, default_value = DEFAULT_GRAPH)]
    pub(crate) graph: PathBuf,
    #[command(flatten)]
    pub(crate) scene: SceneArgs,
    /// Image size, WxH; the window starts at twice this.
    #[arg(long, default_value = "256x256", value_parser = parse_size)]
    pub(crate) size: [u32; 2],
    #[arg(long, default_value_t = 0)]
    pub(crate) seed: u32,
    /// Override a graph param: INSTANCE.PARAM=VALUE, or PARAM=VALUE on every pass that has it
    /// (repeatable).
    #[arg(long = "set")]
    pub(crate) set: Vec<String>,
    #[arg(long)]
    pub(crate) adapter: Option<String>,
    /// Scripted input, one event per line: wait N, key K, hold K N, drag DX DY, scroll N, screenshot PATH.png, quit.
    #[arg(long)]
    pub(crate) script: Option<PathBuf>,
    /// Quit after this many frames.
    #[arg(long)]
    pub(crate) frames: Option<u32>,
}

/// A positive frame count: zero frames would write a black image (or, for bench, render one).
/// Seconds between checkpoints: finite and not negative (0: after every frame).
pub(crate) fn parse_interval(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && (0.0..=1e9).contains(&v) => Ok(v),
        _ => Err(format!(
            "'{s}' is not a number of seconds from 0 to 1e9 (0: a checkpoint after every frame)"
        )),
    }
}

pub(crate) fn parse_frames(s: &str) -> Result<u32, String> {
    match s.trim().parse::<u32>() {
        Ok(n) if n > 0 => Ok(n),
        _ => Err(format!("'{s}' is not a positive number of frames")),
    }
}

/// A path length of at least one segment (Mitsuba's max_depth).
pub(crate) fn parse_max_depth(s: &str) -> Result<u32, String> {
    let depth: i64 = s
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not a whole number"))?;
    passgraph::scene::check_max_depth(depth)
}

/// A finite, positive time budget: NaN or infinity would never be reached.
pub(crate) fn parse_seconds(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(t) if t.is_finite() && t > 0.0 => Ok(t),
        _ => Err(format!("'{s}' is not a finite, positive number of seconds")),
    }
}

/// `NAME=VALUE` (a Mitsuba XML define).
pub(crate) fn parse_define(s: &str) -> Result<(String, String), String> {
    let (name, value) = s
        .split_once('=')
        .ok_or_else(|| format!("'{s}' is not NAME=VALUE"))?;
    if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
        return Err(format!(
            "'{name}' is not a parameter name (letters, digits, _)"
        ));
    }
    Ok((name.to_string(), value.to_string()))
}

pub(crate) fn parse_size(s: &str) -> Result<[u32; 2], String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("'{s}' is not WxH"))?;
    let dim = |v: &str| match v.trim().parse::<u32>() {
        Ok(n) if n > 0 => Ok(n),
        _ => Err(format!("'{v}' in '{s}' is not a positive integer")),
    };
    Ok([dim(w)?, dim(h)?])
}
