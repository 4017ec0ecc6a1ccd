//! `pbdda render`: a PNG picture of the scene at a written step, from a results folder:
//! bodies (polygons, disks and rings as circles; fixed bodies grey); mesh bodies with their
//! elements filled by a stress colour map; the force chains as lines from each moving body's
//! centroid to its contact points, width proportional to the normal force (dark red
//! compression, dark blue tension of cemented contacts); contacts with a named interface marked by a stroke in
//! the colour of their joint set, with a key; connectors from anchor to anchor coloured by
//! their axial force (broken ones grey with a magenta cross, at the step they broke in and
//! after it, where they broke); a colour bar per colour map and
//! a length scale.
//!
//! Shapes come from `geometry.csv` (see [`super::results`]), positions from `bodies.csv`,
//! forces and interfaces from `contacts.csv`, connectors from `connectors.csv` (its anchor
//! columns) and mesh elements from the step's `.vtu` file (without it, a mesh body is drawn by
//! its outline only).

use super::plot::register_fonts;
use super::results::{
    BodyGeometry, Placed, ResultsError, Table, body_states, contact_rows, pick_step, place, read_geometry,
};
use crate::geometry::Vec2;
use plotters::prelude::*;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

pub mod legend;
mod mesh;
pub mod overlays;

pub use legend::{Range, colour_map};
pub use mesh::{Element, elements, von_mises};
pub use overlays::{BROKEN_LINE, BROKEN_MARK, ConnectorLine, connector_lines};

/// Width [px] kept free at the right for colour bars and keys when there are any.
const PANEL: f64 = 150.0;

/// Widest force-chain line [px] (the largest normal force of the step).
const MAX_LINE: f64 = 8.0;

/// Maps model coordinates to pixels: equal scales, y up, a margin around the bounding box.
#[derive(Debug, Clone, Copy)]
pub struct View {
    origin: Vec2,
    /// Pixels per metre.
    pub scale: f64,
    height: f64,
    offset: (f64, f64),
}

impl View {
    /// Fits the box `lo..hi` into a picture of `size`, keeping `right` pixels free at the right.
    fn fit(lo: Vec2, hi: Vec2, size: (u32, u32), right: f64) -> View {
        let (w, h) = (size.0 as f64 - right, size.1 as f64);
        let margin = 0.06 * w.min(h) + 10.0;
        let top = 34.0;
        let span = (hi - lo).map(|v| v.max(1e-12));
        let scale = ((w - 2.0 * margin) / span.x).min((h - 2.0 * margin - top) / span.y).max(1e-12);
        let offset = (0.5 * (w - scale * span.x), top + 0.5 * (h - top - scale * span.y));
        View { origin: lo, scale, height: span.y, offset }
    }

    /// The pixel of model point `p`.
    pub fn px(&self, p: Vec2) -> (i32, i32) {
        let q = p - self.origin;
        let x = self.offset.0 + self.scale * q.x;
        let y = self.offset.1 + self.scale * (self.height - q.y);
        (x.round() as i32, y.round() as i32)
    }

    fn len(&self, l: f64) -> i32 {
        (self.scale * l).round().max(1.0) as i32
    }
}

fn bounds(placed: &[(bool, Placed)]) -> (Vec2, Vec2) {
    let mut lo = Vec2::new(f64::INFINITY, f64::INFINITY);
    let mut hi = -lo;
    let mut grow = |p: Vec2, r: f64| {
        lo = lo.inf(&(p - Vec2::new(r, r)));
        hi = hi.sup(&(p + Vec2::new(r, r)));
    };
    for (_, p) in placed {
        match p {
            Placed::Circle { center, outer, .. } => grow(*center, *outer),
            Placed::Polygon(v) => v.iter().for_each(|q| grow(*q, 0.0)),
        }
    }
    if lo.x > hi.x { (Vec2::zeros(), Vec2::new(1.0, 1.0)) } else { (lo, hi) }
}

/// Writes the picture of written step `step` (default: the last) as the PNG `out`, `size`
/// pixels wide and high; returns `out`.
pub fn render_step(
    dir: &Path,
    step: Option<usize>,
    out: &Path,
    size: (u32, u32),
) -> Result<PathBuf, ResultsError> {
    render_view(dir, step, out, size).map(|(path, _)| path)
}

/// [`render_step`], also returning where the model's points are in the picture.
pub fn render_view(
    dir: &Path,
    step: Option<usize>,
    out: &Path,
    size: (u32, u32),
) -> Result<(PathBuf, View), ResultsError> {
    register_fonts();
    let geometry = read_geometry(dir)?;
    let bodies = Table::read(&dir.join("bodies.csv"))?;
    let step = pick_step(&bodies, step, geometry.len())?;
    let states = body_states(&bodies, step)?;
    let contacts: Vec<_> = contact_rows(&Table::read(&dir.join("contacts.csv"))?)?
        .into_iter()
        .filter(|c| c.step == step)
        .collect();
    let time =
        bodies.numbers("time")?.into_iter().zip(super::results::steps_of(&bodies)?).find(|(_, s)| *s == step);
    let (mut placed, mut rotation) = (Vec::new(), Vec::new());
    let mut centroid: HashMap<&str, (Vec2, bool)> = HashMap::new();
    for g in &geometry {
        let s = states.get(&g.name).ok_or_else(|| ResultsError::Format {
            path: bodies.path.clone(),
            line: 0,
            message: format!("body `{}` of geometry.csv has no row at step {step}", g.name),
        })?;
        placed.push((g.fixed, place(g, s)));
        rotation.push(s.rotation);
        centroid.insert(g.name.as_str(), (s.centroid, g.fixed));
    }
    let (lines, elements) = (connector_lines(dir, step)?, elements(dir, step)?);
    let joints = contacts.iter().any(|c| !c.interface.is_empty());
    let panel = !lines.is_empty() || !elements.is_empty() || joints;
    let view = {
        let (lo, hi) = bounds(&placed);
        View::fit(lo, hi, size, if panel { PANEL } else { 0.0 })
    };
    let root = BitMapBackend::new(out, size).into_drawing_area();
    let draw = |e: DrawingAreaErrorKind<_>| ResultsError::Draw(format!("{}: {e}", out.display()));
    root.fill(&WHITE).map_err(draw)?;
    draw_bodies(&root, &view, &geometry, &placed, &rotation).map_err(draw)?;
    let bars =
        layout(size, !elements.is_empty(), lines.iter().any(|l| !l.broken) || lines.iter().any(|l| l.broken));
    if !elements.is_empty() {
        mesh::draw_elements(&root, &view, &elements, bars[0])?;
    }
    draw_force_chains(&root, &view, &contacts, &centroid).map_err(draw)?;
    let key = (bars[2].0, bars[2].1);
    overlays::draw_joints(&root, &view, &contacts, key)?;
    overlays::draw_connectors(&root, &view, &lines, bars[1])?;
    legend::scale_bar(&root, view.scale, size).map_err(draw)?;
    let t = time.map_or(String::new(), |(t, _)| format!(", t = {} s", (t * 1e9).round() / 1e9));
    root.draw(&Text::new(format!("step {step}{t}"), (10, 8), ("sans-serif", 20))).map_err(draw)?;
    root.present().map_err(draw)?;
    Ok((out.to_path_buf(), view))
}

/// Boxes `(x, top, bottom)` of the right panel: the stress colour bar, the force colour bar (a
/// broken-connector key below it), the joint key (its top left); a bar that is not drawn takes
/// no room.
fn layout(size: (u32, u32), stress: bool, force: bool) -> [(i32, i32, i32); 3] {
    let (w, h) = (size.0 as i32, size.1 as i32);
    let x = w - PANEL as i32 + 40;
    let n = i32::from(stress) + i32::from(force);
    let (top, bottom) = (60, h * 3 / 4 - 30);
    let each = if n > 0 { (bottom - top - 60 * (n - 1)) / n } else { 0 };
    let first = (x, top, top + each);
    let second = if stress { (x, top + each + 60, top + 2 * each + 60) } else { first };
    [first, second, (x - 30, h * 3 / 4 + 20, h)]
}

/// Force chains: a line from each moving body's centroid to each of its contact points, width
/// by the normal force, dark red compression, dark blue tension.
fn draw_force_chains<'a>(
    root: &Area<'a>,
    view: &View,
    contacts: &[super::results::ContactRow],
    centroid: &HashMap<&str, (Vec2, bool)>,
) -> AreaResult<'a> {
    let fmax = contacts.iter().map(|c| c.normal_force.abs()).fold(0.0, f64::max);
    for c in contacts.iter().filter(|c| c.normal_force != 0.0 && fmax > 0.0) {
        let width = (MAX_LINE * c.normal_force.abs() / fmax).max(1.0).round() as u32;
        // dark red and dark blue: apart from the colour map's colours
        let color = if c.normal_force > 0.0 { RGBColor(110, 20, 20) } else { RGBColor(20, 20, 110) };
        for name in [&c.body_a, &c.body_b] {
            if let Some((from, false)) = centroid.get(name.as_str()) {
                root.draw(&PathElement::new(
                    vec![view.px(*from), view.px(c.point)],
                    color.stroke_width(width),
                ))?;
            }
        }
    }
    Ok(())
}

type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;
type AreaResult<'a> = Result<(), DrawingAreaErrorKind<<BitMapBackend<'a> as DrawingBackend>::ErrorType>>;

/// Rings first (their hole is painted white), then the other bodies on top.
fn draw_bodies<'a>(
    root: &Area<'a>,
    view: &View,
    geometry: &[BodyGeometry],
    placed: &[(bool, Placed)],
    rotation: &[f64],
) -> AreaResult<'a> {
    let edge = RGBColor(40, 40, 40);
    let order =
        placed.iter().enumerate().filter(|(_, (_, p))| matches!(p, Placed::Circle { inner: Some(_), .. }));
    let rest =
        placed.iter().enumerate().filter(|(_, (_, p))| !matches!(p, Placed::Circle { inner: Some(_), .. }));
    for (i, (fixed, p)) in order.chain(rest) {
        let fill = if *fixed {
            RGBColor(175, 175, 175)
        } else if geometry[i].deformable {
            RGBColor(150, 200, 150)
        } else {
            RGBColor(140, 180, 230)
        };
        match p {
            Placed::Circle { center, outer, inner } => {
                let c = view.px(*center);
                root.draw(&Circle::new(c, view.len(*outer), fill.filled()))?;
                root.draw(&Circle::new(c, view.len(*outer), edge.stroke_width(1)))?;
                if let Some(r) = inner {
                    root.draw(&Circle::new(c, view.len(*r), WHITE.filled()))?;
                    root.draw(&Circle::new(c, view.len(*r), edge.stroke_width(1)))?;
                }
                if !fixed {
                    // a radius marks the rotation
                    let (s, co) = rotation[i].sin_cos();
                    let dir = Vec2::new(co, s);
                    let from = view.px(center + dir * inner.unwrap_or(0.0));
                    root.draw(&PathElement::new(
                        vec![from, view.px(center + dir * *outer)],
                        edge.stroke_width(1),
                    ))?;
                }
            }
            Placed::Polygon(v) => {
                let pts: Vec<(i32, i32)> = v.iter().map(|q| view.px(*q)).collect();
                root.draw(&Polygon::new(pts.clone(), fill.filled()))?;
                let mut closed = pts;
                closed.push(closed[0]);
                root.draw(&PathElement::new(closed, edge.stroke_width(1)))?;
            }
        }
    }
    Ok(())
}
