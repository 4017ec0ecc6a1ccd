//! `pbdda cut SCENE --out EXPANDED.toml [--png FILE]`: the scene with its rock mass cut into
//! explicit `[[body]]` tables ([`crate::scene::expanded`]), the `.msh` files of meshed blocks
//! beside it, and optionally a picture of the blocks, the joints coloured by set and the bolts.

use crate::model::{Model, Shape};
use crate::rockmass::EdgeSource;
use crate::scene::{self, Expansion};
use miette::{Result, miette};
use plotters::prelude::*;
use std::path::Path;

pub(super) fn cut(scene_path: &Path, out: &Path, png: Option<&Path>) -> Result<()> {
    let file = scene_path.display().to_string();
    let source = std::fs::read_to_string(scene_path).map_err(|e| miette!("{file}: {e}"))?;
    let stem = out.file_stem().map_or("scene".into(), |s| s.to_string_lossy().into_owned());
    let expanded = scene::expanded(&source, &file, &stem)?;
    let dir = out.parent().unwrap_or(Path::new(""));
    for (name, text) in &expanded.meshes {
        std::fs::write(dir.join(name), text).map_err(|e| miette!("{}: {e}", dir.join(name).display()))?;
    }
    std::fs::write(out, &expanded.text).map_err(|e| miette!("{}: {e}", out.display()))?;
    out!("{}", report(&expanded.expansion));
    if let Some(png) = png {
        picture(&expanded.model, &expanded.expansion, png)?;
    }
    Ok(())
}

/// The lines `cut` and `check` print about a rock mass: block count, smallest block, each merge
/// and join, the connectors made. Empty for a scene without one.
pub fn report(e: &Expansion) -> String {
    let mut s = String::new();
    if !e.blocks.is_empty() {
        s += &format!("blocks: {}\n", e.blocks.len());
        if let Some((name, area)) = e.smallest() {
            s += &format!("smallest block: {name} ({area:e} m^2)\n");
        }
    }
    for r in &e.reports {
        s += &format!("{r}\n");
    }
    for (name, blocks) in &e.staged {
        s += &format!("excavation {name}: {} blocks kept for its stage\n", blocks.len());
    }
    if !e.connectors.is_empty() {
        s += &format!("bolts made: {} ({})\n", e.connectors.len(), e.connectors.join(", "));
    }
    s
}

/// Colour of a cut edge: grey outline and excavations, one colour per joint set or joint.
fn colour(source: &EdgeSource) -> RGBColor {
    const SETS: [RGBColor; 6] = [
        RGBColor(200, 40, 40),
        RGBColor(40, 90, 200),
        RGBColor(30, 150, 60),
        RGBColor(200, 120, 0),
        RGBColor(140, 40, 160),
        RGBColor(0, 150, 160),
    ];
    match source {
        EdgeSource::Outline | EdgeSource::Excavation(_) => RGBColor(60, 60, 60),
        EdgeSource::Seam => RGBColor(160, 160, 160),
        EdgeSource::Set(k) | EdgeSource::Bridge(k) => SETS[k % SETS.len()],
        EdgeSource::Joint(k) => SETS[(SETS.len() - 1 - k % SETS.len()) % SETS.len()],
    }
}

/// The picture: polygon bodies filled, cut edges by set colour, connectors brown.
fn picture(model: &Model, e: &Expansion, png: &Path) -> Result<()> {
    let (w, h) = (1200u32, 900u32);
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for b in &model.bodies {
        if let Shape::Polygon { vertices } = &b.shape {
            for v in vertices {
                lo = [lo[0].min(v.x), lo[1].min(v.y)];
                hi = [hi[0].max(v.x), hi[1].max(v.y)];
            }
        }
    }
    for (seg, _) in &e.edges {
        for p in seg {
            lo = [lo[0].min(p[0]), lo[1].min(p[1])];
            hi = [hi[0].max(p[0]), hi[1].max(p[1])];
        }
    }
    if !lo[0].is_finite() {
        return Err(miette!("{}: the scene has no polygon to draw", png.display()));
    }
    let margin = 20.0;
    let scale = ((w as f64 - 2.0 * margin) / (hi[0] - lo[0]).max(1e-12))
        .min((h as f64 - 2.0 * margin) / (hi[1] - lo[1]).max(1e-12));
    let px = |x: f64, y: f64| {
        ((margin + scale * (x - lo[0])) as i32, (h as f64 - margin - scale * (y - lo[1])) as i32)
    };
    let root = BitMapBackend::new(png, (w, h)).into_drawing_area();
    let draw = |e: DrawingAreaErrorKind<_>| miette!("{}: {e}", png.display());
    root.fill(&WHITE).map_err(draw)?;
    for b in &model.bodies {
        if let Shape::Polygon { vertices } = &b.shape {
            let pts: Vec<_> = vertices.iter().map(|v| px(v.x, v.y)).collect();
            let fill = if b.fixed { RGBColor(190, 190, 190) } else { RGBColor(235, 225, 205) };
            root.draw(&Polygon::new(pts, fill.filled())).map_err(draw)?;
        }
    }
    for (seg, source) in &e.edges {
        let line = vec![px(seg[0][0], seg[0][1]), px(seg[1][0], seg[1][1])];
        root.draw(&PathElement::new(line, colour(source).stroke_width(2))).map_err(draw)?;
    }
    for c in &model.connectors {
        let line = vec![px(c.points[0].x, c.points[0].y), px(c.points[1].x, c.points[1].y)];
        root.draw(&PathElement::new(line, RGBColor(110, 70, 20).stroke_width(3))).map_err(draw)?;
    }
    root.present().map_err(draw)?;
    Ok(())
}
