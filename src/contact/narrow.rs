//! Narrow phase (math note §5; paper Section 3, Figures 2-5): dispatches a candidate pair to
//! one function per contact type and holds the pieces they share (body views, edges,
//! tolerances, the vertex-edge contact geometry).
//!
//! - particle-particle and particle-block: `particle.rs`;
//! - block-block vertex-edge and vertex-vertex, and the dedupe: `block.rs`;
//! - block-block edge-edge (two adjoint vertex-edge contacts): `joint.rs`.

use super::{BodyShape, ContactGeom, ContactKey, ContactKind, Feature};
use crate::geometry::{Vec2, cw};

/// Angle below which two edges count as anti-parallel (edge-edge joint, math note §5:
/// "about 1-3°"), and by which an edge next to a vertex may dip through the other body's
/// edge line in the vertex-edge cone test. 2°: a rotation of a few tenths of a degree per
/// step still keeps a resting face a joint, while a block resting on one corner with a
/// visibly tilted face (> 2°) is not mistaken for a face-to-face contact.
pub const ANGLE_TOLERANCE_DEG: f64 = 2.0;

/// Dedupe distance as a fraction of the contact threshold (d0 in the paper): two block-block
/// contacts of the same pair closer than this, with (anti)parallel normals, are one contact;
/// two candidate joint ends closer than this along the edge are one end.
pub const MERGE_FRACTION: f64 = 0.01;

/// Two vertex-vertex candidates whose g0 differ by less than this fraction of d0 are a tie.
pub const TIE_FRACTION: f64 = 1e-6;

/// Finds the contacts between bodies `i` and `j` whose signed separation g0 is below
/// `threshold` (d0 in the paper, math note §5) and appends them to `out`.
/// `shape_i` and `shape_j` are the current shapes of bodies `i` and `j`; the order of the two
/// bodies does not matter.
pub fn pair_contacts(
    i: usize,
    j: usize,
    shape_i: &BodyShape,
    shape_j: &BodyShape,
    threshold: f64,
    out: &mut Vec<ContactGeom>,
) {
    pair_contacts_with(i, j, shape_i, shape_j, &Tolerances::new(threshold), out);
}

/// [`pair_contacts`] with given tolerances.
pub(crate) fn pair_contacts_with(
    i: usize,
    j: usize,
    shape_i: &BodyShape,
    shape_j: &BodyShape,
    tol: &Tolerances,
    out: &mut Vec<ContactGeom>,
) {
    use super::block::block_block;
    use super::particle::{particle_block, particle_particle};
    match (Particle::of(i, shape_i), Particle::of(j, shape_j)) {
        (Some(p), Some(q)) => particle_particle(&p, &q, tol, out),
        (Some(p), None) | (None, Some(p)) => {
            let b = if p.body == i { Outline::of(j, shape_j) } else { Outline::of(i, shape_i) };
            for l in std::iter::once(&b.outer).chain(&b.holes) {
                particle_block(&p, l, tol, out);
            }
        }
        (None, None) => {
            let (a, b) = (Outline::of(i, shape_i), Outline::of(j, shape_j));
            // two holes never meet: a body in a hole of the other meets it with its outer loop
            block_block(&a.outer, &b.outer, tol, out);
            for h in &b.holes {
                block_block(&a.outer, h, tol, out);
            }
            for h in &a.holes {
                block_block(h, &b.outer, tol, out);
            }
        }
    }
}

/// A polygon's outline and a mesh's holes, as the narrow phase sees them (no allocation for the
/// holes of a polygon without any).
struct Outline<'a> {
    outer: Polygon<'a>,
    holes: Vec<Polygon<'a>>,
}

impl<'a> Outline<'a> {
    /// The loops of a polygon; a particle has none (an outline without vertices touches
    /// nothing).
    fn of(body: usize, shape: &'a BodyShape) -> Outline<'a> {
        let BodyShape::Polygon { ref vertices, ref convex, nodes, ref holes } = *shape else {
            return Outline { outer: Polygon::new(body, &[], &[]), holes: Vec::new() };
        };
        let (mut loops, mut first) = (Vec::with_capacity(holes.len()), vertices.len());
        for h in holes {
            let hole = Polygon::new(body, &h.vertices, &h.convex);
            loops.push(Polygon { nodes, hole: true, first: first as u32, ..hole });
            first += h.vertices.len();
        }
        Outline { outer: Polygon { nodes, ..Polygon::new(body, vertices, convex) }, holes: loops }
    }
}

/// The tolerances of one detection pass, all derived from the contact threshold.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Tolerances {
    /// d0 in the paper, or d0 enlarged for a step's predicted motion: contacts are created for
    /// g0 < threshold.
    pub threshold: f64,
    /// d0: vertex-edge contacts also need g0 > -depth (penetration allowance; not enlarged).
    pub depth: f64,
    /// cos of [`ANGLE_TOLERANCE_DEG`].
    pub cos_angle: f64,
    /// sin of [`ANGLE_TOLERANCE_DEG`].
    pub sin_angle: f64,
    /// Dedupe distance, [`MERGE_FRACTION`] × d0.
    pub merge: f64,
    /// Tie width for vertex-vertex candidates, [`TIE_FRACTION`] × d0.
    pub tie: f64,
}

impl Tolerances {
    /// Whether a signed separation is below the threshold (false for NaN).
    pub fn detects(&self, g0: f64) -> bool {
        g0 < self.threshold
    }

    /// These tolerances with the penetration allowance `depth` (at most the threshold).
    pub fn with_depth(self, depth: f64) -> Tolerances {
        Tolerances { depth: depth.min(self.threshold), ..self }
    }

    pub fn new(threshold: f64) -> Tolerances {
        let angle = ANGLE_TOLERANCE_DEG.to_radians();
        Tolerances {
            threshold,
            depth: threshold,
            cos_angle: angle.cos(),
            sin_angle: angle.sin(),
            merge: MERGE_FRACTION * threshold.max(0.0),
            tie: TIE_FRACTION * threshold.max(0.0),
        }
    }
}

/// A disk or a ring as detection sees it; a disk has `inner = 0`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Particle {
    pub body: usize,
    pub center: Vec2,
    /// Outer radius (R, or RE of a ring).
    pub outer: f64,
    /// Inner radius RI of a ring; 0 for a disk.
    pub inner: f64,
}

impl Particle {
    /// The particle of a disk or ring; `None` for a polygon.
    fn of(body: usize, shape: &BodyShape) -> Option<Particle> {
        match *shape {
            BodyShape::Disk { center, radius } => Some(Particle { body, center, outer: radius, inner: 0.0 }),
            BodyShape::Ring { center, outer, inner } => Some(Particle { body, center, outer, inner }),
            BodyShape::Polygon { .. } => None,
        }
    }

    pub fn is_ring(&self) -> bool {
        self.inner > 0.0
    }
}

/// A polygon (CCW) as detection sees it: vertex k, edge k from vertex k to vertex k+1.
#[derive(Debug, Clone)]
pub(crate) struct Polygon<'a> {
    pub body: usize,
    pub vertices: &'a [Vec2],
    /// `convex[k]`: the interior angle at vertex k is below 180°.
    pub convex: &'a [bool],
    /// A mesh's boundary loop (see [`BodyShape::Polygon`]).
    pub nodes: bool,
    /// A hole of a mesh (clockwise; its edges' outward normals point into the hole).
    pub hole: bool,
    /// The body's feature number of this loop's vertex 0 and edge 0 (see [`Polygon::id`]).
    pub first: u32,
    /// `edges[k]`: edge k, computed once per pair. A zero-length edge has a NaN direction, so
    /// every test on it fails and it makes no contact.
    edges: Vec<Edge>,
}

/// One polygon edge: start, unit direction t, length L, outward unit normal `cw(t)`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Edge {
    pub start: Vec2,
    pub t: Vec2,
    pub len: f64,
    /// Normal pointing away from the polygon's material (n_out of math note §5).
    pub n_out: Vec2,
}

impl Edge {
    /// Position of the projection of `p` along the edge, from its start.
    pub fn along(&self, p: Vec2) -> f64 {
        (p - self.start).dot(&self.t)
    }

    /// Signed distance of `p` from the edge line, positive on the outer side.
    pub fn height(&self, p: Vec2) -> f64 {
        (p - self.start).dot(&self.n_out)
    }
}

impl<'a> Polygon<'a> {
    pub fn new(body: usize, vertices: &'a [Vec2], convex: &'a [bool]) -> Polygon<'a> {
        let n = vertices.len();
        let edges = (0..n)
            .map(|k| {
                let (start, d) = (vertices[k], vertices[(k + 1) % n] - vertices[k]);
                let len = d.norm();
                let t = d / len;
                Edge { start, t, len, n_out: cw(t) }
            })
            .collect();
        Polygon { body, vertices, convex, nodes: false, hole: false, first: 0, edges }
    }

    /// Sine of the turn at vertex k (cross product of its edges' unit directions): positive
    /// at a convex corner, within ±[`STRAIGHT_SINE`](crate::geometry::STRAIGHT_SINE) on a
    /// straight stretch of a loop.
    pub fn turn(&self, k: usize) -> f64 {
        crate::geometry::cross(self.edges[self.prev(k)].t, self.edges[k].t)
    }

    /// The same polygon with other contact-vertex flags.
    pub fn with_convex<'b>(&self, convex: &'b [bool]) -> Polygon<'b>
    where
        'a: 'b,
    {
        Polygon { convex, ..self.clone() }
    }

    /// The body's number of vertex or edge k of this loop, for its contact features: loops
    /// are numbered in turn, the outline first.
    pub fn id(&self, k: usize) -> u32 {
        self.first + k as u32
    }

    pub fn vertex_count(&self) -> usize {
        self.vertices.len()
    }

    pub fn next(&self, k: usize) -> usize {
        (k + 1) % self.vertex_count()
    }

    pub fn prev(&self, k: usize) -> usize {
        (k + self.vertex_count() - 1) % self.vertex_count()
    }

    /// Edge k, from vertex k to vertex k+1.
    pub fn edge(&self, k: usize) -> Edge {
        self.edges[k]
    }

    /// Whether the projection of `p` falls inside edge `f`: open at a convex end (beyond it
    /// lies the end vertex's region), closed at a non-convex end (a notch, where the point
    /// may touch both edges).
    pub fn projects_inside(&self, f: usize, p: Vec2) -> bool {
        let e = self.edge(f);
        let s = e.along(p);
        let start_ok = s > 0.0 || (s >= 0.0 && !self.convex[f]);
        let end_ok = s < e.len || (s <= e.len && !self.convex[self.next(f)]);
        start_ok && end_ok
    }

    /// Whether vertex k of `x` (point `p`, `depth` = its height over edge f's line, negative:
    /// behind it) has edge f as its shortest way out of this polygon near edge f (math note §5.2).
    /// Each edge next to edge f at a convex end is a way out if the corner can cross its line, i.e.
    /// passes the cone test for it; then `p` must lie at least as deep behind it as behind edge f
    /// (to within the tie width, i.e. rounding). An edge the corner cannot cross (one of the
    /// corner's own edges runs inside across its line, as when two blocks' sides are flush) is no
    /// way out; `p` must only lie on its inner side (to within the tie width): beyond it is outside
    /// the polygon, not a penetration. Non-convex ends need no test (there the region below edge f
    /// is material).
    pub fn behind_end_edges(&self, f: usize, x: &Polygon, k: usize, depth: f64, tol: &Tolerances) -> bool {
        let p = x.vertices[k];
        let shorter_exit = |g: usize| {
            let e = self.edge(g);
            let bound = if x.cone_clear(k, e.n_out, tol) { depth } else { 0.0 };
            e.height(p) > bound + tol.tie
        };
        let (start, end) = (f, self.next(f));
        let before = !self.convex[start] || !shorter_exit(self.prev(f));
        let after = !self.convex[end] || !shorter_exit(end);
        before && after
    }

    /// The cone test of a vertex-edge contact: neither edge incident to vertex k dips through
    /// a line of outward normal `n_out` by more than the angle tolerance, so vertex k is
    /// locally the point of this body closest to that line.
    pub fn cone_clear(&self, k: usize, n_out: Vec2, tol: &Tolerances) -> bool {
        // unit directions from vertex k along its two edges
        let (to_prev, to_next) = (-self.edges[self.prev(k)].t, self.edges[k].t);
        to_prev.dot(&n_out) >= -tol.sin_angle && to_next.dot(&n_out) >= -tol.sin_angle
    }
}

/// A contact without a joint.
pub(crate) fn plain_contact(
    key: ContactKey,
    kind: ContactKind,
    point: Vec2,
    normal: Vec2,
    g0: f64,
) -> ContactGeom {
    ContactGeom {
        key,
        joint: None,
        joint_length: 0.0,
        kind,
        a: key.a as usize,
        b: key.b as usize,
        point,
        normal,
        g0,
    }
}

/// Vertex k of polygon `x` against edge f of polygon `y` (math note §5, B-B vertex-edge):
/// A = `y` (edge owner), n = inward normal of the edge, g0 = height of the vertex above the
/// edge line, contact point = midpoint of the vertex and its projection on the line.
/// Pure geometry: the caller decides whether the contact exists.
pub(crate) fn vertex_edge_geom(x: &Polygon, k: usize, y: &Polygon, f: usize) -> ContactGeom {
    let e = y.edge(f);
    let v = x.vertices[k];
    let g0 = e.height(v);
    let key = ContactKey {
        a: y.body as u32,
        fa: Feature::Edge(y.id(f)),
        b: x.body as u32,
        fb: Feature::Vertex(x.id(k)),
    };
    plain_contact(key, ContactKind::BB, v - 0.5 * g0 * e.n_out, -e.n_out, g0)
}

#[cfg(test)]
mod tests {
    use super::super::testkit::*;
    use super::super::{ContactKind, Feature::*, JointKey, detect, detect_reaching};

    /// Closed forms evaluated in f64 from coordinates of order 10-100: a few ulp.
    const TOL: f64 = 1e-11;

    /// A threshold enlarged for a big step looks farther ahead, never deeper inside (math note
    /// §5): a 1 m block (body 1) 0.01 above a 0.3 m plate (body 0, [0,2]×[-0.3,0]), threshold
    /// enlarged to 12.5 (a predicted fall of 5 m) with d0 = 0.1. The block's bottom corners lie
    /// 0.31 behind the plate's bottom edge (edge 0, outward normal -y): with the enlargement as
    /// the penetration bound too they made contacts there, opposite to those on the top face, and
    /// the pair's VI was unbounded (a meshed block on a meshed base diverged at dt = 1 s). With
    /// the bound kept at d0 no contact uses edge 0; the top face still holds the block.
    #[test]
    fn enlarged_threshold_does_not_reach_through_a_plate() {
        let shapes = [rect(0.0, -0.3, 2.0, 0.0), rect(0.5, 0.01, 1.5, 1.01)];
        let through = |c: &[crate::contact::ContactGeom]| {
            c.iter().filter(|c| c.key.a == 0 && c.key.fa == Edge(0)).count()
        };
        assert_eq!(through(&detect(&shapes, &[true, false], 12.5)), 2);
        let c = detect_reaching(&shapes, &[true, false], 12.5, 0.1);
        assert_eq!(through(&c), 0, "{c:?}");
        let top: Vec<_> = c.iter().filter(|c| (c.point.y - 0.005).abs() < 1e-12).collect();
        assert_eq!(top.len(), 2, "the block's bottom corners on the plate's top: {c:?}");
        assert!(top.iter().all(|c| (c.g0 - 0.01).abs() < 1e-12));
    }

    /// Math note §7.4 frame: four fixed walls (bodies 0-3: bottom, top, left, right) around the
    /// inner square [-60,60]², walls touching at the corners; a free 20×20 square (body 4)
    /// 0.01 from each wall in turn. Each position gives exactly one joint: the square's two
    /// vertices on the wall's inner edge, A = wall, n = into the wall, g0 = 0.01, points 0.005
    /// off the wall, joint length 20. The touching walls (both fixed) give nothing.
    #[test]
    fn square_near_each_wall_of_a_frame() {
        let walls = [
            rect(-70.0, -70.0, 70.0, -60.0),
            rect(-70.0, 60.0, 70.0, 70.0),
            rect(-70.0, -60.0, -60.0, 60.0),
            rect(60.0, -60.0, 70.0, 60.0),
        ];
        // (square, wall edge, square vertices, n, the two points, joint key)
        type Case = ([f64; 4], u32, [u32; 2], (f64, f64), [(f64, f64); 2], JointKey);
        let jk = |body_lo, edge_lo, edge_hi| JointKey { body_lo, edge_lo, body_hi: 4, edge_hi };
        let cases: [Case; 4] = [
            (
                [-10., -59.99, 10., -39.99],
                2,
                [0, 1],
                (0., -1.),
                [(-10., -59.995), (10., -59.995)],
                jk(0, 2, 0),
            ),
            ([-10., 39.99, 10., 59.99], 0, [2, 3], (0., 1.), [(10., 59.995), (-10., 59.995)], jk(1, 0, 2)),
            (
                [-59.99, -10., -39.99, 10.],
                1,
                [0, 3],
                (-1., 0.),
                [(-59.995, -10.), (-59.995, 10.)],
                jk(2, 1, 3),
            ),
            ([39.99, -10., 59.99, 10.], 3, [1, 2], (1., 0.), [(59.995, -10.), (59.995, 10.)], jk(3, 3, 1)),
        ];
        for (wall, (sq, edge, verts, n, points, joint)) in cases.into_iter().enumerate() {
            let mut shapes = walls.to_vec();
            shapes.push(rect(sq[0], sq[1], sq[2], sq[3]));
            let c = detect(&shapes, &[true, true, true, true, false], 0.1);
            assert_eq!(c.len(), 2, "wall {wall}: {c:?}");
            for k in 0..2 {
                let kk = key(wall as u32, Edge(edge), 4, Vertex(verts[k]));
                check(&c[k], kk, ContactKind::BB, n, 0.01, points[k], TOL);
                assert_eq!(c[k].joint, Some(joint));
                assert!((c[k].joint_length - 20.0).abs() < TOL);
            }
        }
    }

    /// Math note §7.1 heap: floor [-50,50]×[-10,0] (body 0, fixed), disks R = 10 at (0,10),
    /// (0,30), (0,50): disk 1 on the floor's top edge (A = disk, n = +y, point (0,0)); P-P at
    /// y = 20 and 40 with A = the lower (smaller-index) disk, n = e = (P_i - P_j)/|..| = -y.
    /// All g0 = 0.
    #[test]
    fn heap_of_three_disks() {
        let shapes = [
            rect(-50.0, -10.0, 50.0, 0.0),
            disk(0.0, 10.0, 10.0),
            disk(0.0, 30.0, 10.0),
            disk(0.0, 50.0, 10.0),
        ];
        let c = detect(&shapes, &[true, false, false, false], 0.1);
        assert_eq!(c.len(), 3, "{c:?}");
        check(&c[0], key(1, Outer, 0, Edge(2)), ContactKind::PB, (0.0, 1.0), 0.0, (0.0, 0.0), TOL);
        check(&c[1], key(1, Outer, 2, Outer), ContactKind::PP, (0.0, -1.0), 0.0, (0.0, 20.0), TOL);
        check(&c[2], key(2, Outer, 3, Outer), ContactKind::PP, (0.0, -1.0), 0.0, (0.0, 40.0), TOL);
    }

    /// Pairs of fixed bodies never produce contacts (math note §5), however close: touching
    /// blocks, a disk on a block, a disk in a ring.
    #[test]
    fn fixed_pairs_give_nothing() {
        let shapes = [
            rect(0.0, 0.0, 1.0, 1.0),
            rect(1.0, 0.0, 2.0, 1.0),
            disk(0.5, 1.5, 0.5),
            ring(10.0, 0.0, 3.0, 2.0),
            disk(10.0, 1.0, 1.0),
        ];
        assert!(detect(&shapes, &[true; 5], 0.1).is_empty());
    }

    /// A ring far from everything (100 away) has no contact; the rest of the scene still has
    /// its own (the disk resting on the block: one contact).
    #[test]
    fn far_ring_gives_nothing() {
        let shapes = [rect(0.0, 0.0, 1.0, 1.0), disk(0.5, 1.5, 0.5), ring(100.0, 100.0, 3.0, 1.0)];
        let c = detect(&shapes, &[true, false, false], 0.1);
        assert_eq!(c.len(), 1);
        assert!(c.iter().all(|k| k.a != 2 && k.b != 2));
    }
}
