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
    /// The benchmark pile of the issue: radius 0.5, density 1, μ 0.6, dt 1/60.
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
        let wall = |name: &str, x0: f64, y0: f64, x1: f64, y1: f64| BodySpec {
            name: name.into(),
            shape: Shape::Polygon {
                vertices: vec![Vec2::new(x0, y0), Vec2::new(x1, y0), Vec2::new(x1, y1), Vec2::new(x0, y1)],
            },
            model: BodyModel::Rigid,
            material: 0,
            fixed: true,
            velocity: Vec2::zeros(),
            angular_velocity: 0.0,
            initial_stress: None,
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
                bodies.push(BodySpec {
                    name: format!("d{row}_{col}"),
                    shape: Shape::Disk { center: Vec2::new(x, y), radius: r },
                    model: self.model,
                    material: 0,
                    fixed: false,
                    velocity: Vec2::zeros(),
                    angular_velocity: 0.0,
                    initial_stress: None,
                });
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
            connectors: vec![],
            monitors: vec![],
            output: OutputSettings { every: 1, steps_every: 1, vtk: true },
        }
    }
}
