//! Checking one expectation of a graph test against what a case measured: the plan, and per
//! seed the images of the channels read and the dropped-sample count. A failure says what was
//! measured.

use super::decl::Expectation;
use crate::bench::metrics::image_error;
use crate::graph::plan::Plan;
use crate::render::image::RgbImage;
use std::collections::{BTreeMap, BTreeSet};

/// One seed's accumulation.
pub struct SeedMeasure {
    pub seed: u32,
    /// By channel as written in the test.
    pub images: BTreeMap<String, RgbImage>,
    /// The `dropped` counter, or why it could not be read.
    pub dropped: Option<Result<u32, String>>,
}

pub struct Measured<'a> {
    pub plan: &'a Plan,
    pub seeds: &'a [SeedMeasure],
    /// By path as written in the test, at the case's size (Mean reads only their means).
    pub references: &'a BTreeMap<String, RgbImage>,
}

const RGB: [&str; 3] = ["r", "g", "b"];

/// Whether an expectation held, and what was measured against what was expected.
#[derive(Clone, Debug, PartialEq)]
pub struct Verdict {
    pub passed: bool,
    pub report: String,
}

fn verdict(passed: bool, report: String) -> Verdict {
    Verdict { passed, report }
}

/// Checks one expectation.
pub fn check(expectation: &Expectation, m: &Measured) -> Verdict {
    match expectation {
        Expectation::Stages(expected) => {
            let measured = m.plan.stage_names();
            let sorted = |stages: Vec<Vec<&str>>| -> Vec<BTreeSet<String>> {
                stages
                    .into_iter()
                    .map(|s| s.into_iter().map(str::to_string).collect())
                    .collect()
            };
            let wanted: Vec<Vec<&str>> = expected
                .iter()
                .map(|s| s.iter().map(String::as_str).collect())
                .collect();
            verdict(
                sorted(measured.clone()) == sorted(wanted.clone()),
                format!(
                    "measured stages {}, expected {}",
                    stages_text(&measured),
                    stages_text(&wanted)
                ),
            )
        }
        Expectation::Culled(expected) => {
            let measured: BTreeSet<&str> = m.plan.culled.iter().map(|c| c.name.as_str()).collect();
            let wanted: BTreeSet<&str> = expected.iter().map(String::as_str).collect();
            verdict(
                measured == wanted,
                format!(
                    "measured culled [{}], expected [{}]",
                    join(measured.iter().copied()),
                    join(wanted.iter().copied())
                ),
            )
        }
        Expectation::Barriers(n) => verdict(
            m.plan.barriers.len() == *n,
            format!(
                "measured {} barriers ({}), expected {n}",
                m.plan.barriers.len(),
                barriers_text(m.plan)
            ),
        ),
        Expectation::Barrier {
            before_stage,
            resource,
        } => {
            let found = m.plan.barriers.iter().any(|b| {
                b.before_stage.0 == *before_stage && m.plan.resources[b.resource].name == *resource
            });
            verdict(
                found,
                format!(
                    "measured barriers: {}; expected one on '{resource}' before stage {before_stage}",
                    barriers_text(m.plan)
                ),
            )
        }
        Expectation::Mean {
            channel,
            value,
            reference,
            uncertainty,
            within,
        } => {
            let expected = match (value, reference) {
                (Some((r, g, b)), _) => [*r, *g, *b],
                (None, Some(path)) => m.references[path].mean(),
                (None, None) => unreachable!("validated when the file was read"),
            };
            let means: Vec<[f64; 3]> = m.seeds.iter().map(|s| s.images[channel].mean()).collect();
            let n = means.len() as f64;
            let mut passed = true;
            let mut parts = Vec::new();
            for k in 0..3 {
                let mean = means.iter().map(|v| v[k]).sum::<f64>() / n;
                let variance = means.iter().map(|v| (v[k] - mean).powi(2)).sum::<f64>() / (n - 1.0);
                let se = (variance / n).sqrt();
                let off = (mean - expected[k]).abs();
                let allowed = within * se + uncertainty;
                // `off <= allowed` is false for a NaN mean too.
                passed &= off <= allowed;
                parts.push(format!(
                    "{}: measured {mean:.6} ± {se:.2e} (standard error over {n} seeds), expected {:.6} ± {uncertainty:.1e}, off by {:.1} standard errors (allowed {within})",
                    RGB[k],
                    expected[k],
                    off / se
                ));
            }
            verdict(passed, parts.join(", "))
        }
        Expectation::Rmse {
            channel,
            reference,
            below,
        }
        | Expectation::RelMse {
            channel,
            reference,
            below,
        } => {
            let rel = matches!(expectation, Expectation::RelMse { .. });
            let what = if rel { "relMSE" } else { "RMSE" };
            let mut values = Vec::new();
            for s in m.seeds {
                let e = match image_error(&s.images[channel], &m.references[reference]) {
                    Ok(e) => e,
                    Err(message) => return verdict(false, message),
                };
                values.push((if rel { e.relmse } else { e.rmse }, s.seed));
            }
            let n = values.len() as f64;
            let mean = values.iter().map(|v| v.0).sum::<f64>() / n;
            let sd = (values.iter().map(|v| (v.0 - mean).powi(2)).sum::<f64>()
                / (n - 1.0).max(1.0))
            .sqrt();
            // The worst seed decides; a NaN counts as worst.
            let (worst, seed) =
                values
                    .iter()
                    .copied()
                    .fold((f64::NEG_INFINITY, 0), |(w, ws), (v, s)| {
                        if v > w || v.is_nan() { (v, s) } else { (w, ws) }
                    });
            let spread = if values.len() > 1 {
                format!(" (mean {mean:.4e}, standard deviation {sd:.2e} over {n} seeds)")
            } else {
                String::new()
            };
            verdict(
                worst < *below && values.iter().all(|v| !v.0.is_nan()),
                format!(
                    "measured {what} {worst:.4e} (seed {seed}){spread} against {reference}, expected below {below:.4e}"
                ),
            )
        }
        Expectation::NoDroppedSamples => {
            let mut total = 0u64;
            for s in m.seeds {
                match &s.dropped {
                    Some(Ok(n)) => total += u64::from(*n),
                    Some(Err(e)) => return verdict(false, format!("cannot read 'dropped': {e}")),
                    None => unreachable!("read for every seed when expected"),
                }
            }
            verdict(
                total == 0,
                format!(
                    "measured {total} dropped samples over {} seeds, expected 0",
                    m.seeds.len()
                ),
            )
        }
        Expectation::AllFinite { channel } => {
            for s in m.seeds {
                let image = &s.images[channel];
                let bad: Vec<usize> = image
                    .pixels
                    .iter()
                    .enumerate()
                    .filter(|(_, p)| p.iter().any(|v| !v.is_finite()))
                    .map(|(i, _)| i)
                    .collect();
                if let Some(&first) = bad.first() {
                    let w = image.width as usize;
                    return verdict(
                        false,
                        format!(
                            "measured {} of {} pixels not finite (seed {}; first at x {}, y {}: {:?})",
                            bad.len(),
                            image.pixels.len(),
                            s.seed,
                            first % w,
                            first / w,
                            image.pixels[first]
                        ),
                    );
                }
            }
            verdict(
                true,
                format!("measured every pixel finite over {} seeds", m.seeds.len()),
            )
        }
    }
}

fn join<'a>(names: impl IntoIterator<Item = &'a str>) -> String {
    names.into_iter().collect::<Vec<_>>().join(", ")
}

fn stages_text(stages: &[Vec<&str>]) -> String {
    let parts: Vec<String> = stages.iter().map(|s| s.join(", ")).collect();
    format!("[{}]", parts.join(" | "))
}

fn barriers_text(plan: &Plan) -> String {
    if plan.barriers.is_empty() {
        return "none".into();
    }
    let parts: Vec<String> = plan
        .barriers
        .iter()
        .map(|b| {
            format!(
                "{} before stage {}",
                plan.resources[b.resource].name, b.before_stage
            )
        })
        .collect();
    parts.join(", ")
}
