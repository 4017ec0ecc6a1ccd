//! The rock-mass examples run, and do what their geometry and joint laws predict.

mod common;
use common::*;
use pbdda::world::World;

/// `examples/jointed_slope.toml`: joints of set J1 dip 30° out of the face with the interface
/// "bedding", phi = 20° < 30°. A free block resting on a J1 joint and free below it slides along
/// the joint's dip direction (210° from +x) with the closed form of a block on a plane,
/// s(t) = g (sin 30° - cos 30° tan 20°) t²/2 (math note §1.1: exact for constant forces);
/// every other free block is held by the fixed rock and stays. Tolerances: 1e-6 m on the
/// slide of a block that does not turn (the default VI tolerance, 1e-8 relative on the contact
/// forces, over 150 steps), 1e-6 rad on its direction; 2e-3 rad on the direction of any block
/// that moves (a small wedge at the toe also tilts, by about 1e-3 rad); 1e-6 m for "stays".
/// The number of blocks that slide without turning is not asserted exactly: the blocks that
/// could slide (base on J1, cut off from the fixed rock by J2 pieces, free down the dip) follow
/// from the cut, but whether such a block also turns depends on the contacts of the blocks that
/// rest on it and on the toe wedge, which no closed form gives; only "at least one" is predicted.
#[test]
fn jointed_slope_fails_by_sliding_on_the_daylighting_set() {
    let mut world = World::new(example("jointed_slope.toml"));
    let start: Vec<_> = world.bodies.iter().map(|b| b.centroid).collect();
    let steps = world.model.time.steps;
    let dt = world.model.time.step;
    run(&mut world, steps, |_, _| {});
    let t = steps as f64 * dt;
    let a = 9.81 * (30f64.to_radians().sin() - 30f64.to_radians().cos() * 20f64.to_radians().tan());
    let slide = 0.5 * a * t * t;
    let mut sliding = 0;
    for (b, body) in world.bodies.iter().enumerate().filter(|(_, b)| !b.fixed) {
        let d = body.centroid - start[b];
        if d.norm() < 1e-6 {
            continue;
        }
        // every block that moves goes down J1's dip (within 2e-3 rad: a sliver may also tilt)
        let direction = d.y.atan2(d.x);
        assert!((direction - (-150f64).to_radians()).abs() < 2e-3, "{}: direction {direction}", body.name);
        if body.rotation.abs() < 1e-9 {
            // a block that slides without turning follows the closed form
            sliding += 1;
            assert!(
                (d.norm() - slide).abs() < 1e-6,
                "{}: slid {} m, closed form {slide}",
                body.name,
                d.norm()
            );
            assert!(
                (direction - (-150f64).to_radians()).abs() < 1e-6,
                "{}: direction {direction}",
                body.name
            );
        }
    }
    assert!(sliding > 0, "the slope fails");
}

/// `examples/tunnel_bolted.toml`: the roof pattern between 30° and 150° on the 24-gon of radius
/// 3 (vertices every 15°) spans 8 edges, L = 16 · 3 sin 7.5° = 6.27 m: floor(L / 1 m) + 1 = 7
/// bolts, each split into segments `roof-k.j`, each segment joining two distinct blocks; the run
/// completes and no segment breaks (the pattern has no strength).
#[test]
fn tunnel_bolted_runs_with_its_grouted_pattern() {
    let mut world = World::new(example("tunnel_bolted.toml"));
    let model = &world.model;
    let bolts: std::collections::BTreeSet<&str> =
        model.connectors.iter().filter_map(|c| c.name.split('.').next()).collect();
    let expected: std::collections::BTreeSet<String> = (1..=7).map(|k| format!("roof-{k}")).collect();
    assert_eq!(bolts, expected.iter().map(String::as_str).collect());
    for c in &model.connectors {
        assert!(c.name.contains('.'), "{} is a segment", c.name);
        assert_ne!(c.bodies[0], c.bodies[1]);
    }
    let steps = world.model.time.steps;
    run(&mut world, steps, |_, _| {});
    assert!(world.connectors.iter().all(|c| !c.broken));
}
