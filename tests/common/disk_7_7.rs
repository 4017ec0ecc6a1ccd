//! The disk of paper §7.7 (math note §7.7): rigid, R = 1 m, rho = 1000, on a fixed block under
//! gravity 10 m/s², pulled by a horizontal F = 1000 N. Shared by the 7.7 tests.

use super::{body, example};
use pbdda::geometry::Vec2;
use pbdda::model::Model;
use pbdda::world::World;

/// The horizontal pull [N].
pub const F: f64 = 1000.0;
/// Disk radius [m].
pub const R: f64 = 1.0;

/// m = rho π R² [kg per metre of thickness].
pub fn mass() -> f64 {
    1000.0 * std::f64::consts::PI * R * R
}

/// G = m g with g = 10 m/s².
pub fn weight() -> f64 {
    mass() * 10.0
}

/// Loads `examples/SCENE` with the load point moved to height `d` above the contact point
/// (the contact is at y = 0).
pub fn with_lever(scene: &str, d: f64) -> Model {
    let mut model = example(scene);
    model.loads[0].point = Vec2::new(0.0, d);
    model
}

pub fn monitor(world: &World, name: &str) -> usize {
    world.model.monitors.iter().position(|m| m.name == name).unwrap_or_else(|| panic!("no monitor {name}"))
}

/// Where the disk is after 500 steps of 0.01 s (t = 5 s) of `examples/7_7_trajectories.toml`
/// (d = R) with friction `mu` and rolling length `delta`.
pub struct Trajectory {
    /// Horizontal displacement of the centre O (monitor "O") [m].
    pub x: f64,
    /// Rotation of the disk, ccw positive [rad].
    pub rotation: f64,
    /// Angular velocity at t = 5 s, ccw positive [rad/s].
    pub spin: f64,
}

pub fn trajectory(mu: f64, delta: f64) -> Trajectory {
    let mut model = example("7_7_trajectories.toml");
    model.interfaces[0].friction = mu;
    model.interfaces[0].rolling = delta;
    let mut world = World::new(model);
    let disk = body(&world, "disk");
    let o = monitor(&world, "O");
    super::run(&mut world, 500, |_, _| {});
    assert!((world.time - 5.0).abs() < 1e-9);
    Trajectory {
        x: world.monitors[o].current.x - world.monitors[o].initial.x,
        rotation: world.bodies[disk].rotation,
        spin: world.bodies[disk].velocity[2],
    }
}
