//! Shapes, assertions and random-shape helpers shared by the contact tests.

use super::narrow::pair_contacts;
use super::{BodyShape, ContactGeom, ContactKey, ContactKind, Feature};
use crate::geometry::{Vec2, cross, segments_intersect};

/// Polygon from CCW vertices, with `convex` computed from the turn at each vertex.
pub fn polygon(pts: &[(f64, f64)]) -> BodyShape {
    polygon_of(pts.iter().map(|&(x, y)| Vec2::new(x, y)).collect())
}

/// Polygon from CCW vertices, with `convex` computed from the turn at each vertex.
pub fn polygon_of(vertices: Vec<Vec2>) -> BodyShape {
    let n = vertices.len();
    let turn = |k: usize| {
        let (p, v, q) = (vertices[(k + n - 1) % n], vertices[k], vertices[(k + 1) % n]);
        cross(v - p, q - v)
    };
    let convex = (0..n).map(|k| turn(k) > 0.0).collect();
    BodyShape::Polygon { vertices, convex, nodes: false, holes: Vec::new() }
}

/// Axis-aligned rectangle [x0,x1]×[y0,y1], CCW from (x0,y0).
pub fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> BodyShape {
    polygon(&[(x0, y0), (x1, y0), (x1, y1), (x0, y1)])
}

pub fn disk(x: f64, y: f64, radius: f64) -> BodyShape {
    BodyShape::Disk { center: Vec2::new(x, y), radius }
}

pub fn ring(x: f64, y: f64, outer: f64, inner: f64) -> BodyShape {
    BodyShape::Ring { center: Vec2::new(x, y), outer, inner }
}

/// The contacts of one pair, sorted by key.
pub fn contacts(i: usize, j: usize, si: &BodyShape, sj: &BodyShape, d0: f64) -> Vec<ContactGeom> {
    let mut out = Vec::new();
    pair_contacts(i, j, si, sj, d0, &mut out);
    out.sort_by_key(|c| c.key);
    out
}

/// Asserts a, b, key, n, g0 and point of one contact. `tol` absorbs the rounding of
/// the closed-form values (a few ulp of the coordinates).
#[allow(clippy::too_many_arguments)]
pub fn check(
    c: &ContactGeom,
    key: ContactKey,
    kind: ContactKind,
    n: (f64, f64),
    g0: f64,
    p: (f64, f64),
    tol: f64,
) {
    assert_eq!(c.key, key, "{c:?}");
    assert_eq!((c.a, c.b), (key.a as usize, key.b as usize));
    assert_eq!(c.kind, kind);
    assert!((c.normal - Vec2::new(n.0, n.1)).norm() < tol, "normal {c:?}");
    assert!((c.g0 - g0).abs() < tol, "g0 {} vs {g0}", c.g0);
    assert!((c.point - Vec2::new(p.0, p.1)).norm() < tol, "point {c:?}");
}

pub fn key(a: u32, fa: Feature, b: u32, fb: Feature) -> ContactKey {
    ContactKey { a, fa, b, fb }
}

/// Convex polygon with vertices on the circle (c, r), the angular gaps proportional to
/// `gaps`, starting after angle `turn`. It contains c if every gap is below half the total.
pub fn convex(c: Vec2, r: f64, turn: f64, gaps: &[f64]) -> Vec<Vec2> {
    let total: f64 = gaps.iter().sum();
    let mut a = turn;
    gaps.iter()
        .map(|g| {
            a += std::f64::consts::TAU * g / total;
            c + r * Vec2::new(a.cos(), a.sin())
        })
        .collect()
}

/// An L-shape with arms a × t and t × b, the origin inside its corner square, turned by
/// `turn`. Its notch corner (vertex 3) is reflex.
pub fn l_shape(a: f64, b: f64, t: f64, turn: f64) -> Vec<Vec2> {
    let (s, c) = turn.sin_cos();
    let h = 0.5 * t;
    [(0., 0.), (a, 0.), (a, t), (t, t), (t, b), (0., b)]
        .iter()
        .map(|&(x, y)| Vec2::new(c * (x - h) - s * (y - h), s * (x - h) + c * (y - h)))
        .collect()
}

pub fn point_segment(v: Vec2, a: Vec2, b: Vec2) -> f64 {
    let t = ((v - a).dot(&(b - a)) / (b - a).norm_squared()).clamp(0.0, 1.0);
    (v - (a + t * (b - a))).norm()
}

/// Even-odd point-in-polygon test.
pub fn inside(v: Vec2, p: &[Vec2]) -> bool {
    let mut odd = false;
    for k in 0..p.len() {
        let (a, b) = (p[k], p[(k + 1) % p.len()]);
        if (a.y > v.y) != (b.y > v.y) && v.x < a.x + (v.y - a.y) / (b.y - a.y) * (b.x - a.x) {
            odd = !odd;
        }
    }
    odd
}

fn edges(p: &[Vec2]) -> Vec<(Vec2, Vec2)> {
    (0..p.len()).map(|k| (p[k], p[(k + 1) % p.len()])).collect()
}

/// Distance from point `v` to the boundary of polygon `p`, 0 if `v` is inside.
pub fn point_polygon(v: Vec2, p: &[Vec2]) -> f64 {
    if inside(v, p) {
        return 0.0;
    }
    edges(p).iter().map(|s| point_segment(v, s.0, s.1)).fold(f64::INFINITY, f64::min)
}

/// Distance between two simple polygons (0 if they intersect).
pub fn polygon_distance(p: &[Vec2], q: &[Vec2]) -> f64 {
    let (ep, eq) = (edges(p), edges(q));
    let crossing = ep.iter().any(|a| eq.iter().any(|b| segments_intersect(a.0, a.1, b.0, b.1)));
    if crossing || inside(p[0], q) || inside(q[0], p) {
        return 0.0;
    }
    let one_way = |p: &[Vec2], e: &[(Vec2, Vec2)]| {
        p.iter()
            .flat_map(|&v| e.iter().map(move |s| point_segment(v, s.0, s.1)))
            .fold(f64::INFINITY, f64::min)
    };
    one_way(p, &eq).min(one_way(q, &ep))
}

/// The smallest found t in (0, 10] with `dist(t) >= d`, by bisection from `dist(0) < d`:
/// a body moved from an overlapping start along a ray until it is `d` away.
pub fn bisect(dist: impl Fn(f64) -> f64, d: f64) -> f64 {
    assert!(dist(0.0) < d, "the start must overlap");
    let (mut lo, mut hi) = (0.0, 10.0);
    for _ in 0..80 {
        let t = 0.5 * (lo + hi);
        if dist(t) < d { lo = t } else { hi = t }
    }
    hi
}
