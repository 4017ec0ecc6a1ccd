//! Steps that fail are repeated with half the time step (math note §10.8).
//!
//! [`World::step`] advances one scene step of length dt. It runs it as one *trial*; a trial
//! that fails — the VI did not converge (unless `[solver] allow_unconverged`), a displacement
//! is not finite, a body moved farther than the contact detection could see, or a contact
//! penetrates deeper than 5 % of d0 and deeper than at the trial's start — is undone (what it
//! changed was saved as it changed it: [`Undo`]) and the rest of the step is run as trials of
//! half the length, down to dt / 2^max_halvings. If a trial of the smallest length fails, the
//! run stops with [`StepError::Failed`], naming the step, the cause and the bodies. Output
//! times stay on the scene's grid: the record of a split step is the merge of its trials, at
//! the end of the step, with `dt` the smallest trial length used and an [`Event::StepSplit`]
//! per halving.

use super::{Event, StepError, StepRecord, TrackedPoint, World};
use crate::body::{Body, Outline, max_displacement};
use crate::connector::Connector;
use crate::contact::ContactKey;
use crate::dofs::DofMap;
use std::collections::HashSet;
use std::fmt;
use std::time::Instant;

/// Why a trial step failed (math note §10.8).
#[derive(Debug, Clone, PartialEq)]
pub enum Trouble {
    /// The contact VI stopped above its tolerance.
    NotConverged { residual: f64, iterations: usize },
    /// A displacement or velocity is NaN or infinite.
    NonFinite { bodies: Vec<String> },
    /// A body moved more than half the detection threshold: contacts it could meet were not seen.
    MovedTooFar { body: String, motion: f64, limit: f64 },
    /// Two bodies penetrate deeper than 5 % of d0, and deeper than at the trial's start.
    Penetration { body_a: String, body_b: String, depth: f64, limit: f64 },
}

impl fmt::Display for Trouble {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Trouble::NotConverged { residual, iterations } => write!(
                f,
                "the contact solver did not converge (residual {residual:.3e} after {iterations} iterations)"
            ),
            Trouble::NonFinite { bodies } => {
                write!(f, "non-finite displacement in bodies {}", bodies.join(", "))
            }
            Trouble::MovedTooFar { body, motion, limit } => write!(
                f,
                "body {body} moved {motion:.3e} m, more than the {limit:.3e} m the contact detection covers \
                 (half of [contact] threshold)"
            ),
            Trouble::Penetration { body_a, body_b, depth, limit } => {
                write!(f, "bodies {body_a} and {body_b} penetrate by {depth:.3e} m (limit {limit:.3e} m)")
            }
        }
    }
}

/// A trial's outcome when it is not a record: repeat it shorter, or stop.
pub(super) enum Failure {
    Retry(Trouble),
    Fatal(StepError),
}

impl From<Trouble> for Failure {
    fn from(t: Trouble) -> Failure {
        Failure::Retry(t)
    }
}

/// What a trial has changed of the state, saved as the trial first changes it (math note
/// §10.8), so that a failed trial can be undone. The scalars are saved when the trial starts;
/// each other part by [`World::keep`] just before the trial first changes it, and only while a
/// later check can still fail the trial. The contact memory is never saved: a trial changes it
/// last, after its last check: a step whose trials never fail copies nothing (a copy of every
/// body and of the contact memory is a visible share of a warm step, `benches/step.rs`).
#[derive(Clone, Default)]
pub(super) struct Undo {
    time: f64,
    started: bool,
    allowance: f64,
    bodies: Option<(Vec<Body>, Vec<TrackedPoint>, Vec<TrackedPoint>)>,
    connectors: Option<Vec<Connector>>,
    dofs: Option<DofMap>,
    broken: Option<HashSet<ContactKey>>,
}

/// A part of the state a trial changes ([`World::keep`]).
#[derive(Debug, Clone, Copy)]
pub(super) enum Part {
    /// The bodies and the points that move with them.
    Bodies,
    Connectors,
    Dofs,
    /// The broken joints.
    Broken,
}

impl World {
    /// Advances one step of length dt, repeating failed trials with half the length (module
    /// docs; math note §10.8).
    pub fn step(&mut self) -> Result<StepRecord, StepError> {
        let started = Instant::now();
        let stage_starts = self.stage_start();
        let time = self.model.time;
        let (step, dt, t0) = (self.step_index + 1, time.step, self.time);
        let most = if time.adaptive { time.max_halvings } else { 0 };
        // `done` trials of length dt / 2^level so far
        let (mut level, mut done, mut merged, mut splits) = (0u32, 0u64, None::<StepRecord>, Vec::new());
        while done < 1 << level {
            let h = dt / (1u64 << level) as f64;
            // time as step × dt at the step's end, not accumulated
            let t1 = if done + 1 == 1 << level { step as f64 * dt } else { t0 + (done + 1) as f64 * h };
            let (time, started, allowance) = (self.time, self.started, self.allowance);
            self.undo = (level < most).then(|| Undo { time, started, allowance, ..Undo::default() });
            let outcome = self.trial(h, t1);
            match (outcome, self.undo.take()) {
                (Ok(rec), _) => {
                    merged = Some(match merged {
                        Some(m) => merge(m, rec),
                        None => rec,
                    });
                    done += 1;
                }
                (Err(Failure::Fatal(e)), _) => return Err(e),
                (Err(Failure::Retry(trouble)), Some(undo)) => {
                    self.restore(undo);
                    (level, done) = (level + 1, done * 2);
                    splits.push(Event::StepSplit {
                        step,
                        dt: dt / (1u64 << level) as f64,
                        cause: trouble.to_string(),
                    });
                }
                (Err(Failure::Retry(trouble)), None) => {
                    let hint = match trouble {
                        Trouble::NotConverged { .. } => self.stiff_disks(),
                        _ => None,
                    };
                    return Err(StepError::Failed { step, dt: h, trouble, hint });
                }
            }
        }
        let mut rec = merged.expect("at least one trial");
        splits.append(&mut rec.events);
        rec.events = stage_starts;
        rec.events.append(&mut splits);
        rec.wall_seconds = started.elapsed().as_secs_f64();
        self.step_index = step;
        self.stage_step(&mut rec);
        Ok(rec)
    }

    /// For a contact solve that failed: the free deformable disk of largest Π = ρ r² / (E dt²)
    /// at the scene's dt when Π is above twice the tolerance, where frictional piles of such
    /// disks stop at near-solutions above it (math note §10.13), with what to do.
    fn stiff_disks(&self) -> Option<String> {
        let (tolerance, dt) = (self.model.solver.tolerance, self.model.time.step);
        let (pi, name) = (self.bodies.iter())
            .filter(|b| b.deformable && !b.fixed)
            .filter_map(|b| {
                let Outline::Disk { radius } = b.outline else { return None };
                let material = &self.model.materials[b.material];
                let pi = material.density * radius * radius / (material.young? * dt * dt);
                Some((pi, &b.name))
            })
            .max_by(|a, b| a.0.total_cmp(&b.0))?;
        (pi > 2.0 * tolerance).then(|| {
            format!(
                "deformable disk {name} has Π = ρ r² / (E dt²) = {pi:.1e} at the scene's dt, more than \
                 twice the tolerance {tolerance:e}: a pile of such disks with friction may not converge \
                 below about Π / 2, and shorter steps raise Π; loosen [solver] tolerance to about Π / 2, or set \
                 allow_unconverged = true and read `residual` in steps.csv (README, \"Known limitations\")"
            )
        })
    }

    /// Saves `part` into the trial's undo, unless it is saved already or the trial cannot be
    /// undone (no retry left, or no check left that could fail it).
    pub(super) fn keep(&mut self, part: Part) {
        let Some(u) = &mut self.undo else { return };
        match part {
            Part::Bodies => {
                u.bodies.get_or_insert_with(|| {
                    (self.bodies.clone(), self.load_points.clone(), self.monitors.clone())
                });
            }
            Part::Connectors => {
                u.connectors.get_or_insert_with(|| self.connectors.clone());
            }
            Part::Dofs => {
                u.dofs.get_or_insert_with(|| self.dofs.clone());
            }
            Part::Broken => {
                u.broken.get_or_insert_with(|| self.broken.clone());
            }
        }
    }

    fn restore(&mut self, u: Undo) {
        (self.time, self.started, self.allowance) = (u.time, u.started, u.allowance);
        if let Some((bodies, load_points, monitors)) = u.bodies {
            (self.bodies, self.load_points, self.monitors) = (bodies, load_points, monitors);
        }
        if let Some(connectors) = u.connectors {
            self.connectors = connectors;
        }
        if let Some(dofs) = u.dofs {
            self.dofs = dofs;
        }
        if let Some(broken) = u.broken {
            self.broken = broken;
        }
    }

    /// Per body, the largest motion of a point under the increment `dbar`, from the bodies'
    /// reaches `reach` (`Detected::reach`; a mesh's motion is its fastest node's).
    pub(super) fn motions(&self, reach: &[Option<f64>], dbar: &[f64]) -> Vec<f64> {
        let motion = |b: usize, reach: Option<f64>| {
            let d = &dbar[self.dofs.range(b)];
            reach.map_or_else(|| self.bodies[b].max_motion(d), |r| max_displacement(d, r))
        };
        reach.iter().enumerate().map(|(b, &r)| motion(b, r)).collect()
    }

    /// The first body whose largest point motion (`motions`) is farther than half the detection
    /// threshold `threshold` (two bodies closing from both sides then meet within it).
    pub(super) fn moved_too_far(&self, motions: &[f64], threshold: f64) -> Option<Trouble> {
        let limit = 0.5 * threshold;
        motions.iter().enumerate().find_map(|(b, &motion)| {
            // a NaN motion counts as too far
            (motion.is_nan() || motion > limit).then(|| Trouble::MovedTooFar {
                body: self.bodies[b].name.clone(),
                motion,
                limit,
            })
        })
    }

    /// The depth from which a penetration fails a trial: 5 % of d0 (math note §10.8).
    fn penetration_limit(&self) -> f64 {
        0.05 * self.threshold
    }

    /// Whether some body's largest point motion (`motions`) reaches half of 1e-3 of the
    /// penetration limit: otherwise no penetration can grow past its start by that 1e-3 of the
    /// limit (a depth grows by at most its two bodies' motions), and [`Self::new_penetration`]
    /// would find none.
    pub(super) fn may_penetrate(&self, motions: &[f64]) -> bool {
        let limit = self.penetration_limit();
        !motions.iter().all(|&m| m <= 0.5e-3 * limit)
    }

    /// The first contact of the current configuration that penetrates deeper than 5 % of d0
    /// and deeper than at the trial's start (`before`: the trial's contacts, detected sorted by
    /// key, with their start gaps; a start overlap that does not grow, by more than 1e-3 of the
    /// limit, is tolerated, since no shorter step can undo it).
    /// Detection runs with the trial's threshold `threshold`: the narrow phase reports a
    /// penetration only within it. Its candidate pairs come from the pairs kept between steps
    /// (`cache`, the step's own detection's): the sweep's pairs, in its order, without the sweep
    /// while the bodies stay inside their grown boxes (the sweep is most of this check's cost on
    /// a large pile that moves). The caller asks only when
    /// [`Self::may_penetrate`] holds (otherwise no contact can qualify, math note §10.8).
    pub(super) fn new_penetration(
        &self,
        before: &super::detect::Geoms,
        threshold: f64,
        cache: &mut crate::contact::broad::PairCache,
    ) -> Option<Trouble> {
        let limit = self.penetration_limit();
        let (shapes, fixed) = self.shapes_and_fixed();
        let mut pairs = cache.candidate_pairs(&shapes, &fixed, threshold);
        self.without_removed(&mut pairs);
        let found = crate::contact::detect_in(&shapes, pairs, threshold, threshold);
        // the start overlap is looked up only for a contact deeper than the limit, not by a
        // bisection for every contact's key
        found.into_iter().filter(|g| -g.g0 > limit).find_map(|g| {
            let start = before.find(&g.key).map_or(0.0, |b| (-b.g0).max(0.0));
            let depth = -g.g0;
            (depth > start + 1e-3 * limit).then(|| Trouble::Penetration {
                body_a: self.bodies[g.a].name.clone(),
                body_b: self.bodies[g.b].name.clone(),
                depth,
                limit,
            })
        })
    }
}

/// One record for a step run as several trials: the state of the last, the work of all.
fn merge(a: StepRecord, b: StepRecord) -> StepRecord {
    let mut stages = a.stages;
    stages.add(&b.stages);
    let (mut warnings, mut events, mut handovers) = (a.warnings, a.events, a.handovers);
    warnings.extend(b.warnings);
    handovers.extend(b.handovers);
    events.extend(b.events);
    StepRecord {
        dt: a.dt.min(b.dt),
        outer_iterations: a.outer_iterations + b.outer_iterations,
        inner_iterations: a.inner_iterations + b.inner_iterations,
        residual: a.residual.max(b.residual),
        converged: a.converged && b.converged,
        stages,
        warnings,
        events,
        handovers,
        ..b
    }
}
