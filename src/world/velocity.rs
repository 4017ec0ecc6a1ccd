//! The velocity targets of solve 2 (math note §10.15): Newton's coefficient of restitution on
//! closing contacts, and friction rows that stop their slip.
//!
//! The velocity of a step is v1 = 2 d/dt − v0 (§1.1), d the answer of solve 2. A row r of the
//! contact Jacobian B measures the rate u = B_r v; a row that solve 2 holds at G_r = 0 ends with
//! B_r d = −o_r for its gap offset o_r, so that u1 = −2 o_r/dt − u0. The offset
//! o_r = −(1 − e) u0 dt/2 therefore makes u1 = −e u0: Newton's law with coefficient e on a
//! closing normal row, and e = 0 (u1 = 0) on a friction row that sticks.

use super::World;
use super::detect::Detected;
use super::rows::Rows;
use super::solve::Classified;
use crate::contact::law::Law;

/// The offsets solve 2 adds to its gaps (math note §10.15).
pub(super) struct Targets {
    /// Per row of solve 2: restitution and friction-stop offsets together.
    pub offsets: Vec<f64>,
    /// The friction rows among them (a stopping slip); [`Targets::without_stops`] drops them.
    pub stops: Vec<usize>,
}

impl Targets {
    /// The offsets without the friction stops (the fallback of math note §10.15), `None` when
    /// no offset is left.
    pub fn without_stops(&self) -> Option<Vec<f64>> {
        let mut o = self.offsets.clone();
        self.stops.iter().for_each(|&r| o[r] = 0.0);
        o.iter().any(|&x| x != 0.0).then_some(o)
    }
}

impl World {
    /// Per row of `rows` (those of solve 2), the offset solve 2 adds to its gap (math note
    /// §10.15), or `None` when every offset is zero (then nothing changes, bit for bit):
    /// - every row of an impacting contact: −(1 − e) u0 dt/2, e its restitution;
    /// - the normal row of a closed contact that is not impacting and approaches faster than
    ///   the allowance per step: −(1 − e) u0 dt/2;
    /// - a tangential or rolling row of such a contact whose rate solve 1 stops or reverses
    ///   (u0 u1 <= 0 with u1 = 2 G_r/dt − u0, G_r its end gap) and whose |u0| dt is above the
    ///   allowance: −u0 dt/2 (the stick of a stopping slip is an impact with e = 0).
    pub(super) fn velocity_targets(
        &self,
        found: &Detected,
        rows: &Rows,
        laws: &[Law],
        state: &Classified,
    ) -> Option<Targets> {
        // no tangential force can stop a slip and every contact is elastic: no rates to compute
        let holds = |l: &Law| l.friction > 0.0 || l.rolling > 0.0 || l.cohesion > 0.0 || l.bonded;
        // the scene's `[solver] friction_stops` or the program's setting
        let on = self.model.solver.friction_stops || self.settings.friction_stops;
        let stops = on && laws.iter().any(holds);
        if !stops && laws.iter().all(|l| l.restitution >= 1.0) {
            return None;
        }
        let (h, noise) = (self.h, self.allowance);
        // no relative rate exceeds twice the fastest body's speed: below the noise, no target
        if 2.0 * self.fastest_point() * h <= noise {
            return None;
        }
        let v0 = self.start_velocities();
        let mut u0 = vec![0.0; rows.q.len()];
        rows.jac().apply(&v0, &mut u0);
        let mut t = Targets { offsets: vec![0.0; rows.q.len()], stops: Vec::new() };
        for (k, c) in found.brief.iter().enumerate().filter(|&(k, _)| state.closed[k]) {
            let (r, e) = (c.row(), laws[k].restitution);
            let mut target = |row: usize, e: f64| t.offsets[row] = -(1.0 - e) * u0[row] * h / 2.0;
            if state.impacting_rows[r] {
                if e < 1.0 {
                    c.rows().for_each(|row| target(row, e));
                }
                continue;
            }
            if e < 1.0 && u0[r] * h < -noise {
                target(r, e);
            }
            for row in (r + 1..c.rows().end).filter(|_| on) {
                let u = u0[row];
                let u1 = 2.0 * state.gaps[row] / h - u;
                if (u * h).abs() > noise && u * u1 <= 0.0 {
                    target(row, 0.0);
                    t.stops.push(row);
                }
            }
        }
        t.offsets.iter().any(|&x| x != 0.0).then_some(t)
    }

    /// v0 of the coming step as a global DOF vector ([`World::v0`]; a mesh's per node).
    fn start_velocities(&self) -> Vec<f64> {
        let dofs = self.dof_map();
        let mut v = vec![0.0; dofs.total()];
        let scale = self.v0_scale();
        for (b, body) in self.bodies.iter().enumerate().filter(|(_, b)| !b.fixed) {
            match &body.mesh {
                Some(fe) => {
                    let r = dofs.range(b);
                    v[r].iter_mut().zip(&fe.velocity).for_each(|(x, u)| *x = u * scale);
                }
                None => dofs.scatter_add(&mut v, b, &self.v0(body)),
            }
        }
        v
    }

    /// An upper bound of the speed of any point of a free body at the step start.
    fn fastest_point(&self) -> f64 {
        let scale = self.v0_scale();
        let norm = |v: &[f64]| (v[0] * v[0] + v[1] * v[1]).sqrt();
        let speed = |b: &crate::body::Body| match &b.mesh {
            // per node: a roller's node has one DOF, a fixed node none
            Some(fe) => {
                (0..fe.nodes.len()).map(|n| fe.node_value(&fe.velocity, n).norm()).fold(0.0, f64::max)
            }
            // translation, spin and strain rates times the reach
            None => {
                let v = b.velocity.as_slice();
                norm(v) + v[2..].iter().map(|x| x.abs()).sum::<f64>() * b.reach.max(1.0)
            }
        };
        self.bodies.iter().filter(|b| !b.fixed).map(speed).fold(0.0, f64::max) * scale.abs()
    }
}
