//! Validation of `[[traction]]` tables (math note §2.5): the body (a polygon or mesh), the loaded
//! boundary part (`from`/`to`, or a mesh's physical `group`), the law (`pressure`/`shear` or
//! `stress`) and `history`. Each failure is a [`Problem`] at the offending key, or at the
//! `[[traction]]` header for a missing key.

use std::ops::Range;

use toml::Spanned;

use super::Problem;
use super::check::{Check, Names, fail, finite, history, optional, resolve, vec2};
use super::raw;
use crate::geometry::Vec2;
use crate::mesh::loops::boundary_loops;
use crate::model::{BodySpec, Shape};
use crate::traction::{Piece, Traction, TractionLaw, boundary_part, domain_tractions};

/// All tractions, in file order; `body = "domain"` (with a `[domain]`, whose `outline` is given)
/// becomes one traction per block with edges on the outline between `from` and `to`.
pub(super) fn tractions(
    raw: &[Spanned<raw::Traction>],
    body_names: &Names,
    bodies: &[BodySpec],
    outline: Option<&[Vec<f64>]>,
) -> Check<Vec<Traction>> {
    let mut out = Vec::with_capacity(raw.len());
    for t in raw {
        match outline.filter(|_| t.get_ref().body.get_ref() == "domain") {
            Some(outline) => out.extend(domain(t.span(), t.get_ref(), bodies, outline)?),
            None => out.push(traction(t.span(), t.get_ref(), body_names, bodies)?),
        }
    }
    Ok(out)
}

/// A `body = "domain"` traction: every cut block edge on the domain's outline between the
/// outline points nearest `from` and `to`, counter-clockwise (rock-mass design, section 4).
fn domain(
    header: Range<usize>,
    t: &raw::Traction,
    bodies: &[BodySpec],
    outline: &[Vec<f64>],
) -> Check<Vec<Traction>> {
    if let Some(g) = &t.group {
        return fail(g.span(), "a \"domain\" traction takes `from` and `to`, not `group`");
    }
    let (Some(from), Some(to)) = (&t.from, &t.to) else {
        return Err(Problem::missing(header, "from", "a \"domain\" traction needs `from` and `to`"));
    };
    let (a, b) = (vec2(from, "from")?, vec2(to, "to")?);
    let law = law(&header, t)?;
    let history = optional(&t.history, "history", history)?;
    let ring: Vec<Vec2> = outline.iter().map(|p| Vec2::new(p[0], p[1])).collect();
    let found = domain_tractions(&ring, bodies, a, b, law, history);
    if found.is_empty() {
        return fail(to.span(), "no block edge lies on the domain's outline between `from` and `to`");
    }
    Ok(found)
}

fn traction(
    header: Range<usize>,
    t: &raw::Traction,
    body_names: &Names,
    bodies: &[BodySpec],
) -> Check<Traction> {
    let body = resolve(body_names, &t.body, "body")?;
    let name = &bodies[body].name;
    let rings = rings(&bodies[body].shape);
    if rings.is_empty() {
        return fail(
            t.body.span(),
            format!("a traction needs a polygon or mesh body; \"{name}\" is neither"),
        );
    }
    let law = law(&header, t)?;
    let pieces = match (&t.group, &t.from, &t.to) {
        (Some(g), None, None) => group_pieces(g, &bodies[body].shape, &rings, name)?,
        (Some(g), _, _) => return fail(g.span(), "give either `group` or `from` and `to`, not both"),
        (None, Some(from), Some(to)) => {
            let (a, b) = (vec2(from, "from")?, vec2(to, "to")?);
            // the loop (outer boundary or hole) nearest `from`
            let ring = rings
                .iter()
                .min_by(|r, s| distance(&r.1, a).total_cmp(&distance(&s.1, a)))
                .expect("non-empty by the check above");
            let Some(part) = boundary_part(&ring.1, a, b) else {
                return fail(
                    to.span(),
                    format!("`from` and `to` pick the same boundary point of \"{name}\": no boundary part"),
                );
            };
            let n = ring.0.len();
            part.into_iter().map(|(k, s)| Piece { nodes: [ring.0[k], ring.0[(k + 1) % n]], s }).collect()
        }
        (None, None, _) => {
            return Err(Problem::missing(header, "from", "a traction needs `from` and `to`, or `group`"));
        }
        (None, Some(_), None) => {
            return Err(Problem::missing(header, "to", "a traction needs `to` with `from`"));
        }
    };
    let history = optional(&t.history, "history", history)?;
    Ok(Traction { body, pieces, law, history })
}

/// `pressure` and `shear`, or `stress`, not both.
fn law(header: &Range<usize>, t: &raw::Traction) -> Check<TractionLaw> {
    match (&t.stress, &t.pressure, &t.shear) {
        (Some(_), Some(p), _) => fail(p.span(), "give either `pressure` (and `shear`) or `stress`, not both"),
        (Some(_), None, Some(s)) => {
            fail(s.span(), "give either `shear` (and `pressure`) or `stress`, not both")
        }
        (Some(s), None, None) => {
            let v = s.get_ref();
            if v.len() != 3 {
                return fail(s.span(), format!("stress must be [sx, sy, txy] (got {} numbers)", v.len()));
            }
            if let Some(x) = v.iter().find(|x| !x.is_finite()) {
                return fail(s.span(), format!("stress must hold finite numbers (got {x})"));
            }
            Ok(TractionLaw::Stress([v[0], v[1], v[2]]))
        }
        (None, None, None) => Err(Problem::missing(
            header.clone(),
            "pressure",
            "a traction needs `pressure`, `shear` or `stress`",
        )),
        (None, p, s) => Ok(TractionLaw::Pressure {
            pressure: optional(p, "pressure", finite)?.unwrap_or(0.0),
            shear: optional(s, "shear", finite)?.unwrap_or(0.0),
        }),
    }
}

/// The boundary loops of a body: (node or vertex indices, positions), the body on the left; a
/// polygon's vertices, a mesh's outer loop and holes; none for disks and rings.
fn rings(shape: &Shape) -> Vec<(Vec<usize>, Vec<crate::geometry::Vec2>)> {
    match shape {
        Shape::Polygon { vertices } => vec![((0..vertices.len()).collect(), vertices.clone())],
        Shape::Mesh(m) => boundary_loops(&m.mesh.nodes, &m.mesh.triangles)
            .unwrap_or_default()
            .into_iter()
            .map(|l| {
                let at = l.nodes.iter().map(|&i| m.mesh.nodes[i]).collect();
                (l.nodes, at)
            })
            .collect(),
        _ => Vec::new(),
    }
}

fn distance(ring: &[crate::geometry::Vec2], p: crate::geometry::Vec2) -> f64 {
    let n = ring.len();
    (0..n)
        .map(|k| {
            let (a, b) = (ring[k], ring[(k + 1) % n]);
            let ab = b - a;
            let s = ((p - a).dot(&ab) / ab.norm_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
            (a + ab * s - p).norm()
        })
        .fold(f64::INFINITY, f64::min)
}

/// A mesh's physical curve: every boundary edge whose two nodes belong to it.
fn group_pieces(
    g: &Spanned<String>,
    shape: &Shape,
    rings: &[(Vec<usize>, Vec<crate::geometry::Vec2>)],
    name: &str,
) -> Check<Vec<Piece>> {
    let Shape::Mesh(m) = shape else {
        return fail(
            g.span(),
            format!(
                "`group` names a physical curve of a mesh body; \"{name}\" is a polygon: give `from` and `to`"
            ),
        );
    };
    let nodes =
        m.mesh.node_set(&[g.get_ref().as_str()]).map_err(|e| Problem::new(g.span(), e.to_string()))?;
    let pieces: Vec<Piece> = rings
        .iter()
        .flat_map(|(ids, _)| (0..ids.len()).map(move |k| [ids[k], ids[(k + 1) % ids.len()]]))
        .filter(|e| e.iter().all(|n| nodes.binary_search(n).is_ok()))
        .map(|nodes| Piece { nodes, s: [0.0, 1.0] })
        .collect();
    if pieces.is_empty() {
        return fail(g.span(), format!("group \"{}\" holds no boundary edge of \"{name}\"", g.get_ref()));
    }
    Ok(pieces)
}
