//! Checkpoints: a long render writes its accumulation so far as a partial file
//! (`render --checkpoint CKPT.exr`), at an interval, when a signal asks it to stop (SIGTERM
//! from a farm's preemption, SIGINT, SIGHUP) and when done; `render --resume CKPT.exr`
//! continues from it, bit for bit the render that was never stopped (the compensated means and
//! counts are restored as they were, and the sampler goes on at the next sample index:
//! [`Session::resume_from`]). A checkpoint is an ordinary partial file (src/render/partial.rs),
//! so it also merges with partials of the ranges after it.
//!
//! A checkpoint is written whole or not at all (temporary file, then rename): a process killed
//! while writing one, even by SIGKILL, leaves the previous checkpoint as it was.

use super::fingerprint::Fingerprint;
use super::partial::{Packing, Partial, SampleRange};
use super::session::Session;
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

    /// Writes the accumulation of `session` as samples `start..start + accumulated`; returns
    /// them.
    pub fn write(
        &mut self,
        session: &Session,
        start: u32,
        fingerprint: &Fingerprint,
        source: &str,
    ) -> Result<SampleRange, String> {
        let began = Instant::now();
        let partial = accumulation(session, start, fingerprint, source)
            .map_err(|e| format!("{}: {e}", self.path.display()))?;
        partial.write(&self.path, Packing::Fast)?;
        self.last = Instant::now();
        self.costs.push(began.elapsed());
        Ok(partial.samples)
    }

    /// The median cost of a checkpoint so far.
    pub fn median_cost(&self) -> Option<Duration> {
        let mut costs = self.costs.clone();
        costs.sort();
        costs.get(costs.len() / 2).copied()
    }
}

/// The accumulation of `session` so far as a partial file of samples `start..start + n`.
pub fn accumulation(
    session: &Session,
    start: u32,
    fingerprint: &Fingerprint,
    source: &str,
) -> Result<Partial, String> {
    let samples = SampleRange {
        start,
        end: start + session.accumulated(),
    };
    if samples.is_empty() {
        return Err("no frame is rendered yet: nothing to write".into());
    }
    Partial::from_buffers(
        session.tile().image,
        samples,
        u64::from(session.dropped().map_err(|e| e.to_string())?),
        fingerprint.clone(),
        source.to_string(),
        &session.result().map_err(|e| e.to_string())?,
        &session.compensation().map_err(|e| e.to_string())?,
    )
}

/// Reads a checkpoint for the render `session` is about to do (samples `start..end`, with
/// `fingerprint`) and restores it into the session; returns the samples it held. Every error
/// names the file and says what differs.
pub fn resume(
    path: &Path,
    session: &mut Session,
    fingerprint: &Fingerprint,
    end: u32,
) -> Result<SampleRange, String> {
    let partial = Partial::read(path)?;
    let differences = partial.fingerprint.differences(fingerprint);
    if !differences.is_empty() {
        return Err(format!(
            "{}: the checkpoint is of another render: {} differ",
            path.display(),
            differences.join(", ")
        ));
    }
    if partial.samples.end > end {
        return Err(format!(
            "{}: the checkpoint holds samples {}, past this render's last ({}): give --frames {} or more",
            path.display(),
            partial.samples,
            end - 1,
            partial.samples.end
        ));
    }
    session
        .resume_from(&partial)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(partial.samples)
}
