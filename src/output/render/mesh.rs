//! Mesh elements in the picture: the triangles (`kind` 30) of the step's `.vtu` file
//! (`DIR/vtk/step_NNNNNN.vtu`, written when `[output] vtk` is on), filled in the colour of their
//! von Mises stress sqrt(σx² − σx σy + σy² + 3 τxy²) (of the in-plane components), edges drawn.
//! The file is read as [`crate::output::vtk`] writes it: base64 appended data, UInt64 headers.

use super::legend::{Range, colour_bar};
use super::{Area, View};
use crate::geometry::Vec2;
use crate::output::results::ResultsError;
use base64::Engine;
use plotters::prelude::*;
use std::path::Path;

/// One mesh triangle: its corners and its von Mises stress.
#[derive(Debug, Clone)]
pub struct Element {
    pub corners: [Vec2; 3],
    pub von_mises: f64,
}

/// Von Mises stress of the in-plane stress (σx, σy, τxy).
pub fn von_mises(s: [f64; 3]) -> f64 {
    (s[0] * s[0] - s[0] * s[1] + s[1] * s[1] + 3.0 * s[2] * s[2]).sqrt()
}

fn bad(path: &Path, message: String) -> ResultsError {
    ResultsError::Format { path: path.to_path_buf(), line: 0, message }
}

/// The value of attribute `key` in the tag text `tag`.
fn attribute<'t>(tag: &'t str, key: &str) -> Option<&'t str> {
    let at = tag.find(&format!(" {key}=\""))? + key.len() + 3;
    Some(&tag[at..at + tag[at..].find('"')?])
}

/// The arrays `names` of a `.vtu` file written by pbdda, as f64.
fn arrays(path: &Path, names: &[&str]) -> Result<Vec<Vec<f64>>, ResultsError> {
    let bytes =
        std::fs::read(path).map_err(|source| ResultsError::Io { path: path.to_path_buf(), source })?;
    let open = b"<AppendedData encoding=\"base64\">";
    let at = bytes
        .windows(open.len())
        .position(|w| w == open)
        .ok_or_else(|| bad(path, "no appended data".into()))?;
    let head = String::from_utf8_lossy(&bytes[..at]);
    let data = at + open.len() + bytes[at + open.len()..].iter().position(|&b| b == b'_').unwrap_or(0) + 1;
    let b64 = base64::engine::general_purpose::STANDARD;
    let mut out = Vec::new();
    for name in names {
        let tag = head
            .split('<')
            .find(|t| t.starts_with("DataArray") && attribute(t, "Name") == Some(name))
            .ok_or_else(|| bad(path, format!("no array `{name}`")))?;
        let offset: usize = attribute(tag, "offset").and_then(|o| o.parse().ok()).unwrap_or(usize::MAX);
        let start = data.saturating_add(offset).min(bytes.len());
        let decode = |n: usize| b64.decode(&bytes[start..(start + n).min(bytes.len())]).ok();
        let len = decode(12)
            .filter(|h| h.len() >= 8)
            .map(|h| u64::from_le_bytes([0, 1, 2, 3, 4, 5, 6, 7].map(|i| h[i])));
        let block = len
            .and_then(|n| decode((8 + n as usize).div_ceil(3) * 4))
            .ok_or_else(|| bad(path, format!("array `{name}` unreadable")))?;
        let v = &block[8.min(block.len())..];
        let values = match attribute(tag, "type") {
            Some("Float64") => {
                v.chunks_exact(8).map(|c| f64::from_le_bytes(c.try_into().unwrap_or([0; 8]))).collect()
            }
            Some("Int32") => {
                v.chunks_exact(4).map(|c| i32::from_le_bytes(c.try_into().unwrap_or([0; 4])) as f64).collect()
            }
            Some("Int64") => {
                v.chunks_exact(8).map(|c| i64::from_le_bytes(c.try_into().unwrap_or([0; 8])) as f64).collect()
            }
            Some("UInt8") => v.iter().map(|&b| b as f64).collect(),
            other => return Err(bad(path, format!("array `{name}` of type {other:?}"))),
        };
        out.push(values);
    }
    Ok(out)
}

/// The mesh triangles of written step `step` (none when the run wrote no `.vtu` for it).
pub fn elements(dir: &Path, step: usize) -> Result<Vec<Element>, ResultsError> {
    let path = dir.join("vtk").join(format!("step_{step:06}.vtu"));
    if !path.exists() {
        return Ok(Vec::new());
    }
    let a = arrays(&path, &["Points", "connectivity", "offsets", "kind", "stress"])?;
    let (points, ids, offsets, kind, stress) = (&a[0], &a[1], &a[2], &a[3], &a[4]);
    let point = |i: f64| {
        let i = i as usize;
        points.get(3 * i..3 * i + 2).map(|p| Vec2::new(p[0], p[1]))
    };
    let mut out = Vec::new();
    for (c, end) in offsets.iter().enumerate().filter(|&(c, _)| kind.get(c) == Some(&30.0)) {
        let end = *end as usize;
        let corners = ids
            .get(end.saturating_sub(3)..end)
            .and_then(|t| Some([point(t[0])?, point(t[1])?, point(t[2])?]));
        let s = stress.get(3 * c..3 * c + 3).map(|s| [s[0], s[1], s[2]]);
        match (corners, s) {
            (Some(corners), Some(s)) => out.push(Element { corners, von_mises: von_mises(s) }),
            _ => return Err(bad(&path, format!("mesh cell {c} out of range"))),
        }
    }
    Ok(out)
}

/// The stress colour range: the step's elements' von Mises stresses and zero.
pub fn stress_range(elements: &[Element]) -> Range {
    Range::of(elements.iter().map(|e| e.von_mises), Some(0.0))
}

/// Draws the elements and the stress colour bar in the box `(x, top)..(x + 18, bottom)`.
pub fn draw_elements<'a>(
    root: &Area<'a>,
    view: &View,
    elements: &[Element],
    bar: (i32, i32, i32),
) -> Result<(), ResultsError> {
    let err = |e: DrawingAreaErrorKind<_>| ResultsError::Draw(e.to_string());
    let range = stress_range(elements);
    let edge = RGBColor(60, 60, 60);
    for e in elements {
        let pts: Vec<(i32, i32)> = e.corners.iter().map(|p| view.px(*p)).collect();
        root.draw(&Polygon::new(pts.clone(), range.colour(e.von_mises).filled())).map_err(err)?;
        let closed = vec![pts[0], pts[1], pts[2], pts[0]];
        root.draw(&PathElement::new(closed, edge.stroke_width(1))).map_err(err)?;
    }
    colour_bar(root, range, "von Mises stress [Pa]", bar.0, bar.1, bar.2).map_err(err)
}
