//! The sweep's table: errors against the reference and the exact value, observed orders,
//! the Richardson extrapolations, the printed table and sweep.csv.

use super::measure::{CaseResult, SweepRun};
use super::richardson::{Extrapolation, extrapolate};
use super::{Case, Exact, Plan};
use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;

/// One case of the grid with its errors.
#[derive(Debug, Clone)]
pub struct SweepRow {
    pub case: Case,
    pub h: Option<f64>,
    pub result: CaseResult,
    /// Largest distance of a monitor to its reference position [m].
    pub monitor_error: Option<f64>,
    /// Largest |peak - reference| and |final - reference| normal force over body pairs [N].
    pub peak_force_error: Option<f64>,
    pub final_force_error: Option<f64>,
    /// |φ - exact| of the `--exact` quantity.
    pub exact_error: Option<f64>,
    /// Observed orders against the previous row: monitor, peak force, final force, exact.
    pub orders: [Option<f64>; 4],
}

impl SweepRow {
    /// The run, if the case did not fail.
    pub fn run(&self) -> Option<&SweepRun> {
        self.result.outcome().ok()
    }
}

/// The result of a sweep.
#[derive(Debug, Clone)]
pub struct SweepReport {
    /// The swept keys.
    pub keys: Vec<String>,
    /// The reference case and its result.
    pub reference: Option<(Case, CaseResult)>,
    pub exact: Option<Exact>,
    /// One row per case of the grid, in grid order.
    pub rows: Vec<SweepRow>,
    /// Richardson extrapolations from the three finest sizes (none without three sizes).
    pub extrapolations: Vec<Extrapolation>,
}

/// ln(e0/e1) / ln(h0/h1), when both errors are positive and the sizes differ.
fn order(h0: Option<f64>, h1: Option<f64>, e0: Option<f64>, e1: Option<f64>) -> Option<f64> {
    let (h0, h1, e0, e1) = (h0?, h1?, e0?, e1?);
    (e0 > 0.0 && e1 > 0.0 && h0 > 0.0 && h1 > 0.0 && h0 != h1).then(|| (e0 / e1).ln() / (h0 / h1).ln())
}

fn max_distance(a: &SweepRun, b: &SweepRun) -> f64 {
    let d = |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).hypot(p[1] - q[1]);
    a.monitors
        .iter()
        .filter_map(|(k, p)| b.monitors.get(k).map(|q| d(p.position, q.position)))
        .fold(0.0, f64::max)
}

/// Largest |a - b| over the union of keys (an absent pair carries no force).
fn max_difference(a: &BTreeMap<String, f64>, b: &BTreeMap<String, f64>) -> f64 {
    let get = |m: &BTreeMap<String, f64>, k: &String| m.get(k).copied().unwrap_or(0.0);
    a.keys().chain(b.keys()).map(|k| (get(a, k) - get(b, k)).abs()).fold(0.0, f64::max)
}

fn exact_value(run: &SweepRun, e: &Exact) -> Option<f64> {
    run.monitors.get(&e.monitor)?.component(&e.component)
}

impl SweepReport {
    /// The report of `plan` from the results of its cases (in case order).
    pub fn new(plan: &Plan, results: Vec<CaseResult>) -> SweepReport {
        let reference = plan.reference.map(|i| (plan.cases[i].clone(), results[i].clone()));
        let reference_run = reference.as_ref().and_then(|r| r.1.run.clone());
        let mut rows: Vec<SweepRow> = Vec::new();
        for (i, result) in results.iter().enumerate().take(plan.rows) {
            let run = result.outcome().ok();
            let against = |f: &dyn Fn(&SweepRun, &SweepRun) -> f64| Some(f(run?, reference_run.as_ref()?));
            let exact_error = plan.exact.as_ref().and_then(|e| Some((exact_value(run?, e)? - e.value).abs()));
            let mut row = SweepRow {
                case: plan.cases[i].clone(),
                h: plan.h[i],
                result: result.clone(),
                monitor_error: against(&max_distance),
                peak_force_error: against(&|a, b| max_difference(&a.peak_force, &b.peak_force)),
                final_force_error: against(&|a, b| max_difference(&a.final_force, &b.final_force)),
                exact_error,
                orders: [None; 4],
            };
            if let Some(prev) = rows.last() {
                let e =
                    |r: &SweepRow| [r.monitor_error, r.peak_force_error, r.final_force_error, r.exact_error];
                let (e0, e1) = (e(prev), e(&row));
                row.orders = [0, 1, 2, 3].map(|k| order(prev.h, row.h, e0[k], e1[k]));
            }
            rows.push(row);
        }
        let extrapolations = extrapolations(plan, &results);
        SweepReport {
            keys: plan.axes.iter().map(|a| a.key.clone()).collect(),
            reference,
            exact: plan.exact.clone(),
            rows,
            extrapolations,
        }
    }

    /// The printed table: one line per case, then the extrapolations.
    pub fn table(&self) -> String {
        let mut s = format!("sweep of {}", self.keys.join(", "));
        match &self.reference {
            Some((case, _)) => {
                let _ = write!(
                    s,
                    " (reference: {}); errors are the largest over monitors [m] and body pairs [N]",
                    case.label()
                );
            }
            None => s.push_str(" (no reference: errors need a sized key or --reference)"),
        }
        if let Some(e) = &self.exact {
            let _ = write!(s, "; exact {e}");
        }
        s.push('\n');
        let _ = writeln!(
            s,
            "{:>4} {:>10} {:>6} {:>8} {:>10} {:>10} {:>7} {:>10} {:>7} {:>10} {:>7}  case",
            "#",
            "h",
            "steps",
            "wall s",
            "iters",
            "monitor e",
            "order",
            "peak F e",
            "order",
            "exact e",
            "order"
        );
        let e = |x: Option<f64>| x.map_or(String::new(), |x| format!("{x:.3e}"));
        for r in &self.rows {
            let Some(run) = r.run() else {
                let message = r.result.error.as_deref().unwrap_or("no result");
                let _ =
                    writeln!(s, "{:>4} {:>10} failed: {message}  {}", r.case.index, e(r.h), r.case.label());
                continue;
            };
            let _ = writeln!(
                s,
                "{:>4} {:>10} {:>6} {:>8.3} {:>10} {:>10} {:>7} {:>10} {:>7} {:>10} {:>7}  {}",
                r.case.index,
                e(r.h),
                run.steps,
                run.wall_seconds,
                run.iterations,
                e(r.monitor_error),
                opt(r.orders[0]),
                e(r.peak_force_error),
                opt(r.orders[1]),
                e(r.exact_error),
                opt(r.orders[3]),
                r.case.label()
            );
        }
        for x in &self.extrapolations {
            let _ = write!(
                s,
                "Richardson {} from h = {:.4e}, {:.4e}, {:.4e}: ",
                x.quantity, x.h[0], x.h[1], x.h[2]
            );
            let _ = match (x.order, x.extrapolated, x.gci) {
                (Some(p), Some(v), Some(g)) => {
                    writeln!(s, "order {p:.3}, extrapolated {v:.6e}, GCI of the finest {g:.3e}")
                }
                _ => writeln!(s, "no order (values {:?} do not converge monotonically)", x.values),
            };
        }
        s
    }

    /// sweep.csv: one row per case. Columns: case, the swept keys, h, status, message, steps,
    /// wall_seconds, iterations, the errors and orders, then every monitor's final x, y, ux,
    /// uy and error, every connector's final force and broken state, every body pair's peak
    /// and final force with their errors.
    pub fn csv(&self) -> String {
        let runs: Vec<&SweepRun> = self.rows.iter().filter_map(SweepRow::run).collect();
        let union = |f: &dyn Fn(&SweepRun) -> Vec<String>| -> Vec<String> {
            runs.iter().flat_map(|r| f(r)).collect::<BTreeSet<_>>().into_iter().collect()
        };
        let monitors = union(&|r| r.monitors.keys().cloned().collect());
        let connectors = union(&|r| r.connectors.keys().cloned().collect());
        let pairs = union(&|r| r.peak_force.keys().cloned().collect());
        let mut head: Vec<String> = vec!["case".into()];
        head.extend(self.keys.iter().cloned());
        for c in
            "h,status,message,steps,wall_seconds,iterations,monitor_error,monitor_order,peak_force_error,\
                  peak_force_order,final_force_error,final_force_order,exact_error,exact_order"
                .split(',')
        {
            head.push(c.into());
        }
        for m in &monitors {
            head.extend(["x", "y", "ux", "uy", "error"].map(|c| format!("{m}_{c}")));
        }
        for c in &connectors {
            head.extend(["force", "broken"].map(|k| format!("{c}_{k}")));
        }
        for p in &pairs {
            head.extend(["peak", "peak_error", "final", "final_error"].map(|k| format!("{p}_{k}")));
        }
        let mut s = line(&head);
        let reference = self.reference.as_ref().and_then(|r| r.1.run.as_ref());
        for r in &self.rows {
            let mut cells: Vec<String> = vec![r.case.index.to_string()];
            cells.extend(r.case.set.iter().map(|o| o.value.clone()));
            cells.push(r.h.map_or(String::new(), |h| h.to_string()));
            let Some(run) = r.run() else {
                cells.push("failed".into());
                cells.push(r.result.error.clone().unwrap_or_default());
                cells.resize(head.len(), String::new());
                s += &line(&cells);
                continue;
            };
            cells.extend(["ok".to_owned(), String::new(), run.steps.to_string()]);
            cells.extend([run.wall_seconds.to_string(), run.iterations.to_string()]);
            let errors = [r.monitor_error, r.peak_force_error, r.final_force_error, r.exact_error];
            for (e, o) in errors.iter().zip(&r.orders) {
                cells.push(e.map_or(String::new(), |e| format!("{e:e}")));
                cells.push(opt(*o));
            }
            for m in &monitors {
                let Some(end) = run.monitors.get(m) else {
                    cells.extend(std::iter::repeat_n(String::new(), 5));
                    continue;
                };
                cells.extend(end.position.iter().chain(&end.displacement).map(f64::to_string));
                let error = reference
                    .and_then(|q| q.monitors.get(m))
                    .map(|q| (end.position[0] - q.position[0]).hypot(end.position[1] - q.position[1]));
                cells.push(error.map_or(String::new(), |e| format!("{e:e}")));
            }
            for c in &connectors {
                match run.connectors.get(c) {
                    Some(end) => cells.extend([end.force.to_string(), end.broken.to_string()]),
                    None => cells.extend([String::new(), String::new()]),
                }
            }
            for p in &pairs {
                let get = |m: &BTreeMap<String, f64>| m.get(p).copied().unwrap_or(0.0);
                let (pk, fi) = (get(&run.peak_force), get(&run.final_force));
                cells.push(pk.to_string());
                cells.push(
                    reference.map_or(String::new(), |q| format!("{:e}", (pk - get(&q.peak_force)).abs())),
                );
                cells.push(fi.to_string());
                cells.push(
                    reference.map_or(String::new(), |q| format!("{:e}", (fi - get(&q.final_force)).abs())),
                );
            }
            s += &line(&cells);
        }
        s
    }
}

/// Richardson extrapolations of every monitor's ux and uy (and the exact quantity) from the
/// three finest distinct sizes among the cases that ran.
fn extrapolations(plan: &Plan, results: &[CaseResult]) -> Vec<Extrapolation> {
    let mut sized: Vec<(f64, &SweepRun)> =
        results.iter().enumerate().filter_map(|(i, r)| Some((plan.h[i]?, r.outcome().ok()?))).collect();
    sized.sort_by(|a, b| a.0.total_cmp(&b.0));
    sized.dedup_by(|a, b| a.0 == b.0);
    let [a, b, c, ..] = sized.as_slice() else {
        return Vec::new();
    };
    let mut quantities: Vec<(String, String)> = Vec::new();
    for m in a.1.monitors.keys() {
        quantities.extend(["ux", "uy"].map(|c| (m.clone(), c.to_owned())));
    }
    if let Some(e) = &plan.exact
        && !quantities.contains(&(e.monitor.clone(), e.component.clone()))
    {
        quantities.push((e.monitor.clone(), e.component.clone()));
    }
    let value = |run: &SweepRun, (m, c): &(String, String)| run.monitors.get(m).and_then(|e| e.component(c));
    quantities
        .iter()
        .filter_map(|q| {
            let v = [value(a.1, q)?, value(b.1, q)?, value(c.1, q)?];
            Some(extrapolate(&format!("monitor.{}.{}", q.0, q.1), [a.0, b.0, c.0], v))
        })
        .collect()
}

fn opt(x: Option<f64>) -> String {
    x.map_or(String::new(), |p| format!("{p:.3}"))
}

/// One CSV line; a cell with a comma, quote or line break is quoted (RFC 4180).
fn line(cells: &[String]) -> String {
    let quote = |c: &String| {
        if c.contains([',', '"', '\n', '\r']) { format!("\"{}\"", c.replace('"', "\"\"")) } else { c.clone() }
    };
    cells.iter().map(quote).collect::<Vec<_>>().join(",") + "\n"
}
