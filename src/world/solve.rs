//! Stages 3 and 4 of a step: the contact Jacobian per solve, the two VI solves of math note
//! §1.3 (geometry and velocity), the refinement of persistent contacts on the mid-step
//! configuration, and the classification of contacts (closed, impacting).

use super::{Active, World};
use crate::body::Dofs;
use crate::cluster::{Flexibility, Jacobian};
use crate::contact::law::Law;
use crate::contact::{BodyShape, ContactGeom, ContactKey};
use crate::geometry::Vec2;
use crate::vi::{self, Problem};
use std::collections::HashMap;

impl World {
    /// Stages 3 and 4: solve 1 with g0 in the gaps (geometry), refined on the mid-step
    /// configuration (see [`Self::refine`]); then solve 2 with g0 = 0 for the contacts closed
    /// in solve 1 (velocity), skipped when those g0 are all zero (math note §1.3 a, d).
    pub(super) fn solve(&self, contacts: &mut [Active], df: &[Dofs]) -> Solved {
        let opts = vi::Options {
            tolerance: self.model.solver.tolerance,
            max_iterations: self.model.solver.max_iterations,
            max_outer: 50,
            jacobi: self.settings.jacobi,
        };
        let laws: Vec<Law> = contacts.iter().map(|c| c.law).collect();
        let rule = self.bounds(&laws);
        let blocks: Vec<usize> =
            laws.iter().map(|l| l.row).chain([laws.last().map_or(0, |l| l.row + l.rows())]).collect();
        let mut z1 = vec![0.0; laws.last().map_or(0, |l| l.row + l.rows())];
        for c in contacts.iter() {
            let n = c.law.rows();
            let warm = c.memory.map_or([0.0; 3], |m| m.force);
            z1[c.law.row..c.law.row + n].copy_from_slice(&warm[..n]);
        }
        let step = self.step_index + 1;
        let mut report =
            vi::Report { outer_iterations: 0, inner_iterations: 0, residual: 0.0, converged: true };
        let mut warnings = Vec::new();
        let mut run = |w: &sprs::CsMat<f64>, q: &[f64], z: &mut [f64], which: &str| {
            let r = vi::solve(&Problem { w, q, blocks: &blocks }, &rule, z, &opts);
            if !r.converged {
                warnings.push(format!(
                    "step {step}: contact solver ({which}) did not converge: residual {:.3e} after {} iterations",
                    r.residual, r.inner_iterations
                ));
            }
            report.outer_iterations += r.outer_iterations;
            report.inner_iterations += r.inner_iterations;
            report.residual = report.residual.max(r.residual);
            report.converged &= r.converged;
        };
        let mut refinements = 0;
        let (jac, w, q, state) = loop {
            let (jac, q) = self.flexibility(contacts, df, |_| false);
            let w = jac.operator(&self.flex);
            run(&w, &q, &mut z1, if refinements == 0 { "solve 1" } else { "solve 1, refined" });
            let state = self.classify(contacts, &w, &q, &z1);
            if refinements == MAX_REFINEMENTS {
                break (jac, w, q, state);
            }
            let dbar = geometry_increment(&jac, &self.flex, df, &z1, &state.impacting_rows);
            if !self.refine(contacts, &dbar, &state) {
                break (jac, w, q, state);
            }
            refinements += 1;
        };
        // Impacts act on the rigid-body DOFs: the elastic rebound of a stiff body lasts far
        // less than a step, and an impulse through the strain columns would leave a strain
        // rate that the γ = 1 velocity update never returns to the motion (energy lost at
        // every bounce). Solve 2 then gets its own Jacobian, else it shares solve 1's.
        let impacting = |k: usize| state.impacting_rows[contacts[k].law.row];
        let deformable_impact = (0..contacts.len()).any(|k| {
            impacting(k)
                && [contacts[k].geom.a, contacts[k].geom.b].iter().any(|&b| self.bodies[b].deformable)
        });
        let (jac2, w2, q_base) = if deformable_impact {
            let (jac2, q2) = self.flexibility(contacts, df, impacting);
            let w2 = jac2.operator(&self.flex);
            (Some(jac2), Some(w2), q2)
        } else {
            (None, None, q.clone())
        };
        let q2 = self.velocity_gaps(contacts, &q_base, &state);
        let mut z2 = z1.clone();
        if q2 != q {
            run(w2.as_ref().unwrap_or(&w), &q2, &mut z2, "solve 2");
        }
        let Classified { gaps, closed, impacting_rows } = state;
        let w_diag_max = w.diag_iter().flatten().fold(0.0f64, |m, x| m.max(*x));
        Solved { laws, jac, jac2, z1, z2, gaps, closed, impacting_rows, report, warnings, w_diag_max }
    }

    /// Ten times the gap accuracy of a solve: tolerance × max(1, |z|max) × max W_jj (the
    /// scaled natural residual bounds |G_j| by D_jj res |z|), at least 1e-9 d0.
    pub(super) fn gap_accuracy(&self, s: &Solved) -> f64 {
        let zmax = s.z1.iter().fold(1.0f64, |m, z| m.max(z.abs()));
        let wmax = s.w_diag_max;
        (10.0 * self.model.solver.tolerance * zmax * wmax).max(1e-9 * self.threshold)
    }

    /// End-of-step gaps G = q + W z, which contacts are closed (bonded, loaded, or touching at
    /// the end of the step to within the penetration allowance), and the rows of impacting
    /// contacts.
    fn classify(&self, contacts: &[Active], w: &sprs::CsMat<f64>, q: &[f64], z: &[f64]) -> Classified {
        let mut gaps = q.to_vec();
        sprs::prod::mul_acc_mat_vec_csr(w.view(), z, &mut gaps[..]);
        let touching = self.allowance;
        let closed: Vec<bool> = contacts
            .iter()
            .map(|c| c.law.bonded || z[c.law.row] > 0.0 || gaps[c.law.row] <= touching)
            .collect();
        let mut impacting_rows = vec![false; q.len()];
        for (c, &cl) in contacts.iter().zip(&closed) {
            if cl && self.is_impacting(c) {
                impacting_rows[c.law.row..c.law.row + c.law.rows()].fill(true);
            }
        }
        Classified { gaps, closed, impacting_rows }
    }

    /// Moves the linearization of the persistent contacts to the mid-step configuration.
    ///
    /// The gap of math note (3.1) is linearized at the step start, which is exact for flat
    /// contacts only: a disk sliding along a curved surface by v dt penetrates by about
    /// (v dt)²/(2ρ), and the normal force, acting along the start normal, does work on the
    /// chord. Both feed energy into the system (the disk in a ring, paper §7.5, climbs
    /// higher every swing). For each persistent (non-impacting) contact that ends the trial
    /// step closed or nearly so, this takes the normal n and the body points from the
    /// configuration half-way through the trial increment `dbar`, and the offset so that the
    /// linearized gap equals the true gap of the end configuration. At the fixed point the
    /// contact force is orthogonal to the relative chord (it does no work, as the midpoint
    /// rule wants) and the true end-of-step gap is met exactly. Returns whether any contact
    /// changed by more than 1e-9 d0 (in gap terms).
    fn refine(&self, contacts: &mut [Active], dbar: &[Dofs], state: &Classified) -> bool {
        let near = 0.1 * self.threshold;
        let watched: Vec<usize> = (0..contacts.len())
            .filter(|&k| !state.impacting_rows[contacts[k].law.row] && state.gaps[contacts[k].law.row] < near)
            .collect();
        let half: Vec<Dofs> = dbar.iter().map(|d| d * 0.5).collect();
        let mut mid = HashMap::new();
        let mut end = HashMap::new();
        for &k in &watched {
            for b in [contacts[k].geom.a, contacts[k].geom.b] {
                mid.entry(b).or_insert_with(|| self.moved_shape(b, &half[b]));
                end.entry(b).or_insert_with(|| self.moved_shape(b, &dbar[b]));
            }
        }
        let mut changed = false;
        let mut found = Vec::new();
        for k in watched {
            let c = &mut contacts[k];
            let (a, b) = (c.geom.a, c.geom.b);
            let (Some(m), Some(e)) = (
                self.same_contact(c.geom.key, &mid[&a], &mid[&b], a, b, &mut found),
                self.same_contact(c.geom.key, &end[&a], &end[&b], a, b, &mut found),
            ) else {
                continue;
            };
            let anchor = [m.point - translation(&half[a]), m.point - translation(&half[b])];
            let linear: f64 = [(a, 1.0), (b, -1.0)]
                .iter()
                .zip(anchor)
                .map(|(&(body, s), x)| s * self.bodies[body].shape_row(x, m.normal).dot(&dbar[body]))
                .sum();
            // the start gap as the solver sees it, plus what the linearization misses
            let offset = c.start_gap + (e.g0 - c.geom.g0 - linear);
            let reach = self.bodies[a].max_displacement(&dbar[a]) + self.bodies[b].max_displacement(&dbar[b]);
            let change = (offset - c.offset).abs() + (m.normal - c.normal).norm() * reach;
            changed |= change > 1e-9 * self.threshold;
            c.normal = m.normal;
            c.anchor = anchor;
            c.offset = offset;
        }
        changed
    }

    fn moved_shape(&self, b: usize, d: &Dofs) -> BodyShape {
        let mut body = self.bodies[b].clone();
        body.apply_increment(d);
        body.shape()
    }

    /// The contact with `key` between bodies `a` and `b` in the given shapes, if any.
    fn same_contact(
        &self,
        key: ContactKey,
        sa: &BodyShape,
        sb: &BodyShape,
        a: usize,
        b: usize,
        found: &mut Vec<ContactGeom>,
    ) -> Option<ContactGeom> {
        found.clear();
        if a < b {
            crate::contact::narrow::pair_contacts(a, b, sa, sb, self.threshold, found);
        } else {
            crate::contact::narrow::pair_contacts(b, a, sb, sa, self.threshold, found);
        }
        found.iter().find(|g| g.key == key).cloned()
    }

    /// The gaps of solve 2, the velocity solve (math note §1.3 d): g0 dropped for every
    /// contact closed in solve 1 (split impulse), so that the velocity follows from the
    /// constraint alone (an impacting contact reflects its approach velocity).
    fn velocity_gaps(&self, contacts: &[Active], q: &[f64], state: &Classified) -> Vec<f64> {
        let mut q2 = q.to_vec();
        for (c, &closed) in contacts.iter().zip(&state.closed) {
            if closed {
                q2[c.law.row] -= c.start_gap;
            }
        }
        q2
    }

    /// Velocity of A relative to B at the contact point at the step start (v0, math note §0).
    fn relative_velocity(&self, c: &Active) -> Vec2 {
        let x = c.geom.point;
        let velocity = |b: usize| {
            let body = &self.bodies[b];
            body.displacement(x, &self.v0(body))
        };
        velocity(c.geom.a) - velocity(c.geom.b)
    }

    /// Math note §1.3 (b): not closed at the end of the last step and approaching at the
    /// step start (the caller checks that it closed in solve 1).
    fn is_impacting(&self, c: &Active) -> bool {
        if c.memory.is_some_and(|m| m.closed) {
            return false;
        }
        let rate = c.geom.normal.dot(&self.relative_velocity(c));
        // an approach slower than the solver's own gap accuracy per step is noise, not an
        // impact (doubling a resting contact's share would push its bodies into their
        // neighbours)
        rate * self.dt() < -self.allowance
    }
}

/// Refinements of solve 1 on the mid-step configuration (see [`World::refine`]); the fixed
/// point is reached in two or three.
const MAX_REFINEMENTS: usize = 4;

/// Translation (u0, v0) of the centroid under the increment `d`.
fn translation(d: &Dofs) -> Vec2 {
    Vec2::new(d[0], d[1])
}

/// dbar = d^f + K⁻¹ Bᵀ z + K⁻¹ B_impᵀ z_imp: the geometry increment with the impacting
/// contacts' share doubled (math note §1.3 c).
pub(super) fn geometry_increment(
    jac: &Jacobian,
    flex: &Flexibility,
    df: &[Dofs],
    z: &[f64],
    impacting: &[bool],
) -> Vec<Dofs> {
    let dp = jac.response(flex, z, |_| true);
    let dimp = jac.response(flex, z, |r| impacting[r]);
    (0..df.len()).map(|b| df[b] + dp[b] + dimp[b]).collect()
}

/// Contact states after a solve 1.
struct Classified {
    gaps: Vec<f64>,
    closed: Vec<bool>,
    impacting_rows: Vec<bool>,
}

/// Result of stage 4.
pub(super) struct Solved {
    /// The contacts' laws and VI row layout.
    pub(super) laws: Vec<Law>,
    /// The contact Jacobian the forces belong to.
    pub(super) jac: Jacobian,
    /// The Jacobian of solve 2 when it differs (impacts on deformable bodies).
    pub(super) jac2: Option<Jacobian>,
    /// Forces of solve 1 (geometry).
    pub(super) z1: Vec<f64>,
    /// Forces of solve 2 (velocity; reported).
    pub(super) z2: Vec<f64>,
    /// Gaps G(z1) = q + W z1 at the end of the step.
    pub(super) gaps: Vec<f64>,
    /// Per contact: closed (or bonded) in solve 1.
    pub(super) closed: Vec<bool>,
    /// Per VI row: belongs to an impacting contact (math note §1.3 b).
    pub(super) impacting_rows: Vec<bool>,
    pub(super) report: vi::Report,
    pub(super) warnings: Vec<String>,
    /// Largest diagonal entry of W (gap per unit force).
    pub(super) w_diag_max: f64,
}
