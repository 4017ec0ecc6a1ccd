//! Scene generators for benchmarks and large tests (shared by `benches/` and the test suite).

use crate::geometry::Vec2;
use crate::model::*;

/// Parameters of a pile of equal rigid disks in a box.
#[derive(Debug, Clone, Copy)]
pub struct DiskPile {
    /// Disks per row (odd rows are shifted by one radius).
    pub columns: usize,
    pub rows: usize,
    pub radius: f64,
    pub density: f64,
    pub friction: f64,
    pub dt: f64,
    /// Rolling friction length δ for the disk contacts (0: none).
    pub rolling: f64,
    /// Rigid disks, or deformable ones (E = 1e8 Pa, ν = 0.3).
    pub model: BodyModel,
}

impl DiskPile {
    /// The benchmark pile (`benches/`, `pbdda-compare`): radius 0.5, density 1, μ 0.6, dt 1/60.
    pub fn benchmark(columns: usize, rows: usize) -> DiskPile {
        DiskPile {
            columns,
            rows,
            radius: 0.5,
            density: 1.0,
            friction: 0.6,
            dt: 1.0 / 60.0,
            rolling: 0.0,
            model: BodyModel::Rigid,
        }
    }

    /// Hexagonal close packing resting on a fixed floor between two fixed walls: every disk
    /// touches its neighbours (g0 = 0), so the pile is settled from the first step.
    /// Even rows touch the left wall, odd rows the right wall. Steps are fixed and a step that
    /// does not converge is kept (`adaptive = false`, `allow_unconverged = true`): the piles
    /// time steps and report their convergence themselves (`benches/`).
    pub fn model(&self) -> Model {
        let r = self.radius;
        let width = 2.0 * r * self.columns as f64 + r;
        let height = (self.rows as f64 + 1.0) * 2.0 * r;
        let material =
            Material { name: "grain".into(), density: self.density, young: Some(1e8), poisson: Some(0.3) };
        let wall = |name: &str, x0: f64, y0: f64, x1: f64, y1: f64| {
            let vertices = vec![Vec2::new(x0, y0), Vec2::new(x1, y0), Vec2::new(x1, y1), Vec2::new(x0, y1)];
            BodySpec::at_rest(name, Shape::Polygon { vertices }, BodyModel::Rigid, true)
        };
        let mut bodies = vec![
            wall("floor", -r, -r, width + r, 0.0),
            wall("left", -r, 0.0, 0.0, height),
            wall("right", width, 0.0, width + r, height),
        ];
        let dy = 3f64.sqrt() * r;
        for row in 0..self.rows {
            for col in 0..self.columns {
                let x = r + 2.0 * r * col as f64 + if row % 2 == 1 { r } else { 0.0 };
                let y = r + dy * row as f64;
                let disk = Shape::Disk { center: Vec2::new(x, y), radius: r };
                bodies.push(BodySpec::at_rest(format!("d{row}_{col}"), disk, self.model, false));
            }
        }
        Model {
            name: format!("pile of {} disks", self.rows * self.columns),
            time: TimeSettings { adaptive: false, ..TimeSettings::new(self.dt, 1) },
            physics: Physics { gravity: Vec2::new(0.0, -9.81), plane: Plane::Stress, velocity_carry: 1.0 },
            contact: ContactSettings { threshold: Some(0.1 * r) },
            solver: SolverSettings {
                tolerance: 1e-6,
                max_iterations: 20_000,
                allow_unconverged: true,
                ..SolverSettings::default()
            },
            materials: vec![material],
            interfaces: vec![Interface {
                friction: self.friction,
                rolling: self.rolling,
                ..Interface::SMOOTH
            }],
            bodies,
            loads: vec![],
            tractions: Vec::new(),
            connectors: vec![],
            monitors: vec![],
            output: OutputSettings { every: 1, steps_every: 1, vtk: true },
            stages: vec![],
            excavations: vec![],
            gravity_history: None,
        }
    }
}

/// A rectangular meshed block resting on a fixed rigid floor with a rigid disk pressed into the
/// middle of its top (the 100k-DOF block of `benches/mesh.rs`): `nx` × `ny` cells of a
/// structured grid, each split into two 3-node triangles along alternating diagonals (so the mesh has no
/// preferred direction), free nodes only (it rests on the floor by contact, `BL`), under gravity,
/// static relaxation. The disk (radius `width / 8`) carries `load` downwards.
#[derive(Debug, Clone, Copy)]
pub struct PressedBlock {
    pub nx: usize,
    pub ny: usize,
    pub width: f64,
    pub height: f64,
    pub load: f64,
    pub dt: f64,
    /// `[solver] factor_drift` (0: refactor every step).
    pub factor_drift: f64,
}

impl PressedBlock {
    /// A 4 m × 2 m block of rock (ρ 2500, E 1e10 Pa, ν 0.25) with `2 (nx + 1)(nx / 2 + 1)` DOF,
    /// a 0.5 m disk pressed by 1e6 N/m, dt 0.01.
    pub fn benchmark(nx: usize) -> PressedBlock {
        PressedBlock { nx, ny: nx / 2, width: 4.0, height: 2.0, load: 1e6, dt: 0.01, factor_drift: 0.0 }
    }

    /// The structured mesh of the block, its base on y = 0.
    pub fn mesh(&self) -> crate::mesh::Mesh {
        let (nx, ny) = (self.nx, self.ny);
        let node = |i: usize, j: usize| j * (nx + 1) + i;
        let nodes = (0..=ny)
            .flat_map(|j| {
                (0..=nx).map(move |i| {
                    Vec2::new(self.width * i as f64 / nx as f64, self.height * j as f64 / ny as f64)
                })
            })
            .collect::<Vec<_>>();
        let mut triangles = Vec::with_capacity(2 * nx * ny);
        for j in 0..ny {
            for i in 0..nx {
                let (a, b, c, d) = (node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1));
                if (i + j) % 2 == 0 {
                    triangles.extend([[a, b, c], [a, c, d]]);
                } else {
                    triangles.extend([[a, b, d], [b, c, d]]);
                }
            }
        }
        crate::mesh::Mesh {
            file: format!("generated {nx}x{ny} block"),
            node_tags: (1..=nodes.len() as u64).collect(),
            nodes,
            triangles,
            groups: Vec::new(),
        }
    }

    pub fn model(&self) -> Model {
        let (w, h) = (self.width, self.height);
        let r = w / 8.0;
        let rock = Material { name: "rock".into(), density: 2500.0, young: Some(1e10), poisson: Some(0.25) };
        let body = BodySpec::at_rest;
        let floor = vec![
            Vec2::new(-0.5, -0.5),
            Vec2::new(w + 0.5, -0.5),
            Vec2::new(w + 0.5, 0.0),
            Vec2::new(-0.5, 0.0),
        ];
        let block = MeshShape { mesh: self.mesh(), fixed_nodes: Vec::new(), rollers: Vec::new() };
        let center = Vec2::new(0.5 * w, h + r);
        Model {
            name: format!("{}x{} meshed block pressed by a disk", self.nx, self.ny),
            time: TimeSettings::new(self.dt, 1),
            physics: Physics { gravity: Vec2::new(0.0, -10.0), plane: Plane::Strain, velocity_carry: 0.0 },
            contact: ContactSettings { threshold: None },
            solver: SolverSettings {
                tolerance: 1e-8,
                factor_drift: self.factor_drift,
                ..SolverSettings::default()
            },
            materials: vec![rock],
            interfaces: vec![Interface { friction: 0.5, ..Interface::SMOOTH }],
            bodies: vec![
                body("floor", Shape::Polygon { vertices: floor }, BodyModel::Rigid, true),
                body("block", Shape::Mesh(Box::new(block)), BodyModel::Deformable, false),
                body("disk", Shape::Disk { center, radius: r }, BodyModel::Rigid, false),
            ],
            loads: vec![Load { body: 2, point: center, force: Vec2::new(0.0, -self.load), history: None }],
            tractions: Vec::new(),
            connectors: vec![],
            monitors: vec![],
            output: OutputSettings { every: 1, steps_every: 1, vtk: true },
            stages: vec![],
            excavations: vec![],
            gravity_history: None,
        }
    }
}
