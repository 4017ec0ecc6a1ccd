//! The penetration allowance of math note §10.2: a new contact's penetration is removed whole;
//! a contact the last step had that penetrates deeper than the allowance is corrected by the
//! excess only, so it ends the step penetrating by the allowance; and a contact the last step had
//! whose gap is wider than the allowance closes to the allowance, not to zero.

use pbdda::body::Dofs;
use pbdda::world::World;

/// A disk (r = 0.5 m, ρ = 2500) on a fixed floor, no gravity, static relaxation
/// (`velocity_carry = 0`: no velocity is carried from one step to the next), dt = 0.01 s,
/// started `depth` m into the floor.
fn disk_on_floor(depth: f64) -> World {
    let text = format!(
        "[scene]\nname = \"allowance\"\n[time]\nstep = 0.01\nsteps = 2\n[physics]\ngravity = [0.0, 0.0]\n\
         velocity_carry = 0.0\n[[material]]\nname = \"rock\"\ndensity = 2500.0\n[[interface]]\nfriction = 0.5\n\
         [[body]]\nname = \"floor\"\nshape = \"polygon\"\nvertices = [[-2.0, -1.0], [2.0, -1.0], [2.0, 0.0], [-2.0, 0.0]]\n\
         material = \"rock\"\nfixed = true\n\
         [[body]]\nname = \"disk\"\nshape = \"disk\"\ncenter = [0.0, {}]\nradius = 0.5\nmaterial = \"rock\"\n",
        0.5 - depth
    );
    World::new(pbdda::scene::parse(&text, "allowance.toml").unwrap_or_else(|e| panic!("{e}")))
}

/// Step 1: the disk starts 1e-6 m deep, a contact no step has seen: the solver removes the whole
/// depth, and the disk ends on the floor (centre at r) to the solver's gap accuracy, here
/// tol × |z| × W_jj ≈ 1e-8 × 40 × 2.5e-8 = 1e-14 m (tol the scene's default tolerance 1e-8,
/// docs/scene-format.md; W_jj = dt² / (2m), m = ρπr² = 1963 kg; z ≈
/// depth / W_jj), far inside the 1e-12 m asserted.
///
/// Step 2: the disk, now touching, is moved 1e-6 m into the floor between steps. The contact
/// persists, so only the excess over the allowance is corrected. With no load (z = 0 after step 1)
/// the allowance of (10.2) is its floor 1e-9 d0 = 5e-11 m (d0 = 0.1 r = 0.05 m, the scene's
/// default threshold; the accuracy term 10 tol W_jj = 2.5e-15 m is below it), so the disk ends
/// 5e-11 m deep. Tolerance 1e-12 m: the same accuracy as above, and 50 times smaller than the
/// allowance, so the test tells the two rules apart (the whole-depth rule ends at 0).
#[test]
fn a_new_penetration_is_removed_whole_and_a_persistent_gap_or_penetration_down_to_the_allowance() {
    let (r, depth) = (0.5, 1e-6);
    let mut world = disk_on_floor(depth);
    let rec = world.step().unwrap_or_else(|e| panic!("{e}"));
    assert!(rec.converged, "{rec:?}");
    let y1 = world.bodies[1].centroid.y - r;
    assert!(y1.abs() < 1e-12, "after step 1 the disk's centre is {y1:e} m above r, expected 0");

    let mut down = Dofs::zeros();
    down[1] = -depth;
    world.bodies[1].apply_increment(&down);
    let rec = world.step().unwrap_or_else(|e| panic!("{e}"));
    assert!(rec.converged, "{rec:?}");
    let allowance = 1e-9 * 0.1 * r;
    let y2 = world.bodies[1].centroid.y - r;
    assert!(
        (y2 + allowance).abs() < 1e-12,
        "after step 2 the disk's centre is {y2:e} m above r, expected {:e}",
        -allowance
    );

    // Step 3, the gap side: the disk is lifted to 1e-6 m above the floor and gravity (g = 10) is
    // switched on; it falls g dt²/2 = 5e-4 m in the step, far more than the gap, so it lands. The
    // contact persists, its gap is handed over less the allowance (still the 5e-11 m floor: step
    // 2's force z ≈ 1e-6 / W_jj = 39 keeps 10 tol |z| W_jj at 1e-14 m), and the disk stops
    // 5e-11 m above the floor. The solver's gap accuracy is now tol |z| W_jj = 1e-8 × g dt²/2 =
    // 5e-12 m (z ≈ (g dt²/2) / W_jj), so the tolerance is 1e-11 m, 5 times below the allowance
    // (the whole-gap rule ends at 0).
    let mut up = Dofs::zeros();
    up[1] = y2.abs() + depth;
    world.bodies[1].apply_increment(&up);
    world.model.physics.gravity = pbdda::geometry::Vec2::new(0.0, -10.0);
    let rec = world.step().unwrap_or_else(|e| panic!("{e}"));
    assert!(rec.converged, "{rec:?}");
    let y3 = world.bodies[1].centroid.y - r;
    assert!(
        (y3 - allowance).abs() < 1e-11,
        "after step 3 the disk's centre is {y3:e} m above r, expected {allowance:e}"
    );
}
