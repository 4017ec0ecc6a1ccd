//! The cut itself: every outline, trace and joint a constraint of spade's constrained Delaunay
//! triangulation, blocks the regions of triangles no constraint separates (math note §12.3).

use spade::handles::{FixedVertexHandle, OUTER_FACE};
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use super::estimate::Checked;
use super::link::link;
use super::traces::Segment;
use super::{CutError, CutSpec, EdgeSource, Report, clip};

pub(crate) type Cdt = ConstrainedDelaunayTriangulation<Point2<f64>>;

/// Seams are added at most this many times before a block with a hole is an error.
const SEAM_ROUNDS: usize = 16;

/// One block before merges: the outer loop of a region as CDT vertex indices.
#[derive(Debug, Clone)]
pub(crate) struct Region {
    pub verts: Vec<usize>,
    pub edges: Vec<EdgeSource>,
    pub excavation: Option<usize>,
}

/// The cut's topology: vertex positions, their merge rank, the blocks and the seams made.
#[derive(Debug)]
pub(crate) struct Arrangement {
    pub positions: Vec<[f64; 2]>,
    /// The merge rank (math note §12.8): 0 a vertex of the domain, 1 on its outline; 2 and 3 the
    /// same for a removed excavation, 4 and 5 for a kept one; 6 any other. Merged vertices move
    /// to the one of lowest rank (then index).
    pub rank: Vec<u8>,
    pub regions: Vec<Region>,
    pub reports: Vec<Report>,
}

fn pos(cdt: &Cdt, v: FixedVertexHandle) -> [f64; 2] {
    let p = cdt.vertex(v).position();
    [p.x, p.y]
}

fn insert(cdt: &mut Cdt, p: [f64; 2]) -> Result<FixedVertexHandle, CutError> {
    cdt.insert(Point2::new(p[0], p[1])).map_err(|e| CutError::Degenerate {
        at: p,
        message: format!("the triangulation refused a vertex: {e:?}"),
    })
}

/// Adds the segment a -> b as constraints, split at its crossings ([`link`]).
fn add(
    cdt: &mut Cdt,
    a: [f64; 2],
    b: [f64; 2],
    snap: f64,
    reports: &mut Vec<Report>,
) -> Result<(), CutError> {
    let (u, v) = (insert(cdt, a)?, insert(cdt, b)?);
    link(cdt, u, v, snap, reports)
}

/// Cuts the domain by every segment and returns its blocks.
pub(crate) fn build(
    spec: &CutSpec,
    checked: &Checked,
    segments: &[Segment],
) -> Result<Arrangement, CutError> {
    let mut cdt = Cdt::new();
    let mut inputs: Vec<Segment> = Vec::new();
    let mut corners = Vec::new();
    let mut reports = Vec::new();
    // a few dozen ulps of the coordinates (of the domain's size, or of their magnitude where
    // the domain lies far from the origin): far below the 1e-9 D the trace ends reach past a
    // line (§12.1), which a larger snap would pull the line onto
    let magnitude = checked.lo.iter().chain(&checked.hi).fold(0.0_f64, |m, c| m.max(c.abs()));
    let snap = 1e-14 * checked.scale.max(magnitude);
    let mut polygon = |poly: &[[f64; 2]], source: EdgeSource, cdt: &mut Cdt, reports: &mut Vec<Report>| {
        // the domain's corners first, then a removed excavation's, then a kept one's (§12.8)
        let rank = outline_rank(spec, source) - 1;
        for i in 0..poly.len() {
            let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
            corners.push((insert(cdt, a)?, rank));
            add(cdt, a, b, snap, reports)?;
            inputs.push(Segment { a, b, source });
        }
        Ok::<(), CutError>(())
    };
    polygon(&checked.domain, EdgeSource::Outline, &mut cdt, &mut reports)?;
    for (i, e) in checked.excavations.iter().enumerate() {
        polygon(e, EdgeSource::Excavation(i), &mut cdt, &mut reports)?;
    }
    for s in segments {
        add(&mut cdt, s.a, s.b, snap, &mut reports)?;
        inputs.push(*s);
    }
    for _ in 0..SEAM_ROUNDS {
        let regions = regions(spec, checked, &cdt)?;
        let mut seams = Vec::new();
        for r in &regions {
            let holes = holes_of(&cdt, &r.loops);
            if !holes.is_empty() {
                seams.extend(seams_for(&cdt, &r.loops, &holes, checked.reach));
            }
        }
        if seams.is_empty() {
            return finish(&cdt, spec, checked, &inputs, &corners, regions, reports);
        }
        for (a, b) in seams {
            let (pa, pb) = (pos(&cdt, a), b);
            let vb = insert(&mut cdt, pb)?;
            link(&mut cdt, a, vb, snap, &mut reports)?;
            inputs.push(Segment { a: pa, b: pb, source: EdgeSource::Seam });
            reports.push(Report::Seam { from: pa, to: pb });
        }
    }
    let at = checked.domain[0];
    Err(CutError::Degenerate { at, message: "a block with a hole could not be cut by seams".into() })
}

/// A directed constraint edge of a region's boundary: from, to (CDT vertex indices).
type Edge = (FixedVertexHandle, FixedVertexHandle);

struct Found {
    loops: Vec<Vec<Edge>>,
    excavation: Option<usize>,
}

/// The kept regions (inside the domain, outside every removed excavation) and their boundary
/// loops, the outer (counter-clockwise) loop first.
fn regions(spec: &CutSpec, checked: &Checked, cdt: &Cdt) -> Result<Vec<Found>, CutError> {
    let nf = cdt.num_all_faces();
    let mut region = vec![usize::MAX; nf];
    let mut best: Vec<(f64, [f64; 2])> = Vec::new();
    let mut stack = Vec::new();
    for face in cdt.inner_faces() {
        let start = face.fix().index();
        if region[start] != usize::MAX {
            continue;
        }
        let id = best.len();
        best.push((-1.0, [0.0; 2]));
        region[start] = id;
        stack.push(face.fix());
        while let Some(f) = stack.pop() {
            let f = cdt.face(f);
            let area = f.area();
            if area > best[id].0 {
                let c = f.center();
                best[id] = (area, [c.x, c.y]);
            }
            for e in f.adjacent_edges() {
                if e.is_constraint_edge() {
                    continue;
                }
                if let Some(g) = e.rev().face().as_inner()
                    && region[g.fix().index()] == usize::MAX
                {
                    region[g.fix().index()] = id;
                    stack.push(g.fix());
                }
            }
        }
    }
    // which regions are kept, and their excavation tags
    let mut tag: Vec<Option<Option<usize>>> = Vec::with_capacity(best.len());
    for &(_, c) in &best {
        let mut t = Some(None);
        if !clip::inside(c, &checked.domain) {
            t = None;
        }
        for (i, e) in spec.excavations.iter().enumerate() {
            if t.is_some() && clip::inside(c, &checked.excavations[i]) {
                t = if e.keep { Some(t.flatten().or(Some(i))) } else { None };
            }
        }
        tag.push(t);
    }
    let region_of = |f: spade::handles::FixedFaceHandle<spade::handles::PossiblyOuterTag>| {
        if f == OUTER_FACE { usize::MAX } else { region[f.index()] }
    };
    // boundary edges of kept regions, grouped by region
    let mut boundary: Vec<Vec<spade::handles::FixedDirectedEdgeHandle>> = vec![Vec::new(); best.len()];
    for e in cdt.directed_edges() {
        if !e.is_constraint_edge() {
            continue;
        }
        let r = region_of(e.face().fix());
        if r == usize::MAX || tag[r].is_none() || region_of(e.rev().face().fix()) == r {
            continue;
        }
        boundary[r].push(e.fix());
    }
    let mut out = Vec::new();
    for (r, edges) in boundary.into_iter().enumerate() {
        let Some(excavation) = tag[r] else { continue };
        let loops = walk(cdt, &region, r, edges)?;
        out.push(Found { loops, excavation });
    }
    Ok(out)
}

/// The boundary loops of region `r` from its boundary edges; the loop of largest signed area
/// (the outer, counter-clockwise one) first.
fn walk(
    cdt: &Cdt,
    region: &[usize],
    r: usize,
    edges: Vec<spade::handles::FixedDirectedEdgeHandle>,
) -> Result<Vec<Vec<Edge>>, CutError> {
    let is_boundary = |e: spade::handles::DirectedEdgeHandle<'_, Point2<f64>, (), spade::CdtEdge<()>, ()>| {
        e.is_constraint_edge() && {
            let g = e.rev().face().fix();
            g == OUTER_FACE || region[g.index()] != r
        }
    };
    let mut used = std::collections::HashSet::new();
    let mut loops: Vec<(f64, Vec<Edge>)> = Vec::new();
    for &start in &edges {
        if used.contains(&start) {
            continue;
        }
        let mut lp = Vec::new();
        let mut e = cdt.directed_edge(start);
        let mut area2 = 0.0;
        loop {
            if !used.insert(e.fix()) {
                if e.fix() == start {
                    break;
                }
                let p = pos(cdt, e.from().fix());
                return Err(CutError::Degenerate { at: p, message: "a block outline does not close".into() });
            }
            let (a, b) = (e.from().position(), e.to().position());
            area2 += a.x * b.y - a.y * b.x;
            lp.push((e.from().fix(), e.to().fix()));
            let mut f = e.next();
            let mut turns = 0;
            while !is_boundary(f) {
                f = f.rev().next();
                turns += 1;
                if turns > 10_000_000 {
                    let p = pos(cdt, f.from().fix());
                    return Err(CutError::Degenerate {
                        at: p,
                        message: "a block outline does not close".into(),
                    });
                }
            }
            e = f;
        }
        loops.push((area2, lp));
    }
    loops.sort_by(|a, b| b.0.total_cmp(&a.0));
    Ok(loops.into_iter().map(|l| l.1).collect())
}

/// The holes of a region: its inner loops, and the clockwise parts of its outer loop where that
/// touches itself (a hole that meets the outline at one vertex), less the vertices it touches
/// itself at.
fn holes_of(cdt: &Cdt, loops: &[Vec<Edge>]) -> Vec<Vec<FixedVertexHandle>> {
    let mut holes: Vec<Vec<FixedVertexHandle>> =
        loops[1..].iter().map(|l| l.iter().map(|e| e.0).collect()).collect();
    let outer = &loops[0];
    let mut count: std::collections::HashMap<FixedVertexHandle, usize> = std::collections::HashMap::new();
    for e in outer {
        *count.entry(e.0).or_insert(0) += 1;
    }
    if count.values().all(|&c| c == 1) {
        return holes;
    }
    let mut stack: Vec<FixedVertexHandle> = Vec::new();
    let mut parts: Vec<Vec<FixedVertexHandle>> = Vec::new();
    for e in outer {
        if let Some(k) = stack.iter().position(|&v| v == e.0) {
            parts.push(stack.drain(k..).collect());
        }
        stack.push(e.0);
    }
    parts.push(stack);
    for part in parts {
        let area2: f64 = (0..part.len())
            .map(|i| {
                let (p, q) = (pos(cdt, part[i]), pos(cdt, part[(i + 1) % part.len()]));
                p[0] * q[1] - p[1] * q[0]
            })
            .sum();
        if area2 < 0.0 {
            holes.push(part.into_iter().filter(|v| count[v] == 1).collect());
        }
    }
    holes
}

/// Two seams for each hole of a region: from the hole's rightmost vertex towards +x and from its
/// leftmost towards -x, each to `reach` past the first boundary edge of the region they meet.
fn seams_for(
    cdt: &Cdt,
    loops: &[Vec<Edge>],
    holes: &[Vec<FixedVertexHandle>],
    reach: f64,
) -> Vec<(FixedVertexHandle, [f64; 2])> {
    let segs: Vec<([f64; 2], [f64; 2], FixedVertexHandle, FixedVertexHandle)> =
        loops.iter().flatten().map(|&(a, b)| (pos(cdt, a), pos(cdt, b), a, b)).collect();
    let mut out = Vec::new();
    for hole in holes {
        for dir in [1.0, -1.0] {
            let key = |v: FixedVertexHandle| {
                let p = pos(cdt, v);
                (dir * p[0], dir * p[1])
            };
            let Some(h) = hole.iter().copied().max_by(|&a, &b| {
                let (ka, kb) = (key(a), key(b));
                ka.0.total_cmp(&kb.0).then(ka.1.total_cmp(&kb.1))
            }) else {
                continue;
            };
            let p = pos(cdt, h);
            let mut hit: Option<(f64, [f64; 2])> = None;
            for &(a, b, va, vb) in &segs {
                if va == h || vb == h || (a[1] - p[1]) * (b[1] - p[1]) > 0.0 || a[1] == b[1] {
                    continue;
                }
                let t = (p[1] - a[1]) / (b[1] - a[1]);
                let x = a[0] + t * (b[0] - a[0]);
                let d = dir * (x - p[0]);
                if d > 0.0 && hit.is_none_or(|(best, _)| d < best) {
                    hit = Some((d, [x, p[1]]));
                }
            }
            // a little past the boundary, so that the seam crosses it (and is split there)
            if let Some((_, q)) = hit {
                out.push((h, [q[0] + dir * reach, q[1]]));
            }
        }
    }
    out
}

/// The merge rank of a vertex on an edge of `source` (math note §12.8): 1 on the domain's
/// outline, 3 on a removed excavation's, 5 on a kept one's, 6 elsewhere; a corner of the outline
/// ranks one lower.
fn outline_rank(spec: &CutSpec, source: EdgeSource) -> u8 {
    match source {
        EdgeSource::Outline => 1,
        EdgeSource::Excavation(i) if !spec.excavations[i].keep => 3,
        EdgeSource::Excavation(_) => 5,
        _ => 6,
    }
}

/// Edge sources, vertex ranks and the regions as vertex loops.
fn finish(
    cdt: &Cdt,
    spec: &CutSpec,
    checked: &Checked,
    inputs: &[Segment],
    corners: &[(FixedVertexHandle, u8)],
    found: Vec<Found>,
    reports: Vec<Report>,
) -> Result<Arrangement, CutError> {
    let positions: Vec<[f64; 2]> = cdt.vertices().map(|v| [v.position().x, v.position().y]).collect();
    let mut rank = vec![6u8; positions.len()];
    let grid = super::polish::SegmentGrid::new(inputs, checked);
    let mut regions = Vec::with_capacity(found.len());
    for f in found {
        let lp = &f.loops[0];
        let mut verts = Vec::with_capacity(lp.len());
        let mut edges = Vec::with_capacity(lp.len());
        for &(a, b) in lp {
            let (pa, pb) = (positions[a.index()], positions[b.index()]);
            let source = grid.source(pa, pb).ok_or_else(|| CutError::Degenerate {
                at: pa,
                message: "a block edge lies on no trace, joint or outline".into(),
            })?;
            let on = outline_rank(spec, source);
            rank[a.index()] = rank[a.index()].min(on);
            rank[b.index()] = rank[b.index()].min(on);
            verts.push(a.index());
            edges.push(source);
        }
        regions.push(Region { verts, edges, excavation: f.excavation });
    }
    for &(c, r) in corners {
        rank[c.index()] = rank[c.index()].min(r);
    }
    Ok(Arrangement { positions, rank, regions, reports })
}
