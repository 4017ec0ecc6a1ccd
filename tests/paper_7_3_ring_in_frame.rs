//! Paper §7.3, Figure 27: rigid ring (RE = 3) in a fixed square frame, v0 = (2.5, 5),
//! frictionless, dt = 0.05, 2050 steps. Exact path (design note §7.3): x = fold(2.5 t, a),
//! y = fold(5 t, a) with a = half-width - 3; speed sqrt(2.5² + 5²) constant; no rotation.
//! Tolerances (the issue's): 1e-6 m on the centre at every step, 1e-9 relative on the speed.
//! Case 2 widens the frame to 20.07 so that the impacts fall mid-step (design note §1.3: the
//! g0-in-the-gap scheme with doubled impact share stays exact there too).

mod common;
use common::*;
use pbdda::geometry::Vec2;
use pbdda::model::{Model, Shape};
use pbdda::world::World;

fn check_billiard(model: Model, a: f64) {
    let mut world = World::new(model);
    let ring = body(&world, "ring");
    let speed = (2.5f64 * 2.5 + 25.0).sqrt();
    let mut impacts = 0;
    run(&mut world, 2050, |w, rec| {
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
        impacts += rec.contacts.iter().filter(|c| c.normal_force > 0.0).count();
    });
    // 2050 steps = 102.5 s; reflections every 17/2.5·... : at least one impact per wall crossing.
    assert!(impacts >= 10, "the ring must actually hit the walls ({impacts} loaded contacts)");
}

#[test]
fn impacts_on_step_boundaries() {
    check_billiard(example("7_3_ring_in_frame.toml"), 17.0);
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
    check_billiard(model, 17.07);
}
