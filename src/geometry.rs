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
/// O(N²) in the number of vertices, which is fine for block outlines.
pub fn check_simple_polygon(v: &[Vec2]) -> Result<(), PolygonDefect> {
    let n = v.len();
    if n < 3 {
        return Err(PolygonDefect::TooFewVertices);
    }
    // tolerances relative to the polygon's own size, not to its distance from the origin
    let b = Aabb::of_points(v);
    let scale = (b.max - b.min).norm().max(1e-300);
    for i in 0..n {
        if (v[(i + 1) % n] - v[i]).norm() <= 1e-12 * scale {
            return Err(PolygonDefect::ZeroLengthEdge(i));
        }
    }
    for i in 0..n {
        for j in i + 1..n {
            // adjacent edges share a vertex; only test them for overlap (collinear fold-back)
            let adjacent = j == i + 1 || (i == 0 && j == n - 1);
            let (a, b, c, d) = (v[i], v[(i + 1) % n], v[j], v[(j + 1) % n]);
            if adjacent {
                let (p, q, r) = if j == i + 1 { (a, b, d) } else { (b, a, c) };
                // p-q and q-r meet at q; they overlap only if r folds back along q->p
                let u = p - q;
                let w = r - q;
                if cross(u, w).abs() <= 1e-12 * u.norm() * w.norm() && u.dot(&w) > 0.0 {
                    return Err(PolygonDefect::SelfIntersection(i, j));
                }
            } else if segments_intersect(a, b, c, d) {
                return Err(PolygonDefect::SelfIntersection(i, j));
            }
        }
    }
    if signed_area2(v).abs() <= 1e-12 * scale * scale {
        return Err(PolygonDefect::ZeroArea);
    }
    Ok(())
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
