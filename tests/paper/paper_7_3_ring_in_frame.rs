//! Paper §7.3, Figure 27: rigid ring (RE = 3) in a fixed square frame of inner half-width 20,
//! v0 = (2.5, 5), frictionless, no gravity, dt = 0.05, 2050 steps (102.5 s).
//!
//! Criterion: the exact path of math note §7.3, x = fold(2.5 t, a), y = fold(5 t, a) with
//! a = half-width - 3 = 17 (a frictionless elastic billiard is a straight line folded at the
//! walls), speed sqrt(2.5² + 5²) constant, no rotation.
//! - Centre within 1e-6 m of the exact path at every step. The scheme of math note §1.3 makes
//!   each impact exact up to the solver tolerance (1e-12 here); the prototype met 3e-9 m, so
//!   1e-6 m (1e-7 of the 34 m travel between walls) leaves room for rounding over 2050 steps
//!   while catching a one-step lag at any impact (v dt = 0.125 m).
//! - Speed within 1e-9 relative and rotation (angle and rate) below 1e-9: energy conservation of
//!   an elastic frictionless impact, and a normal through the centre exerts no moment; 1e-9 is
//!   well above rounding (1e-16 per step) and far below any lost impulse.
//! - Exact number of wall hits: the folded path meets the side walls when 2.5 t = a, 3a, 5a, ...
//!   and the floor/roof when 5 t = a, 3a, ... (see `common::reflections`). For a = 17 and
//!   t = 102.5 s: 2.5 t = 256.25 = 17 + 7·34 + 1.25, so 8 side-wall hits (t = 6.8 + 13.6 k,
//!   k = 0..7, the last at 102.0 s); 5 t = 512.5 = 17 + 14·34 + 19.5, so 15 floor/roof hits
//!   (t = 3.4 + 6.8 j, j = 0..14, the last at 98.6 s); the two families never coincide
//!   (6.8 + 13.6 k = 3.4 + 6.8 j has no integer solution), so 23 impacts, each counted as a
//!   reversal of vx or vy, and each an impact that loads its contact in exactly one step
//!   (math note §1.3: the impacting step reflects the velocity, the next one separates).
//!
//! Case 2 widens the frame to 20.07 (a = 17.07) so that the impacts fall mid-step (math note
//! §1.3: the g0-in-the-gap scheme with doubled impact share stays exact there too): 2.5 t =
//! 256.25 = 17.07 + 7·34.14 + 0.2, so again 8 side-wall hits (the last at 102.42 s, 1.6 steps
//! before the end), and 5 t = 512.5 = 17.07 + 14·34.14 + 17.47, so 15 floor/roof hits.

use crate::common;
use common::*;
use pbdda::geometry::Vec2;
use pbdda::model::{Model, Shape};
use pbdda::world::World;

fn check_billiard(model: Model, a: f64, expected: (usize, usize)) {
    let (dt, steps) = (model.time.step, 2050);
    let t_end = steps as f64 * dt;
    // the closed-form count (panics if a hit falls within a step of the end)
    assert_eq!((reflections(2.5, a, t_end, dt), reflections(5.0, a, t_end, dt)), expected);
    let mut world = World::new(model);
    let ring = body(&world, "ring");
    let speed = (2.5f64 * 2.5 + 25.0).sqrt();
    let mut hits = WallHits::starting_at(2.5, 5.0);
    let mut loaded_steps = 0;
    run(&mut world, steps, |w, rec| {
        let b = &w.bodies[ring];
        let exact = Vec2::new(fold(2.5 * rec.time, a), fold(5.0 * rec.time, a));
        assert!(
            (b.centroid - exact).norm() < 1e-6,
            "step {}: centre {} vs exact {}",
            rec.step,
            b.centroid,
            exact
        );
        let v = Vec2::new(b.velocity[0], b.velocity[1]).norm();
        assert!((v - speed).abs() < 1e-9 * speed, "step {}: speed {v}", rec.step);
        assert!(b.rotation.abs() < 1e-9 && b.velocity[2].abs() < 1e-9, "step {}: rotation", rec.step);
        hits.observe(b.velocity[0], b.velocity[1]);
        let loaded = rec.contacts.iter().filter(|c| c.normal_force > 0.0).count();
        assert!(loaded <= 1, "step {}: {loaded} loaded contacts (no two walls are hit at once)", rec.step);
        loaded_steps += loaded;
    });
    eprintln!(
        "7.3 (a = {a}): {} side-wall and {} floor/roof hits, {loaded_steps} loaded steps",
        hits.x, hits.y
    );
    assert_eq!((hits.x, hits.y), expected, "wall hits (side, floor/roof)");
    assert_eq!(loaded_steps, expected.0 + expected.1, "steps with a loaded contact (one per impact)");
}

#[test]
fn impacts_on_step_boundaries() {
    check_billiard(example("7_3_ring_in_frame.toml"), 17.0, (8, 15));
}

#[test]
fn impacts_mid_step() {
    let mut model = example("7_3_ring_in_frame.toml");
    // move the four walls out to an inner half-width of 20.07 (thickness kept)
    for b in model.bodies.iter_mut().filter(|b| b.fixed) {
        if let Shape::Polygon { vertices } = &mut b.shape {
            for v in vertices.iter_mut() {
                *v = v.map(|c| if c.abs() >= 20.0 { c + 0.07 * c.signum() } else { c });
            }
        }
    }
    check_billiard(model, 17.07, (8, 15));
}
