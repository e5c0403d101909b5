//! A camera path (`render --camera-path`): its segments rendered one after another.

use crate::output::say_line;
use passgraph::bench::metrics::image_error;
use passgraph::render::camera_path::Segment;
use passgraph::render::channels::ChannelSelection;
use passgraph::render::image::RgbImage;
use passgraph::render::session::Session;
use std::path::Path;

/// The error after one frame of a camera path segment that has a reference.
pub(crate) struct PathError {
    pub(crate) frame: u32,
    pub(crate) segment: usize,
    pub(crate) accumulated: u32,
    pub(crate) error: passgraph::bench::metrics::ImageError,
}

/// Segment `k` (from 1) of a camera path, and the frames of the segments before it. A segment
/// that keeps the previous one's camera continues its accumulation, so it cannot be rendered
/// alone.
pub(crate) fn one_segment<'a>(
    path: &Path,
    segments: &'a [Segment],
    k: u32,
) -> Result<(&'a Segment, u32), String> {
    let i = k as usize - 1;
    let Some(segment) = segments.get(i) else {
        return Err(format!(
            "{}: --segment {k}: the path has {} segments",
            path.display(),
            segments.len()
        ));
    };
    if i > 0 && segments[i - 1].camera == segment.camera {
        return Err(format!(
            "{}: --segment {k}: segment {k} keeps segment {i}'s camera, so it continues that accumulation and cannot be rendered alone (render from the segment that moves the camera)",
            path.display()
        ));
    }
    let before = segments[..i]
        .iter()
        .try_fold(0u32, |sum, s| sum.checked_add(s.frames))
        .ok_or_else(|| {
            format!(
                "{}: more than 2^32 frames before segment {k}",
                path.display()
            )
        })?;
    Ok((segment, before))
}

/// Renders each segment at its camera (a move restarts the accumulation; a reprojecting graph
/// keeps what it can) and measures `channel` after every frame of segments with a reference.
pub(crate) fn render_camera_path(
    session: &mut Session,
    segments: &[Segment],
    (first_segment, frames_before): (u32, u32),
    channel: &ChannelSelection,
) -> Result<Vec<PathError>, String> {
    // Every reference is read and checked before the first frame.
    let [w, h] = session.plan().output_size;
    let mut references = Vec::with_capacity(segments.len());
    for segment in segments {
        references.push(match &segment.reference {
            Some(path) => {
                let image = RgbImage::read_exr(path)?;
                if [image.width, image.height] != [w, h] {
                    return Err(format!(
                        "{}: the reference is {}x{} but --size is {w}x{h}",
                        path.display(),
                        image.width,
                        image.height
                    ));
                }
                Some((path, image))
            }
            None => None,
        });
    }
    let mut rows = Vec::new();
    let mut frame = frames_before;
    for (i, (segment, reference)) in segments.iter().zip(&references).enumerate() {
        let number = first_segment as usize + i;
        if segment.camera != session.scene_description().camera {
            session
                .set_camera(segment.camera)
                .map_err(|e| e.to_string())?;
        }
        for _ in 0..segment.frames {
            session.render_frame().map_err(|e| e.to_string())?;
            frame += 1;
            let Some((path, reference)) = &reference else {
                continue;
            };
            let image = session.image(channel).map_err(|e| e.to_string())?;
            let error =
                image_error(&image, reference).map_err(|e| format!("{}: {e}", path.display()))?;
            say_line(&format!(
                "frame {frame} (segment {number}, {} accumulated): RMSE {:.5}, relMSE {:.3e}",
                session.accumulated(),
                error.rmse,
                error.relmse
            ))?;
            rows.push(PathError {
                frame,
                segment: number,
                accumulated: session.accumulated(),
                error,
            });
        }
    }
    Ok(rows)
}
