//! Stage 5 (update the bodies, breakage, contact memory) and the contact part of stage 6.

use super::detect::Geoms;
use super::solve::{Increment, Solved};
use super::{ContactRecord, ContactState, Event, Warning, World};
use crate::contact::set::{ContactMemory, Memory};

/// The displacements of a step, as global DOF vectors (math note §1.3 c, d).
pub(super) struct Motion {
    /// d̄: geometry and stress (impacting contacts' share doubled).
    pub dbar: Vec<f64>,
    /// Each body's largest point motion under d̄ (`World::motions`).
    pub motions: Vec<f64>,
    /// d_vel = d^f + K̃⁻¹ Bᵀ p2: velocity.
    pub dvel: Vec<f64>,
}

impl World {
    /// The step's motion: d̄ as the last solve 1 gave it.
    pub(super) fn motion(&self, df: &[f64], s: &mut Solved) -> Motion {
        let Increment { dbar, motions } = std::mem::take(&mut s.increment);
        let dp2 = s.dp2.as_ref().unwrap_or(&s.dp1);
        let dvel = (0..df.len()).map(|i| df[i] + dp2[i]).collect();
        Motion { dbar, motions, dvel }
    }

    /// A NaN or infinity anywhere fails the trial, naming the bodies (math note §10.8).
    pub(super) fn check_finite(&self, m: &Motion) -> Result<(), super::Trouble> {
        // one pass over the whole vectors; the bodies' DOF ranges are read only to name the
        // bodies of a failure (a pass per body costs more: `benches/step.rs`)
        if m.dbar.iter().chain(&m.dvel).all(|x| x.is_finite()) {
            return Ok(());
        }
        let bad: Vec<String> = (0..self.bodies.len())
            .filter(|&b| {
                let r = self.dof_map().range(b);
                !m.dbar[r.clone()].iter().chain(&m.dvel[r]).all(|x| x.is_finite())
            })
            .map(|b| self.bodies[b].name.clone())
            .collect();
        if bad.is_empty() { Ok(()) } else { Err(super::Trouble::NonFinite { bodies: bad }) }
    }

    /// Geometry from d̄ (paper eqs. 16–18), velocity v1 = 2 d/dt − v0 (math note eq. 1.1);
    /// the next step starts from k v1 (see [`Self::v0`]). Returns the bodies' kinetic energy
    /// after it, summed in body order while each body is at hand (a pass of its own over the
    /// bodies would stream them from memory again on a large pile).
    pub(super) fn update(&mut self, m: &Motion, dt: f64) -> f64 {
        // a body's d̄ (none for a mesh, which moves by its nodes); gathered where it is used, not
        // into a table per body, as v0
        let dofs = &self.dofs;
        let dbar = |b: usize, body: &crate::body::Body| {
            if body.mesh.is_some() { Default::default() } else { dofs.gather(&m.dbar, b) }
        };
        // points on a mesh keep their triangle and area coordinates (math note §9.2)
        let held: Vec<_> = self
            .load_points
            .iter()
            .chain(self.monitors.iter())
            .map(|p| self.bodies[p.body].mesh.as_ref().and_then(|fe| fe.locate(p.current)))
            .collect();
        for (p, h) in self.load_points.iter_mut().chain(self.monitors.iter_mut()).zip(&held) {
            if h.is_none() {
                let body = &self.bodies[p.body];
                p.current = body.moved_point(p.current, &dbar(p.body, body));
            }
        }
        let v0_scale = self.v0_scale();
        let mut kinetic = 0.0;
        for (b, body) in self.bodies.iter_mut().enumerate() {
            if body.mesh.is_some() {
                let r = dofs.range(b);
                body.apply_mesh_step(&m.dbar[r.clone()], &m.dvel[r], v0_scale, dt);
            } else {
                let v0 = body.velocity * v0_scale;
                body.apply_increment(&dbar(b, body));
                if !body.fixed {
                    body.velocity = dofs.gather(&m.dvel, b) * (2.0 / dt) - v0;
                }
            }
            kinetic += body.kinetic_energy();
        }
        for (p, h) in self.load_points.iter_mut().chain(self.monitors.iter_mut()).zip(held) {
            if let (Some((e, l)), Some(fe)) = (h, &self.bodies[p.body].mesh) {
                p.current = fe.triangles[e].iter().zip(l).map(|(&n, w)| fe.nodes[n] * w).sum();
            }
        }
        kinetic
    }

    /// Bonded contacts that reached their tensile share and opened in solve 1: broken for
    /// good, together with their joint partner (math note §4.5, hypothesis iv); the step is
    /// then solved again without their bond (§10.8). Empty when no contact is bonded.
    pub(super) fn breakage(&self, s: &Solved) -> Vec<bool> {
        if !s.state.bonded {
            return Vec::new();
        }
        let laws = &s.laws;
        let rule = self.bounds(laws);
        let opened = 1e-12 * self.threshold;
        let mut broken: Vec<bool> = (0..laws.len())
            .map(|k| {
                let (law, r) = (&laws[k], laws[k].row);
                law.bonded
                    && s.z1[r] <= -rule.tensile_bound(k, &s.z1) * (1.0 - 1e-9)
                    && s.state.gaps[r] > opened
            })
            .collect();
        for k in 0..laws.len() {
            if let Some(l) = laws[k].partner.filter(|_| broken[k]) {
                broken[l] = true;
            }
        }
        broken
    }

    /// The joints of `contacts` that `broken` marks break in the running trial (its
    /// `adaptive::Next`), with their events.
    pub(super) fn breakage_events(&mut self, contacts: &Geoms, broken: &[bool], step: usize) -> Vec<Event> {
        let mut events = Vec::new();
        for (c, _) in contacts.iter().zip(broken).filter(|(_, b)| **b) {
            self.next.broken.insert(c.key);
            events.push(Event::JointBroke {
                step,
                body_a: self.bodies[c.a].name.clone(),
                body_b: self.bodies[c.b].name.clone(),
                point: c.point,
            });
        }
        events
    }

    /// The step's contact records, the memory of the next step (warm start, "was closed" and
    /// bond; a joint that broke in the step was solved again unbonded: `World::trial`), and a
    /// warning for each pair that started the step penetrating deeper than 5 % of the contact
    /// threshold. One pass over the contacts makes all three (on a large pile each pass over
    /// the contacts streams them from memory); the records only when asked for
    /// ([`super::Settings::contact_records`]).
    pub(super) fn close_contacts(
        &mut self,
        contacts: &Geoms,
        s: &Solved,
        step: usize,
    ) -> (Vec<ContactRecord>, Vec<Warning>) {
        let rule = self.bounds(&s.laws);
        let mut memory = Vec::with_capacity(contacts.len());
        let mut warnings = Vec::new();
        let deep = -0.05 * self.threshold;
        let on = self.settings.contact_records;
        let mut records = Vec::with_capacity(if on { contacts.len() } else { 0 });
        for (k, (c, law)) in contacts.iter().zip(&s.laws).enumerate() {
            let r = law.row;
            let mut force = [0.0; 3];
            crate::jacobian::copy_small(&mut force[..law.rows()], &s.z2[r..r + law.rows()]);
            memory.push((c.key, Memory { force, closed: s.state.closed[k], bonded: law.bonded }));
            if c.g0 < deep {
                warnings.push(Warning::Penetration {
                    step,
                    body_a: self.bodies[c.a].name.clone(),
                    body_b: self.bodies[c.b].name.clone(),
                    depth: -c.g0,
                });
            }
            if !on {
                continue;
            }
            let (pn, pt) = (s.z2[r], s.z2[r + 1]);
            let state = if law.bonded {
                ContactState::Bonded
            } else if pn <= 0.0 {
                ContactState::Open
            } else if pt.abs() >= rule.tangential_bound(k, &s.z2) * (1.0 - 1e-9) {
                ContactState::Slide
            } else {
                ContactState::Stick
            };
            records.push(ContactRecord {
                key: c.key,
                kind: c.kind,
                body_a: c.a,
                body_b: c.b,
                point: c.point,
                normal: c.normal,
                normal_force: pn,
                shear_force: pt,
                rolling_moment: (law.rolling > 0.0).then(|| s.z2[r + 2]),
                gap: s.state.gaps[r],
                state,
                interface: self.law_index(c),
            });
        }
        self.memory = ContactMemory::from_entries(memory);
        (records, warnings)
    }
}
