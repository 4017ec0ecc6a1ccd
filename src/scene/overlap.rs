//! Bodies that lie inside another body at t = 0 (two identical blocks at the same place, a disk
//! inside a fixed floor). Contact detection looks for features within the threshold of each
//! other (math note §5); a body wholly inside another has none, so the pair would never touch.
//!
//! Test (cheap, broad-phase style): body A is inside body B when A's bounding box lies within
//! B's and A's reference point (centre of a particle, centroid of a polygon) lies in B's shape.
//! Candidates come from a uniform grid of the reference points, queried with each body's
//! box: O(N) for bodies of similar size, never all pairs.

use std::collections::HashMap;

use super::check::{Check, fail};
use super::limits::aabb;
use super::raw;
use crate::geometry::{Aabb, Vec2, polygon_moments};
use crate::model::{BodySpec, Shape};

/// The point that must not lie inside another body.
fn reference_point(shape: &Shape) -> Vec2 {
    match shape {
        Shape::Disk { center, .. } | Shape::Ring { center, .. } => *center,
        Shape::Polygon { vertices } => polygon_moments(vertices).centroid,
        Shape::Mesh(mesh) => {
            let tris = super::limits::mesh_triangles(mesh);
            let moments: Vec<_> = tris.iter().map(|t| polygon_moments(t)).collect();
            let area: f64 = moments.iter().map(|m| m.area.abs()).sum();
            moments.iter().map(|m| m.centroid * m.area.abs()).sum::<Vec2>() / area
        }
    }
}

/// Whether `inner` lies within `outer` (with a relative slack for round-off).
fn box_within(inner: &Aabb, outer: &Aabb) -> bool {
    let slack = 1e-9 * (outer.max - outer.min).norm();
    let o = outer.inflated(slack);
    o.min.x <= inner.min.x && o.min.y <= inner.min.y && inner.max.x <= o.max.x && inner.max.y <= o.max.y
}

/// Uniform grid of points: about one point per cell.
struct PointGrid {
    origin: Vec2,
    cell: f64,
    cells: HashMap<(i64, i64), Vec<usize>>,
}

impl PointGrid {
    fn new(points: &[Vec2]) -> PointGrid {
        let b = Aabb::of_points(points);
        let span = (b.max - b.min).amax();
        let cell = if span > 0.0 { span / (points.len() as f64).sqrt() } else { 1.0 };
        let mut grid = PointGrid { origin: b.min, cell, cells: HashMap::new() };
        for (i, p) in points.iter().enumerate() {
            let key = grid.key(*p);
            grid.cells.entry(key).or_default().push(i);
        }
        grid
    }

    fn key(&self, p: Vec2) -> (i64, i64) {
        let k = |x: f64, o: f64| ((x - o) / self.cell).floor().clamp(-1e15, 1e15) as i64;
        (k(p.x, self.origin.x), k(p.y, self.origin.y))
    }

    /// Indices of the points in the cells that `b` covers (a superset of those in `b`).
    fn query(&self, b: &Aabb, mut visit: impl FnMut(usize) -> Check<()>) -> Check<()> {
        let (lo, hi) = (self.key(b.min), self.key(b.max));
        let covered = (hi.0 - lo.0 + 1) as f64 * (hi.1 - lo.1 + 1) as f64;
        if covered > self.cells.len() as f64 {
            // a box larger than the scene: walk the occupied cells instead
            for (&(x, y), list) in &self.cells {
                if (lo.0..=hi.0).contains(&x) && (lo.1..=hi.1).contains(&y) {
                    list.iter().try_for_each(|&i| visit(i))?;
                }
            }
            return Ok(());
        }
        for x in lo.0..=hi.0 {
            for y in lo.1..=hi.1 {
                if let Some(list) = self.cells.get(&(x, y)) {
                    list.iter().try_for_each(|&i| visit(i))?;
                }
            }
        }
        Ok(())
    }
}

/// Fails at the first body found inside another, naming both.
pub(super) fn no_body_inside_another(specs: &[BodySpec], raw: &[toml::Spanned<raw::Body>]) -> Check<()> {
    let points: Vec<Vec2> = specs.iter().map(|s| reference_point(&s.shape)).collect();
    let boxes: Vec<Aabb> = specs.iter().map(|s| aabb(&s.shape)).collect();
    let grid = PointGrid::new(&points);
    for (b, outer) in specs.iter().enumerate() {
        grid.query(&boxes[b], |a| {
            if a == b || !box_within(&boxes[a], &boxes[b]) || !outer.shape.contains(points[a]) {
                return Ok(());
            }
            // report at the later of the two bodies
            let second = a.max(b);
            let (inner, outer_name) = (&specs[a].name, &outer.name);
            let message = format!(
                "body \"{inner}\" lies inside body \"{outer_name}\" at t = 0 (its {} is inside it): \
                 contact detection cannot see a body wholly inside another",
                if matches!(specs[a].shape, Shape::Polygon { .. }) { "centroid" } else { "centre" }
            );
            let r = raw[second].get_ref();
            let span = r.center.as_ref().map(|c| c.span()).or(r.vertices.as_ref().map(|v| v.span()));
            fail(span.unwrap_or(raw[second].span()), message)
        })?;
    }
    Ok(())
}
