//! Connectors anchored on meshed bodies (issue 8, math note §6 and §9.2): a bolt's end on a mesh
//! moves with the three nodes of the triangle that holds it, weighted by its area coordinates, and
//! the bolt's stiffness joins the mesh's sparse K̃ (a mesh bolted to a block is one cluster).
//! Static relaxation, so the references are statics:
//!
//! * `examples/mesh_bolted_slab.toml`: the 2 m × 0.3 m slab (ρ = 2500, g = 10: W = 15 000 N per
//!   metre) hangs from two bolts at x = 0.25 and 1.75 m. The bolt forces must add up to W
//!   (vertical equilibrium of the slab; the bolts stay vertical to within their anchors' lateral
//!   motion, ~1e-8 m over 0.8 m), checked to 1e-9 relative, and each carry W/2 (moment balance
//!   about the slab's centroid, x = 1 m, exact for the mesh's area integration), checked to 1e-6:
//!   the anchors move sideways by about 1e-8 m (the mesh is unstructured, so slightly
//!   unsymmetric), which changes the 0.75 m moment arms by that much.
//! * The same slab carrying a rigid 0.4 m × 0.4 m block (1 m below it, on a third bolt at
//!   x = 1 m): the slab and block form one sparse cluster; the lower bolt carries the block's
//!   weight, 4 000 N, and the upper ones the total, 19 000 N (1e-9 relative, as above).

use crate::common;

use pbdda::world::World;

fn settle(world: &mut World, steps: usize) {
    for _ in 0..steps {
        let rec = world.step().unwrap_or_else(|e| panic!("{e}"));
        assert!(rec.converged, "{rec:?}");
    }
}

fn bolt_force(world: &World, name: &str) -> f64 {
    world.connectors.iter().find(|c| c.name == name).unwrap_or_else(|| panic!("no {name}")).axial_force()
}

#[test]
fn bolted_slab_hangs_at_its_statics() {
    let mut world = World::new(common::example("mesh_bolted_slab.toml"));
    settle(&mut world, 10);
    let (l, r) = (bolt_force(&world, "left"), bolt_force(&world, "right"));
    let w = 2500.0 * 10.0 * 2.0 * 0.3;
    assert!(((l + r) - w).abs() <= 1e-9 * w, "bolts {l} + {r} against the weight {w}");
    for f in [l, r] {
        assert!((f - w / 2.0).abs() <= 1e-6 * w, "bolt {f} against half the weight {}", w / 2.0);
    }
}

#[test]
fn slab_and_a_block_bolted_to_it_form_one_cluster() {
    let mut model = common::example("mesh_bolted_slab.toml");
    let extra = "[[body]]\nname = \"block\"\nshape = \"polygon\"\n\
        vertices = [[0.8, -1.2], [1.2, -1.2], [1.2, -0.8], [0.8, -0.8]]\nmaterial = \"rock\"\n\
        [[connector]]\nname = \"hanger\"\nkind = \"bolt\"\npoints = [[1.0, 0.1], [1.0, -0.9]]\n\
        young = 2.0e11\narea = 5.0e-4\n";
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/mesh_bolted_slab.toml");
    let text = std::fs::read_to_string(&path).expect("example") + extra;
    model = pbdda::scene::parse(&text, path.to_str().expect("utf-8 path"))
        .unwrap_or_else(|e| panic!("{e}\n{model:?}"));
    let mut world = World::new(model);
    let (slab, block) = (common::body(&world, "slab"), common::body(&world, "block"));
    assert_eq!(world.dofs.cluster_of(slab), world.dofs.cluster_of(block));
    settle(&mut world, 10);
    let (wb, ws) = (2500.0 * 10.0 * 0.16, 2500.0 * 10.0 * 0.6);
    let hanger = bolt_force(&world, "hanger");
    assert!((hanger - wb).abs() <= 1e-9 * wb, "hanger {hanger} against the block's weight {wb}");
    let up = bolt_force(&world, "left") + bolt_force(&world, "right");
    assert!((up - (wb + ws)).abs() <= 1e-9 * (wb + ws), "bolts {up} against the total weight {}", wb + ws);
}

/// A beam anchored in a mesh (math note §9.2): its end turns with the triangle holding it. A
/// 1 m steel beam (E = 2e11 Pa, A = 1e-2 m², I = 1e-5 m⁴, shear factor 1.2, G = E/2.6) is
/// clamped in a fixed block at (0, 0.4) and carries at its other end, (1, 0.4), a free meshed
/// block (`square.msh` moved to x in [0.9, 1.9], E = 1e15 Pa, no gravity), loaded by P = 1 N
/// downwards at the anchor. Closed form (Timoshenko cantilever, as in
/// `tests/rock/connectors_world.rs`): the anchor sinks by PL³/(3EI) + 1.2 PL/(GA) and the block turns
/// by PL²/(2EI) clockwise; the root moment is PL. Without the rotation coupling the beam's end
/// would be held at zero rotation (a guided end): a quarter of the bending deflection and no
/// turn. The block is 5e3 times stiffer than the beam's section, so its own strain moves the
/// anchor by under 1e-6 relative: tolerance 1e-5, as for the block and disk cantilevers.
#[test]
fn beam_carries_a_meshed_block() {
    let text = r#"
[scene]
name = "beam into a mesh"
[time]
step = 0.01
steps = 200
[physics]
gravity = [0.0, 0.0]
velocity_carry = 0.0
plane = "stress"
[solver]
tolerance = 1e-12
[[material]]
name = "steel"
density = 1.0
young = 1e15
poisson = 0.25
[[body]]
name = "wall"
shape = "polygon"
vertices = [[-1.0, -1.0], [0.0, -1.0], [0.0, 1.0], [-1.0, 1.0]]
material = "steel"
fixed = true
[[body]]
name = "block"
shape = "mesh"
file = "../meshes/square.msh"
physical = "block"
offset = [0.9, 0.0]
material = "steel"
[[load]]
body = "block"
point = [1.0, 0.4]
force = [0.0, -1.0]
[[connector]]
kind = "beam"
points = [[0.0, 0.4], [1.0, 0.4]]
young = 2e11
area = 1e-2
inertia = 1e-5
"#;
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests").join("scene.toml");
    let model = pbdda::scene::parse(text, &file.display().to_string()).unwrap_or_else(|e| panic!("{e}"));
    let mut world = World::new(model);
    settle(&mut world, 200);
    let (e, area, inertia, p, l): (f64, f64, f64, f64, f64) = (2e11, 1e-2, 1e-5, 1.0, 1.0);
    let (deflection, rotation) = common::timoshenko_tip(e, area, inertia, p, l);
    let dy = 0.4 - world.connectors[0].anchors[1].y;
    assert!((dy - deflection).abs() <= 1e-5 * deflection, "anchor sinks {dy}, exact {deflection}");
    let turn = -world.bodies[1].rotation;
    assert!((turn - rotation).abs() <= 1e-5 * rotation, "block turns {turn}, exact {rotation}");
    let root = world.connectors[0].end_moments().expect("a beam")[0];
    assert!((root.abs() - p * l).abs() <= 1e-5 * p * l, "root moment {root}, exact P L = {}", p * l);
}

/// Peer code on the same discretization: scikit-fem (meshes/reference.py, P1 on slab.msh) solves
/// the bolted slab linearly, each bolt a spring EA/l on the three nodes of its anchor's triangle
/// weighted by the area coordinates, plus its tension's geometric stiffness N/l across it (what
/// pbdda assembles, math note §6, §9.2, §10.7). The monitor's u_y after the example's 10 static
/// relaxation steps agrees within 1e-4 (measured 5.8e-5). The difference is pbdda's geometric
/// nonlinearity (it updates the geometry and takes the bolt force from the true length): it is
/// proportional to the load — 5.8e-7 at g = 0.1 m/s² against the reference computed at that g —
/// so there the tolerance is 5e-6; a mismatch of the discretization (a weight, the body force, the
/// bolt stiffness) would show at 1e-2 or more, whatever the load.
#[test]
fn bolted_slab_matches_scikit_fem() {
    for (g, key, tolerance) in [(10.0, "uy_g10", 1e-4), (0.1, "uy_g0.1", 5e-6)] {
        let mut model = common::example("mesh_bolted_slab.toml");
        model.physics.gravity.y = -g;
        let mut world = World::new(model);
        settle(&mut world, 10);
        let uy = world.monitors[0].current.y - world.monitors[0].initial.y;
        let expected = common::reference(&[key]);
        assert!(
            (uy - expected).abs() <= tolerance * expected.abs(),
            "g = {g}: u_y {uy}, scikit-fem {expected}"
        );
    }
}

/// `examples/mesh_bolt_across_joint.toml`: a meshed block on a frictionless 30° joint (gravity
/// tilted), held by a bolt anchored in it and in the clamped meshed base below (one sparse
/// cluster of two meshes and a bolt). Statics of the block, W = 20 000 N: the bolt's force N l
/// (l its current unit direction, from the block's anchor to the base's), the joint's contact
/// forces and the weight balance in x and y, to 1e-6 of W (the relaxation's out-of-balance after
/// 20 steps is the mass term, 3e-3 of the bolt's stiffness, to the 20th power; the solver's
/// tolerance is 1e-10). With the joint taken as flat (it tilts by 1e-5 rad as the base bends):
/// N |l_x| = W sin 30° to 1e-4. Every step converges at the full dt.
#[test]
fn bolt_holds_a_meshed_block_on_a_frictionless_joint() {
    let mut world = World::new(common::example("mesh_bolt_across_joint.toml"));
    let (base, block) = (common::body(&world, "base"), common::body(&world, "block"));
    assert_eq!(world.dofs.cluster_of(base), world.dofs.cluster_of(block));
    let mut last = None;
    for _ in 0..20 {
        let rec = world.step().unwrap_or_else(|e| panic!("{e}"));
        assert!(rec.converged && rec.dt == 0.1, "{rec:?}");
        last = Some(rec);
    }
    let rec = last.expect("steps");
    let w = 2500.0 * 0.8 * 10.0;
    let weight = pbdda::geometry::Vec2::new(0.5, -(3f64.sqrt()) / 2.0) * w;
    let bolt = &world.connectors[0];
    let l = (bolt.anchors[1] - bolt.anchors[0]).normalize();
    let n = bolt.axial_force();
    let mut total = weight + l * n;
    for c in common::between(&world, &rec, "base", "block") {
        // on body A (the one n points into): p_n n + p_t τ, τ = cw(n)
        let on_a = c.normal * c.normal_force + pbdda::geometry::cw(c.normal) * c.shear_force;
        total += if c.body_a == block { on_a } else { -on_a };
    }
    assert!(total.norm() <= 1e-6 * w, "out of balance {total:?} (bolt {n} N)");
    assert!(
        (n * l.x.abs() - 0.5 * w).abs() <= 1e-4 * w,
        "bolt along the joint {} vs {}",
        n * l.x.abs(),
        0.5 * w
    );
}
