//! Bench outputs: a CSV per run and a markdown report (equal time, equal error, per pass).

use super::rounds::median;
use super::run::Run;
use super::series::Series;
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

/// The markdown report: a summary per run, relMSE at equal times, for each extra series (such
/// as a Mitsuba sampler) the ratio of every run's relMSE to it at equal times, times to equal
/// errors (passgraph runs and the extra series), and GPU milliseconds per pass.
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

    for e in extra {
        let _ = write!(
            out,
            "\nrelMSE(variant) / relMSE({}) at equal time (below 1: passgraph ahead):\n\n| variant |",
            e.label
        );
        for t in times {
            let _ = write!(out, " {t} s |");
        }
        out.push_str("\n|---|");
        out.push_str(&"---|".repeat(times.len()));
        out.push('\n');
        for r in runs {
            let s = Series::from_run(r);
            let _ = write!(out, "| {} |", s.label);
            for t in times {
                let ratio = s.relmse_at(t).zip(e.relmse_at(t)).map(|(a, b)| a / b);
                let _ = write!(out, " {} |", cell(ratio, |v| format!("{v:.2}")));
            }
            out.push('\n');
        }
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
