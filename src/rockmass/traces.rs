//! Trace placement and the random deviations (math note §12.1, §12.2).

use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{Rng, SeedableRng};

use super::estimate::Checked;
use super::{Bridges, CutError, CutSpec, EdgeSource, JointSet, clip};

/// A straight piece to cut along.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Segment {
    pub a: [f64; 2],
    pub b: [f64; 2],
    pub source: EdgeSource,
}

/// A uniform number in [0, 1) from the top 53 bits of the next `u64` (math note §12.2).
fn uniform(rng: &mut ChaCha8Rng) -> f64 {
    (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// `value` plus a uniform deviation in [-dev, dev).
fn deviate(rng: &mut ChaCha8Rng, value: f64, dev: f64) -> f64 {
    value + dev * (2.0 * uniform(rng) - 1.0)
}

/// Every trace, bridge and joint piece inside the domain.
pub(crate) fn segments(spec: &CutSpec, checked: &Checked) -> Result<Vec<Segment>, CutError> {
    let mut out = Vec::new();
    for (index, joint) in spec.joints.iter().enumerate() {
        let before = out.len();
        for (k, w) in joint.points.windows(2).enumerate() {
            let last = joint.points.len() - 2;
            let pieces = on_line(w[0], w[1], checked, &[[0.0, 1.0, 0.0]], (k == 0, k == last));
            push(&mut out, pieces, |_| EdgeSource::Joint(index));
        }
        if out.len() == before {
            let message = "the joint lies outside the domain".to_owned();
            return Err(CutError::Joint { joint: index, message });
        }
    }
    for (index, set) in spec.joint_sets.iter().enumerate() {
        let before = out.len();
        set_segments(spec.seed, index, set, checked, &mut out);
        if out.len() == before {
            let message = "no trace of the set lies inside the domain".to_owned();
            return Err(CutError::Set { set: index, message });
        }
    }
    Ok(out)
}

fn push(out: &mut Vec<Segment>, pieces: Vec<([f64; 2], [f64; 2], f64)>, source: impl Fn(f64) -> EdgeSource) {
    out.extend(pieces.into_iter().map(|(a, b, kind)| Segment { a, b, source: source(kind) }));
}

/// The pieces of the line `p + s (q - p)` inside the domain, for pattern intervals
/// `[s0, s1, kind]` (s in units of |q - p|). A piece's end is pushed `reach` outwards unless
/// it is the start or end of the pattern's neighbour (math note §12.1), or, with
/// `closed = (start, end)` false, the pattern's own first start or last end.
fn on_line(
    p: [f64; 2],
    q: [f64; 2],
    checked: &Checked,
    pattern: &[[f64; 3]],
    ends: (bool, bool),
) -> Vec<([f64; 2], [f64; 2], f64)> {
    let d = [q[0] - p[0], q[1] - p[1]];
    let length = d[0].hypot(d[1]);
    if length == 0.0 || pattern.is_empty() {
        return Vec::new();
    }
    // p and q themselves at s = 0 and 1: a polyline's segments share their points exactly
    let at = |s: f64| {
        if s == 0.0 {
            p
        } else if s == 1.0 {
            q
        } else {
            [p[0] + s * d[0], p[1] + s * d[1]]
        }
    };
    let lo = pattern.iter().map(|x| x[0]).fold(f64::INFINITY, f64::min);
    let hi = pattern.iter().map(|x| x[1]).fold(f64::NEG_INFINITY, f64::max);
    let inside: Vec<[f64; 2]> = clip::clip(at(lo), at(hi), &checked.domain)
        .into_iter()
        .map(|w| [lo + w[0] * (hi - lo), lo + w[1] * (hi - lo)])
        .collect();
    let e = checked.reach / length;
    let mut out = Vec::new();
    for (k, piece) in pattern.iter().enumerate() {
        let joined_before = k > 0 && pattern[k - 1][1] == piece[0];
        let joined_after = k + 1 < pattern.len() && pattern[k + 1][0] == piece[1];
        for w in &inside {
            let (s0, s1) = (piece[0].max(w[0]), piece[1].min(w[1]));
            if s1 <= s0 {
                continue;
            }
            // inner joints of a polyline are shared points: no reach there
            let open_start = !(k == 0 && s0 == 0.0 && !ends.0);
            let open_end = !(k + 1 == pattern.len() && s1 == 1.0 && !ends.1);
            let a = if joined_before && s0 == piece[0] || !open_start { s0 } else { s0 - e };
            let b = if joined_after && s1 == piece[1] || !open_end { s1 } else { s1 + e };
            out.push((at(a), at(b), piece[2]));
        }
    }
    out
}

/// The traces of one set (math note §12.1), drawing deviations in the order of §12.2.
fn set_segments(seed: u64, index: usize, set: &JointSet, checked: &Checked, out: &mut Vec<Segment>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(index as u64);
    let t = clip::direction(set.angle);
    let n = [-t[1], t[0]];
    let o = set.origin;
    let (mut dmin, mut dmax) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in &checked.domain {
        let d = n[0] * (p[0] - o[0]) + n[1] * (p[1] - o[1]);
        dmin = dmin.min(d);
        dmax = dmax.max(d);
    }
    // line 0 through the origin, then the lines above it, then those below
    let angle = deviate(&mut rng, set.angle, set.angle_dev);
    one_line(&mut rng, index, set, checked, o, angle, out);
    for dir in [1.0, -1.0] {
        let mut c = 0.0;
        loop {
            c += dir * deviate(&mut rng, set.spacing, set.spacing_dev);
            if c > dmax || c < dmin {
                break;
            }
            let angle = deviate(&mut rng, set.angle, set.angle_dev);
            one_line(&mut rng, index, set, checked, [o[0] + c * n[0], o[1] + c * n[1]], angle, out);
        }
    }
}

/// One line of a set through `point` at `angle` [deg]: its trace pieces (and bridges), drawn
/// forwards from the foot of the set's origin on the line, then backwards (math note §12.2).
fn one_line(
    rng: &mut ChaCha8Rng,
    index: usize,
    set: &JointSet,
    checked: &Checked,
    point: [f64; 2],
    angle: f64,
    out: &mut Vec<Segment>,
) {
    let t = clip::direction(angle);
    let o = set.origin;
    let along = t[0] * (o[0] - point[0]) + t[1] * (o[1] - point[1]);
    let foot = [point[0] + along * t[0], point[1] + along * t[1]];
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for x in [checked.lo[0], checked.hi[0]] {
        for y in [checked.lo[1], checked.hi[1]] {
            let s = t[0] * (x - foot[0]) + t[1] * (y - foot[1]);
            lo = lo.min(s);
            hi = hi.max(s);
        }
    }
    let q = [foot[0] + t[0], foot[1] + t[1]];
    let source = |kind: f64| if kind == 0.0 { EdgeSource::Set(index) } else { EdgeSource::Bridge(index) };
    if set.trace == 0.0 {
        let pieces = on_line(foot, q, checked, &[[lo, hi, 0.0]], (true, true));
        push(out, pieces, source);
        return;
    }
    let cemented = set.bridges == Bridges::Cemented;
    let mut pattern = Vec::new();
    let mut s = 0.0;
    while s <= hi {
        let trace = deviate(rng, set.trace, set.trace_dev);
        let gap = deviate(rng, set.gap, set.gap_dev);
        pattern.push([s, s + trace, 0.0]);
        if cemented && gap > 0.0 {
            pattern.push([s + trace, s + trace + gap, 1.0]);
        }
        s += trace + gap;
    }
    let mut back = Vec::new();
    let mut s = 0.0;
    while s >= lo {
        let gap = deviate(rng, set.gap, set.gap_dev);
        let trace = deviate(rng, set.trace, set.trace_dev);
        if cemented && gap > 0.0 {
            back.push([s - gap, s, 1.0]);
        }
        back.push([s - gap - trace, s - gap, 0.0]);
        s -= trace + gap;
    }
    back.reverse();
    back.extend(pattern);
    back.retain(|p| p[1] > lo && p[0] < hi);
    let pieces = on_line(foot, q, checked, &back, (true, true));
    push(out, pieces, source);
}
