//! A block stopped by friction stops (math note §10.15): a 1 m rigid block on a 20 degree
//! incline (friction 0.5, gravity 9.81), launched down-slope at v0, dt = 0.01.
//!
//! Closed form: it slides with the constant deceleration a = g (mu cos alpha - sin alpha) and
//! stops at t* = v0 / a after v0^2 / (2 a). The scheme (math note §1.1) is exact for motion under
//! constant forces, so every step that ends before t* is on the parabola
//! s(t) = v0 t - a t^2 / 2 with velocity v0 - a t. The step containing t* (math note §10.15):
//! - velocity: solve 2 holds the stopping friction rows at zero end slip rate, so the block
//!   ends that step, and every later one, with zero velocity and kinetic energy (asserted to
//!   1e-12: the rates are rounding, about 1e-17; before the rule they rang at +-(a dt - v_k)
//!   or +-v_k, 1.6e-4 m/s for v0 = 0.05);
//! - position: solve 1 either sticks at once (t* in the step's first half: the block stays at
//!   s(t_k)) or slides the whole step (second half: s(t_k + dt)). Either way it stops at the
//!   parabola's value at the step boundary nearest t*, within a dt^2 / 8 of the closed-form
//!   distance v0^2 / (2 a). Asserted to 1e-9 m (the solves are run at tolerance 1e-12; the
//!   positions are sums of about 10 increments of 1e-3 m), and against the closed-form
//!   distance within a dt^2 / 8 + 1e-9.
//!
//! Two launch speeds: v0 = 0.048 (t* = 0.0383 s, second half of step 4) and v0 = 0.043
//! (t* = 0.0343 s, first half of step 4). The rule is off by default; the first turns it on by
//! the scene's `[solver] friction_stops = true`, the second by `World::settings`.

use pbdda::geometry::Vec2;
use pbdda::world::World;

const G: f64 = 9.81;
const MU: f64 = 0.5;
const DT: f64 = 0.01;

fn alpha() -> f64 {
    20f64.to_radians()
}

/// The incline (top face through the origin, rising to the right at alpha) and the block on
/// it with its lower corner at the origin, launched down-slope at v0; `key`: the scene turns
/// friction stops on.
fn scene(v0: f64, key: bool) -> String {
    let (s, c) = alpha().sin_cos();
    let rot = |x: f64, y: f64| format!("[{:?}, {:?}]", x * c - y * s, x * s + y * c);
    let poly = |p: &[(f64, f64)]| p.iter().map(|&(x, y)| rot(x, y)).collect::<Vec<_>>().join(", ");
    let slope = poly(&[(-10.0, -1.0), (10.0, -1.0), (10.0, 0.0), (-10.0, 0.0)]);
    let block = poly(&[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]);
    format!(
        r#"[scene]
name = "friction stop"
[time]
step = {DT}
steps = 30
[physics]
gravity = [0.0, -{G}]
[solver]
tolerance = 1e-12
friction_stops = {key}
[[material]]
name = "rock"
density = 2500.0
[[interface]]
friction = {MU}
[[body]]
name = "slope"
shape = "polygon"
vertices = [{slope}]
material = "rock"
fixed = true
[[body]]
name = "block"
shape = "polygon"
vertices = [{block}]
material = "rock"
velocity = [{:?}, {:?}]
"#,
        -v0 * c,
        -v0 * s
    )
}

/// `key`: friction stops from the scene's key, else from `World::settings`.
fn check(v0: f64, key: bool) {
    let (s, c) = alpha().sin_cos();
    let a = G * (MU * c - s);
    let t_star = v0 / a;
    // the step containing t* (steps are numbered from 1), and the boundary nearest t*
    let k_star = (t_star / DT).ceil() as usize;
    let half = t_star / DT - (k_star - 1) as f64;
    assert!((0.05..0.45).contains(&half) || (0.55..0.95).contains(&half), "t* too near a boundary");
    let stop = (t_star / DT).round() * DT;
    let parabola = |t: f64| v0 * t - a * t * t / 2.0;
    let down = Vec2::new(-c, -s);
    let model = pbdda::scene::parse(&scene(v0, key), "stop.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(model.solver.friction_stops, key, "the scene's [solver] friction_stops");
    let mut world = World::new(model);
    world.settings.friction_stops = !key; // off by default (World Settings)
    let b = world.bodies.iter().position(|b| b.name == "block").expect("block");
    let c0 = world.bodies[b].centroid;
    for step in 1..=30 {
        let rec = world.step().unwrap_or_else(|e| panic!("{e}"));
        let body = &world.bodies[b];
        let t = rec.time;
        let travel = (body.centroid - c0).dot(&down);
        let v = Vec2::new(body.velocity[0], body.velocity[1]);
        if step < k_star {
            assert!((travel - parabola(t)).abs() < 1e-9, "v0 {v0}, step {step}: travel {travel}");
            assert!((v.dot(&down) - (v0 - a * t)).abs() < 1e-9, "v0 {v0}, step {step}: speed {v}");
        } else {
            assert!((travel - parabola(stop)).abs() < 1e-9, "v0 {v0}, step {step}: stopped at {travel}");
            let closed = v0 * v0 / (2.0 * a);
            assert!((travel - closed).abs() <= a * DT * DT / 8.0 + 1e-9, "v0 {v0}: {travel} vs {closed}");
            assert!(v.norm() < 1e-12 && body.velocity[2].abs() < 1e-12, "v0 {v0}, step {step}: v = {v}");
            assert!(
                rec.kinetic_energy < 1e-12,
                "v0 {v0}, step {step}: kinetic energy {}",
                rec.kinetic_energy
            );
        }
    }
}

#[test]
fn a_block_stopped_in_the_second_half_of_a_step_stops_at_its_end() {
    check(0.048, true);
}

#[test]
fn a_block_stopped_in_the_first_half_of_a_step_stops_at_its_start() {
    check(0.043, false);
}
