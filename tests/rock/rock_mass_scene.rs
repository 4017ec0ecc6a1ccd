//! Rock masses in scenes (scene-format "Rock masses"): blocks cut from a `[domain]` carry
//! their joint set's interface, grouted bolts split at block edges, bolt patterns along an
//! excavation, and `pbdda cut`'s expanded scene gives the same model.

use crate::common;
use common::*;
use pbdda::model::Shape;
use pbdda::world::World;

const HEAD: &str = r#"
[scene]
name = "rock mass"
[time]
step = 0.01
steps = 20
[[material]]
name = "rock"
density = 2500.0
[[interface]]
friction = 0.9
[[interface]]
name = "bedding"
friction_angle = 20.0
"#;

/// A 1 m x 1.6 m domain cut by one persistent horizontal set through y = 0.8 (spacing 1 m: the
/// other traces, y = -0.2 and 1.8, miss it): two blocks, the lower fixed. Gravity g = 9.81 is
/// tilted by a = 30° from the joint's normal; the set's interface has phi = 20° < a, the default
/// 42° > a. The upper block slides along the joint with a_x = g (sin a - cos a tan phi), x(t) =
/// a_x t²/2, exact for the scheme under constant forces (math note §1.1): tolerance 1e-9 m,
/// the solver's (1e-12 relative on forces of ~20 kN/m) times dt²/m.
#[test]
fn blocks_cut_by_a_set_slide_with_its_friction() {
    let a = 30f64.to_radians();
    let text = format!(
        "{HEAD}
[physics]
gravity = [{}, {}]
[solver]
tolerance = 1e-12
[domain]
vertices = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.6], [0.0, 1.6]]
material = \"rock\"
[[joint_set]]
angle = 0.0
spacing = 1.0
origin = [0.0, 0.8]
interface = \"bedding\"
[[region]]
vertices = [[0.0, 0.0], [1.0, 0.0], [1.0, 0.8], [0.0, 0.8]]
fixed = true
",
        9.81 * a.sin(),
        -9.81 * a.cos()
    );
    let model = pbdda::scene::parse(&text, "slide.toml").unwrap();
    let names: Vec<&str> = model.bodies.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(names, ["blk-1", "blk-2"]);
    assert!(model.bodies[0].fixed && !model.bodies[1].fixed);
    let mut world = World::new(model);
    let x0 = world.bodies[1].centroid.x;
    let ax = 9.81 * (a.sin() - a.cos() * 20f64.to_radians().tan());
    let mut step = 0;
    run(&mut world, 20, |w, rec| {
        step += 1;
        let t = step as f64 * 0.01;
        let x = w.bodies[1].centroid.x - x0;
        assert!(
            (x - 0.5 * ax * t * t).abs() < 1e-9,
            "step {step}: x = {x}, closed form {}",
            0.5 * ax * t * t
        );
        let contacts = between(w, rec, "blk-1", "blk-2");
        assert!(!contacts.is_empty() && contacts.iter().all(|c| c.interface == Some(1)));
    });
}

/// A 10 m x 2 m domain cut by vertical traces at x = 1, 3, 5, 7, 9 (spacing 2 from x = 1):
/// 6 blocks. A grouted bolt from (0.5, 1) to (9.5, 1) runs through all 6: 5 segments, segment k
/// joining the blocks of pieces k and k + 1, each anchor inside its block, their lengths adding
/// up to the bolt's 9 m (to 1e-12 m, round-off of the crossings). The first block is fixed
/// (`fixed_points`).
#[test]
fn a_grouted_bolt_through_n_blocks_gives_n_minus_1_segments() {
    let text = format!(
        "{HEAD}
[domain]
vertices = [[0.0, 0.0], [10.0, 0.0], [10.0, 2.0], [0.0, 2.0]]
material = \"rock\"
fixed_points = [[0.5, 1.0]]
[[joint_set]]
angle = 90.0
spacing = 2.0
origin = [1.0, 0.0]
[[connector]]
name = \"b\"
kind = \"bolt\"
points = [[0.5, 1.0], [9.5, 1.0]]
young = 2.0e11
area = 3.0e-4
grouted = true
"
    );
    let model = pbdda::scene::parse(&text, "grouted.toml").unwrap();
    assert_eq!(model.bodies.len(), 6);
    assert_eq!(model.connectors.len(), 5);
    // anchors: the bolt's ends and the middles of the pieces between, x = 0.5, 2, 4, 6, 8, 9.5
    let xs = [0.5, 2.0, 4.0, 6.0, 8.0, 9.5];
    let mut total = 0.0;
    let mut chain = vec![model.connectors[0].bodies[0]];
    for (k, c) in model.connectors.iter().enumerate() {
        assert_eq!(c.name, format!("b.{}", k + 1));
        assert!((c.points[0].x - xs[k]).abs() < 1e-12 && (c.points[1].x - xs[k + 1]).abs() < 1e-12);
        for e in 0..2 {
            assert!(model.bodies[c.bodies[e]].shape.contains(c.points[e]), "segment {k} end {e}");
        }
        // consecutive segments share the block between them
        assert_eq!(c.bodies[0], *chain.last().unwrap());
        chain.push(c.bodies[1]);
        total += (c.points[1] - c.points[0]).norm();
    }
    chain.sort();
    assert_eq!(chain, (0..6).collect::<Vec<_>>(), "the chain runs through all 6 blocks");
    assert!((total - 9.0).abs() < 1e-12, "total length {total}");
}

/// A bolt pattern on a 24-gon of radius 3 (vertices every 15° from 0°, so 30° and 150° are
/// vertices): the boundary between them is 8 edges of 2 r sin(7.5°), L = 6.2651 m; spacing 1 m
/// gives floor(L / 1) + 1 = 7 bolts `roof-1` ... `roof-7`, each 4 m long, starting on the outline.
/// Horizontal joints every 2 m (y = 10.5, 12.5, 14.5, ...) make each 4 m bolt cross one, so that
/// its ends lie in two blocks.
#[test]
fn a_bolt_pattern_places_floor_l_over_s_plus_1_bolts() {
    let text = format!(
        "{HEAD}
[domain]
vertices = [[0.0, 0.0], [20.0, 0.0], [20.0, 20.0], [0.0, 20.0]]
material = \"rock\"
[[joint_set]]
angle = 0.0
spacing = 2.0
origin = [0.0, 0.5]
[[excavation]]
name = \"tunnel\"
center = [10.0, 10.0]
radius = 3.0
segments = 24
[[bolt_pattern]]
name = \"roof\"
excavation = \"tunnel\"
spacing = 1.0
range = [30.0, 150.0]
length = 4.0
young = 2.0e11
area = 3.3e-4
"
    );
    let model = pbdda::scene::parse(&text, "pattern.toml").unwrap();
    let l = 16.0 * 3.0 * 7.5f64.to_radians().sin();
    let count = (l / 1.0).floor() as usize + 1;
    assert_eq!(count, 7);
    let names: Vec<String> = model.connectors.iter().map(|c| c.name.clone()).collect();
    assert_eq!(names, (1..=count).map(|k| format!("roof-{k}")).collect::<Vec<_>>());
    let center = pbdda::geometry::Vec2::new(10.0, 10.0);
    for c in &model.connectors {
        assert!(((c.points[1] - c.points[0]).norm() - 4.0).abs() < 1e-12);
        // on the 24-gon: between the apothem r cos(7.5°) and r
        let r = (c.points[0] - center).norm();
        assert!(r <= 3.0 + 1e-12 && r >= 3.0 * 7.5f64.to_radians().cos() - 1e-12, "r = {r}");
    }
}

/// `pbdda cut`'s expanded scene, read back, gives the same model as the scene it came from:
/// the tunnel example (blocks, regions, grouted bolt pattern) compared field by field through
/// the models' Debug text.
#[test]
fn the_expanded_scene_gives_the_same_model() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/tunnel_bolted.toml");
    let source = std::fs::read_to_string(&path).unwrap();
    let file = path.display().to_string();
    let expanded = pbdda::scene::expanded(&source, &file, "tunnel").unwrap();
    assert!(expanded.meshes.is_empty());
    let again = pbdda::scene::parse(&expanded.text, &file).unwrap();
    assert_eq!(format!("{:?}", again), format!("{:?}", expanded.model));
    assert!(expanded.text.contains("[[body]]") && !expanded.text.contains("[domain]"));
    assert!(expanded.model.bodies.iter().all(|b| matches!(b.shape, Shape::Polygon { .. })));
}

/// `model = "mesh"`: each block becomes a mesh body; `cut` writes one `.msh` per block beside
/// the expanded scene, and the scene read back has the same nodes and triangles (the files hold
/// the coordinates in shortest round-trip form, so they are equal bit for bit) and the same
/// fixed bodies (the region below y = 0.5).
#[test]
fn meshed_blocks_round_trip_through_msh_files() {
    let text = format!(
        "{HEAD}
[domain]
vertices = [[0.0, 0.0], [4.0, 0.0], [4.0, 2.0], [0.0, 2.0]]
material = \"rock\"
model = \"mesh\"
mesh_size = 0.5
[[joint_set]]
angle = 60.0
spacing = 1.5
origin = [0.3, 0.0]
[[region]]
vertices = [[0.0, 0.0], [4.0, 0.0], [4.0, 0.5], [0.0, 0.5]]
fixed = true
"
    )
    .replace("density = 2500.0", "density = 2500.0\nyoung = 1e10\npoisson = 0.25");
    let dir = std::env::temp_dir().join(format!("pbdda-meshcut-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("meshed.toml");
    let file = scene.display().to_string();
    let expanded = pbdda::scene::expanded(&text, &file, "meshed").unwrap();
    assert_eq!(expanded.meshes.len(), expanded.model.bodies.len());
    for (name, contents) in &expanded.meshes {
        std::fs::write(dir.join(name), contents).unwrap();
    }
    std::fs::write(&scene, &expanded.text).unwrap();
    let again = pbdda::scene::load(&scene).unwrap();
    assert_eq!(again.bodies.len(), expanded.model.bodies.len());
    for (a, b) in again.bodies.iter().zip(&expanded.model.bodies) {
        let (Shape::Mesh(a_mesh), Shape::Mesh(b_mesh)) = (&a.shape, &b.shape) else { panic!("mesh bodies") };
        assert_eq!(a.name, b.name);
        assert_eq!(a.fixed, b.fixed);
        assert_eq!(a_mesh.mesh.nodes, b_mesh.mesh.nodes);
        assert_eq!(a_mesh.mesh.triangles, b_mesh.mesh.triangles);
    }
    assert!(again.bodies.iter().any(|b| b.fixed) && again.bodies.iter().any(|b| !b.fixed));
    let _ = std::fs::remove_dir_all(&dir);
}
