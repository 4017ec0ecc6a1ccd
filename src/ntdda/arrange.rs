//! The blocks that DC (ntdda's `blocks.c`, dc04–dc08) makes from joint lines (math note
//! §12.6): the planar arrangement of the lines (every crossing a vertex), less the pieces that
//! close no block — dangling ends (dc05–dc06 "delete dangling") and bridges that have the same
//! block on both sides — with the bounded faces as blocks and the outer loop as the outline.
//!
//! Vertices closer than `1e-9` of the extent are one vertex; DC's coarser merge radius
//! (1.25 e00 w0) is pbdda's cutter's business (`[domain] min_edge`).

use std::collections::HashMap;

/// One input line and the index of the joint line it came from.
#[derive(Debug, Clone, Copy)]
pub struct Segment {
    pub a: [f64; 2],
    pub b: [f64; 2],
    pub source: usize,
}

/// An edge that survives the pruning.
#[derive(Debug, Clone)]
pub struct Edge {
    pub v: [usize; 2],
    /// Every joint line this edge lies on, lowest first.
    pub sources: Vec<usize>,
    /// The block to the left of v0 -> v1 and to the left of v1 -> v0; `None` outside the outline.
    pub faces: [Option<usize>; 2],
}

/// A block: a counter-clockwise loop of vertex indices.
#[derive(Debug, Clone)]
pub struct Face {
    pub loop_: Vec<usize>,
    pub area: f64,
    pub centroid: [f64; 2],
}

#[derive(Debug, Clone)]
pub struct Arrangement {
    pub vertices: Vec<[f64; 2]>,
    pub edges: Vec<Edge>,
    pub faces: Vec<Face>,
    /// The outline, counter-clockwise (vertex indices).
    pub outline: Vec<usize>,
    /// Distance under which two points are the same.
    pub eps: f64,
}

/// Where a point lies.
#[derive(Debug, Clone, PartialEq)]
pub enum Location {
    Inside(usize),
    /// On the edges of these blocks (lowest first).
    OnEdge(Vec<usize>),
    Outside,
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}
fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}
fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// Signed area and centroid of a closed loop (shoelace).
pub fn area_centroid(p: &[[f64; 2]]) -> (f64, [f64; 2]) {
    let (mut a, mut cx, mut cy) = (0.0, 0.0, 0.0);
    let o = p[0];
    for i in 0..p.len() {
        let (u, v) = (sub(p[i], o), sub(p[(i + 1) % p.len()], o));
        let c = cross(u, v);
        a += c;
        cx += (u[0] + v[0]) * c;
        cy += (u[1] + v[1]) * c;
    }
    if a == 0.0 {
        return (0.0, o);
    }
    (a / 2.0, [o[0] + cx / (3.0 * a), o[1] + cy / (3.0 * a)])
}

/// Distance from `p` to the segment a-b.
pub fn segment_distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let r = sub(b, a);
    let l2 = dot(r, r);
    let t = if l2 > 0.0 { (dot(sub(p, a), r) / l2).clamp(0.0, 1.0) } else { 0.0 };
    let q = [a[0] + t * r[0], a[1] + t * r[1]];
    dot(sub(p, q), sub(p, q)).sqrt()
}

/// Crossing-number test; the boundary is not tested here.
pub fn inside(p: [f64; 2], poly: &[[f64; 2]]) -> bool {
    let mut c = false;
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if p[0] < x {
                c = !c;
            }
        }
    }
    c
}

/// The split parameters of each segment where others cross, touch or overlap it.
fn split_parameters(segs: &[Segment], eps: f64) -> Vec<Vec<f64>> {
    let mut ts: Vec<Vec<f64>> = segs.iter().map(|_| vec![0.0, 1.0]).collect();
    for i in 0..segs.len() {
        let (p, r) = (segs[i].a, sub(segs[i].b, segs[i].a));
        let lr = dot(r, r).sqrt();
        for j in i + 1..segs.len() {
            let (q, s) = (segs[j].a, sub(segs[j].b, segs[j].a));
            let ls = dot(s, s).sqrt();
            let d = cross(r, s);
            if d.abs() > 1e-12 * lr * ls {
                let t = cross(sub(q, p), s) / d;
                let u = cross(sub(q, p), r) / d;
                let (tt, tu) = (eps / lr, eps / ls);
                if t >= -tt && t <= 1.0 + tt && u >= -tu && u <= 1.0 + tu {
                    ts[i].push(t.clamp(0.0, 1.0));
                    ts[j].push(u.clamp(0.0, 1.0));
                }
            } else if cross(sub(q, p), r).abs() / lr <= eps {
                // collinear: each takes the other's ends that lie on it
                for e in [q, segs[j].b] {
                    let t = dot(sub(e, p), r) / (lr * lr);
                    if t > 0.0 && t < 1.0 {
                        ts[i].push(t);
                    }
                }
                for e in [p, segs[i].b] {
                    let u = dot(sub(e, q), s) / (ls * ls);
                    if u > 0.0 && u < 1.0 {
                        ts[j].push(u);
                    }
                }
            }
        }
    }
    ts
}

/// Vertices within `eps` of each other are one (grid hash over cells of `eps`).
struct Snap {
    eps: f64,
    cells: HashMap<(i64, i64), Vec<usize>>,
    points: Vec<[f64; 2]>,
}

impl Snap {
    fn id(&mut self, p: [f64; 2]) -> usize {
        let key = ((p[0] / self.eps).floor() as i64, (p[1] / self.eps).floor() as i64);
        for dx in -1..=1 {
            for dy in -1..=1 {
                if let Some(list) = self.cells.get(&(key.0 + dx, key.1 + dy)) {
                    for &k in list {
                        let d = sub(self.points[k], p);
                        if dot(d, d).sqrt() <= self.eps {
                            return k;
                        }
                    }
                }
            }
        }
        self.points.push(p);
        self.cells.entry(key).or_default().push(self.points.len() - 1);
        self.points.len() - 1
    }
}

/// Builds the arrangement; `Err` says why no single outline exists.
pub fn build(segs: &[Segment]) -> Result<Arrangement, String> {
    let segs: Vec<Segment> = segs.iter().copied().filter(|s| s.a != s.b).collect();
    if segs.is_empty() {
        return Err("no joint line of positive length".into());
    }
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for s in &segs {
        for p in [s.a, s.b] {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
    }
    let extent = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(f64::MIN_POSITIVE);
    let eps = 1e-9 * extent;
    let ts = split_parameters(&segs, eps);
    let mut snap = Snap { eps, cells: HashMap::new(), points: Vec::new() };
    let mut edge_of: HashMap<(usize, usize), usize> = HashMap::new();
    let mut edges: Vec<Edge> = Vec::new();
    for (s, t) in segs.iter().zip(ts) {
        let mut t = t;
        t.sort_by(f64::total_cmp);
        let r = sub(s.b, s.a);
        let ids: Vec<usize> = t.iter().map(|&t| snap.id([s.a[0] + t * r[0], s.a[1] + t * r[1]])).collect();
        for w in ids.windows(2) {
            if w[0] == w[1] {
                continue;
            }
            let key = (w[0].min(w[1]), w[0].max(w[1]));
            let k = *edge_of.entry(key).or_insert_with(|| {
                edges.push(Edge { v: [key.0, key.1], sources: Vec::new(), faces: [None, None] });
                edges.len() - 1
            });
            if !edges[k].sources.contains(&s.source) {
                edges[k].sources.push(s.source);
                edges[k].sources.sort_unstable();
            }
        }
    }
    let vertices = snap.points;
    loop {
        edges = prune_dangling(edges, vertices.len());
        if edges.is_empty() {
            return Err("the joint lines close no block".into());
        }
        let cycles = cycles(&vertices, &edges);
        let mut face_of = vec![usize::MAX; 2 * edges.len()];
        for (c, cyc) in cycles.iter().enumerate() {
            for &h in cyc {
                face_of[h] = c;
            }
        }
        let before = edges.len();
        let bridge: Vec<bool> = (0..edges.len()).map(|e| face_of[2 * e] == face_of[2 * e + 1]).collect();
        let mut k = 0;
        edges.retain(|_| {
            k += 1;
            !bridge[k - 1]
        });
        if edges.len() == before {
            return finish(vertices, edges, cycles, face_of, eps);
        }
    }
}

fn prune_dangling(mut edges: Vec<Edge>, n: usize) -> Vec<Edge> {
    loop {
        let mut degree = vec![0usize; n];
        for e in &edges {
            degree[e.v[0]] += 1;
            degree[e.v[1]] += 1;
        }
        let before = edges.len();
        edges.retain(|e| degree[e.v[0]] > 1 && degree[e.v[1]] > 1);
        if edges.len() == before {
            return edges;
        }
    }
}

/// The face cycles of half-edges (2e: v0 -> v1, 2e + 1: v1 -> v0), each with its face on the left.
fn cycles(vertices: &[[f64; 2]], edges: &[Edge]) -> Vec<Vec<usize>> {
    let head = |h: usize| edges[h / 2].v[1 - h % 2];
    let tail = |h: usize| edges[h / 2].v[h % 2];
    let mut out: Vec<Vec<usize>> = vec![Vec::new(); vertices.len()];
    for h in 0..2 * edges.len() {
        out[tail(h)].push(h);
    }
    let angle = |h: usize| {
        let d = sub(vertices[head(h)], vertices[tail(h)]);
        d[1].atan2(d[0])
    };
    let mut position = vec![0usize; 2 * edges.len()];
    for list in &mut out {
        list.sort_by(|&a, &b| angle(a).total_cmp(&angle(b)));
        for (i, &h) in list.iter().enumerate() {
            position[h] = i;
        }
    }
    let next = |h: usize| {
        let twin = h ^ 1;
        let list = &out[head(h)];
        list[(position[twin] + list.len() - 1) % list.len()]
    };
    let mut seen = vec![false; 2 * edges.len()];
    let mut result = Vec::new();
    for start in 0..2 * edges.len() {
        if seen[start] {
            continue;
        }
        let mut cyc = Vec::new();
        let mut h = start;
        while !seen[h] {
            seen[h] = true;
            cyc.push(h);
            h = next(h);
        }
        result.push(cyc);
    }
    result
}

fn finish(
    vertices: Vec<[f64; 2]>,
    mut edges: Vec<Edge>,
    cycles: Vec<Vec<usize>>,
    face_of: Vec<usize>,
    eps: f64,
) -> Result<Arrangement, String> {
    let tail = |edges: &[Edge], h: usize| edges[h / 2].v[h % 2];
    let mut faces = Vec::new();
    let mut face_index = vec![None; cycles.len()];
    let mut outer = Vec::new();
    for (c, cyc) in cycles.iter().enumerate() {
        let loop_: Vec<usize> = cyc.iter().map(|&h| tail(&edges, h)).collect();
        let pts: Vec<[f64; 2]> = loop_.iter().map(|&v| vertices[v]).collect();
        let (area, centroid) = area_centroid(&pts);
        if area > 0.0 {
            face_index[c] = Some(faces.len());
            faces.push(Face { loop_, area, centroid });
        } else {
            outer.push(loop_);
        }
    }
    if outer.len() != 1 {
        return Err(format!(
            "the joint lines make {} separate groups of blocks (or a group inside a block); \
             pbdda's [domain] is one outline",
            outer.len()
        ));
    }
    for (e, edge) in edges.iter_mut().enumerate() {
        edge.faces = [face_index[face_of[2 * e]], face_index[face_of[2 * e + 1]]];
    }
    let mut outline = outer.pop().unwrap_or_default();
    outline.reverse();
    Ok(Arrangement { vertices, edges, faces, outline, eps })
}

impl Arrangement {
    pub fn points(&self, loop_: &[usize]) -> Vec<[f64; 2]> {
        loop_.iter().map(|&v| self.vertices[v]).collect()
    }

    /// The loop's points without the vertices where it runs straight on, starting at the lowest
    /// (then leftmost) corner.
    pub fn corners(&self, loop_: &[usize]) -> Vec<[f64; 2]> {
        let p = self.points(loop_);
        let n = p.len();
        let mut c: Vec<[f64; 2]> = (0..n)
            .filter(|&i| {
                let (a, b, c) = (p[(i + n - 1) % n], p[i], p[(i + 1) % n]);
                let (u, v) = (sub(b, a), sub(c, b));
                cross(u, v).abs() > self.eps * (dot(u, u).sqrt() + dot(v, v).sqrt()) || dot(u, v) < 0.0
            })
            .map(|i| p[i])
            .collect();
        let first =
            (0..c.len()).min_by(|&a, &b| c[a][1].total_cmp(&c[b][1]).then(c[a][0].total_cmp(&c[b][0])));
        c.rotate_left(first.unwrap_or(0));
        c
    }

    /// The block holding `p`.
    pub fn locate(&self, p: [f64; 2]) -> Location {
        let mut on = Vec::new();
        for (f, face) in self.faces.iter().enumerate() {
            let pts = self.points(&face.loop_);
            let n = pts.len();
            if (0..n).any(|i| segment_distance(p, pts[i], pts[(i + 1) % n]) <= self.eps) {
                on.push(f);
            } else if inside(p, &pts) {
                return Location::Inside(f);
            }
        }
        if on.is_empty() { Location::Outside } else { Location::OnEdge(on) }
    }

    /// A point strictly inside the block: the centroid of its first ear (a convex corner whose
    /// triangle holds no other vertex; every simple polygon has one).
    pub fn interior_point(&self, face: usize) -> [f64; 2] {
        let p = self.points(&self.faces[face].loop_);
        let n = p.len();
        for i in 0..n {
            let (a, b, c) = (p[(i + n - 1) % n], p[i], p[(i + 1) % n]);
            if cross(sub(b, a), sub(c, b)) <= 0.0 {
                continue;
            }
            let tri = [a, b, c];
            let blocked = (0..n).any(|k| {
                k != i && k != (i + n - 1) % n && k != (i + 1) % n && {
                    let q = p[k];
                    inside(q, &tri)
                        || (0..3).any(|m| segment_distance(q, tri[m], tri[(m + 1) % 3]) <= self.eps)
                }
            });
            if !blocked {
                return [(a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0];
            }
        }
        self.faces[face].centroid
    }
}
