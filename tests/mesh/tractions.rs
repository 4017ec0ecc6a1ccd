//! `[[traction]]` and mesh rollers (math note §2.5), each against a closed form:
//! - patch test: a uniform pressure p on a meshed block's top, its base on rollers
//!   (`fixed_y_nodes`) and its left side on rollers (`fixed_x_nodes`), static: the exact solution
//!   is the uniform stress σ_y = −p, σ_x = τ_xy = 0 (a linear displacement, u_y = ε_y y,
//!   u_x = ε_x x, which every Tri3 mesh represents exactly and which meets both rollers), so
//!   every element's stress equals it to round-off, on the gmsh square (`meshes/square.msh`) and
//!   the irregular column (`meshes/column_1.msh`, 246 triangles). Tolerance 1e-9 of p: static
//!   relaxation shrinks the out-of-balance by (2m/dt²)/(K + 2m/dt²) ≈ 1e-7 per step (density 1,
//!   dt = 1 s, E = 1e7 Pa), so after 4 steps only round-off is left;
//! - rollers on both sides too (plane strain, ε_x = 0): σ_x = ν/(1 − ν) σ_y (Hooke's law with
//!   ε_x = ε_z = 0), to 1e-9 of p;
//! - both of the above on a cut-and-meshed block: the left block of a 4 m x 1 m domain cut by a
//!   vertical set at 2 m, meshed by the cutter's own triangulation (`rockmass::mesh_block`,
//!   mesh_size 0.3), its sides grouped by their coordinates; same closed forms, same tolerance;
//! - a rigid block under a pressure p and a shear s on part of its top edge, x in [x1, x2], free
//!   flight from rest for one step: the scheme is exact for a constant force (math note §1.1), so
//!   the centroid moves F dt²/(2m) with F = (−s ℓ, −p ℓ), ℓ = x2 − x1, and the block turns by
//!   M dt²/(2 I) with M = −(x_m − a/2) p ℓ + (h/2) s ℓ about the centroid (x_m the loaded
//!   piece's midpoint) and I = m (a² + h²)/12: each to 1e-9 relative (round-off of a handful of
//!   operations);
//! - a deformable (6-DOF) block under a uniform pressure on its whole boundary (two tractions),
//!   static: its constant stress equals −p I to 1e-9 of p.

use pbdda::scene::parse;
use pbdda::world::World;
use std::path::Path;

const P: f64 = 1.0e5;

fn scene_path() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests").join("scene.toml").display().to_string()
}

fn world(text: &str) -> World {
    World::new(parse(text, &scene_path()).unwrap_or_else(|e| panic!("{e}")))
}

fn run(w: &mut World, steps: usize) {
    for _ in 0..steps {
        let rec = w.step().expect("step");
        assert!(rec.converged);
    }
}

/// A static scene of one mesh body with the `extra` keys and one traction on its `top` group.
fn patch(file: &str, plane: &str, extra: &str) -> String {
    format!(
        r#"[scene]
name = "patch"
[time]
step = 1.0
steps = 4
[physics]
gravity = [0.0, 0.0]
velocity_carry = 0.0
plane = "{plane}"
[[material]]
name = "rock"
density = 1.0
young = 1.0e7
poisson = 0.25
[[body]]
name = "m"
shape = "mesh"
material = "rock"
file = "../meshes/{file}"
{extra}
[[traction]]
body = "m"
group = "top"
pressure = {P}
"#
    )
}

/// The left block of a 4 m x 1 m domain cut by a vertical set at 2 m, meshed by the cutter
/// (`mesh_block`), as a gmsh MSH 2.2 file in the temporary directory: physical curves "bottom",
/// "left", "right", "top" by the boundary edges' coordinates, surface "block". Returns its path.
fn cut_and_meshed_block() -> String {
    use pbdda::rockmass::{CutSpec, JointSet, cut, mesh_block};
    use std::fmt::Write;
    let spec = CutSpec {
        domain: vec![[0.0, 0.0], [4.0, 0.0], [4.0, 1.0], [0.0, 1.0]],
        joint_sets: vec![JointSet { angle: 90.0, spacing: 2.0, ..JointSet::default() }],
        ..CutSpec::default()
    };
    let blocks = cut(&spec).expect("cut").blocks;
    assert_eq!(blocks.len(), 2, "a set at 2 m across 4 m makes two blocks");
    let left = blocks.iter().find(|b| b.centroid[0] < 2.0).expect("the left block");
    let mesh = mesh_block(left, 0.3).expect("mesh");
    let side = |[a, b]: [usize; 2]| {
        let (p, q) = (mesh.nodes[a], mesh.nodes[b]);
        let on = |c: usize, v: f64| (p[c] - v).abs() < 1e-12 && (q[c] - v).abs() < 1e-12;
        [(1, 0.0, 1), (0, 0.0, 2), (0, 2.0, 3), (1, 1.0, 4)]
            .iter()
            .find(|&&(c, v, _)| on(c, v))
            .map(|&(_, _, tag)| tag)
            .expect("every boundary edge on a side of the 2 m x 1 m block")
    };
    let mut msh = String::from("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n5\n");
    msh += "1 1 \"bottom\"\n1 2 \"left\"\n1 3 \"right\"\n1 4 \"top\"\n2 5 \"block\"\n$EndPhysicalNames\n";
    let _ = writeln!(msh, "$Nodes\n{}", mesh.nodes.len());
    for (i, p) in mesh.nodes.iter().enumerate() {
        let _ = writeln!(msh, "{} {:?} {:?} 0", i + 1, p[0], p[1]);
    }
    let _ = writeln!(msh, "$EndNodes\n$Elements\n{}", mesh.boundary.len() + mesh.triangles.len());
    let mut id = 0;
    for (e, _) in &mesh.boundary {
        id += 1;
        let tag = side(*e);
        let _ = writeln!(msh, "{id} 1 2 {tag} {tag} {} {}", e[0] + 1, e[1] + 1);
    }
    for t in &mesh.triangles {
        id += 1;
        let _ = writeln!(msh, "{id} 2 2 5 5 {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    msh += "$EndElements\n";
    let path = std::env::temp_dir().join(format!("pbdda-cut-patch-{}.msh", std::process::id()));
    std::fs::write(&path, msh).expect("write the mesh");
    path.display().to_string()
}

#[test]
fn a_cut_and_meshed_block_passes_the_patch_and_plane_strain_tests() {
    let file = cut_and_meshed_block();
    let nu: f64 = 0.25;
    for (plane, sides, sx) in
        [("stress", "\"left\"", 0.0), ("strain", "\"left\", \"right\"", -nu / (1.0 - nu) * P)]
    {
        let extra = format!("fixed_y_nodes = [\"bottom\"]\nfixed_x_nodes = [{sides}]");
        let mut w = world(&patch("", plane, &extra).replace("../meshes/", &file));
        run(&mut w, 4);
        assert!(element_stresses(&w).len() > 20, "the cutter's mesh of a 2 m x 1 m block at 0.3 m");
        assert_uniform(&w, [sx, -P, 0.0], plane);
    }
    let _ = std::fs::remove_file(&file);
}

fn element_stresses(w: &World) -> Vec<[f64; 3]> {
    let fe = w.bodies[0].mesh.as_ref().expect("a mesh body");
    fe.stress.iter().map(|s| [s[0], s[1], s[2]]).collect()
}

fn assert_uniform(w: &World, expect: [f64; 3], what: &str) {
    for (e, s) in element_stresses(w).iter().enumerate() {
        for c in 0..3 {
            assert!(
                (s[c] - expect[c]).abs() <= 1e-9 * P,
                "{what}: element {e} stress[{c}] = {}, expected {} (diff {:e})",
                s[c],
                expect[c],
                s[c] - expect[c]
            );
        }
    }
}

#[test]
fn a_pressure_on_a_rollered_meshed_block_gives_a_uniform_stress() {
    for (file, base) in [("square.msh", "bottom"), ("column_1.msh", "base")] {
        let extra = format!("fixed_y_nodes = [\"{base}\"]\nfixed_x_nodes = [\"left\"]");
        let mut w = world(&patch(file, "stress", &extra));
        run(&mut w, 4);
        assert_uniform(&w, [0.0, -P, 0.0], file);
    }
}

#[test]
fn rollers_on_both_sides_give_the_plane_strain_lateral_stress() {
    let nu: f64 = 0.25;
    for (file, base) in [("square.msh", "bottom"), ("column_1.msh", "base")] {
        let extra = format!("fixed_y_nodes = [\"{base}\"]\nfixed_x_nodes = [\"left\", \"right\"]");
        let mut w = world(&patch(file, "strain", &extra));
        run(&mut w, 4);
        assert_uniform(&w, [-nu / (1.0 - nu) * P, -P, 0.0], file);
    }
}

/// A 2 × 1 block (a = 2, h = 1), density ρ, the `model` given, with the traction keys `tractions`.
fn block(model: &str, carry: f64, steps: usize, dt: f64, tractions: &str) -> String {
    format!(
        r#"[scene]
name = "block"
[time]
step = {dt}
steps = {steps}
[physics]
gravity = [0.0, 0.0]
velocity_carry = {carry}
[[material]]
name = "rock"
density = 3.0
young = 1.0e7
poisson = 0.25
[[body]]
name = "b"
shape = "polygon"
model = "{model}"
material = "rock"
vertices = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]]
{tractions}
"#
    )
}

#[test]
fn a_rigid_block_moves_under_the_resultant_and_moment_of_its_traction() {
    let (p, s, x1, x2) = (1.0e3, 400.0, 0.25, 1.5);
    let (a, h, rho, dt) = (2.0, 1.0, 3.0, 1.0e-3);
    let text = block(
        "rigid",
        1.0,
        1,
        dt,
        &format!(
            "[[traction]]\nbody = \"b\"\nfrom = [{x2}, 1.2]\nto = [{x1}, 1.2]\npressure = {p}\nshear = {s}"
        ),
    );
    let mut w = world(&text);
    let c0 = w.bodies[0].centroid;
    run(&mut w, 1);
    let m = rho * a * h;
    let l = x2 - x1;
    let xm = 0.5 * (x1 + x2);
    let (fx, fy) = (-s * l, -p * l);
    let moment = -(xm - a / 2.0) * p * l + (h / 2.0) * s * l;
    let inertia = m * (a * a + h * h) / 12.0;
    let du = w.bodies[0].centroid - c0;
    let close = |got: f64, want: f64, what: &str| {
        assert!((got - want).abs() <= 1e-9 * want.abs(), "{what}: {got}, expected {want}");
    };
    close(du.x, fx * dt * dt / (2.0 * m), "x displacement");
    close(du.y, fy * dt * dt / (2.0 * m), "y displacement");
    close(w.bodies[0].rotation, moment * dt * dt / (2.0 * inertia), "rotation");
}

#[test]
fn a_deformable_block_under_uniform_pressure_has_the_stress_minus_p() {
    let half = |from: &str, to: &str| {
        format!("[[traction]]\nbody = \"b\"\nfrom = {from}\nto = {to}\npressure = {P}\n")
    };
    let tractions = half("[0.0, 0.0]", "[2.0, 1.0]") + &half("[2.0, 1.0]", "[0.0, 0.0]");
    let mut w = world(&block("deformable", 0.0, 4, 1.0, &tractions));
    run(&mut w, 4);
    let s = w.bodies[0].stress;
    for (c, want) in [(0, -P), (1, -P), (2, 0.0)] {
        assert!((s[c] - want).abs() <= 1e-9 * P, "stress[{c}] = {}, expected {want}", s[c]);
    }
}
