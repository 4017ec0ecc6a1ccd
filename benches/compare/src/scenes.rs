//! The moving scenes of issue 55, as one description that both engines build from: convex
//! polygons and disks, fixed or free, one density, one friction coefficient and one coefficient
//! of restitution for every contact, one dt.
//!
//! * `collapse(n, aspect)`: a granular column of about `n` disks (radius 0.01 m, density
//!   2,500 kg/m³, hexagonal packing, every disk touching its neighbours) against a left wall on
//!   a floor; the column is released at t = 0 and spreads to the right. Run-out: the largest
//!   x of a disk's centre minus the column's initial right edge.
//! * `slide(nx, ny)`: nx × ny rigid 0.5 m square blocks (density 2,500) stacked on a fixed
//!   base whose top is a joint dipping at 35°, friction angle 20° everywhere; released from
//!   rest the mass slides as one body with the acceleration g (sin a − cos a tan φ).
//! * `rockfall()`: a 0.5 m square block dropped 1 m above the top of a rough slope (fixed
//!   quadrilaterals alternating 40° and 25°, friction 0.5, e = 0.5). Run-out: the block's
//!   horizontal travel at the end.

use pbdda::geometry::Vec2;
use pbdda::model::*;

/// One body of a scene.
#[derive(Clone)]
pub enum Shape2 {
    Disk {
        center: Vec2,
        radius: f64,
    },
    /// Counter-clockwise convex polygon.
    Polygon(Vec<Vec2>),
}

#[derive(Clone)]
pub struct Body {
    pub shape: Shape2,
    pub fixed: bool,
}

/// A scene both engines build.
#[derive(Clone)]
pub struct Scene {
    pub name: String,
    pub bodies: Vec<Body>,
    pub density: f64,
    pub friction: f64,
    pub restitution: f64,
    pub dt: f64,
    pub steps: usize,
    /// The accuracy measure of the scene (run-out or displacement), from the bodies' centres.
    pub measure: Measure,
}

#[derive(Clone, Copy)]
pub enum Measure {
    /// Largest centre x of a free body minus this x.
    RunOut(f64),
    /// Mean travel of the free bodies along this unit vector.
    Travel(Vec2),
}

impl Measure {
    /// The measure from the free bodies' initial and final centres.
    pub fn of(&self, start: &[Vec2], end: &[Vec2]) -> f64 {
        match *self {
            Measure::RunOut(x0) => end.iter().map(|c| c.x).fold(f64::MIN, f64::max) - x0,
            Measure::Travel(d) => {
                start.iter().zip(end).map(|(a, b)| (b - a).dot(&d)).sum::<f64>() / start.len() as f64
            }
        }
    }
}

fn quad(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Vec2> {
    vec![Vec2::new(x0, y0), Vec2::new(x1, y0), Vec2::new(x1, y1), Vec2::new(x0, y1)]
}

/// About `n` disks in a column `aspect` times as high as wide (rounded to whole rows).
pub fn collapse(n: usize, aspect: f64, dt: f64, steps: usize) -> Scene {
    let r = 0.01;
    // width (2 c + 1) r, height (2 + (rows − 1) √3) r ≈ √3 rows r: rows/c ≈ 2 aspect/√3
    let columns = ((n as f64 * 3f64.sqrt() / (2.0 * aspect)).sqrt().round() as usize).max(1);
    let rows = (n as f64 / columns as f64).round() as usize;
    let width = (2 * columns + 1) as f64 * r;
    let mut bodies = vec![
        Body { shape: Shape2::Polygon(quad(-0.1, -0.05, 40.0 * width, 0.0)), fixed: true },
        Body { shape: Shape2::Polygon(quad(-0.05, 0.0, 0.0, 2.0 * aspect * width + 0.1)), fixed: true },
    ];
    let dy = 3f64.sqrt() * r;
    for row in 0..rows {
        for col in 0..columns {
            let x = r + 2.0 * r * col as f64 + if row % 2 == 1 { r } else { 0.0 };
            let center = Vec2::new(x, r + dy * row as f64);
            bodies.push(Body { shape: Shape2::Disk { center, radius: r }, fixed: false });
        }
    }
    Scene {
        name: format!("collapse, {} disks, aspect {aspect}", rows * columns),
        bodies,
        density: 2500.0,
        friction: 0.5,
        restitution: 0.5,
        dt,
        steps,
        measure: Measure::RunOut(width),
    }
}

/// The slope angle and friction angle of `slide` [degrees].
pub const SLIDE_DIP: f64 = 35.0;
pub const SLIDE_PHI: f64 = 20.0;

/// nx × ny blocks on a 35° joint (friction angle 20°).
pub fn slide(nx: usize, ny: usize, dt: f64, steps: usize) -> Scene {
    let (s, c) = SLIDE_DIP.to_radians().sin_cos();
    let rot = |x: f64, y: f64| Vec2::new(x * c - y * s, x * s + y * c);
    let poly = |p: Vec<Vec2>| p.into_iter().map(|v| rot(v.x, v.y)).collect::<Vec<_>>();
    let a = 0.5;
    let length = nx as f64 * a;
    let mut bodies = vec![Body {
        shape: Shape2::Polygon(poly(quad(-3.0 * length, -1.0, length + 1.0, 0.0))),
        fixed: true,
    }];
    for j in 0..ny {
        for i in 0..nx {
            let (x, y) = (i as f64 * a, j as f64 * a);
            bodies.push(Body { shape: Shape2::Polygon(poly(quad(x, y, x + a, y + a))), fixed: false });
        }
    }
    Scene {
        name: format!("slide, {} blocks", nx * ny),
        bodies,
        density: 2500.0,
        friction: SLIDE_PHI.to_radians().tan(),
        restitution: 0.5,
        dt,
        steps,
        measure: Measure::Travel(Vec2::new(-c, -s)),
    }
}

/// The closed-form travel of `slide` after time t: g (sin a − cos a tan φ) t² / 2.
pub fn slide_travel(t: f64) -> f64 {
    let (s, c) = SLIDE_DIP.to_radians().sin_cos();
    9.81 * (s - c * SLIDE_PHI.to_radians().tan()) * t * t / 2.0
}

/// A block dropped on a rough slope (segments alternating 40° and 25°, descending to the right).
pub fn rockfall(dt: f64, steps: usize) -> Scene {
    let mut bodies = Vec::new();
    let (mut x, mut y) = (0.0f64, 0.0f64);
    for k in 0..12 {
        let dip = (if k % 2 == 0 { 40f64 } else { 25f64 }).to_radians();
        let (x1, y1) = (x + 1.0, y - dip.tan());
        // a quadrilateral under the segment, down to y = −20
        let p = vec![Vec2::new(x, -20.0), Vec2::new(x1, -20.0), Vec2::new(x1, y1), Vec2::new(x, y)];
        bodies.push(Body { shape: Shape2::Polygon(p), fixed: true });
        (x, y) = (x1, y1);
    }
    bodies.push(Body { shape: Shape2::Polygon(quad(0.05, 1.0, 0.55, 1.5)), fixed: false });
    Scene {
        name: "rockfall, one block".into(),
        bodies,
        density: 2500.0,
        friction: 0.5,
        restitution: 0.5,
        dt,
        steps,
        measure: Measure::RunOut(0.3),
    }
}

impl Scene {
    /// The pbdda model: rigid bodies, one interface, adaptive steps (the scene format's
    /// default), tolerance `tol`, a step that misses kept (counted by the caller).
    pub fn model(&self, tol: f64) -> Model {
        let material =
            Material { name: "rock".into(), density: self.density, young: Some(1e9), poisson: Some(0.25) };
        let bodies = (self.bodies.iter().enumerate())
            .map(|(i, b)| {
                let shape = match &b.shape {
                    Shape2::Disk { center, radius } => Shape::Disk { center: *center, radius: *radius },
                    Shape2::Polygon(v) => Shape::Polygon { vertices: v.clone() },
                };
                BodySpec::at_rest(format!("b{i}"), shape, BodyModel::Rigid, b.fixed)
            })
            .collect();
        Model {
            name: self.name.clone(),
            time: TimeSettings::new(self.dt, self.steps),
            physics: Physics { gravity: Vec2::new(0.0, -9.81), plane: Plane::Stress, velocity_carry: 1.0 },
            contact: ContactSettings { threshold: None },
            solver: SolverSettings { tolerance: tol, allow_unconverged: true, ..SolverSettings::default() },
            materials: vec![material],
            interfaces: vec![Interface {
                friction: self.friction,
                restitution: self.restitution,
                ..Interface::SMOOTH
            }],
            bodies,
            loads: vec![],
            tractions: Vec::new(),
            connectors: vec![],
            monitors: vec![],
            output: OutputSettings { every: 1, steps_every: 1, vtk: false },
            stages: vec![],
            excavations: vec![],
            gravity_history: None,
        }
    }
}
