//! Sessions of graphs and scenes on the GPU (lavapipe in CI), and checks on their images.

// Also importable from here, as render tests have done.
pub use super::root;
use passgraph::render::channels::ChannelSelection;
use passgraph::render::image::RgbImage;
use passgraph::render::session::{RenderSettings, Session};
use std::path::Path;

/// The shipped path tracer graph, relative to the repository.
pub const PATHTRACER: &str = "graphs/pathtracer.ron";

/// A square render of `scene` with `graph` (relative to the repository, or absolute).
pub fn settings(
    graph: impl AsRef<Path>,
    scene: impl AsRef<Path>,
    size: u32,
    seed: u32,
    set: &[&str],
) -> RenderSettings {
    RenderSettings {
        size: [size, size],
        seed,
        set: set.iter().map(|s| s.to_string()).collect(),
        ..RenderSettings::new(root().join(graph), root().join(scene))
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

/// `frames` frames of `scene` with the path tracer graph.
pub fn render_scene(scene: &Path, size: u32, seed: u32, frames: u32) -> Session {
    render(&settings(PATHTRACER, scene, size, seed, &[]), frames)
}

/// One channel selection (e.g. `l0+direct+indirect`, `denoised`) as an image.
pub fn image(session: &Session, channel: &str) -> RgbImage {
    session
        .image(&channel.parse::<ChannelSelection>().unwrap())
        .unwrap_or_else(|e| panic!("{channel}: {e}"))
}

/// Asserts every value of the result buffer is finite, every pixel has `frames` samples and
/// nothing was dropped.
pub fn assert_clean(session: &Session, frames: u32, what: &str) {
    let result = session.result().unwrap();
    assert!(
        result.iter().flatten().all(|v| v.is_finite()),
        "{what}: non-finite value in the result"
    );
    assert!(
        result.iter().all(|p| p[3] == frames as f32),
        "{what}: a pixel lost samples"
    );
    assert_eq!(session.dropped().unwrap(), 0, "{what}: dropped samples");
}

/// Mean over pixels and components.
pub fn mean(img: &RgbImage) -> f64 {
    let m = img.mean();
    (m[0] + m[1] + m[2]) / 3.0
}

/// How many pixels of two images of one size differ in any bit.
pub fn differing_pixels(a: &RgbImage, b: &RgbImage) -> usize {
    assert_eq!(a.pixels.len(), b.pixels.len(), "images of different sizes");
    a.pixels
        .iter()
        .zip(&b.pixels)
        .filter(|(x, y)| x.map(f32::to_bits) != y.map(f32::to_bits))
        .count()
}

/// The largest difference between two images, relative to the larger of 1 and the pixel.
pub fn max_relative_difference(a: &RgbImage, b: &RgbImage) -> f32 {
    a.pixels
        .iter()
        .flatten()
        .zip(b.pixels.iter().flatten())
        .map(|(&x, &y)| (x - y).abs() / x.abs().max(y.abs()).max(1.0))
        .fold(0.0, f32::max)
}
