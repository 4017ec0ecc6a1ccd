//! Particle-particle and particle-block contacts (math note §5 table; paper Section 3,
//! Figures 2 and 3). A is always a particle: the smaller-index one outside, the inner one in a
//! ring's hole, the particle against a block. Rings seen from outside use their outer radius.

use super::narrow::{Particle, Polygon, Tolerances, plain_contact};
use super::{ContactGeom, ContactKey, ContactKind, Feature};
use crate::geometry::{STRAIGHT_SINE, Vec2};

/// Contacts between two particles (P-P, paper Figure 2): inside a ring's hole when the centre
/// of one particle lies in the hole of the other, otherwise outside.
/// Two rings whose centres lie in each other's holes (only possible with nearly coincident
/// centres): the one with the smaller outer radius is the inner one (the smaller index on a
/// tie), since only it can fit in the other's hole.
pub fn particle_particle(p: &Particle, q: &Particle, tol: &Tolerances, out: &mut Vec<ContactGeom>) {
    let (p, q) = if p.body < q.body { (p, q) } else { (q, p) };
    let d = (p.center - q.center).norm();
    let p_in_q = q.is_ring() && d < q.inner;
    let q_in_p = p.is_ring() && d < p.inner;
    match (p_in_q, q_in_p) {
        (true, true) if p.outer <= q.outer => in_hole(p, q, tol, out),
        (true, true) => in_hole(q, p, tol, out),
        (true, false) => in_hole(p, q, tol, out),
        (false, true) => in_hole(q, p, tol, out),
        (false, false) => outside(p, q, tol, out),
    }
}

/// Unit vector from `to` towards `from`; +x when the two points coincide (to rounding), the
/// "any fixed direction" of math note §5 for coincident centres.
fn unit_from(from: Vec2, to: Vec2, scale: f64) -> Vec2 {
    let d = from - to;
    let len = d.norm();
    if len > f64::EPSILON * scale { d / len } else { Vec2::x() }
}

/// P-P outside (math note §5, paper Figure 2A): A = `p` (smaller index), e = (P_i - P_j)/|..|,
/// n = e, C_i = P_i - R_i e, C_j = P_j + R_j e, g0 = |P_i - P_j| - R_i - R_j.
fn outside(p: &Particle, q: &Particle, tol: &Tolerances, out: &mut Vec<ContactGeom>) {
    let g0 = (p.center - q.center).norm() - p.outer - q.outer;
    if !tol.detects(g0) {
        return;
    }
    let e = unit_from(p.center, q.center, p.outer + q.outer);
    let (ci, cj) = (p.center - p.outer * e, q.center + q.outer * e);
    let key = ContactKey { a: p.body as u32, fa: Feature::Outer, b: q.body as u32, fb: Feature::Outer };
    out.push(plain_contact(key, ContactKind::PP, 0.5 * (ci + cj), e, g0));
}

/// P-P inside (math note §5, paper Figure 2B): particle `p` in the hole of ring `q`.
/// A = `p`, e = (P_i - P_j)/|..|, n = -e, C_i = P_i + R_i e, C_j = P_j + RI_j e,
/// g0 = RI_j - |P_i - P_j| - R_i. Coincident centres: e = +x, so a contact exists only when
/// RI - R < d0 (math note §5, degenerate cases).
fn in_hole(p: &Particle, q: &Particle, tol: &Tolerances, out: &mut Vec<ContactGeom>) {
    let g0 = q.inner - (p.center - q.center).norm() - p.outer;
    if !tol.detects(g0) {
        return;
    }
    let e = unit_from(p.center, q.center, q.inner);
    let (ci, cj) = (p.center + p.outer * e, q.center + q.inner * e);
    let key = ContactKey { a: p.body as u32, fa: Feature::Outer, b: q.body as u32, fb: Feature::Inner };
    out.push(plain_contact(key, ContactKind::PP, 0.5 * (ci + cj), -e, g0));
}

/// Contacts between a particle and a polygon block (P-B, paper Figure 3). A ring whose hole
/// holds the polygon touches it with its inner circle (case IV) only, at convex vertices (the
/// points of a polygon farthest from a centre are on its convex hull, and a segment between
/// two points inside the hole stays inside it); otherwise the outer circle meets the edges
/// (case I) and the convex vertices (case III).
/// Case II (a particle against the edge of a hole in a block) is case I on a mesh's hole loop,
/// whose edges' outward normals point into the hole (math note §9.2).
pub fn particle_block(p: &Particle, b: &Polygon, tol: &Tolerances, out: &mut Vec<ContactGeom>) {
    if p.is_ring() && !b.hole && hole_holds(p, b) {
        for k in (0..b.vertex_count()).filter(|&k| b.convex[k]) {
            vertex_in_hole(p, b, k, tol, out);
        }
        return;
    }
    if b.nodes {
        return particle_loop(p, b, tol, out);
    }
    for f in 0..b.vertex_count() {
        particle_edge(p, b, f, tol, out);
    }
    for k in (0..b.vertex_count()).filter(|&k| b.convex[k]) {
        particle_vertex(p, b, k, tol, out);
    }
}

/// P-L (math note §9.2): a particle against a mesh's boundary loop. Every contact node within
/// the threshold that faces the particle carries its own contact, so a pressed particle bears on
/// every node under it and the nodal forces resolve the pressure (a rigid polygon's vertex cannot
/// move against its edges, a mesh node can). A node on a straight stretch (turn within
/// [`STRAIGHT_SINE`], the band of `loop_contact_flags`) pushes along the surface normal there, the mean of its edges'
/// normals, with the gap measured along it to the circle; a corner node as case III, along the
/// line to the centre. The edges meet the particle as in case I (the true normal at the foot of
/// the centre, so that a rigid particle bouncing on a stiff mesh reflects about the surface),
/// except where the foot lies within 1 % of the edge's length of a node that has its own contact
/// (the same point twice).
fn particle_loop(p: &Particle, b: &Polygon, tol: &Tolerances, out: &mut Vec<ContactGeom>) {
    let n = b.vertex_count();
    let mut touched = vec![false; n];
    for k in (0..n).filter(|&k| b.convex[k]) {
        if let Some((nrm, g0, cp)) = node_contact(p, b, k).filter(|c| c.1 < tol.threshold) {
            touched[k] = true;
            let key = ContactKey {
                a: p.body as u32,
                fa: Feature::Outer,
                b: b.body as u32,
                fb: Feature::Vertex(b.id(k)),
            };
            out.push(plain_contact(key, ContactKind::PB, 0.5 * (cp + b.vertices[k]), nrm, g0));
        }
    }
    for f in 0..n {
        let e = b.edge(f);
        let s = e.along(p.center);
        let near = 0.01 * e.len;
        let (start, end) = (touched[f], touched[b.next(f)]);
        let bracketed = start && end && sagitta(p.outer, e.len) <= SAGITTA_FRACTION * tol.depth;
        if !(bracketed || (s <= near && start) || (s >= e.len - near && end)) {
            particle_edge(p, b, f, tol, out);
        }
    }
}

/// Largest depth, as a fraction of d0, by which a particle may sink between two loop nodes that
/// both carry contacts before the edge between them needs its own (math note §9.2): a fifth of
/// the adaptive step's penetration bound (5 % of d0, math note §10.8).
const SAGITTA_FRACTION: f64 = 0.01;

/// Depth of a circle of radius `r` beyond a chord of length `len` whose ends are on it:
/// r - sqrt(r² - len²/4); infinite when the chord is longer than the diameter.
fn sagitta(r: f64, len: f64) -> f64 {
    let h2 = r * r - 0.25 * len * len;
    if h2 > 0.0 { r - h2.sqrt() } else { f64::INFINITY }
}

/// Node k's contact with particle p: (normal from the loop towards the particle, gap, the
/// particle's point), or None when the node does not face the particle.
fn node_contact(p: &Particle, b: &Polygon, k: usize) -> Option<(Vec2, f64, Vec2)> {
    let v = b.vertices[k];
    let d = p.center - v;
    let (n_in, n_out) = (b.edge(b.prev(k)).n_out, b.edge(k).n_out);
    if b.turn(k).abs() <= STRAIGHT_SINE {
        let nrm = (n_in + n_out).normalize();
        let along = d.dot(&nrm);
        let off = (d - along * nrm).norm_squared();
        if along <= 0.0 || off >= p.outer * p.outer {
            return None;
        }
        let g0 = along - (p.outer * p.outer - off).sqrt();
        return Some((nrm, g0, v + nrm * g0));
    }
    let dist = d.norm();
    if !(dist > 0.0 && d.dot(&(n_in + n_out)) > 0.0) {
        return None;
    }
    let nrm = d / dist;
    Some((nrm, dist - p.outer, p.center - p.outer * nrm))
}

/// Whether polygon `b` lies in the hole of ring `p`: every vertex is nearer the centre than
/// the middle of the ring's wall, (RI + RE)/2. A polygon outside the ring (even penetrating
/// its outer circle) always has a vertex beyond that.
fn hole_holds(p: &Particle, b: &Polygon) -> bool {
    let mid = 0.5 * (p.inner + p.outer);
    b.vertices.iter().all(|v| (v - p.center).norm() < mid)
}

/// P-B case I (math note §5, paper Figure 3A): particle against edge f from outside.
/// Requires the foot of the centre inside the edge, 0 <= (P - V_a)·t_e <= L_e, and the centre
/// on the outer side. A = particle, n = n_out, g0 = (P - V_a)·n_out - R,
/// points: foot F and C_P = P - R n_out.
fn particle_edge(p: &Particle, b: &Polygon, f: usize, tol: &Tolerances, out: &mut Vec<ContactGeom>) {
    let e = b.edge(f);
    let s = e.along(p.center);
    let h = e.height(p.center);
    let g0 = h - p.outer;
    if !(s >= 0.0 && s <= e.len && h > 0.0 && g0 < tol.threshold) {
        return;
    }
    let foot = e.start + s * e.t;
    let cp = p.center - p.outer * e.n_out;
    let key =
        ContactKey { a: p.body as u32, fa: Feature::Outer, b: b.body as u32, fb: Feature::Edge(b.id(f)) };
    out.push(plain_contact(key, ContactKind::PB, 0.5 * (foot + cp), e.n_out, g0));
}

/// P-B case III (math note §5, paper Figure 3C): convex vertex k outside the particle, with
/// the particle centre in the vertex's Voronoi region (its projections on both adjacent edge
/// lines fall beyond the vertex; strictly, so that the boundary belongs to case I).
/// A = particle, e = (V - P)/|V - P|, n = -e, g0 = |V - P| - R, points C_P = P + R e and V.
fn particle_vertex(p: &Particle, b: &Polygon, k: usize, tol: &Tolerances, out: &mut Vec<ContactGeom>) {
    let v = b.vertices[k];
    let r = p.center - v;
    let (t_in, t_out) = (b.edge(b.prev(k)).t, b.edge(k).t);
    let dist = r.norm();
    let g0 = dist - p.outer;
    if !(r.dot(&t_in) > 0.0 && r.dot(&t_out) < 0.0 && g0 < tol.threshold) {
        return;
    }
    let n = r / dist;
    let cp = p.center - p.outer * n;
    let key =
        ContactKey { a: p.body as u32, fa: Feature::Outer, b: b.body as u32, fb: Feature::Vertex(b.id(k)) };
    out.push(plain_contact(key, ContactKind::PB, 0.5 * (cp + v), n, g0));
}

/// P-B case IV (math note §5, paper Figure 3D): convex vertex k in the hole of ring `p`.
/// A = ring, e = (V - P)/|V - P|, n = e, g0 = RI - |V - P|, points C_P = P + RI e and V.
/// A vertex at the ring centre uses e = +x.
fn vertex_in_hole(p: &Particle, b: &Polygon, k: usize, tol: &Tolerances, out: &mut Vec<ContactGeom>) {
    let v = b.vertices[k];
    let g0 = p.inner - (v - p.center).norm();
    if !tol.detects(g0) {
        return;
    }
    let e = unit_from(v, p.center, p.inner);
    let cp = p.center + p.inner * e;
    let key =
        ContactKey { a: p.body as u32, fa: Feature::Inner, b: b.body as u32, fb: Feature::Vertex(b.id(k)) };
    out.push(plain_contact(key, ContactKind::PB, 0.5 * (cp + v), e, g0));
}

#[cfg(test)]
mod tests {
    use super::super::testkit::*;
    use super::*;
    use Feature::*;

    const D0: f64 = 0.1;
    /// Closed forms below are evaluated in f64 from values of order 1-100: a few ulp.
    const TOL: f64 = 1e-12;
    const PP: ContactKind = ContactKind::PP;
    const PB: ContactKind = ContactKind::PB;

    /// Math note §5 P-P outside: R = 1 each, centres 2.01 apart -> g0 = 2.01 - 2 = 0.01,
    /// n = e = (P_0 - P_1)/|..| = -x, C_0 = (1,0), C_1 = (1.01,0), point (1.005, 0).
    #[test]
    fn two_disks_outside() {
        let c = contacts(1, 0, &disk(2.01, 0.0, 1.0), &disk(0.0, 0.0, 1.0), D0);
        assert_eq!(c.len(), 1);
        check(&c[0], key(0, Outer, 1, Outer), PP, (-1.0, 0.0), 0.01, (1.005, 0.0), TOL);
    }

    /// Two disks 2.2 apart (g0 = 0.2 > d0): nothing. A ring seen from outside uses RE:
    /// ring (index 0) RE = 3 at the origin, disk R = 1 at (0, 4.05) -> g0 = 4.05 - 4 = 0.05,
    /// A = ring (smaller index), n = e = (P_0 - P_1)/|..| = -y, C_0 = (0,3), C_1 = (0,3.05),
    /// point (0, 3.025).
    #[test]
    fn far_disks_and_ring_from_outside() {
        assert!(contacts(0, 1, &disk(0.0, 0.0, 1.0), &disk(2.2, 0.0, 1.0), D0).is_empty());
        let c = contacts(0, 1, &ring(0.0, 0.0, 3.0, 1.0), &disk(0.0, 4.05, 1.0), D0);
        assert_eq!(c.len(), 1);
        check(&c[0], key(0, Outer, 1, Outer), PP, (0.0, -1.0), 0.05, (0.0, 3.025), TOL);
    }

    /// Math note §7.5 geometry: ring (index 0) RI = 100, disk (index 1) R = 40 at (-59.99, 0):
    /// A = disk (inner particle, not the smaller index), e = (P_1 - P_0)/|..| = -x, n = -e = +x,
    /// g0 = 100 - 59.99 - 40 = 0.01, C_1 = (-99.99, 0), C_0 = (-100, 0), point (-99.995, 0).
    #[test]
    fn disk_inside_ring() {
        let c = contacts(0, 1, &ring(0.0, 0.0, 110.0, 100.0), &disk(-59.99, 0.0, 40.0), D0);
        assert_eq!(c.len(), 1);
        check(&c[0], key(1, Outer, 0, Inner), PP, (1.0, 0.0), 100.0 - 59.99 - 40.0, (-99.995, 0.0), 1e-11);
        // Centre well inside (g0 = 100 - 10 - 40 = 50): nothing.
        assert!(contacts(0, 1, &ring(0.0, 0.0, 110.0, 100.0), &disk(-10.0, 0.0, 40.0), D0).is_empty());
    }

    /// Math note §5 degenerate case: coincident centres give a contact only if RI - R < d0,
    /// along the fixed direction e = +x (n = -x): g0 = RI - R, C_P = (R,0), C_ring = (RI,0).
    #[test]
    fn coincident_centres_in_hole() {
        assert!(contacts(0, 1, &ring(0.0, 0.0, 2.0, 1.0), &disk(0.0, 0.0, 0.5), D0).is_empty());
        let c = contacts(0, 1, &ring(0.0, 0.0, 2.0, 1.0), &disk(0.0, 0.0, 0.95), D0);
        assert_eq!(c.len(), 1);
        check(&c[0], key(1, Outer, 0, Inner), PP, (-1.0, 0.0), 0.05, (0.975, 0.0), TOL);
    }

    /// A small ring (index 1, RE = 1) in the hole of a big ring (index 0, RI = 5): the inside
    /// case with the small ring's outer radius: centre (3.95, 0) -> g0 = 5 - 3.95 - 1 = 0.05,
    /// n = -x, C_1 = (4.95, 0), C_0 = (5, 0). Both centres are not in each other's hole here.
    #[test]
    fn ring_inside_ring() {
        let c = contacts(0, 1, &ring(0.0, 0.0, 6.0, 5.0), &ring(3.95, 0.0, 1.0, 0.5), D0);
        assert_eq!(c.len(), 1);
        check(&c[0], key(1, Outer, 0, Inner), PP, (-1.0, 0.0), 0.05, (4.975, 0.0), TOL);
    }

    /// Math note §5 P-B case I: unit square [0,1]², disk R = 0.5 at (0.3, 1.52) above the top
    /// edge (edge 2, from (1,1) to (0,1), n_out = +y): g0 = 0.52 - 0.5 = 0.02, n = +y,
    /// foot (0.3,1), C_P = (0.3,1.02), point (0.3, 1.01). A = disk.
    #[test]
    fn disk_above_square_edge() {
        let c = contacts(0, 1, &rect(0.0, 0.0, 1.0, 1.0), &disk(0.3, 1.52, 0.5), D0);
        assert_eq!(c.len(), 1);
        check(&c[0], key(1, Outer, 0, Edge(2)), PB, (0.0, 1.0), 0.02, (0.3, 1.01), TOL);
    }

    /// Math note §5 P-B case III: unit square, disk R = 0.5 on the diagonal beyond the corner
    /// (1,1) (vertex 2) at distance 0.51: g0 = 0.01, n = -e = (1,1)/√2,
    /// point = V + (g0/2) n = (1,1) + 0.005 (1,1)/√2. No edge contact (the centre projects
    /// beyond both edges).
    #[test]
    fn disk_at_square_corner() {
        let s = 0.51 / 2f64.sqrt();
        let c = contacts(0, 1, &rect(0.0, 0.0, 1.0, 1.0), &disk(1.0 + s, 1.0 + s, 0.5), D0);
        assert_eq!(c.len(), 1);
        let (n, h) = (1.0 / 2f64.sqrt(), 0.005 / 2f64.sqrt());
        check(&c[0], key(1, Outer, 0, Vertex(2)), PB, (n, n), 0.01, (1.0 + h, 1.0 + h), TOL);
    }

    /// A disk in the notch of an L-shape touches both notch edges (case I twice) and never the
    /// reflex vertex: L = [0,2]×[0,1] ∪ [0,1]×[1,2], notch corner (1,1) is vertex 3; disk
    /// R = 0.25 at (1.26, 1.27): floor (edge 2, n_out +y) g0 = 0.02, point (1.26, 1.01);
    /// wall (edge 3, n_out +x) g0 = 0.01, point (1.005, 1.27).
    #[test]
    fn disk_in_notch_touches_both_edges() {
        let l = polygon(&[(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)]);
        let c = contacts(0, 1, &l, &disk(1.26, 1.27, 0.25), D0);
        assert_eq!(c.len(), 2);
        check(&c[0], key(1, Outer, 0, Edge(2)), PB, (0.0, 1.0), 0.02, (1.26, 1.01), TOL);
        check(&c[1], key(1, Outer, 0, Edge(3)), PB, (1.0, 0.0), 0.01, (1.005, 1.27), TOL);
    }

    /// Math note §5 P-B case IV: a diamond with vertices (0.99,0), (0.5,0.49), (0.01,0),
    /// (0.5,-0.49) in the hole of a ring RI = 1, RE = 3 at the origin: only (0.99, 0) (vertex 0)
    /// is within d0 of the inner circle: g0 = 1 - 0.99 = 0.01, n = e = +x, C_P = (1,0),
    /// point (0.995, 0). The others are at least 0.3 away. A = ring, feature Inner.
    #[test]
    fn square_vertex_inside_ring() {
        let diamond = polygon(&[(0.99, 0.0), (0.5, 0.49), (0.01, 0.0), (0.5, -0.49)]);
        let c = contacts(0, 1, &diamond, &ring(0.0, 0.0, 3.0, 1.0), D0);
        assert_eq!(c.len(), 1);
        check(&c[0], key(1, Inner, 0, Vertex(0)), PB, (1.0, 0.0), 1.0 - 0.99, (0.995, 0.0), TOL);
    }

    /// A ring (RE = 3) resting on a block from outside uses its outer radius: square
    /// [-5,5]×[-10,0], ring centre (0, 3.04): g0 = 3.04 - 3 = 0.04 on the top edge (edge 2),
    /// n = +y, point (0, 0.02). The block is not in the hole, so no case IV.
    #[test]
    fn ring_on_block_uses_outer_radius() {
        let c = contacts(0, 1, &rect(-5.0, -10.0, 5.0, 0.0), &ring(0.0, 3.04, 3.0, 1.0), D0);
        assert_eq!(c.len(), 1);
        check(&c[0], key(1, Outer, 0, Edge(2)), PB, (0.0, 1.0), 0.04, (0.0, 0.02), TOL);
    }

    /// P-L (math note §9.2): a loop whose top has nodes at x = ±0.05 (edge 3 between them,
    /// L = 0.1), corners at x = ±3 (beyond d0 = 0.1 of the disks). A disk R = 10 resting on it
    /// at gap 0.001 under its centre reaches both nodes (gap 0.001 + 10 − √(100 − 0.0025)) and
    /// sinks between them by at most the sagitta L²/(8R) = 1.25e-4 ≤ 1 % of d0: the two node
    /// contacts only, along the surface normal +y. A disk R = 0.06 at gap 0.01 also reaches both
    /// nodes (0.07 − √(0.0036 − 0.0025) = 0.0368) but would sink between them by
    /// 0.06 − √0.0011 = 0.0268 > 1 % of d0: edge 3 keeps its case-I contact, g0 = 0.01.
    #[test]
    fn loop_edge_between_two_node_contacts() {
        let v: Vec<Vec2> = [(-3., -1.), (3., -1.), (3., 0.), (0.05, 0.), (-0.05, 0.), (-3., 0.)]
            .iter()
            .map(|&(x, y)| Vec2::new(x, y))
            .collect();
        let convex = crate::geometry::loop_contact_flags(&v);
        let mesh = super::super::BodyShape::Polygon { vertices: v, convex, nodes: true, holes: Vec::new() };
        let c = contacts(0, 1, &mesh, &disk(0.0, 10.001, 10.0), D0);
        let node_gap = 0.001 + 10.0 - (100.0f64 - 0.0025).sqrt();
        assert_eq!(c.len(), 2, "{c:?}");
        check(&c[0], key(1, Outer, 0, Vertex(3)), PB, (0.0, 1.0), node_gap, (0.05, 0.5 * node_gap), TOL);
        check(&c[1], key(1, Outer, 0, Vertex(4)), PB, (0.0, 1.0), node_gap, (-0.05, 0.5 * node_gap), TOL);
        let c = contacts(0, 1, &mesh, &disk(0.0, 0.07, 0.06), D0);
        assert_eq!(c.len(), 3, "{c:?}");
        check(&c[2], key(1, Outer, 0, Edge(3)), PB, (0.0, 1.0), 0.01, (0.0, 0.005), TOL);
    }

    /// A disk in a mesh's hole (math note §9.2): outer square [-3,3]² (vertices 0-3) around a
    /// clockwise square hole [-1,1]² (vertices 4-7: (-1,-1), (-1,1), (1,1), (1,-1)); the hole's
    /// corners turn away from the material (not contact nodes). Disk R = 0.5 at (0, -0.48): the
    /// hole's bottom edge (its edge 3, feature Edge(4 + 3)) from (1,-1) to (-1,-1) has outward
    /// normal +y, into the hole: g0 = 0.52 - 0.5 = 0.02, foot (0,-1), point (0, -0.99).
    #[test]
    fn disk_in_a_mesh_hole() {
        let pts = |p: &[(f64, f64)]| p.iter().map(|&(x, y)| Vec2::new(x, y)).collect::<Vec<_>>();
        let outer = pts(&[(-3., -3.), (3., -3.), (3., 3.), (-3., 3.)]);
        let hole = pts(&[(-1., -1.), (-1., 1.), (1., 1.), (1., -1.)]);
        let flags = crate::geometry::loop_contact_flags;
        let holes = vec![super::super::HoleLoop { convex: flags(&hole), vertices: hole }];
        let mesh =
            super::super::BodyShape::Polygon { convex: flags(&outer), vertices: outer, nodes: true, holes };
        let c = contacts(0, 1, &mesh, &disk(0.0, -0.48, 0.5), D0);
        assert_eq!(c.len(), 1, "{c:?}");
        check(&c[0], key(1, Outer, 0, Edge(7)), PB, (0.0, 1.0), 0.02, (0.0, -0.99), TOL);
    }

    mod random_particle_block {
        //! A random disk or ring at a known distance d from a random convex polygon or
        //! L-shape (found by bisection along a random direction from inside the polygon).
        use super::*;
        use proptest::prelude::*;

        fn particle_near_block() -> impl Strategy<Value = (Vec<Vec2>, f64, bool, Vec2)> {
            let gaps = prop::collection::vec(1.0..1.9f64, 3..7);
            let l = (1.0..2.0f64, 1.0..2.0f64, 0.5..0.9f64);
            (gaps, l, 1.0..2.0f64, 0.0..6.3f64, any::<bool>(), 0.1..0.5f64, any::<bool>(), 0.0..6.3f64)
                .prop_map(|(g, (a, b, t), r, turn, concave, radius, is_ring, dir)| {
                    let poly =
                        if concave { l_shape(a, b, t, turn) } else { convex(Vec2::zeros(), r, turn, &g) };
                    (poly, radius, is_ring, Vec2::new(dir.cos(), dir.sin()))
                })
        }

        proptest! {
            /// Closer than d0: at least one contact; every g0 is at least the true gap d (each
            /// is measured to a line or vertex of the polygon) and the smallest equals it.
            #[test]
            fn close_particle_is_detected((poly, r, is_ring, u) in particle_near_block(), d in 0.0..0.9 * D0) {
                let t = bisect(|t| point_polygon(t * u, &poly) - r, d);
                let (x, y) = (t * u.x, t * u.y);
                let particle = if is_ring { ring(x, y, r, 0.5 * r) } else { disk(x, y, r) };
                let c = contacts(0, 1, &polygon_of(poly), &particle, D0);
                prop_assert!(!c.is_empty());
                prop_assert!(c.iter().all(|k| k.a == 1 && k.kind == PB && k.g0 >= d - 1e-9), "{c:?}");
                let min = c.iter().map(|k| k.g0).fold(f64::INFINITY, f64::min);
                prop_assert!((min - d).abs() < 1e-9, "{min} vs {d}");
            }
        }
    }
}
