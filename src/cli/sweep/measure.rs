//! One case of a sweep: run the model and keep what the table compares (monitors, contact
//! forces between body pairs, connector forces and states, cost), and the case's result file.

use crate::cli::{Progress, ProgressMode};
use crate::model::Model;
use crate::world::World;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::time::Instant;

/// A monitor at the end of a run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MonitorEnd {
    /// Final position [m].
    pub position: [f64; 2],
    /// Displacement from the initial position [m].
    pub displacement: [f64; 2],
}

impl MonitorEnd {
    /// The component `x`, `y`, `ux` or `uy`.
    pub fn component(&self, c: &str) -> Option<f64> {
        match c {
            "x" => Some(self.position[0]),
            "y" => Some(self.position[1]),
            "ux" => Some(self.displacement[0]),
            "uy" => Some(self.displacement[1]),
            _ => None,
        }
    }
}

/// A connector at the end of a run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ConnectorEnd {
    /// Final axial force [N], tension positive (0 once broken).
    pub force: f64,
    pub broken: bool,
    /// The step it broke in.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub broken_at: Option<usize>,
}

/// What one run of the sweep measured.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct SweepRun {
    pub steps: usize,
    /// Simulated time at the end [s].
    pub end_time: f64,
    pub wall_seconds: f64,
    /// Inner solver iterations, all steps.
    pub iterations: usize,
    /// Every monitor, by name.
    pub monitors: BTreeMap<String, MonitorEnd>,
    /// Peak and final total normal force between two bodies, by "a/b" (names sorted).
    pub peak_force: BTreeMap<String, f64>,
    pub final_force: BTreeMap<String, f64>,
    /// Every connector, by name.
    pub connectors: BTreeMap<String, ConnectorEnd>,
}

/// A case's result file (`results/case-NNNN.toml` of a plan): the run, or why it failed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CaseResult {
    pub index: usize,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub run: Option<SweepRun>,
}

impl CaseResult {
    pub fn outcome(&self) -> Result<&SweepRun, &str> {
        match (&self.run, &self.error) {
            (Some(run), None) => Ok(run),
            (_, Some(e)) => Err(e),
            (None, None) => Err("no result"),
        }
    }
}

/// Runs `model` to its end; a step that fails ends the case with its error message.
pub fn run_case(model: Model, index: usize, label: &str, quiet: bool) -> CaseResult {
    let steps = model.time.steps;
    let mut world = World::new(model);
    let mode = if quiet { ProgressMode::Quiet } else { ProgressMode::detect(false) };
    if !quiet {
        errln!("case {index} ({label}): {steps} steps");
    }
    let mut progress = Progress::new(steps, mode);
    let mut run = SweepRun { steps, ..SweepRun::default() };
    let started = Instant::now();
    // the last two totals of every pair that has been in contact
    let mut history: BTreeMap<String, [f64; 2]> = BTreeMap::new();
    for _ in 0..steps {
        if world.finished() {
            // a staged run whose last stage ended early (`until_kinetic`)
            break;
        }
        let rec = match world.step() {
            Ok(rec) => rec,
            Err(e) => return CaseResult { index, error: Some(e.to_string()), run: None },
        };
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
        let (c, d) = (p.current, p.current - p.initial);
        run.monitors.insert(m.name.clone(), MonitorEnd { position: [c.x, c.y], displacement: [d.x, d.y] });
    }
    for c in &world.connectors {
        let force = if c.broken { 0.0 } else { c.axial_force() };
        let end = ConnectorEnd { force, broken: c.broken, broken_at: c.broken_at };
        run.connectors.insert(c.name.clone(), end);
    }
    CaseResult { index, error: None, run: Some(run) }
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
