//! Paper §7.2, Table 2: four rigid 20 x 10 blocks in a staircase with 5 m offsets on a fixed
//! floor. Statics of the stack (math note §7.2) with block weight W = 2000 * 200 * 10 = 4e6 N:
//! floor reactions F1 = W/2 at x = 0 and F2 = 7W/2 at x = 20; level 1/2: 0 at x = 5 and 3W at
//! x = 20; level 2/3: W/3 at x = 10 and 5W/3 at x = 25; level 3/4: W/3 at x = 15 and 2W/3 at
//! x = 30. Tolerance 1e-7 W on every normal and shear force: the forces are statically determinate,
//! so the only error is the solver's, its tolerance 1e-12 relative to the largest force 3.5 W
//! (math note §4.3), about 4e-12 W; 1e-7 W leaves room for the slow convergence of the marginal
//! zero-force contact at x = 5 (math note §4.3, about 1000 PC iterations) and is still 3e-7 of
//! the smallest nonzero force W/3.

use crate::common;
use common::*;
use pbdda::world::World;

#[test]
fn staircase_interface_forces_match_statics() {
    let w = 2000.0 * 200.0 * 10.0;
    let mut world = World::new(example("7_2_block_staircase.toml"));
    let mut last = None;
    run(&mut world, 100, |_, rec| last = Some(rec.clone()));
    let rec = last.expect("ran");
    let expected = [
        ("floor", "B4", 0.0, w / 2.0),
        ("floor", "B4", 20.0, 3.5 * w),
        ("B4", "B3", 5.0, 0.0),
        ("B4", "B3", 20.0, 3.0 * w),
        ("B3", "B2", 10.0, w / 3.0),
        ("B3", "B2", 25.0, 5.0 * w / 3.0),
        ("B2", "B1", 15.0, w / 3.0),
        ("B2", "B1", 30.0, 2.0 * w / 3.0),
    ];
    for (a, b, x, f) in expected {
        let cs = between(&world, &rec, a, b);
        assert_eq!(cs.len(), 2, "{a}/{b}: an edge-edge joint gives two contacts");
        let c = cs
            .iter()
            .find(|c| (c.point.x - x).abs() < 1e-6)
            .unwrap_or_else(|| panic!("{a}/{b}: no contact at x = {x}"));
        assert!(
            (c.normal_force - f).abs() <= 1e-7 * w,
            "{a}/{b} at x = {x}: {} N, expected {f} N",
            c.normal_force
        );
        assert!(c.shear_force.abs() <= 1e-7 * w, "{a}/{b} at x = {x}: shear {} N", c.shear_force);
    }
}
