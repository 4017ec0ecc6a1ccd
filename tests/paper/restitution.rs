//! `restitution` on `[[interface]]`: Newton's normal coefficient e (math note §10.15).
//!
//! 1. A disk between two fixed walls, no gravity, v = 2 m/s, impacts mid-step. Closed form: a
//!    straight path folded at the walls, the speed e^k v after the k-th impact, the impacts at
//!    t_1 = D_1 / v and t_{k+1} = t_k + 2 (L - r) / (e^k v). The scheme is exact for an impact
//!    under no other force (math note §1.3, §10.15: the end gap e (v dt - g0), the rate -e u0),
//!    so centre, speed and the step of each impact are asserted to 1e-9 (solver tolerance
//!    1e-12; 1,400 steps of rounding stay far below), e = 0.8 and e = 0 (the disk stays at the
//!    wall with zero velocity, to 1e-12).
//! 2. A disk dropped from h = 1 m on a fixed floor, g = 9.81, e = 0.5, dt = 1e-3. The scheme's
//!    impact step (math note §10.15, "Under gravity") maps the step-start gap g0 and approach
//!    speed v to the end gap e (v dt + g dt^2/2 - g0) and the rebound speed e v; every other
//!    step is the exact parabola. Both are asserted to 1e-9 at every step. Against the
//!    closed form: the first impact falls in the step containing sqrt(2 h / g), and each
//!    rebound apex is e^2 times the apex before it (the first: e^2 h) within the bound
//!    e (v dt + g dt^2/2) that the map gives (the contact holds the body against gravity for
//!    the rest of the impact step).
//! 3. Newton's cradle: a disk (v = 1 m/s) striking a row of n = 3 touching equal disks, no
//!    gravity, no friction. The contacts of the row are persistent, not impacts, so solve 2
//!    moves the row as one body of mass n m (math note §10.15, "Simultaneous impacts"):
//!    e = 1 gives the striker (1 - n)/(1 + n) v = -0.5 and the row 2 v/(n + 1) = 0.5 (momentum
//!    and energy conserved), e = 0 everything v/(n + 1) = 0.25 (the perfectly plastic
//!    impact). Velocities to 1e-9 at every step after the impact; for e = 0 every centre, for
//!    e = 1 the striker's (the row's position lags by v s/(n+1), §10.12) to 1e-9.

use pbdda::world::World;

fn header(gravity: f64, dt: f64, steps: usize, e: f64) -> String {
    format!(
        r#"[scene]
name = "restitution"
[time]
step = {dt}
steps = {steps}
[physics]
gravity = [0.0, -{gravity}]
[solver]
tolerance = 1e-12
[[material]]
name = "rock"
density = 1000.0
[[interface]]
restitution = {e}
"#
    )
}

fn wall(name: &str, x0: f64, y0: f64, x1: f64, y1: f64) -> String {
    format!(
        "[[body]]\nname = \"{name}\"\nshape = \"polygon\"\nvertices = [[{x0}, {y0}], [{x1}, {y0}], [{x1}, {y1}], [{x0}, {y1}]]\nmaterial = \"rock\"\nfixed = true\n"
    )
}

fn disk(name: &str, x: f64, y: f64, r: f64, vx: f64, vy: f64) -> String {
    format!(
        "[[body]]\nname = \"{name}\"\nshape = \"disk\"\ncenter = [{x}, {y}]\nradius = {r}\nmaterial = \"rock\"\nvelocity = [{vx}, {vy}]\n"
    )
}

fn world(scene: &str) -> World {
    World::new(pbdda::scene::parse(scene, "restitution.toml").unwrap_or_else(|e| panic!("{e}")))
}

/// Case 1: walls at x = +-3, disk r = 0.5 from x = 0.003 at v = 2, dt = 0.01, 1,400 steps.
fn billiard(e: f64) {
    let (v, r, l, x0, dt) = (2.0, 0.5, 3.0, 0.003, 0.01);
    let mut s = header(0.0, dt, 1400, e);
    s += &wall("left", -4.0, -2.0, -l, 2.0);
    s += &wall("right", l, -2.0, 4.0, 2.0);
    s += &disk("disk", x0, 0.0, r, v, 0.0);
    let mut w = world(&s);
    let b = w.bodies.iter().position(|b| b.name == "disk").expect("disk");
    // impact times and the exact centre
    let reach = l - r;
    let mut times = vec![(reach - x0) / v];
    while e > 0.0 && times.len() < 8 {
        let k = times.len() as i32;
        times.push(times[k as usize - 1] + 2.0 * reach / (e.powi(k) * v));
    }
    let exact = |t: f64| -> (f64, f64) {
        let hits = times.iter().filter(|&&tk| tk <= t).count();
        let (speed, dir) = (v * e.powi(hits as i32), if hits % 2 == 0 { 1.0 } else { -1.0 });
        let x = if hits == 0 {
            x0 + v * t
        } else {
            let wall = if hits % 2 == 1 { reach } else { -reach };
            wall + dir * speed * (t - times[hits - 1])
        };
        (x, dir * speed)
    };
    for &tk in &times {
        let f = tk / dt - (tk / dt).floor();
        assert!((0.01..0.99).contains(&f), "impact at {tk} too near a step boundary");
    }
    let mut impacts = 0;
    for _ in 0..1400 {
        let before = w.bodies[b].velocity[0];
        let rec = w.step().unwrap_or_else(|e| panic!("{e}"));
        let (x, vx) = (w.bodies[b].centroid.x, w.bodies[b].velocity[0]);
        let (xe, ve) = exact(rec.time);
        assert!((x - xe).abs() < 1e-9, "e {e}, t {}: x {x} vs {xe}", rec.time);
        assert!((vx - ve).abs() < 1e-9 * v.max(1.0), "e {e}, t {}: vx {vx} vs {ve}", rec.time);
        if e == 0.0 && rec.time > times[0] {
            assert!(vx.abs() < 1e-12 && rec.kinetic_energy < 1e-12, "e 0, t {}: vx {vx}", rec.time);
        }
        if e > 0.0 && vx.signum() != before.signum() {
            // the step of the impact contains its closed-form time
            let tk = times[impacts];
            assert!(rec.time - dt < tk && tk <= rec.time, "impact {impacts} at {} vs {tk}", rec.time);
            impacts += 1;
        }
    }
    let expected = times.iter().filter(|&&t| t <= 14.0).count();
    let expected = if e == 0.0 { 0 } else { expected };
    assert_eq!(impacts, expected, "e {e}: impacts");
}

#[test]
fn a_disk_between_walls_rebounds_with_e_times_its_speed() {
    billiard(0.8);
}

#[test]
fn a_disk_with_e_zero_stays_at_the_wall() {
    billiard(0.0);
}

#[test]
fn a_dropped_disk_follows_the_impact_map_and_rebounds_to_e_squared_its_height() {
    let (g, h, r, e, dt, steps) = (9.81, 1.0, 0.1, 0.5, 1e-3, 1300);
    let mut s = header(g, dt, steps, e);
    s += &wall("floor", -1.0, -0.5, 1.0, 0.0);
    s += &disk("disk", 0.0, h + r, r, 0.0, 0.0);
    let mut w = world(&s);
    let b = w.bodies.iter().position(|b| b.name == "disk").expect("disk");
    let (mut y, mut v) = (h, 0.0);
    let (mut apex, mut bounces) = (h, 0);
    for _ in 0..steps {
        let rec = w.step().unwrap_or_else(|e| panic!("{e}"));
        let free = y + v * dt - g * dt * dt / 2.0;
        let (ye, ve) = if free < 0.0 {
            // the impact map of math note §10.15
            let (speed, y1, v1) = (-v, e * (-v * dt + g * dt * dt / 2.0 - y), -e * v);
            if bounces == 0 {
                let t1 = (2.0 * h / g).sqrt();
                assert!(rec.time - dt < t1 && t1 <= rec.time, "first impact at {} vs {t1}", rec.time);
            }
            let next = y1 + v1 * v1 / (2.0 * g);
            let bound = e * (speed * dt + g * dt * dt / 2.0);
            assert!(
                (next - e * e * apex).abs() <= bound,
                "bounce {bounces}: apex {next} vs {}",
                e * e * apex
            );
            (apex, bounces) = (next, bounces + 1);
            (y1, v1)
        } else {
            (free, v - g * dt)
        };
        let body = &w.bodies[b];
        let (yb, vb) = (body.centroid.y - r, body.velocity[1]);
        assert!((yb - ye).abs() < 1e-9, "t {}: gap {yb} vs {ye}", rec.time);
        assert!((vb - ve).abs() < 1e-9, "t {}: vy {vb} vs {ve}", rec.time);
        (y, v) = (yb, vb);
    }
    // 0.45, 0.90, 1.13, 1.24 s and 1.30 s, just past the end (apexes 0.25, 0.0625, 0.016 m)
    assert_eq!(bounces, 4, "bounces in 1.3 s");
}

fn cradle(e: f64) {
    let (v, dt, x0, n) = (1.0, 0.01, -0.2033, 3);
    let mut s = header(0.0, dt, 60, e);
    s += &disk("striker", x0, 0.0, 0.5, v, 0.0);
    for i in 1..=n {
        s += &disk(&format!("d{i}"), i as f64, 0.0, 0.5, 0.0, 0.0);
    }
    let mut w = world(&s);
    let tau = -x0 / v;
    let nf = n as f64;
    let (vs, vr) = if e == 1.0 {
        ((1.0 - nf) / (1.0 + nf) * v, 2.0 * v / (nf + 1.0))
    } else {
        (v / (nf + 1.0), v / (nf + 1.0))
    };
    for _ in 0..60 {
        let rec = w.step().unwrap_or_else(|e| panic!("{e}"));
        let t = rec.time;
        for (i, body) in w.bodies.iter().enumerate() {
            let (x, vx) = (body.centroid.x, body.velocity[0]);
            let (xe, ve) = match (i, t < tau) {
                (0, true) => (x0 + v * t, v),
                (_, true) => (i as f64, 0.0),
                (0, false) => (vs * (t - tau), vs),
                (_, false) => (i as f64 + vr * (t - tau), vr),
            };
            assert!((vx - ve).abs() < 1e-9, "e {e}, t {t}: {} vx {vx} vs {ve}", body.name);
            if i == 0 || e == 0.0 {
                assert!((x - xe).abs() < 1e-9, "e {e}, t {t}: {} x {x} vs {xe}", body.name);
            }
        }
    }
}

#[test]
fn newtons_cradle_elastic_moves_the_touching_row_as_one_body() {
    cradle(1.0);
}

#[test]
fn newtons_cradle_plastic_moves_everything_at_v_over_n_plus_one() {
    cradle(0.0);
}
