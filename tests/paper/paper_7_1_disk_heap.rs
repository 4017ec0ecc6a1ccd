//! Paper §7.1, Table 1: static heap of three rigid disks (R = 10, rho = 2500, g = 10) on a
//! fixed floor. Closed form (statics): F1 = G, F2 = 2G, F3 = 3G with G = rho pi R^2 g, all
//! tangential forces 0, no motion. Tolerance 1e-3 N (4e-11 relative) on every force: tighter than
//! the paper's own PB-DDA errors (0.75e-3 to 2.2e-3 N), and the statics are exact in the scheme,
//! so the only error is the solver's: its tolerance (1e-13 scaled residual, relative to the
//! largest force, math note §4.3) is ~2e-6 N on forces of 2e7 N, leaving ample room.

use crate::common;
use common::*;
use pbdda::world::World;

#[test]
fn heap_forces_match_table_1_at_step_100() {
    let g_weight = 2500.0 * std::f64::consts::PI * 100.0 * 10.0;
    let mut world = World::new(example("7_1_disk_heap.toml"));
    let y0: Vec<f64> = world.bodies.iter().map(|b| b.centroid.y).collect();
    let mut last = None;
    run(&mut world, 100, |_, rec| last = Some(rec.clone()));
    let rec = last.expect("100 steps ran");
    assert_eq!(rec.step, 100);
    for (a, b, expected) in
        [("d1", "d2", g_weight), ("d2", "d3", 2.0 * g_weight), ("d3", "floor", 3.0 * g_weight)]
    {
        let c = between(&world, &rec, a, b);
        assert_eq!(c.len(), 1, "one contact between {a} and {b}");
        assert!(
            (c[0].normal_force - expected).abs() < 1e-3,
            "{a}-{b}: F = {} N, expected {expected} N",
            c[0].normal_force
        );
        assert!(c[0].shear_force.abs() < 1e-3, "{a}-{b}: shear {} N", c[0].shear_force);
    }
    // d = 0 at every step: the disks stay where they were (static solution is exact).
    for (b, y) in world.bodies.iter().zip(&y0) {
        assert!((b.centroid.y - y).abs() < 1e-9, "{} moved by {}", b.name, b.centroid.y - y);
    }
}
