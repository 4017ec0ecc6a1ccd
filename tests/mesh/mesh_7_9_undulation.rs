//! Paper §7.9 (math note §7.9, §9.5): a rigid particle (R = 0.5 m) bouncing between a stiff
//! meshed block below (`examples/7_9_undulation.toml`: `meshes/undulation.msh`, clamped on its
//! base, E = 1e17 Pa) and a fixed rigid block above, 0.5 m of free centre travel, starting midway
//! with v = (1, v_y), frictionless, no gravity, 1 s. Closed form: the centre's height is the
//! triangle wave 0.75 + fold(v_y t, 0.25) (exact reflections), x = t, the speed stays
//! sqrt(1 + v_y²), and the particle meets the walls 2 v_y times (2, 4, 6 for v_y = 1, 2, 3),
//! counted as sign reversals of v_y. Tolerances (the issue's): path within 1e-5 m, speed within
//! 1e-6 relative. The mesh under a contact is 1e-17/(dt²/2m) ~ 4e-8 as compliant as the particle
//! is mobile in one step, so the energy an impact leaves in the block's vibration is ~4e-8 per impact (measured: with E = 1e16 the speed drifts by 1.7e-6 after 4 impacts).

use crate::common;

use common::{WallHits, fold, reflections};
use pbdda::world::World;

fn bounce(vy: f64) {
    let mut model = common::example("7_9_undulation.toml");
    let p = model.bodies.iter().position(|b| b.name == "P").expect("particle");
    model.bodies[p].velocity.y = vy;
    let mut world = World::new(model);
    let speed = (1.0 + vy * vy).sqrt();
    let mut hits = WallHits::starting_at(1.0, vy);
    let (mut worst_path, mut worst_speed) = (0.0f64, 0.0f64);
    for _ in 0..1000 {
        world.step().unwrap_or_else(|e| panic!("{e}"));
        let (b, t) = (&world.bodies[p], world.time);
        let exact = pbdda::geometry::Vec2::new(t, 0.75 + fold(vy * t, 0.25));
        worst_path = worst_path.max((b.centroid - exact).norm());
        let v = b.velocity;
        worst_speed = worst_speed.max(((v[0] * v[0] + v[1] * v[1]).sqrt() - speed).abs() / speed);
        hits.observe(v[0], v[1]);
    }
    assert!(worst_path < 1e-5, "v_y = {vy}: path off the triangle wave by {worst_path:e} m");
    assert!(worst_speed < 1e-6, "v_y = {vy}: speed changed by {worst_speed:e}");
    assert_eq!(hits.y, reflections(vy, 0.25, 1.0, 0.001), "v_y = {vy}: impacts");
    assert_eq!(hits.y, 2 * vy as usize);
}

#[test]
fn particle_on_a_meshed_block_follows_the_triangle_wave() {
    for vy in [1.0, 2.0, 3.0] {
        bounce(vy);
    }
}
