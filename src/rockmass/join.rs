//! Joins of blocks thinner than `min_edge` to a neighbour (math note §12.3).

use std::collections::HashMap;

use super::polish::area2;
use super::{EdgeSource, Report};

/// A block as a loop of vertex ids.
#[derive(Debug, Clone)]
pub(crate) struct Poly {
    pub verts: Vec<usize>,
    pub edges: Vec<EdgeSource>,
    pub excavation: Option<usize>,
    pub alive: bool,
}

fn dist(p: [f64; 2], q: [f64; 2]) -> f64 {
    (p[0] - q[0]).hypot(p[1] - q[1])
}

/// Thickness (area / longest edge), area and centroid of a loop.
fn measure(positions: &[[f64; 2]], p: &Poly) -> (f64, f64, [f64; 2]) {
    let n = p.verts.len();
    let at = |i: usize| positions[p.verts[i % n]];
    let longest = (0..n).map(|i| dist(at(i), at(i + 1))).fold(0.0, f64::max);
    let area = area2(positions, &p.verts) / 2.0;
    let mut c = [0.0; 2];
    for i in 0..n {
        c[0] += at(i)[0] / n as f64;
        c[1] += at(i)[1] / n as f64;
    }
    (area / longest, area, c)
}

/// The union of loops `a` and `b`: their edges less the pairs they share, walked as one loop;
/// `None` if that is not one simple loop of vertex ids.
fn union(a: &Poly, b: &Poly) -> Option<Poly> {
    let directed = |p: &Poly| -> Vec<(usize, usize, EdgeSource)> {
        let n = p.verts.len();
        (0..n).map(|i| (p.verts[i], p.verts[(i + 1) % n], p.edges[i])).collect()
    };
    let (ea, eb) = (directed(a), directed(b));
    let in_b: std::collections::HashSet<(usize, usize)> = eb.iter().map(|e| (e.0, e.1)).collect();
    let in_a: std::collections::HashSet<(usize, usize)> = ea.iter().map(|e| (e.0, e.1)).collect();
    let rest: Vec<(usize, usize, EdgeSource)> = ea
        .into_iter()
        .filter(|e| !in_b.contains(&(e.1, e.0)))
        .chain(eb.into_iter().filter(|e| !in_a.contains(&(e.1, e.0))))
        .collect();
    let mut next: HashMap<usize, (usize, EdgeSource)> = HashMap::new();
    for e in &rest {
        if next.insert(e.0, (e.1, e.2)).is_some() {
            return None;
        }
    }
    let start = rest.first()?.0;
    let (mut verts, mut edges) = (Vec::new(), Vec::new());
    let mut v = start;
    loop {
        let (w, s) = *next.get(&v)?;
        verts.push(v);
        edges.push(s);
        v = w;
        if v == start || verts.len() > rest.len() {
            break;
        }
    }
    (verts.len() == rest.len() && v == start).then_some(Poly {
        verts,
        edges,
        excavation: a.excavation,
        alive: true,
    })
}

/// Joins every block thinner than `min_edge`, thinnest first, to the neighbour (of the same
/// excavation tag) with which it shares the longest boundary; a block with none is kept. Each
/// join or keep is reported.
pub(crate) fn join_thin(
    positions: &[[f64; 2]],
    polys: &mut [Poly],
    min_edge: f64,
    reports: &mut Vec<Report>,
) {
    let mut owner: HashMap<(usize, usize), usize> = HashMap::new();
    for (k, p) in polys.iter().enumerate() {
        let n = p.verts.len();
        for i in 0..n {
            owner.insert((p.verts[i], p.verts[(i + 1) % n]), k);
        }
    }
    let mut queue: Vec<(f64, usize)> = polys
        .iter()
        .enumerate()
        .map(|(k, p)| (measure(positions, p).0, k))
        .filter(|t| t.0 < min_edge)
        .collect();
    while !queue.is_empty() {
        queue.sort_by(|a, b| b.0.total_cmp(&a.0).then(b.1.cmp(&a.1)));
        let Some((_, i)) = queue.pop() else { break };
        if !polys[i].alive {
            continue;
        }
        let (thickness, area, at) = measure(positions, &polys[i]);
        if thickness >= min_edge {
            continue;
        }
        // shared length and the source of the longest shared edge, per neighbour
        let mut shared: HashMap<usize, (f64, f64, EdgeSource)> = HashMap::new();
        let p = &polys[i];
        let n = p.verts.len();
        for e in 0..n {
            let (u, v) = (p.verts[e], p.verts[(e + 1) % n]);
            if let Some(&j) = owner.get(&(v, u))
                && j != i
                && polys[j].alive
                && polys[j].excavation == p.excavation
            {
                let l = dist(positions[u], positions[v]);
                let s = shared.entry(j).or_insert((0.0, 0.0, p.edges[e]));
                s.0 += l;
                if l > s.1 {
                    s.1 = l;
                    s.2 = p.edges[e];
                }
            }
        }
        let mut candidates: Vec<(usize, (f64, f64, EdgeSource))> = shared.into_iter().collect();
        candidates.sort_by(|a, b| b.1.0.total_cmp(&a.1.0).then(a.0.cmp(&b.0)));
        let mut joined = false;
        for (j, (length, _, across)) in candidates {
            let Some(u) = union(&polys[j], &polys[i]) else { continue };
            polys[i].alive = false;
            let m = u.verts.len();
            for e in 0..m {
                owner.insert((u.verts[e], u.verts[(e + 1) % m]), j);
            }
            polys[j] = Poly { excavation: polys[j].excavation, ..u };
            reports.push(Report::JoinedBlock { thickness, area, at, shared: length, across });
            let t = measure(positions, &polys[j]).0;
            if t < min_edge {
                queue.push((t, j));
            }
            joined = true;
            break;
        }
        if !joined {
            reports.push(Report::ThinBlockKept { thickness, area, at });
        }
    }
}
