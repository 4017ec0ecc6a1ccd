//! A deformable (6-DOF, constant-strain) rectangular block, B = 2 m wide and H = 1 m high,
//! rho = 2500, resting frictionlessly on a fixed base under g = 10, static relaxation
//! (velocity_carry = 0). Closed form of the DDA block (math note §2.3-2.4): at rest the
//! strain rows of K d = f + C p read S sigma = (generalized contact force on the strains); the
//! two corner reactions (sum m g = rho g B H, lever -H/2 in the ey column y - yc of T) give
//! S sigma_y = -m g H/2, i.e. the mean of the exact linear stress profile,
//!     sigma_y = -rho g H/2 = -12 500 Pa,  sigma_x = 0, tau_xy = 0
//! (no shear force: frictionless, so the block is free to expand sideways; the body force
//! has no strain component about the centroid). The strain is D^-1 sigma with sigma_x = 0:
//!   plane stress: ey = sigma_y/E,          ex = -nu sigma_y/E,         gxy = 0;
//!   plane strain: ey = (1-nu²) sigma_y/E,  ex = -nu(1+nu) sigma_y/E,   gxy = 0
//! (from D of math note §2.3: sigma_x = k((1-nu) ex + nu ey) = 0 gives ex = -nu/(1-nu) ey,
//! then sigma_y = k (1-2nu)/(1-nu) ey = E/(1-nu²) ey). Tolerance 1e-6 relative, above the effect of the
//! deformation on the closed form: with E = 1e11 the strains are ~1e-7, so the current geometry (sigma_y = -m g H'/(2 S') =
//! -rho g H/(2(1+ex))) differs from the initial one by ~4e-8 relative; sigma_x and tau_xy are
//! asserted below 1e-6 |sigma_y|. The relaxation contracts the error by a factor of order
//! (2 rho S_yy/dt²)/(S E) ~ 1e-4 per step at dt = 0.01 (measured: 1.7e-4 after step 1, 3e-8
//! after step 2, the fixed point from step 3 on); 10 steps are run.

use pbdda::model::{Model, Plane};
use pbdda::world::World;

const SCENE: &str = r#"
[scene]
name = "deformable block resting on a fixed base"

[time]
step = 0.01
steps = 10

[physics]
gravity = [0.0, -10.0]
velocity_carry = 0.0

[solver]
tolerance = 1e-12

[[material]]
name = "rock"
density = 2500.0
young = 1.0e11
poisson = 0.3

[[interface]]
friction = 0.0

[[body]]
name = "base"
shape = "polygon"
vertices = [[-2.0, -1.0], [2.0, -1.0], [2.0, 0.0], [-2.0, 0.0]]
material = "rock"
fixed = true

[[body]]
name = "block"
shape = "polygon"
vertices = [[-1.0, 0.0], [1.0, 0.0], [1.0, 1.0], [-1.0, 1.0]]
model = "deformable"
material = "rock"
"#;

const E: f64 = 1.0e11;
const NU: f64 = 0.3;
const STEPS: usize = 10;

fn model(plane: Plane) -> Model {
    let mut m = pbdda::scene::parse(SCENE, "deformable_block_statics").unwrap_or_else(|e| panic!("{e}"));
    m.physics.plane = plane;
    m
}

/// Runs the relaxation and returns the block's (strain, stress) after `STEPS` steps.
fn relax(plane: Plane) -> ([f64; 3], [f64; 3]) {
    let mut world = World::new(model(plane));
    let block = world.bodies.iter().position(|b| b.name == "block").expect("block");
    assert!(world.bodies[block].deformable);
    for _ in 0..STEPS {
        let rec = world.step().unwrap_or_else(|e| panic!("{e}"));
        assert!(rec.converged, "step {}: solver did not converge", rec.step);
    }
    let b = &world.bodies[block];
    ([b.strain[0], b.strain[1], b.strain[2]], [b.stress[0], b.stress[1], b.stress[2]])
}

fn rel(got: f64, expected: f64) -> f64 {
    (got - expected).abs() / expected.abs()
}

fn check(plane: Plane, ex_exact: f64, ey_exact: f64) {
    let sy_exact = -2500.0 * 10.0 * 1.0 / 2.0;
    let (strain, stress) = relax(plane);
    let e_sy = rel(stress[1], sy_exact);
    let (e_ex, e_ey) = (rel(strain[0], ex_exact), rel(strain[1], ey_exact));
    eprintln!(
        "{plane:?}: sigma = {stress:?} (sigma_y rel. error {e_sy:e}), strain = {strain:?} (ex {e_ex:e}, ey {e_ey:e})"
    );
    assert!(e_sy <= 1e-6, "{plane:?}: sigma_y = {} Pa, expected {sy_exact} Pa", stress[1]);
    assert!(stress[0].abs() <= 1e-6 * sy_exact.abs(), "{plane:?}: sigma_x = {} Pa, expected 0", stress[0]);
    assert!(stress[2].abs() <= 1e-6 * sy_exact.abs(), "{plane:?}: tau_xy = {} Pa, expected 0", stress[2]);
    assert!(e_ey <= 1e-6, "{plane:?}: ey = {:e}, expected {ey_exact:e}", strain[1]);
    assert!(e_ex <= 1e-6, "{plane:?}: ex = {:e}, expected {ex_exact:e}", strain[0]);
    assert!(strain[2].abs() <= 1e-6 * ey_exact.abs(), "{plane:?}: gxy = {:e}, expected 0", strain[2]);
}

#[test]
fn plane_stress_mean_vertical_stress_and_strain() {
    let sy = -12_500.0;
    check(Plane::Stress, -NU * sy / E, sy / E);
}

#[test]
fn plane_strain_mean_vertical_stress_and_strain() {
    let sy = -12_500.0;
    check(Plane::Strain, -NU * (1.0 + NU) * sy / E, (1.0 - NU * NU) * sy / E);
}
