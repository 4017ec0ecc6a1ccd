//! A block meshed into 3-node triangles by spade's Delaunay refinement, written as gmsh MSH 2.2
//! (math note §12.5).

use std::collections::{BTreeMap, HashMap, HashSet};
use std::fmt::Write;

use spade::{AngleLimit, ConstrainedDelaunayTriangulation, Point2, RefinementParameters, Triangulation};

use super::{Block, CutError, EdgeSource};
use crate::geometry::Vec2;
use crate::mesh::{Mesh, MeshError};

/// The smallest angle spade's refinement aims for [deg] (below its 30 deg limit of sure termination).
const ANGLE_LIMIT: f64 = 25.0;

/// Meshes with more nodes than this are refused.
const MAX_NODES: f64 = 2.0e6;

/// A triangle mesh of one block.
#[derive(Debug, Clone, PartialEq)]
pub struct TriMesh {
    pub nodes: Vec<[f64; 2]>,
    /// Counter-clockwise.
    pub triangles: Vec<[usize; 3]>,
    /// Every boundary edge (counter-clockwise along the block's outline) and the block edge's source.
    pub boundary: Vec<([usize; 2], EdgeSource)>,
}

impl TriMesh {
    /// The source of each edge of the mesh's contact loops, in the order contacts number them
    /// ([`crate::mesh::loops::contact_loops`]: the outer loop's edges, then each hole's): the
    /// joint provenance of a meshed block's boundary (math note §4.14). An edge that is on no
    /// block edge (none, as [`mesh_block`] makes them) counts as the outline.
    pub fn loop_sources(&self) -> Vec<EdgeSource> {
        let nodes: Vec<Vec2> = self.nodes.iter().map(|p| Vec2::new(p[0], p[1])).collect();
        let (outer, holes) = crate::mesh::loops::contact_loops(&nodes, &self.triangles);
        let sources: HashMap<[usize; 2], EdgeSource> = self.boundary.iter().copied().collect();
        std::iter::once(&outer)
            .chain(&holes)
            .flat_map(|l| (0..l.len()).map(move |k| [l[k], l[(k + 1) % l.len()]]))
            .map(|[a, b]| {
                sources.get(&[a, b]).or(sources.get(&[b, a])).copied().unwrap_or(EdgeSource::Outline)
            })
            .collect()
    }
}

/// Meshes `block` with triangles of area at most that of the equilateral triangle of side
/// `mesh_size` and angles of at least 25 degrees where the block's own corners allow (spade's
/// refinement); the outline's edges are split as needed and keep their source.
pub fn mesh_block(block: &Block, mesh_size: f64) -> Result<TriMesh, CutError> {
    let n = block.vertices.len();
    let max_area = 3f64.sqrt() / 4.0 * mesh_size * mesh_size;
    let expected = expected_nodes(block, mesh_size, max_area)?;
    let mut cdt: ConstrainedDelaunayTriangulation<Point2<f64>> = ConstrainedDelaunayTriangulation::new();
    let mut handles = Vec::with_capacity(n);
    for p in &block.vertices {
        let h = cdt
            .insert(Point2::new(p[0], p[1]))
            .map_err(|e| CutError::Mesh(format!("vertex ({}, {}) refused: {e:?}", p[0], p[1])))?;
        handles.push(h);
    }
    for i in 0..n {
        let (a, b) = (handles[i], handles[(i + 1) % n]);
        if a == b || !cdt.can_add_constraint(a, b) {
            return Err(CutError::Mesh("the block outline is not a simple polygon".into()));
        }
        cdt.add_constraint(a, b);
    }
    let params = RefinementParameters::<f64>::new()
        .with_max_allowed_area(max_area)
        .with_angle_limit(AngleLimit::from_deg(ANGLE_LIMIT))
        .exclude_outer_faces(true)
        .with_max_additional_vertices(expected as usize * 4 + 1000);
    let result = cdt.refine(params);
    if !result.refinement_complete {
        return Err(CutError::Mesh(format!(
            "the refinement of a block at ({}, {}) did not finish",
            block.centroid[0], block.centroid[1]
        )));
    }
    let excluded: HashSet<usize> = result.excluded_faces.iter().map(|f| f.index()).collect();
    let mut index: HashMap<usize, usize> = HashMap::new();
    let mut nodes = Vec::new();
    let mut triangles = Vec::new();
    let mut kept = HashSet::new();
    for f in cdt.inner_faces() {
        if excluded.contains(&f.fix().index()) {
            continue;
        }
        kept.insert(f.fix().index());
        let t = f.vertices().map(|v| {
            *index.entry(v.fix().index()).or_insert_with(|| {
                nodes.push([v.position().x, v.position().y]);
                nodes.len() - 1
            })
        });
        triangles.push(t);
    }
    let mut boundary = Vec::new();
    for f in cdt.inner_faces() {
        if !kept.contains(&f.fix().index()) {
            continue;
        }
        for e in f.adjacent_edges() {
            let other = e.rev().face().as_inner().map(|g| g.fix().index());
            if other.is_some_and(|g| kept.contains(&g)) {
                continue;
            }
            let (a, b) = (index[&e.from().fix().index()], index[&e.to().fix().index()]);
            boundary.push(([a, b], source_of(block, nodes[a], nodes[b])?));
        }
    }
    boundary.sort_by_key(|e| e.0);
    Ok(TriMesh { nodes, triangles, boundary })
}

/// About how many nodes the mesh of `block` will have (an upper estimate from its area and
/// perimeter); an error when `mesh_size` is not positive and finite or the count passes
/// `MAX_NODES`.
fn expected_nodes(block: &Block, mesh_size: f64, max_area: f64) -> Result<f64, CutError> {
    if !mesh_size.is_finite() || mesh_size <= 0.0 {
        return Err(CutError::Mesh(format!("mesh_size must be positive and finite (got {mesh_size})")));
    }
    let n = block.vertices.len();
    let perimeter: f64 = (0..n)
        .map(|i| {
            let (p, q) = (block.vertices[i], block.vertices[(i + 1) % n]);
            (p[0] - q[0]).hypot(p[1] - q[1])
        })
        .sum();
    let expected = 4.0 * block.area / max_area + 4.0 * perimeter / mesh_size + 10.0 * n as f64;
    if expected.is_nan() || expected > MAX_NODES {
        return Err(CutError::Mesh(format!(
            "mesh_size {mesh_size} m would make about {expected:.3e} nodes in a block of area {} m2, above {MAX_NODES:e}",
            block.area
        )));
    }
    Ok(expected)
}

/// The source of the block edge on which the mesh edge `p`-`q` lies.
fn source_of(block: &Block, p: [f64; 2], q: [f64; 2]) -> Result<EdgeSource, CutError> {
    let n = block.vertices.len();
    let mut best = (f64::INFINITY, None);
    for i in 0..n {
        let (a, b) = (block.vertices[i], block.vertices[(i + 1) % n]);
        let d = [b[0] - a[0], b[1] - a[1]];
        let l = d[0].hypot(d[1]);
        let off = |r: [f64; 2]| ((r[0] - a[0]) * d[1] - (r[1] - a[1]) * d[0]).abs() / l;
        let along = |r: [f64; 2]| ((r[0] - a[0]) * d[0] + (r[1] - a[1]) * d[1]) / l;
        let m = [0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])];
        let miss = off(p).max(off(q)) + (-along(m)).max(along(m) - l).max(0.0);
        if miss < best.0 {
            best = (miss, Some(block.edges[i]));
        }
    }
    match best {
        (miss, Some(s)) if miss <= 1e-9 * block.area.sqrt() => Ok(s),
        _ => Err(CutError::Mesh(format!("a boundary edge at ({}, {}) lies on no block edge", p[0], p[1]))),
    }
}

/// The mesh as a gmsh MSH 2.2 ASCII file: physical surface "block" (the largest tag) and one
/// physical curve per distinct `names(source)` of the boundary edges, tagged 1, 2, ... in the
/// order of the names. Coordinates are written in Rust's shortest round-trip form, so reading
/// the file back gives the same doubles.
pub fn write_msh(mesh: &TriMesh, names: &dyn Fn(&EdgeSource) -> String) -> String {
    let mut curves: BTreeMap<String, usize> = BTreeMap::new();
    for (_, s) in &mesh.boundary {
        curves.entry(names(s)).or_insert(0);
    }
    for (k, v) in curves.values_mut().enumerate() {
        *v = k + 1;
    }
    let surface = curves.len() + 1;
    let mut out = String::from("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n");
    let _ = writeln!(out, "{}", curves.len() + 1);
    for (name, tag) in &curves {
        let _ = writeln!(out, "1 {tag} \"{name}\"");
    }
    let _ = writeln!(out, "2 {surface} \"block\"\n$EndPhysicalNames\n$Nodes\n{}", mesh.nodes.len());
    for (i, p) in mesh.nodes.iter().enumerate() {
        let _ = writeln!(out, "{} {:?} {:?} 0", i + 1, p[0], p[1]);
    }
    let _ = writeln!(out, "$EndNodes\n$Elements\n{}", mesh.boundary.len() + mesh.triangles.len());
    let mut id = 0;
    for ([a, b], s) in &mesh.boundary {
        id += 1;
        let tag = curves[&names(s)];
        let _ = writeln!(out, "{id} 1 2 {tag} {tag} {} {}", a + 1, b + 1);
    }
    for t in &mesh.triangles {
        id += 1;
        let _ = writeln!(out, "{id} 2 2 {surface} {surface} {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    out.push_str("$EndElements\n");
    out
}

/// The mesh as a [`Mesh`], through the same reader and checks as a gmsh file (`file` names it).
pub fn to_mesh(mesh: &TriMesh, names: &dyn Fn(&EdgeSource) -> String, file: &str) -> Result<Mesh, MeshError> {
    Mesh::parse(file, write_msh(mesh, names).as_bytes())
}
