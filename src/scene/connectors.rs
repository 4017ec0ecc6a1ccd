//! Validation of `[[connector]]` tables (scene-format contract; math note §6): kind and its
//! constants, the two anchors and the bodies that hold them, pretension, strength and names.
//! Each failure is a [`Problem`] at the offending key, or at the `[[connector]]` header for a
//! missing key.

use std::collections::HashMap;
use std::ops::Range;

use toml::Spanned;

use super::Problem;
use super::check::{Check, Names, choice, fail, non_negative, numbers, optional, positive, resolve};
use super::raw;
use crate::connector::is_zero_length;
use crate::geometry::Vec2;
use crate::model::{BodySpec, ConnectorKind, ConnectorSpec};

/// Poisson's ratio behind the default shear modulus G = E / (2 (1 + 0.3)) (scene-format contract).
const DEFAULT_POISSON: f64 = 0.3;
/// Default k_Be of eq. 89 (rectangular section).
const DEFAULT_SHEAR_FACTOR: f64 = 1.2;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Spring,
    Bolt,
    Beam,
}

const KINDS: [(&str, Kind); 3] = [("spring", Kind::Spring), ("bolt", Kind::Bolt), ("beam", Kind::Beam)];

/// All connectors, in file order, with unique names.
pub(super) fn connectors(
    raw: &[Spanned<raw::Connector>],
    body_names: &Names,
    bodies: &[BodySpec],
) -> Check<Vec<ConnectorSpec>> {
    let list: Vec<ConnectorSpec> =
        raw.iter().enumerate().map(|(i, c)| connector(i, c, body_names, bodies)).collect::<Check<_>>()?;
    unique(raw, &list)?;
    Ok(list)
}

fn connector(
    index: usize,
    c: &Spanned<raw::Connector>,
    body_names: &Names,
    bodies: &[BodySpec],
) -> Check<ConnectorSpec> {
    let (header, c) = (c.span(), c.get_ref());
    let kind = choice(&c.kind, "kind", &KINDS)?;
    reject_foreign_keys(c, kind)?;
    let law = law(c, &header, kind)?;
    let points = points(&c.points)?;
    let name = match &c.name {
        Some(n) => n.get_ref().clone(),
        None => format!("connector-{}", index + 1),
    };
    let held_by = holders(c, &points, body_names, bodies, &name)?;
    let place = c.bodies.as_ref().map_or(c.points.span(), Spanned::span);
    if held_by[0] == held_by[1] {
        let body = &bodies[held_by[0]].name;
        return fail(place, format!("both anchors of connector \"{name}\" are on the same body \"{body}\""));
    }
    for (k, &b) in held_by.iter().enumerate() {
        if !matches!(bodies[b].shape, crate::model::Shape::Mesh(_)) {
            continue;
        }
        let body = &bodies[b].name;
        if !bodies[b].shape.contains(points[k]) {
            let (x, y) = (points[k].x, points[k].y);
            return fail(
                c.points.get_ref()[k].span(),
                format!(
                    "anchor points[{k}] = ({x}, {y}) of connector \"{name}\" lies outside mesh body \"{body}\""
                ),
            );
        }
    }
    if bodies[held_by[0]].fixed && bodies[held_by[1]].fixed {
        let (a, b) = (&bodies[held_by[0]].name, &bodies[held_by[1]].name);
        return fail(place, format!("connector \"{name}\" joins two fixed bodies, \"{a}\" and \"{b}\""));
    }
    let zero_length = is_zero_length(points[0], points[1]);
    if zero_length && kind != Kind::Spring {
        return fail(
            c.points.span(),
            format!("a {} needs two distinct points (zero length)", kind_word(kind)),
        );
    }
    let pretension = optional(&c.pretension, "pretension", non_negative)?;
    if let (Some(p), true) = (&c.pretension, zero_length) {
        return fail(p.span(), "a zero-length spring has no axis to carry a pretension");
    }
    let pretension = pretension.unwrap_or(0.0);
    let strength = optional(&c.strength, "strength", positive)?;
    if let (Some(s), Some(value)) = (&c.strength, strength)
        && value < pretension
    {
        return fail(s.span(), format!("strength ({value}) is below the pretension ({pretension})"));
    }
    let (yield_force, ultimate_strain) = plastic_limits(c, strength, pretension)?;
    Ok(ConnectorSpec {
        name,
        kind: law,
        bodies: held_by,
        points,
        pretension,
        strength,
        yield_force,
        ultimate_strain,
    })
}

/// A bolt's `yield_force` (positive, at most `strength`, at least the pretension) and
/// `ultimate_strain` (positive) (math note §6.1).
fn plastic_limits(
    c: &raw::Connector,
    strength: Option<f64>,
    pretension: f64,
) -> Check<(Option<f64>, Option<f64>)> {
    let yield_force = optional(&c.yield_force, "yield_force", positive)?;
    if let (Some(y), Some(value)) = (&c.yield_force, yield_force) {
        if let Some(s) = strength.filter(|&s| value > s) {
            return fail(
                y.span(),
                format!(
                    "yield_force ({value}) is above the strength ({s}): the bolt would break before it yields"
                ),
            );
        }
        if value < pretension {
            return fail(y.span(), format!("yield_force ({value}) is below the pretension ({pretension})"));
        }
    }
    Ok((yield_force, optional(&c.ultimate_strain, "ultimate_strain", positive)?))
}

fn kind_word(kind: Kind) -> &'static str {
    KINDS.iter().find(|(_, k)| *k == kind).map_or("connector", |(w, _)| *w)
}

/// Keys that belong to another kind are errors, not silently ignored.
fn reject_foreign_keys(c: &raw::Connector, kind: Kind) -> Check<()> {
    let used: &[&str] = match kind {
        Kind::Spring => &["stiffness", "pretension", "strength"],
        Kind::Bolt => &["young", "area", "pretension", "strength", "yield_force", "ultimate_strain"],
        Kind::Beam => &["young", "area", "inertia", "shear_modulus", "shear_factor", "strength"],
    };
    let given = c.numbers();
    for (key, value) in given {
        if let Some(v) = value
            && !used.contains(&key)
        {
            return fail(v.span(), format!("`{key}` is not used by a {} connector", kind_word(kind)));
        }
    }
    Ok(())
}

/// A positive constant the kind requires; missing, the error points at the `[[connector]]` header.
fn need(header: &Range<usize>, value: &Option<Spanned<f64>>, key: &str, kind: Kind) -> Check<f64> {
    match value {
        Some(v) => positive(v, key),
        None => {
            let message = format!("a {} connector needs `{key}`", kind_word(kind));
            Err(Problem::missing(header.clone(), key, message))
        }
    }
}

/// The kind with its constants (math note §6; defaults of the scene-format contract).
fn law(c: &raw::Connector, header: &Range<usize>, kind: Kind) -> Check<ConnectorKind> {
    Ok(match kind {
        Kind::Spring => ConnectorKind::Spring { stiffness: need(header, &c.stiffness, "stiffness", kind)? },
        Kind::Bolt => ConnectorKind::Bolt {
            young: need(header, &c.young, "young", kind)?,
            area: need(header, &c.area, "area", kind)?,
        },
        Kind::Beam => {
            let young = need(header, &c.young, "young", kind)?;
            let default_g = young / (2.0 * (1.0 + DEFAULT_POISSON));
            ConnectorKind::Beam {
                young,
                area: need(header, &c.area, "area", kind)?,
                inertia: need(header, &c.inertia, "inertia", kind)?,
                shear_modulus: optional(&c.shear_modulus, "shear_modulus", positive)?.unwrap_or(default_g),
                shear_factor: optional(&c.shear_factor, "shear_factor", non_negative)?
                    .unwrap_or(DEFAULT_SHEAR_FACTOR),
            }
        }
    })
}

/// Exactly two finite `[x, y]` anchors.
fn points(p: &Spanned<Vec<Spanned<Vec<f64>>>>) -> Check<[Vec2; 2]> {
    let list = p.get_ref();
    if list.len() != 2 {
        return fail(p.span(), format!("points must hold 2 anchors (got {})", list.len()));
    }
    let point = |i: usize| {
        let [x, y] = numbers(list[i].get_ref(), list[i].span(), &format!("points[{i}]"))?;
        Ok(Vec2::new(x, y))
    };
    Ok([point(0)?, point(1)?])
}

/// The body holding each anchor: from `bodies`, else the one body whose shape contains it.
fn holders(
    c: &raw::Connector,
    points: &[Vec2; 2],
    body_names: &Names,
    bodies: &[BodySpec],
    name: &str,
) -> Check<[usize; 2]> {
    if let Some(b) = &c.bodies {
        return match b.get_ref().as_slice() {
            [a, b] => Ok([resolve(body_names, a, "body")?, resolve(body_names, b, "body")?]),
            other => fail(b.span(), format!("bodies must name 2 bodies (got {})", other.len())),
        };
    }
    let locate = |k: usize| {
        let p = points[k];
        let span = c.points.get_ref()[k].span();
        let inside: Vec<usize> = (0..bodies.len()).filter(|&i| bodies[i].shape.contains(p)).collect();
        let at = format!("anchor points[{k}] = ({}, {}) of connector \"{name}\"", p.x, p.y);
        match inside.as_slice() {
            [i] => Ok(*i),
            [] => fail(span, format!("{at} lies inside no body; move it or give `bodies`")),
            [i, j, ..] => {
                let (a, b) = (&bodies[*i].name, &bodies[*j].name);
                fail(span, format!("{at} lies inside two bodies, \"{a}\" and \"{b}\"; give `bodies`"))
            }
        }
    };
    Ok([locate(0)?, locate(1)?])
}

/// Names are unique (defaults included) and safe to write unquoted into connectors.csv. A clash
/// is reported at the explicit name involved (two defaults never clash).
fn unique(raw: &[Spanned<raw::Connector>], list: &[ConnectorSpec]) -> Check<()> {
    let mut seen: HashMap<&str, usize> = HashMap::new();
    for (i, spec) in list.iter().enumerate() {
        let name = &spec.name;
        if let Some(n) = &raw[i].get_ref().name
            && (name.is_empty() || name.contains([',', '"', '\n', '\r']))
        {
            let message =
                format!("connector name \"{name}\" must be non-empty, without commas, quotes or line breaks");
            return fail(n.span(), message);
        }
        if let Some(first) = seen.insert(name.as_str(), i) {
            let span = match (&raw[i].get_ref().name, &raw[first].get_ref().name) {
                (Some(n), _) | (None, Some(n)) => n.span(),
                (None, None) => raw[i].span(),
            };
            return fail(span, format!("duplicate connector name \"{name}\" (connector[{first}] has it)"));
        }
    }
    Ok(())
}
