//! Clipping of lines to the domain, point-in-polygon tests.

use crate::geometry::{Vec2, segments_intersect};

fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

/// Whether `p` lies inside `poly` (crossing number; a point on the outline may go either way).
pub(crate) fn inside(p: [f64; 2], poly: &[[f64; 2]]) -> bool {
    let mut c = false;
    let n = poly.len();
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if p[0] < x {
                c = !c;
            }
        }
    }
    c
}

/// The parts of segment `a`-`b` inside `poly`, as parameter intervals `[t0, t1]` of
/// `a + t (b - a)`, in increasing order.
pub(crate) fn clip(a: [f64; 2], b: [f64; 2], poly: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let d = sub(b, a);
    let dd = d[0] * d[0] + d[1] * d[1];
    let mut ts = vec![0.0, 1.0];
    let n = poly.len();
    for i in 0..n {
        let (c, e) = (poly[i], poly[(i + 1) % n]);
        let f = sub(e, c);
        let denom = cross(d, f);
        let ca = sub(c, a);
        if denom != 0.0 {
            let t = cross(ca, f) / denom;
            let u = cross(ca, d) / denom;
            if (0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u) {
                ts.push(t);
            }
        } else if cross(ca, d) == 0.0 && dd > 0.0 {
            // collinear: the edge's ends split the segment
            for q in [c, e] {
                let t = (sub(q, a)[0] * d[0] + sub(q, a)[1] * d[1]) / dd;
                if (0.0..=1.0).contains(&t) {
                    ts.push(t);
                }
            }
        }
    }
    ts.sort_by(f64::total_cmp);
    let mut out: Vec<[f64; 2]> = Vec::new();
    for w in ts.windows(2) {
        if w[1] <= w[0] {
            continue;
        }
        let t = 0.5 * (w[0] + w[1]);
        if inside([a[0] + t * d[0], a[1] + t * d[1]], poly) {
            match out.last_mut() {
                Some(last) if last[1] == w[0] => last[1] = w[1],
                _ => out.push([w[0], w[1]]),
            }
        }
    }
    out
}

/// Whether two simple polygons have no point in common.
pub(crate) fn polygons_disjoint(p: &[[f64; 2]], q: &[[f64; 2]]) -> bool {
    let v = |a: [f64; 2]| Vec2::new(a[0], a[1]);
    for i in 0..p.len() {
        let (a, b) = (v(p[i]), v(p[(i + 1) % p.len()]));
        for j in 0..q.len() {
            if segments_intersect(a, b, v(q[j]), v(q[(j + 1) % q.len()])) {
                return false;
            }
        }
    }
    !inside(p[0], q) && !inside(q[0], p)
}

/// (cos, sin) of an angle in degrees, exact at multiples of 90 degrees (so that axis-aligned
/// sets give exactly axis-aligned traces).
pub(crate) fn direction(deg: f64) -> [f64; 2] {
    let r = deg.rem_euclid(360.0);
    if r == 0.0 {
        [1.0, 0.0]
    } else if r == 90.0 {
        [0.0, 1.0]
    } else if r == 180.0 {
        [-1.0, 0.0]
    } else if r == 270.0 {
        [0.0, -1.0]
    } else {
        let (s, c) = deg.to_radians().sin_cos();
        [c, s]
    }
}
