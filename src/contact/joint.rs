//! Edge-edge contacts (math note §5 "Edge-edge", §4.6; paper Section 3, Figure 5): two nearly
//! anti-parallel edges whose projections overlap become two adjoint vertex-edge contacts, one
//! at each end of the overlap, tagged with the same [`JointKey`] and the overlap length
//! (cohesion and tensile capacity are shared by the pair, math note §4.6).

use super::block::{seam_end, vertex_edge_admissible};
use super::narrow::{Polygon, Tolerances, vertex_edge_geom};
use super::{ContactGeom, JointKey};
use std::collections::BTreeMap;

/// Joints between the edges of `x` and `y`; `x` must be the body with the smaller index.
/// Where one vertex ends several joints (a mesh node between two edges of a face), the joints'
/// strength is shared by tributary lengths ([`tributary`], math note §4.15).
pub fn edge_edge(x: &Polygon, y: &Polygon, tol: &Tolerances, out: &mut Vec<ContactGeom>) {
    let mut found = Vec::new();
    for e in 0..x.vertex_count() {
        for f in 0..y.vertex_count() {
            joint(x, e, y, f, tol, &mut found);
        }
    }
    tributary(found, tol, |c| seam_end(c, x, y, tol), out);
}

/// Math note §4.15: the joints' contacts, with those that coincide merged. Two contacts
/// coincide as the block-block dedupe sees them (same key, or within the merge distance with
/// parallel or anti-parallel normals): the same node ending two joints of a face. Without a
/// coincidence the contacts are left as found (two partners share their joint's length,
/// §4.6). With one, every joint that has a merged end (its "face") gives each of its n end
/// contacts (1 or 2) L/n of its length L; such a contact carries the sum of its shares over the
/// joints it ends as its own capacity length, without a partner (`joint` None). The lengths
/// of a face's contacts then add up to the joints' lengths, the merged ends' shares included. At a seam (`seam`, math note §5.1) the end contacts of the two
/// edge pieces do not coincide: each keeps its own joint and law.
fn tributary(
    found: Vec<ContactGeom>,
    tol: &Tolerances,
    seam: impl Fn(&ContactGeom) -> bool,
    out: &mut Vec<ContactGeom>,
) {
    let same = |a: &ContactGeom, b: &ContactGeom| {
        a.key == b.key
            || ((a.point - b.point).norm() <= tol.merge
                && a.normal.dot(&b.normal).abs() >= tol.cos_angle
                && !(seam(a) && seam(b)))
    };
    // owner[k]: the first contact that contact k coincides with (itself if none)
    let owner: Vec<usize> =
        (0..found.len()).map(|k| (0..k).find(|&i| same(&found[i], &found[k])).unwrap_or(k)).collect();
    if owner.iter().enumerate().all(|(k, &o)| o == k) {
        out.extend(found);
        return;
    }
    // per joint: its end contacts and whether one of them is merged
    let mut joints: BTreeMap<Option<JointKey>, (f64, bool)> = BTreeMap::new();
    for (k, c) in found.iter().enumerate() {
        let j = joints.entry(c.joint).or_default();
        j.0 += 1.0;
        j.1 |= owner[k] != k || owner[k + 1..].contains(&k);
    }
    let mut length = vec![0.0; found.len()];
    let mut face = vec![false; found.len()];
    for (k, c) in found.iter().enumerate() {
        if let Some(&(ends, true)) = joints.get(&c.joint) {
            length[owner[k]] += c.joint_length / ends;
            face[owner[k]] = true;
        }
    }
    for (k, mut c) in found.into_iter().enumerate() {
        if owner[k] != k {
            continue;
        }
        if face[k] {
            c.joint = None;
            c.joint_length = length[k];
        }
        out.push(c);
    }
}

/// Edge e of `x` against edge f of `y`. Nearly anti-parallel (within the angle tolerance), the
/// overlap of their projections on e longer than the merge distance, and both end contacts
/// admissible vertex-edge contacts (g0 within (-d0, d0), cone test): two contacts.
/// At each end of the overlap the contact is the vertex lying inside the other edge, on that
/// edge: in a full overlap both are on the longer edge (same A, same normal); in a partial
/// overlap each body contributes one vertex (different A, nearly opposite normals).
/// The overlap length is measured along e (edge of the smaller body index).
/// If one end fails the band or cone test, there is no joint: the other end, if valid, is
/// found as a single vertex-edge contact. An end whose vertex is not convex (a straight 180°
/// vertex in the middle of a longer face) makes no contact, and the joint keeps one contact.
fn joint(x: &Polygon, e: usize, y: &Polygon, f: usize, tol: &Tolerances, out: &mut Vec<ContactGeom>) {
    let (ex, ey) = (x.edge(e), y.edge(f));
    let anti_parallel = ex.t.dot(&ey.t) <= -tol.cos_angle;
    if !anti_parallel {
        return;
    }
    // f runs backwards along e: its end lies towards e's start, its start towards e's end
    let s_lo = ex.along(y.vertices[y.next(f)]);
    let s_hi = ex.along(ey.start);
    let overlap = s_hi.min(ex.len) - s_lo.max(0.0);
    let long_enough = overlap > tol.merge;
    if !long_enough {
        return;
    }
    let ends = [
        end_contact(x, e, e, y, f, y.next(f), s_lo, tol),
        end_contact(x, e, x.next(e), y, f, f, ex.len - s_hi, tol),
    ];
    if ends.iter().any(|c| matches!(c, End::Invalid)) {
        return;
    }
    let key = JointKey { body_lo: x.body as u32, edge_lo: x.id(e), body_hi: y.body as u32, edge_hi: y.id(f) };
    for end in ends {
        if let End::Contact(mut c) = end {
            c.joint = Some(key);
            c.joint_length = overlap;
            out.push(c);
        }
    }
}

/// What one end of an overlap contributes.
enum End {
    Contact(ContactGeom),
    /// The end vertex is not convex: no contact here.
    Absent,
    /// The end vertex is too far, too deep, or not locally closest: no joint at all.
    Invalid,
}

/// One end of the overlap of edge e of `x` and edge f of `y`. `vx` and `vy` are the two
/// candidate vertices at this end, and `depth` is how far `vy` lies inside e beyond `vx`.
/// The vertex lying inside the other edge makes the contact. When the two are closer than the
/// merge distance (coincident ends), exactly one contact is made: preferably `vy` on e (the
/// vertex of the larger body index on the edge of the smaller), else `vx` on f (when `vy` is
/// not convex, or not admissible, e.g. rounding puts it just outside `x` in a penetrating
/// joint).
#[allow(clippy::too_many_arguments)]
fn end_contact(
    x: &Polygon,
    e: usize,
    vx: usize,
    y: &Polygon,
    f: usize,
    vy: usize,
    depth: f64,
    tol: &Tolerances,
) -> End {
    let y_on_e = (y, vy, x, e);
    let x_on_f = (x, vx, y, f);
    let candidates = if depth.abs() <= tol.merge {
        vec![y_on_e, x_on_f]
    } else if depth > 0.0 {
        vec![y_on_e]
    } else {
        vec![x_on_f]
    };
    let convex: Vec<_> = candidates.into_iter().filter(|(p, k, ..)| p.convex[*k]).collect();
    if convex.is_empty() {
        return End::Absent;
    }
    convex
        .into_iter()
        .find(|(p, k, q, g)| vertex_edge_admissible(p, *k, q, *g, tol))
        .map_or(End::Invalid, |(p, k, q, g)| End::Contact(vertex_edge_geom(p, k, q, g)))
}

#[cfg(test)]
mod tests {
    use super::super::testkit::*;
    use super::super::{ContactKind, Feature::*, JointKey};

    const D0: f64 = 0.1;
    /// Closed forms evaluated in f64 from coordinates of order 1-20: a few ulp.
    const TOL: f64 = 1e-12;
    const BB: ContactKind = ContactKind::BB;

    fn jk(body_lo: u32, edge_lo: u32, body_hi: u32, edge_hi: u32) -> Option<JointKey> {
        Some(JointKey { body_lo, edge_lo, body_hi, edge_hi })
    }

    /// Math note §7.2, level 1/2 of the staircase: upper block [5,25]×[10,20] (body 1) on
    /// [0,20]×[0,10] (body 0). The top edge of body 0 (edge 2, (20,10)->(0,10)) and the bottom
    /// edge of body 1 (edge 0) overlap on x in [5,20] (length 15). At x = 5 body 1's vertex 0
    /// lies on body 0's edge: A = body 0, n = -y; at x = 20 body 0's vertex 2 lies on body 1's
    /// edge: A = body 1, n = +y. g0 = 0, points on y = 10. Same joint, either argument order.
    #[test]
    fn staircase_partial_overlap() {
        let (lower, upper) = (rect(0.0, 0.0, 20.0, 10.0), rect(5.0, 10.0, 25.0, 20.0));
        for (i, j) in [(0, 1), (1, 0)] {
            let (si, sj) = if i == 0 { (&lower, &upper) } else { (&upper, &lower) };
            let c = contacts(i, j, si, sj, D0);
            assert_eq!(c.len(), 2, "{c:?}");
            check(&c[0], key(0, Edge(2), 1, Vertex(0)), BB, (0.0, -1.0), 0.0, (5.0, 10.0), TOL);
            check(&c[1], key(1, Edge(0), 0, Vertex(2)), BB, (0.0, 1.0), 0.0, (20.0, 10.0), TOL);
            for k in &c {
                assert_eq!(k.joint, jk(0, 2, 1, 0));
                assert!((k.joint_length - 15.0).abs() < TOL);
            }
        }
    }

    /// The same staircase with the upper block as body 0: the joint key lists body 0's bottom
    /// edge (edge 0) first, body 1's top edge (edge 2) second; contacts mirror the above.
    #[test]
    fn staircase_with_swapped_indices() {
        let c = contacts(0, 1, &rect(5.0, 10.0, 25.0, 20.0), &rect(0.0, 0.0, 20.0, 10.0), D0);
        assert_eq!(c.len(), 2, "{c:?}");
        check(&c[0], key(0, Edge(0), 1, Vertex(2)), BB, (0.0, 1.0), 0.0, (20.0, 10.0), TOL);
        check(&c[1], key(1, Edge(2), 0, Vertex(0)), BB, (0.0, -1.0), 0.0, (5.0, 10.0), TOL);
        assert!(c.iter().all(|k| k.joint == jk(0, 0, 1, 2) && (k.joint_length - 15.0).abs() < TOL));
    }

    /// Full overlap with a gap (math note §7.6 geometry): unit block [0,1]×[0.01,1.01] (body 1)
    /// above a long block [-5,5]×[-1,0] (body 0). Both bottom vertices of body 1 lie over body
    /// 0's top edge (edge 2): A = body 0, n = -y, g0 = 0.01, points (0, 0.005) and (1, 0.005),
    /// joint length 1.
    #[test]
    fn full_overlap_same_normal() {
        let c = contacts(0, 1, &rect(-5.0, -1.0, 5.0, 0.0), &rect(0.0, 0.01, 1.0, 1.01), D0);
        assert_eq!(c.len(), 2, "{c:?}");
        check(&c[0], key(0, Edge(2), 1, Vertex(0)), BB, (0.0, -1.0), 0.01, (0.0, 0.005), TOL);
        check(&c[1], key(0, Edge(2), 1, Vertex(1)), BB, (0.0, -1.0), 0.01, (1.0, 0.005), TOL);
        assert!(c.iter().all(|k| k.joint == jk(0, 2, 1, 0) && (k.joint_length - 1.0).abs() < TOL));
    }

    /// Coincident end vertices: equal blocks [0,20]×[0,10] (body 0) and [0,20]×[10,20] (body 1)
    /// have coincident vertices at both ends; exactly one contact per end, body 1's vertex on
    /// body 0's edge (larger index on smaller), so A = body 0 and n = -y at both, length 20.
    /// Shifting body 1 by 1e-9 along x (below the merge distance 1e-3) changes nothing but
    /// the points.
    #[test]
    fn coincident_ends_give_one_contact_each() {
        for dx in [0.0, 1e-9, -1e-9] {
            let c = contacts(0, 1, &rect(0.0, 0.0, 20.0, 10.0), &rect(dx, 10.0, 20.0 + dx, 20.0), D0);
            assert_eq!(c.len(), 2, "{c:?}");
            check(&c[0], key(0, Edge(2), 1, Vertex(0)), BB, (0.0, -1.0), 0.0, (dx, 10.0), TOL);
            check(&c[1], key(0, Edge(2), 1, Vertex(1)), BB, (0.0, -1.0), 0.0, (20.0 + dx, 10.0), TOL);
            assert!(c.iter().all(|k| k.joint == jk(0, 2, 1, 0) && (k.joint_length - 20.0).abs() < 1e-8));
        }
    }

    /// One coincident end: body 1 = [-5,20]×[10,20] on body 0 = [0,20]×[0,10]. At x = 20 the
    /// vertices coincide: body 1's vertex 1 on body 0's edge 2 (A = 0, n = -y). At x = 0 body
    /// 0's vertex 3 lies inside body 1's bottom edge: A = body 1, n = +y. Length 20.
    #[test]
    fn one_coincident_end() {
        let c = contacts(0, 1, &rect(0.0, 0.0, 20.0, 10.0), &rect(-5.0, 10.0, 20.0, 20.0), D0);
        assert_eq!(c.len(), 2, "{c:?}");
        check(&c[0], key(0, Edge(2), 1, Vertex(1)), BB, (0.0, -1.0), 0.0, (20.0, 10.0), TOL);
        check(&c[1], key(1, Edge(0), 0, Vertex(3)), BB, (0.0, 1.0), 0.0, (0.0, 10.0), TOL);
        assert!(c.iter().all(|k| k.joint == jk(0, 2, 1, 0) && (k.joint_length - 20.0).abs() < TOL));
    }

    /// A slightly tilted face: body 1 is [0,1]² rotated by α about its corner (0, 0.01), above
    /// [-5,5]×[-1,0] (body 0, top edge 2). α = 1° (< 2°): a joint; vertex 0 has g0 = 0.01,
    /// vertex 1 at (cos α, 0.01 + sin α) has g0 = 0.01 + sin α (< d0), both A = body 0,
    /// n = -y; overlap along body 0's edge = cos α. α = 3°: the bottom edge dips 3° from
    /// vertex 1 (cone test fails there) and is not anti-parallel: one single contact at
    /// vertex 0, no joint.
    #[test]
    fn tilted_face() {
        let tilted = |deg: f64| {
            let (s, c) = deg.to_radians().sin_cos();
            (polygon(&[(0.0, 0.01), (c, 0.01 + s), (c - s, 0.01 + s + c), (-s, 0.01 + c)]), c, s)
        };
        let floor = rect(-5.0, -1.0, 5.0, 0.0);
        let (b, c, s) = tilted(1.0);
        let got = contacts(0, 1, &floor, &b, D0);
        assert_eq!(got.len(), 2, "{got:?}");
        check(&got[0], key(0, Edge(2), 1, Vertex(0)), BB, (0.0, -1.0), 0.01, (0.0, 0.005), TOL);
        let g1 = 0.01 + s;
        check(&got[1], key(0, Edge(2), 1, Vertex(1)), BB, (0.0, -1.0), g1, (c, 0.5 * g1), TOL);
        assert!(got.iter().all(|k| k.joint == jk(0, 2, 1, 0) && (k.joint_length - c).abs() < TOL));
        let got = contacts(0, 1, &floor, &tilted(3.0).0, D0);
        assert_eq!(got.len(), 1, "{got:?}");
        check(&got[0], key(0, Edge(2), 1, Vertex(0)), BB, (0.0, -1.0), 0.01, (0.0, 0.005), TOL);
        assert!(got[0].joint.is_none() && got[0].joint_length == 0.0);
    }

    /// A small square [1,1.5]² seated in the notch corner of L = [0,2]×[0,1] ∪ [0,1]×[1,2]
    /// (notch corner (1,1) = L's vertex 3, reflex). Two joints of length 0.5: the square's
    /// bottom (edge 0) on the notch floor (L's edge 2) and its left side (edge 3) on the notch
    /// wall (L's edge 3). At the notch corner the vertices coincide; the L's is reflex, so the
    /// square's vertex 0 makes the contact, once on the floor (n = -y) and once on the wall
    /// (n = -x): two contacts at one point, but distinct constraints. g0 = 0 everywhere.
    #[test]
    fn square_seated_in_l_notch() {
        let l = polygon(&[(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)]);
        let c = contacts(0, 1, &l, &rect(1.0, 1.0, 1.5, 1.5), D0);
        assert_eq!(c.len(), 4, "{c:?}");
        check(&c[0], key(0, Edge(2), 1, Vertex(0)), BB, (0.0, -1.0), 0.0, (1.0, 1.0), TOL);
        check(&c[1], key(0, Edge(2), 1, Vertex(1)), BB, (0.0, -1.0), 0.0, (1.5, 1.0), TOL);
        check(&c[2], key(0, Edge(3), 1, Vertex(0)), BB, (-1.0, 0.0), 0.0, (1.0, 1.0), TOL);
        check(&c[3], key(0, Edge(3), 1, Vertex(3)), BB, (-1.0, 0.0), 0.0, (1.0, 1.5), TOL);
        assert!(c[..2].iter().all(|k| k.joint == jk(0, 2, 1, 0) && (k.joint_length - 0.5).abs() < TOL));
        assert!(c[2..].iter().all(|k| k.joint == jk(0, 3, 1, 3) && (k.joint_length - 0.5).abs() < TOL));
    }

    /// A mesh's boundary loop (straight nodes are contact nodes, math note §9.2).
    fn mesh_loop(pts: &[(f64, f64)]) -> crate::contact::BodyShape {
        let v: Vec<crate::geometry::Vec2> =
            pts.iter().map(|&(x, y)| crate::geometry::Vec2::new(x, y)).collect();
        let convex = crate::geometry::loop_contact_flags(&v);
        crate::contact::BodyShape::Polygon { vertices: v, convex, nodes: true, holes: Vec::new() }
    }

    /// The joint contacts of a pair as (x of the point, capacity length), sorted by x, and
    /// whether any keeps a joint partner.
    fn lengths(c: &[crate::contact::ContactGeom]) -> (Vec<(f64, f64)>, bool) {
        let mut l: Vec<(f64, f64)> =
            c.iter().filter(|k| k.joint_length > 0.0).map(|k| (k.point.x, k.joint_length)).collect();
        l.sort_by(|a, b| a.0.total_cmp(&b.0));
        (l, c.iter().any(|k| k.joint.is_some()))
    }

    fn assert_lengths(got: &[(f64, f64)], want: &[(f64, f64)]) {
        assert_eq!(got.len(), want.len(), "{got:?}");
        for (g, w) in got.iter().zip(want) {
            assert!((g.0 - w.0).abs() < TOL && (g.1 - w.1).abs() < TOL, "{got:?} vs {want:?}");
        }
    }

    /// Math note §4.15, meshed on rigid (B-L): a loop [0,1]×[0.01,1.01] with bottom nodes at
    /// x = 0, 0.3, 0.55, 1 over the floor [-5,5]×[-1,0]. Three joints (one per bottom edge,
    /// lengths 0.3, 0.25, 0.45); each node's length is half of each edge beside it: 0.15,
    /// 0.275, 0.35, 0.225, adding up to the face's 1 (the rigid block's joint length), with no
    /// partners. Sums of halves of exact decimals: a few ulp.
    #[test]
    fn mesh_face_on_rigid_floor_carries_tributary_lengths() {
        let block =
            mesh_loop(&[(0.0, 0.01), (0.3, 0.01), (0.55, 0.01), (1.0, 0.01), (1.0, 1.01), (0.0, 1.01)]);
        let (got, partnered) = lengths(&contacts(0, 1, &rect(-5.0, -1.0, 5.0, 0.0), &block, D0));
        assert!(!partnered);
        assert_lengths(&got, &[(0.0, 0.15), (0.3, 0.275), (0.55, 0.35), (1.0, 0.225)]);
        let sum: f64 = got.iter().map(|g| g.1).sum();
        assert!((sum - 1.0).abs() < TOL);
    }

    /// Math note §4.15, rigid on meshed (B-L): the block [0.2,0.9]×[0.01,1] on a meshed base
    /// [0,1]×[-1,0] with top nodes every 0.25. Joints: the block's bottom edge against the
    /// base's top edges, overlaps 0.05 ([0.2,0.25], the block's corner on the base's edge and the
    /// node at 0.25 on the block's edge), 0.25, 0.25 and 0.15 ([0.75,0.9]). Lengths: corner 0.2
    /// 0.025, nodes 0.25, 0.5, 0.75: 0.15, 0.25, 0.2, corner 0.9 0.075; sum 0.7, the block's
    /// width.
    #[test]
    fn rigid_block_on_mesh_face_carries_tributary_lengths() {
        let base = mesh_loop(&[
            (0.0, -1.0),
            (1.0, -1.0),
            (1.0, 0.0),
            (0.75, 0.0),
            (0.5, 0.0),
            (0.25, 0.0),
            (0.0, 0.0),
        ]);
        let (got, partnered) = lengths(&contacts(0, 1, &base, &rect(0.2, 0.01, 0.9, 1.0), D0));
        assert!(!partnered);
        assert_lengths(&got, &[(0.2, 0.025), (0.25, 0.15), (0.5, 0.25), (0.75, 0.2), (0.9, 0.075)]);
    }

    /// Math note §4.15 with §9.2's one-pass L-L: a fine loop [0.5,1.5]×[0.01,1.01] (bottom nodes
    /// every 0.25) on a coarse base [0,2]×[-1,0] whose top has a straight node at x = 1 (masked:
    /// the coarse loop keeps its corners only). The fine nodes carry the face; the node at
    /// x = 1 ends a joint on each of the coarse top edges (two keys, one point): merged, it
    /// carries 0.125 + 0.125. Lengths 0.125, 0.25, 0.25, 0.25, 0.125: sum 1, the fine face.
    #[test]
    fn mesh_face_on_mesh_face_carries_tributary_lengths() {
        let base = mesh_loop(&[(0.0, -1.0), (2.0, -1.0), (2.0, 0.0), (1.0, 0.0), (0.0, 0.0)]);
        let mut pts: Vec<(f64, f64)> = (0..5).map(|k| (0.5 + 0.25 * k as f64, 0.01)).collect();
        pts.extend([(1.5, 1.01), (0.5, 1.01)]);
        let (got, partnered) = lengths(&contacts(0, 1, &base, &mesh_loop(&pts), D0));
        assert!(!partnered);
        assert_lengths(&got, &[(0.5, 0.125), (0.75, 0.25), (1.0, 0.25), (1.25, 0.25), (1.5, 0.125)]);
    }
}
