//! Rock masses cut from joints (math note §12): a domain outline, joint sets, single joints and
//! excavations become a list of simple, counter-clockwise block polygons that tile the domain minus
//! the removed excavations, each edge remembering where it came from.
//!
//! The geometry is spade's constrained Delaunay triangulation: every outline, trace and joint is a
//! constraint edge, crossing constraints are split where they cross (by the glue, math note
//! §12.7), and a block is a connected set of triangles that no constraint
//! separates. A trace piece that closes no block has the same block on both sides and so
//! vanishes by itself (the tree cutting of Shi's DC cutter).
//!
//! ```
//! use pbdda::rockmass::{Bridges, CutSpec, JointSet, cut};
//! let set = |angle: f64| JointSet { angle, spacing: 1.0, ..JointSet::default() };
//! let spec = CutSpec {
//!     domain: vec![[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [0.0, 3.0]],
//!     joint_sets: vec![set(0.0), set(90.0)],
//!     ..CutSpec::default()
//! };
//! let blocks = cut(&spec)?.blocks;
//! assert_eq!(blocks.len(), 12);
//! # Ok::<(), pbdda::rockmass::CutError>(())
//! ```

mod arrange;
mod clip;
mod estimate;
mod join;
mod link;
mod mesh;
mod polish;
mod traces;

use std::fmt;

pub use mesh::{TriMesh, mesh_block, to_mesh, write_msh};

/// A family of parallel traces (math note §12.1).
#[derive(Debug, Clone, PartialEq)]
pub struct JointSet {
    /// [deg] direction of the traces, counter-clockwise from +x.
    pub angle: f64,
    /// [m] normal distance between successive traces.
    pub spacing: f64,
    /// One trace passes through this point; the trace/gap pattern along each line starts at the
    /// line's point nearest to it.
    pub origin: [f64; 2],
    /// [m] length of each trace piece; 0 = persistent (the traces cross the whole domain).
    pub trace: f64,
    /// [m] rock bridge between successive trace pieces on one line (`trace > 0`).
    pub gap: f64,
    /// Uniform deviations +-: per line (angle [deg], spacing [m]) and per piece (trace, gap [m]).
    pub angle_dev: f64,
    pub spacing_dev: f64,
    pub trace_dev: f64,
    pub gap_dev: f64,
    /// What becomes of the gaps between trace pieces.
    pub bridges: Bridges,
}

impl Default for JointSet {
    fn default() -> Self {
        Self {
            angle: 0.0,
            spacing: 1.0,
            origin: [0.0, 0.0],
            trace: 0.0,
            gap: 0.0,
            angle_dev: 0.0,
            spacing_dev: 0.0,
            trace_dev: 0.0,
            gap_dev: 0.0,
            bridges: Bridges::Remove,
        }
    }
}

/// The rock bridges between the trace pieces of a non-persistent set.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Bridges {
    /// Pieces that close no block vanish (DDA, UDEC).
    #[default]
    Remove,
    /// The traces are cut through their gaps; the gap pieces are [`EdgeSource::Bridge`] edges.
    Cemented,
}

/// One explicit trace (a fault): a polyline of at least 2 points.
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    pub points: Vec<[f64; 2]>,
}

/// A polygon removed from the domain (`keep = false`) or cut out and kept, its blocks tagged with
/// the excavation's index (`keep = true`, for removal at a later stage).
#[derive(Debug, Clone, PartialEq)]
pub struct Excavation {
    pub vertices: Vec<[f64; 2]>,
    pub keep: bool,
}

/// A circle as a counter-clockwise polygon of `segments` vertices on it, the first at angle 0.
pub fn circle(center: [f64; 2], radius: f64, segments: usize) -> Vec<[f64; 2]> {
    (0..segments)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / segments as f64;
            [center[0] + radius * a.cos(), center[1] + radius * a.sin()]
        })
        .collect()
}

/// Everything that cuts a rock mass.
#[derive(Debug, Clone, PartialEq)]
pub struct CutSpec {
    /// The outline of the rock mass: a simple polygon of either orientation.
    pub domain: Vec<[f64; 2]>,
    pub joint_sets: Vec<JointSet>,
    pub joints: Vec<Joint>,
    pub excavations: Vec<Excavation>,
    /// [m] cut vertices closer than this are merged and blocks thinner than this are joined to a
    /// neighbour (math note §12.3); each is a [`Report`]. An outline or excavation edge shorter
    /// than this (or than 1e-9 of the domain's diagonal) is an error, and so is a merge that
    /// would pinch a hole off a block (math note §12.8).
    pub min_edge: f64,
    /// Seed of every random deviation (math note §12.2).
    pub seed: u64,
    /// The largest block count the sets may make, estimated before cutting (math note §12.1).
    pub block_limit: usize,
}

impl Default for CutSpec {
    fn default() -> Self {
        Self {
            domain: Vec::new(),
            joint_sets: Vec::new(),
            joints: Vec::new(),
            excavations: Vec::new(),
            min_edge: 1e-3,
            seed: 1,
            block_limit: 100_000,
        }
    }
}

/// Where a block edge comes from. Sorted by priority: where two sources run along the same edge,
/// the edge takes the smaller one (the outline before an excavation, ..., the lower index first).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum EdgeSource {
    /// The domain's outline.
    Outline,
    /// The outline of excavation `i`.
    Excavation(usize),
    /// Explicit joint `i`.
    Joint(usize),
    /// A trace of joint set `i`.
    Set(usize),
    /// A cemented rock bridge of joint set `i` ([`Bridges::Cemented`]).
    Bridge(usize),
    /// A straight cut the cutter added through intact rock so that no block has a hole (a block
    /// that would enclose an island or a kept excavation); intact rock, to be bonded like a
    /// bridge. Each seam is a [`Report`].
    Seam,
}

impl fmt::Display for EdgeSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EdgeSource::Outline => write!(f, "the outline"),
            EdgeSource::Excavation(i) => write!(f, "excavation {i}"),
            EdgeSource::Joint(i) => write!(f, "joint {i}"),
            EdgeSource::Set(i) => write!(f, "joint set {i}"),
            EdgeSource::Bridge(i) => write!(f, "a bridge of joint set {i}"),
            EdgeSource::Seam => write!(f, "a seam"),
        }
    }
}

/// One cut block.
#[derive(Debug, Clone, PartialEq)]
pub struct Block {
    /// Counter-clockwise, simple; two consecutive edges are collinear only where the source
    /// changes along a straight line (a trace piece and its cemented bridge, math note §12.3).
    pub vertices: Vec<[f64; 2]>,
    /// `edges[i]` joins `vertices[i]` to `vertices[(i + 1) % n]`.
    pub edges: Vec<EdgeSource>,
    pub area: f64,
    pub centroid: [f64; 2],
    /// The kept excavation ([`Excavation::keep`]) the block lies in.
    pub excavation: Option<usize>,
}

/// Something the cutter changed in the geometry it was given; never done silently.
#[derive(Debug, Clone, PartialEq)]
pub enum Report {
    /// `count` cut vertices up to `distance` apart became one at `at`.
    MergedVertices { count: usize, distance: f64, at: [f64; 2] },
    /// A block `thickness` thin (area / longest edge) of `area` at `at` was joined to the
    /// neighbour across `shared` metres of common boundary from `across`.
    JoinedBlock { thickness: f64, area: f64, at: [f64; 2], shared: f64, across: EdgeSource },
    /// A block thinner than `min_edge` with no neighbour to join was kept.
    ThinBlockKept { thickness: f64, area: f64, at: [f64; 2] },
    /// A block that would have held a hole was cut by a seam from `from` to `to`.
    Seam { from: [f64; 2], to: [f64; 2] },
    /// A piece of zero area left by merged vertices was dropped.
    DroppedSliver { area: f64, at: [f64; 2] },
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let p = |q: &[f64; 2]| format!("({}, {})", q[0], q[1]);
        match self {
            Report::MergedVertices { count, distance, at } => {
                write!(f, "merged {count} vertices {distance:.3e} m apart at {}", p(at))
            }
            Report::JoinedBlock { thickness, area, at, shared, across } => write!(
                f,
                "joined a block {thickness:.3e} m thin (area {area:.3e} m2) at {} to its neighbour \
                 across {shared:.3e} m of {across}",
                p(at)
            ),
            Report::ThinBlockKept { thickness, area, at } => write!(
                f,
                "kept a block {thickness:.3e} m thin (area {area:.3e} m2) at {}: it has no neighbour",
                p(at)
            ),
            Report::Seam { from, to } => {
                write!(f, "cut a seam from {} to {} so that no block has a hole", p(from), p(to))
            }
            Report::DroppedSliver { area, at } => {
                write!(f, "dropped a sliver of area {area:.3e} m2 at {} left by merged vertices", p(at))
            }
        }
    }
}

/// The blocks, in order of centroid y, then centroid x, then area, and what was changed.
#[derive(Debug, Clone, PartialEq)]
pub struct Cut {
    pub blocks: Vec<Block>,
    pub reports: Vec<Report>,
}

/// Why a rock mass cannot be cut. The messages name the item as the scene does (`joint_set[1]`).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CutError {
    #[error("domain: {0}")]
    Domain(String),
    #[error("joint_set[{set}]: {message}")]
    Set { set: usize, message: String },
    #[error(
        "joint_set[{set}]: spacing {spacing} m would make about {estimate:.3e} blocks with the other \
         sets, above the block limit {limit}"
    )]
    TooManyBlocks { set: usize, spacing: f64, estimate: f64, limit: usize },
    #[error("joint[{joint}]: {message}")]
    Joint { joint: usize, message: String },
    #[error("excavation[{excavation}]: {message}")]
    Excavation { excavation: usize, message: String },
    #[error("min_edge must be finite and non-negative (got {0})")]
    MinEdge(f64),
    #[error("the cut failed at ({}, {}): {message}", at[0], at[1])]
    Degenerate { at: [f64; 2], message: String },
    #[error("meshing a block: {0}")]
    Mesh(String),
}

/// Cuts the domain into blocks (math note §12).
pub fn cut(spec: &CutSpec) -> Result<Cut, CutError> {
    let checked = estimate::check(spec)?;
    let segments = traces::segments(spec, &checked)?;
    // the last guard only: the glue never asks spade to split a constraint (math note §12.7),
    // whose assertion on nearly coincident crossings this once caught; a panic left in the
    // triangulation is still an error naming where, not a crash
    let built =
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| arrange::build(spec, &checked, &segments)));
    let arrangement = built.map_err(|_| CutError::Degenerate {
        at: checked.domain[0],
        message:
            "the triangulation failed on nearly coincident crossings; move a set's origin or change min_edge"
                .into(),
    })??;
    polish::finish(spec, &checked, arrangement)
}

/// The block order (math note §12.4): centroid y, then centroid x, then area, then the vertex
/// lists ([`shape_order`]).
pub(crate) fn block_order(a: &Block, b: &Block) -> std::cmp::Ordering {
    a.centroid[1]
        .total_cmp(&b.centroid[1])
        .then(a.centroid[0].total_cmp(&b.centroid[0]))
        .then(a.area.total_cmp(&b.area))
        .then_with(|| shape_order(&a.vertices, &b.vertices))
}

/// Two vertex loops compared point by point (y, then x, by `f64::total_cmp`), each from its
/// lowest, then leftmost, vertex; then by length. Two different loops never compare equal, so
/// with it the block order is total (math note §12.4).
pub(crate) fn shape_order(a: &[[f64; 2]], b: &[[f64; 2]]) -> std::cmp::Ordering {
    let yx = |p: &[f64; 2], q: &[f64; 2]| p[1].total_cmp(&q[1]).then(p[0].total_cmp(&q[0]));
    let from_lowest = |v: &[[f64; 2]]| -> Vec<usize> {
        let start = (0..v.len()).min_by(|&i, &j| yx(&v[i], &v[j])).unwrap_or(0);
        (0..v.len()).map(|k| (start + k) % v.len()).collect()
    };
    let mut pairs = from_lowest(a).into_iter().zip(from_lowest(b));
    pairs.find_map(|(i, j)| Some(yx(&a[i], &b[j])).filter(|o| o.is_ne())).unwrap_or(a.len().cmp(&b.len()))
}
