//! Input checks and the block-count estimate made before cutting (math note §12.1).

use super::{CutError, CutSpec, JointSet};
use crate::geometry::{PolygonDefect, Vec2, check_simple_polygon, signed_area2};

/// Coordinates beyond this are refused: far below the range where spade's predicates and the
/// squared lengths of the checks lose their meaning.
const MAX_COORDINATE: f64 = 1e12;

/// The validated, normalised input.
#[derive(Debug, Clone)]
pub(crate) struct Checked {
    /// The domain outline, counter-clockwise.
    pub domain: Vec<[f64; 2]>,
    /// Excavation outlines, counter-clockwise.
    pub excavations: Vec<Vec<[f64; 2]>>,
    /// Bounding box of the domain: min, max.
    pub lo: [f64; 2],
    pub hi: [f64; 2],
    /// Diagonal of the domain's bounding box.
    pub scale: f64,
    /// Vertices closer than this are merged: max(min_edge, 1e-9 scale) (math note §12.3).
    pub merge: f64,
    /// Every trace and joint piece reaches this far past its ends, so that pieces meant to
    /// end on another line cross it (1e-9 scale).
    pub reach: f64,
}

fn finite(p: &[f64; 2]) -> bool {
    p.iter().all(|c| c.is_finite() && c.abs() <= MAX_COORDINATE)
}

fn v2(p: &[f64; 2]) -> Vec2 {
    Vec2::new(p[0], p[1])
}

/// A simple polygon, returned counter-clockwise; `Err` says what is wrong.
pub(crate) fn ccw_polygon(v: &[[f64; 2]]) -> Result<Vec<[f64; 2]>, String> {
    if let Some(k) = v.iter().position(|p| !finite(p)) {
        return Err(format!(
            "vertices[{k}] = ({}, {}) is not a finite coordinate within +-{MAX_COORDINATE:e}",
            v[k][0], v[k][1]
        ));
    }
    let pts: Vec<Vec2> = v.iter().map(v2).collect();
    let edge = |i: usize| format!("vertices[{i}]-vertices[{}]", (i + 1) % v.len());
    match check_simple_polygon(&pts) {
        Ok(()) => {}
        Err(PolygonDefect::TooFewVertices) => {
            return Err(format!("a polygon needs at least 3 vertices (got {})", v.len()));
        }
        Err(PolygonDefect::ZeroLengthEdge(i)) => return Err(format!("zero-length edge {}", edge(i))),
        Err(PolygonDefect::SelfIntersection(i, j)) => {
            return Err(format!("the outline intersects itself: edge {} meets edge {}", edge(i), edge(j)));
        }
        Err(PolygonDefect::ZeroArea) => return Err("the outline has zero area".into()),
    }
    let mut out = v.to_vec();
    if signed_area2(&pts) < 0.0 {
        out.reverse();
    }
    Ok(out)
}

/// Checks every input and estimates the block count (math note §12.1).
pub(crate) fn check(spec: &CutSpec) -> Result<Checked, CutError> {
    let domain = ccw_polygon(&spec.domain).map_err(CutError::Domain)?;
    if !spec.min_edge.is_finite() || spec.min_edge < 0.0 {
        return Err(CutError::MinEdge(spec.min_edge));
    }
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in &domain {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let scale = (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
    let reach = 1e-9 * scale;
    let merge = spec.min_edge.max(reach);
    long_edges(&spec.domain, merge).map_err(CutError::Domain)?;
    for (set, s) in spec.joint_sets.iter().enumerate() {
        check_set(s).map_err(|message| CutError::Set { set, message })?;
    }
    for (joint, j) in spec.joints.iter().enumerate() {
        let fail = |message: String| CutError::Joint { joint, message };
        if j.points.len() < 2 {
            return Err(fail(format!("a joint needs at least 2 points (got {})", j.points.len())));
        }
        if let Some(k) = j.points.iter().position(|p| !finite(p)) {
            return Err(fail(format!("points[{k}] is not a finite coordinate within +-{MAX_COORDINATE:e}")));
        }
    }
    let mut excavations = Vec::new();
    for (excavation, e) in spec.excavations.iter().enumerate() {
        let fail = |message: String| CutError::Excavation { excavation, message };
        let outline = ccw_polygon(&e.vertices).map_err(fail)?;
        long_edges(&e.vertices, merge).map_err(fail)?;
        if super::clip::polygons_disjoint(&domain, &outline) {
            return Err(fail("the excavation lies outside the domain".into()));
        }
        excavations.push(outline);
    }
    estimate_blocks(spec, &domain)?;
    Ok(Checked { domain, excavations, lo, hi, scale, merge, reach })
}

/// An outline (the domain's or an excavation's, as given) whose every edge is at least the
/// merge distance long (math note §12.8): the ends of a shorter edge would merge, and a polygon
/// of such edges would shrink or vanish.
fn long_edges(v: &[[f64; 2]], merge: f64) -> Result<(), String> {
    for i in 0..v.len() {
        let (p, q) = (v[i], v[(i + 1) % v.len()]);
        let length = (q[0] - p[0]).hypot(q[1] - p[1]);
        if length < merge {
            return Err(format!(
                "edge vertices[{i}]-vertices[{}] is {length:.3e} m long, shorter than the merge \
                 distance {merge:.3e} m (max(min_edge, 1e-9 D)); lower min_edge or use fewer vertices",
                (i + 1) % v.len()
            ));
        }
    }
    Ok(())
}

fn check_set(s: &JointSet) -> Result<(), String> {
    let named = [
        ("angle", s.angle),
        ("spacing", s.spacing),
        ("origin[0]", s.origin[0]),
        ("origin[1]", s.origin[1]),
        ("trace", s.trace),
        ("gap", s.gap),
        ("angle_dev", s.angle_dev),
        ("spacing_dev", s.spacing_dev),
        ("trace_dev", s.trace_dev),
        ("gap_dev", s.gap_dev),
    ];
    for (key, value) in named {
        if !value.is_finite() || value.abs() > MAX_COORDINATE {
            return Err(format!("{key} must be a finite number within +-{MAX_COORDINATE:e} (got {value})"));
        }
        if key != "angle" && !key.starts_with("origin") && value < 0.0 {
            return Err(format!("{key} must not be negative (got {value})"));
        }
    }
    if s.spacing <= 0.0 {
        return Err(format!("spacing must be positive (got {})", s.spacing));
    }
    if s.spacing_dev >= s.spacing {
        return Err(format!(
            "spacing_dev must be less than spacing (got {} >= {})",
            s.spacing_dev, s.spacing
        ));
    }
    if s.angle_dev >= 90.0 {
        return Err(format!("angle_dev must be less than 90 degrees (got {})", s.angle_dev));
    }
    if s.trace > 0.0 && s.trace_dev >= s.trace {
        return Err(format!("trace_dev must be less than trace (got {} >= {})", s.trace_dev, s.trace));
    }
    if s.gap_dev > s.gap {
        return Err(format!("gap_dev must not exceed gap (got {} > {})", s.gap_dev, s.gap));
    }
    Ok(())
}

/// Number of lines of a set across the domain: its width across the traces over the smallest
/// spacing, plus one.
fn line_count(s: &JointSet, domain: &[[f64; 2]]) -> f64 {
    let t = super::clip::direction(s.angle);
    let n = [-t[1], t[0]];
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in domain {
        let d = n[0] * p[0] + n[1] * p[1];
        lo = lo.min(d);
        hi = hi.max(d);
    }
    ((hi - lo) / (s.spacing - s.spacing_dev)).floor() + 1.0
}

/// The estimate of math note §12.1: 1 + sum n_i + sum_{i<j} n_i n_j, as if every set were
/// persistent; and, for non-persistent sets, the number of trace pieces, which must not pass
/// four times the limit either.
fn estimate_blocks(spec: &CutSpec, domain: &[[f64; 2]]) -> Result<(), CutError> {
    let n: Vec<f64> = spec.joint_sets.iter().map(|s| line_count(s, domain)).collect();
    let limit = spec.block_limit as f64;
    let (mut sum, mut pairs) = (0.0, 0.0);
    for (i, &ni) in n.iter().enumerate() {
        pairs += ni * sum;
        sum += ni;
        let estimate = 1.0 + sum + pairs;
        if estimate > limit {
            // name the set of most lines among those so far
            let set = (0..=i).max_by(|&a, &b| n[a].total_cmp(&n[b])).unwrap_or(i);
            let spacing = spec.joint_sets[set].spacing;
            return Err(CutError::TooManyBlocks { set, spacing, estimate, limit: spec.block_limit });
        }
    }
    let (lo, hi) = domain.iter().fold(([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]), |(l, h), p| {
        ([l[0].min(p[0]), l[1].min(p[1])], [h[0].max(p[0]), h[1].max(p[1])])
    });
    let diagonal = (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
    for (set, s) in spec.joint_sets.iter().enumerate() {
        if s.trace > 0.0 {
            let period = (s.trace - s.trace_dev) + (s.gap - s.gap_dev);
            // the pattern is drawn from the foot of the origin on each line to the far side
            let gap_x = (lo[0] - s.origin[0]).max(s.origin[0] - hi[0]).max(0.0);
            let gap_y = (lo[1] - s.origin[1]).max(s.origin[1] - hi[1]).max(0.0);
            let length = diagonal + 2.0 * gap_x.hypot(gap_y);
            let pieces = n[set] * ((length / period).floor() + 2.0);
            if pieces.is_nan() || pieces > 4.0 * limit {
                return Err(CutError::Set {
                    set,
                    message: format!(
                        "trace {} m and gap {} m would make about {pieces:.3e} trace pieces, above \
                         four times the block limit {}",
                        s.trace, s.gap, spec.block_limit
                    ),
                });
            }
        }
    }
    Ok(())
}
