//! From the raw contents of a `.msh` file to a checked [`Mesh`]: node look-up, re-orientation of
//! clockwise triangles (math note §9.1), and the checks for missing nodes, zero-area triangles,
//! edges shared by more than two triangles and meshes without triangles.

use std::collections::{BTreeMap, HashMap};

use super::{Raw, Reader};
use crate::geometry::cross;
use crate::mesh::{Mesh, MeshError, MeshErrorKind as K, PhysicalGroup};

/// Relative size of `|2A| / max edge²` below which a triangle counts as zero-area (collinear corners
/// to round-off of coordinates written with 16 digits).
const DEGENERATE: f64 = 1e-12;

pub(super) fn build(r: &Reader, raw: Raw) -> Result<Mesh, MeshError> {
    let mut index: HashMap<u64, usize> = HashMap::with_capacity(raw.nodes.len());
    for (i, n) in raw.nodes.iter().enumerate() {
        if index.insert(n.tag, i).is_some() {
            return Err(r.err(raw.node_pos[i], K::Malformed(format!("node tag {} is defined twice", n.tag))));
        }
    }
    // Resolve every element's nodes (file order) to raw node indices.
    let mut resolved: Vec<Vec<usize>> = Vec::with_capacity(raw.elements.len());
    for e in &raw.elements {
        let tags = raw.element_nodes.get(e.first..e.first + e.dim + 1).unwrap_or(&[]);
        let mut ids = Vec::with_capacity(tags.len());
        for &t in tags {
            match index.get(&t) {
                Some(&i) => ids.push(i),
                None => return Err(r.err(e.pos, K::MissingNode { element: e.tag, node: t })),
            }
        }
        resolved.push(ids);
    }
    let triangles = triangles(r, &raw, &resolved)?;
    if triangles.is_empty() {
        return Err(r.err(raw.elements_pos, K::NoTriangles));
    }
    // Keep the nodes that triangles use, in ascending tag order.
    let mut used: Vec<usize> = triangles.iter().flat_map(|(_, t)| *t).collect();
    used.sort_unstable_by_key(|&i| raw.nodes[i].tag);
    used.dedup();
    let mut compact: HashMap<usize, usize> = HashMap::with_capacity(used.len());
    for (new, &old) in used.iter().enumerate() {
        compact.insert(old, new);
    }
    let groups = groups(&raw, &resolved, &triangles, &compact);
    Ok(Mesh {
        file: r.file.to_owned(),
        nodes: used.iter().map(|&i| raw.nodes[i].p).collect(),
        node_tags: used.iter().map(|&i| raw.nodes[i].tag).collect(),
        triangles: triangles.iter().map(|(_, t)| t.map(|i| compact[&i])).collect(),
        groups,
    })
}

/// The triangles (element index, raw node indices counter-clockwise), checked.
fn triangles(r: &Reader, raw: &Raw, resolved: &[Vec<usize>]) -> Result<Vec<(usize, [usize; 3])>, MeshError> {
    let mut out = Vec::new();
    let mut edges: HashMap<(usize, usize), u8> = HashMap::new();
    for (k, e) in raw.elements.iter().enumerate() {
        let [a, b, c] = match resolved[k].as_slice() {
            &[a, b, c] if e.dim == 2 => [a, b, c],
            _ => continue,
        };
        let (pa, pb, pc) = (raw.nodes[a].p, raw.nodes[b].p, raw.nodes[c].p);
        let area2 = cross(pb - pa, pc - pa);
        let longest = (pb - pa).norm_squared().max((pc - pb).norm_squared()).max((pa - pc).norm_squared());
        if !area2.is_finite() || area2.abs() <= DEGENERATE * longest {
            let nodes = [raw.nodes[a].tag, raw.nodes[b].tag, raw.nodes[c].tag];
            return Err(r.err(e.pos, K::Degenerate { element: e.tag, nodes }));
        }
        let tri = if area2 > 0.0 { [a, b, c] } else { [a, c, b] };
        for (i, j) in [(tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])] {
            let count = edges.entry((i.min(j), i.max(j))).or_insert(0);
            *count += 1;
            if *count > 2 {
                let (ta, tb) = (raw.nodes[i].tag, raw.nodes[j].tag);
                return Err(r.err(e.pos, K::NonManifoldEdge { element: e.tag, a: ta.min(tb), b: ta.max(tb) }));
            }
        }
        out.push((k, tri));
    }
    Ok(out)
}

/// Physical groups: every (dim, tag) named in `$PhysicalNames` or carried by an element.
fn groups(
    raw: &Raw,
    resolved: &[Vec<usize>],
    triangles: &[(usize, [usize; 3])],
    compact: &HashMap<usize, usize>,
) -> Vec<PhysicalGroup> {
    let mut map: BTreeMap<(usize, i64), PhysicalGroup> = BTreeMap::new();
    for (dim, tag, name) in &raw.names {
        entry(&mut map, *dim, *tag).name = Some(name.clone());
    }
    let mut triangle_of: HashMap<usize, usize> = HashMap::new();
    for (t, (k, _)) in triangles.iter().enumerate() {
        triangle_of.insert(*k, t);
    }
    for (k, e) in raw.elements.iter().enumerate() {
        for &p in &e.physical {
            let g = entry(&mut map, e.dim, p);
            if let Some(&t) = triangle_of.get(&k) {
                g.triangles.push(t);
            }
            g.nodes.extend(resolved[k].iter().filter_map(|i| compact.get(i).copied()));
        }
    }
    map.into_values()
        .map(|mut g| {
            g.nodes.sort_unstable();
            g.nodes.dedup();
            g
        })
        .collect()
}

fn entry(map: &mut BTreeMap<(usize, i64), PhysicalGroup>, dim: usize, tag: i64) -> &mut PhysicalGroup {
    map.entry((dim, tag)).or_insert_with(|| PhysicalGroup {
        dim,
        tag,
        name: None,
        triangles: Vec::new(),
        nodes: Vec::new(),
    })
}
