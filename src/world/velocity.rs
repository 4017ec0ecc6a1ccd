//! The velocity targets of solve 2 (math note §10.15): Newton's coefficient of restitution on
//! closing contacts.
//!
//! The velocity of a step is v1 = 2 d/dt − v0 (§1.1), d the answer of solve 2. A row r of the
//! contact Jacobian B measures the rate u = B_r v; a row that solve 2 holds at G_r = 0 ends with
//! B_r d = −o_r for its gap offset o_r, so that u1 = −2 o_r/dt − u0. The offset
//! o_r = −(1 − e) u0 dt/2 therefore makes u1 = −e u0: Newton's law with coefficient e on a
//! closing normal row.

use super::World;
use super::detect::Detected;
use super::rows::Rows;
use super::solve::Classified;
use crate::contact::law::Law;

impl World {
    /// Per row of `rows` (those of solve 2), the offset solve 2 adds to its gap (math note
    /// §10.15), or `None` when every offset is zero (then nothing changes, bit for bit):
    /// - every row of an impacting contact: −(1 − e) u0 dt/2, e its restitution;
    /// - the normal row of a closed contact that is not impacting and approaches faster than
    ///   the allowance per step: −(1 − e) u0 dt/2.
    ///
    /// Friction rows of persistent contacts get none (math note §10.15, "Friction stops").
    pub(super) fn velocity_targets(
        &self,
        found: &Detected,
        rows: &Rows,
        laws: &[Law],
        state: &Classified,
    ) -> Option<Vec<f64>> {
        // every contact elastic (the default): no offset, and no rates to compute
        if laws.iter().all(|l| l.restitution >= 1.0) {
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
        let mut offsets = vec![0.0; rows.q.len()];
        let mut any = false;
        for (k, c) in found.brief.iter().enumerate().filter(|&(k, _)| state.closed[k]) {
            let (r, e) = (c.row(), laws[k].restitution);
            let mut target = |row: usize, e: f64| {
                offsets[row] = -(1.0 - e) * u0[row] * h / 2.0;
                any = true;
            };
            if state.impacting_rows[r] {
                if e < 1.0 {
                    c.rows().for_each(|row| target(row, e));
                }
                continue;
            }
            if e < 1.0 && u0[r] * h < -noise {
                target(r, e);
            }
        }
        any.then_some(offsets)
    }

    /// v0 of the coming step as a global DOF vector ([`World::v0`]; a mesh's per node).
    fn start_velocities(&self) -> Vec<f64> {
        let mut v = vec![0.0; self.dofs.total()];
        let scale = self.v0_scale();
        for (b, body) in self.bodies.iter().enumerate().filter(|(_, b)| !b.fixed) {
            match &body.mesh {
                Some(fe) => {
                    let r = self.dofs.range(b);
                    v[r].iter_mut().zip(&fe.velocity).for_each(|(x, u)| *x = u * scale);
                }
                None => self.dofs.scatter_add(&mut v, b, &self.v0(body)),
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
