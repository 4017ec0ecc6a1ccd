//! Blocks sliding past crossings of two persistent joint sets (math note §5.2): four blocks meet at
//! every crossing, and the slab's corner there makes no contact with the block diagonally across,
//! so the slab slides along the bedding as a block on a single joint does.

use crate::common;
use common::*;
use pbdda::world::World;

/// A 4 m x 2 m domain cut by a persistent bedding set (angle 0°, spacing 1 m from y = 0.5:
/// traces y = 0.5 and 1.5, phi = 20°) and a persistent cross set at `cross` degrees (spacing
/// 1 m from (0.5, 0), phi = 35°). Everything below y = 1.5 is fixed; the top layer's blocks are
/// free. Gravity g = 9.81 is tilted by a = 30° from the bedding's normal, toward +x (the
/// bedding "dips" 30° and daylights at x = 4): every free block's base slides past crossings of
/// the two sets, propped by nothing, at a_x = g (sin a - cos a tan phi) = 1.8128 m/s², x(t) =
/// a_x t²/2, exact for the scheme under constant forces (math note §1.1). The free blocks move
/// together, so the cross joints between them carry no force. 40 steps (s = 0.145 m; every base
/// corner is past its crossing from step 1). Tolerance 1e-9 m: the solver's (1e-12 relative on
/// forces of ~20 kN/m) times dt²/m, as for a block on a single joint (tests/rock/rock_mass_scene.rs);
/// a block propped at a crossing misses it by its whole path. Every contact between a free and
/// a fixed block lies on the bedding (normal ±y, its interface) or carries no force (a trailing
/// corner leaving a cross edge): none props a slab along the cross joint's normal.
fn slide_past_crossings(cross: f64) {
    let a = 30f64.to_radians();
    let text = format!(
        r#"
[scene]
name = "crossings"
[time]
step = 0.01
steps = 40
[physics]
gravity = [{gx}, {gy}]
[solver]
tolerance = 1e-12
[[material]]
name = "rock"
density = 2500.0
[[interface]]
friction = 0.9
[[interface]]
name = "bedding"
friction_angle = 20.0
[[interface]]
name = "cross"
friction_angle = 35.0
[domain]
vertices = [[0.0, 0.0], [4.0, 0.0], [4.0, 2.0], [0.0, 2.0]]
material = "rock"
[[joint_set]]
angle = 0.0
spacing = 1.0
origin = [0.0, 0.5]
interface = "bedding"
[[joint_set]]
angle = {cross}
spacing = 1.0
origin = [0.5, 0.0]
interface = "cross"
[[region]]
vertices = [[0.0, 0.0], [4.0, 0.0], [4.0, 1.5], [0.0, 1.5]]
fixed = true
"#,
        gx = 9.81 * a.sin(),
        gy = -9.81 * a.cos()
    );
    let model = pbdda::scene::parse(&text, "crossings.toml").unwrap();
    let free: Vec<usize> = (0..model.bodies.len()).filter(|&i| !model.bodies[i].fixed).collect();
    // the top layer, 0.5 m thick, is cut by the cross set into 5 blocks
    assert_eq!(free.len(), 5, "free blocks");
    let mut world = World::new(model);
    let x0: Vec<f64> = free.iter().map(|&i| world.bodies[i].centroid.x).collect();
    let ax = 9.81 * (a.sin() - a.cos() * 20f64.to_radians().tan());
    let mut step = 0;
    run(&mut world, 40, |w, rec| {
        step += 1;
        let t = step as f64 * 0.01;
        for (k, &i) in free.iter().enumerate() {
            let x = w.bodies[i].centroid.x - x0[k];
            let name = &w.bodies[i].name;
            assert!(
                (x - 0.5 * ax * t * t).abs() < 1e-9,
                "step {step}, {name}: x = {x}, closed form {}",
                0.5 * ax * t * t
            );
        }
        for c in &rec.contacts {
            if w.bodies[c.body_a].fixed != w.bodies[c.body_b].fixed {
                let on_bedding = c.normal.y.abs() > 1.0 - 1e-12 && c.interface == Some(1);
                let idle = c.normal_force == 0.0 && c.shear_force == 0.0;
                assert!(on_bedding || idle, "step {step}: a force off the bedding {c:?}");
            }
        }
    });
}

#[test]
fn slabs_slide_past_perpendicular_crossings() {
    slide_past_crossings(90.0);
}
