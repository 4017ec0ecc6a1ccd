//! Contact detection (math note §5): a broad phase over inflated AABBs, then one narrow-phase
//! function per contact type. Detection knows nothing about the solver: its only output is a
//! list of [`ContactGeom`].

mod block;
pub mod broad;
mod joint;
pub mod law;
pub mod narrow;
mod particle;
pub mod set;
#[cfg(test)]
mod testkit;

use crate::geometry::Vec2;

/// Current geometry of one body, as detection sees it.
#[derive(Debug, Clone)]
pub enum BodyShape {
    Disk {
        center: Vec2,
        radius: f64,
    },
    /// A ring particle; contacts from outside use `outer`, contacts in its hole use `inner`.
    Ring {
        center: Vec2,
        outer: f64,
        inner: f64,
    },
    /// A simple polygon, vertices counter-clockwise in the current configuration.
    /// `convex[i]` tells whether vertex i has an interior angle below 180°.
    Polygon {
        vertices: Vec<Vec2>,
        convex: Vec<bool>,
        /// A mesh's boundary loop: every flagged vertex is a node that moves on its own and
        /// carries its own contact with a particle (math note §9.2).
        nodes: bool,
        /// A mesh's holes (empty for a block); contact features number their vertices and
        /// edges after the outer loop's, hole by hole.
        holes: Vec<HoleLoop>,
    },
}

/// The boundary loop of a hole in a mesh (math note §9.2): clockwise, the material on its left,
/// so that its edges' outward normals point into the hole.
#[derive(Debug, Clone)]
pub struct HoleLoop {
    pub vertices: Vec<Vec2>,
    /// As `BodyShape::Polygon::convex`: a vertex where the material's interior angle is at
    /// most 180° (or nearly straight).
    pub convex: Vec<bool>,
}

/// `PP` particle-particle, `PB` particle-block, `BB` block-block; on a mesh's boundary loop (math
/// note §9.2) `LL` loop-loop, `PL` particle-loop, `BL` block-loop (contacts.csv `kind`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ContactKind {
    PP,
    PB,
    BB,
    LL,
    PL,
    BL,
}

impl ContactKind {
    pub fn as_str(self) -> &'static str {
        match self {
            ContactKind::PP => "PP",
            ContactKind::PB => "PB",
            ContactKind::BB => "BB",
            ContactKind::LL => "LL",
            ContactKind::PL => "PL",
            ContactKind::BL => "BL",
        }
    }
}

/// Renames the kind of a contact on a mesh body (`mesh(b)`): a mesh's outer loop is detected as a
/// polygon block (math note §9.2: L-L as B-B, P-L as P-B, B-L as B-B).
pub fn label_mesh_kind(g: &mut ContactGeom, mesh: impl Fn(usize) -> bool) {
    g.kind = match (g.kind, mesh(g.a), mesh(g.b)) {
        (ContactKind::PB, true, _) | (ContactKind::PB, _, true) => ContactKind::PL,
        (ContactKind::BB, true, true) => ContactKind::LL,
        (ContactKind::BB, true, false) | (ContactKind::BB, false, true) => ContactKind::BL,
        (kind, _, _) => kind,
    };
}

/// Which features of the two bodies touch; part of the persistent contact key.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize)]
pub enum Feature {
    /// The whole outer circle of a particle.
    Outer,
    /// The inner circle (hole) of a ring.
    Inner,
    Vertex(u32),
    Edge(u32),
}

/// Persistent identity of a contact across steps (warm start, "was closed" memory).
/// `a` is the body the normal points into (math note §0), `b` the other.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize)]
pub struct ContactKey {
    pub a: u32,
    pub fa: Feature,
    pub b: u32,
    pub fb: Feature,
}

/// Identity of an edge-edge joint: the two edges, body indices ascending.
/// Both adjoint vertex-edge contacts of the joint carry it (math note §4.6, §5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct JointKey {
    pub body_lo: u32,
    pub edge_lo: u32,
    pub body_hi: u32,
    pub edge_hi: u32,
}

/// One contact found by detection at the start of a step.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactGeom {
    pub key: ContactKey,
    /// Edge-edge joint this contact is one end of, if it shares the joint's strength with the
    /// joint's other end (math note §4.6).
    pub joint: Option<JointKey>,
    /// The length of joint whose strength the contact carries [m] (cohesion and tensile
    /// capacity = stress × this length): the overlap of its joint's two edges, shared with the
    /// partner; on a face of several joints (a mesh's nodes along an edge), without a joint,
    /// its tributary length (math note §4.15); 0 for other contacts.
    pub joint_length: f64,
    pub kind: ContactKind,
    /// Body index the normal points into (A of math note §0).
    pub a: usize,
    /// The other body (B).
    pub b: usize,
    /// Contact point C: midpoint of the two surface points (math note §5).
    pub point: Vec2,
    /// Unit normal n, pointing into A.
    pub normal: Vec2,
    /// Signed separation g0 along n: positive when apart, negative when penetrating.
    pub g0: f64,
}

/// Finds all contacts with `g0 < threshold` between pairs of bodies that are not both fixed.
/// The result is sorted by key, so that runs are deterministic.
pub fn detect(shapes: &[BodyShape], fixed: &[bool], threshold: f64) -> Vec<ContactGeom> {
    detect_reaching(shapes, fixed, threshold, threshold)
}

/// [`detect`] with the threshold enlarged to `reach` for a step's predicted motion (math note
/// §5) while a vertex may still start at most `depth` (d0) inside the other body's edge line:
/// the enlargement looks farther ahead, never deeper inside (a vertex `reach` deep behind an
/// edge of a body thinner than that is on the body's far side, and its contact, opposite to
/// the near side's, would make the VI unbounded).
pub fn detect_reaching(shapes: &[BodyShape], fixed: &[bool], reach: f64, depth: f64) -> Vec<ContactGeom> {
    detect_in(shapes, broad::candidate_pairs(shapes, fixed, reach), reach, depth)
}

/// [`detect_reaching`] over the candidate pairs of `reach` (from [`broad::candidate_pairs`] or
/// a [`broad::PairCache`]).
pub fn detect_in(
    shapes: &[BodyShape],
    pairs: Vec<(usize, usize)>,
    reach: f64,
    depth: f64,
) -> Vec<ContactGeom> {
    let [mut contacts, second] = detect_in_order(shapes, &pairs, reach, depth).into_sorted();
    contacts.extend(second);
    contacts
}

/// From this many candidate pairs on, [`detect_in_order`] runs the narrow phase in two halves
/// of the pairs, one per core; below it the join costs more than the half it saves (math note
/// §3.3, "Both cores"; `benches/step.rs`, `rigid_disks_1000` on one core, `rigid_disks_10000`
/// on two).
const HALVES_FROM: usize = 8_000;

/// [`detect_in_order`]'s contacts: those of the first half of the pairs, then those of the
/// second, and the indices that read them in key order (into `halves[0]`, which then holds
/// them all), or `None` when they were found in key order.
pub(crate) struct InOrder {
    pub halves: [Vec<ContactGeom>; 2],
    pub order: Option<Vec<usize>>,
}

impl InOrder {
    /// How many contacts were found.
    pub fn count(&self) -> usize {
        self.halves.iter().map(Vec::len).sum()
    }

    /// The contacts in key order, in two vectors read one after the other: as found when that
    /// is key order, else copied in the indices' order into the first (each contact copied once).
    pub fn into_sorted(self) -> [Vec<ContactGeom>; 2] {
        match self.order {
            None => self.halves,
            Some(order) => [order.into_iter().map(|k| self.halves[0][k].clone()).collect(), Vec::new()],
        }
    }
}

/// [`detect_in`]'s contacts in the order the pairs gave them, and the indices that read them in
/// key order (a stable sort's), or `None` when they were found in key order, as a pile's are
/// from pairs listed as [`broad::candidate_pairs`] lists them. A caller that reads each
/// contact once reads them through the indices instead of moving them (sorting the contacts
/// themselves, 112 bytes each, costs cache misses on a large pile; math note §3.3, "Per-body
/// tables"). From
/// [`HALVES_FROM`] pairs on, each half of the pairs is done on a core of its own, into a vector
/// of its own: the reader goes on from one to the other, where one vector would have to be
/// copied onto the end of the other.
pub(crate) fn detect_in_order(
    shapes: &[BodyShape],
    pairs: &[(usize, usize)],
    reach: f64,
    depth: f64,
) -> InOrder {
    in_order(shapes, pairs, reach, depth, HALVES_FROM)
}

/// [`detect_in_order`], in halves from `halves_from` pairs on.
fn in_order(
    shapes: &[BodyShape],
    pairs: &[(usize, usize)],
    reach: f64,
    depth: f64,
    halves_from: usize,
) -> InOrder {
    let tol = narrow::Tolerances::new(reach).with_depth(depth);
    let half = if pairs.len() >= halves_from { pairs.len() / 2 } else { pairs.len() };
    let (first, second) = pairs.split_at(half);
    let narrow = |pairs: &[(usize, usize)]| {
        let mut out: Vec<ContactGeom> = Vec::with_capacity(pairs.len());
        // whether the contacts come in key order, as the pairs' order gives a pile's
        // (`broad::oriented`): each pair's contacts checked against the last one before them
        // while they are in the cache (a pass of its own over 30,000 contacts cost 37,000 cache
        // misses)
        let mut sorted = true;
        for &(i, j) in pairs {
            let from = out.len();
            narrow::pair_contacts_with(i, j, &shapes[i], &shapes[j], &tol, &mut out);
            for k in from.max(1)..out.len() {
                sorted &= out[k - 1].key < out[k].key;
            }
        }
        (out, sorted)
    };
    let ((mut out, sorted1), (out2, sorted2)) = if second.is_empty() {
        (narrow(first), (Vec::new(), true))
    } else {
        micropool::join(|| narrow(first), || narrow(second))
    };
    let meet = match (out.last(), out2.first()) {
        (Some(a), Some(b)) => a.key < b.key,
        _ => true,
    };
    if sorted1 && sorted2 && meet {
        return InOrder { halves: [out, out2], order: None };
    }
    out.extend(out2);
    let mut order: Vec<(ContactKey, usize)> = out.iter().enumerate().map(|(k, c)| (c.key, k)).collect();
    // stable, and adaptive to the sorted runs the pairs give
    order.sort_by_key(|e| e.0);
    InOrder { halves: [out, Vec::new()], order: Some(order.into_iter().map(|e| e.1).collect()) }
}

#[cfg(test)]
mod tests {
    use super::testkit::{disk, rect};
    use super::*;

    /// Detection's key order, read through [`detect_in_order`]'s indices. A floor (body 0)
    /// under a row of four touching disks (bodies 1–4): the floor's contacts have the disks as
    /// `a`, and the oriented pairs (`broad::oriented`) give all seven in key order as found, so
    /// there are no indices (counted by hand: four disk–floor contacts, three disk–disk). With
    /// a box (body 5) on the floor right of the disks, the floor–box pair (0, 5) comes first;
    /// its edge-edge joint's two vertex–edge contacts (`a` = 0, the floor's edge) come from
    /// `joint::edge_edge` in the order of the floor's top edge, which runs opposite to the
    /// box's bottom edge (vertex 0 to 1, counter-clockwise from `rect`'s first corner): box
    /// vertex 1 first, then vertex 0, not in key order, so the indices read them swapped, as a
    /// stable sort of the contacts as found does. In both scenes `detect` gives the contacts in
    /// the indices' order.
    #[test]
    fn indices_read_the_contacts_in_key_order() {
        let mut shapes = vec![rect(-1.0, -1.0, 12.0, 0.0)];
        shapes.extend((0..4).map(|k| disk(1.0 + 2.0 * k as f64, 1.0, 1.0)));
        let read = |shapes: &[BodyShape]| {
            let mut fixed = vec![false; shapes.len()];
            fixed[0] = true;
            let pairs = broad::candidate_pairs(shapes, &fixed, 0.1);
            let InOrder { halves: [found, rest], order } = detect_in_order(shapes, &pairs, 0.1, 0.1);
            assert!(rest.is_empty(), "a few pairs are one half");
            let mut expected = found.clone();
            expected.sort_by_key(|c| c.key);
            let identity: Vec<usize> = (0..found.len()).collect();
            let read: Vec<ContactGeom> =
                order.as_ref().unwrap_or(&identity).iter().map(|&k| found[k].clone()).collect();
            assert_eq!(read, expected);
            assert_eq!(detect(shapes, &fixed, 0.1), expected);
            let keys: Vec<(u32, u32)> = expected.iter().map(|c| (c.key.a, c.key.b)).collect();
            (order, keys)
        };
        let (order, keys) = read(&shapes);
        assert_eq!(order, None);
        assert_eq!(keys, [(1, 0), (1, 2), (2, 0), (2, 3), (3, 0), (3, 4), (4, 0)]);
        shapes.push(rect(9.5, 0.0, 11.5, 1.0));
        let (order, keys) = read(&shapes);
        assert_eq!(order, Some(vec![1, 0, 2, 3, 4, 5, 6, 7, 8]));
        assert_eq!(keys, [(0, 5), (0, 5), (1, 0), (1, 2), (2, 0), (2, 3), (3, 0), (3, 4), (4, 0)]);
    }

    /// The narrow phase in halves ([`in_order`] from `HALVES_FROM` pairs) gives the contacts of
    /// the serial one, in the same order, with the same indices: a hexagonal pile of 60 × 50
    /// disks of radius 1 on a floor (about 8,900 pairs, above `HALVES_FROM`), then the same
    /// pile with a box on the floor whose pair comes first and whose joint's two contacts come
    /// out of key order (as in the test above), so that the halves are joined and sorted. The
    /// indices read the contacts in key order both times.
    #[test]
    fn halves_find_the_serial_contacts_in_order() {
        let mut shapes = vec![rect(-2.0, -1.0, 125.0, 0.0)];
        for row in 0..50 {
            let y = 1.0 + row as f64 * 3f64.sqrt();
            let x0 = if row % 2 == 0 { 1.0 } else { 2.0 };
            shapes.extend((0..60).map(|k| disk(x0 + 2.0 * k as f64, y, 1.0)));
        }
        for with_box in [false, true] {
            if with_box {
                shapes.push(rect(122.5, 0.0, 124.5, 1.0));
            }
            let mut fixed = vec![false; shapes.len()];
            fixed[0] = true;
            let pairs = broad::candidate_pairs(&shapes, &fixed, 0.1);
            assert!(pairs.len() >= HALVES_FROM, "{} pairs", pairs.len());
            let read = |found: InOrder| found.into_sorted().concat();
            let (halves, serial) = (
                in_order(&shapes, &pairs, 0.1, 0.1, HALVES_FROM),
                in_order(&shapes, &pairs, 0.1, 0.1, usize::MAX),
            );
            assert_eq!(halves.order.is_some(), with_box);
            assert_eq!(serial.order.is_some(), with_box);
            assert!(!halves.halves[1].is_empty() || with_box, "two halves");
            let (got, want) = (read(halves), read(serial));
            assert_eq!(got, want);
            assert!(got.windows(2).all(|w| w[0].key < w[1].key));
        }
    }
}
