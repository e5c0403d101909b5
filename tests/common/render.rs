//! Test support: sessions of the shipped graphs and scenes on the GPU (lavapipe in CI).

use passgraph::render::channels::ChannelSelection;
use passgraph::render::image::RgbImage;
use passgraph::render::session::{RenderSettings, Session};
use std::path::Path;

pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// A square render of `scene` with `graph` (both relative to the repository).
pub fn settings(graph: &str, scene: &str, size: u32, seed: u32, set: &[&str]) -> RenderSettings {
    RenderSettings {
        graph: root().join(graph),
        scene: root().join(scene),
        size: [size, size],
        seed,
        set: set.iter().map(|s| s.to_string()).collect(),
        adapter: None,
        max_frames: RenderSettings::DEFAULT_MAX_FRAMES,
    }
}

/// A session after `frames` frames.
pub fn render(s: &RenderSettings, frames: u32) -> Session {
    let mut session = Session::new(s).unwrap_or_else(|e| panic!("session: {e}"));
    for _ in 0..frames {
        assert!(session.render_frame().unwrap());
    }
    session
}

/// One channel selection (e.g. `l0+direct+indirect`, `denoised`) as an image.
pub fn image(session: &Session, channel: &str) -> RgbImage {
    session
        .image(&channel.parse::<ChannelSelection>().unwrap())
        .unwrap_or_else(|e| panic!("{channel}: {e}"))
}
