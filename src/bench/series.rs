//! Error-against-time curves, from passgraph runs or from Mitsuba's CSV, and reading them at
//! equal time or equal error.

use super::rounds::{all_keys, median, median_seconds};
use super::run::Run;
use std::path::Path;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    pub seconds: f64,
    pub rmse: f64,
    pub relmse: f64,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    pub label: String,
    /// In increasing time.
    pub points: Vec<Point>,
}

impl Series {
    pub fn from_run(run: &Run) -> Series {
        Series {
            label: run.label.clone(),
            points: run
                .checkpoints
                .iter()
                .map(|c| Point {
                    seconds: c.seconds,
                    rmse: c.error.rmse,
                    relmse: c.error.relmse,
                })
                .collect(),
        }
    }

    /// Reads `scripts/mitsuba-reference`'s CSV (columns spp, seconds, ..., rmse, relmse).
    pub fn from_mitsuba_csv(path: &Path, label: &str) -> Result<Series, String> {
        Series::from_mitsuba_csvs(&[path], label)
    }

    /// One curve from several rounds of `scripts/mitsuba-reference` (one CSV each): per sample
    /// count, the median time over the rounds (see `rounds`: a round that stopped at a lower
    /// count counts with its time extrapolated) and the median error over those that rendered it.
    pub fn from_mitsuba_csvs(paths: &[&Path], label: &str) -> Result<Series, String> {
        let rounds: Vec<Vec<(u64, Point)>> = paths
            .iter()
            .map(|p| read_mitsuba_csv(p))
            .collect::<Result<_, _>>()?;
        let times: Vec<Vec<(u64, f64)>> = rounds
            .iter()
            .map(|r| r.iter().map(|(k, p)| (*k, p.seconds)).collect())
            .collect();
        let mut points: Vec<Point> = all_keys(&times)
            .into_iter()
            .map(|k| {
                let at: Vec<&Point> = rounds
                    .iter()
                    .flatten()
                    .filter(|(key, _)| *key == k)
                    .map(|(_, p)| p)
                    .collect();
                let m = |get: fn(&Point) -> f64| {
                    median(at.iter().map(|p| get(p)).collect()).unwrap_or(f64::NAN)
                };
                Point {
                    seconds: median_seconds(&times, k),
                    rmse: m(|p| p.rmse),
                    relmse: m(|p| p.relmse),
                }
            })
            .collect();
        points.sort_by(|a, b| a.seconds.total_cmp(&b.seconds));
        Ok(Series {
            label: label.to_string(),
            points,
        })
    }

    /// relMSE at `seconds`, interpolated log-log between measured points; `None` outside them.
    pub fn relmse_at(&self, seconds: f64) -> Option<f64> {
        interpolate(self.points.iter().map(|p| (p.seconds, p.relmse)), seconds)
    }

    /// Time to reach `relmse`, interpolated log-log; `None` if never reached. Error falls with
    /// time only on average, so this takes the first crossing.
    pub fn seconds_to(&self, relmse: f64) -> Option<f64> {
        let first = self.points.first()?;
        if first.relmse <= relmse {
            return Some(first.seconds);
        }
        self.points.windows(2).find_map(|w| {
            (w[1].relmse <= relmse).then(|| {
                log_lerp(
                    (w[0].relmse, w[0].seconds),
                    (w[1].relmse, w[1].seconds),
                    relmse,
                )
            })
        })
    }
}

#[cfg(test)]
impl Series {
    /// A curve through (seconds, relMSE) points, for tests.
    pub(crate) fn of_relmse(label: &str, points: &[(f64, f64)]) -> Series {
        Series {
            label: label.into(),
            points: points
                .iter()
                .map(|&(seconds, relmse)| Point {
                    seconds,
                    rmse: relmse.sqrt(),
                    relmse,
                })
                .collect(),
        }
    }
}

/// The lowest relMSE that any of `series` reaches at `seconds` (each read as `relmse_at`), with
/// the curve that reaches it: the best of several configurations at each time. `None` if no
/// curve spans that time.
pub fn best_at<'a>(series: &[&'a Series], seconds: f64) -> Option<(f64, &'a Series)> {
    series
        .iter()
        .filter_map(|s| Some((s.relmse_at(seconds)?, *s)))
        .min_by(|a, b| a.0.total_cmp(&b.0))
}

/// The longest time a curve's point may have (11.6 days): beyond any benchmark.
const MAX_SECONDS: f64 = 1e6;
/// The largest error a point may have: beyond any image's.
const MAX_ERROR: f64 = 1e12;

/// The rows of one CSV, keyed by their sample count (the row number if there is no `spp`).
fn read_mitsuba_csv(path: &Path) -> Result<Vec<(u64, Point)>, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let position = |name: &str| header.iter().position(|h| *h == name);
    let column = |name: &str| {
        position(name).ok_or_else(|| {
            format!(
                "{}: no '{name}' column (run the script with --reference)",
                path.display()
            )
        })
    };
    let (s, r, q) = (column("seconds")?, column("rmse")?, column("relmse")?);
    let spp = position("spp");
    let mut rows = Vec::new();
    for (i, line) in lines.enumerate() {
        let cells: Vec<&str> = line.split(',').collect();
        // Every number is checked where it is read: an infinite or absurd time would send the
        // report's tables and chart after it without end.
        // `positive`: above 0, else from 0; at most `max`, so never infinite.
        let number = |k: usize, name: &str, positive: bool, max: f64, what: &str| {
            let cell = cells.get(k).map(|c| c.trim()).unwrap_or("");
            match cell.parse::<f64>() {
                Ok(v) if (if positive { v > 0.0 } else { v >= 0.0 }) && v <= max => Ok(v),
                _ => Err(format!(
                    "{}:{}: {name} is '{cell}'; it must be {what}",
                    path.display(),
                    i + 2
                )),
            }
        };
        let key = match spp {
            Some(k) => number(k, "spp", true, 1e15, "a positive number of samples")? as u64,
            None => i as u64,
        };
        rows.push((
            key,
            Point {
                seconds: number(
                    s,
                    "seconds",
                    true,
                    MAX_SECONDS,
                    "a positive number of seconds up to 1e6",
                )?,
                rmse: number(r, "rmse", false, MAX_ERROR, "an error from 0 to 1e12")?,
                relmse: number(q, "relmse", false, MAX_ERROR, "an error from 0 to 1e12")?,
            },
        ));
    }
    rows.sort_by_key(|(key, _)| *key);
    Ok(rows)
}

fn log_lerp(a: (f64, f64), b: (f64, f64), x: f64) -> f64 {
    let t = (x.ln() - a.0.ln()) / (b.0.ln() - a.0.ln());
    (a.1.ln() + t * (b.1.ln() - a.1.ln())).exp()
}

fn interpolate(points: impl Iterator<Item = (f64, f64)>, x: f64) -> Option<f64> {
    let points: Vec<(f64, f64)> = points.collect();
    if points.len() == 1 && points[0].0 == x {
        return Some(points[0].1);
    }
    points
        .windows(2)
        .find(|w| w[0].0 <= x && x <= w[1].0)
        .map(|w| log_lerp(w[0], w[1], x))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn series(points: &[(f64, f64)]) -> Series {
        Series::of_relmse("s", points)
    }

    #[test]
    fn a_one_over_time_curve_interpolates_exactly_in_log_log() {
        let s = series(&[(1.0, 1e-2), (100.0, 1e-4)]);
        assert!((s.relmse_at(10.0).unwrap() - 1e-3).abs() < 1e-12);
        assert!((s.seconds_to(1e-3).unwrap() - 10.0).abs() < 1e-9);
        assert_eq!(s.relmse_at(1000.0), None);
        assert_eq!(s.seconds_to(1e-5), None);
    }

    #[test]
    fn the_best_at_a_time_is_the_lowest_curve_there_among_those_spanning_it() {
        // Two curves crossing at 4 s, and one that ends early.
        let mut fast_start = series(&[(1.0, 1e-2), (16.0, 1e-3)]);
        fast_start.label = "fast start".into();
        let mut steep = series(&[(1.0, 4e-2), (16.0, 1e-4)]);
        steep.label = "steep".into();
        let mut short = series(&[(0.5, 3e-2), (1.0, 2e-2)]);
        short.label = "short".into();
        let all = [&fast_start, &steep, &short];
        let best =
            |t| best_at(&all, t).map(|(relmse, s)| (format!("{relmse:.3e}"), s.label.as_str()));
        assert_eq!(best(1.0), Some(("1.000e-2".into(), "fast start")));
        assert_eq!(best(16.0), Some(("1.000e-4".into(), "steep")));
        // Only the short curve spans 0.5 s; none spans 32 s.
        assert_eq!(best(0.5), Some(("3.000e-2".into(), "short")));
        assert_eq!(best(32.0), None);
        let (at_8, curve) = best_at(&all, 8.0).unwrap();
        assert_eq!(curve.label, "steep");
        assert!(at_8 < fast_start.relmse_at(8.0).unwrap());
    }

    #[test]
    fn mitsuba_csv_numbers_must_be_finite_and_in_range_naming_file_and_line() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("m.csv");
        for (row, expect) in [
            (
                "4,inf,0.1,0.01",
                "m.csv:3: seconds is 'inf'; it must be a positive number of seconds up to 1e6",
            ),
            ("4,1e300,0.1,0.01", "m.csv:3: seconds is '1e300'"),
            ("4,0,0.1,0.01", "m.csv:3: seconds is '0'"),
            (
                "4,2.0,NaN,0.01",
                "m.csv:3: rmse is 'NaN'; it must be an error from 0 to 1e12",
            ),
            ("4,2.0,0.1,-1", "m.csv:3: relmse is '-1'"),
            (
                "0,2.0,0.1,0.01",
                "m.csv:3: spp is '0'; it must be a positive number of samples",
            ),
        ] {
            std::fs::write(
                &path,
                format!("spp,seconds,rmse,relmse\n1,1.0,0.2,0.04\n{row}\n"),
            )
            .unwrap();
            let e = read_mitsuba_csv(&path).unwrap_err();
            assert!(e.ends_with(expect) || e.contains(expect), "{row}: {e}");
        }
    }

    #[test]
    fn mitsuba_csv_needs_error_columns() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("m.csv");
        std::fs::write(&path, "spp,seconds\n1,0.1\n").unwrap();
        let err = Series::from_mitsuba_csv(&path, "m").unwrap_err();
        assert!(err.contains("'rmse'"), "{err}");
        std::fs::write(
            &path,
            "spp,seconds,rmse,relmse\n4,0.4,0.1,0.02\n1,0.1,0.2,0.08\n",
        )
        .unwrap();
        let s = Series::from_mitsuba_csv(&path, "m").unwrap();
        assert_eq!(s.points[0].seconds, 0.1, "sorted by time");
    }

    #[test]
    fn mitsuba_rounds_combine_by_sample_count() {
        let dir = tempfile::tempdir().unwrap();
        let write = |name: &str, text: &str| {
            let path = dir.path().join(name);
            std::fs::write(&path, text).unwrap();
            path
        };
        let a = write(
            "a.csv",
            "spp,seconds,rmse,relmse\n1,0.1,0.2,0.08\n4,0.4,0.1,0.02\n",
        );
        let b = write("b.csv", "spp,seconds,rmse,relmse\n1,0.3,0.2,0.08\n");
        let c = write(
            "c.csv",
            "spp,seconds,rmse,relmse\n1,0.2,0.2,0.08\n4,0.6,0.1,0.02\n",
        );
        let s = Series::from_mitsuba_csvs(&[&a, &b, &c], "m").unwrap();
        let points: Vec<(f64, f64)> = s.points.iter().map(|p| (p.seconds, p.relmse)).collect();
        // b stopped at 1 spp (0.3 s): at 4 spp it counts as 1.2 s.
        assert_eq!(points, [(0.2, 0.08), (0.6, 0.02)]);
    }
}
