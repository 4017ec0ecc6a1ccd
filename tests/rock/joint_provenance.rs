//! Joint provenance (math note §4.14): a contact between two polygon edges tagged with the same
//! interface (`edge_interfaces`, as the cut blocks of a rock mass carry them) takes that
//! interface's law, others the material pair's.
//!
//! A unit block on a fixed base under gravity g tilted by a = 30° from the base's normal
//! (g = 9.81 (sin a, -cos a)): the default interface has friction 0.9 (42°, above a: the block
//! stays), the joint's friction_angle is phi = 20° (below a). With both edges of the contact
//! tagged "joint" the block slides with the closed form a_x = g (sin a - cos a tan phi) =
//! 1.81283 m/s² and x(t) = a_x t²/2, which the scheme meets exactly under constant forces
//! (math note §1.1): tolerance 1e-9 m, the solver's tolerance (1e-12 relative) on forces of
//! ~10 kN times dt² / m. With one edge untagged, or tagged with another interface, the default
//! law holds and the block stays to the same tolerance.

use crate::common;
use common::*;
use pbdda::world::World;

fn scene(block_tags: &str, base_tags: &str) -> String {
    let a = 30f64.to_radians();
    let (gx, gy) = (9.81 * a.sin(), -9.81 * a.cos());
    format!(
        r#"
[scene]
name = "joint provenance"
[time]
step = 0.01
steps = 20
[physics]
gravity = [{gx}, {gy}]
[solver]
tolerance = 1e-12
[[material]]
name = "rock"
density = 1000.0
[[interface]]
friction = 0.9
[[interface]]
name = "joint"
friction_angle = 20.0
[[interface]]
name = "other"
friction_angle = 20.0
[[body]]
name = "base"
shape = "polygon"
vertices = [[-5.0, -1.0], [5.0, -1.0], [5.0, 0.0], [-5.0, 0.0]]
material = "rock"
fixed = true
edge_interfaces = {base_tags}
[[body]]
name = "block"
shape = "polygon"
vertices = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
material = "rock"
edge_interfaces = {block_tags}
"#
    )
}

/// The block's x shift after each of 20 steps of 0.01 s, and the interface index each step's
/// contacts report.
fn shifts(block_tags: &str, base_tags: &str) -> (Vec<f64>, Vec<Option<usize>>) {
    let model = pbdda::scene::parse(&scene(block_tags, base_tags), "provenance.toml").unwrap();
    let mut world = World::new(model);
    let block = body(&world, "block");
    let x0 = world.bodies[block].centroid.x;
    let (mut xs, mut laws) = (Vec::new(), Vec::new());
    run(&mut world, 20, |w, rec| {
        xs.push(w.bodies[block].centroid.x - x0);
        laws.extend(between(w, rec, "base", "block").iter().map(|c| c.interface));
    });
    (xs, laws)
}

#[test]
fn tagged_joint_slides_with_its_friction() {
    let a = 30f64.to_radians();
    let ax = 9.81 * (a.sin() - a.cos() * 20f64.to_radians().tan());
    // the base's top edge is edge 2 ((5, 0) -> (-5, 0)), the block's bottom edge 0
    let (xs, laws) = shifts(r#"["joint", "", "", ""]"#, r#"["", "", "joint", ""]"#);
    for (i, x) in xs.iter().enumerate() {
        let t = (i + 1) as f64 * 0.01;
        assert!(
            (x - 0.5 * ax * t * t).abs() < 1e-9,
            "step {}: x = {x}, closed form {}",
            i + 1,
            0.5 * ax * t * t
        );
    }
    // every contact reports interface 1 ("joint")
    assert!(!laws.is_empty());
    assert!(laws.iter().all(|l| *l == Some(1)), "{laws:?}");
}

#[test]
fn untagged_or_differently_tagged_edges_keep_the_material_law() {
    for (block, base) in [
        (r#"["joint", "", "", ""]"#, r#"["", "", "", ""]"#),
        (r#"["joint", "", "", ""]"#, r#"["", "", "other", ""]"#),
    ] {
        let (xs, laws) = shifts(block, base);
        assert!(xs.iter().all(|x| x.abs() < 1e-9), "{block} / {base}: {xs:?}");
        assert!(laws.iter().all(|l| *l == Some(0)), "{laws:?}");
    }
}

/// Clockwise vertices are stored counter-clockwise; the tags follow their edges: the block given
/// clockwise from (0, 0) has its bottom edge last.
#[test]
fn tags_follow_edges_of_a_clockwise_polygon() {
    let clockwise = scene(r#"["", "", "", "joint"]"#, r#"["", "", "joint", ""]"#).replace(
        "[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]",
        "[[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]]",
    );
    let model = pbdda::scene::parse(&clockwise, "cw.toml").unwrap();
    let block = &model.bodies[1];
    let pbdda::model::Shape::Polygon { vertices } = &block.shape else { panic!("polygon") };
    let bottom = (0..4).find(|&i| vertices[i].y == 0.0 && vertices[(i + 1) % 4].y == 0.0).unwrap();
    let tagged: Vec<usize> = (0..4).filter(|&i| block.edge_interfaces[i].is_some()).collect();
    assert_eq!(tagged, vec![bottom]);
}
