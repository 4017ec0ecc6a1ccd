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

/// Where a case of a plan keeps its state while it runs (`--run-plan`): a state file
/// ([`crate::checkpoint::encode`]) saved every `every` steps, with the case's running table
/// beside the world. A case that finds the file goes on from it; the file is removed when the
/// case's result is written.
pub struct CaseCheckpoint<'a> {
    pub path: std::path::PathBuf,
    pub every: usize,
    /// The case's scene text (the state is tied to it).
    pub scene: &'a str,
}

/// What a case has measured so far, saved with its state.
#[derive(Default, Serialize, Deserialize)]
struct Running {
    run: SweepRun,
    /// The last two totals of every pair that has been in contact.
    history: BTreeMap<String, [f64; 2]>,
}

/// Runs `model` to its end (from `checkpoint`'s state when there is one); a step that fails
/// ends the case with its error message.
pub fn run_case(
    model: Model,
    index: usize,
    label: &str,
    quiet: bool,
    checkpoint: Option<&CaseCheckpoint>,
) -> CaseResult {
    let steps = model.time.steps;
    let (mut world, mut running) = match checkpoint.filter(|c| c.path.exists()) {
        Some(c) => match resumed(c, model) {
            Ok(found) => found,
            Err(e) => return CaseResult { index, error: Some(e), run: None },
        },
        None => (
            World::new(model),
            Running { run: SweepRun { steps, ..SweepRun::default() }, ..Running::default() },
        ),
    };
    let mode = if quiet { ProgressMode::Quiet } else { ProgressMode::detect(false) };
    if !quiet {
        match world.step_index {
            0 => errln!("case {index} ({label}): {steps} steps"),
            s => errln!("case {index} ({label}): {steps} steps, resumed at step {s}"),
        }
    }
    let mut progress = Progress::new(steps - world.step_index.min(steps), mode);
    let started = Instant::now();
    let wall = running.run.wall_seconds;
    // a staged run whose last stage ended early (`until_kinetic`) is finished before `steps`
    while world.step_index < steps && !world.finished() {
        let rec = match world.step() {
            Ok(rec) => rec,
            Err(e) => return CaseResult { index, error: Some(e.to_string()), run: None },
        };
        running.measure(&world, &rec);
        progress.step(&rec);
        if let Some(c) = checkpoint.filter(|c| rec.step % c.every.max(1) == 0 && rec.step < steps) {
            running.run.wall_seconds = wall + started.elapsed().as_secs_f64();
            if let Err(e) = save(c, &world, &running) {
                return CaseResult { index, error: Some(e), run: None };
            }
        }
    }
    progress.finish();
    let mut run = running.run;
    run.wall_seconds = wall + started.elapsed().as_secs_f64();
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

impl Running {
    /// Adds a step: its iterations, and each body pair's total normal force to the peaks.
    fn measure(&mut self, world: &World, rec: &crate::world::StepRecord) {
        let run = &mut self.run;
        run.iterations += rec.inner_iterations;
        let mut pairs: BTreeMap<String, f64> = BTreeMap::new();
        for c in &rec.contacts {
            let (a, b) = (&world.bodies[c.body_a].name, &world.bodies[c.body_b].name);
            let pair = if a <= b { format!("{a}/{b}") } else { format!("{b}/{a}") };
            *pairs.entry(pair).or_default() += c.normal_force;
        }
        for pair in pairs.keys().chain(run.final_force.keys()) {
            self.history.entry(pair.clone()).or_default();
        }
        for (pair, h) in self.history.iter_mut() {
            let f = pairs.get(pair).copied().unwrap_or(0.0);
            let peak = run.peak_force.entry(pair.clone()).or_insert(f64::NEG_INFINITY);
            *peak = peak.max(refined_peak(h, f));
        }
        run.final_force = pairs;
    }
}

/// Saves the case's state (atomically: `crate::checkpoint::write_atomic`).
fn save(c: &CaseCheckpoint, world: &World, running: &Running) -> Result<(), String> {
    let extra = postcard::to_stdvec(running).map_err(|e| format!("{}: {e}", c.path.display()))?;
    let bytes = crate::checkpoint::encode(c.scene, world, &extra);
    crate::checkpoint::write_atomic(&c.path, &bytes).map_err(|e| e.to_string())
}

/// The world and running table of a case's state file.
fn resumed(c: &CaseCheckpoint, model: Model) -> Result<(World, Running), String> {
    let bytes = std::fs::read(&c.path).map_err(|e| format!("{}: {e}", c.path.display()))?;
    let (extra, world) =
        crate::checkpoint::decode(&c.path, &bytes, c.scene, model).map_err(|e| e.to_string())?;
    let running = postcard::from_bytes(extra).map_err(|e| format!("{}: {e}", c.path.display()))?;
    Ok((world, running))
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
