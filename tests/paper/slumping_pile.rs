//! A frictional pile that slumps must lose energy: the impact rule of math note §10.12.
//!
//! The bench pile `DiskPile::benchmark(10, 6)` (60 rigid disks, radius 0.5 m, density 1,
//! μ = 0.6, dt = 1/60 s) with its right wall moved 0.05 m outwards: the rows shift into the
//! gap and the disks of the right-hand side strike neighbours that their other contacts hold.
//! Gravity is conservative, Coulomb contacts dissipate, the γ = 1 update conserves energy in
//! free flight and an impact's reversal conserves it (math note §1.1, §1.3), so the total
//! energy (kinetic plus m g y) can never rise above its value at release, E0 = 1,232.02 J.
//! The only other source is the correction of penetrations within the allowance (§10.2,
//! about 1e-9 m here, so below 1e-6 J for the whole pile), hence the bound E <= E0 (1 + 1e-9).
//! Before §10.12 the doubled share of such impacts drove the held disks into their
//! neighbours, and the corrections of those penetrations fed the pile energy: 0.13 J above E0
//! at step 16, 8,080 J by step 30.
//!
//! Every step must also meet the solver's tolerance (1e-6). The iterative methods stop short on
//! 8 of these 40 steps (the first at step 16) (math note §4.8, "Piles that move"): MPRGP's passes and PC
//! do not settle, and NSGS's stall guard gives up on plateaus. Those steps have exact
//! solutions, which Lemke's method, the last resort on problems of this size, finds (§4.12).
//!
//! The same slump of `DiskPile::benchmark(20, 12)` (240 disks, about 700 contacts, 2,756 LCP
//! variables; E0 = 9,732.29 J, so the bound's 1e-9 of it is still above the allowance's
//! corrections) checks NSGS's stall guard (§4.7, §4.8 "Piles that move") and
//! Lemke's sparse basis (§4.12, "A sparse basis"). NSGS's plateaus last up to some 5,000 sweeps
//! before a contact changes state and it converges: with a window of 400 sweeps, 4 of its first
//! 20 steps ended unconverged (the first at step 12); with a twentieth of the budget every one
//! converges. Step 23 is the first that the iterative methods leave unconverged (2.3e-6 after
//! the whole budget) and Lemke solves (3,117 pivots); it was beyond the dense basis's 1,000
//! variables.

use crate::common;

use pbdda::generate::DiskPile;
use pbdda::model::Shape;
use pbdda::world::World;

#[test]
fn slow_a_slumping_pile_converges_and_loses_energy() {
    slump(10, 6, 40);
}

#[test]
fn slow_a_larger_pile_slumps_converged() {
    slump(20, 12, 23);
}

/// The bench pile of `cols` × `rows` disks with its right wall moved 0.05 m out, run for
/// `steps` steps: every step converged, the energy never above its value at release, and the
/// pile moving (largest kinetic energy above 0.1 J; the locked bench piles stay below 1e-6 J, so
/// the bound was tested on moving disks).
fn slump(cols: usize, rows: usize, steps: usize) {
    let mut model = DiskPile::benchmark(cols, rows).model();
    let Shape::Polygon { vertices } = &mut model.bodies[2].shape else { panic!("the right wall") };
    vertices.iter_mut().for_each(|v| v.x += 0.05);
    // the scene format's default budget (the bench pile's 20,000 is for timing runs)
    model.solver.max_iterations = pbdda::model::SolverSettings::default().max_iterations;
    let g = model.physics.gravity.norm();
    let tolerance = model.solver.tolerance;
    let mut world = World::new(model);
    let potential =
        |w: &World| -> f64 { w.bodies.iter().filter(|b| !b.fixed).map(|b| b.mass * g * b.centroid.y).sum() };
    let e0 = potential(&world);
    let mut kinetic_max = 0.0f64;
    common::run(&mut world, steps, |world, r| {
        common::assert_converged(r, tolerance);
        let e = r.kinetic_energy + potential(world);
        kinetic_max = kinetic_max.max(r.kinetic_energy);
        assert!(e <= e0 * (1.0 + 1e-9), "step {}: energy {e} J against {e0} J at release", r.step);
    });
    assert!(kinetic_max > 0.1, "largest kinetic energy {kinetic_max} J");
}
