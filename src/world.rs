//! The simulation state and one time step, as the data flow of the architecture note:
//!
//! ```text
//! 1 predict     f, K per body -> d^f = K⁻¹ f                     (math note §1.2)
//! 2 detect      broad + narrow phase -> contacts with g0          (§5)
//! 3 flexibility B per body, W = B K⁻¹ Bᵀ, q = g0 + B d^f           (§3.1)
//! 4 solve       VI with the friction/cohesion bounds (QVI)        (§4), twice (§1.3)
//! 5 update      dbar -> geometry, d -> velocity                   (§1.3, paper eq. 16)
//! 6 record      StepRecord for the writers
//! ```

use crate::body::{Body, Dofs};
use crate::cluster::{Flexibility, Jacobian, is_finite};
use crate::contact::set::{ContactMemory, Memory, interface_for, joint_partners};
use crate::contact::{ContactGeom, ContactKey, ContactKind, detect};
use crate::geometry::{Vec2, cw};
use crate::model::{Interface, Load, Model};
use crate::vi::{self, BoundRule, Problem};
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
}

impl ContactState {
    pub fn as_str(self) -> &'static str {
        match self {
            ContactState::Open => "open",
            ContactState::Stick => "stick",
            ContactState::Slide => "slide",
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
}

/// A contact as the solve stage sees it: geometry, law and memory.
struct Active {
    geom: ContactGeom,
    friction: f64,
    /// Cohesive capacity of the contact's joint [N] (stress × overlap length).
    cohesion: f64,
    partner: Option<usize>,
    memory: Option<Memory>,
}

impl World {
    pub fn new(model: Model) -> World {
        World::with_settings(model, Settings::default())
    }

    pub fn with_settings(model: Model, settings: Settings) -> World {
        let bodies: Vec<Body> =
            model.bodies.iter().map(|s| Body::new(s, &model.materials[s.material], model.physics.plane)).collect();
        let track = |body: usize, p: Vec2| TrackedPoint { body, initial: p, current: p };
        let load_points = model.loads.iter().map(|l| track(l.body, l.point)).collect();
        let monitors = model.monitors.iter().map(|m| track(m.body, m.point)).collect();
        let threshold = model.contact.threshold.unwrap_or_else(|| default_threshold(&bodies));
        let flex = Flexibility::new(&bodies, model.time.step);
        World {
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
        }
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
        let t1 = self.time + dt;
        let df = self.predict(t1);
        let contacts = self.detect(&df);
        let (jac, q) = self.flexibility(&contacts, &df);
        let w = jac.operator(&self.flex);
        let solved = self.solve(&contacts, &w, &q);
        let (dbar, dvel) = self.split_displacements(&jac, &df, &solved);
        let bad: Vec<String> = (0..self.bodies.len())
            .filter(|&b| !is_finite(&dbar[b]) || !is_finite(&dvel[b]))
            .map(|b| self.bodies[b].name.clone())
            .collect();
        if !bad.is_empty() {
            return Err(StepError::NonFinite { step, bodies: bad });
        }
        self.update(&dbar, &dvel, dt);
        self.flex.refresh(&self.bodies);
        let records = self.contact_records(&contacts, &solved);
        self.remember(&records, &solved.z1);
        self.step_index = step;
        self.time = t1;
        let mut warnings = solved.warnings;
        warnings.extend(self.penetration_warnings(&contacts, step));
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
        })
    }

    /// Stage 1: the contact-free prediction d^f = K⁻¹ f, with
    /// f = f_ext(t1) + (2/dt) M v0 (math note eq. 1.2; loads at the end of the step, where
    /// the implicit scheme evaluates the equation of motion).
    fn predict(&self, t1: f64) -> Vec<Dofs> {
        let dt = self.dt();
        let g = self.model.physics.gravity;
        let mut f: Vec<Dofs> = self
            .bodies
            .iter()
            .map(|b| {
                // f = (2/dt) M v0 + f_σ + body force (math note eq. 1.2, §2.4)
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
    /// step needs it (math note §5: d0 >= 2 u_max; 2.5 as in Shi's DDA).
    fn detect(&self, df: &[Dofs]) -> Vec<Active> {
        let u_max = self.bodies.iter().zip(df).map(|(b, d)| b.max_displacement(d)).fold(0.0, f64::max);
        let threshold = self.threshold.max(2.5 * u_max);
        let shapes: Vec<_> = self.bodies.iter().map(Body::shape).collect();
        let fixed: Vec<bool> = self.bodies.iter().map(|b| b.fixed).collect();
        let geoms = detect(&shapes, &fixed, threshold);
        let partners = joint_partners(&geoms);
        geoms
            .into_iter()
            .zip(partners)
            .map(|(geom, partner)| {
                let law = self.interface(geom.a, geom.b);
                Active {
                    friction: law.friction,
                    cohesion: law.cohesion * geom.joint_length,
                    partner,
                    memory: self.memory.get(&geom.key).copied(),
                    geom,
                }
            })
            .collect()
    }

    fn interface(&self, a: usize, b: usize) -> &Interface {
        interface_for(&self.model.interfaces, self.bodies[a].material, self.bodies[b].material)
    }

    /// Stage 3: the contact Jacobian (rows 2k normal, 2k+1 tangent; math note §3.1) and
    /// q = g0 + B d^f.
    fn flexibility(&self, contacts: &[Active], df: &[Dofs]) -> (Jacobian, Vec<f64>) {
        let mut jac = Jacobian::new(self.bodies.len(), 2 * contacts.len());
        for (k, c) in contacts.iter().enumerate() {
            let (n, tau) = (c.geom.normal, cw(c.geom.normal));
            for (body, sign) in [(c.geom.a, 1.0), (c.geom.b, -1.0)] {
                let b = &self.bodies[body];
                if b.fixed {
                    continue;
                }
                jac.push(body, 2 * k, b.shape_row(c.geom.point, n) * sign);
                jac.push(body, 2 * k + 1, b.shape_row(c.geom.point, tau) * sign);
            }
        }
        let mut q = jac.apply(df);
        for (k, c) in contacts.iter().enumerate() {
            q[2 * k] += c.geom.g0;
        }
        (jac, q)
    }

    /// Stage 4: solve 1 with g0 in the gaps (geometry), solve 2 with g0 = 0 for the contacts
    /// closed in solve 1 (velocity), skipped when those g0 are all zero (math note §1.3 a, d).
    fn solve(&self, contacts: &[Active], w: &sprs::CsMat<f64>, q: &[f64]) -> Solved {
        let opts = vi::Options {
            tolerance: self.model.solver.tolerance,
            max_iterations: self.model.solver.max_iterations,
            max_outer: 50,
            jacobi: self.settings.jacobi,
        };
        let mut rule = ContactBounds { contacts, share: self.settings.share_cohesion };
        let mut z1: Vec<f64> = contacts
            .iter()
            .flat_map(|c| c.memory.map_or([0.0, 0.0], |m| m.force))
            .collect();
        let mut report = vi::solve(&Problem { w, q }, &mut rule, &mut z1, &opts);
        let mut warnings = Vec::new();
        let step = self.step_index + 1;
        let mut note = |r: &vi::Report, which: &str| {
            if !r.converged {
                warnings.push(format!(
                    "step {step}: contact solver ({which}) did not converge: residual {:.3e} after {} iterations",
                    r.residual, r.inner_iterations
                ));
            }
        };
        note(&report, "solve 1");
        let zero_g0 = 1e-12 * self.threshold;
        let closed = |k: usize, z: &[f64]| z[2 * k] > 0.0;
        let needs_second = (0..contacts.len()).any(|k| closed(k, &z1) && contacts[k].geom.g0.abs() > zero_g0);
        let z2 = if needs_second {
            let mut q2 = q.to_vec();
            for (k, c) in contacts.iter().enumerate() {
                if closed(k, &z1) {
                    q2[2 * k] -= c.geom.g0;
                }
            }
            let mut z2 = z1.clone();
            let r2 = vi::solve(&Problem { w, q: &q2 }, &mut rule, &mut z2, &opts);
            note(&r2, "solve 2");
            report.outer_iterations += r2.outer_iterations;
            report.inner_iterations += r2.inner_iterations;
            report.residual = report.residual.max(r2.residual);
            report.converged &= r2.converged;
            z2
        } else {
            z1.clone()
        };
        let gaps = {
            let mut g = q.to_vec();
            sprs::prod::mul_acc_mat_vec_csr(w.view(), &z1[..], &mut g[..]);
            g
        };
        let impacting = (0..contacts.len()).map(|k| self.is_impacting(&contacts[k], closed(k, &z1))).collect();
        Solved { z1, z2, gaps, impacting, report, warnings }
    }

    /// Math note §1.3 (b): not closed at the end of the last step, approaching at the step
    /// start, and closed in solve 1.
    fn is_impacting(&self, c: &Active, closed_now: bool) -> bool {
        if !closed_now || c.memory.is_some_and(|m| m.closed) {
            return false;
        }
        let x = c.geom.point;
        let velocity = |b: usize| {
            let body = &self.bodies[b];
            body.displacement(x, &self.v0(body))
        };
        let rate = c.geom.normal.dot(&(velocity(c.geom.a) - velocity(c.geom.b)));
        rate * self.dt() < -1e-9 * self.threshold
    }

    /// Math note §1.3 (c, d): dbar = d + K⁻¹ C_imp p1_imp for the geometry (only impacting
    /// contacts' share doubled), d_vel = d^f + K⁻¹ C p2 for the velocity.
    fn split_displacements(&self, jac: &Jacobian, df: &[Dofs], s: &Solved) -> (Vec<Dofs>, Vec<Dofs>) {
        let all = |_: usize| true;
        let dp1 = jac.response(&self.flex, &s.z1, all);
        let dimp = jac.response(&self.flex, &s.z1, |r| s.impacting[r / 2]);
        let dp2 = jac.response(&self.flex, &s.z2, all);
        let dbar = (0..df.len()).map(|b| df[b] + dp1[b] + dimp[b]).collect();
        let dvel = (0..df.len()).map(|b| df[b] + dp2[b]).collect();
        (dbar, dvel)
    }

    /// Stage 5: geometry from dbar (paper eq. 16), velocity v1 = 2 d/dt − v0 (math note
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

    fn contact_records(&self, contacts: &[Active], s: &Solved) -> Vec<ContactRecord> {
        let rule = ContactBounds { contacts, share: self.settings.share_cohesion };
        contacts
            .iter()
            .enumerate()
            .map(|(k, c)| {
                let (pn, pt) = (s.z2[2 * k], s.z2[2 * k + 1]);
                let bound = rule.tangential_bound(k, &s.z2);
                let state = if pn <= 0.0 {
                    ContactState::Open
                } else if pt.abs() >= bound * (1.0 - 1e-9) {
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
                    gap: s.gaps[2 * k],
                    state,
                }
            })
            .collect()
    }

    /// Warm start and "was closed" memory for the next step (closed in solve 1).
    fn remember(&mut self, records: &[ContactRecord], z1: &[f64]) {
        self.memory = records
            .iter()
            .enumerate()
            .map(|(k, r)| {
                let m = Memory { force: [r.normal_force, r.shear_force], closed: z1[2 * k] > 0.0 };
                (r.key, m)
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

/// Result of stage 4.
struct Solved {
    /// Forces of solve 1 (geometry).
    z1: Vec<f64>,
    /// Forces of solve 2 (velocity; reported).
    z2: Vec<f64>,
    /// Gaps G(z1) = q + W z1 at the end of the step.
    gaps: Vec<f64>,
    impacting: Vec<bool>,
    report: vi::Report,
    warnings: Vec<String>,
}

impl Active {
    /// Coulomb bound with cohesion, τ = c + μ max(p_n, 0) (paper eq. 19); cohesion acts only
    /// on a closed contact.
    fn tangential_bound(&self, pn: f64, cohesion: f64) -> f64 {
        if pn > 0.0 { cohesion + self.friction * pn } else { 0.0 }
    }
}

/// The QVI bounds of math note §4.1, recomputed in the outer loop (§4.3): normal [0, ∞),
/// tangential ±(c_share + μ p_n), with the joint's cohesion shared between its two contacts
/// by the mobilization-equalizing rule of §4.6.
struct ContactBounds<'a> {
    contacts: &'a [Active],
    share: bool,
}

impl ContactBounds<'_> {
    /// τ_k for the iterate z.
    fn tangential_bound(&self, k: usize, z: &[f64]) -> f64 {
        let c = &self.contacts[k];
        let cohesion = match (c.partner, self.share) {
            (Some(l), true) => {
                cohesion_share(c.cohesion, c.friction, [z[2 * k], z[2 * k + 1]], [z[2 * l], z[2 * l + 1]])
            }
            _ => c.cohesion,
        };
        c.tangential_bound(z[2 * k], cohesion)
    }
}

impl BoundRule for ContactBounds<'_> {
    fn bounds(&mut self, z: &[f64], lo: &mut [f64], hi: &mut [f64]) {
        for k in 0..self.contacts.len() {
            lo[2 * k] = 0.0;
            hi[2 * k] = f64::INFINITY;
            let tau = self.tangential_bound(k, z);
            lo[2 * k + 1] = -tau;
            hi[2 * k + 1] = tau;
        }
    }
}

/// Share c1 of a joint's cohesion c for contact 1 with forces `p1 = (p_n, p_t)`, partner `p2`
/// (math note §4.6): both contacts at the same mobilization |p_t|/(c_i + μ p_n);
/// equal split when neither carries shear.
fn cohesion_share(c: f64, mu: f64, p1: [f64; 2], p2: [f64; 2]) -> f64 {
    let (t1, t2) = (p1[1].abs(), p2[1].abs());
    if t1 + t2 <= 0.0 {
        return 0.5 * c;
    }
    let (n1, n2) = (p1[0].max(0.0), p2[0].max(0.0));
    ((t1 * (c + mu * n2) - mu * n1 * t2) / (t1 + t2)).clamp(0.0, c)
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
