//! A meshed block's node contacts carry a joint's whole strength, c L and T L (math note §4.15:
//! each node of a face takes the strength of its tributary length), against the closed forms a
//! rigid block meets (§4.6, §7.6, §7.8). The meshes: the gmsh square (`meshes/square.msh`,
//! 1 m × 0.8 m) and slab (`meshes/slab.msh`, 2 m × 0.3 m), and a 1 m × 0.8 m square of seven
//! nodes whose boundary loop starts in the middle of its base (written here: a mesh's loop starts
//! at its lowest-numbered boundary node; on such a face one edge's joint had both ends merged
//! away and its strength went with them). Meshed blocks of a rock mass carry their joints' tags.

use pbdda::scene::parse;
use pbdda::world::{Event, World};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

fn world(text: &str) -> World {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests").join("scene.toml");
    World::new(parse(text, &path.display().to_string()).unwrap_or_else(|e| panic!("{e}")))
}

/// A 1 m × 0.8 m square of five triangles fanned from its top-left corner, base nodes at
/// x = 0, 0.25, 0.5, 0.75, 1; node 1 (the lowest, where the boundary loop starts) at (0.5, 0).
fn mid_start_mesh() -> PathBuf {
    static WRITTEN: OnceLock<PathBuf> = OnceLock::new();
    WRITTEN.get_or_init(write_mid_start_mesh).clone()
}

fn write_mid_start_mesh() -> PathBuf {
    let path = Path::new(env!("CARGO_TARGET_TMPDIR")).join("square_mid_start.msh");
    let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n2 1 \"block\"\n$EndPhysicalNames\n\
                $Nodes\n7\n1 0.5 0 0\n2 1 0 0\n3 1 0.8 0\n4 0 0.8 0\n5 0 0 0\n6 0.25 0 0\n7 0.75 0 0\n$EndNodes\n\
                $Elements\n5\n1 2 2 1 1 5 6 4\n2 2 2 1 1 6 1 4\n3 2 2 1 1 1 7 4\n4 2 2 1 1 7 2 4\n\
                5 2 2 1 1 2 3 4\n$EndElements\n";
    std::fs::write(&path, text).expect("write the mesh");
    path
}

/// The meshed blocks as `[[body]]` scene text (named "block", material "rock", the keys
/// `extra`), each with its base length L on y = 0 from x = 0.
fn blocks(extra: &str) -> Vec<(String, f64)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes");
    let body = |file: &Path| {
        let file = file.display().to_string();
        format!(
            "[[body]]\nname = \"block\"\nshape = \"mesh\"\nfile = {file:?}\nmaterial = \"rock\"\n{extra}\n"
        )
    };
    vec![
        (body(&dir.join("square.msh")), 1.0),
        (body(&dir.join("slab.msh")), 2.0),
        (body(&mid_start_mesh()), 1.0),
    ]
}

/// The meshed block (the last body) on a fixed rigid floor (body 0), gravity g = 10 tilted by
/// α = 30° (the slope's frame), the floor's interface `law`.
/// The scenes' common head: 300 steps of 1 ms under g = 10 m/s² tilted by 30° (the slope
/// along x), tolerance 1e-12, elastic rock of 2,500 kg/m³; `interfaces` follows it.
fn head(name: &str, interfaces: &str) -> String {
    let (s, c) = 30f64.to_radians().sin_cos();
    format!(
        r#"[scene]
name = "{name}"
[time]
step = 0.001
steps = 300
[physics]
gravity = [{:?}, {:?}]
plane = "stress"
[solver]
tolerance = 1e-12
[[material]]
name = "rock"
density = 2500.0
young = 1.0e9
poisson = 0.25
{interfaces}
"#,
        10.0 * s,
        -10.0 * c
    )
}

fn slope(block: &str, law: &str) -> String {
    format!(
        r#"{}[[body]]
name = "floor"
shape = "polygon"
vertices = [[-1.0, -0.5], [8.0, -0.5], [8.0, 0.0], [-1.0, 0.0]]
material = "rock"
fixed = true
{block}"#,
        head("meshed block on a cohesive slope", &format!("[[interface]]\n{law}"))
    )
}

/// Math note §4.15 against the rigid block's closed form: a block sliding down a slope α = 30°
/// on a joint of friction μ = tan φ = 0.3 and cohesion c = 1000 Pa over its base L has
/// a = [W (sin α − cos α tan φ) − c L]/m (m = ρ A, W = m g). Each meshed block slides from
/// rest; a is measured from its mass-weighted mean velocity (the momentum over m, which the
/// contact forces change exactly, math note §1.1) between steps 100 and 300 (t = 0.1 to 0.3 s).
/// Tolerance 1e-6 relative: the elastic block settles under the suddenly applied gravity and
/// its normal vibration, damped by the scheme, changes Σ p_n, hence the friction μ Σ p_n, by the
/// centroid's normal momentum change over the window: about 2e-7 of a here. A lost joint share
/// (one base edge of the seven-node square: a quarter of c L) changes a by 7 %. The gmsh meshes
/// keep every base node closed; a meshed block whose heel lifts (a corner node opening under the
/// sliding moment) carries no cohesion there (§10.4, §4.15), unlike a rigid block.
#[test]
fn a_meshed_block_slides_at_the_rigid_closed_form() {
    let (alpha, mu, c, dt) = (30f64.to_radians(), 0.3, 1000.0, 0.001);
    for (block, l) in blocks("") {
        let mut w = world(&slope(&block, &format!("friction = {mu:?}\ncohesion = {c:?}")));
        let b = w.bodies.len() - 1;
        let m = w.bodies[b].mesh.as_ref().expect("a mesh").mass();
        let a = (m * 10.0 * (alpha.sin() - alpha.cos() * mu) - c * l) / m;
        let mut v = Vec::new();
        for _ in 0..300 {
            w.step().unwrap_or_else(|e| panic!("{e}"));
            v.push(w.bodies[b].mesh.as_ref().expect("a mesh").mean_motion().0.x);
        }
        let measured = (v[299] - v[99]) / (200.0 * dt);
        assert!((measured - a).abs() < 1e-6 * a, "{block}: a = {measured}, closed form {a}");
    }
}

/// A meshed block at rest on a fixed rigid floor, no gravity, dt = 0.01 s, 100 steps, in the
/// uniform stress `stress` (σ_x, σ_y, τ_xy; `initial_stress`) held by the traction σ·n of the
/// same stress on its sides and top (the boundary from (L, 0) to (0, 0) counter-clockwise): in
/// equilibrium from t = 0 when its base nodes hold, each of them carrying σ·n times its
/// tributary length ℓ_i (consistent nodal loads, half of each edge); the floor's interface `law`.
fn loaded(block: &str, l: f64, law: &str) -> String {
    format!(
        r#"[scene]
name = "meshed block under a uniform stress"
[time]
step = 0.01
steps = 100
[physics]
gravity = [0.0, 0.0]
[solver]
tolerance = 1e-12
[[material]]
name = "rock"
density = 2500.0
young = 1.0e9
poisson = 0.25
[[interface]]
{law}
[[body]]
name = "floor"
shape = "polygon"
vertices = [[-1.0, -0.5], [3.0, -0.5], [3.0, 0.0], [-1.0, 0.0]]
material = "rock"
fixed = true
{block}
[[traction]]
body = "block"
from = [{l:?}, 0.0]
to = [0.0, 0.0]
"#
    )
}

/// `[x, y, z]` in TOML.
fn array(v: [f64; 3]) -> String {
    format!("[{:?}, {:?}, {:?}]", v[0], v[1], v[2])
}

/// The meshed blocks in the uniform stress `stress`, in [`loaded`]'s scene with `law`.
fn stressed(stress: [f64; 3], law: &str) -> Vec<(World, String, f64)> {
    let keys = format!("initial_stress = {}", array(stress));
    blocks(&keys)
        .into_iter()
        .map(|(block, l)| {
            let text = format!("{}stress = {}\n", loaded(&block, l, law), array(stress));
            (world(&text), block, l)
        })
        .collect()
}

/// The largest displacement of the meshed block's base nodes (y = 0 at t = 0), and their count.
fn base(w: &World) -> (f64, usize) {
    let fe = w.bodies.last().and_then(|b| b.mesh.as_ref()).expect("a mesh");
    let nodes: Vec<usize> = (0..fe.nodes.len()).filter(|&k| fe.reference[k].y == 0.0).collect();
    (nodes.iter().map(|&k| fe.displacement[k].norm()).fold(0.0, f64::max), nodes.len())
}

/// Math note §4.15 with a stress state the mesh carries exactly: σ = (0, −p, s), a state of
/// constant strain, in equilibrium with the traction on the top and sides when every base node
/// holds, each carrying p ℓ_i and s ℓ_i of its tributary length (a rigid block: p L and s L).
/// The joint holds while s <= c + μ p. With p = 1e5 Pa, μ = 0.5 and s = 7e4 Pa it needs the
/// cohesion c = s − μ p = 2e4 Pa: 1e-6 more and every node holds, so nothing moves (the base
/// nodes by less than 1e-9 m in 100 steps; the solver's 1e-12 of the forces moves them by
/// ~1e-15 m); 1e-6 less (ΔF = 1e-6 × 2e4 Pa × L short of the shear) and the block slides as a
/// whole at a = ΔF/m (m = ρ A, constant forces: exact parabola of the scheme, math note §1.1),
/// x = a t²/2 = 5e-6 m at t = 1 s for the square: the base's motion is that to 1e-4 relative
/// (the elastic shear of the block does not change while its forces do not).
#[test]
fn a_meshed_face_holds_just_above_the_cohesion_it_needs_and_slides_just_below() {
    let (p, s, mu) = (1.0e5, 7.0e4, 0.5);
    for margin in [1e-6, -1e-6] {
        let c = (s - mu * p) * (1.0 + margin);
        let law = format!("friction = {mu:?}\ncohesion = {c:?}");
        for (mut w, block, l) in stressed([0.0, -p, s], &law) {
            for _ in 0..100 {
                assert!(w.step().unwrap_or_else(|e| panic!("{e}")).converged);
            }
            let (motion, _) = base(&w);
            let m = w.bodies[1].mesh.as_ref().expect("a mesh").mass();
            let x = 0.5 * (s - c - mu * p) * l / m * w.time * w.time;
            if margin > 0.0 {
                assert!(motion < 1e-9, "{block}: c {c} holds, yet the base moved {motion} m");
            } else {
                assert!((motion - x).abs() < 1e-4 * x, "{block}: c {c} slides {motion} m, closed form {x}");
            }
        }
    }
}

/// Math note §4.15 and §4.5 on a cemented face: the uniform tension σ = (0, q, 0) pulls each
/// base node by q ℓ_i (a rigid block's joint by q L). With the tensile strength T = 1e5 Pa,
/// q = T (1 − 1e-6) leaves every node bonded (no break in 100 steps, the base nodes move by less
/// than 1e-9 m, as above) and q = T (1 + 1e-6) breaks every one of them in the first step (one
/// `JointBroke` event per base node): the face breaks at T L to 1e-6, as the rigid joint does.
#[test]
fn a_cemented_meshed_face_breaks_at_its_tensile_strength() {
    let t = 1.0e5;
    for margin in [-1e-6, 1e-6] {
        let law = format!("tensile_strength = {t:?}");
        for (mut w, block, _) in stressed([0.0, t * (1.0 + margin), 0.0], &law) {
            let mut broke = Vec::new();
            for _ in 0..100 {
                let rec = w.step().unwrap_or_else(|e| panic!("{e}"));
                let events = rec.events.iter().filter(|e| matches!(e, Event::JointBroke { .. }));
                broke.extend(events.map(|_| rec.step));
            }
            let (motion, nodes) = base(&w);
            if margin < 0.0 {
                assert!(broke.is_empty(), "{block}: {broke:?}");
                assert!(motion < 1e-9, "{block}: bonded, yet the base moved {motion} m");
            } else {
                assert_eq!(broke, vec![1; nodes], "{block}");
            }
        }
    }
}

/// Joint provenance on meshed blocks (math note §4.14): a rock mass [0,2]×[−0.8,0.8] cut by one
/// horizontal joint (a set of spacing 10 through the origin: the trace y = 0) whose interface
/// "bedding" has friction 0.2, the default interface friction 0.7, both blocks meshed
/// (`model = "mesh"`, mesh_size 0.2), the lower one fixed; gravity g = 10 tilted by α = 30°.
/// The upper block's base edges carry the set's tag as the lower block's top edges do, so the
/// meshed-on-meshed (L-L) contacts take the bedding law and the block slides at the set's closed
/// form a = g (sin α − 0.2 cos α) = 3.2679 m/s² (the default's 0.7 > tan α would hold it).
/// Measured from the mean velocity between steps 100 and 300, as above; tolerance 1e-5
/// relative: both blocks are elastic, and the normal vibration of the settling couples through
/// μ Σ p_n as above (the shrinking overlap changes nothing: friction does not depend on it).
#[test]
fn a_meshed_cut_block_slides_on_its_joint_sets_law() {
    let (s, c) = 30f64.to_radians().sin_cos();
    let interfaces = "[[interface]]\nfriction = 0.7\n[[interface]]\nname = \"bedding\"\nfriction = 0.2";
    let text = format!(
        r#"{}[domain]
vertices = [[0.0, -0.8], [2.0, -0.8], [2.0, 0.8], [0.0, 0.8]]
material = "rock"
model = "mesh"
mesh_size = 0.2
fixed_points = [[1.0, -0.4]]
[[joint_set]]
angle = 0.0
spacing = 10.0
origin = [0.0, 0.0]
interface = "bedding"
"#,
        head("meshed cut block on a tagged joint", interfaces)
    );
    let mut w = world(&text);
    let upper = w.bodies.iter().position(|b| !b.fixed).expect("a free block");
    assert!(w.bodies[upper].centroid.y > 0.0);
    let a = 10.0 * (s - 0.2 * c);
    let mut v = Vec::new();
    for _ in 0..300 {
        w.step().unwrap_or_else(|e| panic!("{e}"));
        v.push(w.bodies[upper].mesh.as_ref().expect("a mesh").mean_motion().0.x);
    }
    let measured = (v[299] - v[99]) / 0.2;
    assert!((measured - a).abs() < 1e-5 * a, "a = {measured}, closed form {a}");
}
