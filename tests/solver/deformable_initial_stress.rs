//! `initial_stress` of a deformable body (math note §2.4: the load f_σ = −S Bᵀ σ0, stress
//! accumulated as σ += D Δε). A free body (no gravity, no contact) released with an initial
//! stress relaxes in static mode (velocity_carry = 0) to zero stress, and its accumulated strain
//! to the closed form ε = −D⁻¹ σ0: in plane stress εx = −(σx − ν σy)/E, εy = −(σy − ν σx)/E,
//! γxy = −2(1 + ν) τxy/E; for a disk with isotropic σ0, ε = −(1 − ν) σ0/E. Static relaxation
//! converges geometrically (factor 2M/dt² / (K_e + 2M/dt²) per step); with E = 1e9, rho = 1000,
//! dt = 1 the factor is ~1e-6, so 10 steps reach round-off. Tolerance 1e-9 relative.

use pbdda::scene::parse;
use pbdda::world::World;

const SCENE: &str = r#"
[scene]
name = "free deformable bodies with initial stress"
[time]
step = 1.0
steps = 10
[physics]
velocity_carry = 0.0
[solver]
tolerance = 1e-12
[[material]]
name = "rock"
density = 1000.0
young = 1.0e9
poisson = 0.25
[[body]]
name = "block"
shape = "polygon"
vertices = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]]
model = "deformable"
material = "rock"
initial_stress = [-2.0e6, 1.0e6, 5.0e5]
[[body]]
name = "disk"
shape = "disk"
center = [10.0, 0.0]
radius = 1.0
model = "deformable"
material = "rock"
initial_stress = [-3.0e6, -3.0e6, 0.0]
"#;

#[test]
fn initial_stress_relaxes_to_the_closed_form_strain() {
    let (e, nu) = (1.0e9, 0.25);
    let mut world = World::new(parse(SCENE, "scene.toml").expect("scene"));
    for _ in 0..10 {
        world.step().expect("step");
    }
    let block = &world.bodies[0];
    let (sx, sy, txy) = (-2.0e6, 1.0e6, 5.0e5);
    let expected = [-(sx - nu * sy) / e, -(sy - nu * sx) / e, -2.0 * (1.0 + nu) * txy / e];
    for (i, want) in expected.iter().enumerate() {
        assert!(block.stress[i].abs() < 1e-9 * 2.0e6, "block stress {i}: {}", block.stress[i]);
        assert!(
            (block.strain[i] - want).abs() < 1e-9 * 1e-3,
            "block strain {i}: {} vs {want}",
            block.strain[i]
        );
    }
    let disk = &world.bodies[1];
    let eps = -(1.0 - nu) * -3.0e6 / e;
    assert!(disk.stress[0].abs() < 1e-9 * 3.0e6, "disk stress {}", disk.stress[0]);
    assert!((disk.strain[0] - eps).abs() < 1e-9 * eps.abs(), "disk strain {} vs {eps}", disk.strain[0]);
}
