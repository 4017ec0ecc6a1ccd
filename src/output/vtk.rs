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
//! `shear_force`, `axial_force` (zero where they do not apply) and `state`. Codes:
//!
//! | array | code |
//! |---|---|
//! | `kind` | 0 rigid body, 1 deformable body, 2 fixed body, 10 PP, 11 PB, 12 BB, 13 LL, 14 PL, 15 BL contact, 20 connector, 30 mesh triangle |
//! | `state` | −1 body, 0 open, 1 stick, 2 slide, 3 bonded, 4 intact, 5 broken connector |
//!
//! The legend is repeated as a comment in `scene.pvd`.

use super::csv::OutputError;
use crate::body::{Body, Outline};
use crate::contact::ContactKind;
use crate::geometry::Vec2;
use crate::world::{ContactState, StepRecord, World};
use std::fs::{self, File};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

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
pub const LEGEND: &str = "kind: 0 rigid body, 1 deformable body, 2 fixed body, 10 PP, 11 PB, 12 BB contact, \
20 connector, 30 mesh triangle; state: -1 body, 0 open, 1 stick, 2 slide, 3 bonded, 4 intact, 5 broken";

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
}

/// A line cell for [`add_lines`] (connectors): end points and the values of the line
/// (`axial_force` tension-positive, `state` 4 intact or 5 broken, `kind` 20).
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

    /// Empties the grid, keeping its storage for the next step's (the 10,000-disk pile's grid
    /// is 28 MB: new storage each step costs its page faults).
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

/// One data array of a `.vtu` file: its XML attributes and its values, appended raw.
struct Array<'a> {
    name: &'a str,
    components: usize,
    values: Values<'a>,
}

enum Values<'a> {
    F64(std::borrow::Cow<'a, [f64]>),
    I32(Vec<i32>),
    /// Point ids and offsets: Int32 while every value fits (half the bytes), else Int64.
    Ids(&'a [u64], bool),
    U8(Vec<u8>),
}

impl Values<'_> {
    fn vtk_type(&self) -> &'static str {
        match self {
            Values::F64(_) => "Float64",
            Values::I32(_) => "Int32",
            Values::Ids(_, true) => "Int64",
            Values::Ids(_, false) => "Int32",
            Values::U8(_) => "UInt8",
        }
    }

    /// Size of the data in bytes.
    fn bytes(&self) -> usize {
        match self {
            Values::F64(v) => 8 * v.len(),
            Values::I32(v) => 4 * v.len(),
            Values::Ids(v, wide) => (if *wide { 8 } else { 4 }) * v.len(),
            Values::U8(v) => v.len(),
        }
    }

    /// The block of the appended data: its size (UInt64), then its values, little-endian,
    /// base64-encoded together as one stream (padded at the block's end).
    fn write(&self, w: &mut impl Write, buf: &mut Vec<u8>) -> std::io::Result<()> {
        let mut w = base64::write::EncoderWriter::new(w, &base64::engine::general_purpose::STANDARD);
        self.write_raw(&mut w, buf)?;
        w.finish().map(|_| ())
    }

    fn write_raw(&self, w: &mut impl Write, buf: &mut Vec<u8>) -> std::io::Result<()> {
        w.write_all(&(self.bytes() as u64).to_le_bytes())?;
        match self {
            Values::F64(v) => write_le(w, buf, v, |x| x.to_le_bytes()),
            Values::I32(v) => write_le(w, buf, v, |x| x.to_le_bytes()),
            Values::Ids(v, true) => write_le(w, buf, v, |x| (x as i64).to_le_bytes()),
            Values::Ids(v, false) => write_le(w, buf, v, |x| (x as i32).to_le_bytes()),
            Values::U8(v) => w.write_all(v),
        }
    }
}

/// Writes `values` as little-endian bytes, a few thousand at a time through `buf`.
fn write_le<T: Copy, const N: usize>(
    w: &mut impl Write,
    buf: &mut Vec<u8>,
    values: &[T],
    bytes: impl Fn(T) -> [u8; N],
) -> std::io::Result<()> {
    for chunk in values.chunks(4096) {
        buf.clear();
        chunk.iter().for_each(|&x| buf.extend_from_slice(&bytes(x)));
        w.write_all(buf)?;
    }
    Ok(())
}

impl Grid {
    /// Writes the grid as a VTK XML UnstructuredGrid (`.vtu`) with its data appended raw: the
    /// cell data of the module notes, the points' `displacement` once a mesh is added.
    pub fn write_vtu(&self, w: &mut impl Write) -> std::io::Result<()> {
        let c = &self.cells;
        let ints = |f: fn(&CellValues) -> i32| Values::I32(c.iter().map(f).collect());
        let reals = |f: fn(&CellValues) -> f64| Values::F64(c.iter().map(f).collect());
        let triple = |f: fn(&CellValues) -> [f64; 3]| Values::F64(c.iter().flat_map(f).collect());
        let array = |name, components, values| Array { name, components, values };
        let cell = [
            array("body", 1, ints(|v| v.body)),
            array("body_b", 1, ints(|v| v.body_b)),
            array("kind", 1, ints(|v| v.kind)),
            array("state", 1, ints(|v| v.state)),
            array("velocity", 3, triple(|v| [v.velocity[0], v.velocity[1], 0.0])),
            array("angular_velocity", 1, reals(|v| v.angular_velocity)),
            array("rotation", 1, reals(|v| v.rotation)),
            array("stress", 3, triple(|v| v.stress)),
            array("strain", 3, triple(|v| v.strain)),
            array("normal_force", 1, reals(|v| v.normal_force)),
            array("shear_force", 1, reals(|v| v.shear_force)),
            array("axial_force", 1, reals(|v| v.axial_force)),
        ];
        let point: Vec<Array> =
            self.displacement.iter().map(|d| array("displacement", 3, Values::F64(d.into()))).collect();
        let points = [array("Points", 3, Values::F64((&self.points[..]).into()))];
        // every id is below the point count, every offset at most the connectivity's length
        let wide = self.num_points().max(self.connectivity.len()) > i32::MAX as usize;
        let cells = [
            array("connectivity", 1, Values::Ids(&self.connectivity, wide)),
            array("offsets", 1, Values::Ids(&self.offsets, wide)),
            array("types", 1, Values::U8(self.types.iter().map(|&t| t as u8).collect())),
        ];
        let (np, nc) = (self.num_points(), self.num_cells());
        writeln!(w, "<?xml version=\"1.0\"?>")?;
        writeln!(
            w,
            "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">"
        )?;
        writeln!(w, "  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"{np}\" NumberOfCells=\"{nc}\">")?;
        let mut offset = 0;
        let sections: [(&str, &str, &[Array]); 4] = [
            ("PointData", if point.is_empty() { "" } else { " Vectors=\"displacement\"" }, &point),
            ("CellData", " Scalars=\"body\" Vectors=\"velocity\"", &cell),
            ("Points", "", &points),
            ("Cells", "", &cells),
        ];
        for (tag, active, arrays) in sections {
            writeln!(w, "      <{tag}{active}>")?;
            for a in arrays {
                let (ty, name, n) = (a.values.vtk_type(), a.name, a.components);
                writeln!(
                    w,
                    "        <DataArray type=\"{ty}\" Name=\"{name}\" NumberOfComponents=\"{n}\" format=\"appended\" offset=\"{offset}\"/>"
                )?;
                offset += (8 + a.values.bytes()).div_ceil(3) * 4;
            }
            writeln!(w, "      </{tag}>")?;
        }
        writeln!(w, "    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"base64\">")?;
        w.write_all(b"_")?;
        let mut buf = Vec::with_capacity(8 * 4096);
        for (_, _, arrays) in sections {
            for a in arrays {
                a.values.write(w, &mut buf)?;
            }
        }
        writeln!(w, "\n  </AppendedData>\n</VTKFile>")
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

/// The connectors as line cells between their anchors: intact ones, and those that broke in
/// this step (as in `connectors.csv`).
pub fn connector_lines(world: &World, step: usize) -> Vec<LineCell> {
    world
        .connectors
        .iter()
        .filter(|c| !c.broken || c.broken_at == Some(step))
        .map(|c| LineCell {
            a: c.anchors[0],
            b: c.anchors[1],
            values: CellValues {
                body: c.bodies[0] as i32,
                body_b: c.bodies[1] as i32,
                kind: 20,
                state: if c.broken { 5 } else { 4 },
                axial_force: if c.broken { 0.0 } else { c.axial_force() },
                ..CellValues::default()
            },
        })
        .collect()
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

/// Writes `DIR/vtk/` as the run goes.
pub struct VtkWriter {
    dir: PathBuf,
    every: usize,
    last_step: usize,
    /// (time, file name) of the written steps.
    written: Vec<(f64, String)>,
    /// The last step's grid, whose storage the next one reuses.
    grid: Grid,
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> OutputError + '_ {
    move |source| OutputError::Io { path: path.to_path_buf(), source }
}

impl VtkWriter {
    /// Creates `DIR/vtk/` and removes the `.vtu`/`.pvd` files of an earlier run in it (call
    /// after [`super::csv::CsvWriter::create`], which refuses to mix runs unless told to
    /// overwrite). Writes the empty time series.
    pub fn create(dir: &Path, world: &World) -> Result<VtkWriter, OutputError> {
        let dir = dir.join("vtk");
        fs::create_dir_all(&dir).map_err(io_err(&dir))?;
        for entry in fs::read_dir(&dir).map_err(io_err(&dir))? {
            let path = entry.map_err(io_err(&dir))?.path();
            let ours = path.extension().is_some_and(|e| e == "vtu" || e == "pvd" || e == "tmp");
            if ours {
                fs::remove_file(&path).map_err(io_err(&path))?;
            }
        }
        let out = &world.model.output;
        let w = VtkWriter {
            dir,
            every: out.every.max(1),
            last_step: world.model.time.steps,
            written: vec![],
            grid: Grid::default(),
        };
        w.write_pvd()?;
        Ok(w)
    }

    /// Path of the time series file.
    pub fn pvd_path(&self) -> PathBuf {
        self.dir.join("scene.pvd")
    }

    /// Writes the step's `.vtu` on every N-th and the last step (as the CSVs), then the
    /// updated `.pvd`.
    pub fn write_step(&mut self, world: &World, rec: &StepRecord) -> Result<(), OutputError> {
        let s = rec.step;
        if !self.writes(s) {
            return Ok(());
        }
        let mut grid = std::mem::take(&mut self.grid);
        step_grid(&mut grid, world, rec);
        let name = format!("step_{s:06}.vtu");
        let written = self.write_vtu(&grid, &name);
        self.grid = grid;
        written?;
        self.written.push((rec.time, name));
        self.write_pvd()
    }

    /// Makes `step` the last step, always written (a run whose last stage ended early).
    pub fn finish_at(&mut self, step: usize) {
        self.last_step = step;
    }

    /// Whether step `step` gets a file: every `every`-th step and the last.
    pub fn writes(&self, step: usize) -> bool {
        super::written(step, self.every, self.last_step)
    }

    fn write_vtu(&self, grid: &Grid, name: &str) -> Result<(), OutputError> {
        let path = self.dir.join(name);
        let tmp = self.dir.join(format!("{name}.tmp"));
        let file = File::create(&tmp).map_err(io_err(&tmp))?;
        let mut w = BufWriter::with_capacity(1 << 16, file);
        grid.write_vtu(&mut w).map_err(io_err(&tmp))?;
        w.flush().map_err(io_err(&tmp))?;
        fs::rename(&tmp, &path).map_err(io_err(&path))
    }

    /// The collection file, written to a temporary file and renamed (atomic on one file
    /// system), so a reader never sees a half-written index.
    fn write_pvd(&self) -> Result<(), OutputError> {
        let path = self.pvd_path();
        let tmp = self.dir.join("scene.pvd.tmp");
        let mut text = String::from("<?xml version=\"1.0\"?>\n");
        text.push_str(&format!("<!-- pbdda time series; {LEGEND} -->\n"));
        text.push_str("<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n");
        text.push_str("  <Collection>\n");
        for (t, name) in &self.written {
            text.push_str(&format!(
                "    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{name}\"/>\n",
                super::csv::Num(*t)
            ));
        }
        text.push_str("  </Collection>\n</VTKFile>\n");
        fs::write(&tmp, text).map_err(io_err(&tmp))?;
        fs::rename(&tmp, &path).map_err(io_err(&path))
    }
}
