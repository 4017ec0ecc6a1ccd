//! Stages of a run (math note §10.14): a stage starts with its settings, removes bodies and
//! brings connectors into being; it ends at its end time, or earlier once its kinetic energy
//! per unit mass on the steps' mean velocity d/dt has stayed below `until_kinetic` for
//! [`QUIET_STEPS`] steps.
//!
//! A removed body keeps its index (names, monitors and output columns stay put) and becomes a
//! fixed body that no contact sees: it has no DOFs ([`crate::dofs::DofMap`] numbers free bodies
//! only), detection drops every pair that holds it ([`World::without_removed`]), its connectors
//! break, and bodies.csv leaves it out. A connector not yet in being is held as a broken one
//! (no stiffness, no force, no coupling, not written), whose anchors still move with their
//! bodies; at its stage it is built afresh from its spec at the anchors' current positions, so
//! it starts unstressed (plus its pretension).

use std::fmt;

use super::{Event, StepRecord, World};
use crate::body::Dofs;
use crate::connector::Connector;
use crate::geometry::Vec2;
use crate::model::{ConnectorSpec, QUIET_STEPS, history_factor};

/// Where a staged run is (all empty or zero in a run without stages).
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct StageState {
    /// Index into `Model::stages` of the current stage.
    pub current: usize,
    /// Consecutive steps of the current stage below its `until_kinetic`.
    quiet: usize,
    /// Per body: removed by a stage (empty while no body is).
    pub removed: Vec<bool>,
    /// Per connector: not yet in being.
    pub pending: Vec<bool>,
    /// Stage starts for the next step's record (empty between steps after the first: not in a
    /// checkpoint's state).
    #[serde(skip)]
    events: Vec<Event>,
}

/// Why a stage ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StageEnd {
    /// At its `end`; `until_kinetic` is the stage's, if it had one (then never met).
    EndTime { until_kinetic: Option<f64> },
    /// Its kinetic energy per unit mass stayed below `until_kinetic` for [`QUIET_STEPS`] steps.
    Quiet { until_kinetic: f64 },
}

impl fmt::Display for StageEnd {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StageEnd::EndTime { until_kinetic: None } => write!(f, "its end time"),
            StageEnd::EndTime { until_kinetic: Some(u) } => write!(
                f,
                "its end time; until_kinetic = {u} J/kg was not met (the kinetic energy per unit mass did not \
                 stay below it for {QUIET_STEPS} steps)"
            ),
            StageEnd::Quiet { until_kinetic } => write!(
                f,
                "until_kinetic met: the kinetic energy per unit mass stayed below {until_kinetic} J/kg for \
                 {QUIET_STEPS} steps"
            ),
        }
    }
}

impl World {
    /// Starts the first stage at t = 0 (a new world).
    pub(super) fn first_stage(&mut self) {
        if self.model.stages.is_empty() {
            return;
        }
        let mut pending = vec![false; self.connectors.len()];
        for &c in self.model.stages.iter().flat_map(|s| &s.connectors) {
            pending[c] = true;
            self.connectors[c].break_off();
        }
        self.stage.pending = pending;
        self.enter(0);
    }

    /// Why the current stage is over after the last step, if it is.
    fn stage_over(&self) -> Option<StageEnd> {
        let stage = self.model.stages.get(self.stage.current)?;
        match stage.until_kinetic {
            Some(u) if self.stage.quiet >= QUIET_STEPS => Some(StageEnd::Quiet { until_kinetic: u }),
            u if self.step_index >= stage.end_step => Some(StageEnd::EndTime { until_kinetic: u }),
            _ => None,
        }
    }

    /// Whether the run is over: its last step done, or its last stage over.
    pub fn finished(&self) -> bool {
        let last = self.stage.current + 1 >= self.model.stages.len();
        self.step_index >= self.model.time.steps || (last && self.stage_over().is_some())
    }

    /// Before a step: starts the next stage if the current one is over. Returns the stage
    /// starts to report in the step's record.
    pub(super) fn stage_start(&mut self) -> Vec<Event> {
        if self.stage_over().is_some() && self.stage.current + 1 < self.model.stages.len() {
            self.enter(self.stage.current + 1);
        }
        std::mem::take(&mut self.stage.events)
    }

    /// After a step: counts it towards `until_kinetic` and reports the end of its stage.
    pub(super) fn stage_step(&mut self, rec: &mut StepRecord) {
        let Some(stage) = self.model.stages.get(self.stage.current) else { return };
        if let Some(u) = stage.until_kinetic {
            self.stage.quiet = if rec.mean_kinetic < u { self.stage.quiet + 1 } else { 0 };
        }
        if let Some(end) = self.stage_over() {
            let (step, time, stage) = (rec.step, rec.time, stage.name.clone());
            rec.events.push(Event::StageEnded { step, time, stage, end });
        }
    }

    /// Starts stage `k`: its settings, removals and connectors (module docs).
    fn enter(&mut self, k: usize) {
        let stage = self.model.stages[k].clone();
        if self.started {
            // the velocity the last stage's carry leaves (a static stage hands over bodies at rest)
            self.scale_velocities(self.model.physics.velocity_carry);
        }
        self.current_settings(stage.settings);
        let step = self.step_index + 1;
        let mut removed = Vec::new();
        for &b in &stage.remove {
            self.remove_body(b, step);
            removed.push(self.bodies[b].name.clone());
        }
        let (mut connectors, mut unborn) = (Vec::new(), Vec::new());
        for &c in &stage.connectors {
            let spec = &self.model.connectors[c];
            if spec.bodies.iter().any(|&b| self.is_removed(b)) {
                unborn.push(spec.name.clone());
                continue;
            }
            let here = ConnectorSpec { points: self.connectors[c].anchors, ..spec.clone() };
            self.connectors[c] = Connector::from_spec(&here).held_in(&self.bodies);
            self.stage.pending[c] = false;
            connectors.push(spec.name.clone());
        }
        self.renumber();
        self.stage.current = k;
        self.stage.quiet = 0;
        let (time, stage) = (self.time, stage.name);
        self.stage.events.push(Event::StageStarted { step, time, stage, removed, connectors, unborn });
    }

    /// The model with the settings of the current stage, as its start set them (a world loaded
    /// from a checkpoint's state, `snapshot.rs`).
    pub(super) fn stage_settings(&mut self) {
        if let Some(stage) = self.model.stages.get(self.stage.current) {
            self.current_settings(stage.settings.clone());
        }
    }

    /// Makes `s` the model's physics, solver, interfaces, loads and gravity history.
    fn current_settings(&mut self, s: crate::model::StageSettings) {
        (self.model.physics, self.model.solver) = (s.physics, s.solver);
        (self.model.interfaces, self.model.loads, self.model.gravity_history) =
            (s.interfaces, s.loads, s.gravity_history);
    }

    /// Takes body `b` out of the run before step `step`: fixed, at rest, seen by no contact;
    /// its connectors break (connectors.csv shows them broken at that step).
    fn remove_body(&mut self, b: usize, step: usize) {
        if self.stage.removed.is_empty() {
            self.stage.removed = vec![false; self.bodies.len()];
        }
        self.stage.removed[b] = true;
        let body = &mut self.bodies[b];
        body.fixed = true;
        body.velocity = Dofs::zeros();
        if let Some(fe) = &mut body.mesh {
            fe.velocity.iter_mut().for_each(|v| *v = 0.0);
        }
        for (c, connector) in self.connectors.iter_mut().enumerate() {
            let pending = self.stage.pending.get(c).copied().unwrap_or(false);
            if connector.bodies.contains(&b) && !connector.broken && !pending {
                connector.break_off();
                connector.broken_at = Some(step);
            }
        }
    }

    /// The name of the current stage (`None` without stages).
    pub fn stage_name(&self) -> Option<&str> {
        self.model.stages.get(self.stage.current).map(|s| s.name.as_str())
    }

    /// Whether body `b` has been removed by a stage.
    pub fn is_removed(&self, b: usize) -> bool {
        self.stage.removed.get(b).copied().unwrap_or(false)
    }

    /// Drops the candidate pairs that hold a removed body.
    pub(super) fn without_removed(&self, pairs: &mut Vec<(usize, usize)>) {
        if !self.stage.removed.is_empty() {
            pairs.retain(|&(a, b)| !self.is_removed(a) && !self.is_removed(b));
        }
    }

    /// Multiplies every body's velocity by `k`.
    fn scale_velocities(&mut self, k: f64) {
        for body in &mut self.bodies {
            body.velocity *= k;
            if let Some(fe) = &mut body.mesh {
                fe.velocity.iter_mut().for_each(|v| *v *= k);
            }
        }
    }

    /// Gravity at time `t`: `[physics] gravity` times `gravity_history`'s factor.
    pub(super) fn gravity(&self, t: f64) -> Vec2 {
        self.model.physics.gravity * history_factor(self.model.gravity_history.as_deref(), t)
    }

    /// The kinetic energy per unit mass of the free bodies on the step's mean velocity d/dt
    /// (`dbar`, the geometry increment; math note §10.14): ½ (d/dt)ᵀ M (d/dt) summed, over their
    /// mass; a mesh with its lumped nodal masses. 0 in a run without stages, which reads it
    /// nowhere.
    pub(super) fn mean_kinetic(&self, dbar: &[f64], dt: f64) -> f64 {
        if self.model.stages.is_empty() {
            return 0.0;
        }
        let (mut energy, mut mass, dofs) = (0.0, 0.0, self.dof_map());
        for (b, body) in self.bodies.iter().enumerate().filter(|(_, b)| !b.fixed) {
            let d = &dbar[dofs.range(b)];
            mass += body.mass;
            energy += match &body.mesh {
                Some(fe) => {
                    let m = fe.nodal_masses();
                    (0..fe.nodes.len()).map(|n| 0.5 * m[n] * fe.node_value(d, n).norm_squared()).sum::<f64>()
                }
                None => {
                    let v = Dofs::from_fn(|i, _| d.get(i).copied().unwrap_or(0.0));
                    0.5 * v.dot(&body.mass_times(&v))
                }
            } / (dt * dt);
        }
        if mass > 0.0 { energy / mass } else { 0.0 }
    }
}
