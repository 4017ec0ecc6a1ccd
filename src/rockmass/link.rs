//! Constraint insertion without spade's own splitting (math note §12.7): a constraint that
//! crosses another is split at the crossing by this glue, which snaps a crossing within the snap
//! distance of a vertex of the two segments onto that vertex (a reported merge), so spade never
//! has to re-route a constraint through a vertex of its own choosing.

use spade::handles::FixedVertexHandle;
use spade::{Intersection, LineIntersectionIterator, Point2, Triangulation};

use super::arrange::Cdt;
use super::{CutError, Report};

/// Steps one constraint may take (each splits it or a crossed constraint once) before the cut is
/// refused: a segment across the 100,000-block benchmark crosses about 630 others, one step each.
const LINK_STEPS: usize = 1 << 16;

fn at(cdt: &Cdt, v: FixedVertexHandle) -> [f64; 2] {
    let p = cdt.vertex(v).position();
    [p.x, p.y]
}

fn dist(p: [f64; 2], q: [f64; 2]) -> f64 {
    (p[0] - q[0]).hypot(p[1] - q[1])
}

/// The crossing of the crossed edge p1p2 with the new constraint p3p4 (math note §12.8): by
/// spade's formula (`cdt::get_edge_intersections`, exact where both lines are axis-parallel)
/// when that point lies within `snap` of the crossed edge; else `p1 + t (p2 - p1)`,
/// `t = ((p3 - p1) x d2) / (d1 x d2)` clamped to [0, 1]. Spade's line walk has found (by exact
/// predicates) that the two cross properly, so the exact t lies in (0, 1) and that point is on
/// the crossed edge to the rounding of its coordinates, however far they are from the origin.
/// Lines parallel in floating point give the crossed edge's end nearer the constraint's line.
fn crossing(p1: [f64; 2], p2: [f64; 2], p3: [f64; 2], p4: [f64; 2], snap: f64) -> [f64; 2] {
    let (a1, b1) = (p2[1] - p1[1], p1[0] - p2[0]);
    let c1 = a1 * p1[0] + b1 * p1[1];
    let (a2, b2) = (p4[1] - p3[1], p3[0] - p4[0]);
    let c2 = a2 * p3[0] + b2 * p3[1];
    let det = a1 * b2 - a2 * b1;
    let p = [(b2 * c1 - b1 * c2) / det, (a1 * c2 - a2 * c1) / det];
    let d1 = [p2[0] - p1[0], p2[1] - p1[1]];
    let len2 = d1[0] * d1[0] + d1[1] * d1[1];
    let along = (((p[0] - p1[0]) * d1[0] + (p[1] - p1[1]) * d1[1]) / len2).clamp(0.0, 1.0);
    let foot = [p1[0] + along * d1[0], p1[1] + along * d1[1]];
    if p[0].is_finite() && p[1].is_finite() && dist(p, foot) <= snap {
        return p;
    }
    let cross = |u: [f64; 2], w: [f64; 2]| u[0] * w[1] - u[1] * w[0];
    let d2 = [p4[0] - p3[0], p4[1] - p3[1]];
    let t = cross([p3[0] - p1[0], p3[1] - p1[1]], d2) / cross(d1, d2);
    if t.is_finite() {
        let t = t.clamp(0.0, 1.0);
        return [p1[0] + t * d1[0], p1[1] + t * d1[1]];
    }
    let side = |q: [f64; 2]| cross([q[0] - p3[0], q[1] - p3[1]], d2).abs();
    if side(p1) <= side(p2) { p1 } else { p2 }
}

/// The first constraint edge the segment u -> v crosses (not through a vertex), as (from, to).
fn first_crossing(cdt: &Cdt, u: FixedVertexHandle, v: FixedVertexHandle) -> Option<[FixedVertexHandle; 2]> {
    LineIntersectionIterator::new_from_handles(cdt, u, v).find_map(|i| match i {
        Intersection::EdgeIntersection(e) if e.is_constraint_edge() => Some([e.from().fix(), e.to().fix()]),
        _ => None,
    })
}

/// Makes u -> v a chain of constraint edges. Where it crosses a constraint a -> b, the crossing
/// w is: u, v, a or b if one lies within `snap` of the crossing point (reported when it is not
/// exactly there), else a new vertex there; a -> b is then re-made as a -> w -> b unless the new
/// vertex split it already, and u -> w, w -> v are linked the same way.
pub(crate) fn link(
    cdt: &mut Cdt,
    u: FixedVertexHandle,
    v: FixedVertexHandle,
    snap: f64,
    reports: &mut Vec<Report>,
) -> Result<(), CutError> {
    let mut todo = vec![(u, v)];
    let mut steps = 0;
    while let Some((u, v)) = todo.pop() {
        if u == v || cdt.exists_constraint(u, v) || !cdt.try_add_constraint(u, v).is_empty() {
            continue;
        }
        steps += 1;
        let (pu, pv) = (at(cdt, u), at(cdt, v));
        let degenerate = |message: &str| CutError::Degenerate { at: pu, message: message.into() };
        if steps > LINK_STEPS {
            return Err(degenerate("a constraint could not be split at its crossings"));
        }
        let Some([a, b]) = first_crossing(cdt, u, v) else {
            return Err(degenerate("the triangulation refused a constraint that crosses none"));
        };
        let p = crossing(at(cdt, a), at(cdt, b), pu, pv, snap);
        let near = [u, v, a, b].into_iter().map(|k| (dist(at(cdt, k), p), k));
        let (d, k) = near.min_by(|x, y| x.0.total_cmp(&y.0)).unwrap_or((f64::INFINITY, u));
        let w = if d <= snap {
            if d > 0.0 {
                reports.push(Report::MergedVertices { count: 2, distance: d, at: at(cdt, k) });
            }
            k
        } else {
            cdt.insert(Point2::new(p[0], p[1]))
                .map_err(|e| degenerate(&format!("the triangulation refused a vertex: {e:?}")))?
        };
        // popped in the order a -> w, w -> b, u -> w, w -> v: the crossed constraint first
        todo.push((w, v));
        todo.push((u, w));
        let crossed = cdt.get_edge_from_neighbors(a, b).map(|e| e.fix().as_undirected());
        if let Some(e) = crossed.filter(|e| cdt.is_constraint_edge(*e) && w != a && w != b) {
            cdt.remove_constraint_edge(e);
            todo.push((w, b));
            todo.push((a, w));
        }
    }
    Ok(())
}
