//! Mesh bodies through the whole engine (scene -> World -> steps), against closed forms and peer
//! code under mesh refinement (math note §9.5).

use crate::common;

use pbdda::mesh::Mesh;
use pbdda::world::World;
use std::path::Path;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Parses a scene whose `file` keys are relative to `tests/` (so `../meshes/...`).
fn scene(text: &str) -> pbdda::model::Model {
    let file = root().join("tests").join("scene.toml");
    pbdda::scene::parse(text, &file.display().to_string()).unwrap_or_else(|e| panic!("{e}"))
}

fn run(text: &str, steps: usize) -> World {
    let mut world = World::new(scene(text));
    for step in 0..steps {
        world.step().unwrap_or_else(|e| panic!("step {step}: {e}"));
    }
    world
}

/// Mean of `u_y` over the mesh nodes whose initial position satisfies `pick`.
fn mean_uy(world: &World, body: usize, pick: impl Fn(f64, f64) -> bool) -> f64 {
    let fe = world.bodies[body].mesh.as_ref().expect("a mesh body");
    let ids: Vec<usize> =
        (0..fe.nodes.len()).filter(|&n| pick(fe.reference[n].x, fe.reference[n].y)).collect();
    ids.iter().map(|&n| fe.displacement[n].y).sum::<f64>() / ids.len() as f64
}

/// Observed order p = log2((e1 - e2)/(e2 - e3)) of three values on meshes refined by 2, and the
/// Richardson extrapolation v3 + (v3 - v2)/(2^p - 1).
fn richardson(v: [f64; 3]) -> (f64, f64) {
    let p = ((v[1] - v[0]) / (v[2] - v[1])).log2();
    (p, v[2] + (v[2] - v[1]) / (2f64.powf(p) - 1.0))
}

/// Cantilever, tip shear P = 1 N (math note §9.5): `cantilever_1/2/3.msh` (L = 10, h = 1), plane
/// stress, E = 1e7, ν = 0.3, clamped by `fixed_nodes = ["clamp"]`, P as a uniform traction on x = L
/// given as [[load]] points at the tip nodes with the consistent shares (half of each tip edge's
/// load to each of its nodes; a load at a node goes to that node alone). Static relaxation
/// (`velocity_carry = 0`, dt = 1 s, ρ = 1: the mass term is 2e-3 of the tip stiffness, so 12
/// steps converge to round-off).
/// - Peer code: scikit-fem (meshes/reference.json, same meshes, P1) gives the mean tip deflection;
///   the engine accumulates its steps on the updated geometry, which differs from the linear
///   solution by the order of the rotations (6e-5) times the small second steps: 1e-6 relative.
/// - Convergence: observed order of the three meshes 2 ± 0.3 (Tri3, O(h²)), and the Richardson
///   extrapolation within 1 % of P L³/(3EI) + P L/(κ G A), κ = 5/6.
#[test]
fn cantilever_clamped_by_fixed_nodes_converges_to_beam_theory() {
    let names = ["cantilever_1.msh", "cantilever_2.msh", "cantilever_3.msh"];
    let mut tips = [0.0; 3];
    for (k, name) in names.iter().enumerate() {
        let mesh = Mesh::read(&root().join("meshes").join(name)).expect("mesh");
        let mut tip: Vec<f64> =
            mesh.nodes.iter().filter(|p| (p.x - 10.0).abs() < 1e-9).map(|p| p.y).collect();
        tip.sort_by(f64::total_cmp);
        let mut loads = String::new();
        for (i, &y) in tip.iter().enumerate() {
            let below = if i > 0 { y - tip[i - 1] } else { 0.0 };
            let above = if i + 1 < tip.len() { tip[i + 1] - y } else { 0.0 };
            let f = -(below + above) / 2.0; // P/h = 1 N/m
            loads += &format!("[[load]]\nbody = \"beam\"\npoint = [10.0, {y:?}]\nforce = [0.0, {f:?}]\n");
        }
        let text = format!(
            r#"
[scene]
name = "cantilever"
[time]
step = 1.0
steps = 12
[physics]
gravity = [0.0, 0.0]
velocity_carry = 0.0
plane = "stress"
[[material]]
name = "steel"
density = 1.0
young = 1.0e7
poisson = 0.3
[[body]]
name = "beam"
shape = "mesh"
file = "../meshes/{name}"
physical = "beam"
fixed_nodes = ["clamp"]
material = "steel"
{loads}"#
        );
        let world = run(&text, 12);
        tips[k] = mean_uy(&world, 0, |x, _| (x - 10.0).abs() < 1e-9);
        let reference = common::reference(&[name, "tip_uy"]);
        let rel = (tips[k] - reference).abs() / reference.abs();
        assert!(rel < 1e-5, "{name}: tip {:e} vs scikit-fem {reference:e} ({rel:e})", tips[k]);
    }
    let (p, extrapolated) = richardson(tips);
    eprintln!("cantilever: tips {tips:?}, order {p}, extrapolated {extrapolated:e}");
    assert!((p - 2.0).abs() < 0.3, "observed order {p}");
    let (e, nu, l, h, load) = (1.0e7f64, 0.3, 10.0f64, 1.0f64, 1.0);
    let (i, g, kappa) = (h.powi(3) / 12.0, e / (2.0 * (1.0 + nu)), 5.0 / 6.0);
    let beam = -(load * l.powi(3) / (3.0 * e * i) + load * l / (kappa * g * h));
    let rel = (extrapolated - beam).abs() / beam.abs();
    assert!(rel < 0.01, "extrapolated {extrapolated:e} vs beam theory {beam:e} ({rel:e})");
}

/// Column under self-weight (math note §9.5): `column_1/2/3.msh` (width 0.25 m, H = 1 m), ν = 0,
/// plane stress, ρ = 2500, g = 10. Top settlement: ρ g H²/(2E). With ν = 0 the exact solution has
/// no horizontal displacement, so a frictionless base and a clamped base (`fixed_nodes = ["base"]`)
/// are the same problem; the clamp is used so that the contact solver's gap accuracy does not
/// cover the discretization error, which is small here (the problem is nearly one-dimensional, and
/// P1 is nodally exact in 1D): the top settlement is within 2e-5 of ρ g H²/(2E) on every mesh
/// (measured 1.0e-5, 1.4e-6, 6.6e-7: too small and of changing sign to show an order). The order
/// is that of the displacement error in L2, ‖u_h − u‖ with u_y = −(ρg/E)(H y − y²/2), u_x = 0,
/// by the edge-midpoint rule (degree 2): Tri3 converges at O(h²), observed order 2 ± 0.3 over the
/// three meshes (lc halved each time). E = 2.5e13 keeps the strain (1e-9), and so the effect of
/// equilibrium on the updated geometry, far below these errors; the nodal displacements are
/// accumulated from the increments (`MeshBody::displacement`), not read from coordinates whose
/// round-off (1e-16 m) would be 2e-7 of the 5e-10 m settlement. Static relaxation contracts by
/// (2ρ/dt²)/(E/H²) ~ 1e-6 per step at dt = 0.01; 8 steps.
#[test]
fn column_under_self_weight_settles_at_second_order() {
    let (rho, g, h, e) = (2500.0, 10.0, 1.0, 2.5e13);
    let exact = rho * g * h * h / (2.0 * e);
    let mut errors = [0.0; 3];
    for (k, errors) in errors.iter_mut().enumerate() {
        let text = format!(
            r#"
[scene]
name = "column"
[time]
step = 0.01
steps = 8
[physics]
gravity = [0.0, -10.0]
velocity_carry = 0.0
plane = "stress"
[[material]]
name = "rock"
density = 2500.0
young = 2.5e13
poisson = 0.0
[[body]]
name = "column"
shape = "mesh"
file = "../meshes/column_{}.msh"
fixed_nodes = ["base"]
material = "rock"
"#,
            k + 1
        );
        let world = run(&text, 8);
        let settlement = -mean_uy(&world, 0, |_, y| (y - 1.0).abs() < 1e-9);
        let rel = (settlement - exact).abs() / exact;
        assert!(rel < 2e-5, "column_{}: settlement {settlement:e} vs {exact:e}", k + 1);
        let fe = world.bodies[0].mesh.as_ref().expect("mesh");
        let uy = |y: f64| -(rho * g / e) * (h * y - y * y / 2.0);
        let mut sum = 0.0;
        for t in &fe.triangles {
            let area = pbdda::mesh::tri3::Tri3::of(&fe.reference, *t).area;
            for (i, j) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                let mid = (fe.reference[i] + fe.reference[j]) / 2.0;
                let u = (fe.displacement[i] + fe.displacement[j]) / 2.0;
                sum += area / 3.0 * (u.x * u.x + (u.y - uy(mid.y)).powi(2));
            }
        }
        *errors = sum.sqrt();
    }
    let orders = [(errors[0] / errors[1]).log2(), (errors[1] / errors[2]).log2()];
    eprintln!("column: L2 displacement errors {errors:?}, observed orders {orders:?}");
    for p in orders {
        assert!((p - 2.0).abs() < 0.3, "observed orders {orders:?} (errors {errors:?})");
    }
}
