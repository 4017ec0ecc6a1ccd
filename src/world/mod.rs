//! The simulation state and one time step, as the data flow of the architecture note. Each
//! stage is a function that takes the previous stage's output:
//!
//! ```text
//!   flexibility   K̃ per cluster, factorized (cached)              cluster.rs   (math note §1.2, §10.6)
//! 1 predict       d^f = K̃⁻¹ f  (global DOF vector)                predict.rs   (§1.2, §2.4)
//! 2 detect        broad + narrow phase -> geometries with laws    detect.rs    (§5, §4)
//! 3 rows          [Linearization] -> Rows: B, q, blocks, W        rows.rs      (§3.1, §10.1)
//! 4 solve         VI solve 1 (geometry), refined on the mid-step   solve.rs,    (§4, §1.3, §10.1-10.5)
//!                 configuration (new rows each time), solve 2     refine.rs
//!                 (velocity) -> Solved
//! 5 update        d̄ -> geometry and stress, d_vel -> velocity,    update.rs    (§1.3, paper eqs. 16-18)
//!                 breakage, contact memory
//! 6 record        StepRecord, typed warnings and events           record.rs
//! ```
//!
//! [`World`] holds the state a checkpoint saves ([`World::state`], `snapshot.rs`: bodies,
//! contact memory, connectors, stage, kept factors, time); the [`Pipeline`] it carries holds
//! scratch (the VI workspace, W's assembly storage, the Jacobians of earlier passes, the
//! refinement's shape buffers, the broad phase's pairs), reused across steps, and one value
//! that is state: the VI solver's MPRGP step-length guess, which the checkpoint saves too.

use crate::body::{Body, Dofs};
use crate::cluster::Flexibility;
use crate::connector::Connector;
use crate::contact::law::ContactBounds;
use crate::contact::set::{ContactMemory, interface_for};
use crate::contact::{BodyShape, ContactKey};
use crate::dofs::DofMap;
use crate::geometry::Vec2;
use crate::model::{Interface, Model};
use std::collections::HashSet;
use std::time::Instant;

mod adaptive;
mod connectors;
mod detect;
mod polish;
mod predict;
mod record;
mod refine;
mod rows;
mod snapshot;
mod solve;
mod stages;
mod update;
mod velocity;

pub use adaptive::Trouble;
pub use record::{
    ContactRecord, ContactState, Event, HandOver, SolveKind, StageTimes, StepError, StepRecord, Warning,
};
pub use snapshot::StateError;
pub use stages::{StageEnd, StageState};

/// Library-level switches that are not part of the scene format.
#[derive(Debug, Clone, Copy)]
pub struct Settings {
    /// Share an edge-edge joint's cohesion between its two contacts (math note §4.6). Off
    /// reproduces the DDA-d over-resistance of the paper's Table 3 (each contact gets all of c).
    pub share_cohesion: bool,
    /// Jacobi scaling in the VI solver (math note §4.2).
    pub jacobi: bool,
    /// Factorize every cluster, single bodies included, with the sparse Cholesky instead of
    /// the closed-form body inverse: a reference check of the sparse path.
    pub sparse_only: bool,
    /// Factor on the VI tolerances of a cold step, one whose contacts all start from zero force
    /// (math note §10.11); 1 turns the rule off.
    pub cold_tightening: f64,
    /// A step's VI solve that has to iterate stops at this fraction of the tolerance or one
    /// iteration past it ([`crate::vi::Options::aim`], math note §4.11); 1 stops at the
    /// tolerance.
    pub aim: f64,
    /// Make each step's contact records ([`StepRecord::contacts`]). A run that writes its state
    /// every N-th step asks for them on those steps only (`pbdda run`): on the 10,000-disk pile
    /// they were about 8 % of a warm step. The contact memory is made on every step either way,
    /// so the motion does not depend on it.
    pub contact_records: bool,
    /// Solve 2 holds the friction rows whose slip solve 1 stops (math note §10.15, "Friction
    /// stops"). Off by default: with it `tests/paper/slumping_pile.rs` takes about six times as long
    /// (its failed offset solves are solved again without them); off, the velocity of a
    /// friction-stopped body rings.
    pub friction_stops: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            share_cohesion: true,
            jacobi: true,
            sparse_only: false,
            cold_tightening: 1e-2,
            aim: crate::vi::AIM,
            contact_records: true,
            friction_stops: false,
        }
    }
}

/// A material point that moves with its body (load points, monitors).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct TrackedPoint {
    pub body: usize,
    pub initial: Vec2,
    pub current: Vec2,
}

/// Scratch memory of the step, reused across steps; nothing in it is state but the VI
/// solver's step-length guess ([`crate::vi::Solver::step_length`], saved by a checkpoint).
#[derive(Clone, Default)]
pub struct Pipeline {
    vi: crate::vi::Solver,
    /// Work storage of the rows: W's assembly and Jacobians of earlier passes.
    rows: rows::Scratch,
    /// The refinement's shape buffers.
    shapes: refine::Shapes,
    /// The broad phase's pairs, kept while the bodies stay inside their grown boxes.
    pairs: crate::contact::broad::PairCache,
}

impl Pipeline {
    /// Keeps the storage of rows that are no longer needed for the next ones.
    fn recycle(&mut self, rows: rows::Rows) {
        self.rows.spare.push(rows.w.into_jacobian());
    }
}

/// Simulation state: bodies in their current configuration and the memory of the contacts.
#[derive(Clone)]
pub struct World {
    pub model: Model,
    pub settings: Settings,
    pub bodies: Vec<Body>,
    /// Index of the last completed step (0 before the first).
    pub step_index: usize,
    pub time: f64,
    /// d0 of the scene (math note §5), before any per-step enlargement.
    pub threshold: f64,
    /// The smallest feature of the scene (particle radius, edge length) [m]; the solver's
    /// gaps are asked to be right to `tolerance` times it (math note §4.9).
    pub feature: f64,
    pub load_points: Vec<TrackedPoint>,
    pub monitors: Vec<TrackedPoint>,
    /// Bolts, springs and beams, in their state at the step start (broken ones included).
    pub connectors: Vec<Connector>,
    /// Body → global DOF range; clusters.
    pub dofs: DofMap,
    /// Where a staged run is: its stage, the removed bodies, the connectors not yet in being.
    pub stage: StageState,
    flex: Flexibility,
    memory: ContactMemory,
    /// Contacts of cemented joints that broke: their cohesion is lost for good (§4.5).
    broken: HashSet<ContactKey>,
    /// Penetration allowance [m] of math note §10.2, from the last step's solve.
    allowance: f64,
    /// Whether a (trial) step has been taken: v0 is the initial velocity before, k v1 after.
    started: bool,
    /// Length of the current trial step (dt, or a fraction of it: `adaptive.rs`).
    h: f64,
    /// The running trial's values that its solves read again, committed when it succeeds
    /// (`adaptive.rs`).
    next: adaptive::Next,
    pipeline: Pipeline,
}

impl World {
    pub fn new(model: Model) -> World {
        World::with_settings(model, Settings::default())
    }

    pub fn with_settings(model: Model, settings: Settings) -> World {
        let bodies: Vec<Body> = model
            .bodies
            .iter()
            .map(|s| Body::new(s, &model.materials[s.material], model.physics.plane))
            .collect();
        let track = |body: usize, p: Vec2| TrackedPoint { body, initial: p, current: p };
        let load_points = model.loads.iter().map(|l| track(l.body, l.point)).collect();
        let monitors = model.monitors.iter().map(|m| track(m.body, m.point)).collect();
        let feature = smallest_feature(&bodies);
        // Default d0: a tenth of the smallest feature, so that feature tests stay unambiguous
        // (math note §5); enlarged per step when motion needs it.
        let threshold = model.contact.threshold.unwrap_or(0.1 * feature);
        let connectors: Vec<Connector> =
            model.connectors.iter().map(|s| Connector::from_spec(s).held_in(&bodies)).collect();
        let mut world = World {
            model,
            settings,
            bodies,
            step_index: 0,
            time: 0.0,
            threshold,
            feature,
            load_points,
            monitors,
            connectors,
            dofs: DofMap::default(),
            stage: StageState::default(),
            flex: Flexibility::default(),
            memory: ContactMemory::default(),
            broken: HashSet::new(),
            allowance: 1e-9 * threshold,
            started: false,
            h: 0.0,
            next: adaptive::Next::default(),
            pipeline: Pipeline::default(),
        };
        world.renumber();
        world.cement();
        world.first_stage();
        world
    }

    /// One trial of length `dt` ending at time `t1` (`adaptive.rs` repeats failed ones): the
    /// six stages, top to bottom, computed as values from the step's start, then the checks of
    /// math note §10.8 on those values, then the commit of a trial that passed them.
    fn trial(&mut self, dt: f64, t1: f64) -> Result<StepRecord, adaptive::Failure> {
        let started = Instant::now();
        let mut clock = Clock(started);
        let mut stages = StageTimes::default();
        let step = self.step_index + 1;
        let mut events = Vec::new();
        self.h = dt;
        self.next.start(&self.connectors);
        let (contacts, solved, motion, threshold) =
            self.stages(dt, t1, &mut clock, &mut stages, &mut events)?;
        let r = &solved.report;
        if !r.converged && !self.model.solver.allow_unconverged {
            let (residual, iterations) = (r.residual, r.inner_iterations);
            return Err(adaptive::Trouble::NotConverged { residual, iterations }.into());
        }
        // with `adaptive = false` a trial is never repeated: motion and penetration are warnings
        let adaptive = self.model.time.adaptive;
        let mut warnings = solved.warnings.clone();
        if let Some(trouble) = self.moved_too_far(&motion.motions, threshold) {
            if adaptive {
                return Err(trouble.into());
            }
            warnings.push(Warning::Trouble { step, trouble });
        }
        if self.may_penetrate(&motion.motions) {
            let mut pairs = std::mem::take(&mut self.pipeline.pairs);
            let shapes = self.moved_shapes(&motion.dbar);
            let penetration = self.new_penetration(shapes, &contacts, threshold, &mut pairs);
            self.pipeline.pairs = pairs;
            if let Some(trouble) = penetration {
                if adaptive {
                    return Err(trouble.into());
                }
                warnings.push(Warning::Trouble { step, trouble });
            }
        }
        let mean_kinetic = self.mean_kinetic(&motion.dbar, dt);
        let allowance = self.gap_accuracy(&solved);
        let kinetic_energy = self.commit(&motion, step, dt, t1, allowance);
        // the contact memory last: a trial that reaches it has passed every check
        let (records, penetrations) = self.close_contacts(&contacts, &solved, step);
        self.pipeline.recycle(solved.rows);
        if let Some(rows2) = solved.rows2 {
            self.pipeline.recycle(rows2);
        }
        warnings.extend(penetrations);
        stages.update = clock.lap();
        Ok(StepRecord {
            step,
            time: t1,
            dt,
            contacts: records,
            contact_count: contacts.len(),
            outer_iterations: solved.report.outer_iterations,
            inner_iterations: solved.report.inner_iterations,
            residual: solved.report.residual,
            converged: solved.report.converged,
            method: solved.method,
            handovers: solved.handovers,
            kinetic_energy,
            mean_kinetic,
            stage: self.stage.current,
            wall_seconds: started.elapsed().as_secs_f64(),
            stages,
            warnings,
            events,
        })
    }

    /// Stages 0–4 and the motion of a trial. A connector or cemented joint that breaks changes
    /// the system: the step is solved again without it (§6, §10.8), its event in `events`.
    fn stages(
        &mut self,
        dt: f64,
        t1: f64,
        clock: &mut Clock,
        stages: &mut StageTimes,
        events: &mut Vec<Event>,
    ) -> Result<(detect::Geoms, solve::Solved, update::Motion, f64), adaptive::Failure> {
        let step = self.step_index + 1;
        let mut yield_rounds = 0;
        loop {
            let (couplings, damping) = (self.couplings(), self.damping());
            let dofs = self.next.dofs.as_ref().unwrap_or(&self.dofs);
            self.flex
                .refresh(dofs, &self.bodies, &couplings, dt, damping)
                .map_err(|source| adaptive::Failure::Fatal(StepError::Singular { step, source }))?;
            let df = self.predict(t1);
            stages.predict += clock.lap();
            let mut pipeline = std::mem::take(&mut self.pipeline);
            let (found, inputs, threshold) = self.detect(&df, &mut pipeline.pairs);
            stages.detect += clock.lap();
            let mut solved = self.solve(&found, inputs, &df, &mut pipeline);
            self.pipeline = pipeline;
            stages.rows += solved.times.rows;
            stages.vi += solved.times.vi;
            stages.refine += clock.lap() - solved.times.rows - solved.times.vi;
            let motion = self.motion(&df, &mut solved);
            self.check_finite(&motion)?;
            let joints = self.breakage(&solved);
            if joints.contains(&true) {
                events.extend(self.breakage_events(&found.geoms, &joints, step));
                continue;
            }
            let broke = self.break_connectors(&motion.dbar, step);
            if broke.is_empty() {
                // the yield active set (math note §6.1), at most YIELD_ROUNDS solves again
                if yield_rounds < YIELD_ROUNDS && self.switch_yields(&motion.dbar) {
                    yield_rounds += 1;
                    continue;
                }
                return Ok((found.geoms, solved, motion, threshold));
            }
            events.extend(broke);
            self.renumber_trial();
        }
    }

    /// The strain DOFs' numerical damping c of math note §10.9: on in dynamic runs, off in
    /// static relaxation (velocity carry 0), which discards the velocities it acts on.
    fn damping(&self) -> f64 {
        if self.model.physics.velocity_carry > 0.0 { STRAIN_DAMPING } else { 0.0 }
    }

    /// Numeric factorizations of sparse clusters (meshes, bolted groups) since the clusters last
    /// changed (`[solver] factor_drift` keeps factors: math note §9.3).
    pub fn sparse_factorizations(&self) -> usize {
        self.flex.sparse_factorizations()
    }

    /// The DOF map the step reads: the running trial's after a connector broke in it
    /// (`adaptive::Next`), else the World's.
    fn dof_map(&self) -> &DofMap {
        self.next.dofs.as_ref().unwrap_or(&self.dofs)
    }

    /// The scene's time step (a step may run as shorter trials: `adaptive.rs`).
    pub fn dt(&self) -> f64 {
        self.model.time.step
    }

    /// The bodies' shapes and fixed flags, as contact detection reads them (one pass over the
    /// bodies for both).
    fn shapes_and_fixed(&self) -> (Vec<BodyShape>, Vec<bool>) {
        self.bodies.iter().map(|b| (b.shape(), b.fixed)).unzip()
    }

    /// v0 of the coming step: the initial velocity on the first (trial) step, then k v1 with k the
    /// velocity carry (DDA's dynamic ratio, math note §1.1).
    fn v0(&self, body: &Body) -> Dofs {
        body.velocity * self.v0_scale()
    }

    /// The factor of [`Self::v0`]: 1 on the first step (`v * 1.0` is `v` bit for bit), then the
    /// velocity carry.
    fn v0_scale(&self) -> f64 {
        if self.started { self.model.physics.velocity_carry } else { 1.0 }
    }

    fn interface(&self, a: usize, b: usize) -> &Interface {
        interface_for(&self.model.interfaces, self.bodies[a].material, self.bodies[b].material)
    }

    /// The interface (index into the model's) a contact's edge tags select
    /// ([`crate::contact::set::shared_tag`]), if any.
    fn contact_interface(&self, g: &crate::contact::ContactGeom) -> Option<usize> {
        let bodies = &self.model.bodies;
        crate::contact::set::shared_tag(g, |b| bodies[b].edge_interfaces.as_slice())
    }

    /// The index of the interface whose law a contact takes: its tags' ([`Self::contact_interface`])
    /// or its material pair's; `None` for the smooth law of a scene without a default.
    fn law_index(&self, g: &crate::contact::ContactGeom) -> Option<usize> {
        self.contact_interface(g).or_else(|| {
            let law = self.interface(g.a, g.b);
            self.model.interfaces.iter().position(|i| std::ptr::eq(i, law))
        })
    }

    /// The QVI bound rule over the contacts' laws (contact/law.rs).
    fn bounds<'a>(&self, laws: &'a [crate::contact::law::Law]) -> ContactBounds<'a> {
        ContactBounds { laws, share_cohesion: self.settings.share_cohesion }
    }
}

/// c of math note §10.9: the damping C = c dt K of the strain DOFs; a stiff strain mode's
/// velocity is multiplied by −1/(1 + 2c) = −0.2 per step (spectral radius at ω dt → ∞).
pub const STRAIN_DAMPING: f64 = 2.0;

/// Solves of one step again for the yield active set of bolts (math note §6.1): a switch is a
/// bolt reaching its yield force or unloading from it, and one round settles a single bolt; past
/// this the step keeps its last solve and the force at the step's end is capped explicitly.
const YIELD_ROUNDS: usize = 8;

/// Stage timer: seconds since the last lap.
struct Clock(Instant);

impl Clock {
    fn lap(&mut self) -> f64 {
        let now = Instant::now();
        let t = (now - self.0).as_secs_f64();
        self.0 = now;
        t
    }
}

/// The smallest feature (particle radius, ring width, edge length) of the bodies.
pub fn smallest_feature(bodies: &[Body]) -> f64 {
    bodies.iter().map(Body::feature_size).fold(f64::INFINITY, f64::min)
}
