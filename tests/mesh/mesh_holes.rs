//! Contacts on the holes of a mesh (issue 8 scope 3, math note §9.2): a hole's boundary is a
//! clockwise loop, and bodies inside it meet its edges and nodes as they meet the outer loop.
//!
//! `meshes/hole.msh` is a 2 m × 2 m block with a circular hole of radius 0.4 m at its centre
//! (17 boundary edges of about 0.15 m around the hole), clamped on its base. A body dropped
//! into the hole under gravity (g = 10 m/s²) settles on the hole's lower edges: a disk (PL
//! contacts), a rigid square (BL) and a small meshed square (LL). Static relaxation, so the
//! reference is statics: the contact forces on the body, every one of them on the hole's loop
//! (features numbered after the outer loop's), add up to its weight, and their horizontal parts
//! cancel. Tolerance 1e-9 of the weight: the solver's is 1e-12, and after 30 relaxation steps
//! the remaining out-of-balance, the mass term times the last step's motion, is below it
//! (measured: 1e-12 of the weight or less in all three cases).

use pbdda::contact::Feature;
use pbdda::world::World;
use std::path::Path;

const BLOCK: &str = r#"
[scene]
name = "hole"
[time]
step = 0.01
steps = 30
[physics]
gravity = [0.0, -10.0]
velocity_carry = 0.0
[solver]
tolerance = 1e-12
[[material]]
name = "rock"
density = 2500.0
young = 1.0e9
poisson = 0.25
[[interface]]
friction = 0.5
[[body]]
name = "block"
shape = "mesh"
file = "../meshes/hole.msh"
physical = "block"
fixed_nodes = ["base"]
material = "rock"
"#;

/// Runs the block with `inner` (one `[[body]]`) inside its hole for 30 steps; every loaded
/// contact is of `kind` and on the hole's loop, and their resultant on the inner body is
/// `weight` upwards.
fn settle(inner: &str, kind: &str, weight: f64) {
    let text = format!("{BLOCK}{inner}");
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests").join("scene.toml");
    let model = pbdda::scene::parse(&text, &file.display().to_string()).unwrap_or_else(|e| panic!("{e}"));
    let mut world = World::new(model);
    let n_outer = world.bodies[0].mesh.as_deref().expect("a mesh").outer.len() as u32;
    let mut last = None;
    for _ in 0..30 {
        let rec = world.step().unwrap_or_else(|e| panic!("{e}"));
        assert!(rec.converged, "{rec:?}");
        last = Some(rec);
    }
    let rec = last.expect("steps");
    let mut force = pbdda::geometry::Vec2::zeros();
    for c in rec.contacts.iter().filter(|c| c.normal_force != 0.0 || c.shear_force != 0.0) {
        assert_eq!(c.kind.as_str(), kind, "{c:?}");
        let block_feature = if c.key.a == 0 { c.key.fa } else { c.key.fb };
        // the hole's vertices and edges are numbered after the outer loop's
        let id = match block_feature {
            Feature::Vertex(k) | Feature::Edge(k) => k,
            other => panic!("block feature {other:?}"),
        };
        assert!(id >= n_outer, "contact on the outer loop: {c:?}");
        // on body A (the one n points into): p_n n + p_t τ with τ = cw(n)
        let on_a = c.normal * c.normal_force + pbdda::geometry::cw(c.normal) * c.shear_force;
        force += if c.body_a == 1 { on_a } else { -on_a };
    }
    assert!((force.y - weight).abs() <= 1e-9 * weight, "contacts carry {force:?}, weight {weight}");
    assert!(force.x.abs() <= 1e-9 * weight, "horizontal resultant {}", force.x);
}

/// A disk of radius 0.1 m (m = 2500 π 0.01 kg) released 1.7 mm above the hole's two lowest
/// edges (from (0, -0.4) to (±0.1236, -0.3804), 9.0° from level), on which it settles.
#[test]
fn disk_rests_in_the_hole() {
    let disk = r#"
[[body]]
name = "inner"
shape = "disk"
center = [0.0, -0.297]
radius = 0.1
material = "rock"
"#;
    settle(disk, "PL", 2500.0 * std::f64::consts::PI * 0.01 * 10.0);
}

/// A rigid 0.2 m square whose base corners (x = ±0.1 m) are released 1.1 mm above the hole's two
/// lowest edges (y = -0.38414 there), on which it settles.
#[test]
fn block_rests_in_the_hole() {
    let square = r#"
[[body]]
name = "inner"
shape = "polygon"
vertices = [[-0.1, -0.383], [0.1, -0.383], [0.1, -0.183], [-0.1, -0.183]]
material = "rock"
"#;
    settle(square, "BL", 2500.0 * 0.04 * 10.0);
}

/// `square.msh` (1.0 m × 0.8 m) scaled by 0.2 to 0.2 m × 0.16 m, free, placed as the square.
#[test]
fn meshed_block_rests_in_the_hole() {
    let mesh = r#"
[[body]]
name = "inner"
shape = "mesh"
file = "../meshes/square.msh"
physical = "block"
scale = 0.2
offset = [-0.1, -0.383]
material = "rock"
"#;
    settle(mesh, "LL", 2500.0 * 0.2 * 0.16 * 10.0);
}
