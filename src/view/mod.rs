//! `passgraph view`: a window showing a graph's image as it accumulates, with a fly camera,
//! channel keys, screenshots, hot reload of the graph's files and scripted input for tests.

pub mod camera_control;
pub mod channel_list;
pub mod frame_clock;
pub mod keys;
pub mod present;
pub mod reload;
pub mod script;
mod window;

use crate::render::session::RenderSettings;
use std::path::PathBuf;

/// What `passgraph view` was asked for.
#[derive(Clone, Debug)]
pub struct ViewOptions {
    pub settings: RenderSettings,
    /// The window shows each image pixel as this many screen pixels at first.
    pub window_scale: u32,
    /// Scripted input (see [`script`]).
    pub script: Option<PathBuf>,
    /// Quit after presenting this many frames.
    pub frames: Option<u32>,
}

/// Opens the window and runs until Esc, the script's `quit`, `frames`, or an error.
pub fn run(options: ViewOptions) -> Result<(), String> {
    window::run(options)
}
