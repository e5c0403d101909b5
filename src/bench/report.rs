//! Bench outputs: a CSV per run and a markdown report (equal time, equal error, per pass).

use super::rounds::median;
use super::run::Run;
use super::series::{Series, best_at};
use std::fmt::Write;

pub fn run_csv(run: &Run) -> String {
    let mut out = String::from("frames,seconds,rmse,relmse,bias");
    for name in &run.pass_names {
        let _ = write!(out, ",gpu_ms_{name}");
    }
    out.push('\n');
    for c in &run.checkpoints {
        let _ = write!(
            out,
            "{},{:.6},{:.6e},{:.6e},{:.6e}",
            c.frames, c.seconds, c.error.rmse, c.error.relmse, c.error.bias
        );
        for i in 0..run.pass_names.len() {
            match c.pass_ms.as_ref().and_then(|ms| ms.get(i)) {
                Some(ms) => {
                    let _ = write!(out, ",{ms:.4}");
                }
                None => out.push(','),
            }
        }
        out.push('\n');
    }
    out
}

fn cell(v: Option<f64>, format: impl Fn(f64) -> String) -> String {
    v.map_or("–".to_string(), format)
}

/// Seconds at which the report compares relMSE.
pub const EQUAL_TIMES: [f64; 6] = [0.5, 1.0, 2.0, 4.0, 8.0, 16.0];
/// relMSE levels whose time to reach the report compares (the multijitter reference's own
/// noise, relMSE ~2e-6, stays below the last).
pub const EQUAL_ERRORS: [f64; 7] = [1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5];

/// The markdown report: a summary per run, relMSE at equal times, the race against the extra
/// series (such as Mitsuba's samplers; see `race`), times to equal errors (passgraph runs and
/// the extra series), and GPU milliseconds per pass.
pub fn markdown(runs: &[Run], extra: &[Series]) -> String {
    let mut out = String::new();
    // Speed depends on the driver as much as on the graph (Mesa 25's lavapipe is ~25 % faster
    // than 22.3's), so the report names it.
    let mut adapters: Vec<&str> = Vec::new();
    for r in runs {
        if !r.adapter.is_empty() && !adapters.contains(&r.adapter.as_str()) {
            adapters.push(&r.adapter);
        }
    }
    if !adapters.is_empty() {
        let _ = writeln!(out, "Adapter: {}\n", adapters.join("; "));
    }
    let all: Vec<Series> = runs
        .iter()
        .map(Series::from_run)
        .chain(extra.iter().cloned())
        .collect();
    out.push_str("| variant | frames | seconds | frames/s | CPU ms/frame | Mrays/s (counted) | RMSE | relMSE |\n|---|---|---|---|---|---|---|---|\n");
    for r in runs {
        if let Some(c) = r.checkpoints.last() {
            let fps = r.frames_per_second();
            let _ = writeln!(
                out,
                "| {} | {} | {:.2} | {:.1} | {:.2} | {} | {:.4} | {:.2e} |",
                r.label,
                c.frames,
                c.seconds,
                fps,
                r.cpu_ms_per_frame,
                cell(r.rays_per_frame, |rays| format!("{:.2}", rays * fps / 1e6)),
                c.error.rmse,
                c.error.relmse
            );
        }
    }
    for s in extra {
        if let Some(p) = s.points.last() {
            let _ = writeln!(
                out,
                "| {} | – | {:.2} | – | – | – | {:.4} | {:.2e} |",
                s.label, p.seconds, p.rmse, p.relmse
            );
        }
    }

    let times = EQUAL_TIMES;
    out.push_str(
        "\nrelMSE at equal time (log-log interpolation between checkpoints):\n\n| variant |",
    );
    for t in times {
        let _ = write!(out, " {t} s |");
    }
    out.push_str("\n|---|");
    out.push_str(&"---|".repeat(times.len()));
    out.push('\n');
    for s in &all {
        let _ = write!(out, "| {} |", s.label);
        for t in times {
            let _ = write!(out, " {} |", cell(s.relmse_at(t), |v| format!("{v:.2e}")));
        }
        out.push('\n');
    }

    if !extra.is_empty() {
        race(&mut out, runs, extra);
    }

    let errors = EQUAL_ERRORS;
    out.push_str("\nSeconds to reach a relMSE:\n\n| variant |");
    for e in errors {
        let _ = write!(out, " {e:.1e} |");
    }
    out.push_str("\n|---|");
    out.push_str(&"---|".repeat(errors.len()));
    out.push('\n');
    for s in &all {
        let _ = write!(out, "| {} |", s.label);
        for e in errors {
            let _ = write!(out, " {} |", cell(s.seconds_to(e), |v| format!("{v:.2}")));
        }
        out.push('\n');
    }

    out.push_str("\nGPU milliseconds per pass (timestamp queries; median over checkpoints):\n\n");
    for r in runs {
        let _ = writeln!(out, "- {}:", r.label);
        for (i, name) in r.pass_names.iter().enumerate() {
            let ms = median(
                r.checkpoints
                    .iter()
                    .filter_map(|c| c.pass_ms.as_ref()?.get(i).copied())
                    .collect(),
            );
            let _ = writeln!(out, "  - {name}: {}", cell(ms, |v| format!("{v:.2} ms")));
        }
    }
    out
}

/// The race at equal times: passgraph's best estimate against the best extra series (Mitsuba's
/// configurations, from `bench --mitsuba`), each the lowest relMSE at that time (so a
/// configuration that is best early and another that is best late both count), then every run
/// against that best. Runs that compare something other than the renderer's estimate (a
/// denoiser's output) are in the second table only.
fn race(out: &mut String, runs: &[Run], extra: &[Series]) {
    let times = EQUAL_TIMES;
    let header = |out: &mut String| {
        for t in times {
            let _ = write!(out, " {t} s |");
        }
        out.push_str("\n|---|");
        out.push_str(&"---|".repeat(times.len()));
        out.push('\n');
    };
    let ours: Vec<Series> = runs
        .iter()
        .filter(|r| r.estimate)
        .map(Series::from_run)
        .collect();
    let ours: Vec<&Series> = ours.iter().collect();
    let theirs: Vec<&Series> = extra.iter().collect();
    out.push_str(
        "\nThe race at equal time: the lowest relMSE of passgraph's variants (estimates only) and \
         of Mitsuba's curves at each time, and whose it is:\n\n| |",
    );
    header(out);
    for (name, curves) in [("passgraph, best", &ours), ("Mitsuba, best", &theirs)] {
        let _ = write!(out, "| {name} |");
        for t in times {
            let best = best_at(curves, t);
            let _ = write!(
                out,
                " {} |",
                cell(best.map(|b| b.0), |v| format!(
                    "{v:.2e} ({})",
                    best.map_or("", |b| b.1.label.as_str())
                ))
            );
        }
        out.push('\n');
    }
    out.push_str("| ratio (below 1: passgraph ahead) |");
    for t in times {
        let ratio = best_at(&ours, t)
            .zip(best_at(&theirs, t))
            .map(|(a, b)| a.0 / b.0);
        let _ = write!(out, " {} |", cell(ratio, |v| format!("{v:.2}")));
    }
    out.push('\n');

    out.push_str(
        "\nrelMSE(variant) / the lowest relMSE of Mitsuba's curves at equal time (below 1: \
         passgraph ahead):\n\n| variant |",
    );
    header(out);
    for r in runs {
        let s = Series::from_run(r);
        let _ = write!(out, "| {} |", s.label);
        for t in times {
            let ratio = s
                .relmse_at(t)
                .zip(best_at(&theirs, t))
                .map(|(a, b)| a / b.0);
            let _ = write!(out, " {} |", cell(ratio, |v| format!("{v:.2}")));
        }
        out.push('\n');
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::metrics::ImageError;
    use crate::bench::run::Checkpoint;

    fn run(label: &str, estimate: bool, points: &[(f64, f64)]) -> Run {
        Run {
            label: label.into(),
            adapter: String::new(),
            pass_names: Vec::new(),
            checkpoints: points
                .iter()
                .enumerate()
                .map(|(i, &(seconds, relmse))| Checkpoint {
                    frames: 1 << i,
                    seconds,
                    error: ImageError {
                        rmse: relmse.sqrt(),
                        relmse,
                        bias: 0.0,
                        mse_standard_error: 0.0,
                    },
                    pass_ms: None,
                })
                .collect(),
            rays_per_frame: None,
            cpu_ms_per_frame: 0.0,
            dropped: 0,
            estimate,
        }
    }

    fn row<'a>(md: &'a str, name: &str) -> Vec<&'a str> {
        let line = md
            .lines()
            .find(|l| l.starts_with(&format!("| {name} |")))
            .unwrap_or_else(|| panic!("no row '{name}' in\n{md}"));
        line.trim_matches('|')
            .split('|')
            .map(str::trim)
            .skip(1)
            .collect()
    }

    #[test]
    fn the_race_pits_the_best_estimate_against_mitsubas_best_at_each_time() {
        // At 2 s: passgraph's best estimate is `fast` (1e-3; the denoiser's 1e-4 is no
        // estimate), Mitsuba's best `mj` (2e-3); at 8 s `rr` (2.5e-4) beats `mj` (5e-4).
        let runs = [
            run("fused", true, &[(2.0, 4e-3), (8.0, 1e-3)]),
            run("fast", true, &[(2.0, 1e-3), (8.0, 5e-4)]),
            run("denoised", false, &[(2.0, 1e-4), (8.0, 1e-5)]),
        ];
        let mitsuba = [
            Series::of_relmse("mj", &[(2.0, 2e-3), (8.0, 5e-4)]),
            Series::of_relmse("rr", &[(2.0, 4e-3), (8.0, 2.5e-4)]),
        ];
        let md = markdown(&runs, &mitsuba);
        // Columns: 0.5, 1, 2, 4, 8, 16 s.
        let ours = row(&md, "passgraph, best");
        assert_eq!((ours[2], ours[4]), ("1.00e-3 (fast)", "5.00e-4 (fast)"));
        assert_eq!(ours[0], "–");
        let theirs = row(&md, "Mitsuba, best");
        assert_eq!((theirs[2], theirs[4]), ("2.00e-3 (mj)", "2.50e-4 (rr)"));
        let ratio = row(&md, "ratio (below 1: passgraph ahead)");
        assert_eq!((ratio[2], ratio[4], ratio[5]), ("0.50", "2.00", "–"));
        // Every run, the denoiser too, against Mitsuba's best.
        let against = &md[md.find("relMSE(variant) / the lowest relMSE").expect(&md)..];
        assert_eq!(row(against, "fused")[2], "2.00");
        assert_eq!(row(against, "denoised")[4], "0.04");
    }
}
