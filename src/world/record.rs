//! Stage 6: what a step produced, as typed values the writers format.

use crate::cluster::FactorError;
use crate::contact::{ContactKey, ContactKind};
use crate::geometry::Vec2;
use std::fmt;

/// Contact state as written to `contacts.csv`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ContactState {
    Open,
    Stick,
    Slide,
    /// Intact cemented joint (math note §4.5).
    Bonded,
}

impl ContactState {
    pub fn as_str(self) -> &'static str {
        match self {
            ContactState::Open => "open",
            ContactState::Stick => "stick",
            ContactState::Slide => "slide",
            ContactState::Bonded => "bonded",
        }
    }
}

/// One contact's result for a step.
#[derive(Debug, Clone)]
pub struct ContactRecord {
    pub key: ContactKey,
    pub kind: ContactKind,
    /// The body the normal points into (edge owner, particle of a particle-block contact).
    pub body_a: usize,
    pub body_b: usize,
    pub point: Vec2,
    pub normal: Vec2,
    /// Compression-positive normal force p_n [N/m].
    pub normal_force: f64,
    /// Tangential force along τ = cw(n), acting on body A [N/m].
    pub shear_force: f64,
    /// Rolling-resistance couple on body A, ccw positive [N m/m]; `None` without a rolling row.
    pub rolling_moment: Option<f64>,
    /// Normal gap at the end of the step (linearized, solve 1) [m].
    pub gap: f64,
    pub state: ContactState,
    /// The interface whose law the contact takes (index into the model's), `None` for the
    /// smooth law of a scene without a default interface.
    pub interface: Option<usize>,
}

/// Which VI solve of a step (math note §1.3, §10.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SolveKind {
    /// Solve 1, on the step-start linearization.
    Geometry,
    /// Solve 1 again after a mid-step refinement (math note §10.1).
    GeometryRefined,
    /// Solve 2 (velocity).
    Velocity,
}

impl fmt::Display for SolveKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            SolveKind::Geometry => "solve 1",
            SolveKind::GeometryRefined => "solve 1, refined",
            SolveKind::Velocity => "solve 2",
        })
    }
}

/// Numerical trouble worth a line in the run log.
#[derive(Debug, Clone, PartialEq)]
pub enum Warning {
    /// A VI solve stopped above its tolerance.
    NotConverged { step: usize, solve: SolveKind, residual: f64, iterations: usize },
    /// Two bodies started the step penetrating deeper than 5 % of the contact threshold.
    Penetration { step: usize, body_a: String, body_b: String, depth: f64 },
    /// What would have failed the step with `[time] adaptive = true` (math note §10.8).
    Trouble { step: usize, trouble: super::Trouble },
    /// Solve 2 with the friction stops of math note §10.15 missed its tolerance (`residual`
    /// after `iterations`) and was solved again without them.
    StopsDropped { step: usize, residual: f64, iterations: usize },
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Warning::NotConverged { step, solve, residual, iterations } => write!(
                f,
                "step {step}: contact solver ({solve}) did not converge: residual {residual:.3e} after {iterations} iterations"
            ),
            Warning::Penetration { step, body_a, body_b, depth } => {
                write!(f, "step {step}: bodies {body_a} and {body_b} penetrate by {depth:.3e} m")
            }
            Warning::Trouble { step, trouble } => write!(f, "step {step}: {trouble}"),
            Warning::StopsDropped { step, residual, iterations } => write!(
                f,
                "step {step}: solve 2 with friction stops did not converge (residual {residual:.3e} after \
                 {iterations} iterations); solved without them, so a body friction stopped may keep a velocity"
            ),
        }
    }
}

/// A method of the VI chain that handed a solve over to the next (math note §4.17): a line
/// of the run log.
#[derive(Debug, Clone, PartialEq)]
pub struct HandOver {
    pub step: usize,
    pub solve: SolveKind,
    pub from: crate::vi::Method,
    pub to: crate::vi::Method,
    /// Why `from` did not answer.
    pub why: &'static str,
}

impl fmt::Display for HandOver {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let HandOver { step, solve, from, to, why } = self;
        write!(f, "step {step} ({solve}): {from} handed over to {to} ({why})")
    }
}

/// Events of the physics worth a line in the run log.
#[derive(Debug, Clone, PartialEq)]
pub enum Event {
    /// A cemented contact reached its tensile share and opened (math note §4.5).
    JointBroke { step: usize, body_a: String, body_b: String, point: Vec2 },
    /// A connector's tension exceeded its strength: it broke for good and the step was solved
    /// again without it (math note §6).
    ConnectorBroke { step: usize, connector: String, force: f64 },
    /// A trial failed and the rest of the step runs as trials of length `dt` (math note §10.8).
    StepSplit { step: usize, dt: f64, cause: String },
    /// A stage started before step `step` (math note §10.14): the bodies it removed and the
    /// connectors that came into being (those on a removed body do not, `unborn`).
    StageStarted {
        step: usize,
        time: f64,
        stage: String,
        removed: Vec<String>,
        connectors: Vec<String>,
        unborn: Vec<String>,
    },
    /// A stage ended with step `step`, and why.
    StageEnded { step: usize, time: f64, stage: String, end: super::stages::StageEnd },
}

impl fmt::Display for Event {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Event::JointBroke { step, body_a, body_b, point } => write!(
                f,
                "step {step}: cemented contact between {body_a} and {body_b} at ({}, {}) broke",
                point.x, point.y
            ),
            Event::ConnectorBroke { step, connector, force } => write!(
                f,
                "step {step}: connector {connector} broke at axial force {force} N; the step was solved again without it"
            ),
            Event::StepSplit { step, dt, cause } => {
                write!(f, "step {step}: {cause}; repeated with dt = {dt:e}")
            }
            Event::StageStarted { step, time, stage, removed, connectors, unborn } => {
                write!(f, "step {step}: stage \"{stage}\" starts at t = {time}")?;
                for (what, list) in [
                    ("removed", removed),
                    ("connectors installed", connectors),
                    ("connectors not installed (a body of theirs is removed)", unborn),
                ] {
                    if !list.is_empty() {
                        write!(f, "; {what}: {}", list.join(", "))?;
                    }
                }
                Ok(())
            }
            Event::StageEnded { step, time, stage, end } => {
                write!(f, "step {step}: stage \"{stage}\" ended at t = {time}: {end}")
            }
        }
    }
}

/// Wall time of the stages of one step [s] (measurement only; never used by the physics).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StageTimes {
    /// Factorization of the step stiffness and the prediction d^f (stages 0-1).
    pub predict: f64,
    /// Broad and narrow phase (stage 2).
    pub detect: f64,
    /// Contact rows and W, every pass (stage 3).
    pub rows: f64,
    /// VI solves (stage 4).
    pub vi: f64,
    /// Mid-step refinements and the rest of stage 4 (classification, increments).
    pub refine: f64,
    /// Update, breakage, memory and records (stages 5-6).
    pub update: f64,
}

impl StageTimes {
    /// Adds another trial's times.
    pub fn add(&mut self, o: &StageTimes) {
        self.predict += o.predict;
        self.detect += o.detect;
        self.rows += o.rows;
        self.vi += o.vi;
        self.refine += o.refine;
        self.update += o.update;
    }
}

impl fmt::Display for StageTimes {
    /// The stage times in milliseconds, in step order.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let ms = |x: f64| x * 1e3;
        write!(
            f,
            "factorization+prediction {:.2}, detect {:.2}, rows+W {:.2}, VI {:.2}, refine {:.2}, update {:.2} ms",
            ms(self.predict),
            ms(self.detect),
            ms(self.rows),
            ms(self.vi),
            ms(self.refine),
            ms(self.update)
        )
    }
}

/// What one step produced.
#[derive(Debug, Clone)]
pub struct StepRecord {
    pub step: usize,
    pub time: f64,
    pub dt: f64,
    /// The step's contacts, in key order; empty when the world was asked for none
    /// ([`super::Settings::contact_records`]).
    pub contacts: Vec<ContactRecord>,
    /// How many contacts the step had (with or without their records).
    pub contact_count: usize,
    pub outer_iterations: usize,
    pub inner_iterations: usize,
    pub residual: f64,
    pub converged: bool,
    /// The method of the VI chain whose answer the step took: of the step's solves, the one
    /// answered latest in the chain's order (`None`: no solve ran a method, e.g. no contacts).
    pub method: Option<crate::vi::Method>,
    /// The hand-overs between the chain's methods in the step's solves, in order.
    pub handovers: Vec<HandOver>,
    pub kinetic_energy: f64,
    /// The kinetic energy per unit mass of the free bodies on the step's mean velocity d/dt
    /// [J/kg] (math note §10.14); computed in staged runs only (0 otherwise).
    pub mean_kinetic: f64,
    /// Index into `Model::stages` of the step's stage (0 without stages).
    pub stage: usize,
    pub wall_seconds: f64,
    pub stages: StageTimes,
    pub warnings: Vec<Warning>,
    pub events: Vec<Event>,
}

/// Numerical failure that stops a run.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum StepError {
    /// A trial of the smallest allowed length failed (math note §10.8). `hint`: what to do
    /// about a known cause (a contact solve of stiff deformable disks, math note §10.13).
    #[error("step {step} failed at dt = {dt:e}: {trouble}{}", .hint.as_ref().map(|h| format!("; {h}")).unwrap_or_default())]
    Failed { step: usize, dt: f64, trouble: super::Trouble, hint: Option<String> },
    #[error("step {step}: {source}")]
    Singular { step: usize, source: FactorError },
}
