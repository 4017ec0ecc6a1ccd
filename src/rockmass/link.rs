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

/// The crossing of the lines p1p2 (the crossed edge) and p3p4 (the new constraint), by spade's
/// formula (`cdt::get_edge_intersections`, so that a cut spade could split alone gets the same
/// coordinates); parallel lines, or a point off the crossed edge by more than `snap`, give the
/// crossed edge's point nearest the constraint's line instead.
fn crossing(p1: [f64; 2], p2: [f64; 2], p3: [f64; 2], p4: [f64; 2], snap: f64) -> [f64; 2] {
    let (a1, b1) = (p2[1] - p1[1], p1[0] - p2[0]);
    let c1 = a1 * p1[0] + b1 * p1[1];
    let (a2, b2) = (p4[1] - p3[1], p3[0] - p4[0]);
    let c2 = a2 * p3[0] + b2 * p3[1];
    let det = a1 * b2 - a2 * b1;
    let p = [(b2 * c1 - b1 * c2) / det, (a1 * c2 - a2 * c1) / det];
    let (ex, ey) = (p2[0] - p1[0], p2[1] - p1[1]);
    let len2 = ex * ex + ey * ey;
    let t = ((p[0] - p1[0]) * ex + (p[1] - p1[1]) * ey) / len2;
    let foot = |t: f64| [p1[0] + t * ex, p1[1] + t * ey];
    if p[0].is_finite() && p[1].is_finite() && dist(p, foot(t.clamp(0.0, 1.0))) <= snap {
        return p;
    }
    // the end of the crossed edge nearer the constraint's line (the two lie on either side)
    let side = |q: [f64; 2]| (a2 * q[0] + b2 * q[1] - c2).abs();
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
