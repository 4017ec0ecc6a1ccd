//! The sweep's log-log picture: error against cost (wall time), one series per error
//! measure. Drawn with plotters' bitmap backend and the vendored DejaVu Sans
//! (`assets/fonts/`), so no system font library is needed.

use super::{SweepReport, SweepRow};
use miette::{Result, miette};
use plotters::prelude::*;
use std::path::Path;

/// One error measure: legend, colour, (cost, error) points.
type Series<'a> = (&'a str, RGBColor, Vec<(f64, f64)>);

/// Writes `path` (PNG, 900 x 600): log-log error against wall time; false (and no file) when
/// the sweep has no errors to plot (no reference and no exact value).
pub fn error_against_cost(report: &SweepReport, path: &Path) -> Result<bool> {
    crate::output::plot::register_fonts();
    let fail = |e: &dyn std::fmt::Display| miette!("{}: cannot draw the sweep plot: {e}", path.display());
    let points = |f: fn(&SweepRow) -> Option<f64>| -> Vec<(f64, f64)> {
        report.rows.iter().filter_map(|r| Some((r.run()?.wall_seconds, f(r)?))).collect()
    };
    let exact =
        report.exact.as_ref().map_or("exact value".to_owned(), |e| format!("{} against exact", e.quantity()));
    let series: Vec<Series> = vec![
        ("monitor position [m]", BLUE, points(|r| r.monitor_error)),
        ("peak contact force [N]", RED, points(|r| r.peak_force_error)),
        ("final contact force [N]", GREEN, points(|r| r.final_force_error)),
        (exact.as_str(), MAGENTA, points(|r| r.exact_error)),
    ];
    if series.iter().all(|s| s.2.is_empty()) {
        return Ok(false);
    }
    let positive: Vec<(f64, f64)> =
        series.iter().flat_map(|s| s.2.iter().copied()).filter(|p| p.0 > 0.0 && p.1 > 0.0).collect();
    let range = |f: fn(&(f64, f64)) -> f64| {
        let lo = positive.iter().map(f).fold(f64::INFINITY, f64::min);
        let hi = positive.iter().map(f).fold(0.0, f64::max);
        if lo.is_finite() { lo / 2.0..hi * 2.0 } else { 1.0..10.0 }
    };
    let (xr, yr) = (range(|p| p.0), range(|p| p.1));
    let root = BitMapBackend::new(path, (900, 600)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| fail(&e))?;
    let caption = format!("sweep of {}: error against cost", report.keys.join(", "));
    let mut chart = ChartBuilder::on(&root)
        .caption(caption, ("sans-serif", 22))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(80)
        .build_cartesian_2d(xr.log_scale(), yr.log_scale())
        .map_err(|e| fail(&e))?;
    chart
        .configure_mesh()
        .x_desc("cost: wall time [s]")
        .y_desc("error")
        .x_label_formatter(&|x| format!("{x:.1e}"))
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .draw()
        .map_err(|e| fail(&e))?;
    for (name, color, points) in series {
        let points: Vec<(f64, f64)> = points.into_iter().filter(|p| p.0 > 0.0 && p.1 > 0.0).collect();
        if points.is_empty() {
            continue;
        }
        chart
            .draw_series(LineSeries::new(points.clone(), color.stroke_width(2)))
            .map_err(|e| fail(&e))?
            .label(name)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2)));
        chart.draw_series(points.iter().map(|p| Circle::new(*p, 4, color.filled()))).map_err(|e| fail(&e))?;
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(|e| fail(&e))?;
    root.present().map_err(|e| fail(&e))?;
    Ok(true)
}
