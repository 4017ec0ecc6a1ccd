//! `pbdda sweep SCENE --set KEY=V1,V2,... [--reference V] [--out DIR]`: runs a scene once per
//! value of one key (the other `--set` overrides apply to every run) and measures what each
//! value costs (wall time, solver iterations) and how far its results are from the reference
//! run (the smallest numeric value, or `--reference`): the final position of every monitor
//! and the peak and final normal force between every pair of bodies in contact.
//!
//! Observed order between successive values h_i, h_{i+1} with errors e_i, e_{i+1} (errors
//! against the reference): p = ln(e_i / e_{i+1}) / ln(h_i / h_{i+1}). It is the order of the
//! scheme when the reference is much finer than the values compared (its own error is then
//! negligible).
//!
//! A time-step sweep keeps the simulated time fixed: when the swept key is `time.step`, every
//! run ends at the base scene's end time (`time.end` is set, which replaces `time.steps`).

mod plot;

use super::progress::{Progress, ProgressMode};
use crate::geometry::Vec2;
use crate::scene::{Override, parse_with};
use crate::world::World;
use miette::{IntoDiagnostic, Result, miette};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

/// Options of a sweep besides the scene and the values.
#[derive(Debug, Clone, Default)]
pub struct SweepOptions {
    /// Value of the swept key for the reference run (run in addition if not among the values).
    pub reference: Option<String>,
    pub quiet: bool,
}

/// What one run of the sweep measured.
#[derive(Debug, Clone)]
pub struct SweepRun {
    /// The swept key's value as given.
    pub value: String,
    /// The value as a number, if it is one.
    pub h: Option<f64>,
    pub steps: usize,
    /// Simulated time at the end [s].
    pub end_time: f64,
    pub wall_seconds: f64,
    /// Inner solver iterations, all steps.
    pub iterations: usize,
    /// Final position of every monitor, by name.
    pub monitors: BTreeMap<String, Vec2>,
    /// Peak and final total normal force between two bodies, by "a/b" (names sorted).
    pub peak_force: BTreeMap<String, f64>,
    pub final_force: BTreeMap<String, f64>,
}

/// Errors of one run against the reference (the largest over monitors, over body pairs).
#[derive(Debug, Clone)]
pub struct SweepRow {
    pub run: SweepRun,
    pub monitor_error: f64,
    pub peak_force_error: f64,
    pub final_force_error: f64,
    /// Observed orders against the previous row: monitor, peak force, final force.
    pub orders: [Option<f64>; 3],
}

/// The result of a sweep.
#[derive(Debug, Clone)]
pub struct SweepReport {
    pub key: String,
    pub reference: SweepRun,
    /// One row per swept value, in the order given (the reference run included, error 0).
    pub rows: Vec<SweepRow>,
}

/// Splits `V1,V2,...` at the commas outside brackets, braces and quotes.
pub fn split_values(text: &str) -> Vec<String> {
    let (mut out, mut cur, mut depth, mut quote) = (Vec::new(), String::new(), 0i32, None);
    for c in text.chars() {
        match (c, quote) {
            ('"' | '\'', None) => quote = Some(c),
            (q, Some(open)) if q == open => quote = None,
            ('[' | '{', None) => depth += 1,
            (']' | '}', None) => depth -= 1,
            (',', None) if depth == 0 => {
                out.push(cur.trim().to_owned());
                cur.clear();
                continue;
            }
            _ => {}
        }
        cur.push(c);
    }
    out.push(cur.trim().to_owned());
    out
}

/// Runs the sweep of `key` over `values` on the scene text `source`.
pub fn sweep(
    source: &str,
    file: &str,
    base: &[Override],
    key: &str,
    values: &[String],
    options: &SweepOptions,
) -> Result<SweepReport> {
    let mut base = base.to_vec();
    if key == "time.step" {
        // keep the simulated time: every run ends where the base scene ends
        let model = parse_with(source, file, &base)?;
        let end = model.time.step * model.time.steps as f64;
        base.push(Override { key: "time.end".into(), value: format!("{end:e}") });
    }
    let reference_value = match &options.reference {
        Some(v) => v.clone(),
        None => finest(values),
    };
    let mut runs = Vec::new();
    for value in values {
        runs.push(one_run(source, file, &base, key, value, options.quiet)?);
    }
    let reference = match runs.iter().find(|r| r.value == reference_value) {
        Some(r) => r.clone(),
        None => one_run(source, file, &base, key, &reference_value, options.quiet)?,
    };
    let mut rows: Vec<SweepRow> = Vec::new();
    for run in runs {
        let errors = [
            max_distance(&run.monitors, &reference.monitors),
            max_difference(&run.peak_force, &reference.peak_force),
            max_difference(&run.final_force, &reference.final_force),
        ];
        let orders = match rows.last() {
            Some(prev) => {
                let prev_e = [prev.monitor_error, prev.peak_force_error, prev.final_force_error];
                [0, 1, 2].map(|k| order(prev.run.h, run.h, prev_e[k], errors[k]))
            }
            None => [None; 3],
        };
        let [monitor_error, peak_force_error, final_force_error] = errors;
        rows.push(SweepRow { run, monitor_error, peak_force_error, final_force_error, orders });
    }
    Ok(SweepReport { key: key.to_owned(), reference, rows })
}

/// The smallest numeric value (the finest time step or tolerance), else the last one.
fn finest(values: &[String]) -> String {
    let numeric = values.iter().filter_map(|v| v.parse::<f64>().ok().map(|x| (x.abs(), v)));
    numeric
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map_or_else(|| values.last().cloned().unwrap_or_default(), |(_, v)| v.clone())
}

/// ln(e0/e1) / ln(h0/h1), when both errors are positive and the values differ.
fn order(h0: Option<f64>, h1: Option<f64>, e0: f64, e1: f64) -> Option<f64> {
    let (h0, h1) = (h0?, h1?);
    (e0 > 0.0 && e1 > 0.0 && h0 > 0.0 && h1 > 0.0 && h0 != h1).then(|| (e0 / e1).ln() / (h0 / h1).ln())
}

fn max_distance(a: &BTreeMap<String, Vec2>, b: &BTreeMap<String, Vec2>) -> f64 {
    a.iter().filter_map(|(k, p)| b.get(k).map(|q| (*p - *q).norm())).fold(0.0, f64::max)
}

/// Largest |a - b| over the union of keys (an absent pair carries no force).
fn max_difference(a: &BTreeMap<String, f64>, b: &BTreeMap<String, f64>) -> f64 {
    let get = |m: &BTreeMap<String, f64>, k: &String| m.get(k).copied().unwrap_or(0.0);
    a.keys().chain(b.keys()).map(|k| (get(a, k) - get(b, k)).abs()).fold(0.0, f64::max)
}

fn one_run(
    source: &str,
    file: &str,
    base: &[Override],
    key: &str,
    value: &str,
    quiet: bool,
) -> Result<SweepRun> {
    let mut overrides = base.to_vec();
    overrides.push(Override { key: key.to_owned(), value: value.to_owned() });
    let model = parse_with(source, file, &overrides)?;
    let steps = model.time.steps;
    let mut world = World::new(model);
    let mode = if quiet { ProgressMode::Quiet } else { ProgressMode::detect(false) };
    if !quiet {
        errln!("{key} = {value}: {steps} steps");
    }
    let mut progress = Progress::new(steps, mode);
    let mut run = SweepRun {
        value: value.to_owned(),
        h: value.parse().ok(),
        steps,
        end_time: 0.0,
        wall_seconds: 0.0,
        iterations: 0,
        monitors: BTreeMap::new(),
        peak_force: BTreeMap::new(),
        final_force: BTreeMap::new(),
    };
    let started = Instant::now();
    // the last two totals of every pair that has been in contact
    let mut history: BTreeMap<String, [f64; 2]> = BTreeMap::new();
    for _ in 0..steps {
        if world.finished() {
            // a staged run whose last stage ended early (`until_kinetic`)
            break;
        }
        let rec = world.step()?;
        run.iterations += rec.inner_iterations;
        let mut pairs: BTreeMap<String, f64> = BTreeMap::new();
        for c in &rec.contacts {
            let (a, b) = (&world.bodies[c.body_a].name, &world.bodies[c.body_b].name);
            let pair = if a <= b { format!("{a}/{b}") } else { format!("{b}/{a}") };
            *pairs.entry(pair).or_default() += c.normal_force;
        }
        for pair in pairs.keys().chain(run.final_force.keys()) {
            history.entry(pair.clone()).or_default();
        }
        for (pair, h) in history.iter_mut() {
            let f = pairs.get(pair).copied().unwrap_or(0.0);
            let peak = run.peak_force.entry(pair.clone()).or_insert(f64::NEG_INFINITY);
            *peak = peak.max(refined_peak(h, f));
        }
        run.final_force = pairs;
        progress.step(&rec);
    }
    progress.finish();
    run.wall_seconds = started.elapsed().as_secs_f64();
    run.end_time = world.time;
    for (m, p) in world.model.monitors.iter().zip(&world.monitors) {
        run.monitors.insert(m.name.clone(), p.current);
    }
    Ok(run)
}

/// Feeds the next step's force `f` of a pair whose last two values are `h`; returns the best
/// peak estimate so far from this step: the raw value `f`, or, when the previous step was a
/// local maximum, the vertex of the parabola through the three values. The refinement removes
/// the O(dt²) error of sampling a smooth peak at step times, whose size depends on where the
/// steps fall, so that the peak of runs with different steps can be compared.
fn refined_peak(h: &mut [f64; 2], f: f64) -> f64 {
    let [f0, f1] = *h;
    *h = [f1, f];
    let curvature = f0 - 2.0 * f1 + f;
    if f1 >= f0 && f1 >= f && curvature < 0.0 && f0 > 0.0 && f > 0.0 {
        f1 - (f - f0) * (f - f0) / (8.0 * curvature)
    } else {
        f
    }
}

fn opt(x: Option<f64>) -> String {
    x.map_or(String::new(), |p| format!("{p:.3}"))
}

impl SweepReport {
    /// The printed table: one line per value.
    pub fn table(&self) -> String {
        let mut s = format!(
            "sweep of {} (reference: {} = {}); errors are the largest over monitors [m] and body pairs [N]\n",
            self.key, self.key, self.reference.value
        );
        let _ = writeln!(
            s,
            "{:>12} {:>7} {:>9} {:>11} {:>11} {:>7} {:>11} {:>7} {:>11} {:>7}",
            "value",
            "steps",
            "wall s",
            "iterations",
            "monitor err",
            "order",
            "peak F err",
            "order",
            "final F err",
            "order"
        );
        let ends = self.rows.iter().map(|r| r.run.end_time);
        let (lo, hi) = ends.fold((f64::INFINITY, 0.0f64), |(lo, hi), t| (lo.min(t), hi.max(t)));
        if hi - lo > 1e-9 * hi.max(self.reference.end_time)
            || (hi - self.reference.end_time).abs() > 1e-9 * hi
        {
            let _ = writeln!(
                s,
                "note: the runs end between t = {lo} s and {hi} s (reference {} s): final values are not \
                 comparable; choose time.end as a multiple of every time step",
                self.reference.end_time
            );
        }
        for r in &self.rows {
            let [o1, o2, o3] = r.orders;
            let _ = writeln!(
                s,
                "{:>12} {:>7} {:>9.3} {:>11} {:>11.3e} {:>7} {:>11.3e} {:>7} {:>11.3e} {:>7}",
                r.run.value,
                r.run.steps,
                r.run.wall_seconds,
                r.run.iterations,
                r.monitor_error,
                opt(o1),
                r.peak_force_error,
                opt(o2),
                r.final_force_error,
                opt(o3)
            );
        }
        s
    }

    /// sweep.csv: the table's columns, then every monitor's final x, y and every pair's peak
    /// and final force with its error against the reference.
    pub fn csv(&self) -> String {
        let r0 = &self.reference;
        let mut head = String::from(
            "value,steps,wall_seconds,iterations,monitor_error,monitor_order,\
             peak_force_error,peak_force_order,final_force_error,final_force_order",
        );
        let pairs: Vec<&String> = {
            let mut p: Vec<&String> =
                self.rows.iter().flat_map(|r| r.run.peak_force.keys()).chain(r0.peak_force.keys()).collect();
            p.sort();
            p.dedup();
            p
        };
        for m in r0.monitors.keys() {
            let _ = write!(head, ",{m}_x,{m}_y,{m}_error");
        }
        for p in &pairs {
            let _ = write!(head, ",{p}_peak,{p}_peak_error,{p}_final,{p}_final_error");
        }
        let mut s = head + "\n";
        for r in &self.rows {
            let [o1, o2, o3] = r.orders;
            let _ = write!(
                s,
                "{},{},{},{},{:e},{},{:e},{},{:e},{}",
                r.run.value,
                r.run.steps,
                r.run.wall_seconds,
                r.run.iterations,
                r.monitor_error,
                opt(o1),
                r.peak_force_error,
                opt(o2),
                r.final_force_error,
                opt(o3)
            );
            for (m, q) in &r0.monitors {
                let p = r.run.monitors.get(m).copied().unwrap_or(Vec2::new(f64::NAN, f64::NAN));
                let _ = write!(s, ",{},{},{:e}", p.x, p.y, (p - *q).norm());
            }
            for p in &pairs {
                let get = |m: &BTreeMap<String, f64>| m.get(*p).copied().unwrap_or(0.0);
                let (pk, fi) = (get(&r.run.peak_force), get(&r.run.final_force));
                let _ = write!(
                    s,
                    ",{pk},{:e},{fi},{:e}",
                    (pk - get(&r0.peak_force)).abs(),
                    (fi - get(&r0.final_force)).abs()
                );
            }
            s.push('\n');
        }
        s
    }
}

pub(super) fn command(scene: &Path, set: &[Override], out: &Path, options: &SweepOptions) -> Result<()> {
    let swept: Vec<&Override> = set.iter().filter(|o| split_values(&o.value).len() > 1).collect();
    let [swept] = swept.as_slice() else {
        return Err(miette!(
            "sweep needs exactly one --set KEY=V1,V2,... with several values (got {})",
            swept.len()
        ));
    };
    let base: Vec<Override> =
        set.iter().filter(|o| o.key != swept.key || o.value != swept.value).cloned().collect();
    let file = scene.display().to_string();
    let source =
        std::fs::read_to_string(scene).map_err(|e| crate::scene::SceneError::unreadable(&file, &e))?;
    let values = split_values(&swept.value);
    let report = sweep(&source, &file, &base, &swept.key, &values, options)?;
    out!("{}", report.table());
    std::fs::create_dir_all(out).into_diagnostic()?;
    std::fs::write(out.join("sweep.csv"), report.csv()).into_diagnostic()?;
    plot::error_against_cost(&report, &out.join("sweep.png"))?;
    outln!("wrote {} and {}", out.join("sweep.csv").display(), out.join("sweep.png").display());
    Ok(())
}
