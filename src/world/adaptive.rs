//! Steps that fail are repeated with half the time step (math note §10.8).
//!
//! [`World::step`] advances one scene step of length dt. It runs it as one *trial*; a trial
//! that fails — the VI did not converge (unless `[solver] allow_unconverged`), a displacement
//! is not finite, a body moved farther than the contact detection could see, or a contact
//! penetrates deeper than 5 % of d0 and deeper than at the trial's start — is dropped and the
//! rest of the step is run as trials of half the length, down to dt / 2^max_halvings. If a
//! trial of the smallest length fails, the run stops with [`StepError::Failed`], naming the
//! step, the cause and the bodies. Output times stay on the scene's grid: the record of a split
//! step is the merge of its trials, at the end of the step, with `dt` the smallest trial length
//! used and an [`Event::StepSplit`] per halving.
//!
//! A trial computes its outcome as values and commits them into the World once, at its end,
//! after its last check ([`World::commit`]): the increments of the bodies, the connectors'
//! breaks, yield switches and end forces ([`Next`]), the DOF map after a break, the joints
//! that broke, time and the penetration allowance. Its checks read those values: the
//! penetration check detects contacts on the bodies' shapes moved by the increments
//! ([`World::moved_shapes`]), without moving the bodies. A failed trial changes no state; its
//! values are dropped when the next trial starts. The factor cache, the VI solver's step
//! length and the broad phase's pairs are the step's working memory, not values of a trial:
//! every trial updates them as it runs, a failed one too.

use super::update::Motion;
use super::{Event, StepError, StepRecord, World};
use crate::body::{Body, Outline, max_displacement};
use crate::connector::Connector;
use crate::contact::{BodyShape, ContactKey};
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

/// The values of the running trial that its solves read again (math note §10.8): kept in the
/// World beside the state of the step's start, which they replace only when the trial is
/// committed ([`World::commit`]). Each trial starts them afresh from the World's.
#[derive(Clone, Default)]
pub(super) struct Next {
    /// The connectors: the step start's with the trial's breaks and yield switches, after the
    /// update with their forces and anchors at the trial's end.
    pub connectors: Vec<Connector>,
    /// The DOF map and clusters after a connector broke in the trial.
    pub dofs: Option<DofMap>,
    /// The cemented joints that broke in the trial.
    pub broken: HashSet<ContactKey>,
}

impl Next {
    /// A trial's values before it has changed anything: the World's connectors `connectors`
    /// (copied into the storage of the last trial's), the World's DOF map and broken joints.
    pub(super) fn start(&mut self, connectors: &[Connector]) {
        self.connectors.clear();
        self.connectors.extend_from_slice(connectors);
        self.dofs = None;
        self.broken.clear();
    }
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
            match self.trial(h, t1) {
                Ok(rec) => {
                    merged = Some(match merged {
                        Some(m) => merge(m, rec),
                        None => rec,
                    });
                    done += 1;
                }
                Err(Failure::Fatal(e)) => return Err(self.dropped(e)),
                Err(Failure::Retry(trouble)) if level < most => {
                    (level, done) = (level + 1, done * 2);
                    splits.push(Event::StepSplit {
                        step,
                        dt: dt / (1u64 << level) as f64,
                        cause: trouble.to_string(),
                    });
                }
                Err(Failure::Retry(trouble)) => {
                    let hint = match trouble {
                        Trouble::NotConverged { .. } => self.stiff_disks(),
                        _ => None,
                    };
                    return Err(self.dropped(StepError::Failed { step, dt: h, trouble, hint }));
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

    /// Drops the values of the trial that failed with `e` (the World stays at the step's start).
    fn dropped(&mut self, e: StepError) -> StepError {
        self.next.start(&[]);
        e
    }

    /// Commits the values of a trial that passed its checks (module docs), as one step from
    /// the step's start: the trial's DOF map, its connectors with their forces and anchors
    /// after `motion` ([`Self::update_connectors`], step `step`), its broken joints, the
    /// penetration allowance `allowance`, the bodies and tracked points moved by `motion` over
    /// the trial's length `dt` ([`Self::update`]), time `t1`. Returns the bodies' kinetic
    /// energy after it.
    pub(super) fn commit(&mut self, motion: &Motion, step: usize, dt: f64, t1: f64, allowance: f64) -> f64 {
        if let Some(dofs) = self.next.dofs.take() {
            self.dofs = dofs;
        }
        self.update_connectors(&motion.dbar, step);
        std::mem::swap(&mut self.connectors, &mut self.next.connectors);
        self.broken.extend(self.next.broken.drain());
        self.allowance = allowance;
        let kinetic = self.update(motion, dt);
        (self.time, self.started) = (t1, true);
        kinetic
    }

    /// Per body, the largest motion of a point under the increment `dbar`, from the bodies'
    /// reaches `reach` (`Detected::reach`; a mesh's motion is its fastest node's).
    pub(super) fn motions(&self, reach: &[Option<f64>], dbar: &[f64]) -> Vec<f64> {
        let dofs = self.dof_map();
        let motion = |b: usize, reach: Option<f64>| {
            let d = &dbar[dofs.range(b)];
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

    /// The bodies' shapes and fixed flags as contact detection reads them, moved by the trial's
    /// increment `dbar`: the shapes the bodies take when the trial is committed
    /// ([`Body::moved_shape`]).
    pub(super) fn moved_shapes(&self, dbar: &[f64]) -> (Vec<BodyShape>, Vec<bool>) {
        let dofs = self.dof_map();
        let moved = |(b, body): (usize, &Body)| (body.moved_shape(&dbar[dofs.range(b)]), body.fixed);
        self.bodies.iter().enumerate().map(moved).unzip()
    }

    /// The first contact of the trial's end configuration (`shapes` and `fixed`:
    /// [`Self::moved_shapes`]) that penetrates deeper than 5 % of d0
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
        (shapes, fixed): (Vec<BodyShape>, Vec<bool>),
        before: &super::detect::Geoms,
        threshold: f64,
        cache: &mut crate::contact::broad::PairCache,
    ) -> Option<Trouble> {
        let limit = self.penetration_limit();
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
