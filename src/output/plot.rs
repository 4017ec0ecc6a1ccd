//! `pbdda plot`: PNG and SVG figures from a results folder (finished or still running):
//! monitor paths and displacement histories, contact force histories of chosen bodies,
//! connector force histories (a connector's break marked by a cross at the force it broke
//! at), kinetic energy, solver iterations and residual per step.
//!
//! Drawn with `plotters` on its pure-Rust bitmap and SVG backends; text uses the vendored
//! DejaVu Sans (`assets/fonts`, Bitstream Vera licence) through `ab_glyph`, so no system
//! font library is needed.

use super::results::{ResultsError, Table, contact_rows, steps_of};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

static FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// Registers the vendored font for every family name plotters asks for (once).
pub fn register_fonts() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        for family in ["sans-serif", "serif", "monospace"] {
            for style in [FontStyle::Normal, FontStyle::Bold, FontStyle::Italic, FontStyle::Oblique] {
                // the bytes are a valid TTF committed with the crate: failure is a build defect
                plotters::style::register_font(family, style, FONT)
                    .unwrap_or_else(|_| panic!("vendored font is invalid"));
            }
        }
    });
}

/// What `plot_results` draws.
#[derive(Debug, Clone)]
pub struct PlotOptions {
    /// Bodies whose contact forces to plot; empty: the first four bodies met in contacts.csv.
    pub bodies: Vec<String>,
    /// Figure size in pixels.
    pub size: (u32, u32),
    pub png: bool,
    pub svg: bool,
}

impl Default for PlotOptions {
    fn default() -> Self {
        PlotOptions { bodies: Vec::new(), size: (1000, 700), png: true, svg: true }
    }
}

/// One named curve.
pub type Series = (String, Vec<(f64, f64)>);

/// One panel: title, axis labels and curves.
pub struct Panel {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    /// Points marked by a cross in [`BROKEN_MARK`] with the key "broken" (connectors at the
    /// step they broke in, at the force they broke at).
    pub broken: Vec<(f64, f64)>,
}

/// Colour of the broken-connector crosses (as in `pbdda render`).
pub use super::render::BROKEN_MARK;

type DrawResult = Result<(), Box<dyn std::error::Error>>;

/// Data range of the panel's curves, padded so that a single point or a constant still
/// spans an axis.
fn range(series: &[Series], pick: fn(&(f64, f64)) -> f64) -> (f64, f64) {
    let (lo, hi) = series
        .iter()
        .flat_map(|(_, p)| p.iter().map(pick))
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
    if lo > hi {
        return (0.0, 1.0);
    }
    let pad = if hi > lo {
        0.05 * (hi - lo)
    } else if lo != 0.0 {
        0.5 * lo.abs()
    } else {
        1.0
    };
    (lo - pad, hi + pad)
}

/// Axis tick text for an axis spanning `lo..hi`: plain for moderate magnitudes, scientific
/// for all ticks of an axis with large or tiny values.
fn ticker(lo: f64, hi: f64) -> impl Fn(&f64) -> String {
    let m = lo.abs().max(hi.abs());
    let scientific = !(1e-3..1e5).contains(&m);
    move |v: &f64| {
        if *v == 0.0 {
            "0".to_string()
        } else if scientific {
            format!("{v:.2e}")
        } else {
            format!("{}", (v * 1e6).round() / 1e6)
        }
    }
}

fn draw_panel<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, panel: &Panel) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let marked = [(String::new(), panel.broken.clone())];
    let all: Vec<Series> = panel.series.iter().chain(&marked).cloned().collect();
    let (x0, x1) = range(&all, |p| p.0);
    let (y0, y1) = range(&all, |p| p.1);
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(85)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    chart
        .configure_mesh()
        .x_desc(panel.x_label.as_str())
        .y_desc(panel.y_label.as_str())
        .label_style(("sans-serif", 14))
        .x_label_formatter(&ticker(x0, x1))
        .y_label_formatter(&ticker(y0, y1))
        .draw()?;
    for (i, (name, points)) in panel.series.iter().enumerate() {
        let color = Palette99::pick(i).to_rgba();
        chart
            .draw_series(LineSeries::new(points.iter().copied(), color.stroke_width(2)))?
            .label(name.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2)));
    }
    if !panel.broken.is_empty() {
        let cross = |(x, y): (i32, i32)| {
            let s = BROKEN_MARK.stroke_width(3);
            EmptyElement::at((x, y))
                + PathElement::new(vec![(-7, -7), (7, 7)], s)
                + PathElement::new(vec![(-7, 7), (7, -7)], s)
        };
        chart
            .draw_series(panel.broken.iter().map(|&(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new(vec![(-7, -7), (7, 7)], BROKEN_MARK.stroke_width(3))
                    + PathElement::new(vec![(-7, 7), (7, -7)], BROKEN_MARK.stroke_width(3))
            }))?
            .label("broken")
            .legend(move |(x, y)| cross((x + 10, y)));
    }
    if panel.series.iter().any(|(n, _)| !n.is_empty()) || !panel.broken.is_empty() {
        chart
            .configure_series_labels()
            .label_font(("sans-serif", 14))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()?;
    }
    Ok(())
}

fn draw_figure<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, panels: &[Panel]) -> DrawResult
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    for (area, panel) in root.split_evenly((panels.len(), 1)).iter().zip(panels) {
        draw_panel(area, panel)?;
    }
    root.present()?;
    Ok(())
}

/// Writes `out/NAME.png` and/or `out/NAME.svg` with the panels stacked vertically.
pub fn write_figure(
    out: &Path,
    name: &str,
    panels: &[Panel],
    opts: &PlotOptions,
) -> Result<Vec<PathBuf>, ResultsError> {
    register_fonts();
    let mut written = Vec::new();
    let draw_err =
        |p: &Path, e: Box<dyn std::error::Error>| ResultsError::Draw(format!("{}: {e}", p.display()));
    if opts.png {
        let path = out.join(format!("{name}.png"));
        draw_figure(BitMapBackend::new(&path, opts.size).into_drawing_area(), panels)
            .map_err(|e| draw_err(&path, e))?;
        written.push(path);
    }
    if opts.svg {
        let path = out.join(format!("{name}.svg"));
        draw_figure(SVGBackend::new(&path, opts.size).into_drawing_area(), panels)
            .map_err(|e| draw_err(&path, e))?;
        written.push(path);
    }
    Ok(written)
}

fn panel(title: &str, x: &str, y: &str, series: Vec<Series>) -> Panel {
    Panel { title: title.into(), x_label: x.into(), y_label: y.into(), series, broken: Vec::new() }
}

/// Writes every figure the folder's data allow into `out` (created if missing); returns the
/// files written. Figures: `energy`, `solver` (steps.csv); `monitor_paths`,
/// `monitor_displacements` (if there are monitors); `contact_forces_BODY` per chosen body with
/// contacts; `connector_forces` (if connectors.csv exists).
pub fn plot_results(dir: &Path, out: &Path, opts: &PlotOptions) -> Result<Vec<PathBuf>, ResultsError> {
    std::fs::create_dir_all(out).map_err(|source| ResultsError::Io { path: out.to_path_buf(), source })?;
    let mut written = Vec::new();
    let steps = Table::read(&dir.join("steps.csv"))?;
    if steps.rows.is_empty() {
        return Err(ResultsError::Empty { path: steps.path });
    }
    let (t, s) = (steps.numbers("time")?, steps.numbers("step")?);
    let ke = steps.numbers("kinetic_energy")?;
    let energy = vec![(String::new(), t.iter().copied().zip(ke).collect())];
    let energy = panel("Kinetic energy", "time [s]", "kinetic energy [J]", energy);
    written.extend(write_figure(out, "energy", &[energy], opts)?);
    let (inner, outer) = (steps.numbers("inner_iterations")?, steps.numbers("outer_iterations")?);
    let residual = steps.numbers("residual")?;
    let iters = vec![
        ("inner".to_string(), s.iter().copied().zip(inner).collect()),
        ("outer".to_string(), s.iter().copied().zip(outer).collect()),
    ];
    let res = vec![(
        String::new(),
        s.iter().copied().zip(residual.iter().map(|r| r.max(1e-300).log10())).collect(),
    )];
    let solver = [
        panel("Solver iterations per step", "step", "iterations", iters),
        panel("Scaled natural residual per step", "step", "log10 residual", res),
    ];
    written.extend(write_figure(out, "solver", &solver, opts)?);
    written.extend(monitor_figures(dir, out, opts)?);
    written.extend(contact_figures(dir, out, opts)?);
    let connectors = dir.join("connectors.csv");
    if connectors.exists() {
        written.extend(connector_figure(&Table::read(&connectors)?, out, opts)?);
    }
    Ok(written)
}

/// Rows of a table grouped by the text of `key`, in order of first appearance.
fn grouped(t: &Table, key: &str) -> Result<Vec<(String, Vec<usize>)>, ResultsError> {
    let mut groups: Vec<(String, Vec<usize>)> = Vec::new();
    for (i, k) in t.text(key)?.into_iter().enumerate() {
        match groups.iter_mut().find(|(g, _)| *g == k) {
            Some((_, rows)) => rows.push(i),
            None => groups.push((k, vec![i])),
        }
    }
    Ok(groups)
}

fn monitor_figures(dir: &Path, out: &Path, opts: &PlotOptions) -> Result<Vec<PathBuf>, ResultsError> {
    let t = Table::read(&dir.join("monitors.csv"))?;
    if t.rows.is_empty() {
        return Ok(Vec::new());
    }
    let (time, x, y, ux, uy) =
        (t.numbers("time")?, t.numbers("x")?, t.numbers("y")?, t.numbers("ux")?, t.numbers("uy")?);
    let (mut paths, mut disp) = (Vec::new(), Vec::new());
    for (name, rows) in grouped(&t, "monitor")? {
        paths.push((name.clone(), rows.iter().map(|&i| (x[i], y[i])).collect()));
        disp.push((format!("{name} ux"), rows.iter().map(|&i| (time[i], ux[i])).collect()));
        disp.push((format!("{name} uy"), rows.iter().map(|&i| (time[i], uy[i])).collect()));
    }
    let mut w = write_figure(out, "monitor_paths", &[panel("Monitor paths", "x [m]", "y [m]", paths)], opts)?;
    let d = panel("Monitor displacements", "time [s]", "displacement [m]", disp);
    w.extend(write_figure(out, "monitor_displacements", &[d], opts)?);
    Ok(w)
}

/// Normal and shear force of the contacts of each chosen body, by partner body, summed over
/// the contacts between the two at a step (zero at written steps without contact). The shear
/// force is the one acting on the chosen body (contacts.csv gives it on body_a).
fn contact_figures(dir: &Path, out: &Path, opts: &PlotOptions) -> Result<Vec<PathBuf>, ResultsError> {
    let rows = contact_rows(&Table::read(&dir.join("contacts.csv"))?)?;
    let bodies_table = Table::read(&dir.join("bodies.csv"))?;
    let mut times: BTreeMap<usize, f64> = BTreeMap::new();
    for (s, t) in steps_of(&bodies_table)?.into_iter().zip(bodies_table.numbers("time")?) {
        times.insert(s, t);
    }
    let chosen: Vec<String> = if opts.bodies.is_empty() {
        let mut seen: Vec<String> = Vec::new();
        for r in &rows {
            for b in [&r.body_a, &r.body_b] {
                if !seen.contains(b) && seen.len() < 4 {
                    seen.push(b.clone());
                }
            }
        }
        seen
    } else {
        let mut known = bodies_table.text("body")?;
        known.dedup();
        known.sort();
        known.dedup();
        if let Some(name) = opts.bodies.iter().find(|b| !known.contains(b)) {
            let (path, name, known) = (bodies_table.path.clone(), name.clone(), known.join(", "));
            return Err(ResultsError::UnknownBody { path, name, known });
        }
        opts.bodies.clone()
    };
    let mut written = Vec::new();
    for body in chosen {
        // partner -> step -> (normal, shear on `body`)
        let mut by_partner: BTreeMap<String, BTreeMap<usize, (f64, f64)>> = BTreeMap::new();
        for r in rows.iter().filter(|r| r.body_a == body || r.body_b == body) {
            let (partner, sign) = if r.body_a == body { (&r.body_b, 1.0) } else { (&r.body_a, -1.0) };
            let e = by_partner.entry(partner.clone()).or_default().entry(r.step).or_insert((0.0, 0.0));
            e.0 += r.normal_force;
            e.1 += sign * r.shear_force;
        }
        if by_partner.is_empty() {
            continue;
        }
        let (mut normal, mut shear) = (Vec::new(), Vec::new());
        for (partner, at) in &by_partner {
            let value = |s: &usize, k: usize| at.get(s).map_or(0.0, |v| if k == 0 { v.0 } else { v.1 });
            normal.push((partner.clone(), times.iter().map(|(s, t)| (*t, value(s, 0))).collect()));
            shear.push((partner.clone(), times.iter().map(|(s, t)| (*t, value(s, 1))).collect()));
        }
        let panels = [
            panel(
                &format!("Normal contact force on {body}, by partner"),
                "time [s]",
                "normal force [N]",
                normal,
            ),
            panel(
                &format!("Shear contact force on {body}, by partner"),
                "time [s]",
                "shear force [N]",
                shear,
            ),
        ];
        written.extend(write_figure(out, &format!("contact_forces_{body}"), &panels, opts)?);
    }
    Ok(written)
}

fn connector_figure(t: &Table, out: &Path, opts: &PlotOptions) -> Result<Vec<PathBuf>, ResultsError> {
    if t.rows.is_empty() {
        return Ok(Vec::new());
    }
    let (time, axial, state) = (t.numbers("time")?, t.numbers("axial_force")?, t.text("state")?);
    let series = grouped(t, "connector")?
        .into_iter()
        .map(|(name, rows)| (name, rows.iter().map(|&i| (time[i], axial[i])).collect()))
        .collect();
    let mut p = panel("Connector axial forces (tension positive)", "time [s]", "axial force [N]", series);
    p.broken = (0..time.len()).filter(|&i| state[i] == "broken").map(|i| (time[i], axial[i])).collect();
    write_figure(out, "connector_forces", &[p], opts)
}
