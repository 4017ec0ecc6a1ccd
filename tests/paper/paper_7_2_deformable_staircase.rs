//! Paper §7.2, Table 2, with deformable blocks (the paper's E = 0.10e15 Pa, nu = 0.45): four
//! 20 x 10 blocks in a staircase with 5 m offsets on a fixed floor, 6-DOF constant-strain DDA
//! blocks. The normal forces of the stack are statically determinate whatever the stiffness
//! (math note §7.2): each interface's shear pair is self-equilibrated (top-down horizontal
//! balance) and collinear, so it adds no moment. With W = 2000 * 200 * 10 = 4e6 N the floor
//! reactions are F1 = W/2 at x = 0 and F2 = 7W/2 at x = 20. Tolerance 1e-6 relative at step 100,
//! above the effect of the deformation on the statics: the strains are ~ 7W/(20 m E) ~ 7e-9, so the statics of the deformed
//! configuration differ from those of the initial one by far less; the solver tolerance of the
//! example is 1e-12. The example runs as DDA's static analysis (velocity_carry = 0), whose
//! fixed point is these statics. The dynamic run (velocity_carry = 1) reaches them too: the
//! strain DOFs' numerical damping (math note §10.9) takes out the stiff strain modes that the
//! γ = 1 scheme alone flipped every step forever (F1 was off by 1.4e-3 at step 100 without
//! it; with it, 4e-8).

use crate::common;
use common::*;
use pbdda::world::World;

fn floor_reactions_at_step_100(velocity_carry: f64) {
    let w = 2000.0 * 200.0 * 10.0;
    let mut model = example("7_2_block_staircase_deformable.toml");
    model.physics.velocity_carry = velocity_carry;
    let mut world = World::new(model);
    assert!(world.bodies.iter().filter(|b| !b.fixed).all(|b| b.deformable), "the blocks must be deformable");
    let mut last = None;
    run(&mut world, 100, |_, rec| last = Some(rec.clone()));
    let rec = last.expect("ran");
    assert_eq!(rec.step, 100);
    let cs = between(&world, &rec, "floor", "B4");
    assert_eq!(cs.len(), 2, "the floor joint gives two contacts");
    let mut errors = Vec::new();
    for (x, f) in [(0.0, w / 2.0), (20.0, 3.5 * w)] {
        let c = cs
            .iter()
            .find(|c| (c.point.x - x).abs() < 1e-3)
            .unwrap_or_else(|| panic!("no floor contact at x = {x}"));
        let err = (c.normal_force - f).abs() / f;
        eprintln!(
            "7.2 deformable (velocity_carry = {velocity_carry}): F at x = {x}: {} N, expected {f} N, relative error {err:e}",
            c.normal_force
        );
        errors.push((x, c.normal_force, f, err));
    }
    for (x, got, f, err) in errors {
        assert!(err <= 1e-6, "floor contact at x = {x}: {got} N, expected {f} N (relative error {err:e})");
    }
}

#[test]
fn deformable_staircase_floor_reactions_at_step_100() {
    floor_reactions_at_step_100(1.0);
}

#[test]
fn deformable_staircase_floor_reactions_static_relaxation() {
    floor_reactions_at_step_100(0.0);
}
