//! Several rounds of one benchmark, alternated with other renderers so that machine load hits
//! every contender alike, combined into one curve per variant: the **median** per checkpoint.
//!
//! With the same seed a round renders the same images, so a checkpoint's error is the same in
//! every round and only its time varies with the load. Every checkpoint (frame count, or
//! Mitsuba's sample count) any round reached is kept. A time budget ends a slower round one
//! doubling earlier; leaving it out of the last checkpoint would keep only the faster rounds
//! there, so it counts with its time extrapolated in proportion to the count from its own last
//! checkpoint (time per frame is steady within a run).

use super::metrics::ImageError;
use super::run::{Checkpoint, Run};
use std::path::Path;

/// The middle value; the mean of the two middle values of an even count.
pub fn median(mut v: Vec<f64>) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some(if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    })
}

/// The file `passgraph bench` writes beside its CSVs with every run it measured.
pub const RUNS_FILE: &str = "runs.ron";

pub fn write_runs(dir: &Path, runs: &[Run]) -> Result<(), String> {
    let text = ron::ser::to_string_pretty(runs, ron::ser::PrettyConfig::default())
        .map_err(|e| format!("runs: {e}"))?;
    crate::atomic_write::write_text(&dir.join(RUNS_FILE), &text)
}

pub fn read_runs(dir: &Path) -> Result<Vec<Run>, String> {
    let path = dir.join(RUNS_FILE);
    let text = std::fs::read_to_string(&path)
        .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    ron::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))
}

/// The median time at checkpoint `key` over rounds given as (count, seconds) in increasing
/// count; a round that stopped before `key` counts with its last time scaled by
/// `key / its last count`, a round that started after it does not count.
pub fn median_seconds(rounds: &[Vec<(u64, f64)>], key: u64) -> f64 {
    let times = rounds.iter().filter_map(|points| {
        let &(last_key, last_seconds) = points.last()?;
        match points.iter().find(|(k, _)| *k == key) {
            Some(&(_, seconds)) => Some(seconds),
            None if key > last_key && last_key > 0 => {
                Some(last_seconds * key as f64 / last_key as f64)
            }
            None => None,
        }
    });
    median(times.collect()).unwrap_or(f64::NAN)
}

/// Every key of every round, in increasing order.
pub fn all_keys(rounds: &[Vec<(u64, f64)>]) -> Vec<u64> {
    let keys: std::collections::BTreeSet<u64> = rounds.iter().flatten().map(|(k, _)| *k).collect();
    keys.into_iter().collect()
}

/// One run per label (in the order of first appearance) from the runs of every round.
pub fn combine(rounds: &[Vec<Run>]) -> Vec<Run> {
    let mut labels: Vec<&str> = Vec::new();
    for run in rounds.iter().flatten() {
        if !labels.contains(&run.label.as_str()) {
            labels.push(&run.label);
        }
    }
    labels
        .into_iter()
        .map(|label| {
            let same: Vec<&Run> = rounds
                .iter()
                .flatten()
                .filter(|r| r.label == label)
                .collect();
            combine_runs(&same)
        })
        .collect()
}

fn combine_runs(runs: &[&Run]) -> Run {
    let times: Vec<Vec<(u64, f64)>> = runs
        .iter()
        .map(|r| {
            r.checkpoints
                .iter()
                .map(|c| (u64::from(c.frames), c.seconds))
                .collect()
        })
        .collect();
    let checkpoints = all_keys(&times)
        .into_iter()
        .map(|f| {
            let at: Vec<&Checkpoint> = runs
                .iter()
                .filter_map(|r| r.checkpoints.iter().find(|c| u64::from(c.frames) == f))
                .collect();
            let m = |get: &dyn Fn(&Checkpoint) -> f64| {
                median(at.iter().map(|c| get(c)).collect()).unwrap_or(f64::NAN)
            };
            let passes = at
                .iter()
                .map(|c| c.pass_ms.as_ref().map_or(0, Vec::len))
                .min()
                .unwrap_or(0);
            Checkpoint {
                frames: f as u32,
                seconds: median_seconds(&times, f),
                error: ImageError {
                    rmse: m(&|c| c.error.rmse),
                    relmse: m(&|c| c.error.relmse),
                    bias: m(&|c| c.error.bias),
                    mse_standard_error: m(&|c| c.error.mse_standard_error),
                },
                pass_ms: (passes > 0).then(|| {
                    (0..passes)
                        .map(|i| m(&|c| c.pass_ms.as_ref().map_or(f64::NAN, |p| p[i])))
                        .collect()
                }),
            }
        })
        .collect();
    Run {
        label: runs[0].label.clone(),
        adapter: runs[0].adapter.clone(),
        pass_names: runs[0].pass_names.clone(),
        checkpoints,
        rays_per_frame: median(runs.iter().filter_map(|r| r.rays_per_frame).collect()),
        cpu_ms_per_frame: median(runs.iter().map(|r| r.cpu_ms_per_frame).collect()).unwrap_or(0.0),
        dropped: runs.iter().map(|r| r.dropped).max().unwrap_or(0),
        estimate: runs.iter().all(|r| r.estimate),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(label: &str, points: &[(u32, f64)]) -> Run {
        Run {
            label: label.into(),
            adapter: "llvmpipe (Vulkan) · llvmpipe, Mesa 25.0.7".into(),
            pass_names: vec!["a".into()],
            checkpoints: points
                .iter()
                .map(|&(frames, seconds)| Checkpoint {
                    frames,
                    seconds,
                    error: ImageError {
                        rmse: 0.1,
                        relmse: 1.0 / f64::from(frames),
                        bias: 0.0,
                        mse_standard_error: 0.0,
                    },
                    pass_ms: Some(vec![seconds * 1e3 / f64::from(frames)]),
                })
                .collect(),
            rays_per_frame: Some(4.0),
            cpu_ms_per_frame: seconds_of(points),
            dropped: 0,
            estimate: true,
        }
    }

    fn seconds_of(points: &[(u32, f64)]) -> f64 {
        points.last().map_or(0.0, |p| p.1)
    }

    #[test]
    fn medians_of_odd_and_even_counts() {
        assert_eq!(median(vec![3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(vec![4.0, 1.0]), Some(2.5));
        assert_eq!(median(vec![]), None);
    }

    #[test]
    fn checkpoints_take_the_median_time_of_every_round() {
        let rounds = vec![
            vec![
                run("a", &[(1, 1.0), (2, 2.0), (4, 4.0)]),
                run("b", &[(1, 5.0)]),
            ],
            vec![run("a", &[(1, 3.0), (2, 6.0)])],
            vec![run("a", &[(1, 2.0), (2, 4.0), (4, 8.0), (8, 16.0)])],
        ];
        let combined = combine(&rounds);
        assert_eq!(combined.len(), 2);
        let a = &combined[0];
        assert_eq!(a.label, "a");
        let points: Vec<(u32, f64)> = a
            .checkpoints
            .iter()
            .map(|c| (c.frames, c.seconds))
            .collect();
        // The second round stopped at 2 frames (6 s): at 4 frames it counts as 12 s, at 8 as 24;
        // the first round counts as 8 s at 8 frames.
        assert_eq!(points, [(1, 2.0), (2, 4.0), (4, 8.0), (8, 16.0)]);
        assert_eq!(a.checkpoints[2].error.relmse, 0.25);
        assert_eq!(a.checkpoints[0].pass_ms, Some(vec![2000.0]));
        assert_eq!(combined[1].checkpoints.len(), 1, "b ran once");
    }

    #[test]
    fn runs_survive_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let runs = vec![run("pathtracer:intersect.sampler=1", &[(1, 0.5), (2, 1.0)])];
        write_runs(dir.path(), &runs).unwrap();
        let back = read_runs(dir.path()).unwrap();
        assert_eq!(back[0].label, runs[0].label);
        assert_eq!(back[0].checkpoints, runs[0].checkpoints);
    }
}
