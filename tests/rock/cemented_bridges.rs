//! Cemented rock bridges hold their full strength (math note §4.5, §4.14, §5.1).
//!
//! A 3 m x 1 m domain is cut by one set at 90° through (1, 0), spacing 10 m (one line, x = 1),
//! pieces of trace 0.6 m and gap 0.4 m from the origin up: the trace [0, 0.6] and, with
//! `bridges = "cemented"`, the bridge [0.6, 1.0] (math note §12.1). So blk-1 = [0,1]x[0,1]
//! (fixed) and blk-2 = [1,3]x[0,1] share the face x = 1, whose lower 0.6 m carry the set's
//! interface "joint" (no tensile strength) and whose upper 0.4 m carry the bridge's "intact"
//! (tensile strength T = 1000 Pa, cohesion 0: with a pure normal pull the shear is zero, so
//! tension governs). The straight vertex (1, 0.6) where the tag changes is a contact vertex of
//! both blocks (§5.1): the bridge's joint has contacts at y = 0.6 and 1.0 sharing T L = 400 N
//! (L = 0.4 m, §4.5), the trace's at y = 0 and 0.6.
//!
//! No gravity; a horizontal point force F at (2, 0.8) pulls blk-2 away, its line of action
//! through the bridge's middle: the bridge alone can hold it (F / 2 at each of its contacts).
//! - F = 0.9 T L: the bridge holds; blk-2 does not move (1e-9 m: the solver's tolerance 1e-12,
//!   relative, on forces of 360 N over stiffness 2 m / dt^2 = 4e6 N/m gives ~1e-16 m; 1e-9 m
//!   leaves room for the outer iteration of the tensile share), both bridge contacts stay
//!   bonded, and the four contacts' normal forces sum to -F (equilibrium of blk-2 along x; 1e-9
//!   F for the solver's tolerance). How the sum splits among the four collinear contacts is
//!   statically indeterminate for a rigid block, so no single contact's force is asserted.
//! - F = 1.1 T L: the bridge reaches its strength and opens in the first step, breaks, and
//!   that step is solved again without the bond (math note §10.8, events within their step),
//!   so blk-2 flies free from t = 0 under the constant force: x = F t^2 / (2 m), m = rho A =
//!   100 kg/m^3 x 2 m^2 = 200 kg, which the scheme meets exactly (math note §1.1). The load
//!   point is 0.3 m above the centroid, so blk-2 also turns, but the centroid's motion does
//!   not depend on that (mass matrix about the centroid, §2.2). 1e-9 relative: rounding of a
//!   few hundred operations per step over 10 steps.

use crate::common;
use common::*;
use pbdda::world::World;

use pbdda::world::ContactState;

const T: f64 = 1000.0;
const L: f64 = 0.4;
const MASS: f64 = 100.0 * 2.0;
const DT: f64 = 0.01;
const STEPS: usize = 10;

fn scene(force: f64) -> String {
    format!(
        r#"
[scene]
name = "cemented bridge"
[time]
step = {DT}
steps = {STEPS}
[physics]
gravity = [0.0, 0.0]
[solver]
tolerance = 1e-12
[[material]]
name = "rock"
density = 100.0
[[interface]]
friction_angle = 30.0
[[interface]]
name = "joint"
friction_angle = 30.0
[[interface]]
name = "intact"
friction_angle = 30.0
cohesion = 0.0
tensile_strength = {T}
[domain]
vertices = [[0.0, 0.0], [3.0, 0.0], [3.0, 1.0], [0.0, 1.0]]
material = "rock"
model = "rigid"
fixed_points = [[0.5, 0.5]]
[[joint_set]]
angle = 90.0
spacing = 10.0
origin = [1.0, 0.0]
trace = 0.6
gap = 0.4
interface = "joint"
bridges = "cemented"
bridge_interface = "intact"
[[load]]
body = "blk-2"
point = [2.0, 0.8]
force = [{force}, 0.0]
"#
    )
}

fn world(force: f64) -> World {
    let model = pbdda::scene::parse(&scene(force), "bridge.toml").unwrap_or_else(|e| panic!("{e}"));
    World::new(model)
}

#[test]
fn a_bridge_holds_below_its_strength() {
    let f = 0.9 * T * L;
    let mut w = world(f);
    let right = body(&w, "blk-2");
    let intact = w.model.interfaces.iter().position(|i| i.name.as_deref() == Some("intact"));
    let x0 = w.bodies[right].centroid;
    run(&mut w, STEPS, |w, rec| {
        assert_converged(rec, 1e-12);
        let moved = (w.bodies[right].centroid - x0).norm().max(w.bodies[right].rotation.abs());
        assert!(moved < 1e-9, "step {}: moved {moved}", rec.step);
        let c = between(w, rec, "blk-1", "blk-2");
        assert_eq!(c.len(), 4, "{c:?}");
        let bridge: Vec<_> = c.iter().filter(|c| c.interface == intact).collect();
        assert_eq!(bridge.len(), 2, "{c:?}");
        assert!(bridge.iter().all(|b| b.state == ContactState::Bonded), "{bridge:?}");
        let total: f64 = c.iter().map(|c| c.normal_force).sum();
        assert!((total + f).abs() < 1e-9 * f, "{total} against {}", -f);
    });
}

#[test]
fn a_bridge_breaks_above_its_strength_and_the_block_flies_free() {
    let f = 1.1 * T * L;
    let mut w = world(f);
    let right = body(&w, "blk-2");
    let x0 = w.bodies[right].centroid.x;
    let mut t = 0.0;
    run(&mut w, STEPS, |w, rec| {
        t += DT;
        let x = w.bodies[right].centroid.x - x0;
        let exact = f * t * t / (2.0 * MASS);
        assert!((x - exact).abs() < 1e-9 * exact, "step {}: {x} against {exact}", rec.step);
    });
}
