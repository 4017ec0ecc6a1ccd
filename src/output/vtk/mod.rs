//! ParaView output of the scene format's output contract: `DIR/vtk/scene.pvd`, a time series
//! indexing one XML UnstructuredGrid `step_NNNNNN.vtu` per written step (the steps the CSVs
//! write: every N-th and the last).
//!
//! Written by hand as VTK's XML format with its data appended in base64 (UInt64 block headers
//! encoded with their values, little-endian: what VTK, meshio and vtkio all read; the last two
//! read no raw appended data), ids and offsets Int32 while they fit, else Int64 (signed, as VTK
//! and meshio take them), streamed through a buffered writer; the grid's storage is kept from step
//! to step (`benches/output.rs`). `scripts/check-vtu.py` reads the files with VTK and meshio
//! (`.ci/run`, every example). `scene.pvd` is rewritten through a renamed temporary file after
//! every step, so it always indexes the steps on disk.
//!
//! Cells of one step, in this order:
//! - one cell per body: a disk is a 64-gon (`VTK_POLYGON`, display only), a ring a keyhole
//!   polygon (`VTK_POLYGON`: its 64-gon outer circle, a bridge, its inner circle the other way
//!   round; VTK polygons have no holes, and meshio reads no triangle strips), a polygon its
//!   current vertices;
//! - one line (`VTK_LINE`) per contact, joining the two bodies' sides of the contact: the
//!   contact point C (midpoint of the two surface points) ± gap/2 along the normal, first the
//!   side of body B (C − g/2 n), then the side of body A (C + g/2 n), since n points into A;
//! - the hooks [`add_lines`] (connectors) and [`add_mesh`] (mesh triangles) add their cells.
//!
//! Cell data (units as in the CSVs): `body` (index; body A for a contact, B in `body_b`),
//! `body_b` (−1 for bodies), `kind`, `velocity` (vx, vy, 0), `angular_velocity`, `rotation`,
//! `stress` and `strain` (xx, yy, xy; zero for rigid bodies and lines), `normal_force`,
//! `shear_force`, `axial_force`, `plastic_strain` (zero where they do not apply) and `state`.
//! A connector's line joins its two anchors in the current configuration (the `anchor_a_*`,
//! `anchor_b_*` columns of `connectors.csv`); its `axial_force`, `state` and `plastic_strain` are
//! that file's columns of the same row (a broken connector's line is written once, at the step it
//! broke in, with the force it broke at). Codes:
//!
//! | array | code |
//! |---|---|
//! | `kind` | 0 rigid body, 1 deformable body, 2 fixed body, 10 PP, 11 PB, 12 BB, 13 LL, 14 PL, 15 BL contact, 20 connector, 30 mesh triangle |
//! | `state` | −1 body, 0 open, 1 stick, 2 slide, 3 bonded, 4 intact, 5 broken, 6 yielding connector |
//!
//! The legend is repeated as a comment in `scene.pvd`.

use crate::body::{Body, Outline};
use crate::connector::Connector;
use crate::contact::ContactKind;
use crate::geometry::Vec2;
use crate::world::{ContactState, StepRecord, World};

mod writer;
mod xml;

pub use writer::VtkWriter;

/// VTK cell type codes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum CellType {
    Line = 3,
    Triangle = 5,
    Polygon = 7,
}

/// Segments of the display polygon of a disk or ring circle.
pub const CIRCLE_SEGMENTS: usize = 64;

/// Legend of the `kind` and `state` codes (also written into `scene.pvd`).
pub const LEGEND: &str = "kind: 0 rigid body, 1 deformable body, 2 fixed body, 10 PP, 11 PB, 12 BB, 13 LL, \
14 PL, 15 BL contact, 20 connector, 30 mesh triangle; state: -1 body, 0 open, 1 stick, 2 slide, 3 bonded, \
4 intact, 5 broken, 6 yielding connector";

/// `kind` code of a body.
pub fn body_kind(b: &Body) -> i32 {
    if b.fixed {
        2
    } else if b.deformable {
        1
    } else {
        0
    }
}

/// `kind` code of a contact.
pub fn contact_kind(k: ContactKind) -> i32 {
    match k {
        ContactKind::PP => 10,
        ContactKind::PB => 11,
        ContactKind::BB => 12,
        ContactKind::LL => 13,
        ContactKind::PL => 14,
        ContactKind::BL => 15,
    }
}

/// `state` code of a contact.
pub fn state_code(s: ContactState) -> i32 {
    match s {
        ContactState::Open => 0,
        ContactState::Stick => 1,
        ContactState::Slide => 2,
        ContactState::Bonded => 3,
    }
}

/// Values of one cell; fields that do not apply to the cell stay zero.
#[derive(Debug, Clone, Copy, Default)]
pub struct CellValues {
    pub body: i32,
    pub body_b: i32,
    pub kind: i32,
    pub state: i32,
    pub velocity: [f64; 2],
    pub angular_velocity: f64,
    pub rotation: f64,
    pub stress: [f64; 3],
    pub strain: [f64; 3],
    pub normal_force: f64,
    pub shear_force: f64,
    pub axial_force: f64,
    pub plastic_strain: f64,
}

/// A line cell for [`add_lines`] (connectors): end points and the values of the line
/// (`axial_force` tension-positive, `state` 4 intact, 5 broken or 6 yielding, `kind` 20).
#[derive(Debug, Clone, Copy)]
pub struct LineCell {
    pub a: Vec2,
    pub b: Vec2,
    pub values: CellValues,
}

/// Mesh cells for [`add_mesh`]: nodes (current positions) with their displacement, and
/// triangles with their stress and strain.
#[derive(Debug, Clone, Default)]
pub struct MeshCells {
    pub body: i32,
    pub nodes: Vec<Vec2>,
    pub displacement: Vec<Vec2>,
    pub triangles: Vec<[usize; 3]>,
    pub stress: Vec<[f64; 3]>,
    pub strain: Vec<[f64; 3]>,
}

/// One step's unstructured grid under construction.
#[derive(Debug, Default)]
pub struct Grid {
    points: Vec<f64>,
    connectivity: Vec<u64>,
    offsets: Vec<u64>,
    types: Vec<CellType>,
    cells: Vec<CellValues>,
    /// Point displacement, filled for every point only once a mesh is added.
    displacement: Option<Vec<f64>>,
}

impl Grid {
    fn point(&mut self, p: Vec2) -> u64 {
        let id = (self.points.len() / 3) as u64;
        self.points.extend_from_slice(&[p.x, p.y, 0.0]);
        if let Some(d) = &mut self.displacement {
            d.extend_from_slice(&[0.0; 3]);
        }
        id
    }

    /// Adds `points` in turn; the id of the first.
    fn points(&mut self, points: impl Iterator<Item = Vec2>) -> u64 {
        let first = self.num_points() as u64;
        points.for_each(|p| {
            self.point(p);
        });
        first
    }

    fn cell(&mut self, ids: impl IntoIterator<Item = u64>, ty: CellType, values: CellValues) {
        self.connectivity.extend(ids);
        self.offsets.push(self.connectivity.len() as u64);
        self.types.push(ty);
        self.cells.push(values);
    }

    /// Empties the grid, keeping its storage for the next step's: a large pile's grid is tens of
    /// megabytes, whose fresh pages each step would cost (`benches/output.rs`, `vtk_step`).
    pub fn clear(&mut self) {
        self.points.clear();
        self.connectivity.clear();
        self.offsets.clear();
        self.types.clear();
        self.cells.clear();
        self.displacement = None;
    }

    pub fn num_cells(&self) -> usize {
        self.cells.len()
    }

    pub fn num_points(&self) -> usize {
        self.points.len() / 3
    }
}

/// Display points of a circle: `CIRCLE_SEGMENTS` vertices, the first at angle `phase`.
/// Their mean is the centre (to rounding). The unit circle's points are computed once and
/// turned by `phase`: one sine and cosine per circle, not one per point (64 per disk were 2 %
/// of a run of the 10,000-disk pile writing every step).
pub fn circle_points(center: Vec2, radius: f64, phase: f64) -> impl Iterator<Item = Vec2> {
    static UNIT: std::sync::OnceLock<Vec<Vec2>> = std::sync::OnceLock::new();
    let unit = UNIT.get_or_init(|| {
        (0..CIRCLE_SEGMENTS)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / CIRCLE_SEGMENTS as f64;
                Vec2::new(a.cos(), a.sin())
            })
            .collect()
    });
    let (s, c) = phase.sin_cos();
    unit.iter().map(move |u| center + Vec2::new(c * u.x - s * u.y, s * u.x + c * u.y) * radius)
}

/// Body cells: one per body (see the module notes for the shapes), bodies removed by a stage
/// left out.
pub fn add_bodies(grid: &mut Grid, world: &World) {
    for (i, b) in world.bodies.iter().enumerate().filter(|&(i, _)| !world.is_removed(i)) {
        let v = &b.velocity;
        let mut values = CellValues {
            body: i as i32,
            body_b: -1,
            kind: body_kind(b),
            state: -1,
            velocity: [v[0], v[1]],
            angular_velocity: v[2],
            rotation: b.rotation,
            ..CellValues::default()
        };
        if b.deformable {
            values.stress = [b.stress[0], b.stress[1], b.stress[2]];
            values.strain = [b.strain[0], b.strain[1], b.strain[2]];
        }
        match &b.outline {
            Outline::Disk { radius } => {
                let first = grid.points(circle_points(b.centroid, *radius, b.rotation));
                grid.cell(first..grid.num_points() as u64, CellType::Polygon, values);
            }
            Outline::Ring { outer, inner } => {
                // the outer circle's points, then the inner's
                let o = grid.points(circle_points(b.centroid, *outer, b.rotation));
                let n = grid.points(circle_points(b.centroid, *inner, b.rotation));
                // a keyhole polygon: the outer circle ccw and back to its first point, across
                // to the inner circle's first point, the inner circle cw and back to its first
                // point; the bridge's two edges coincide, so the polygon covers the annulus
                let m = CIRCLE_SEGMENTS as u64;
                let outer = (0..=m).map(|k| o + k % m);
                let inner = (0..=m).map(|k| n + (m - k) % m);
                grid.cell(outer.chain(inner), CellType::Polygon, values);
            }
            Outline::Polygon { vertices, .. } => {
                let first = grid.points(vertices.iter().copied());
                grid.cell(first..grid.num_points() as u64, CellType::Polygon, values);
            }
        }
    }
}

/// Contact lines: B's side C − g/2 n to A's side C + g/2 n (n points into A).
pub fn add_contacts(grid: &mut Grid, rec: &StepRecord) {
    for c in &rec.contacts {
        let half = c.normal * (0.5 * c.gap);
        let ids = [grid.point(c.point - half), grid.point(c.point + half)];
        let values = CellValues {
            body: c.body_a as i32,
            body_b: c.body_b as i32,
            kind: contact_kind(c.kind),
            state: state_code(c.state),
            normal_force: c.normal_force,
            shear_force: c.shear_force,
            ..CellValues::default()
        };
        grid.cell(ids, CellType::Line, values);
    }
}

/// Hook for connectors: one line cell per segment, with its values (`axial_force`, `state`).
pub fn add_lines(grid: &mut Grid, lines: &[LineCell]) {
    for l in lines {
        let ids = [grid.point(l.a), grid.point(l.b)];
        grid.cell(ids, CellType::Line, l.values);
    }
}

/// Hook for mesh bodies: triangles (`kind` 30) with stress and strain as cell data, nodes with
/// `displacement` as point data (zero at the points of other cells).
pub fn add_mesh(grid: &mut Grid, mesh: &MeshCells) {
    if grid.displacement.is_none() {
        grid.displacement = Some(vec![0.0; grid.points.len()]);
    }
    let first = grid.num_points() as u64;
    for (k, p) in mesh.nodes.iter().enumerate() {
        grid.point(*p);
        let u = mesh.displacement.get(k).copied().unwrap_or_else(Vec2::zeros);
        if let Some(d) = &mut grid.displacement {
            let n = d.len();
            d[n - 3] = u.x;
            d[n - 2] = u.y;
        }
    }
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let values = CellValues {
            body: mesh.body,
            body_b: -1,
            kind: 30,
            state: -1,
            stress: mesh.stress.get(t).copied().unwrap_or_default(),
            strain: mesh.strain.get(t).copied().unwrap_or_default(),
            ..CellValues::default()
        };
        grid.cell(tri.iter().map(|&i| first + i as u64), CellType::Triangle, values);
    }
}

/// The grid of a step (bodies, then contact lines, connectors and meshes), into `grid`.
pub fn step_grid(grid: &mut Grid, world: &World, rec: &StepRecord) {
    grid.clear();
    add_bodies(grid, world);
    add_contacts(grid, rec);
    add_lines(grid, &connector_lines(world, rec.step));
    for (i, b) in world.bodies.iter().enumerate().filter(|&(i, _)| !world.is_removed(i)) {
        if let Some(fe) = &b.mesh {
            add_mesh(grid, &mesh_cells(i, fe));
        }
    }
}

/// The connectors as line cells between their current anchors: intact ones, and those that
/// broke in this step (the rows of `connectors.csv`, with its values).
pub fn connector_lines(world: &World, step: usize) -> Vec<LineCell> {
    world
        .connectors
        .iter()
        .filter(|c| !c.broken || c.broken_at == Some(step))
        .map(|c| LineCell { a: c.anchors[0], b: c.anchors[1], values: connector_values(c) })
        .collect()
}

/// `state` code of a connector: 4 intact, 5 broken, 6 yielding.
pub fn connector_state(c: &Connector) -> i32 {
    if c.broken {
        5
    } else if c.is_yielding() {
        6
    } else {
        4
    }
}

/// A connector's cell values: those of its `connectors.csv` row (the force it broke at for a
/// broken one; plastic strain zero for kinds other than bolts).
fn connector_values(c: &Connector) -> CellValues {
    CellValues {
        body: c.bodies[0] as i32,
        body_b: c.bodies[1] as i32,
        kind: 20,
        state: connector_state(c),
        axial_force: if c.broken { c.broke_with.unwrap_or(0.0) } else { c.axial_force() },
        plastic_strain: c.strain().map_or(0.0, |_| c.plastic_strain),
        ..CellValues::default()
    }
}

/// The cells of a mesh body (math note §9): its triangles on the current nodes, the nodes'
/// accumulated displacement, the elements' stress and strain.
pub fn mesh_cells(body: usize, fe: &crate::mesh::body::MeshBody) -> MeshCells {
    let triple = |v: &nalgebra::Vector3<f64>| [v[0], v[1], v[2]];
    MeshCells {
        body: body as i32,
        nodes: fe.nodes.clone(),
        displacement: fe.displacement.clone(),
        triangles: fe.triangles.clone(),
        stress: fe.stress.iter().map(triple).collect(),
        strain: fe.strain.iter().map(triple).collect(),
    }
}
