//! Block-block contacts (math note §5; paper Section 3, Figures 4-5): edge-edge joints first
//! ([`super::joint`]), then single vertex-edge contacts, then vertex-vertex contacts, then a
//! dedupe that keeps one contact where candidates coincide.
//!
//! Only convex vertices make contacts: a reflex (or straight, 180°) vertex is never the point
//! of its body nearest to another body. A convex vertex in a notch of a concave body touches
//! the notch's edges, because an edge's projection range is closed at a non-convex end. The one
//! exception is a straight vertex where the edge's interface changes (a seam, math note §5.1):
//! it is flagged as a contact vertex, so each edge piece has contacts at both of its ends.

use super::narrow::{Polygon, Tolerances, vertex_edge_geom};
use super::{ContactGeom, Feature};
use crate::geometry::{STRAIGHT_SINE, Vec2};

/// All contacts between polygons `p` and `q` (either order). The polygon with the smaller
/// body index is handled first, so the result does not depend on the argument order.
pub fn block_block(p: &Polygon, q: &Polygon, tol: &Tolerances, out: &mut Vec<ContactGeom>) {
    let (x, y) = if p.body < q.body { (p, q) } else { (q, p) };
    if x.nodes && y.nodes {
        return loop_loop(x, y, tol, out);
    }
    pairs(x, y, tol, out);
}

/// L-L (math note §9.2): one pass on flat stretches. Two meshes meeting along a face would
/// otherwise press every node of each on the other's edges (two-pass node-on-segment): the rows
/// over-constrain the face, the forces alternate from node to node, and without a large mass
/// term W is near-singular. The coarser loop (longer mean edge; the smaller body index on a
/// tie) keeps only its corners — nodes where it turns by more than the straight band — so its
/// straight nodes make no contact of their own; the finer loop's nodes carry the face.
fn loop_loop(x: &Polygon, y: &Polygon, tol: &Tolerances, out: &mut Vec<ContactGeom>) {
    let mean =
        |p: &Polygon| (0..p.vertex_count()).map(|k| p.edge(k).len).sum::<f64>() / p.vertex_count() as f64;
    let x_coarser = mean(x) >= mean(y);
    let master = if x_coarser { x } else { y };
    let corners: Vec<bool> =
        (0..master.vertex_count()).map(|k| master.convex[k] && master.turn(k) > STRAIGHT_SINE).collect();
    let masked = master.with_convex(&corners);
    if x_coarser { pairs(&masked, y, tol, out) } else { pairs(x, &masked, tol, out) }
}

/// Joints, vertex-edge and vertex-vertex contacts of `x` (the smaller body index) and `y`.
fn pairs(x: &Polygon, y: &Polygon, tol: &Tolerances, out: &mut Vec<ContactGeom>) {
    let mut found = Vec::new();
    super::joint::edge_edge(x, y, tol, &mut found);
    // vertices of the larger index first: where the two bodies' candidates coincide, the one
    // kept is then a vertex of the larger index on an edge of the smaller, as at joint ends
    vertex_edges(y, x, tol, &mut found);
    vertex_edges(x, y, tol, &mut found);
    let mut corners = Vec::new();
    vertex_vertex(x, y, tol, &mut corners);
    let seam = |c: &ContactGeom| seam_end(c, x, y, tol);
    dedupe(found, corners, tol, seam, out);
}

/// Whether `c` is a contact at a seam (math note §5.1): its vertex is a straight contact vertex
/// of a rigid polygon (flagged by [`crate::geometry::polygon_contact_flags`] where the edge's
/// interface changes) and one end of its edge is such a vertex of the other polygon at the same
/// point. Two joints end there, one per edge piece, and each keeps its own end contact.
pub(super) fn seam_end(c: &ContactGeom, x: &Polygon, y: &Polygon, tol: &Tolerances) -> bool {
    let (Feature::Vertex(kv), Feature::Edge(f)) = (c.key.fb, c.key.fa) else { return false };
    let (p, q) = if c.key.b as usize == x.body { (x, y) } else { (y, x) };
    let straight = |poly: &Polygon, k: usize| {
        !poly.nodes && k < poly.vertex_count() && poly.convex[k] && poly.turn(k).abs() <= STRAIGHT_SINE
    };
    let (kv, f) = (kv as usize, f as usize);
    if !straight(p, kv) || f >= q.vertex_count() {
        return false;
    }
    let v = p.vertices[kv];
    [f, q.next(f)].into_iter().any(|m| (q.vertices[m] - v).norm() <= tol.merge && straight(q, m))
}

/// Whether vertex k of `x` against edge f of `y` is a vertex-edge contact, apart from where
/// its projection falls (math note §5, B-B vertex-edge): vertex k convex, g0 within
/// (-d0, threshold) (d0 the penetration allowance, the threshold d0 or its enlargement), and the
/// cone test (the edges at vertex k do not dip through the edge line). A penetrating vertex
/// (g0 < 0) must also be inside `y` near the edge, with this edge its shortest way out
/// ([`Polygon::behind_end_edges`]): below the edge line but beyond a convex corner's other edge
/// is outside `y`, not a penetration; a corner sliding along the other edge's line (a joint
/// crossing) is pushed back onto that line, not through this edge.
pub fn vertex_edge_admissible(x: &Polygon, k: usize, y: &Polygon, f: usize, tol: &Tolerances) -> bool {
    let e = y.edge(f);
    let v = x.vertices[k];
    let g0 = e.height(v);
    x.convex[k]
        && g0 > -tol.depth
        && g0 < tol.threshold
        && x.cone_clear(k, e.n_out, tol)
        && (g0 >= 0.0 || y.behind_end_edges(f, x, k, g0, tol))
}

/// Single vertex-edge contacts of the convex vertices of `x` against the edges of `y`
/// (math note §5, paper Figure 4): the vertex must project inside the edge
/// ([`Polygon::projects_inside`]) and not lie at a convex end vertex of the edge (within the merge
/// distance): two corners there are a vertex-vertex pair, whichever way rounding puts the
/// projection (math note §5.2). A = `y`, the edge owner.
fn vertex_edges(x: &Polygon, y: &Polygon, tol: &Tolerances, out: &mut Vec<ContactGeom>) {
    for k in 0..x.vertex_count() {
        for f in 0..y.vertex_count() {
            let v = x.vertices[k];
            let at_corner = [f, y.next(f)].into_iter().any(|m| coincident(y, m, v, tol));
            if vertex_edge_admissible(x, k, y, f, tol) && y.projects_inside(f, v) && !at_corner {
                out.push(vertex_edge_geom(x, k, y, f));
            }
        }
    }
}

/// Whether `p` lies within the merge distance of the convex vertex m of `poly`.
fn coincident(poly: &Polygon, m: usize, p: Vec2, tol: &Tolerances) -> bool {
    poly.convex[m] && (poly.vertices[m] - p).norm() <= tol.merge
}

/// Vertex-vertex contacts (math note §5; the paper defers to Shi's DDA): convex vertex V of
/// `x` and convex vertex W of `y` closer than d0, either coincident (within the merge distance,
/// math note §5.2) or neither projecting inside an edge incident to the other. Exactly one
/// contact per such pair ([`separating_line`]), or none at a joint crossing.
fn vertex_vertex(x: &Polygon, y: &Polygon, tol: &Tolerances, out: &mut Vec<ContactGeom>) {
    for k in (0..x.vertex_count()).filter(|&k| x.convex[k]) {
        for m in (0..y.vertex_count()).filter(|&m| y.convex[m]) {
            let (v, w) = (x.vertices[k], y.vertices[m]);
            let close = (v - w).norm() < tol.threshold;
            let apart = !inside_incident(y, m, v) && !inside_incident(x, k, w);
            if close && (apart || coincident(y, m, v, tol)) {
                out.extend(separating_line(x, k, y, m, tol));
            }
        }
    }
}

/// The one contact of corners V (vertex k of `x`) and W (vertex m of `y`), from four candidates: V
/// against the two edge lines at W, and W against the two edge lines at V. Admissible: on the outer
/// side of the line (g0 >= -merge distance) and passing the cone test, i.e. the line separates the
/// two corners. Chosen: the largest g0 (the separating line with the widest gap). Tie-break (the
/// note's approach-direction rule needs velocities, which detection does not have), among
/// candidates within the tie width of the largest g0: a line that carries an edge of each body (the
/// corners meet end to end along it, [`on_common_line`]) before one that does not; if such lines
/// run in two directions, the corners meet at a crossing of two joint lines and there is no contact
/// (math note §5.2); then the smallest contact key, i.e. the edge of the smaller body index, then
/// the smaller edge index.
fn separating_line(x: &Polygon, k: usize, y: &Polygon, m: usize, tol: &Tolerances) -> Option<ContactGeom> {
    let candidates = [(x, k, y, m), (x, k, y, y.prev(m)), (y, m, x, k), (y, m, x, x.prev(k))];
    let admissible: Vec<(ContactGeom, bool)> = candidates
        .iter()
        .filter(|(a, ka, b, fb)| a.cone_clear(*ka, b.edge(*fb).n_out, tol))
        .map(|(a, ka, b, fb)| (vertex_edge_geom(a, *ka, b, *fb), on_common_line(a, *ka, b, *fb, tol)))
        .filter(|(c, _)| c.g0 >= -tol.merge)
        .collect();
    let best = admissible.iter().map(|(c, _)| c.g0).fold(f64::NEG_INFINITY, f64::max);
    let tied: Vec<(ContactGeom, bool)> =
        admissible.into_iter().filter(|(c, _)| c.g0 >= best - tol.tie).collect();
    let common: Vec<&ContactGeom> = tied.iter().filter(|(_, on)| *on).map(|(c, _)| c).collect();
    let crossing =
        common.iter().any(|c| common.iter().any(|d| c.normal.dot(&d.normal).abs() < tol.cos_angle));
    if crossing {
        return None;
    }
    let preferred = !common.is_empty();
    tied.into_iter().filter(|(_, on)| *on || !preferred).map(|(c, _)| c).min_by_key(|c| c.key)
}

/// Whether the line of edge `fb` of `b` (incident to b's corner) also carries an edge of `a`
/// at its vertex `ka`: the vertex lies on the line (to the merge distance) and one of its two
/// edges runs opposite to edge `fb` (to the angle tolerance), so the two bodies meet end to
/// end along the line, as the blocks on either side of a persistent joint do at a crossing.
fn on_common_line(a: &Polygon, ka: usize, b: &Polygon, fb: usize, tol: &Tolerances) -> bool {
    let e = b.edge(fb);
    let opposite = |f: usize| a.edge(f).t.dot(&e.t) <= -tol.cos_angle;
    e.height(a.vertices[ka]).abs() <= tol.merge && (opposite(ka) || opposite(a.prev(ka)))
}

/// Whether `p` projects inside one of the two edges of `poly` incident to vertex m.
fn inside_incident(poly: &Polygon, m: usize, p: Vec2) -> bool {
    poly.projects_inside(m, p) || poly.projects_inside(poly.prev(m), p)
}

/// Keeps one contact where candidates coincide. `found` (joint contacts first, then
/// vertex-edge) in order: a candidate is dropped when a kept contact has the same key, or lies
/// within the merge distance with a parallel or anti-parallel normal (the same constraint seen
/// from the other body). Contacts at one point with clearly different normals (a vertex in a
/// notch corner) are distinct constraints and are both kept. A vertex-vertex contact
/// (`corners`) is dropped if any kept contact lies within the merge distance: the corner is
/// already held there (e.g. at the coincident end of a joint). The exception: at a seam
/// (`seam`, [`seam_end`]) the end contacts of two different joints are both kept, one per edge
/// piece with its own law (math note §5.1).
fn dedupe(
    found: Vec<ContactGeom>,
    corners: Vec<ContactGeom>,
    tol: &Tolerances,
    seam: impl Fn(&ContactGeom) -> bool,
    out: &mut Vec<ContactGeom>,
) {
    let near = |a: &ContactGeom, b: &ContactGeom| (a.point - b.point).norm() <= tol.merge;
    let mut kept: Vec<ContactGeom> = Vec::with_capacity(found.len() + corners.len());
    for c in found {
        let parallel = |k: &ContactGeom| k.normal.dot(&c.normal).abs() >= tol.cos_angle;
        let other_joint = |k: &ContactGeom| k.joint.is_some() && c.joint.is_some() && k.joint != c.joint;
        let same = |k: &ContactGeom| near(k, &c) && parallel(k) && !(other_joint(k) && seam(k) && seam(&c));
        if !kept.iter().any(|k| k.key == c.key || same(k)) {
            kept.push(c);
        }
    }
    for c in corners {
        if !kept.iter().any(|k| k.key == c.key || near(k, &c)) {
            kept.push(c);
        }
    }
    out.extend(kept);
}

#[cfg(test)]
mod tests {
    use super::super::testkit::*;
    use super::super::{ContactKind, Feature::*};

    const D0: f64 = 0.1;
    /// Closed forms evaluated in f64 from coordinates of order 1: a few ulp.
    const TOL: f64 = 1e-12;
    const BB: ContactKind = ContactKind::BB;

    /// Math note §5 B-B vertex-edge: a tilted square (10° about its lowest corner) whose lowest
    /// vertex (0.5, 1.03) sits above the top edge of [0,1]² (edge 2, from (1,1) to (0,1)):
    /// A = lower square (edge owner), n = n_in = -y, g0 = 0.03, point (0.5, 1.015).
    /// The other vertices of the tilted square are at least sin(10°) higher.
    /// L-L on a flat face (math note §9.2, one pass): a fine loop, [0,2]×[-1,0] with top nodes
    /// every 0.25 m (mean edge 0.55 m), under a coarse one, [0.5,1.5]×[0.01,1.01] with bottom
    /// nodes at x = 0.5, 0.9, 1.5 (mean edge 0.8 m), 0.01 apart. The coarse loop keeps only its
    /// corners: its bottom corners (vertices 0, 2) bear on the fine face (A = fine loop, n = -y
    /// into it); its straight node at x = 0.9 makes no contact (two passes would add it, on the
    /// fine edge from x = 1 to 0.75). The fine face's nodes at x = 0.75, 1, 1.25 (vertices 7, 6,
    /// 5) bear on the coarse bottom edges (A = coarse loop, n = +y). g0 = 0.01 everywhere.
    #[test]
    fn loop_loop_face_is_one_pass() {
        let as_loop = |pts: &[(f64, f64)]| {
            let v: Vec<crate::geometry::Vec2> =
                pts.iter().map(|&(x, y)| crate::geometry::Vec2::new(x, y)).collect();
            let convex = crate::geometry::loop_contact_flags(&v);
            super::super::BodyShape::Polygon { vertices: v, convex, nodes: true, holes: Vec::new() }
        };
        let mut fine = vec![(0.0, -1.0), (2.0, -1.0), (2.0, 0.0)];
        fine.extend((0..8).map(|k| (1.75 - 0.25 * k as f64, 0.0)));
        let coarse = [(0.5, 0.01), (0.9, 0.01), (1.5, 0.01), (1.5, 1.01), (0.5, 1.01)];
        let c = contacts(0, 1, &as_loop(&fine), &as_loop(&coarse), D0);
        assert_eq!(c.len(), 5, "{c:?}");
        check(&c[0], key(0, Edge(4), 1, Vertex(2)), BB, (0.0, -1.0), 0.01, (1.5, 0.005), TOL);
        check(&c[1], key(0, Edge(7), 1, Vertex(0)), BB, (0.0, -1.0), 0.01, (0.5, 0.005), TOL);
        check(&c[2], key(1, Edge(0), 0, Vertex(7)), BB, (0.0, 1.0), 0.01, (0.75, 0.005), TOL);
        check(&c[3], key(1, Edge(1), 0, Vertex(5)), BB, (0.0, 1.0), 0.01, (1.25, 0.005), TOL);
        check(&c[4], key(1, Edge(1), 0, Vertex(6)), BB, (0.0, 1.0), 0.01, (1.0, 0.005), TOL);
    }

    #[test]
    fn vertex_above_edge() {
        let a = 10f64.to_radians();
        let (c, s) = (a.cos(), a.sin());
        let v0 = (0.5, 1.03);
        let tilted = polygon(&[v0, (v0.0 + c, v0.1 + s), (v0.0 + c - s, v0.1 + s + c), (v0.0 - s, v0.1 + c)]);
        let got = contacts(0, 1, &rect(0.0, 0.0, 1.0, 1.0), &tilted, D0);
        assert_eq!(got.len(), 1, "{got:?}");
        check(&got[0], key(0, Edge(2), 1, Vertex(0)), BB, (0.0, -1.0), 0.03, (0.5, 1.015), TOL);
        assert!(got[0].joint.is_none() && got[0].joint_length == 0.0);
    }

    /// Math note §5 vertex-vertex, clear winner. A = [0,1]² (vertex V = (1,1) is vertex 2);
    /// B is a unit square rotated by α = 10° with its corner W = V + (a, b), a = 0.03,
    /// b = 0.01, edges from W along u1 = (cos α, sin α) and u2 = (-sin α, cos α); tan α < b/a
    /// keeps V out of B's edges and W is in V's corner region. Candidates:
    /// W vs A's top line g0 = b (admissible); W vs A's right line: B's edge u2 dips by α > 2°
    /// (rejected); V vs B's edge 0 line: A's top edge dips (rejected); V vs B's edge 3 line
    /// (from W + u2 to W, n_out = -u1): g0 = a cos α + b sin α = 0.0313 (admissible, largest).
    /// So A = B, n = u1, point = V + (g0/2) u1.
    #[test]
    fn vertex_vertex_largest_gap() {
        let (al, a, b) = (10f64.to_radians(), 0.03, 0.01);
        let (c, s) = (al.cos(), al.sin());
        let w = (1.0 + a, 1.0 + b);
        let sq_b = polygon(&[w, (w.0 + c, w.1 + s), (w.0 + c - s, w.1 + s + c), (w.0 - s, w.1 + c)]);
        let got = contacts(0, 1, &rect(0.0, 0.0, 1.0, 1.0), &sq_b, D0);
        assert_eq!(got.len(), 1, "{got:?}");
        let g0 = a * c + b * s;
        let p = (1.0 + 0.5 * g0 * c, 1.0 + 0.5 * g0 * s);
        check(&got[0], key(1, Edge(3), 0, Vertex(2)), BB, (c, s), g0, p, TOL);
    }

    /// Math note §5 vertex-vertex tie: A = [0,1]², B = [1.03,2.03]×[1.01,2.01] (corner to
    /// corner, W = (1.03,1.01) is B's vertex 0). Admissible candidates: W vs A's right line
    /// and V vs B's left line, both g0 = 0.03 (the lines x = 1 and x = 1.03); the y-lines give
    /// only 0.01. Tie-break: the edge of the smaller body index, so W on A's edge 1:
    /// A = body 0, n = -x, point (1.015, 1.01). Exactly one contact.
    #[test]
    fn vertex_vertex_tie_takes_smaller_body_edge() {
        let got = contacts(1, 0, &rect(1.03, 1.01, 2.03, 2.01), &rect(0.0, 0.0, 1.0, 1.0), D0);
        assert_eq!(got.len(), 1, "{got:?}");
        check(&got[0], key(0, Edge(1), 1, Vertex(0)), BB, (-1.0, 0.0), 0.03, (1.015, 1.01), TOL);
    }

    /// Four blocks at a crossing of two persistent joints (math note §5.2): the bedding line
    /// through the origin at 30° (unit direction u) and the cross line at 120° (direction v =
    /// perp(u)). In the (u, v) frame: slab A = [-1,0]×[0,1] (body 0), B = [-1,0]×[-1,0] below it
    /// (1), C = [0,1]×[0,1] beside it (2), D = [0,1]×[-1,0] across the crossing (3). Every line
    /// through the crossing carries an edge of each diagonal pair, so A-D and B-C make no contact;
    /// A's corner is held by the joints A-B (normal ±v, the bedding's) and A-C (±u, the cross
    /// joint's). Expected contacts at the crossing: one per side pair, each on the line between
    /// them, g0 = 0. Tolerance: closed-form values rotated in f64, a few ulp.
    #[test]
    fn crossing_diagonal_blocks_make_no_corner_contact() {
        let a = 30f64.to_radians();
        let (u, v) = ((a.cos(), a.sin()), (-a.sin(), a.cos()));
        let at = |p: (f64, f64)| (p.0 * u.0 + p.1 * v.0, p.0 * u.1 + p.1 * v.1);
        let sq = |x0: f64, y0: f64| {
            polygon(&[(x0, y0), (x0 + 1.0, y0), (x0 + 1.0, y0 + 1.0), (x0, y0 + 1.0)].map(at))
        };
        let shapes = [sq(-1.0, 0.0), sq(-1.0, -1.0), sq(0.0, 0.0), sq(0.0, -1.0)];
        let near = |i: usize, j: usize| {
            let c = contacts(i, j, &shapes[i], &shapes[j], D0);
            c.into_iter().filter(|c| c.point.norm() < 1e-9).collect::<Vec<_>>()
        };
        assert!(near(0, 3).is_empty() && near(1, 2).is_empty());
        for (i, j, n) in [(0, 1, v), (0, 2, u), (1, 3, u), (2, 3, v)] {
            let c = near(i, j);
            assert_eq!(c.len(), 1, "{i}-{j}: {c:?}");
            assert!(
                c[0].g0.abs() < TOL
                    && c[0].normal.dot(&crate::geometry::Vec2::new(n.0, n.1)).abs() > 1.0 - TOL
            );
        }
    }

    /// The crossing of `crossing_diagonal_blocks_make_no_corner_contact` as a cutter leaves it,
    /// with rounding: D = [0,1]×[-1+ε, ε], ε = 1e-12, so A's corner (0, 0) lies on D's cross
    /// line and projects ε inside D's cross edge. Corners within the merge distance (1e-3 here)
    /// are a vertex-vertex pair whatever rounding says about projections (math note §5.2), so the
    /// diagonal pair still makes no contact; a contact on D's cross edge would prop A's slide
    /// down the bedding.
    #[test]
    fn crossing_within_rounding_makes_no_corner_contact() {
        let a = 30f64.to_radians();
        let (u, v) = ((a.cos(), a.sin()), (-a.sin(), a.cos()));
        let at = |p: (f64, f64)| (p.0 * u.0 + p.1 * v.0, p.0 * u.1 + p.1 * v.1);
        let sq = |x0: f64, y0: f64| {
            polygon(&[(x0, y0), (x0 + 1.0, y0), (x0 + 1.0, y0 + 1.0), (x0, y0 + 1.0)].map(at))
        };
        let c = contacts(0, 3, &sq(-1.0, 0.0), &sq(0.0, -1.0 + 1e-12), D0);
        assert!(c.iter().all(|c| c.point.norm() > 1e-9), "{c:?}");
    }

    /// The same crossing after the slab A has slid s = 0.02 down the bedding (along +u): its
    /// bottom edge overlaps D's top edge from (0, 0) to (0.02, 0) in the (u, v) frame, so the
    /// pair's contacts are the two ends of that overlap, both on the bedding line: n = ±v,
    /// g0 = 0, at the crossing and at A's corner. Tolerance: a few ulp of the rotated
    /// coordinates.
    #[test]
    fn slab_past_crossing_rests_on_bedding() {
        let a = 30f64.to_radians();
        let (u, v) = ((a.cos(), a.sin()), (-a.sin(), a.cos()));
        let at = |p: (f64, f64)| (p.0 * u.0 + p.1 * v.0, p.0 * u.1 + p.1 * v.1);
        let sq = |x0: f64, y0: f64| {
            polygon(&[(x0, y0), (x0 + 1.0, y0), (x0 + 1.0, y0 + 1.0), (x0, y0 + 1.0)].map(at))
        };
        let got = contacts(0, 3, &sq(-0.98, 0.0), &sq(0.0, -1.0), D0);
        assert_eq!(got.len(), 2, "{got:?}");
        let v = crate::geometry::Vec2::new(v.0, v.1);
        let corner = at((0.02, 0.0));
        let corner = crate::geometry::Vec2::new(corner.0, corner.1);
        assert!(got.iter().all(|c| c.normal.dot(&v).abs() > 1.0 - TOL && c.g0.abs() < TOL), "{got:?}");
        assert!(
            got.iter().any(|c| c.point.norm() < TOL) && got.iter().any(|c| (c.point - corner).norm() < TOL)
        );
    }

    /// The shortest way out (math note §5.2): the
    /// slab of `slab_past_crossing_rests_on_bedding`, s = 0.02 down the bedding, also sunk
    /// δ = 0.005 into it (A = [-0.98,0.02]×[-0.005,0.995] in the (u, v) frame). Its corner
    /// (0.02, -0.005) lies 0.005 behind D's top edge and 0.02 behind D's cross edge, and D's
    /// corner (0, 0) 0.005 behind A's bottom edge and 0.02 behind A's cross edge: each corner's
    /// shortest way out is the bedding, so the pair's only contacts are the joint's two ends on
    /// it, n = ±v, g0 = -δ. Contacts on the cross edges (g0 = -0.02) would push the slab back
    /// up the bedding. Tolerance: a few ulp of the rotated coordinates.
    #[test]
    fn penetrating_corner_leaves_by_the_shortest_way() {
        let a = 30f64.to_radians();
        let (u, v) = ((a.cos(), a.sin()), (-a.sin(), a.cos()));
        let at = |p: (f64, f64)| (p.0 * u.0 + p.1 * v.0, p.0 * u.1 + p.1 * v.1);
        let sq = |x0: f64, y0: f64| {
            polygon(&[(x0, y0), (x0 + 1.0, y0), (x0 + 1.0, y0 + 1.0), (x0, y0 + 1.0)].map(at))
        };
        let got = contacts(0, 3, &sq(-0.98, -0.005), &sq(0.0, -1.0), D0);
        assert_eq!(got.len(), 2, "{got:?}");
        let v = crate::geometry::Vec2::new(v.0, v.1);
        let ok = |c: &crate::contact::ContactGeom| {
            c.normal.dot(&v).abs() > 1.0 - TOL && (c.g0 + 0.005).abs() < TOL && c.joint.is_some()
        };
        assert!(got.iter().all(ok), "{got:?}");
    }

    /// Flush sides (math note §5.2): B =
    /// [0,1]×[0.999,1.999] (body 1) sunk δ = 0.001 into A = [0,1]² (body 0), side by side flush.
    /// B's bottom corners lie δ behind A's top edge and on A's side lines, but B's bottom edge
    /// runs inside across each side line, so a side is no way out for them: the joint keeps both
    /// ends, B's vertices 0 and 1 on A's top edge (edge 2), n = -y, g0 = -δ, points at
    /// y = 1 - δ/2. (A heavy block pressed into a light one sinks so, tests/paper/mass_ratio.rs.)
    /// Tolerance: a few ulp of coordinates of order 1.
    #[test]
    fn flush_sides_are_no_way_out() {
        let got = contacts(0, 1, &rect(0.0, 0.0, 1.0, 1.0), &rect(0.0, 0.999, 1.0, 1.999), D0);
        assert_eq!(got.len(), 2, "{got:?}");
        let y = 1.0 - 0.0005;
        check(&got[0], key(0, Edge(2), 1, Vertex(0)), BB, (0.0, -1.0), -0.001, (0.0, y), TOL);
        check(&got[1], key(0, Edge(2), 1, Vertex(1)), BB, (0.0, -1.0), -0.001, (1.0, y), TOL);
    }

    /// Coincident corners with one common line: A = [-1,0]×[0,1] listed from (0,0), so its
    /// right edge is edge 0 and its bottom edge edge 3 (body 0), and the triangle D = (0,0),
    /// (cos 60°, -sin 60°), (1, 0) (body 1), whose top edge lies on A's bottom line. The
    /// admissible lines all give g0 = 0 (a tie): A's right line x = 0 (the smallest key, A's
    /// edge 0) carries no edge of D; the bedding line y = 0 carries an edge of each, so it is
    /// chosen, with its smallest key: D's vertex 0 on A's edge 3, A = body 0, n = +y, point (0, 0).
    #[test]
    fn coincident_corners_prefer_the_common_line() {
        let (c, s) = (60f64.to_radians().cos(), 60f64.to_radians().sin());
        let tri = polygon(&[(0.0, 0.0), (c, -s), (1.0, 0.0)]);
        let a = polygon(&[(0.0, 0.0), (0.0, 1.0), (-1.0, 1.0), (-1.0, 0.0)]);
        let got = contacts(0, 1, &a, &tri, D0);
        assert_eq!(got.len(), 1, "{got:?}");
        check(&got[0], key(0, Edge(3), 1, Vertex(0)), BB, (0.0, 1.0), 0.0, (0.0, 0.0), TOL);
    }

    /// Corners further apart than d0 (gap (0.08, 0.08), |V - W| = 0.113): nothing.
    #[test]
    fn corners_beyond_threshold() {
        assert!(contacts(0, 1, &rect(0.0, 0.0, 1.0, 1.0), &rect(1.08, 1.08, 2.0, 2.0), D0).is_empty());
    }

    /// Two vertex-edge contacts at one point with the same constraint: corners crossing by
    /// 1e-5 in x (below the merge distance 0.01 d0 = 1e-3) with parallel edges 0.004 apart.
    /// A's vertex (1,1) projects inside B's bottom edge and B's vertex (0.99999, 1.004) inside
    /// A's top edge; the overlap (1e-5) is too short for a joint, the two candidates coincide
    /// to 1e-5 with opposite normals, so one is kept: B's vertex 0 on A's edge 2 (found first,
    /// A = body 0), n = -y, g0 = 0.004, point (0.99999, 1.002).
    #[test]
    fn coincident_vertex_edge_pair_is_one_contact() {
        let got = contacts(0, 1, &rect(0.0, 0.0, 1.0, 1.0), &rect(0.99999, 1.004, 2.0, 2.0), D0);
        assert_eq!(got.len(), 1, "{got:?}");
        check(&got[0], key(0, Edge(2), 1, Vertex(0)), BB, (0.0, -1.0), 0.004, (0.99999, 1.002), TOL);
    }

    /// Concave body: L = [0,2]×[0,1] ∪ [0,1]×[1,2], notch corner (1,1) = vertex 3 (reflex).
    /// A triangle (1.08,1.03), (1.5,1.5), (1.03,1.08) sits in the notch; its edge 2 (line
    /// x + y = 2.11) passes 0.11/√2 = 0.078 < d0 from the reflex corner, which projects inside
    /// it, yet the reflex vertex makes no contact. The triangle's vertex 0 touches the floor
    /// (L's edge 2, projection closed at the reflex end): A = L, n = -y, g0 = 0.03, point
    /// (1.08, 1.015); its vertex 2 touches the wall (edge 3): n = -x, g0 = 0.03, point
    /// (1.015, 1.08). Vertex 0 vs the wall (g0 = 0.08) fails the cone test: the triangle's
    /// edge 2 dips 45° through the wall line; likewise vertex 2 vs the floor.
    #[test]
    fn convex_vertices_touch_notch_edges_reflex_vertex_does_not() {
        let l = polygon(&[(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)]);
        let tri = polygon(&[(1.08, 1.03), (1.5, 1.5), (1.03, 1.08)]);
        let got = contacts(0, 1, &l, &tri, D0);
        assert_eq!(got.len(), 2, "{got:?}");
        check(&got[0], key(0, Edge(2), 1, Vertex(0)), BB, (0.0, -1.0), 0.03, (1.08, 1.015), TOL);
        check(&got[1], key(0, Edge(3), 1, Vertex(2)), BB, (-1.0, 0.0), 0.03, (1.015, 1.08), TOL);
    }

    mod random_convex_pairs {
        //! Properties of random separated convex polygons at a known distance d (found by
        //! bisection along a random direction). Edges are at least 0.2 long (> 10 d0, the
        //! resolution assumed by math note §5 "Choosing d0").
        use super::super::super::narrow::Tolerances;
        use super::super::super::{BodyShape, ContactGeom};
        use super::*;
        use crate::geometry::Vec2;
        use proptest::prelude::*;

        const D0: f64 = 0.02;

        /// The second polygon moved along `u` until its distance to the first is `d`.
        fn place(p: &[Vec2], q: &[Vec2], u: Vec2, d: f64) -> Vec<Vec2> {
            let moved = |t: f64| -> Vec<Vec2> { q.iter().map(|v| v + t * u).collect() };
            moved(bisect(|t| polygon_distance(p, &moved(t)), d))
        }

        fn shape(v: Vec<Vec2>) -> BodyShape {
            polygon_of(v)
        }

        fn concave_pair() -> impl Strategy<Value = (Vec<Vec2>, Vec<Vec2>, Vec2)> {
            let gaps = prop::collection::vec(1.0..1.9f64, 3..6);
            let l = (1.0..2.0f64, 1.0..2.0f64, 0.3..0.8f64, 0.0..6.3f64);
            (l, gaps, 0.4..0.8f64, 0.0..6.3f64, 0.0..6.3f64).prop_map(|((a, b, t, lt), gb, rb, tb, dir)| {
                let q = convex(Vec2::zeros(), rb, tb, &gb);
                (l_shape(a, b, t, lt), q, Vec2::new(dir.cos(), dir.sin()))
            })
        }

        fn pair() -> impl Strategy<Value = (Vec<Vec2>, Vec<Vec2>, Vec2)> {
            let gaps = prop::collection::vec(1.0..1.9f64, 3..7);
            (gaps.clone(), gaps, 1.0..2.0f64, 1.0..2.0f64, 0.0..6.3f64, 0.0..6.3f64, 0.0..6.3f64).prop_map(
                |(ga, gb, ra, rb, ta, tb, dir)| {
                    let a = convex(Vec2::zeros(), ra, ta, &ga);
                    let b = convex(Vec2::zeros(), rb, tb, &gb);
                    (a, b, Vec2::new(dir.cos(), dir.sin()))
                },
            )
        }

        fn check_invariants(c: &[ContactGeom]) {
            let tol = Tolerances::new(D0);
            for (i, x) in c.iter().enumerate() {
                assert!((x.normal.norm() - 1.0).abs() < 1e-12 && x.g0 < D0 && x.g0 > -D0);
                assert!(matches!((x.key.fa, x.key.fb), (Edge(_), Vertex(_))));
                for y in &c[i + 1..] {
                    let same_point = (x.point - y.point).norm() <= tol.merge;
                    let parallel = x.normal.dot(&y.normal).abs() >= tol.cos_angle;
                    assert!(!(same_point && parallel), "duplicate {x:?} {y:?}");
                }
                let in_joint = c.iter().filter(|y| x.joint.is_some() && y.joint == x.joint).count();
                assert!(in_joint <= 2);
            }
        }

        proptest! {
            /// Closer than d0: at least one contact, none claiming penetration (g0 >= -merge
            /// distance), no duplicates, and the same result in either argument order.
            #[test]
            fn close_pairs_are_detected((a, b, u) in pair(), d in 1e-4..0.9 * D0) {
                let b = place(&a, &b, u, d);
                let c = contacts(0, 1, &shape(a.clone()), &shape(b.clone()), D0);
                prop_assert!(!c.is_empty(), "distance {d}: no contact");
                prop_assert!(c.iter().all(|x| x.g0 >= -0.01 * D0), "{c:?}");
                check_invariants(&c);
                prop_assert_eq!(c, contacts(1, 0, &shape(b), &shape(a), D0));
            }

            /// The same with a concave L-shape (a convex polygon may sit in its notch).
            #[test]
            fn close_concave_pairs_are_detected((a, b, u) in concave_pair(), d in 1e-4..0.9 * D0) {
                let b = place(&a, &b, u, d);
                let c = contacts(0, 1, &shape(a.clone()), &shape(b.clone()), D0);
                prop_assert!(!c.is_empty(), "distance {d}: no contact");
                prop_assert!(c.iter().all(|x| x.g0 >= -0.01 * D0), "{c:?}");
                check_invariants(&c);
            }

            /// Further than 1.5 d0 apart: nothing.
            #[test]
            fn far_pairs_give_nothing((a, b, u) in pair(), d in 1.5 * D0..0.5) {
                let b = place(&a, &b, u, d);
                prop_assert!(contacts(0, 1, &shape(a), &shape(b), D0).is_empty());
            }
        }
    }
}
