//! The RON schema of graph test files (`tests/graphs/*.ron`): cases, each a graph (a file, or
//! changes to one written inline in the composition syntax), a scene, a size, frames, seeds and
//! expectations.

use crate::graph::decl::{GraphDecl, plain_option};
use serde::Deserialize;

/// A graph test file.
#[derive(Clone, Debug, Deserialize)]
#[serde(rename = "GraphTests", deny_unknown_fields)]
pub struct TestFile {
    pub cases: Vec<CaseDecl>,
}

/// One test case. Paths are relative to the test file.
#[derive(Clone, Debug, Deserialize)]
#[serde(rename = "Case", deny_unknown_fields)]
pub struct CaseDecl {
    /// Unique within the file.
    pub name: String,
    /// The graph file under test...
    #[serde(default, deserialize_with = "plain_option")]
    pub graph: Option<String>,
    /// ...or a graph written here, usually `Graph(extends: "...", ...changes)`.
    #[serde(default, deserialize_with = "plain_option")]
    pub changes: Option<GraphDecl>,
    /// Needed when an expectation reads an image or a counter.
    #[serde(default, deserialize_with = "plain_option")]
    pub scene: Option<String>,
    #[serde(default = "default_size")]
    pub size: (u32, u32),
    /// Frames accumulated per seed.
    #[serde(default = "default_frames")]
    pub frames: u32,
    /// The first seed; the case renders `seeds` independent accumulations, seed, seed + 1, ...
    #[serde(default)]
    pub seed: u32,
    #[serde(default = "one")]
    pub seeds: u32,
    /// `INSTANCE.PARAM=VALUE` overrides, as `--set`.
    #[serde(default)]
    pub set: Vec<String>,
    /// The most pixel-samples (frames x seeds x pixels) the case may render: a guard against a
    /// mistyped `frames` that would run for days; a case that needs more raises it.
    #[serde(default = "default_max_samples")]
    pub max_samples: u64,
    pub expect: Vec<Expectation>,
}

/// 2^26 pixel-samples: 4 seeds of 1024 frames at 128x128, about a minute on lavapipe.
pub const DEFAULT_MAX_SAMPLES: u64 = 1 << 26;

fn default_max_samples() -> u64 {
    DEFAULT_MAX_SAMPLES
}

fn default_size() -> (u32, u32) {
    (32, 32)
}

fn default_frames() -> u32 {
    8
}

fn one() -> u32 {
    1
}

/// What a case asserts. Channels are as `--channel`: `sum`, `l0+direct+indirect`, or an output
/// texture such as `denoised`.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(rename = "Expectation", deny_unknown_fields)]
pub enum Expectation {
    /// The passes of each stage, in stage order (within a stage, in any order).
    Stages(Vec<Vec<String>>),
    /// Exactly these passes are culled.
    Culled(Vec<String>),
    /// The number of barriers between stages.
    Barriers(usize),
    /// A barrier on `resource` before stage `before_stage`.
    Barrier {
        before_stage: usize,
        resource: String,
    },
    /// The image mean over the seeds is within `within` standard errors (from the spread of
    /// the seeds' means; at least 2 seeds) plus `uncertainty` of the expected mean: `value`
    /// (RGB), or the mean of the EXR `reference` (of any size: a box-filtered image's mean does
    /// not depend on its resolution).
    Mean {
        channel: String,
        #[serde(default, deserialize_with = "plain_option")]
        value: Option<(f64, f64, f64)>,
        #[serde(default, deserialize_with = "plain_option")]
        reference: Option<String>,
        #[serde(default)]
        uncertainty: f64,
        within: f64,
    },
    /// RMSE against an EXR reference below `below` for every seed (a reference 2^k times the
    /// size is box-filtered down to it).
    Rmse {
        channel: String,
        reference: String,
        below: f64,
    },
    /// relMSE (mean of (x - y)^2 / (y^2 + 0.01)) against an EXR reference below `below`.
    RelMse {
        channel: String,
        reference: String,
        below: f64,
    },
    /// The graph's `dropped` counter is 0 for every seed.
    NoDroppedSamples,
    /// Every component of every pixel of the channel is finite, for every seed.
    AllFinite { channel: String },
}

impl Expectation {
    /// Whether checking it needs frames rendered (not only the plan).
    pub fn renders(&self) -> bool {
        !matches!(
            self,
            Expectation::Stages(_)
                | Expectation::Culled(_)
                | Expectation::Barriers(_)
                | Expectation::Barrier { .. }
        )
    }

    /// The channel it reads, if any.
    pub fn channel(&self) -> Option<&str> {
        match self {
            Expectation::Mean { channel, .. }
            | Expectation::Rmse { channel, .. }
            | Expectation::RelMse { channel, .. }
            | Expectation::AllFinite { channel } => Some(channel),
            _ => None,
        }
    }

    /// How a report names it.
    pub fn label(&self) -> String {
        match self {
            Expectation::Stages(_) => "Stages".into(),
            Expectation::Culled(_) => "Culled".into(),
            Expectation::Barriers(_) => "Barriers".into(),
            Expectation::Barrier {
                before_stage,
                resource,
            } => format!("Barrier({resource} before stage {before_stage})"),
            Expectation::Mean { channel, .. } => format!("Mean({channel})"),
            Expectation::Rmse { channel, .. } => format!("Rmse({channel})"),
            Expectation::RelMse { channel, .. } => format!("RelMse({channel})"),
            Expectation::NoDroppedSamples => "NoDroppedSamples".into(),
            Expectation::AllFinite { channel } => format!("AllFinite({channel})"),
        }
    }
}
