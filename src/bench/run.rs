//! One speed-against-error run: render a graph, and at log-spaced frame counts measure the
//! error against a reference. Only rendering is timed: each checkpoint waits for the GPU, stops
//! the clock, then reads back and measures.

use super::metrics::{ImageError, image_error};
use crate::gpu::context::describe;
use crate::render::channels::ChannelSelection;
use crate::render::image::RgbImage;
use crate::render::session::{RenderError, RenderSettings, Session};
use std::time::{Duration, Instant};

/// When a run stops.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Budget {
    Frames(u32),
    Seconds(f64),
}

/// The error and cost after some frames.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Checkpoint {
    pub frames: u32,
    /// Wall time of rendering only (submission and GPU work), readbacks excluded.
    pub seconds: f64,
    pub error: ImageError,
    /// GPU milliseconds per kept pass in the latest frame (timestamp queries), if available.
    pub pass_ms: Option<Vec<f64>>,
}

#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Run {
    pub label: String,
    /// The adapter with its driver and version ([`crate::gpu::context::describe`]); empty in
    /// runs files written before it was recorded.
    #[serde(default)]
    pub adapter: String,
    pub pass_names: Vec<String>,
    pub checkpoints: Vec<Checkpoint>,
    /// Rays per frame as the passes counted them; `None` if no pass counts.
    pub rays_per_frame: Option<f64>,
    /// CPU milliseconds per frame to record and submit it (the GPU works meanwhile).
    pub cpu_ms_per_frame: f64,
    pub dropped: u32,
    /// Whether the compared image is the renderer's estimate of the scene's channels. A
    /// graph's output texture (a denoiser's) is not: the report shows it, but does not count it
    /// as passgraph's best in the race.
    #[serde(default = "estimate_by_default")]
    pub estimate: bool,
}

/// Runs files written before `estimate` was recorded count as estimates.
fn estimate_by_default() -> bool {
    true
}

impl Run {
    pub fn frames_per_second(&self) -> f64 {
        self.checkpoints
            .last()
            .map_or(0.0, |c| f64::from(c.frames) / c.seconds)
    }
}

/// Frame counts 1, 2, 4, ... : a checkpoint per doubling keeps readbacks to a log of the frames.
pub fn next_checkpoint(frames: u32) -> u32 {
    frames.max(1) * 2
}

/// Renders with `settings` until `budget`, measuring `channels` against `reference` at each
/// checkpoint.
pub fn run(
    label: &str,
    settings: &RenderSettings,
    channels: &ChannelSelection,
    reference: &RgbImage,
    budget: Budget,
) -> Result<Run, RenderError> {
    match budget {
        // Never reached: the run would not end.
        Budget::Seconds(s) if !(s.is_finite() && s > 0.0) => {
            return Err(RenderError::Other(format!(
                "a budget of {s} seconds is not a finite, positive time"
            )));
        }
        Budget::Frames(0) => {
            return Err(RenderError::Other(
                "a budget of 0 frames renders nothing".into(),
            ));
        }
        _ => {}
    }
    let mut session = Session::builder(settings).showing(channels).build()?;
    let pass_names = session
        .plan()
        .passes
        .iter()
        .map(|p| p.name.clone())
        .collect();
    let mut checkpoints = Vec::new();
    let mut rendering = Duration::ZERO;
    let mut submitting = Duration::ZERO;
    let mut frames = 0u32;
    let mut target = 1u32;
    loop {
        let start = Instant::now();
        while frames < target {
            let submit = Instant::now();
            let rendered = session.render_frame()?;
            submitting += submit.elapsed();
            if !rendered {
                break;
            }
            frames += 1;
        }
        session.wait()?;
        rendering += start.elapsed();
        let image = session.image(channels)?;
        let error = image_error(&image, reference).map_err(RenderError::Other)?;
        let pass_ms = session.last_frame_times().and_then(|t| t.passes);
        checkpoints.push(Checkpoint {
            frames,
            seconds: rendering.as_secs_f64(),
            error,
            pass_ms,
        });
        let done = match budget {
            Budget::Frames(n) => frames >= n,
            Budget::Seconds(s) => rendering.as_secs_f64() >= s,
        };
        if done || frames < target {
            break;
        }
        target = match budget {
            Budget::Frames(n) => next_checkpoint(frames).min(n),
            Budget::Seconds(_) => next_checkpoint(frames),
        };
    }
    let counted = session.rays_counted()?;
    Ok(Run {
        label: label.to_string(),
        adapter: describe(session.context().adapter_info()),
        pass_names,
        rays_per_frame: counted.map(|c| c as f64 / f64::from(frames.max(1))),
        cpu_ms_per_frame: submitting.as_secs_f64() * 1e3 / f64::from(frames.max(1)),
        dropped: session.dropped()?,
        checkpoints,
        estimate: matches!(channels, ChannelSelection::Planes(_)),
    })
}
