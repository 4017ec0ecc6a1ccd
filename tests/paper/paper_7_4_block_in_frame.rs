//! Paper §7.4, Figure 29F: rigid 20 m square block in a fixed frame of inner side 120,
//! v0 = (2.5, 5), frictionless, dt = 0.01, 10 000 steps. Exact path (math note §7.4):
//! x = fold(2.5 t, 50), y = fold(5 t, 50), rotation identically 0 (every impact is an
//! edge-edge contact whose two impulses are equal by symmetry). Tolerances at every step:
//! 1e-6 m on the centre: the scheme of math note §1.3 makes each impact exact up to the solver
//! tolerance, so 1e-6 m (1e-8 of the 100 m travel between walls) leaves room for rounding over
//! 10 000 steps while catching a one-step lag at any impact (v dt = 0.056 m); 1e-9 rad on the
//! rotation: the two impulses of an edge-edge impact differ only by the solver's error, which
//! turns the 20 m block by ~1e-12 rad per impact.

use crate::common;
use common::*;
use pbdda::geometry::Vec2;
use pbdda::world::World;

#[test]
fn block_follows_exact_folded_path_without_rotation() {
    let mut world = World::new(example("7_4_block_in_frame.toml"));
    let block = body(&world, "block");
    let mut worst = 0.0f64;
    run(&mut world, 10_000, |w, rec| {
        let b = &w.bodies[block];
        let exact = Vec2::new(fold(2.5 * rec.time, 50.0), fold(5.0 * rec.time, 50.0));
        worst = worst.max((b.centroid - exact).norm());
        assert!((b.centroid - exact).norm() < 1e-6, "step {}: centre {} vs {}", rec.step, b.centroid, exact);
        assert!(b.rotation.abs() < 1e-9, "step {}: rotation {}", rec.step, b.rotation);
    });
    eprintln!("7.4: worst centre error {worst:e} m");
}
