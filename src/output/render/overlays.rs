//! What the picture draws over the bodies: connectors from anchor to anchor coloured by their
//! axial force (broken ones grey with a cross), and contacts marked by the colour of their
//! interface (the joint sets).

use super::legend::{Range, colour_bar};
use super::{Area, View};
use crate::geometry::Vec2;
use crate::output::results::{ContactRow, ResultsError, Table, steps_of};
use plotters::prelude::*;
use std::path::Path;

/// Colour of a broken connector's line, and of the cross at its middle.
pub const BROKEN_LINE: RGBColor = RGBColor(120, 120, 120);
pub const BROKEN_MARK: RGBColor = RGBColor(200, 0, 200);
/// Width of a connector's line [px].
pub const CONNECTOR_WIDTH: u32 = 4;

/// One connector row of a step: its anchors, axial force and whether it broke.
#[derive(Debug, Clone)]
pub struct ConnectorLine {
    pub a: Vec2,
    pub b: Vec2,
    pub force: f64,
    pub broken: bool,
}

/// The `connectors.csv` rows of `step`, and the rows of the connectors that broke before it
/// (their one `broken` row: where they broke); none without the file.
pub fn connector_lines(dir: &Path, step: usize) -> Result<Vec<ConnectorLine>, ResultsError> {
    let path = dir.join("connectors.csv");
    if !path.exists() {
        return Ok(Vec::new());
    }
    let t = Table::read(&path)?;
    let steps = steps_of(&t)?;
    let (force, state) = (t.numbers("axial_force")?, t.text("state")?);
    let xy = ["anchor_a_x", "anchor_a_y", "anchor_b_x", "anchor_b_y"].map(|k| t.numbers(k));
    let [ax, ay, bx, by] = xy;
    let (ax, ay, bx, by) = (ax?, ay?, bx?, by?);
    // the step's rows, and connectors that broke before it where they broke
    let broke_before = |i: usize| steps[i] < step && state[i] == "broken";
    Ok((0..steps.len())
        .filter(|&i| steps[i] == step || broke_before(i))
        .map(|i| ConnectorLine {
            a: Vec2::new(ax[i], ay[i]),
            b: Vec2::new(bx[i], by[i]),
            force: force[i],
            broken: state[i] == "broken",
        })
        .collect())
}

/// The colour range of the connectors' forces: the intact ones' axial forces and zero.
pub fn force_range(lines: &[ConnectorLine]) -> Range {
    Range::of(lines.iter().filter(|l| !l.broken).map(|l| l.force), Some(0.0))
}

/// Draws the connectors (intact ones in the colour of their force, broken ones grey with a
/// magenta cross at their middle) and, if any is intact, the force colour bar in the box
/// `(x, top)..(x + 18, bottom)`.
pub fn draw_connectors<'a>(
    root: &Area<'a>,
    view: &View,
    lines: &[ConnectorLine],
    bar: (i32, i32, i32),
) -> Result<(), ResultsError> {
    let err = |e: DrawingAreaErrorKind<_>| ResultsError::Draw(e.to_string());
    let range = force_range(lines);
    for l in lines {
        let colour = if l.broken { BROKEN_LINE } else { range.colour(l.force) };
        let path = PathElement::new(vec![view.px(l.a), view.px(l.b)], colour.stroke_width(CONNECTOR_WIDTH));
        root.draw(&path).map_err(err)?;
    }
    for l in lines.iter().filter(|l| l.broken) {
        let (x, y) = view.px((l.a + l.b) / 2.0);
        let mark = BROKEN_MARK.stroke_width(3);
        root.draw(&PathElement::new(vec![(x - 7, y - 7), (x + 7, y + 7)], mark)).map_err(err)?;
        root.draw(&PathElement::new(vec![(x - 7, y + 7), (x + 7, y - 7)], mark)).map_err(err)?;
    }
    if lines.iter().any(|l| !l.broken) {
        colour_bar(root, range, "axial force [N]", bar.0, bar.1, bar.2).map_err(err)?;
    }
    if lines.iter().any(|l| l.broken) {
        let (x, y) = (bar.0, bar.2 + 28);
        let mark = BROKEN_MARK.stroke_width(3);
        root.draw(&PathElement::new(vec![(x, y - 6), (x + 12, y + 6)], mark)).map_err(err)?;
        root.draw(&PathElement::new(vec![(x, y + 6), (x + 12, y - 6)], mark)).map_err(err)?;
        root.draw(&Text::new("broken", (x + 18, y - 8), ("sans-serif", 14))).map_err(err)?;
    }
    Ok(())
}

/// Colours of the joint sets, by interface name in sorted order.
const JOINTS: [RGBColor; 6] = [
    RGBColor(230, 120, 0),
    RGBColor(0, 140, 140),
    RGBColor(150, 60, 170),
    RGBColor(120, 90, 40),
    RGBColor(0, 100, 230),
    RGBColor(200, 40, 110),
];

/// Marks each contact with a named interface by a short stroke along its tangent in its joint
/// set's colour, with a key of the names at `(x, y)` downwards. Returns the names keyed.
pub fn draw_joints<'a>(
    root: &Area<'a>,
    view: &View,
    contacts: &[ContactRow],
    key: (i32, i32),
) -> Result<Vec<String>, ResultsError> {
    let err = |e: DrawingAreaErrorKind<_>| ResultsError::Draw(e.to_string());
    let mut names: Vec<String> =
        contacts.iter().filter(|c| !c.interface.is_empty()).map(|c| c.interface.clone()).collect();
    names.sort();
    names.dedup();
    let colour = |name: &str| JOINTS[names.iter().position(|n| n == name).unwrap_or(0) % JOINTS.len()];
    let half = 6.0 / view.scale;
    for c in contacts.iter().filter(|c| !c.interface.is_empty()) {
        let t = Vec2::new(c.normal.y, -c.normal.x) * half;
        let stroke = colour(&c.interface).stroke_width(3);
        root.draw(&PathElement::new(vec![view.px(c.point - t), view.px(c.point + t)], stroke))
            .map_err(err)?;
    }
    for (k, name) in names.iter().enumerate() {
        let y = key.1 + 20 * k as i32;
        root.draw(&Rectangle::new([(key.0, y), (key.0 + 14, y + 10)], colour(name).filled())).map_err(err)?;
        root.draw(&Text::new(name.clone(), (key.0 + 20, y - 2), ("sans-serif", 14))).map_err(err)?;
    }
    Ok(names)
}
