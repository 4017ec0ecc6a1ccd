//! Triangle meshes from gmsh (math note §9): the `.msh` reader ([`msh`]), the 3-node triangle element
//! kernels and sparse assembly ([`tri3`]) and the boundary loops that carry contacts ([`loops`]).
//!
//! ```no_run
//! let mesh = pbdda::mesh::Mesh::read(std::path::Path::new("meshes/cantilever_1.msh"))?;
//! let beam = mesh.select_surface(Some("beam"))?;
//! let clamped = beam.node_set(&["clamp"])?;
//! println!("{} nodes, {} triangles, {} clamped", beam.nodes.len(), beam.triangles.len(), clamped.len());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod body;
pub mod loops;
pub mod msh;
pub mod tri3;

use std::collections::HashMap;
use std::fmt;
use std::path::Path;

use crate::geometry::Vec2;

/// A 2D first-order triangle mesh read from a gmsh file.
/// A mesh body's geometry as the scene gives it: the selected surface, scaled and offset, and the
/// nodes without DOFs (`fixed_nodes`).
#[derive(Debug, Clone, PartialEq)]
pub struct MeshShape {
    /// The selected physical surface in its initial position (scene keys `physical`, `scale`,
    /// `offset` applied).
    pub mesh: Mesh,
    /// Sorted indices into `mesh.nodes` of the nodes of the `fixed_nodes` groups.
    pub fixed_nodes: Vec<usize>,
    /// Rollers: `(node, component)` (0 = x, 1 = y) of the `fixed_x_nodes` and `fixed_y_nodes`
    /// groups, sorted, that component without a DOF.
    pub rollers: Vec<(usize, usize)>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// The file it was read from (names it in errors).
    pub file: String,
    /// Node coordinates, in ascending order of the file's node tags; only nodes used by a triangle.
    pub nodes: Vec<Vec2>,
    /// The file's node tag of each node (same order as `nodes`), for messages.
    pub node_tags: Vec<u64>,
    /// Triangles as node indices, counter-clockwise (clockwise triangles of the file are re-oriented).
    pub triangles: Vec<[usize; 3]>,
    /// Physical groups of the file, in the order of their (dimension, tag).
    pub groups: Vec<PhysicalGroup>,
}

/// One physical group: its triangles (surfaces) and the mesh nodes of its elements (any dimension).
#[derive(Debug, Clone, PartialEq)]
pub struct PhysicalGroup {
    /// 0 point, 1 curve, 2 surface.
    pub dim: usize,
    /// The physical tag.
    pub tag: i64,
    /// The name from `$PhysicalNames`, if any.
    pub name: Option<String>,
    /// Indices into [`Mesh::triangles`] (surface groups only).
    pub triangles: Vec<usize>,
    /// Sorted, unique indices into [`Mesh::nodes`].
    pub nodes: Vec<usize>,
}

impl PhysicalGroup {
    /// Whether `key` names this group: its name, or its numeric tag written as text.
    pub fn is_named(&self, key: &str) -> bool {
        self.name.as_deref() == Some(key) || key.parse::<i64>().ok() == Some(self.tag)
    }

    fn label(&self) -> String {
        match &self.name {
            Some(n) => format!("\"{n}\" (dim {}, tag {})", self.dim, self.tag),
            None => format!("{} (dim {}, unnamed)", self.tag, self.dim),
        }
    }
}

/// Where in the file an error was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Location {
    /// Not tied to a place in the file (e.g. a group asked for by the scene).
    File,
    /// 1-based line of an ASCII file.
    Line(usize),
    /// Byte offset in a binary file.
    Byte(usize),
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::File => Ok(()),
            Location::Line(l) => write!(f, ":{l}"),
            Location::Byte(b) => write!(f, ": byte {b}"),
        }
    }
}

/// An unreadable or unusable mesh file; displays as `file:line: message` (binary: `file: byte N: ...`).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}{location}: {kind}")]
pub struct MeshError {
    /// The file name as given to the reader.
    pub file: String,
    /// Line (ASCII) or byte offset (binary) of the offending text.
    pub location: Location,
    /// What is wrong.
    pub kind: MeshErrorKind,
}

impl MeshError {
    /// The 1-based line, for ASCII files.
    pub fn line(&self) -> Option<usize> {
        match self.location {
            Location::Line(l) => Some(l),
            _ => None,
        }
    }
}

/// The kinds of [`MeshError`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshErrorKind {
    #[error("cannot read the mesh file: {0}")]
    Io(String),
    #[error("the file ends inside {0} (truncated file?)")]
    Truncated(String),
    #[error("missing section {0}")]
    MissingSection(&'static str),
    #[error("unsupported MSH version {0}: write MSH 4.1 (ASCII or binary) or 2.2 ASCII (gmsh -format msh41)")]
    UnsupportedVersion(String),
    #[error("{0}")]
    Malformed(String),
    #[error("element {element} references node {node}, which is not in $Nodes")]
    MissingNode { element: u64, node: u64 },
    #[error("triangle {element} has zero area (nodes {nodes:?} are collinear or repeated)")]
    Degenerate { element: u64, nodes: [u64; 3] },
    #[error(
        "edge between nodes {a} and {b} is shared by more than two triangles (element {element} is the third)"
    )]
    NonManifoldEdge { element: u64, a: u64, b: u64 },
    #[error("the mesh has no 3-node triangles (mesh the surface in 2D: gmsh -2)")]
    NoTriangles,
    #[error("no physical group {name} in the mesh; it has: {available}")]
    NoSuchGroup { name: String, available: String },
    #[error("physical group {0} has no triangles (a body takes a physical surface)")]
    NotASurface(String),
    #[error("physical group {0} has no nodes in the selected mesh")]
    EmptyNodeSet(String),
    #[error("element {element} is a {what}: re-mesh with `-order 1` (first-order 3-node triangles)")]
    SecondOrder { element: u64, what: &'static str },
    #[error(
        "element {element} is a {what}: re-mesh without recombination (no `Recombine`, Mesh.RecombineAll = 0)"
    )]
    Quadrilateral { element: u64, what: &'static str },
    #[error("element {element} is a {what}: pbdda reads 2D meshes (gmsh -2)")]
    Solid { element: u64, what: &'static str },
    #[error("unknown element type {0}")]
    UnknownElementType(i64),
}

/// The area coordinates of `x` in `triangle` (node indices into `nodes`): `x = Σ L_i x_i`.
pub(crate) fn area_coords(nodes: &[Vec2], triangle: [usize; 3], x: Vec2) -> [f64; 3] {
    let [pa, pb, pc] = triangle.map(|n| nodes[n]);
    let area2 = crate::geometry::cross(pb - pa, pc - pa);
    let la = crate::geometry::cross(pb - x, pc - x) / area2;
    let lb = crate::geometry::cross(pc - x, pa - x) / area2;
    [la, lb, 1.0 - la - lb]
}

/// The first triangle, in order, that holds `x` with every area coordinate at least `-tol`, and
/// those coordinates: a point on a shared edge or node goes to the first triangle that has it.
pub(crate) fn first_holding(
    nodes: &[Vec2],
    triangles: &[[usize; 3]],
    x: Vec2,
    tol: f64,
) -> Option<(usize, [f64; 3])> {
    triangles.iter().enumerate().find_map(|(t, &tri)| {
        let l = area_coords(nodes, tri, x);
        l.iter().all(|&v| v >= -tol).then_some((t, l))
    })
}

impl Mesh {
    /// Reads a gmsh file: MSH 4.1 ASCII or binary, or MSH 2.2 ASCII.
    pub fn read(path: &Path) -> Result<Mesh, MeshError> {
        let file = path.display().to_string();
        let bytes = std::fs::read(path).map_err(|e| MeshError {
            file: file.clone(),
            location: Location::File,
            kind: MeshErrorKind::Io(e.to_string()),
        })?;
        msh::parse(&file, &bytes)
    }

    /// Parses the bytes of a gmsh file; `file` names it in errors.
    pub fn parse(file: &str, bytes: &[u8]) -> Result<Mesh, MeshError> {
        msh::parse(file, bytes)
    }

    /// The physical group named `key` (its name, or its tag as text).
    pub fn group(&self, key: &str) -> Result<&PhysicalGroup, MeshError> {
        self.groups.iter().find(|g| g.is_named(key)).ok_or_else(|| MeshError {
            file: self.file.clone(),
            location: Location::File,
            kind: MeshErrorKind::NoSuchGroup {
                name: format!("\"{key}\""),
                available: if self.groups.is_empty() {
                    "no physical groups".into()
                } else {
                    self.groups.iter().map(PhysicalGroup::label).collect::<Vec<_>>().join(", ")
                },
            },
        })
    }

    /// The mesh of one physical surface (`None`: every triangle), with unused nodes dropped and the
    /// groups restricted to what remains.
    pub fn select_surface(&self, key: Option<&str>) -> Result<Mesh, MeshError> {
        let Some(key) = key else { return Ok(self.clone()) };
        let g = self.group(key)?;
        if g.triangles.is_empty() {
            return Err(self.error(MeshErrorKind::NotASurface(g.label())));
        }
        Ok(self.subset(&g.triangles))
    }

    /// Sorted, unique nodes of the named physical groups (curves or points, for `fixed_nodes`).
    pub fn node_set(&self, keys: &[&str]) -> Result<Vec<usize>, MeshError> {
        let mut out = Vec::new();
        for key in keys {
            let g = self.group(key)?;
            if g.nodes.is_empty() {
                return Err(self.error(MeshErrorKind::EmptyNodeSet(g.label())));
            }
            out.extend_from_slice(&g.nodes);
        }
        out.sort_unstable();
        out.dedup();
        Ok(out)
    }

    /// The mesh scaled by `scale` about the origin, then translated by `offset` (scene keys `scale`,
    /// `offset`). A negative scale mirrors it through the origin (a rotation by 180°) and keeps the
    /// triangles counter-clockwise.
    pub fn transformed(&self, scale: f64, offset: Vec2) -> Mesh {
        Mesh { nodes: self.nodes.iter().map(|p| p * scale + offset).collect(), ..self.clone() }
    }

    /// The triangle holding point `x` and the area coordinates of `x` in it (math note §9.2: a
    /// point moves as `sum L_i u_i`), or `None` outside the mesh. Points on a shared edge go to the
    /// first triangle in file order; `tol` widens each triangle by that much in area coordinates.
    pub fn locate(&self, x: Vec2, tol: f64) -> Option<(usize, [f64; 3])> {
        first_holding(&self.nodes, &self.triangles, x, tol)
    }

    /// Twice the signed area of triangle `t` (positive: counter-clockwise).
    pub fn area2(&self, t: usize) -> f64 {
        let [a, b, c] = self.triangles[t];
        crate::geometry::cross(self.nodes[b] - self.nodes[a], self.nodes[c] - self.nodes[a])
    }

    fn error(&self, kind: MeshErrorKind) -> MeshError {
        MeshError { file: self.file.clone(), location: Location::File, kind }
    }

    fn subset(&self, keep: &[usize]) -> Mesh {
        let mut map: HashMap<usize, usize> = HashMap::new();
        let mut used: Vec<usize> = keep.iter().flat_map(|&t| self.triangles[t]).collect();
        used.sort_unstable();
        used.dedup();
        for (new, &old) in used.iter().enumerate() {
            map.insert(old, new);
        }
        let tmap: HashMap<usize, usize> = keep.iter().enumerate().map(|(new, &old)| (old, new)).collect();
        let groups = self
            .groups
            .iter()
            .map(|g| PhysicalGroup {
                triangles: g.triangles.iter().filter_map(|t| tmap.get(t).copied()).collect(),
                nodes: g.nodes.iter().filter_map(|n| map.get(n).copied()).collect(),
                ..g.clone()
            })
            .collect();
        Mesh {
            file: self.file.clone(),
            nodes: used.iter().map(|&n| self.nodes[n]).collect(),
            node_tags: used.iter().map(|&n| self.node_tags[n]).collect(),
            triangles: keep.iter().map(|&t| self.triangles[t].map(|n| map[&n])).collect(),
            groups,
        }
    }
}
