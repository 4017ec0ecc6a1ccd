//! Boundary tractions (`[[traction]]`, math note §2.5): a load per unit length on a part of a
//! polygon's or mesh's boundary, integrated exactly edge by edge.
//!
//! A traction is uniform along each loaded edge piece and follows the boundary: it is evaluated on
//! the step-start (current) configuration, so a pressure stays normal to the edge as the body
//! turns and deforms. On a piece of edge `a → b` (the body on its left) from `s0` to `s1`, with
//! unit tangent τ = (b − a)/|b − a| and outward normal n = (τ_y, −τ_x), the traction t (pressure p
//! and shear s: t = −p n + s τ; a stress σ: t = σ n) acts over the length ℓ = (s1 − s0)|b − a|.
//! Its work on a displacement field affine along the edge, u(x) = T(x) d (a block's first-order
//! map, paper eqs. 3, 5, 7; a Tri3 edge's linear interpolation), is d^T T(x_m)^T t ℓ with x_m the
//! piece's midpoint (the midpoint rule is exact for a linear integrand). So a block gets the point
//! load t ℓ at x_m, and a mesh the consistent nodal loads (1 − s_m) t ℓ at a and s_m t ℓ at b,
//! s_m = (s0 + s1)/2 (half of t ℓ to each node of a whole edge).

use crate::geometry::Vec2;
use crate::mesh::loops::boundary_loops;
use crate::model::{BodySpec, Shape};
/// The traction types are model data ([`crate::model`]); their physics is here.
pub use crate::model::{Piece, Traction, TractionLaw};

impl TractionLaw {
    /// The traction [Pa] on a boundary with unit tangent `tau` (the body on its left).
    pub fn vector(&self, tau: Vec2) -> Vec2 {
        let n = Vec2::new(tau.y, -tau.x);
        match *self {
            TractionLaw::Pressure { pressure, shear } => -n * pressure + tau * shear,
            TractionLaw::Stress([sx, sy, txy]) => Vec2::new(sx * n.x + txy * n.y, txy * n.x + sy * n.y),
        }
    }
}

impl Traction {
    /// The factor at time t (piecewise linear, constant beyond the ends: [`crate::model::Load::factor`]).
    pub fn factor(&self, t: f64) -> f64 {
        let load = crate::model::Load {
            body: self.body,
            point: Vec2::zeros(),
            force: Vec2::zeros(),
            history: self.history.clone(),
        };
        load.factor(t)
    }

    /// The traction's loads at time `t` on the current positions `at` of the nodes: per piece
    /// `(a, b, s_m, F)`, the force F = t ℓ and the midpoint parameter s_m (module docs).
    pub fn forces(&self, at: impl Fn(usize) -> Vec2, t: f64) -> Vec<(usize, usize, f64, Vec2)> {
        let factor = self.factor(t);
        self.pieces
            .iter()
            .filter_map(|p| {
                let (a, b) = (at(p.nodes[0]), at(p.nodes[1]));
                let len = (b - a).norm();
                (len > 0.0).then(|| {
                    let tau = (b - a) / len;
                    let force = self.law.vector(tau) * (len * (p.s[1] - p.s[0]) * factor);
                    (p.nodes[0], p.nodes[1], 0.5 * (p.s[0] + p.s[1]), force)
                })
            })
            .collect()
    }
}

/// The nearest point of the closed boundary `ring` (edge k from `ring[k]` to `ring[k + 1]`) to
/// `p`: `(k, s)` with s in [0, 1), a vertex given as the start of the edge leaving it; ties to
/// the first edge.
fn nearest(ring: &[Vec2], p: Vec2) -> (usize, f64) {
    let n = ring.len();
    let mut best = (f64::INFINITY, 0, 0.0);
    for k in 0..n {
        let (a, b) = (ring[k], ring[(k + 1) % n]);
        let ab = b - a;
        let s = if ab.norm_squared() > 0.0 {
            ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let d = (a + ab * s - p).norm();
        if d < best.0 {
            best = (d, k, s);
        }
    }
    let (_, k, s) = best;
    if s >= 1.0 { ((k + 1) % n, 0.0) } else { (k, s) }
}

/// The part of the closed boundary `ring` (the body on its left) from the point nearest `from`
/// to the point nearest `to`, in the ring's direction: `(edge k, [s0, s1])` pieces (edge k from
/// `ring[k]` to `ring[k + 1]`), none of zero length. `None` when both points are the same
/// boundary point (no boundary part).
pub fn boundary_part(ring: &[Vec2], from: Vec2, to: Vec2) -> Option<Vec<(usize, [f64; 2])>> {
    let n = ring.len();
    if n < 2 {
        return None;
    }
    let (kf, sf) = nearest(ring, from);
    let (kt, st) = nearest(ring, to);
    if kf == kt && sf == st {
        return None;
    }
    let mut pieces = Vec::new();
    if kf == kt && st > sf {
        return Some(vec![(kf, [sf, st])]);
    }
    pieces.push((kf, [sf, 1.0]));
    let mut k = (kf + 1) % n;
    while k != kt {
        pieces.push((k, [0.0, 1.0]));
        k = (k + 1) % n;
    }
    if st > 0.0 {
        pieces.push((kt, [0.0, st]));
    }
    Some(pieces)
}

/// Every edge of the bodies that lies on the part of the domain's `outline` (counter-clockwise)
/// from the point nearest `from` to the point nearest `to` (counter-clockwise): `(body, edge)`,
/// edge k of a polygon from vertex k to k + 1, of a mesh the k-th edge of its outer boundary
/// loop. An edge lies on it when both its ends are within 1e-9 of the outline's size of one
/// piece of that part and it runs the same way (the body inside the domain).
pub fn domain_edges(outline: &[Vec2], bodies: &[BodySpec], from: Vec2, to: Vec2) -> Vec<(usize, usize)> {
    let Some(part) = boundary_part(outline, from, to) else { return Vec::new() };
    let size = outline.iter().map(|p| p.norm()).fold(0.0, f64::max).max(f64::MIN_POSITIVE);
    let tol = 1e-9 * size;
    let n = outline.len();
    let segments: Vec<(Vec2, Vec2)> = part
        .iter()
        .map(|&(k, [s0, s1])| {
            let (a, b) = (outline[k], outline[(k + 1) % n]);
            (a + (b - a) * s0, a + (b - a) * s1)
        })
        .collect();
    let on = |p: Vec2, (a, b): (Vec2, Vec2)| {
        let ab = b - a;
        let s = (p - a).dot(&ab) / ab.norm_squared();
        (-1e-12..=1.0 + 1e-12).contains(&s) && (a + ab * s - p).norm() <= tol
    };
    let mut out = Vec::new();
    for (i, body) in bodies.iter().enumerate() {
        let ring = body_ring(&body.shape);
        let m = ring.len();
        for k in 0..m {
            let (p, q) = (ring[k], ring[(k + 1) % m]);
            if segments.iter().any(|&seg| on(p, seg) && on(q, seg) && (q - p).dot(&(seg.1 - seg.0)) > 0.0) {
                out.push((i, k));
            }
        }
    }
    out
}

/// The tractions of a `body = "domain"` traction: one per body with an edge on the part of the
/// outline from `from` to `to` ([`domain_edges`]), its pieces those whole edges (a polygon's
/// vertices k, k + 1; a mesh's outer-loop nodes), each with `law` and `history`.
pub fn domain_tractions(
    outline: &[Vec2],
    bodies: &[BodySpec],
    from: Vec2,
    to: Vec2,
    law: TractionLaw,
    history: Option<Vec<(f64, f64)>>,
) -> Vec<Traction> {
    let mut out: Vec<Traction> = Vec::new();
    for (body, k) in domain_edges(outline, bodies, from, to) {
        let ids: Vec<usize> = match &bodies[body].shape {
            Shape::Mesh(m) => outer_loop(&m.mesh.nodes, &m.mesh.triangles),
            shape => (0..body_ring(shape).len()).collect(),
        };
        let piece = Piece { nodes: [ids[k], ids[(k + 1) % ids.len()]], s: [0.0, 1.0] };
        match out.last_mut().filter(|t| t.body == body) {
            Some(t) => t.pieces.push(piece),
            None => out.push(Traction { body, pieces: vec![piece], law, history: history.clone() }),
        }
    }
    out
}

/// The counter-clockwise outer boundary of a polygon (its vertices) or mesh (its outer loop's
/// nodes); empty for disks and rings.
pub fn body_ring(shape: &Shape) -> Vec<Vec2> {
    match shape {
        Shape::Polygon { vertices } => vertices.clone(),
        Shape::Mesh(m) => {
            outer_loop(&m.mesh.nodes, &m.mesh.triangles).iter().map(|&i| m.mesh.nodes[i]).collect()
        }
        _ => Vec::new(),
    }
}

/// A mesh's outer boundary loop (node indices, counter-clockwise); empty if unusable.
pub fn outer_loop(nodes: &[Vec2], triangles: &[[usize; 3]]) -> Vec<usize> {
    let loops = boundary_loops(nodes, triangles).unwrap_or_default();
    loops.into_iter().find(|l| !l.is_hole()).map(|l| l.nodes).unwrap_or_default()
}

#[cfg(test)]
mod tests;
