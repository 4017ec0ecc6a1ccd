//! Boundary loops of a triangle mesh (math note §9.2): the edges used by exactly one triangle,
//! chained into closed loops with the material on the left, so the outer loop runs
//! counter-clockwise and holes clockwise. Contacts on a mesh are detected on these loops.

use std::collections::{BTreeMap, HashMap};

use crate::geometry::{Vec2, signed_area2};

/// One closed boundary loop: node indices in order, material on the left.
#[derive(Debug, Clone, PartialEq)]
pub struct BoundaryLoop {
    /// Node indices; the loop closes from the last back to the first. Starts at its smallest index.
    pub nodes: Vec<usize>,
    /// Signed area of the loop's polygon: positive for an outer loop, negative for a hole.
    pub signed_area: f64,
}

impl BoundaryLoop {
    /// A hole (clockwise loop).
    pub fn is_hole(&self) -> bool {
        self.signed_area < 0.0
    }
}

/// A mesh whose boundary is not a set of simple closed loops.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LoopError {
    #[error("the edge between nodes {a} and {b} is shared by {count} triangles (at most 2)")]
    NonManifoldEdge { a: usize, b: usize, count: usize },
    #[error(
        "the two triangles on the edge between nodes {a} and {b} run it the same way: they overlap \
         (folded or inverted triangles)"
    )]
    Overlap { a: usize, b: usize },
    #[error("boundary node {node} is a pinch point: two boundary loops touch there (non-manifold vertex)")]
    Pinched { node: usize },
    #[error("the boundary through node {node} does not close")]
    Open { node: usize },
}

/// The boundary loops of counter-clockwise `triangles` over `nodes`: outer loops first (largest
/// area first), then holes (largest first).
pub fn boundary_loops(nodes: &[Vec2], triangles: &[[usize; 3]]) -> Result<Vec<BoundaryLoop>, LoopError> {
    // Directed edges of counter-clockwise triangles have the material on their left.
    let mut edges: HashMap<(usize, usize), (usize, (usize, usize))> = HashMap::new();
    for t in triangles {
        for (i, j) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            let e = edges.entry((i.min(j), i.max(j))).or_insert((0, (i, j)));
            e.0 += 1;
            if e.0 > 2 {
                return Err(LoopError::NonManifoldEdge { a: i.min(j), b: i.max(j), count: e.0 });
            }
            if e.0 == 2 && e.1 == (i, j) {
                return Err(LoopError::Overlap { a: i.min(j), b: i.max(j) });
            }
        }
    }
    let mut next: BTreeMap<usize, usize> = BTreeMap::new();
    for (&(a, b), &(count, (i, j))) in &edges {
        match count {
            1 => {
                if next.insert(i, j).is_some() {
                    return Err(LoopError::Pinched { node: i });
                }
            }
            2 => {}
            _ => return Err(LoopError::NonManifoldEdge { a, b, count }),
        }
    }
    let mut loops = Vec::new();
    let mut seen: HashMap<usize, bool> = HashMap::new();
    for &start in next.keys() {
        if seen.contains_key(&start) {
            continue;
        }
        let mut chain = vec![start];
        seen.insert(start, true);
        let mut at = start;
        loop {
            let Some(&to) = next.get(&at) else { return Err(LoopError::Open { node: at }) };
            if to == start {
                break;
            }
            if seen.insert(to, true).is_some() || chain.len() > next.len() {
                return Err(LoopError::Pinched { node: to });
            }
            chain.push(to);
            at = to;
        }
        let poly: Vec<Vec2> = chain.iter().map(|&n| nodes[n]).collect();
        loops.push(BoundaryLoop { signed_area: 0.5 * signed_area2(&poly), nodes: chain });
    }
    loops.sort_by(|a, b| {
        (a.is_hole(), -a.signed_area.abs())
            .partial_cmp(&(b.is_hole(), -b.signed_area.abs()))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    Ok(loops)
}

/// The loops that carry a mesh's contacts (math note §9.2), in the order contact features number
/// their vertices and edges: the outer loop (the first of [`boundary_loops`], unless it is a
/// hole) and the holes, as node lists. Nothing for an unusable boundary (the scene refuses one;
/// a model built in code loses its contacts).
pub fn contact_loops(nodes: &[Vec2], triangles: &[[usize; 3]]) -> (Vec<usize>, Vec<Vec<usize>>) {
    let loops = boundary_loops(nodes, triangles).unwrap_or_default();
    let outer = loops.first().filter(|l| !l.is_hole()).map(|l| l.nodes.clone()).unwrap_or_default();
    let holes = loops.iter().filter(|l| l.is_hole()).map(|l| l.nodes.clone()).collect();
    (outer, holes)
}
