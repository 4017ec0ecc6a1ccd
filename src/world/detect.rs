//! Stage 2: contacts within the threshold, with their laws and memory (math note §5, §4).

use super::World;
use super::rows::{Linearization, Site};
use crate::contact::broad::PairCache;
use crate::contact::law::Law;
use crate::contact::set::{ContactMemory, InterfaceTable, Memory, joint_partners, shared_tag};
use crate::contact::{ContactGeom, ContactKey, ContactKind, detect, detect_in_order, label_mesh_kind};
use crate::model::Interface;

/// A trial's contacts' geometries in key order, where the narrow phase left them: the contacts
/// of its first half of the pairs, then those of its second (`contact::InOrder`), or all in the
/// first when they had to be sorted. Immutable once detected; the solve stages linearize them
/// (see `rows.rs`). Contact k's law is [`Inputs::laws`]' entry k, and what it remembers from the
/// last step went into the warm start and its [`Brief`]. Not copied into one vector of their
/// own, which would write every contact's geometry once more a step (`benches/step.rs`).
pub(super) struct Geoms([Vec<ContactGeom>; 2]);

impl Geoms {
    pub fn len(&self) -> usize {
        self.0[0].len() + self.0[1].len()
    }

    /// Contact k's geometry.
    pub fn get(&self, k: usize) -> &ContactGeom {
        let first = &self.0[0];
        if k < first.len() { &first[k] } else { &self.0[1][k - first.len()] }
    }

    /// The geometries in key order (a chain of two slices, whose length `collect` allocates at
    /// once: `flatten` gave no length, and collecting the records grew their vector by copies).
    pub fn iter(&self) -> impl Iterator<Item = &ContactGeom> {
        let [first, second] = &self.0;
        first.iter().chain(second)
    }

    /// The geometry with key `key`, if detected.
    pub fn find(&self, key: &ContactKey) -> Option<&ContactGeom> {
        let [first, second] = &self.0;
        let half = if second.first().is_some_and(|g| g.key <= *key) { second } else { first };
        half.binary_search_by_key(key, |g| g.key).ok().map(|i| &half[i])
    }
}

/// What the solve stages read of a contact on each of their passes (rows, classification,
/// refinement, velocity gaps), in 24 bytes against a geometry's 112: on a large pile the
/// contacts do not fit the caches, and each pass streams what it reads from memory.
#[derive(Debug, Clone, Copy)]
pub(super) struct Brief {
    a: u32,
    b: u32,
    row: u32,
    /// 2, or 3 with a rolling row.
    rows: u8,
    pub bonded: bool,
    /// Closed at the end of the last step.
    pub was_closed: bool,
    /// g0 as the solver sees it ([`solver_gap`]): a gap or penetration within the allowance
    /// counts as touching; beyond it, a persistent contact's by its excess (math note §10.2).
    pub start_gap: f64,
}

impl Brief {
    /// (u32 indices, as B's segments: `jacobian.rs`.)
    fn of(geom: &ContactGeom, start_gap: f64, law: &Law, memory: Option<Memory>) -> Brief {
        Brief {
            a: geom.a as u32,
            b: geom.b as u32,
            row: law.row as u32,
            rows: law.rows() as u8,
            bonded: law.bonded,
            was_closed: memory.is_some_and(|m| m.closed),
            start_gap,
        }
    }

    /// Body A (the normal points into it) and body B.
    pub fn bodies(&self) -> [usize; 2] {
        [self.a as usize, self.b as usize]
    }

    /// The first VI row: normal; then tangential, and rolling with [`Self::rolling`].
    pub fn row(&self) -> usize {
        self.row as usize
    }

    /// The contact's VI rows.
    pub fn rows(&self) -> std::ops::Range<usize> {
        self.row()..self.row() + self.rows as usize
    }

    /// Whether the contact has a rolling row.
    pub fn rolling(&self) -> bool {
        self.rows == 3
    }
}

/// A trial's contacts, detected sorted by key, and their [`Brief`]s.
pub(super) struct Detected {
    pub geoms: Geoms,
    pub brief: Vec<Brief>,
    /// Per body, what a contact frame reads of it.
    pub sites: Vec<Site>,
    /// Per body that is no mesh, its reach: its largest point motion follows from its DOFs
    /// (`World::motions`, one pass over these 16 bytes per body where the bodies' took 0.2–0.3
    /// ms of a warm step of the 10,000-disk pile).
    pub reach: Vec<Option<f64>>,
}

/// What the solve starts from, made in detection's pass over the contacts: the warm start (last
/// step's forces of the contacts that persist, by row), the laws and the step-start
/// linearizations.
pub(super) struct Inputs {
    pub warm: Vec<f64>,
    pub laws: Vec<Law>,
    pub lin: Vec<Linearization>,
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
    /// layout; what the solve starts from; and the threshold used.
    pub(super) fn detect(&self, df: &[f64], cache: &mut PairCache) -> (Detected, Inputs, f64) {
        // one pass over the bodies (336 bytes apiece) for all detection reads of them, their
        // shapes included (a pass of their own took 1.4 % of the main thread's time on the
        // 40,000-disk pile): the law of each contact reads its two bodies' materials, which
        // through the bodies took 0.3 of detection's loop in perf's samples on the 10,000-disk
        // pile
        let bodies = self.bodies.len();
        let (mut materials, mut fixed, mut sites, mut reach, mut shapes, mut tags) = (
            Vec::with_capacity(bodies),
            Vec::with_capacity(bodies),
            Vec::with_capacity(bodies),
            Vec::with_capacity(bodies),
            Vec::with_capacity(bodies),
            Vec::with_capacity(bodies),
        );
        let (mut u_max, dofs) = (0.0f64, self.dof_map());
        for (b, body) in self.bodies.iter().enumerate() {
            u_max = u_max.max(body.max_motion(&df[dofs.range(b)]));
            materials.push(body.material);
            fixed.push(body.fixed);
            sites.push(Site::of(body, b, dofs));
            reach.push(body.mesh.is_none().then_some(body.reach));
            shapes.push(body.shape());
            tags.push(self.model.bodies[b].edge_interfaces.as_slice());
        }
        let tagged = tags.iter().any(|t| !t.is_empty());
        let threshold = self.threshold.max(2.5 * u_max);
        let mut pairs = cache.candidate_pairs(&shapes, &fixed, threshold);
        self.without_removed(&mut pairs);
        let geoms = detect_in_order(&shapes, &pairs, threshold, self.threshold);
        // (a mesh is the body without a reach)
        let any_mesh = reach.contains(&None);
        let interfaces = InterfaceTable::new(&self.model.interfaces, self.model.materials.len());
        // one pass over the detected contacts, in key order, which makes all the solve reads of
        // them (math note §3.3, "Contact frames from the rows"); joint partners after it, if any
        let (mut row, mut joints) = (0, false);
        let mut memory = self.memory.lookup();
        let n = geoms.count();
        let (mut warm, mut laws, mut lin, mut brief) =
            (Vec::with_capacity(2 * n), Vec::with_capacity(n), Vec::with_capacity(n), Vec::with_capacity(n));
        let mut add = |geom: &mut ContactGeom| {
            if any_mesh {
                label_mesh_kind(geom, |b| reach[b].is_none());
            }
            joints |= geom.joint.is_some();
            let memory = memory.get(&geom.key);
            let interface = match tagged.then(|| shared_tag(geom, |b| tags[b])).flatten() {
                Some(i) => &self.model.interfaces[i],
                None => interfaces.get(materials[geom.a], materials[geom.b]),
            };
            let law = self.law(geom, interface, memory, row);
            row += law.rows();
            let start_gap = solver_gap(geom.g0, self.allowance, memory.is_some());
            let force = memory.map_or([0.0; 3], |m| m.force);
            warm.extend([force[0], force[1]]);
            if law.rows() == 3 {
                warm.push(force[2]);
            }
            lin.push(Linearization::initial(geom, start_gap));
            brief.push(Brief::of(geom, start_gap, &law, memory));
            laws.push(law);
        };
        let mut geoms = Geoms(geoms.into_sorted());
        geoms.0.iter_mut().flatten().for_each(&mut add);
        if joints {
            let partners = joint_partners((0..geoms.len()).map(|k| geoms.get(k)));
            for (l, p) in laws.iter_mut().zip(partners) {
                l.partner = p;
            }
        }
        let found = Detected { geoms, brief, sites, reach };
        (found, Inputs { warm, laws, lin }, threshold)
    }

    /// The law of one contact: interface of the two materials, capacities over the joint's
    /// length, rolling rows for particle contacts only (math note §4.4); its joint partner is
    /// set once all contacts are known.
    fn law(&self, g: &ContactGeom, i: &Interface, memory: Option<Memory>, row: usize) -> Law {
        let particle = matches!(g.kind, ContactKind::PP | ContactKind::PB | ContactKind::PL);
        // the joints broken before the step, or in the running trial
        let broke = |set: &std::collections::HashSet<_>| !set.is_empty() && set.contains(&g.key);
        let intact = !broke(&self.broken) && !broke(&self.next.broken);
        Law {
            row,
            friction: i.friction,
            cohesion: if intact { i.cohesion * g.joint_length } else { 0.0 },
            tensile: i.tensile_strength * g.joint_length,
            rolling: if particle { i.rolling } else { 0.0 },
            bonded: intact && memory.is_some_and(|m| m.bonded),
            partner: None,
            restitution: i.restitution,
        }
    }

    /// Cements the contacts closed at t = 0 whose interface has a tensile strength (math
    /// note §4.5, hypothesis i): the memory of a new world. Only joints have a length, so only
    /// edge-edge joints bond.
    pub(super) fn cement(&mut self) {
        let closed = 1e-9 * self.threshold;
        let (shapes, fixed) = self.shapes_and_fixed();
        let bonds = detect(&shapes, &fixed, self.threshold)
            .into_iter()
            .filter(|g| {
                let law = self
                    .contact_interface(g)
                    .map_or_else(|| self.interface(g.a, g.b), |i| &self.model.interfaces[i]);
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
