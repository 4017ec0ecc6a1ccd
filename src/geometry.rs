//! Plane geometry: vectors, polygon moments, orientation and simplicity checks.

pub type Vec2 = nalgebra::Vector2<f64>;

/// 2D cross product `a x b = a_x b_y - a_y b_x` (math note §0).
#[inline]
pub fn cross(a: Vec2, b: Vec2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// `a` turned counter-clockwise by 90° (`rperp` of math note §0).
#[inline]
pub fn perp(a: Vec2) -> Vec2 {
    Vec2::new(-a.y, a.x)
}

/// `a` turned clockwise by 90°: the contact tangent `tau = cw(n)` (math note §0).
#[inline]
pub fn cw(a: Vec2) -> Vec2 {
    Vec2::new(a.y, -a.x)
}

/// Sine of the turn below which a loop vertex counts as straight (3°): a mesh node that the load
/// pushes slightly inwards stays a contact node (`loop_contact_flags`), and a particle presses
/// such a node along the surface normal (`contact::particle`, math note §9.2).
pub const STRAIGHT_SINE: f64 = 0.05;

/// Which vertices of a mesh's outer loop make contacts (math note §9.2: every boundary node
/// carries its own contact): the convex ones and the straight ones (up to [`STRAIGHT_SINE`]
/// past 180°), which on a rigid polygon would never be nearest to another body but on a mesh
/// are nodes that move on their own.
pub fn loop_contact_flags(v: &[Vec2]) -> Vec<bool> {
    let n = v.len();
    (0..n)
        .map(|i| {
            let (a, b) = (v[i] - v[(i + n - 1) % n], v[(i + 1) % n] - v[i]);
            cross(a, b) > -STRAIGHT_SINE * a.norm() * b.norm()
        })
        .collect()
}

/// Convex flags of a counter-clockwise polygon's vertices (interior angle below 180°).
pub fn convex_flags(v: &[Vec2]) -> Vec<bool> {
    let n = v.len();
    (0..n).map(|i| cross(v[i] - v[(i + n - 1) % n], v[(i + 1) % n] - v[i]) > 0.0).collect()
}

/// Which vertices of a rigid polygon make contacts (math note §5.1): the convex ones
/// ([`convex_flags`]) and the straight ones (the turn's sine within ±[`STRAIGHT_SINE`]) where
/// the two edges carry different interfaces (`tags[k - 1] != tags[k]`, e.g. a trace piece meeting
/// its cemented bridge), so that every edge piece with its own law has contacts at both ends.
/// `tags` is empty (no edge tagged: the convex flags) or holds one entry per edge.
pub fn polygon_contact_flags(v: &[Vec2], tags: &[Option<usize>]) -> Vec<bool> {
    let mut flags = convex_flags(v);
    let n = v.len();
    if tags.len() != n {
        return flags;
    }
    for (i, flag) in flags.iter_mut().enumerate() {
        let (a, b) = (v[i] - v[(i + n - 1) % n], v[(i + 1) % n] - v[i]);
        let straight = cross(a, b).abs() <= STRAIGHT_SINE * a.norm() * b.norm();
        *flag |= straight && tags[(i + n - 1) % n] != tags[i];
    }
    flags
}

/// Area moments of a polygon about its centroid (math note §2.1, Shi's simplex integration).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PolygonMoments {
    /// Signed area S (positive for counter-clockwise vertices).
    pub area: f64,
    pub centroid: Vec2,
    /// Central second moments Sxx = ∫(x-xc)², Syy = ∫(y-yc)², Sxy = ∫(x-xc)(y-yc).
    pub sxx: f64,
    pub syy: f64,
    pub sxy: f64,
}

/// Moments of the polygon `v` (math note §2.1). Evaluated about vertex 0 to avoid
/// cancellation, then shifted to the centroid.
pub fn polygon_moments(v: &[Vec2]) -> PolygonMoments {
    let o = v[0];
    let (mut s, mut sx, mut sy, mut ixx, mut iyy, mut ixy) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for i in 0..v.len() {
        let p = v[i] - o;
        let q = v[(i + 1) % v.len()] - o;
        let c = p.x * q.y - q.x * p.y;
        s += c;
        sx += (p.x + q.x) * c;
        sy += (p.y + q.y) * c;
        ixx += (p.x * p.x + p.x * q.x + q.x * q.x) * c;
        iyy += (p.y * p.y + p.y * q.y + q.y * q.y) * c;
        ixy += (p.x * q.y + 2.0 * p.x * p.y + 2.0 * q.x * q.y + q.x * p.y) * c;
    }
    let s = s / 2.0;
    let (xc, yc) = (sx / 6.0 / s, sy / 6.0 / s);
    PolygonMoments {
        area: s,
        centroid: o + Vec2::new(xc, yc),
        sxx: ixx / 12.0 - s * xc * xc,
        syy: iyy / 12.0 - s * yc * yc,
        sxy: ixy / 24.0 - s * xc * yc,
    }
}

/// Twice the signed area (positive when counter-clockwise).
pub fn signed_area2(v: &[Vec2]) -> f64 {
    (0..v.len()).map(|i| cross(v[i], v[(i + 1) % v.len()])).sum()
}

/// Proper or touching intersection of the closed segments `ab` and `cd`.
pub fn segments_intersect(a: Vec2, b: Vec2, c: Vec2, d: Vec2) -> bool {
    let o = |p: Vec2, q: Vec2, r: Vec2| cross(q - p, r - p);
    let on = |p: Vec2, q: Vec2, r: Vec2| {
        r.x >= p.x.min(q.x) && r.x <= p.x.max(q.x) && r.y >= p.y.min(q.y) && r.y <= p.y.max(q.y)
    };
    let (d1, d2, d3, d4) = (o(c, d, a), o(c, d, b), o(a, b, c), o(a, b, d));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    (d1 == 0.0 && on(c, d, a))
        || (d2 == 0.0 && on(c, d, b))
        || (d3 == 0.0 && on(a, b, c))
        || (d4 == 0.0 && on(a, b, d))
}

/// Why a polygon is unusable as a block.
#[derive(Debug, Clone, PartialEq)]
pub enum PolygonDefect {
    TooFewVertices,
    /// Two consecutive vertices coincide (edge index).
    ZeroLengthEdge(usize),
    /// Edges `i` and `j` cross or touch.
    SelfIntersection(usize, usize),
    ZeroArea,
}

/// Checks that `v` is a simple polygon with positive area (either orientation).
/// O(N log N): a Shamos–Hoey sweep looks for a crossing pair of edges (see [`sweep_crossing`]).
pub fn check_simple_polygon(v: &[Vec2]) -> Result<(), PolygonDefect> {
    let n = v.len();
    if n < 3 {
        return Err(PolygonDefect::TooFewVertices);
    }
    // tolerances relative to the polygon's own size, not to its distance from the origin
    let b = Aabb::of_points(v);
    // hypot, not norm: lengths of coordinates near 1e200 must not overflow to inf
    let length = |d: Vec2| d.x.hypot(d.y);
    let scale = length(b.max - b.min).max(1e-300);
    for i in 0..n {
        if length(v[(i + 1) % n] - v[i]) <= 1e-12 * scale {
            return Err(PolygonDefect::ZeroLengthEdge(i));
        }
    }
    if let Some((i, j)) = sweep_crossing(v) {
        return Err(PolygonDefect::SelfIntersection(i.min(j), i.max(j)));
    }
    // an area that overflows is not zero (the scene reader rejects it as out of range)
    let area = signed_area2(v).abs();
    if area.is_finite() && area <= (1e-6 * scale) * (1e-6 * scale) {
        return Err(PolygonDefect::ZeroArea);
    }
    Ok(())
}

/// Whether polygon edges `i` and `j` meet where they should not: non-adjacent edges that
/// cross or touch, or adjacent edges (sharing a vertex) that fold back onto each other.
fn edges_conflict(v: &[Vec2], i: usize, j: usize) -> bool {
    let n = v.len();
    let (i, j) = (i.min(j), i.max(j));
    let (a, b, c, d) = (v[i], v[(i + 1) % n], v[j], v[(j + 1) % n]);
    if j == i + 1 || (i == 0 && j == n - 1) {
        let (p, q, r) = if j == i + 1 { (a, b, d) } else { (b, a, c) };
        // p-q and q-r meet at q; they overlap only if r folds back along q->p
        let (u, w) = (p - q, r - q);
        cross(u, w).abs() <= 1e-12 * u.norm() * w.norm() && u.dot(&w) > 0.0
    } else {
        segments_intersect(a, b, c, d)
    }
}

/// Lexicographic (x, then y) order of points: the sweep order.
fn lex(p: Vec2, q: Vec2) -> std::cmp::Ordering {
    p.x.total_cmp(&q.x).then(p.y.total_cmp(&q.y))
}

/// An edge in the sweep's status: ordered bottom to top along the sweep line.
struct SweepEdge<'a> {
    edge: usize,
    /// (left, right) end points of every edge, lexicographically ordered.
    ends: &'a [(Vec2, Vec2)],
}

impl SweepEdge<'_> {
    /// Bottom-to-top order of two edges that both cross the sweep line and do not cross each
    /// other. The one whose left end comes later starts on or beside the other's line (which
    /// spans that x): the side of its left end, or of its right end if the left one is on the
    /// line (a shared vertex), decides. Independent of the sweep position, so `BTreeSet` works.
    fn order(&self, other: &Self) -> std::cmp::Ordering {
        use std::cmp::Ordering::*;
        if self.edge == other.edge {
            return Equal;
        }
        let (p, q) = (self.ends[self.edge], self.ends[other.edge]);
        let later_is_self = lex(p.0, q.0).then(self.edge.cmp(&other.edge)) == Greater;
        let (first, later) = if later_is_self { (q, p) } else { (p, q) };
        let side = |x: Vec2| cross(first.1 - first.0, x - first.0);
        let s = side(later.0);
        let s = if s == 0.0 { side(later.1) } else { s };
        if s == 0.0 {
            // collinear: any fixed order; an overlap is found as a conflict of neighbours
            return self.edge.cmp(&other.edge);
        }
        // later above first: later > first
        let later_vs_first = if s > 0.0 { Greater } else { Less };
        if later_is_self { later_vs_first } else { later_vs_first.reverse() }
    }
}

impl PartialEq for SweepEdge<'_> {
    fn eq(&self, other: &Self) -> bool {
        self.edge == other.edge
    }
}
impl Eq for SweepEdge<'_> {}
impl PartialOrd for SweepEdge<'_> {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for SweepEdge<'_> {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.order(other)
    }
}

/// Shamos–Hoey sweep (Shamos & Hoey 1976; the simple-polygon test of D. Sunday): a vertical
/// line sweeps the edge end points left to right; the edges it crosses are kept ordered bottom
/// to top. Until the first conflict no two of them cross, so their order never changes, and
/// a conflict first shows between two edges that are neighbours in that order when one is
/// inserted or when the edge between them is removed. O(N log N) for N edges.
/// Returns one conflicting pair (see `edges_conflict`), or None for a simple polygon.
pub fn sweep_crossing(v: &[Vec2]) -> Option<(usize, usize)> {
    use std::collections::BTreeSet;
    use std::ops::Bound::{Excluded, Unbounded};
    let n = v.len();
    let ends: Vec<(Vec2, Vec2)> = (0..n)
        .map(|i| {
            let (a, b) = (v[i], v[(i + 1) % n]);
            if lex(a, b).is_le() { (a, b) } else { (b, a) }
        })
        .collect();
    // events: (point, is_right_end, edge); at one point left ends (insertions) come first
    let mut events: Vec<(Vec2, bool, usize)> =
        (0..n).flat_map(|i| [(ends[i].0, false, i), (ends[i].1, true, i)]).collect();
    events.sort_by(|a, b| lex(a.0, b.0).then(a.1.cmp(&b.1)));
    let key = |edge| SweepEdge { edge, ends: &ends };
    let mut status: BTreeSet<SweepEdge> = BTreeSet::new();
    let conflict = |a: usize, b: usize| edges_conflict(v, a, b).then_some((a, b));
    for &(_, right, e) in &events {
        let k = key(e);
        let below = status.range(..&k).next_back().map(|s| s.edge);
        let above = status.range((Excluded(&k), Unbounded)).next().map(|s| s.edge);
        if right {
            status.remove(&k);
            if let (Some(a), Some(b)) = (below, above)
                && let Some(pair) = conflict(a, b)
            {
                return Some(pair);
            }
        } else {
            for other in [below, above].into_iter().flatten() {
                if let Some(pair) = conflict(e, other) {
                    return Some(pair);
                }
            }
            status.insert(k);
        }
    }
    None
}

/// Axis-aligned bounding box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    pub min: Vec2,
    pub max: Vec2,
}

impl Aabb {
    pub fn of_points(points: &[Vec2]) -> Aabb {
        let mut b = Aabb { min: points[0], max: points[0] };
        for p in &points[1..] {
            b.min = b.min.inf(p);
            b.max = b.max.sup(p);
        }
        b
    }
    pub fn of_circle(c: Vec2, r: f64) -> Aabb {
        Aabb { min: c - Vec2::new(r, r), max: c + Vec2::new(r, r) }
    }
    pub fn inflated(self, m: f64) -> Aabb {
        Aabb { min: self.min - Vec2::new(m, m), max: self.max + Vec2::new(m, m) }
    }
    pub fn overlaps(&self, o: &Aabb) -> bool {
        self.min.x <= o.max.x && o.min.x <= self.max.x && self.min.y <= o.max.y && o.min.y <= self.max.y
    }
    /// Whether `o` lies inside this box (boundary included).
    pub fn contains(&self, o: &Aabb) -> bool {
        self.min.x <= o.min.x && self.min.y <= o.min.y && o.max.x <= self.max.x && o.max.y <= self.max.y
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// L-shape: 2x2 square minus its 1x1 upper-right quarter, CCW (also used by body.rs).
    pub(crate) fn l_shape() -> Vec<Vec2> {
        [(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)]
            .iter()
            .map(|&(x, y)| Vec2::new(x, y))
            .collect()
    }

    /// Exact moments of the L-shape from the decomposition into a 2x1 rectangle [0,2]x[0,1]
    /// and a 1x1 square [0,1]x[1,2]: area 3, centroid (5/6, 5/6),
    /// ∫x² = 8/3 + 1/3 = 3, ∫xy = 1 + 3/4 = 7/4; central: Sxx = 3 - 3(5/6)², Sxy = 7/4 - 3(5/6)².
    #[test]
    fn l_shape_moments_are_exact() {
        let m = polygon_moments(&l_shape());
        let c = 5.0 / 6.0;
        assert!((m.area - 3.0).abs() < 1e-14);
        assert!((m.centroid - Vec2::new(c, c)).norm() < 1e-14);
        assert!((m.sxx - (3.0 - 3.0 * c * c)).abs() < 1e-14);
        assert!((m.syy - (3.0 - 3.0 * c * c)).abs() < 1e-14);
        assert!((m.sxy - (7.0 / 4.0 - 3.0 * c * c)).abs() < 1e-14);
    }

    /// Translation invariance: moving the L-shape far away changes only the centroid.
    /// Tolerance: cancellation at |x| = 1e6 costs ~1e6 * eps relative to the moments' scale.
    #[test]
    fn moments_are_translation_invariant() {
        let m0 = polygon_moments(&l_shape());
        let shifted: Vec<Vec2> = l_shape().iter().map(|p| p + Vec2::new(1e6, -2e6)).collect();
        let m1 = polygon_moments(&shifted);
        assert!((m1.area - m0.area).abs() < 1e-9);
        assert!((m1.sxx - m0.sxx).abs() < 1e-9 && (m1.syy - m0.syy).abs() < 1e-9);
        assert!((m1.sxy - m0.sxy).abs() < 1e-9);
        assert!((m1.centroid - m0.centroid - Vec2::new(1e6, -2e6)).norm() < 1e-8);
    }

    #[test]
    fn clockwise_polygon_has_negative_area() {
        let mut v = l_shape();
        v.reverse();
        assert!((polygon_moments(&v).area + 3.0).abs() < 1e-14);
    }

    /// The O(N²) all-pairs test that the sweep replaces: the oracle of the property test.
    fn brute_crossing(v: &[Vec2]) -> Option<(usize, usize)> {
        let n = v.len();
        (0..n).flat_map(|i| (i + 1..n).map(move |j| (i, j))).find(|&(i, j)| edges_conflict(v, i, j))
    }

    /// The sweep and the all-pairs test agree on whether a polygon is simple: random polygons
    /// with 3-12 vertices on a small integer grid (many collinear and touching cases, where
    /// orientation tests are exact) and on the unit square in floating point.
    #[test]
    fn sweep_agrees_with_all_pairs() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        for trial in 0..20_000 {
            let n = 3 + (next() % 10) as usize;
            let grid = trial % 2 == 0;
            let v: Vec<Vec2> = (0..n)
                .map(|_| {
                    let (a, b) = (next(), next());
                    if grid {
                        Vec2::new((a % 5) as f64, (b % 5) as f64)
                    } else {
                        Vec2::new(
                            (a >> 11) as f64 / (1u64 << 53) as f64,
                            (b >> 11) as f64 / (1u64 << 53) as f64,
                        )
                    }
                })
                .collect();
            if (0..n).any(|i| v[i] == v[(i + 1) % n]) {
                continue;
            }
            let (fast, slow) = (sweep_crossing(&v), brute_crossing(&v));
            assert_eq!(fast.is_some(), slow.is_some(), "polygon {v:?}: sweep {fast:?}, all pairs {slow:?}");
            if let Some((i, j)) = fast {
                assert!(edges_conflict(&v, i, j));
            }
        }
    }

    /// A convex 200k-gon (a circle) is simple; denting one vertex across the far side makes
    /// two edges cross, which the sweep finds (the all-pairs test would take 2·10¹⁰ tests).
    #[test]
    fn sweep_handles_large_polygons() {
        let n = 200_000;
        let mut v: Vec<Vec2> = (0..n)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / n as f64;
                Vec2::new(a.cos(), a.sin())
            })
            .collect();
        assert_eq!(check_simple_polygon(&v), Ok(()));
        v[10] = Vec2::new(-2.0, 0.0);
        assert!(matches!(check_simple_polygon(&v), Err(PolygonDefect::SelfIntersection(..))));
    }

    #[test]
    fn simplicity_checks() {
        assert!(check_simple_polygon(&l_shape()).is_ok());
        let bow: Vec<Vec2> =
            [(0., 0.), (1., 1.), (1., 0.), (0., 1.)].iter().map(|&(x, y)| Vec2::new(x, y)).collect();
        assert!(matches!(check_simple_polygon(&bow), Err(PolygonDefect::SelfIntersection(..))));
        let flat: Vec<Vec2> = [(0., 0.), (1., 0.), (2., 0.)].iter().map(|&(x, y)| Vec2::new(x, y)).collect();
        assert!(check_simple_polygon(&flat).is_err());
        let dup: Vec<Vec2> =
            [(0., 0.), (1., 0.), (1., 0.), (0., 1.)].iter().map(|&(x, y)| Vec2::new(x, y)).collect();
        assert_eq!(check_simple_polygon(&dup), Err(PolygonDefect::ZeroLengthEdge(1)));
    }
}
