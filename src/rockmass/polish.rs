//! From the cut's regions to blocks: edge sources, merges of close vertices, joins of thin
//! blocks, removal of straight-through vertices, the block order (math note §12.3, §12.4).

use std::collections::HashMap;

use super::arrange::Arrangement;
use super::estimate::Checked;
use super::join::{Poly, join_thin};
use super::traces::Segment;
use super::{Block, Cut, CutError, CutSpec, EdgeSource, Report};
use crate::geometry::{Vec2, check_simple_polygon};

/// Input segments bucketed on a grid, to find which one a cut edge lies on.
pub(crate) struct SegmentGrid<'a> {
    inputs: &'a [Segment],
    lo: [f64; 2],
    cell: f64,
    nx: usize,
    ny: usize,
    cells: Vec<Vec<u32>>,
    tol: f64,
}

impl<'a> SegmentGrid<'a> {
    pub(crate) fn new(inputs: &'a [Segment], checked: &Checked) -> Self {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for s in inputs {
            for p in [s.a, s.b] {
                for k in 0..2 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
        }
        let extent = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(checked.scale * 1e-6);
        let per_side = ((inputs.len() as f64).sqrt().ceil() as usize).clamp(1, 1000);
        let cell = extent / per_side as f64 * 1.000001;
        let (nx, ny) = (per_side + 1, per_side + 1);
        let mut cells = vec![Vec::new(); nx * ny];
        let mut grid = Self { inputs, lo, cell, nx, ny, cells: Vec::new(), tol: 1e-7 * checked.scale };
        for (k, s) in inputs.iter().enumerate() {
            let length = (s.b[0] - s.a[0]).hypot(s.b[1] - s.a[1]);
            let steps = (2.0 * length / cell).ceil() as usize + 1;
            let mut last = usize::MAX;
            for i in 0..=steps {
                let t = i as f64 / steps as f64;
                let c = grid.cell_of([s.a[0] + t * (s.b[0] - s.a[0]), s.a[1] + t * (s.b[1] - s.a[1])]);
                if c != last {
                    cells[c].push(k as u32);
                    last = c;
                }
            }
        }
        grid.cells = cells;
        grid
    }

    fn ij(&self, p: [f64; 2]) -> (usize, usize) {
        let i = ((p[0] - self.lo[0]) / self.cell).floor().clamp(0.0, (self.nx - 1) as f64) as usize;
        let j = ((p[1] - self.lo[1]) / self.cell).floor().clamp(0.0, (self.ny - 1) as f64) as usize;
        (i, j)
    }

    fn cell_of(&self, p: [f64; 2]) -> usize {
        let (i, j) = self.ij(p);
        j * self.nx + i
    }

    /// The source of the cut edge `a`-`b`: of the input segments it lies on (both ends within
    /// 1e-7 of the domain's size of the segment's line, its midpoint within the segment), the
    /// first in [`EdgeSource`]'s order.
    ///
    /// An edge on none of them (spade may route a split constraint through an existing vertex
    /// close to the crossing, math note §12.3) takes the source of the segment nearest to its
    /// midpoint.
    pub(crate) fn source(&self, a: [f64; 2], b: [f64; 2]) -> Option<EdgeSource> {
        let m = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
        self.on_source(a, b, m).or_else(|| self.nearest(m))
    }

    fn nearest(&self, m: [f64; 2]) -> Option<EdgeSource> {
        let distance = |s: &Segment| {
            let d = [s.b[0] - s.a[0], s.b[1] - s.a[1]];
            let dd = d[0] * d[0] + d[1] * d[1];
            let t = if dd > 0.0 {
                (((m[0] - s.a[0]) * d[0] + (m[1] - s.a[1]) * d[1]) / dd).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (m[0] - s.a[0] - t * d[0]).hypot(m[1] - s.a[1] - t * d[1])
        };
        self.inputs
            .iter()
            .min_by(|p, q| distance(p).total_cmp(&distance(q)).then(p.source.cmp(&q.source)))
            .map(|s| s.source)
    }

    fn on_source(&self, a: [f64; 2], b: [f64; 2], m: [f64; 2]) -> Option<EdgeSource> {
        let (i, j) = self.ij(m);
        let mut best: Option<EdgeSource> = None;
        for jj in j.saturating_sub(1)..=(j + 1).min(self.ny - 1) {
            for ii in i.saturating_sub(1)..=(i + 1).min(self.nx - 1) {
                for &k in &self.cells[jj * self.nx + ii] {
                    let s = &self.inputs[k as usize];
                    if best.is_some_and(|b| b <= s.source) || !self.on(s, a, b, m) {
                        continue;
                    }
                    best = Some(s.source);
                }
            }
        }
        best
    }

    fn on(&self, s: &Segment, a: [f64; 2], b: [f64; 2], m: [f64; 2]) -> bool {
        let d = [s.b[0] - s.a[0], s.b[1] - s.a[1]];
        let l = d[0].hypot(d[1]);
        if l == 0.0 {
            return false;
        }
        let off = |p: [f64; 2]| ((p[0] - s.a[0]) * d[1] - (p[1] - s.a[1]) * d[0]).abs() / l;
        let along = ((m[0] - s.a[0]) * d[0] + (m[1] - s.a[1]) * d[1]) / l;
        off(a) <= self.tol && off(b) <= self.tol && along >= -self.tol && along <= l + self.tol
    }
}

/// Merges, joins, clean-up and the block order.
pub(crate) fn finish(spec: &CutSpec, checked: &Checked, arr: Arrangement) -> Result<Cut, CutError> {
    let Arrangement { positions, rank, regions, mut reports } = arr;
    let rep = merge_vertices(&positions, &rank, &regions, checked.merge, &mut reports);
    let mut polys = Vec::new();
    for r in regions {
        let verts: Vec<usize> = r.verts.iter().map(|&v| rep[v]).collect();
        split_pinches(&positions, verts, r.edges, r.excavation, &mut polys, &mut reports)?;
    }
    if spec.min_edge > 0.0 {
        join_thin(&positions, &mut polys, spec.min_edge, &mut reports);
    }
    let mut blocks = Vec::with_capacity(polys.len());
    for p in polys.into_iter().filter(|p| p.alive) {
        let (mut verts, mut edges) = straighten(&positions, p.verts, p.edges);
        // each loop from its lowest, then leftmost, vertex (math note §12.4): the output does
        // not depend on where the triangulation's walk began
        let yx = |i: &usize, j: &usize| {
            let (a, b) = (positions[verts[*i]], positions[verts[*j]]);
            a[1].total_cmp(&b[1]).then(a[0].total_cmp(&b[0]))
        };
        let start = (0..verts.len()).min_by(yx).unwrap_or(0);
        verts.rotate_left(start);
        edges.rotate_left(start);
        blocks.push(block(&positions, &verts, edges, p.excavation)?);
    }
    blocks.sort_by(super::block_order);
    Ok(Cut { blocks, reports })
}

/// The merge of close vertices (math note §12.3, §12.8), without chains: the used vertices in
/// order of (rank, index); each one closer than `tol` to no centre so far is a centre. Every
/// other vertex moves to the centre of lowest rank, then nearest, then lowest index, of those
/// closer than `tol` to it. So no vertex moves by `tol` or more, and two centres are at least
/// `tol` apart. One report per centre that took another vertex.
fn merge_vertices(
    positions: &[[f64; 2]],
    rank: &[u8],
    regions: &[super::arrange::Region],
    tol: f64,
    reports: &mut Vec<Report>,
) -> Vec<usize> {
    let mut used: Vec<usize> = regions.iter().flat_map(|r| r.verts.iter().copied()).collect();
    used.sort_unstable_by_key(|&v| (rank[v], v));
    used.dedup();
    let key = |p: [f64; 2]| cell(p, tol);
    let dist = |v: usize, w: usize| distance(positions, v, w);
    let mut centres: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    for &v in &used {
        if near(&centres, positions, tol, v).next().is_none() {
            centres.entry(key(positions[v])).or_default().push(v);
        }
    }
    let mut rep: Vec<usize> = (0..positions.len()).collect();
    let mut taken: HashMap<usize, (usize, f64)> = HashMap::new();
    for &v in &used {
        let best = near(&centres, positions, tol, v)
            .min_by(|&a, &b| rank[a].cmp(&rank[b]).then(dist(v, a).total_cmp(&dist(v, b))).then(a.cmp(&b)));
        if let Some(c) = best.filter(|&c| c != v) {
            rep[v] = c;
            let e = taken.entry(c).or_insert((1, 0.0));
            e.0 += 1;
            e.1 = e.1.max(dist(v, c));
        }
    }
    let mut list: Vec<(usize, (usize, f64))> = taken.into_iter().collect();
    list.sort_unstable_by_key(|c| (rank[c.0], c.0));
    for (c, (count, distance)) in list {
        reports.push(Report::MergedVertices { count, distance, at: positions[c] });
    }
    rep
}

/// The merge grid's cell of side `tol` that holds `p`.
fn cell(p: [f64; 2], tol: f64) -> (i64, i64) {
    ((p[0] / tol).floor() as i64, (p[1] / tol).floor() as i64)
}

fn distance(positions: &[[f64; 2]], v: usize, w: usize) -> f64 {
    (positions[v][0] - positions[w][0]).hypot(positions[v][1] - positions[w][1])
}

/// The centres closer than `tol` to vertex `v`, from the 3 x 3 cells around it.
fn near<'a>(
    centres: &'a HashMap<(i64, i64), Vec<usize>>,
    positions: &'a [[f64; 2]],
    tol: f64,
    v: usize,
) -> impl Iterator<Item = usize> + 'a {
    let (i, j) = cell(positions[v], tol);
    let cells = (-1..=1).flat_map(move |di| (-1..=1).map(move |dj| (i + di, j + dj)));
    cells.filter_map(|c| centres.get(&c)).flatten().copied().filter(move |&c| distance(positions, v, c) < tol)
}

/// Drops edges whose ends merged and splits a loop that now touches itself into simple loops.
/// A loop of no positive area is dropped (reported) when it is a fold, of area at most
/// `1e-13 l^2` (`l` its longest edge; rounding); a clockwise loop of more area is a hole the
/// merges have pinched off (other blocks fill it, so dropping it would count their area twice):
/// the cut is refused (math note §12.8).
fn split_pinches(
    positions: &[[f64; 2]],
    verts: Vec<usize>,
    edges: Vec<EdgeSource>,
    excavation: Option<usize>,
    out: &mut Vec<Poly>,
    reports: &mut Vec<Report>,
) -> Result<(), CutError> {
    let n = verts.len();
    let mut stack: Vec<(usize, EdgeSource)> = Vec::with_capacity(n);
    let mut at: HashMap<usize, usize> = HashMap::new();
    let mut emit = |lp: Vec<(usize, EdgeSource)>, out: &mut Vec<Poly>| {
        let vs: Vec<usize> = lp.iter().map(|e| e.0).collect();
        let a = area2(positions, &vs) / 2.0;
        if vs.len() >= 3 && a > 0.0 {
            out.push(Poly { verts: vs, edges: lp.iter().map(|e| e.1).collect(), excavation, alive: true });
            return Ok(());
        }
        let Some(&first) = vs.first() else { return Ok(()) };
        let longest = (0..vs.len())
            .map(|i| {
                let (p, q) = (positions[vs[i]], positions[vs[(i + 1) % vs.len()]]);
                (q[0] - p[0]).hypot(q[1] - p[1])
            })
            .fold(0.0, f64::max);
        if -a > 1e-13 * longest * longest {
            return Err(CutError::Degenerate {
                at: positions[first],
                message: format!(
                    "merging vertices closer than the merge distance (min_edge) pinches off a hole of \
                     area {:.3e} m2 in a block; lower min_edge",
                    -a
                ),
            });
        }
        reports.push(Report::DroppedSliver { area: a.abs(), at: positions[first] });
        Ok(())
    };
    for i in 0..n {
        let (v, w) = (verts[i], verts[(i + 1) % n]);
        if v == w {
            continue;
        }
        if let Some(&k) = at.get(&v) {
            let lp: Vec<(usize, EdgeSource)> = stack.drain(k..).collect();
            for e in &lp {
                at.remove(&e.0);
            }
            emit(lp, out)?;
        }
        at.insert(v, stack.len());
        stack.push((v, edges[i]));
    }
    emit(stack, out)
}

pub(crate) fn area2(positions: &[[f64; 2]], verts: &[usize]) -> f64 {
    let n = verts.len();
    if n == 0 {
        return 0.0;
    }
    let o = positions[verts[0]];
    let mut s = 0.0;
    for i in 1..n.saturating_sub(1) {
        let (p, q) = (positions[verts[i]], positions[verts[i + 1]]);
        s += (p[0] - o[0]) * (q[1] - o[1]) - (p[1] - o[1]) * (q[0] - o[0]);
    }
    s
}

/// Removes vertices where the outline runs straight on between edges of one source, or folds
/// straight back, to 1e-10 in the sine of the turn; a folded edge keeps the first of the two
/// sources. A straight-through vertex between two sources (a trace piece and its cemented
/// bridge) stays, so that each edge has one source.
fn straighten(
    positions: &[[f64; 2]],
    mut verts: Vec<usize>,
    mut edges: Vec<EdgeSource>,
) -> (Vec<usize>, Vec<EdgeSource>) {
    let mut changed = true;
    while changed && verts.len() > 3 {
        changed = false;
        let mut i = 0;
        while i < verts.len() && verts.len() > 3 {
            let n = verts.len();
            let (a, b, c) =
                (positions[verts[(i + n - 1) % n]], positions[verts[i]], positions[verts[(i + 1) % n]]);
            let u = [b[0] - a[0], b[1] - a[1]];
            let w = [c[0] - b[0], c[1] - b[1]];
            let cross = u[0] * w[1] - u[1] * w[0];
            let prev = (i + n - 1) % n;
            let straight = cross.abs() <= 1e-10 * u[0].hypot(u[1]) * w[0].hypot(w[1]);
            let folds = u[0] * w[0] + u[1] * w[1] < 0.0;
            if straight && (folds || edges[prev] == edges[i]) {
                edges[prev] = edges[prev].min(edges[i]);
                verts.remove(i);
                edges.remove(i);
                changed = true;
            } else {
                i += 1;
            }
        }
    }
    (verts, edges)
}

fn block(
    positions: &[[f64; 2]],
    verts: &[usize],
    edges: Vec<EdgeSource>,
    excavation: Option<usize>,
) -> Result<Block, CutError> {
    let vertices: Vec<[f64; 2]> = verts.iter().map(|&v| positions[v]).collect();
    let o = vertices[0];
    let (mut a2, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for i in 1..vertices.len() - 1 {
        let (p, q) = (vertices[i], vertices[i + 1]);
        let (px, py, qx, qy) = (p[0] - o[0], p[1] - o[1], q[0] - o[0], q[1] - o[1]);
        let c = px * qy - py * qx;
        a2 += c;
        cx += (px + qx) * c;
        cy += (py + qy) * c;
    }
    let area = a2 / 2.0;
    let centroid = [o[0] + cx / (3.0 * a2), o[1] + cy / (3.0 * a2)];
    let pts: Vec<Vec2> = vertices.iter().map(|p| Vec2::new(p[0], p[1])).collect();
    if let Err(defect) = check_simple_polygon(&pts) {
        return Err(CutError::Degenerate {
            at: centroid,
            message: format!(
                "a block is not a simple polygon after merging vertices ({defect:?}); try another min_edge"
            ),
        });
    }
    if area.is_nan() || area <= 0.0 {
        return Err(CutError::Degenerate { at: o, message: "a block has no positive area".into() });
    }
    Ok(Block { vertices, edges, area, centroid, excavation })
}
