//! The error-against-time chart: relMSE over seconds, log-log, every variant on one chart;
//! other renderers' curves (Mitsuba's samplers) dashed, so the two sides read apart.

use super::series::Series;
use plotters::prelude::*;
use std::path::Path;

/// DejaVu Sans from Debian's fonts-dejavu-core, which `.ci/run` installs when missing.
const FONT: &str = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

fn register_font() -> Result<(), String> {
    let bytes = std::fs::read(FONT).map_err(|e| {
        format!("{FONT}: {e}; the chart's labels need it: scripts/setup, or apt-get install -y fonts-dejavu-core")
    })?;
    // The font lives for the whole program: plotters keeps a 'static reference.
    let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
    plotters::style::register_font("sans-serif", FontStyle::Normal, bytes)
        .map_err(|_| format!("{FONT}: not a font plotters can read"))
}

/// Draws `runs` (passgraph's variants) solid and `others` dashed.
pub fn write_plot(
    path: &Path,
    title: &str,
    runs: &[Series],
    others: &[Series],
) -> Result<(), String> {
    let series: Vec<&Series> = runs.iter().chain(others).collect();
    static FONT_ONCE: std::sync::OnceLock<Result<(), String>> = std::sync::OnceLock::new();
    FONT_ONCE.get_or_init(register_font).clone()?;
    let points = || series.iter().flat_map(|s| &s.points);
    let (mut t0, mut t1, mut e0, mut e1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for p in points().filter(|p| p.seconds > 0.0 && p.relmse > 0.0) {
        t0 = t0.min(p.seconds);
        t1 = t1.max(p.seconds);
        e0 = e0.min(p.relmse);
        e1 = e1.max(p.relmse);
    }
    if t0 > t1 {
        return Err("nothing to plot: no checkpoint with positive time and error".into());
    }
    let (width, height) = (900u32, 600u32);
    let mut pixels = vec![0u8; (width * height * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut pixels, (width, height)).into_drawing_area();
        let fail = |e: &dyn std::fmt::Display| format!("plot: {e}");
        root.fill(&WHITE).map_err(|e| fail(&e))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d(
                (t0 / 1.5..t1 * 1.5).log_scale(),
                (e0 / 1.5..e1 * 1.5).log_scale(),
            )
            .map_err(|e| fail(&e))?;
        chart
            .configure_mesh()
            .x_desc("wall time (s)")
            .y_desc("relMSE")
            .max_light_lines(1)
            .x_label_formatter(&|v| {
                format!("{v:.3}")
                    .trim_end_matches('0')
                    .trim_end_matches('.')
                    .to_string()
            })
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .draw()
            .map_err(|e| fail(&e))?;
        for (i, s) in series.iter().enumerate() {
            let color = Palette99::pick(i).to_rgba();
            let dashed = i >= runs.len();
            let line: Vec<(f64, f64)> = s
                .points
                .iter()
                .filter(|p| p.seconds > 0.0 && p.relmse > 0.0)
                .map(|p| (p.seconds, p.relmse))
                .collect();
            let style = color.stroke_width(2);
            let drawn = if dashed {
                chart.draw_series(DashedLineSeries::new(line.clone(), 8, 5, style))
            } else {
                chart.draw_series(LineSeries::new(line.clone(), style))
            };
            drawn
                .map_err(|e| fail(&e))?
                .label(s.label.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                });
            chart
                .draw_series(line.into_iter().map(|p| Circle::new(p, 3, color.filled())))
                .map_err(|e| fail(&e))?;
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(|e| fail(&e))?;
        root.present().map_err(|e| fail(&e))?;
    }
    let img = image::RgbImage::from_raw(width, height, pixels).ok_or("plot buffer size")?;
    let mut png = std::io::Cursor::new(Vec::new());
    img.write_to(&mut png, image::ImageFormat::Png)
        .map_err(|e| e.to_string())?;
    crate::atomic_write::write_atomic(path, &png.into_inner())
        .map_err(|e| format!("{}: cannot write: {e}", path.display()))
}
