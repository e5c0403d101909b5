//! Checkpoints: a long render writes its accumulation so far as a partial file
//! (`render --checkpoint CKPT.exr`), at an interval, when a signal asks it to stop (SIGTERM
//! from a farm's preemption, SIGINT, SIGHUP) and when done; `render --resume CKPT.exr`
//! continues from it, bit for bit the render that was never stopped (the compensated means and
//! counts are restored as they were, and the sampler goes on at the next sample index:
//! `Session::restore`). A checkpoint is an ordinary partial file (src/render/partial.rs),
//! so it also merges with partials of the ranges after it.
//!
//! A render in tiles (src/render/tiles.rs) takes one tile after another: its checkpoint holds
//! the finished tiles and the current one's frames so far (the partial's `tiles` line says how
//! far it got), and its resume renders from there, in tiles of the same size. Such a
//! checkpoint is for resuming only: until the last tile is done it is not a merge's input.
//!
//! A checkpoint is written whole or not at all (temporary file, then rename): a process killed
//! while writing one, even by SIGKILL, leaves the previous checkpoint as it was.

use super::fingerprint::Fingerprint;
use super::partial::{Packing, Partial};
use super::tiles::ImageRender;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Where and how often a render writes its checkpoint, and what writing them has cost.
pub struct Checkpoints {
    pub path: PathBuf,
    every: Duration,
    last: Instant,
    /// Time spent writing checkpoints (read back, encode, write, rename), one entry each.
    pub costs: Vec<Duration>,
}

impl Checkpoints {
    /// Checkpoints to `path` every `every`, counted from now.
    pub fn new(path: PathBuf, every: Duration) -> Checkpoints {
        Checkpoints {
            path,
            every,
            last: Instant::now(),
            costs: Vec::new(),
        }
    }

    /// Whether the interval has passed since the last checkpoint (or the start).
    pub fn due(&self) -> bool {
        self.last.elapsed() >= self.every
    }

    /// Writes the accumulation of `render` so far, of samples from `start` on; returns what
    /// it holds, for a log line ([`Partial::holds`]).
    pub fn write(
        &mut self,
        render: &ImageRender,
        start: u32,
        fingerprint: &Fingerprint,
        source: &str,
    ) -> Result<String, String> {
        let began = Instant::now();
        let partial = render
            .accumulation(start, fingerprint, source)
            .map_err(|e| format!("{}: {e}", self.path.display()))?;
        partial.write(&self.path, Packing::Fast)?;
        self.last = Instant::now();
        self.costs.push(began.elapsed());
        Ok(partial.holds())
    }

    /// The median cost of a checkpoint so far.
    pub fn median_cost(&self) -> Option<Duration> {
        let mut costs = self.costs.clone();
        costs.sort();
        costs.get(costs.len() / 2).copied()
    }
}

/// Restores `checkpoint` (read from `path`) into the render about to do samples
/// `start..end` with `fingerprint`; returns what it held ([`Partial::holds`]). Every error
/// names the file and says what differs.
pub fn resume(
    path: &Path,
    checkpoint: &Partial,
    render: &mut ImageRender,
    fingerprint: &Fingerprint,
    end: u32,
) -> Result<String, String> {
    let differences = checkpoint.fingerprint.differences(fingerprint);
    if !differences.is_empty() {
        return Err(format!(
            "{}: the checkpoint is of another render: {} differ",
            path.display(),
            differences.join(", ")
        ));
    }
    if checkpoint.samples.end > end {
        return Err(format!(
            "{}: the checkpoint holds samples {}, past this render's last ({}): give --frames {} or more",
            path.display(),
            checkpoint.samples,
            end - 1,
            checkpoint.samples.end
        ));
    }
    render
        .resume_from(checkpoint)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(checkpoint.holds())
}
