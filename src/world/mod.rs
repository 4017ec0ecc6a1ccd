//! The simulation state and one time step, as the data flow of the architecture note:
//!
//! ```text
//! 1 predict     f, K per body -> d^f = K⁻¹ f                     (math note §1.2)
//! 2 detect      broad + narrow phase -> contacts with g0          (§5)
//! 3 flexibility B per body, W = B K⁻¹ Bᵀ, q = g0 + B d^f           (§3.1)
//! 4 solve       VI with the friction/cohesion bounds (QVI)        (§4), twice (§1.3):
//!               geometry (refined on the mid-step configuration), then velocity
//! 5 update      dbar -> geometry, d -> velocity                   (§1.3, paper eqs. 16-18)
//! 6 record      StepRecord for the writers
//! ```
//!
//! Stages 3 and 4 live in `solve.rs`.

use crate::body::{Body, Dofs};
use crate::cluster::{Flexibility, Jacobian, is_finite};
use crate::contact::law::{ContactBounds, Law};
use crate::contact::set::{ContactMemory, Memory, interface_for, joint_partners};
use crate::contact::{BodyShape, ContactGeom, ContactKey, ContactKind, detect};
use crate::geometry::{Vec2, cw};
use crate::model::{Interface, Load, Model};
use std::collections::HashSet;

mod solve;
use solve::{Solved, geometry_increment};
use std::time::Instant;

/// Library-level switches that are not part of the scene format.
#[derive(Debug, Clone, Copy)]
pub struct Settings {
    /// Share an edge-edge joint's cohesion between its two contacts (math note §4.6). Off
    /// reproduces the DDA-d over-resistance of the paper's Table 3 (each contact gets all of c).
    pub share_cohesion: bool,
    /// Jacobi scaling in the VI solver (math note §4.2).
    pub jacobi: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Settings { share_cohesion: true, jacobi: true }
    }
}

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
}

/// What one step produced.
#[derive(Debug, Clone)]
pub struct StepRecord {
    pub step: usize,
    pub time: f64,
    pub dt: f64,
    pub contacts: Vec<ContactRecord>,
    pub outer_iterations: usize,
    pub inner_iterations: usize,
    pub residual: f64,
    pub converged: bool,
    pub kinetic_energy: f64,
    pub wall_seconds: f64,
    /// Numerical trouble worth a line in the run log (non-convergence, penetration).
    pub warnings: Vec<String>,
    /// Events of the physics worth a line in the run log (cemented joints breaking).
    pub events: Vec<String>,
}

/// Numerical failure that stops a run.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum StepError {
    #[error("step {step}: non-finite displacement (NaN or infinity) in bodies {bodies:?}")]
    NonFinite { step: usize, bodies: Vec<String> },
}

/// A material point that moves with its body (load points, monitors).
#[derive(Debug, Clone)]
pub struct TrackedPoint {
    pub body: usize,
    pub initial: Vec2,
    pub current: Vec2,
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
    pub load_points: Vec<TrackedPoint>,
    pub monitors: Vec<TrackedPoint>,
    flex: Flexibility,
    memory: ContactMemory,
    /// Contacts of cemented joints that broke: their cohesion is lost for good (§4.5).
    broken: HashSet<ContactKey>,
    /// Penetration allowance [m]: ten times the gap accuracy of the last step's solve
    /// (tolerance × |p|max × max W_jj), at least 1e-9 d0. Rigid bodies in a closed loop of
    /// contacts (a hexagonal pile) cannot remove tiny penetrations of all loop members at
    /// once: the VI has no solution and the forces grow along the loop's self-stress. Below
    /// the allowance a penetration is therefore not corrected (it never grows beyond it).
    allowance: f64,
}

/// A contact as the solve stage sees it: geometry, law, memory and the linearization of its
/// gap.
struct Active {
    geom: ContactGeom,
    law: Law,
    memory: Option<Memory>,
    /// The gap is linearized as `offset + Σ_b s_b nᵀ T_b(anchor_b) d_b` (math note §3.1 with
    /// offset = g0, anchors = contact point), until [`World::refine`] moves it to the mid-step
    /// configuration.
    normal: Vec2,
    anchor: [Vec2; 2],
    offset: f64,
    /// g0 as the solver sees it: a penetration shallower than the solver's own gap accuracy
    /// counts as touching (see [`World::allowance`]).
    start_gap: f64,
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
        let threshold = model.contact.threshold.unwrap_or_else(|| default_threshold(&bodies));
        let flex = Flexibility::new(&bodies, model.time.step);
        let mut world = World {
            model,
            settings,
            bodies,
            step_index: 0,
            time: 0.0,
            threshold,
            load_points,
            monitors,
            flex,
            memory: ContactMemory::new(),
            broken: HashSet::new(),
            allowance: 1e-9 * threshold,
        };
        world.cement();
        world
    }

    /// Cements the contacts closed at t = 0 whose interface has a tensile strength (math
    /// note §4.5, hypothesis i). Only joints have a length, so only edge-edge joints bond.
    fn cement(&mut self) {
        let closed = 1e-9 * self.threshold;
        for g in detect(&self.shapes(), &self.fixed(), self.threshold) {
            let law = self.interface(g.a, g.b);
            if law.tensile_strength > 0.0 && g.joint_length > 0.0 && g.g0.abs() <= closed {
                self.memory.insert(g.key, Memory { force: [0.0; 3], closed: true, bonded: true });
            }
        }
    }

    fn shapes(&self) -> Vec<BodyShape> {
        self.bodies.iter().map(Body::shape).collect()
    }

    fn fixed(&self) -> Vec<bool> {
        self.bodies.iter().map(|b| b.fixed).collect()
    }

    pub fn dt(&self) -> f64 {
        self.model.time.step
    }

    /// v0 of the coming step: the initial velocity on the first step, then k v1 with k the
    /// velocity carry (DDA's dynamic ratio, math note §1.1).
    fn v0(&self, body: &Body) -> Dofs {
        if self.step_index == 0 { body.velocity } else { body.velocity * self.model.physics.velocity_carry }
    }

    /// Advances one step of length dt.
    pub fn step(&mut self) -> Result<StepRecord, StepError> {
        let started = Instant::now();
        let dt = self.dt();
        let step = self.step_index + 1;
        // time as step × dt, not accumulated, so that t is exact at step boundaries
        let t1 = step as f64 * dt;
        let df = self.predict(t1);
        let mut contacts = self.detect(&df);
        let solved = self.solve(&mut contacts, &df);
        self.allowance = self.gap_accuracy(&solved);
        let (dbar, dvel) = self.split_displacements(&solved.jac, &df, &solved);
        let bad: Vec<String> = (0..self.bodies.len())
            .filter(|&b| !is_finite(&dbar[b]) || !is_finite(&dvel[b]))
            .map(|b| self.bodies[b].name.clone())
            .collect();
        if !bad.is_empty() {
            return Err(StepError::NonFinite { step, bodies: bad });
        }
        self.update(&dbar, &dvel, dt);
        self.flex.refresh(&self.bodies);
        let broken = self.breakage(&solved);
        let records = self.contact_records(&contacts, &solved, &broken);
        self.remember(&contacts, &solved, &broken);
        self.step_index = step;
        self.time = t1;
        let mut warnings = solved.warnings;
        warnings.extend(self.penetration_warnings(&contacts, step));
        let events = self.breakage_events(&contacts, &broken, step);
        Ok(StepRecord {
            step,
            time: t1,
            dt,
            contacts: records,
            outer_iterations: solved.report.outer_iterations,
            inner_iterations: solved.report.inner_iterations,
            residual: solved.report.residual,
            converged: solved.report.converged,
            kinetic_energy: self.bodies.iter().map(Body::kinetic_energy).sum(),
            wall_seconds: started.elapsed().as_secs_f64(),
            warnings,
            events,
        })
    }

    /// Stage 1: the contact-free prediction d^f = K⁻¹ f, with
    /// f = f_ext(t1) + (2/dt) M v0 + f_σ (math note eq. 1.2; loads at the end of the step,
    /// where the implicit scheme evaluates the equation of motion).
    fn predict(&self, t1: f64) -> Vec<Dofs> {
        let dt = self.dt();
        let g = self.model.physics.gravity;
        let mut f: Vec<Dofs> = self
            .bodies
            .iter()
            .map(|b| {
                let mut fb = b.mass_matrix() * self.v0(b) * (2.0 / dt) + b.stress_load();
                // body force, centroid reference (math note §2.4)
                fb[0] += b.mass * g.x;
                fb[1] += b.mass * g.y;
                fb
            })
            .collect();
        for (load, p) in self.model.loads.iter().zip(&self.load_points) {
            let body = &self.bodies[load.body];
            let force = load_force(load, t1);
            f[load.body] += body.shape_row(p.current, Vec2::x()) * force.x
                + body.shape_row(p.current, Vec2::y()) * force.y;
        }
        f.iter().enumerate().map(|(b, fb)| self.flex.of(b) * fb).collect()
    }

    /// Stage 2: contacts within the threshold, enlarged when the predicted motion of this
    /// step needs it (math note §5: d0 >= 2 u_max; 2.5 as in Shi's DDA), with their laws and
    /// VI row layout.
    fn detect(&self, df: &[Dofs]) -> Vec<Active> {
        let u_max = self.bodies.iter().zip(df).map(|(b, d)| b.max_displacement(d)).fold(0.0, f64::max);
        let threshold = self.threshold.max(2.5 * u_max);
        let geoms = detect(&self.shapes(), &self.fixed(), threshold);
        let partners = joint_partners(&geoms);
        let mut row = 0;
        geoms
            .into_iter()
            .zip(partners)
            .map(|(geom, partner)| {
                let memory = self.memory.get(&geom.key).copied();
                let law = self.law(&geom, partner, memory, row);
                row += law.rows();
                let start_gap = if geom.g0 < 0.0 && geom.g0 > -self.allowance { 0.0 } else { geom.g0 };
                Active {
                    normal: geom.normal,
                    anchor: [geom.point; 2],
                    offset: start_gap,
                    start_gap,
                    geom,
                    law,
                    memory,
                }
            })
            .collect()
    }

    /// The law of one contact: interface of the two materials, capacities over the joint's
    /// length, rolling rows for particle contacts only (math note §4.4).
    fn law(&self, g: &ContactGeom, partner: Option<usize>, memory: Option<Memory>, row: usize) -> Law {
        let i = self.interface(g.a, g.b);
        let particle = g.kind != ContactKind::BB;
        let intact = !self.broken.contains(&g.key);
        Law {
            row,
            friction: i.friction,
            cohesion: if intact { i.cohesion * g.joint_length } else { 0.0 },
            tensile: i.tensile_strength * g.joint_length,
            rolling: if particle { i.rolling } else { 0.0 },
            bonded: intact && memory.is_some_and(|m| m.bonded),
            partner,
        }
    }

    fn interface(&self, a: usize, b: usize) -> &Interface {
        interface_for(&self.model.interfaces, self.bodies[a].material, self.bodies[b].material)
    }

    /// Stage 3: the contact Jacobian (rows normal, tangent and rolling of each contact;
    /// math note §3.1, §4.4) and q = g0 + B d^f. Contacts for which `rigid(k)` holds act on
    /// the rigid-body DOFs only (their strain columns are zero; see [`Self::solve`]).
    fn flexibility(
        &self,
        contacts: &[Active],
        df: &[Dofs],
        rigid: impl Fn(usize) -> bool,
    ) -> (Jacobian, Vec<f64>) {
        let rows = contacts.last().map_or(0, |c| c.law.row + c.law.rows());
        let mut jac = Jacobian::new(self.bodies.len(), rows);
        for (k, c) in contacts.iter().enumerate() {
            let (n, tau, r) = (c.normal, cw(c.normal), c.law.row);
            let keep = |mut row: Dofs| {
                if rigid(k) {
                    row.rows_mut(3, 3).fill(0.0);
                }
                row
            };
            for ((body, sign), x) in [(c.geom.a, 1.0), (c.geom.b, -1.0)].into_iter().zip(c.anchor) {
                let b = &self.bodies[body];
                if b.fixed {
                    continue;
                }
                jac.push(body, r, keep(b.shape_row(x, n) * sign));
                jac.push(body, r + 1, keep(b.shape_row(x, tau) * sign));
                if c.law.rolling > 0.0 {
                    // the couple acts on θ alone, on a block too (math note §4.4)
                    let mut couple = Dofs::zeros();
                    couple[2] = sign;
                    jac.push(body, r + 2, couple);
                }
            }
        }
        let mut q = jac.apply(df);
        for c in contacts {
            q[c.law.row] += c.offset;
        }
        (jac, q)
    }

    /// Math note §1.3 (c, d): dbar = d + K⁻¹ C_imp p1_imp for the geometry (only impacting
    /// contacts' share doubled), d_vel = d^f + K⁻¹ C p2 for the velocity.
    fn split_displacements(&self, jac: &Jacobian, df: &[Dofs], s: &Solved) -> (Vec<Dofs>, Vec<Dofs>) {
        let dbar = geometry_increment(jac, &self.flex, df, &s.z1, &s.impacting_rows);
        let dp2 = s.jac2.as_ref().unwrap_or(jac).response(&self.flex, &s.z2, |_| true);
        let dvel = (0..df.len()).map(|b| df[b] + dp2[b]).collect();
        (dbar, dvel)
    }

    /// Stage 5: geometry from dbar (paper eqs. 16–18), velocity v1 = 2 d/dt − v0 (math note
    /// eq. 1.1); the next step starts from k v1 (see [`Self::v0`]).
    fn update(&mut self, dbar: &[Dofs], dvel: &[Dofs], dt: f64) {
        for p in self.load_points.iter_mut().chain(self.monitors.iter_mut()) {
            p.current = self.bodies[p.body].moved_point(p.current, &dbar[p.body]);
        }
        let v0: Vec<Dofs> = self.bodies.iter().map(|b| self.v0(b)).collect();
        for (b, body) in self.bodies.iter_mut().enumerate() {
            body.apply_increment(&dbar[b]);
            if !body.fixed {
                body.velocity = dvel[b] * (2.0 / dt) - v0[b];
            }
        }
    }

    /// The QVI bound rule over the contacts' laws (contact/law.rs).
    fn bounds<'a>(&self, laws: &'a [Law]) -> ContactBounds<'a> {
        ContactBounds { laws, share_cohesion: self.settings.share_cohesion }
    }

    /// Bonded contacts that reached their tensile share and opened in solve 1: broken for
    /// good, together with their joint partner (math note §4.5, hypothesis iv).
    fn breakage(&self, s: &Solved) -> Vec<bool> {
        let laws = &s.laws;
        let rule = self.bounds(laws);
        let opened = 1e-12 * self.threshold;
        let mut broken: Vec<bool> = (0..laws.len())
            .map(|k| {
                let (law, r) = (&laws[k], laws[k].row);
                law.bonded && s.z1[r] <= -rule.tensile_bound(k, &s.z1) * (1.0 - 1e-9) && s.gaps[r] > opened
            })
            .collect();
        for k in 0..laws.len() {
            if let Some(l) = laws[k].partner.filter(|_| broken[k]) {
                broken[l] = true;
            }
        }
        broken
    }

    fn breakage_events(&mut self, contacts: &[Active], broken: &[bool], step: usize) -> Vec<String> {
        let mut events = Vec::new();
        for (c, _) in contacts.iter().zip(broken).filter(|(_, b)| **b) {
            self.broken.insert(c.geom.key);
            events.push(format!(
                "step {step}: cemented contact between {} and {} at ({}, {}) broke",
                self.bodies[c.geom.a].name, self.bodies[c.geom.b].name, c.geom.point.x, c.geom.point.y
            ));
        }
        events
    }

    fn contact_records(&self, contacts: &[Active], s: &Solved, broken: &[bool]) -> Vec<ContactRecord> {
        let rule = self.bounds(&s.laws);
        contacts
            .iter()
            .enumerate()
            .map(|(k, c)| {
                let r = c.law.row;
                let (pn, pt) = (s.z2[r], s.z2[r + 1]);
                let state = if c.law.bonded && !broken[k] {
                    ContactState::Bonded
                } else if pn <= 0.0 {
                    ContactState::Open
                } else if pt.abs() >= rule.tangential_bound(k, &s.z2) * (1.0 - 1e-9) {
                    ContactState::Slide
                } else {
                    ContactState::Stick
                };
                ContactRecord {
                    key: c.geom.key,
                    kind: c.geom.kind,
                    body_a: c.geom.a,
                    body_b: c.geom.b,
                    point: c.geom.point,
                    normal: c.geom.normal,
                    normal_force: pn,
                    shear_force: pt,
                    rolling_moment: (c.law.rolling > 0.0).then(|| s.z2[r + 2]),
                    gap: s.gaps[r],
                    state,
                }
            })
            .collect()
    }

    /// Warm start, "was closed" and bond memory for the next step.
    fn remember(&mut self, contacts: &[Active], s: &Solved, broken: &[bool]) {
        self.memory = contacts
            .iter()
            .enumerate()
            .map(|(k, c)| {
                let r = c.law.row;
                let mut force = [0.0; 3];
                force[..c.law.rows()].copy_from_slice(&s.z2[r..r + c.law.rows()]);
                let bonded = c.law.bonded && !broken[k];
                (c.geom.key, Memory { force, closed: s.closed[k] && !broken[k], bonded })
            })
            .collect();
    }

    /// Pairs that started this step penetrating deeper than 5 % of the contact threshold.
    fn penetration_warnings(&self, contacts: &[Active], step: usize) -> Vec<String> {
        contacts
            .iter()
            .filter(|c| c.geom.g0 < -0.05 * self.threshold)
            .map(|c| {
                format!(
                    "step {step}: bodies {} and {} penetrate by {:.3e} m",
                    self.bodies[c.geom.a].name, self.bodies[c.geom.b].name, -c.geom.g0
                )
            })
            .collect()
    }
}

/// Point-load force at time t.
fn load_force(load: &Load, t: f64) -> Vec2 {
    load.force * load.factor(t)
}

/// Default d0: a tenth of the smallest feature (particle radius, edge length), so that
/// feature tests stay unambiguous (math note §5); enlarged per step when motion needs it.
pub fn default_threshold(bodies: &[Body]) -> f64 {
    0.1 * bodies.iter().map(Body::feature_size).fold(f64::INFINITY, f64::min)
}
