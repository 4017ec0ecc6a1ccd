//! A very stiff deformable block in a dynamic run (math note §10.9): a 1 m x 1 m block of
//! E = 1e15 Pa (ρ = 2500, ν = 0.25, g = 10) resting on a fixed floor, velocity carry 1, dt =
//! 0.01 s, 100 steps. Its strain modes have ω dt ~ 1e4: with the γ = 1 scheme alone their
//! velocity flips sign every step and never decays (the issue measured 1,500 non-convergence
//! warnings in such a run). With the strain DOFs' damping every step converges, no step is split
//! and no warning is raised, and the block is in equilibrium: the floor's reactions sum to the
//! weight ρ g A = 25 000 N/m (tolerance 1e-6 relative: the VI's tolerance 1e-10 on these
//! forces, and strain velocities that shrink by 5 per step) and the block does not move
//! (centroid within 1e-9 m of its start: the strains are ρ g H/E ~ 1e-11). The strain rates
//! have died out: below 1e-15 1/s after 100 steps (they start near ε/dt ~ 1e-9 1/s and shrink
//! by 5 per step to round-off); without the damping they ring at 2.3e-9 1/s, flipping sign every
//! step (measured), which this assertion catches.

use pbdda::world::World;

#[test]
fn stiff_block_rests_on_the_floor_without_warnings() {
    let text = r#"
[scene]
name = "stiff"
[time]
step = 0.01
steps = 100
[physics]
gravity = [0.0, -10.0]
[solver]
tolerance = 1e-10
[[material]]
name = "rock"
density = 2500.0
young = 1.0e15
poisson = 0.25
[[interface]]
friction = 0.5
[[body]]
name = "floor"
shape = "polygon"
vertices = [[-1.0, -1.0], [2.0, -1.0], [2.0, 0.0], [-1.0, 0.0]]
material = "rock"
fixed = true
[[body]]
name = "block"
shape = "polygon"
vertices = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
material = "rock"
model = "deformable"
"#;
    let mut world = World::new(pbdda::scene::parse(text, "stiff.toml").unwrap_or_else(|e| panic!("{e}")));
    let start = world.bodies[1].centroid;
    let mut last = None;
    for _ in 0..100 {
        let rec = world.step().unwrap_or_else(|e| panic!("{e}"));
        assert!(
            rec.converged && rec.warnings.is_empty() && rec.events.is_empty(),
            "step {}: {rec:?}",
            rec.step
        );
        last = Some(rec);
    }
    let rec = last.expect("100 steps");
    let weight = 2500.0 * 10.0;
    let reaction: f64 = rec.contacts.iter().map(|c| c.normal_force * c.normal.y.abs()).sum();
    assert!((reaction - weight).abs() < 1e-6 * weight, "floor reactions {reaction} N/m, weight {weight}");
    let v = world.bodies[1].velocity;
    let rate = v[3].abs().max(v[4].abs()).max(v[5].abs());
    assert!(rate < 1e-15, "strain rates {:?} still ringing", [v[3], v[4], v[5]]);
    let moved = (world.bodies[1].centroid - start).norm();
    assert!(moved < 1e-9, "the block moved {moved} m");
}
