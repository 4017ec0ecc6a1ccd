//! Stage 2: contacts within the threshold, with their laws and memory (math note §5, §4).

use super::World;
use crate::contact::broad::PairCache;
use crate::contact::law::Law;
use crate::contact::set::{ContactMemory, Memory, joint_partners};
use crate::contact::{ContactGeom, ContactKind, detect, detect_in, label_mesh_kind};

/// A detected contact: geometry, law and what it remembers from the last step. Immutable
/// once detected; the solve stages linearize it (see `rows.rs`).
pub(super) struct Contact {
    pub geom: ContactGeom,
    pub law: Law,
    pub memory: Option<Memory>,
    /// g0 as the solver sees it ([`solver_gap`]): a gap or penetration within the allowance
    /// counts as touching; beyond it, a persistent contact's by its excess (math note §10.2).
    pub start_gap: f64,
}

/// g0 as the solver sees it (math note §10.2): 0 within the allowance on either side; for a
/// contact the last step had (`persistent`), a gap or penetration beyond it less the allowance,
/// so that a gap or penetration creeping through the allowance asks the solver for that step's
/// creep, not for its whole size at once; a new contact's g0 whole.
pub(super) fn solver_gap(g0: f64, allowance: f64, persistent: bool) -> f64 {
    if g0.abs() < allowance {
        0.0
    } else if !persistent {
        g0
    } else if g0 < 0.0 {
        g0 + allowance
    } else {
        g0 - allowance
    }
}

impl World {
    /// Contacts within the threshold, enlarged when the predicted motion of this step needs
    /// it (math note §5: d0 >= 2 u_max; 2.5 as in Shi's DDA), with their laws and VI row
    /// layout; and the threshold used.
    pub(super) fn detect(&self, df: &[f64], cache: &mut PairCache) -> (Vec<Contact>, f64) {
        let u_max = (0..self.bodies.len())
            .map(|b| self.bodies[b].max_motion(&df[self.dofs.range(b)]))
            .fold(0.0, f64::max);
        let threshold = self.threshold.max(2.5 * u_max);
        let shapes = self.shapes();
        let pairs = cache.candidate_pairs(&shapes, &self.fixed(), threshold);
        let geoms = detect_in(&shapes, pairs, threshold, self.threshold);
        let meshes: Vec<bool> = self.bodies.iter().map(|b| b.mesh.is_some()).collect();
        let any_mesh = meshes.contains(&true);
        // one pass over the detected contacts (each pass over their 112 bytes apiece cost about
        // 5 µs of a warm step on the 1,000-disk pile); joint partners after it, if any
        let (mut row, mut joints) = (0, false);
        let mut memory = self.memory.lookup();
        let mut contacts: Vec<Contact> = geoms
            .into_iter()
            .map(|mut geom| {
                if any_mesh {
                    label_mesh_kind(&mut geom, &meshes);
                }
                joints |= geom.joint.is_some();
                let memory = memory.get(&geom.key);
                let law = self.law(&geom, memory, row);
                row += law.rows();
                let start_gap = solver_gap(geom.g0, self.allowance, memory.is_some());
                Contact { geom, law, memory, start_gap }
            })
            .collect();
        if joints {
            let partners = joint_partners(contacts.iter().map(|c| &c.geom));
            contacts.iter_mut().zip(partners).for_each(|(c, p)| c.law.partner = p);
        }
        (contacts, threshold)
    }

    /// The law of one contact: interface of the two materials, capacities over the joint's
    /// length, rolling rows for particle contacts only (math note §4.4); its joint partner is
    /// set once all contacts are known.
    fn law(&self, g: &ContactGeom, memory: Option<Memory>, row: usize) -> Law {
        let i = self.interface(g.a, g.b);
        let particle = matches!(g.kind, ContactKind::PP | ContactKind::PB | ContactKind::PL);
        let intact = !self.broken.contains(&g.key);
        Law {
            row,
            friction: i.friction,
            cohesion: if intact { i.cohesion * g.joint_length } else { 0.0 },
            tensile: i.tensile_strength * g.joint_length,
            rolling: if particle { i.rolling } else { 0.0 },
            bonded: intact && memory.is_some_and(|m| m.bonded),
            partner: None,
        }
    }

    /// Cements the contacts closed at t = 0 whose interface has a tensile strength (math
    /// note §4.5, hypothesis i): the memory of a new world. Only joints have a length, so only
    /// edge-edge joints bond.
    pub(super) fn cement(&mut self) {
        let closed = 1e-9 * self.threshold;
        let bonds = detect(&self.shapes(), &self.fixed(), self.threshold)
            .into_iter()
            .filter(|g| {
                let law = self.interface(g.a, g.b);
                law.tensile_strength > 0.0 && g.joint_length > 0.0 && g.g0.abs() <= closed
            })
            .map(|g| (g.key, Memory { force: [0.0; 3], closed: true, bonded: true }))
            .collect();
        self.memory = ContactMemory::from_entries(bonds);
    }
}

#[cfg(test)]
mod tests {
    use super::solver_gap;

    /// Math note §10.2: 0 within the allowance; a persistent contact's gap or penetration beyond
    /// it by its excess (continuous at the allowance); a new contact's g0 whole. All values are
    /// sums of powers of two, so the comparisons are exact.
    #[test]
    fn solver_gap_is_zero_within_the_allowance_and_a_persistent_contact_its_excess() {
        let a = 0.25;
        for persistent in [false, true] {
            assert_eq!(solver_gap(0.0, a, persistent), 0.0);
            assert_eq!(solver_gap(0.125, a, persistent), 0.0);
            assert_eq!(solver_gap(-0.125, a, persistent), 0.0);
            // with no allowance, g0 itself
            assert_eq!(solver_gap(-0.5, 0.0, persistent), -0.5);
            assert_eq!(solver_gap(0.5, 0.0, persistent), 0.5);
        }
        assert_eq!(solver_gap(-0.25, a, true), 0.0);
        assert_eq!(solver_gap(0.25, a, true), 0.0);
        assert_eq!(solver_gap(-0.375, a, true), -0.125);
        assert_eq!(solver_gap(0.375, a, true), 0.125);
        assert_eq!(solver_gap(-2.0, a, true), -1.75);
        assert_eq!(solver_gap(-0.375, a, false), -0.375);
        assert_eq!(solver_gap(0.375, a, false), 0.375);
        assert_eq!(solver_gap(-2.0, a, false), -2.0);
    }
}
