//! The refinement of persistent contacts on the mid-step configuration (math note §10.1).
//!
//! The gap of math note (3.1) is linearized at the step start, which is exact for flat
//! contacts only: a disk sliding along a curved surface by v dt penetrates by about
//! (v dt)²/(2ρ), and the normal force, acting along the start normal, does work on the
//! chord. Both feed energy into the system (the disk in a ring, paper §7.5, climbs higher
//! every swing). For each persistent (non-impacting) contact that ends the trial step closed
//! or nearly so, the refinement takes the normal n and the body points from the
//! configuration half-way through the trial increment d̄, and the offset so that the
//! linearized gap equals the true gap of the end configuration. At the fixed point the
//! contact force is orthogonal to the relative chord (it does no work, as the midpoint rule
//! wants) and the true end-of-step gap is met exactly.

use super::World;
use super::detect::Detected;
use super::rows::Linearization;
use super::solve::Classified;
use crate::body::Dofs;
use crate::contact::{BodyShape, ContactGeom, ContactKey};
use crate::geometry::Vec2;

/// A contact whose bodies' largest displacements u_A + u_B under the trial increment stay below
/// sqrt(SETTLED d0 L), L the smallest feature, keeps its rows (math note §10.1): its second-order
/// gap change, about (u_A + u_B)²/ρ for a radius of curvature ρ >= L/100, is below the stop
/// criterion 1e-9 d0.
const SETTLED: f64 = 1e-11;

/// The refinement's shape buffers, kept by the world's pipeline across passes and steps.
#[derive(Debug, Clone, Default)]
pub(super) struct Shapes {
    /// Per body, its shape half-way through and at the end of the trial increment (watched
    /// bodies only).
    mid: Vec<Option<BodyShape>>,
    end: Vec<Option<BodyShape>>,
    /// The bodies whose shapes are set: only they are cleared for the next refinement, not
    /// every body's.
    set: Vec<usize>,
    /// Narrow-phase output of one pair.
    found: Vec<ContactGeom>,
}

impl Shapes {
    /// No shape set, for `bodies` bodies.
    fn reset(&mut self, bodies: usize) {
        if self.mid.len() != bodies {
            self.set.clear();
            for v in [&mut self.mid, &mut self.end] {
                v.clear();
                v.resize(bodies, None);
            }
        }
        for b in self.set.drain(..) {
            (self.mid[b], self.end[b]) = (None, None);
        }
    }
}

/// A refinement's outcome: the new linearizations of the contacts it looked at, by contact index
/// in increasing order (the others keep theirs), and whether any changed by more than 1e-9 d0.
pub(super) struct Refined {
    pub patches: Vec<(usize, Linearization)>,
    pub changed: bool,
}

impl Refined {
    /// `lin` with the patches applied.
    pub fn apply(&self, lin: &[Linearization]) -> Vec<Linearization> {
        let mut next = lin.to_vec();
        self.patches.iter().for_each(|&(k, l)| next[k] = l);
        next
    }
}

impl World {
    /// New linearizations from the trial increment `dbar` (a global DOF vector; `reach`, its
    /// bodies' largest point motions), and whether any contact changed by more than 1e-9 d0 (in
    /// gap terms); `None` when no contact moved enough to be looked at (a settled pile). The
    /// linearizations are not copied: the caller applies the patches where it needs them.
    pub(super) fn refine(
        &self,
        found: &Detected,
        lin: &[Linearization],
        dbar: &[f64],
        reach: &[f64],
        state: &Classified,
        shapes: &mut Shapes,
    ) -> Option<Refined> {
        let near = 0.1 * self.threshold;
        let full = |b: usize| self.dof_map().gather(dbar, b);
        // math note §10.1: below this reach, what the refinement can change is far below its
        // stop criterion
        let still = (SETTLED * self.threshold * self.feature).sqrt();
        // no pair of bodies reaches it (a pass over the bodies, not over the contacts)
        if 2.0 * reach.iter().copied().fold(0.0, f64::max) <= still {
            return None;
        }
        let watched: Vec<usize> = (0..found.brief.len())
            .filter(|&k| {
                let (r, [a, b]) = (found.brief[k].row(), found.brief[k].bodies());
                // contacts on a mesh keep their step-start rows (no mid-step refinement yet); the
                // bodies are read last, for the few contacts that pass the other tests
                let on_mesh = || [a, b].iter().any(|&b| self.bodies[b].mesh.is_some());
                reach[a] + reach[b] > still && !state.impacting_rows[r] && state.gaps[r] < near && !on_mesh()
            })
            .collect();
        if watched.is_empty() {
            return None;
        }
        shapes.reset(self.bodies.len());
        let Shapes { mid, end, set, found: pair } = shapes;
        for &k in &watched {
            for b in found.brief[k].bodies() {
                if mid[b].is_none() {
                    mid[b] = Some(self.moved_shape(b, &(full(b) * 0.5)));
                    end[b] = Some(self.moved_shape(b, &full(b)));
                    set.push(b);
                }
            }
        }
        let mut patches = Vec::with_capacity(watched.len());
        let mut changed = false;
        for k in watched {
            let (c, start_gap) = (found.geoms.get(k), found.brief[k].start_gap);
            let (a, b) = (c.a, c.b);
            let (Some(ma), Some(mb), Some(ea), Some(eb)) = (&mid[a], &mid[b], &end[a], &end[b]) else {
                continue;
            };
            let (Some(m), Some(e)) =
                (self.same_contact(c.key, ma, mb, a, b, pair), self.same_contact(c.key, ea, eb, a, b, pair))
            else {
                continue;
            };
            let (da, db) = (full(a), full(b));
            let anchor = [m.point - translation(&(da * 0.5)), m.point - translation(&(db * 0.5))];
            let linear: f64 = [(a, 1.0, &da), (b, -1.0, &db)]
                .iter()
                .zip(anchor)
                .map(|(&(body, s, d), x)| s * self.bodies[body].shape_row(x, m.normal).dot(d))
                .sum();
            // the start gap as the solver sees it, plus what the linearization misses
            let offset = start_gap + (e.g0 - c.g0 - linear);
            let change =
                (offset - lin[k].offset).abs() + (m.normal - lin[k].normal).norm() * (reach[a] + reach[b]);
            changed |= change > 1e-9 * self.threshold;
            patches.push((k, Linearization { normal: m.normal, anchor, offset }));
        }
        Some(Refined { patches, changed })
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
}

/// Translation (u0, v0) of the centroid under the increment `d`.
fn translation(d: &Dofs) -> Vec2 {
    Vec2::new(d[0], d[1])
}
