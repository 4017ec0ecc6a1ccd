//! In-situ stress on a cut rock mass with no opening (rock-mass design, section 4: a `[[traction]]`
//! with `body = "domain"` and `stress = [sx, sy, txy]` loads every cut block edge on the domain's
//! outline with sigma . n; math note §2.5).
//!
//! A 4 m x 2 m domain cut by one vertical joint at x = 2 (a set 4 m apart) into two rigid 2 m x 2 m blocks, no
//! gravity, the whole outline under the uniform stress sx = sy = -p (compression), p = 1 MPa.
//! Where the numbers come from:
//! - two tractions cover the outline (from (0, 0) to (4, 2) counter-clockwise, and back);
//! - each block's outline tractions are sigma . n on every edge of the domain outline it has:
//!   the left block gets p * 2 m pushing it right, the right block p * 2 m pushing it left, and
//!   the top and bottom tractions cancel on each; a uniform stress on a straight edge has no
//!   moment about the edge's midpoint. The joint must carry sigma . n times its tributary
//!   length: a normal force of p * 2 m = 2 MN in total over its contacts, no shear (Cauchy's
//!   relation for the uniform stress field the tractions come from);
//! - the blocks start at rest in contact and the loads balance, so nothing moves: the
//!   displacement is the solver's gap accuracy, tolerance 1e-12 times the forces' scale, far
//!   below the 1e-9 m asserted;
//! - the joint force to 1e-9 relative: the VI's tolerance is 1e-12 (scaled natural residual,
//!   math note §4.3), three orders below.

use pbdda::world::World;

const P: f64 = 1.0e6;

fn scene() -> String {
    format!(
        r#"
[scene]
name = "in-situ stress on a cut rock mass"
[time]
step = 0.01
steps = 5
[solver]
tolerance = 1e-12
[[material]]
name = "rock"
density = 2500.0
[[interface]]
friction_angle = 30.0
[domain]
vertices = [[0.0, 0.0], [4.0, 0.0], [4.0, 2.0], [0.0, 2.0]]
material = "rock"
[[joint_set]]
angle = 90.0
spacing = 4.0
origin = [2.0, 0.0]
[[traction]]
body = "domain"
from = [0.0, 0.0]
to = [4.0, 2.0]
stress = [{s}, {s}, 0.0]
[[traction]]
body = "domain"
from = [4.0, 2.0]
to = [0.0, 0.0]
stress = [{s}, {s}, 0.0]
"#,
        s = -P
    )
}

#[test]
fn in_situ_stress_holds_a_cut_mass_still_and_loads_its_joint_with_sigma_n_l() {
    let model = pbdda::scene::parse(&scene(), "in_situ.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(model.bodies.len(), 2, "one joint cuts the domain in two");
    // the two tractions, each on the outline edges of both blocks: one per block and traction
    assert_eq!(model.tractions.len(), 4);
    let mut world = World::new(model);
    let x0: Vec<_> = world.bodies.iter().map(|b| b.centroid).collect();
    let mut joint = 0.0;
    for _ in 0..5 {
        let rec = world.step().unwrap_or_else(|e| panic!("{e}"));
        assert!(rec.converged);
        joint = rec.contacts.iter().map(|c| c.normal_force).sum::<f64>();
        let shear: f64 = rec.contacts.iter().map(|c| c.shear_force).sum();
        assert!(shear.abs() <= 1e-9 * 2.0 * P, "no shear on the joint: {shear}");
    }
    assert!((joint - 2.0 * P).abs() <= 1e-9 * 2.0 * P, "joint normal force {joint} against {}", 2.0 * P);
    for (b, x) in world.bodies.iter().zip(&x0) {
        let moved = (b.centroid - x).norm();
        assert!(moved <= 1e-9, "{} moved {moved} m", b.name);
        assert!(b.rotation.abs() <= 1e-9, "{} turned {}", b.name, b.rotation);
    }
}

/// A cut-and-meshed rock mass (`[domain] model = "mesh"`: the 4 m x 2 m domain, no joint, meshed
/// by the cutter into Tri3) under the in-situ stress sigma = (sx, sy, txy) = (-1, -2, 0.3) x 1e5 Pa
/// on its whole outline (two "domain" tractions), static, no gravity, no support: the loads are
/// self-equilibrated and the exact solution is the uniform stress sigma (a linear displacement
/// field, which every Tri3 mesh represents: the patch test), whatever the mesh. Tolerance 1e-9 of
/// the largest stress: static relaxation shrinks the out-of-balance by (2m/dt²)/(K + 2m/dt²),
/// about 1e-7 a step (density 1, dt = 1 s, E = 1e7 Pa), so after 6 steps only round-off is left
/// (as tests/mesh/tractions.rs).
#[test]
fn in_situ_stress_on_a_cut_and_meshed_mass_is_uniform_in_every_element() {
    let s = [-1.0e5, -2.0e5, 0.3e5];
    let text = format!(
        r#"
[scene]
name = "in-situ stress on a cut-and-meshed mass"
[time]
step = 1.0
steps = 6
[physics]
gravity = [0.0, 0.0]
velocity_carry = 0.0
[[material]]
name = "rock"
density = 1.0
young = 1.0e7
poisson = 0.25
[domain]
vertices = [[0.0, 0.0], [4.0, 0.0], [4.0, 2.0], [0.0, 2.0]]
material = "rock"
model = "mesh"
mesh_size = 0.5
[[traction]]
body = "domain"
from = [0.0, 0.0]
to = [4.0, 2.0]
stress = [{sx}, {sy}, {txy}]
[[traction]]
body = "domain"
from = [4.0, 2.0]
to = [0.0, 0.0]
stress = [{sx}, {sy}, {txy}]
"#,
        sx = s[0],
        sy = s[1],
        txy = s[2]
    );
    let model = pbdda::scene::parse(&text, "meshed.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(model.bodies.len(), 1, "no joint: one block");
    let mut world = World::new(model);
    for _ in 0..6 {
        assert!(world.step().unwrap_or_else(|e| panic!("{e}")).converged);
    }
    let fe = world.bodies[0].mesh.as_ref().expect("a meshed block");
    assert!(fe.stress.len() > 8, "a mesh of {} triangles", fe.stress.len());
    for (e, stress) in fe.stress.iter().enumerate() {
        for c in 0..3 {
            assert!(
                (stress[c] - s[c]).abs() <= 1e-9 * 2.0e5,
                "element {e}: stress[{c}] = {} against {}",
                stress[c],
                s[c]
            );
        }
    }
}
