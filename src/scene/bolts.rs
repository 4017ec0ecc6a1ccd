//! Bolts as rock engineers place them (scene-format "Bolts in a rock mass"):
//! `[[bolt_pattern]]` expands into bolts `NAME-1`, `NAME-2`, ... along an excavation's
//! boundary, and a `grouted = true` bolt is split at every polygon edge it crosses into
//! segments `NAME.1`, `NAME.2`, ..., each a bolt between the two bodies it joins (ntdda's
//! `produce_boltsegments`). Runs on the raw scene after the rock-mass expansion, so that the
//! segments' bodies are the blocks.

use std::ops::Range;

use toml::Spanned;

use super::check::{Check, fail, non_negative, numbers, positive};
use super::raw;
use crate::geometry::Vec2;
use crate::model::Shape;

fn at<T>(span: &Range<usize>, value: T) -> Spanned<T> {
    Spanned::new(span.clone(), value)
}

/// An excavation's outline (counter-clockwise) by name, for the patterns.
pub(super) type Outlines = Vec<(String, Vec<Vec2>)>;

/// Expands the bolt patterns (appended to the connectors) and splits the grouted bolts in place.
/// Returns the names of the connectors made.
pub(super) fn expand(raw: &mut raw::Scene, outlines: &Outlines) -> Check<Vec<String>> {
    let mut made = Vec::new();
    let mut patterns = Vec::new();
    for p in &raw.bolt_pattern {
        patterns.extend(pattern(p, outlines)?);
    }
    let first_pattern = raw.connector.len();
    raw.connector.extend(patterns);
    let polygons = polygons(raw);
    let connectors = std::mem::take(&mut raw.connector);
    for (i, c) in connectors.into_iter().enumerate() {
        let grouted = c.get_ref().grouted.as_ref().is_some_and(|g| *g.get_ref());
        let c = if i >= first_pattern && !grouted { held_outside(c, &polygons) } else { c };
        if !grouted {
            if c.get_ref().name.as_ref().is_some_and(|n| n.get_ref().contains('-'))
                && !raw.bolt_pattern.is_empty()
            {
                made.push(c.get_ref().name.as_ref().map_or(String::new(), |n| n.get_ref().clone()));
            }
            raw.connector.push(c);
            continue;
        }
        let mut segments = split(i, c, &polygons)?;
        if i >= first_pattern && segments.len() == 1 && segments[0].get_ref().bodies.is_none() {
            // a grouted pattern bolt that crosses no block edge comes back whole
            segments = segments.into_iter().map(|s| held_outside(s, &polygons)).collect();
        }
        made.extend(segments.iter().filter_map(|s| s.get_ref().name.as_ref().map(|n| n.get_ref().clone())));
        raw.connector.extend(segments);
    }
    Ok(made)
}

/// Every polygon body of the raw scene (those whose vertices read), with its name.
fn polygons(raw: &raw::Scene) -> Vec<(String, Shape)> {
    let polygon = |b: &raw::Body| {
        let v = b.vertices.as_ref()?.get_ref();
        let vertices: Option<Vec<Vec2>> =
            v.iter().map(|p| (p.len() == 2).then(|| Vec2::new(p[0], p[1]))).collect();
        Some((b.name.get_ref().clone(), Shape::Polygon { vertices: vertices? }))
    };
    raw.body.get_ref().iter().filter_map(|b| polygon(b.get_ref())).collect()
}

/// A pattern bolt `c` with the bodies that hold its anchors: it starts on its excavation's
/// boundary, which the blocks of a staged excavation (kept until their stage) share with the
/// rock, so its first anchor is held by the body just beyond it along the bolt (the rock), its
/// second by the body holding it. Left as it is when either is not a single body (the reader's
/// anchor check then reports it).
fn held_outside(mut c: Spanned<raw::Connector>, polygons: &[(String, Shape)]) -> Spanned<raw::Connector> {
    let point = |k: usize| {
        let q = c.get_ref().points.get_ref().get(k)?.get_ref();
        (q.len() == 2).then(|| Vec2::new(q[0], q[1]))
    };
    let (Some(a), Some(b)) = (point(0), point(1)) else { return c };
    let holder = |x: Vec2| {
        let found: Vec<&String> = polygons.iter().filter(|(_, s)| s.contains(x)).map(|(n, _)| n).collect();
        (found.len() == 1).then(|| found[0].clone())
    };
    if let (Some(first), Some(second)) = (holder(a + (b - a) * 1e-6), holder(b)) {
        let header = c.span();
        c.get_mut().bodies = Some(at(&header, vec![at(&header, first), at(&header, second)]));
    }
    c
}

/// The parameters t in (0, 1) where the segment a + t (b - a) crosses an edge of a polygon.
fn crossings(a: Vec2, b: Vec2, polygons: &[(String, Shape)]) -> Vec<f64> {
    let d = b - a;
    let mut ts = Vec::new();
    for (_, shape) in polygons {
        let Shape::Polygon { vertices } = shape else { continue };
        for i in 0..vertices.len() {
            let (p, q) = (vertices[i], vertices[(i + 1) % vertices.len()]);
            let e = q - p;
            let den = d.x * e.y - d.y * e.x;
            if den.abs() <= 1e-14 * d.norm() * e.norm() {
                continue; // parallel: no single crossing
            }
            let w = p - a;
            let t = (w.x * e.y - w.y * e.x) / den;
            let s = (w.x * d.y - w.y * d.x) / den;
            if t > 1e-12 && t < 1.0 - 1e-12 && (-1e-12..=1.0 + 1e-12).contains(&s) {
                ts.push(t);
            }
        }
    }
    ts.sort_by(f64::total_cmp);
    ts.dedup_by(|x, y| (*x - *y).abs() <= 1e-9);
    ts
}

/// A grouted bolt from a to b cut at the edges it crosses into pieces, each inside one body
/// (pieces in no body, e.g. across a void, are skipped); segment k joins the bodies of pieces
/// k and k + 1, anchored at the middle of each piece, the first at a and the last at b. A bolt
/// through n bodies thus gives n - 1 segments whose lengths add up to the bolt's.
fn split(
    index: usize,
    c: Spanned<raw::Connector>,
    polygons: &[(String, Shape)],
) -> Check<Vec<Spanned<raw::Connector>>> {
    let (header, raw_c) = (c.span(), c.get_ref());
    let grouted_span = raw_c.grouted.as_ref().map_or(header.clone(), Spanned::span);
    if raw_c.kind.get_ref() != "bolt" {
        return fail(grouted_span, "grouted is only for bolts");
    }
    if let Some(b) = &raw_c.bodies {
        return fail(b.span(), "a grouted bolt finds its bodies along its length; remove `bodies`");
    }
    let ends: Vec<[f64; 2]> = raw_c
        .points
        .get_ref()
        .iter()
        .enumerate()
        .map(|(k, p)| numbers(p.get_ref(), p.span(), &format!("points[{k}]")))
        .collect::<Check<_>>()?;
    let [a, b] = match ends.as_slice() {
        [a, b] => [Vec2::new(a[0], a[1]), Vec2::new(b[0], b[1])],
        _ => return fail(raw_c.points.span(), format!("points must have 2 points (got {})", ends.len())),
    };
    let mut cuts = vec![0.0];
    cuts.extend(crossings(a, b, polygons));
    cuts.push(1.0);
    // each piece: its parameter interval and the body holding its middle
    let pieces: Vec<(f64, f64, usize)> = cuts
        .windows(2)
        .filter_map(|w| {
            let mid = a + (b - a) * (0.5 * (w[0] + w[1]));
            polygons.iter().position(|(_, s)| s.contains(mid)).map(|k| (w[0], w[1], k))
        })
        .collect();
    if pieces.len() < 2 {
        let mut c = c;
        c.get_mut().grouted = None;
        return Ok(vec![c]);
    }
    let name = raw_c.name.as_ref().map_or(format!("connector-{}", index + 1), |n| n.get_ref().clone());
    let n = pieces.len();
    let anchor = |k: usize, first: bool| -> Vec2 {
        let (t0, t1, _) = pieces[k];
        match (k, first) {
            (0, true) => a,
            (k, false) if k == n - 1 => b,
            _ => a + (b - a) * (0.5 * (t0 + t1)),
        }
    };
    let mut segments = Vec::with_capacity(n - 1);
    for k in 0..n - 1 {
        let (p, q) = (anchor(k, true), anchor(k + 1, false));
        let bodies = [&polygons[pieces[k].2].0, &polygons[pieces[k + 1].2].0];
        let mut s = copy_constants(raw_c, &header);
        s.name = Some(at(&header, format!("{name}.{}", k + 1)));
        s.points = at(&raw_c.points.span(), vec![at(&header, vec![p.x, p.y]), at(&header, vec![q.x, q.y])]);
        s.bodies = Some(at(&header, bodies.iter().map(|b| at(&header, (*b).clone())).collect()));
        segments.push(at(&header, s));
    }
    Ok(segments)
}

/// A bolt with `c`'s constants and no points, name or bodies yet.
fn copy_constants(c: &raw::Connector, header: &Range<usize>) -> raw::Connector {
    raw::Connector {
        name: None,
        kind: c.kind.clone(),
        points: at(header, Vec::new()),
        bodies: None,
        stiffness: c.stiffness.clone(),
        young: c.young.clone(),
        area: c.area.clone(),
        inertia: c.inertia.clone(),
        shear_modulus: c.shear_modulus.clone(),
        shear_factor: c.shear_factor.clone(),
        pretension: c.pretension.clone(),
        strength: c.strength.clone(),
        grouted: None,
        yield_force: c.yield_force.clone(),
        ultimate_strain: c.ultimate_strain.clone(),
        stage: c.stage.clone(),
    }
}

/// The bolts of one pattern: on the excavation's boundary, from the point at polar angle
/// `range[0]` (from the outline's centroid) counter-clockwise every `spacing` along the boundary
/// while the polar angle stays within the range (a full turn: while the arc is shorter than the
/// perimeter), each `length` long along the outward normal of the edge it starts on. The
/// count is floor(L / spacing) + 1 for an arc of length L shorter than the perimeter.
fn pattern(p: &Spanned<raw::BoltPattern>, outlines: &Outlines) -> Check<Vec<Spanned<raw::Connector>>> {
    let (header, p) = (p.span(), p.get_ref());
    let Some((_, outline)) = outlines.iter().find(|(n, _)| n == p.excavation.get_ref()) else {
        return fail(p.excavation.span(), format!("unknown excavation \"{}\"", p.excavation.get_ref()));
    };
    let spacing = positive(&p.spacing, "spacing")?;
    let length = positive(&p.length, "length")?;
    positive(&p.young, "young")?;
    positive(&p.area, "area")?;
    if let Some(t) = &p.pretension {
        non_negative(t, "pretension")?;
    }
    let (from, to) = match &p.range {
        Some(r) => {
            let [a, b] = numbers(r.get_ref(), r.span(), "range")?;
            if !(a < b && b - a <= 360.0) {
                return fail(
                    r.span(),
                    format!("range must be [from, to] with from < to <= from + 360 (got [{a}, {b}])"),
                );
            }
            (a, b)
        }
        None => (0.0, 360.0),
    };
    let points = pattern_points(outline, from, to, spacing);
    if points.is_empty() {
        let message =
            format!("the range [{from}, {to}] holds no point of excavation \"{}\"", p.excavation.get_ref());
        return fail(p.range.as_ref().map_or(header.clone(), Spanned::span), message);
    }
    let mut bolts = Vec::with_capacity(points.len());
    for (k, (q, n)) in points.into_iter().enumerate() {
        let far = q + n * length;
        let mut anchors = vec![at(&header, vec![q.x, q.y]), at(&header, vec![far.x, far.y])];
        anchors[1] = at(&p.length.span(), vec![far.x, far.y]);
        bolts.push(at(
            &header,
            raw::Connector {
                name: Some(at(&p.name.span(), format!("{}-{}", p.name.get_ref(), k + 1))),
                kind: at(&header, "bolt".to_owned()),
                points: at(&header, anchors),
                bodies: None,
                stiffness: None,
                young: Some(p.young.clone()),
                area: Some(p.area.clone()),
                inertia: None,
                shear_modulus: None,
                shear_factor: None,
                pretension: p.pretension.clone(),
                strength: p.strength.clone(),
                grouted: p.grouted.clone(),
                yield_force: p.yield_force.clone(),
                ultimate_strain: p.ultimate_strain.clone(),
                stage: p.stage.clone(),
            },
        ));
    }
    Ok(bolts)
}

/// Points (with the outward normal of their edge) every `spacing` along a counter-clockwise
/// outline from polar angle `from` to `to` [deg] about its vertex centroid.
pub(super) fn pattern_points(outline: &[Vec2], from: f64, to: f64, spacing: f64) -> Vec<(Vec2, Vec2)> {
    let n = outline.len();
    let c = outline.iter().fold(Vec2::zeros(), |s, v| s + v) / n as f64;
    let polar = |p: Vec2| (p.y - c.y).atan2(p.x - c.x).to_degrees();
    // angle of p counter-clockwise past `from`, in [0, 360)
    let past = |p: Vec2| (polar(p) - from).rem_euclid(360.0);
    let span = to - from;
    let full = span >= 360.0;
    // the edge where the ray at `from` leaves the outline, and the point on it
    let Some(start) = (0..n).find_map(|i| {
        let (a, b) = (outline[i], outline[(i + 1) % n]);
        let (pa, pb) = (past(a), past(b));
        // the edge crosses the ray when its end has wrapped past 360 back near 0 (or starts on it)
        if pa == 0.0 || pa > pb && pa - pb > 180.0 {
            let dir = Vec2::new(from.to_radians().cos(), from.to_radians().sin());
            let e = b - a;
            let den = dir.x * e.y - dir.y * e.x;
            let w = a - c;
            let s = if den.abs() > 0.0 { (dir.y * w.x - dir.x * w.y) / den } else { 0.0 };
            Some((i, a + e * s.clamp(0.0, 1.0)))
        } else {
            None
        }
    }) else {
        return Vec::new();
    };
    let (mut edge, mut at_point) = start;
    let (mut travelled, mut next) = (0.0, 0.0);
    let perimeter: f64 = (0..n).map(|i| (outline[(i + 1) % n] - outline[i]).norm()).sum();
    let mut points = Vec::new();
    for _ in 0..=n {
        let b = outline[(edge + 1) % n];
        let e = b - at_point;
        let len = e.norm();
        let full_edge = outline[(edge + 1) % n] - outline[edge];
        let normal = Vec2::new(full_edge.y, -full_edge.x) / full_edge.norm();
        while next <= travelled + len {
            let q = at_point + e * ((next - travelled) / len.max(f64::MIN_POSITIVE));
            let inside_range = if full {
                next < perimeter - 1e-9 * perimeter
            } else {
                past(q) <= span + 1e-9 || next == 0.0
            };
            if !inside_range {
                return points;
            }
            points.push((q, normal));
            next += spacing;
        }
        travelled += len;
        at_point = b;
        edge = (edge + 1) % n;
    }
    points
}
