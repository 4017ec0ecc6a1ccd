//! Staged runs (`[[stage]]`, math note §10.14), gravity ramps and connectors installed at a stage.
//!
//! Where each expected number comes from:
//! - removal: a block whose support is removed falls freely. The time scheme (math note §1.1,
//!   Newmark gamma = 1, beta = 1/2) gives d = dt v0 + g dt^2/2 and v1 = v0 + g dt under a constant
//!   force, so from rest y_n - y_0 = -g (n dt)^2 / 2 exactly; the tolerance 1e-9 m is round-off of
//!   a sum of 20 increments (about 1e-16 m each), and allows the solver's 1e-8-scaled residual in
//!   the static stage before it (the block starts the fall at rest: a static stage hands bodies
//!   over at rest, §10.14);
//! - a bolt loaded by gravity (undamped oscillator m x'' + k x = m g): a sudden load peaks at
//!   2 m g; the scheme damps a free vibration by |lambda| = (1 + (w dt)^2/2)^(-1/2) a step
//!   (det of its amplification matrix, math note §10.14), so the first peak, half a period
//!   (pi / (w dt) steps) after the start, is m g (1 + (1 + (w dt)^2/2)^(-pi/(2 w dt))), to the
//!   sampling of the peak by the steps (relative (w dt)^2/8 = 5e-6 here, so 1e-4 is asserted).
//!   The bolt's force history is also the scheme's own recurrence for this one DOF (bolt stiffness
//!   EA/l at the step start, force from the true length after it, math note §10.7) to 1e-9;
//! - a gravity ramp over t_r: the undamped response to a linear ramp overshoots the static force
//!   by at most m g / (w t_r / 2) = 0.63 % here (Duhamel's integral), and the scheme's damping only
//!   lowers it: within 1 % of m g;
//! - a bolt installed at a stage on a block that a joint's cohesion held: after the cohesion is
//!   set to 0, the static stage ends in limit equilibrium along the slope, N = W (sin a - cos a
//!   tan phi) for a bolt parallel to it (the slope is the floor, gravity tilted by a); static
//!   relaxation approaches it geometrically (factor 2m / (2m + k dt^2) = 0.1 a step here), so
//!   1e-6 relative after 100 steps is reached with a margin of orders;
//! - until_kinetic: the step a stage ends at is the first step n with the kinetic energy per unit
//!   mass on the mean velocity d/dt of steps n-9..n all below the threshold, computed here from
//!   bodies.csv's positions (x, y, rotation) independently of the code's own sum.

use crate::common;
use common::body;
use pbdda::scene::parse;
use pbdda::world::World;
use std::path::{Path, PathBuf};
use std::process::Command;

fn world(text: &str) -> World {
    World::new(parse(text, "stages.toml").unwrap_or_else(|e| panic!("{e}")))
}

const REMOVAL: &str = r#"
[scene]
name = "removal"
[time]
step = 0.01
[physics]
gravity = [0.0, -9.81]
[[material]]
name = "rock"
density = 2000.0
[[interface]]
friction = 0.5
[[body]]
name = "support"
shape = "polygon"
vertices = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
material = "rock"
fixed = true
[[body]]
name = "top"
shape = "polygon"
vertices = [[0.0, 1.0], [1.0, 1.0], [1.0, 2.0], [0.0, 2.0]]
material = "rock"
[[stage]]
name = "rest"
end = 0.1
velocity_carry = 0.0
[[stage]]
name = "fall"
end = 0.3
velocity_carry = 1.0
remove = ["support"]
"#;

/// The upper block rests on the support in the static stage, then falls freely from the
/// instant the support is removed: y(t) - y0 = -g t^2/2 to 1e-9 m.
#[test]
fn a_block_falls_freely_once_its_support_is_removed() {
    let mut w = world(REMOVAL);
    let top = body(&w, "top");
    let g = 9.81;
    // (time, y) at the end of the resting stage: where the fall starts
    let mut start = (0.0, 1.5);
    let mut steps = 0;
    while !w.finished() {
        let rec = w.step().unwrap_or_else(|e| panic!("{e}"));
        steps += 1;
        let y = w.bodies[top].centroid.y;
        match w.stage_name() {
            Some("rest") => {
                assert!((y - 1.5).abs() < 1e-9, "step {}: y = {y} while resting", rec.step);
                start = (rec.time, y);
            }
            Some("fall") => {
                let t = rec.time - start.0;
                let fallen = y - start.1;
                assert!((fallen + g * t * t / 2.0).abs() < 1e-9, "t = {t}: y - y0 = {fallen}");
            }
            other => panic!("unexpected stage {other:?}"),
        }
    }
    assert_eq!(steps, 30);
    assert!((start.0 - 0.1).abs() < 1e-12, "the fall starts at t = {}", start.0);
    assert!(w.is_removed(body(&w, "support")));
}

/// A 1 m x 1 m block of 1000 kg hung at its centroid by a 2 m vertical bolt (EA = 8e8 N, k =
/// EA/L = 4e8 N/m, w = sqrt(k/m) = 632.5 rad/s) from a fixed roof, `extra` appended.
fn hung(step: f64, end: f64, extra: &str) -> String {
    format!(
        r#"
[scene]
name = "hung"
[time]
step = {step}
end = {end}
[physics]
gravity = [0.0, -9.81]
{extra}
[[material]]
name = "rock"
density = 1000.0
[[body]]
name = "roof"
shape = "polygon"
vertices = [[-1.0, 2.0], [1.0, 2.0], [1.0, 3.0], [-1.0, 3.0]]
material = "rock"
fixed = true
[[body]]
name = "block"
shape = "polygon"
vertices = [[-0.5, 0.0], [0.5, 0.0], [0.5, 1.0], [-0.5, 1.0]]
material = "rock"
[[connector]]
name = "bolt"
kind = "bolt"
points = [[0.0, 2.5], [0.0, 0.5]]
young = 2.0e11
area = 4.0e-3
"#
    )
}

const M: f64 = 1000.0;
const G: f64 = 9.81;
const EA: f64 = 8.0e8;
const L: f64 = 2.0;

/// The bolt's force at every step of a run to its end.
fn bolt_forces(text: &str) -> Vec<f64> {
    let mut w = world(text);
    let mut forces = Vec::new();
    while !w.finished() {
        w.step().unwrap_or_else(|e| panic!("{e}"));
        forces.push(w.connectors[0].axial_force());
    }
    forces
}

/// The scheme's recurrence for the hung block (one DOF, x down from the unstressed position):
/// m (2/dt^2)(x1 - x0 - dt v0) + (EA/l0)(x1 - x0) = m g - N0 with l0 = L + x0 (math note §1.1,
/// §6), N1 = EA x1 / L from the true length (§10.7), v1 = 2 (x1 - x0)/dt - v0.
fn recurrence(dt: f64, steps: usize) -> Vec<f64> {
    let (mut x, mut v, mut n) = (0.0f64, 0.0f64, 0.0f64);
    let mut out = Vec::new();
    for _ in 0..steps {
        let k = EA / (L + x);
        let a = 2.0 * M / (dt * dt);
        let d = (a * dt * v + M * G - n) / (a + k);
        v = 2.0 * d / dt - v;
        x += d;
        n = EA * x / L;
        out.push(n);
    }
    out
}

#[test]
fn a_sudden_load_peaks_at_about_twice_the_static_force() {
    let dt = 1e-5;
    let forces = bolt_forces(&hung(dt, 0.012, ""));
    let expected = recurrence(dt, forces.len());
    for (i, (f, e)) in forces.iter().zip(&expected).enumerate() {
        assert!((f - e).abs() <= 1e-9 * M * G, "step {}: {f} against the recurrence's {e}", i + 1);
    }
    let peak = forces.iter().copied().fold(0.0, f64::max);
    let w_dt = (EA / L / M).sqrt() * dt;
    let decay = (1.0 + w_dt * w_dt / 2.0).powf(-std::f64::consts::PI / (2.0 * w_dt));
    let ratio = peak / (M * G);
    assert!((ratio - (1.0 + decay)).abs() < 1e-4, "peak {ratio} m g, closed form {}", 1.0 + decay);
    assert!(ratio > 1.99 && ratio < 2.0, "peak {ratio} m g");
}

#[test]
fn gravity_ramped_over_half_a_second_peaks_within_one_percent_of_the_static_force() {
    let ramp = "gravity_history = [[0.0, 0.0], [0.5, 1.0]]";
    let forces = bolt_forces(&hung(1e-3, 0.6, ramp));
    assert_eq!(forces.len(), 600);
    let peak = forces.iter().copied().fold(0.0, f64::max);
    assert!((peak / (M * G) - 1.0).abs() < 0.01, "peak {} m g", peak / (M * G));
    // the ramp itself: at t = 0.25 s, half the weight (to the same 1 %)
    assert!((forces[249] / (0.5 * M * G) - 1.0).abs() < 0.01, "{} at t = 0.25", forces[249]);
}

/// The slope is the floor, gravity tilted by a = 30 degrees (down-slope is +x); phi = 20
/// degrees; a 1 m x 1 m block of 1000 kg; the bolt is horizontal (parallel to the slope) from a
/// post up-slope to the block, EA = 2e8 N over 1.25 m (k dt^2 = 1.6e4 against 2m = 2e3).
const INCLINE: &str = r#"
[scene]
name = "incline"
[time]
step = 0.01
[physics]
gravity = [4.905, -8.495709211]
velocity_carry = 0.0
[[material]]
name = "rock"
density = 1000.0
[[interface]]
friction_angle = 20.0
cohesion = 1.0e4
[[body]]
name = "floor"
shape = "polygon"
vertices = [[-3.0, -1.0], [3.0, -1.0], [3.0, 0.0], [-3.0, 0.0]]
material = "rock"
fixed = true
[[body]]
name = "post"
shape = "polygon"
vertices = [[-2.0, 0.0], [-1.0, 0.0], [-1.0, 1.0], [-2.0, 1.0]]
material = "rock"
fixed = true
[[body]]
name = "block"
shape = "polygon"
vertices = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
material = "rock"
[[connector]]
name = "bolt"
kind = "bolt"
points = [[-1.0, 0.5], [0.25, 0.5]]
young = 2.0e11
area = 1.0e-3
stage = "support"
[[stage]]
name = "hold"
end = 0.5
[[stage]]
name = "support"
end = 1.5
set = ["interface[0].cohesion=0.0"]
"#;

#[test]
fn a_bolt_installed_at_a_stage_takes_the_limit_equilibrium_force() {
    let mut w = world(INCLINE);
    let block = body(&w, "block");
    let g = w.model.physics.gravity;
    let (weight, a) = (M * g.norm(), g.x.atan2(-g.y));
    let phi = 20f64.to_radians();
    let limit = weight * (a.sin() - a.cos() * phi.tan());
    let mut last_x = w.bodies[block].centroid.x;
    let mut step_change = f64::INFINITY;
    while !w.finished() {
        let rec = w.step().unwrap_or_else(|e| panic!("{e}"));
        let x = w.bodies[block].centroid.x;
        step_change = (x - last_x).abs();
        last_x = x;
        if w.stage_name() == Some("hold") {
            // held by cohesion; the bolt is not in being and carries nothing
            assert!((x - 0.5).abs() < 1e-9, "step {}: x = {x}", rec.step);
            assert!(w.stage.pending[0] && w.connectors[0].axial_force() == 0.0);
        }
    }
    assert_eq!(w.step_index, 150);
    let n = w.connectors[0].axial_force();
    assert!((n / limit - 1.0).abs() < 1e-6, "bolt {n} N, limit equilibrium {limit} N");
    assert!(step_change < 1e-9, "the block still creeps {step_change} m a step");
}

/// A block sliding on a flat floor from 1 m/s with friction 0.5 stops after v/(mu g) = 0.204 s;
/// the stage `slide` ends once it has been at rest for 10 steps; `late`'s threshold is below
/// anything a sliding block reaches before its end.
fn sliding(until: &str) -> String {
    format!(
        r#"
[scene]
name = "sliding"
[time]
step = 0.01
[physics]
gravity = [0.0, -9.81]
[[material]]
name = "rock"
density = 1000.0
[[interface]]
friction = 0.5
[[body]]
name = "floor"
shape = "polygon"
vertices = [[-1.0, -1.0], [5.0, -1.0], [5.0, 0.0], [-1.0, 0.0]]
material = "rock"
fixed = true
[[body]]
name = "block"
shape = "polygon"
vertices = [[0.0, 0.0], [1.0, 0.0], [1.0, 0.5], [0.0, 0.5]]
material = "rock"
velocity = [1.0, 0.0]
[[stage]]
name = "slide"
end = 0.6
{until}
[[stage]]
name = "after"
end = 0.8
[output]
vtk = false
"#
    )
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("pbdda-stages-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

fn run_cli(scene: &Path, out: &Path, extra: &[&str]) -> bool {
    let status = Command::new(env!("CARGO_BIN_EXE_pbdda"))
        .args(["run", "-q", "--overwrite"])
        .arg(scene)
        .arg("--out")
        .arg(out)
        .args(extra)
        .status()
        .expect("pbdda run");
    status.success()
}

/// Column `name` of a CSV file, rows as strings.
fn column(path: &Path, name: &str) -> Vec<String> {
    let text = std::fs::read_to_string(path).expect("csv");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    let i = header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("no column {name}"));
    lines.map(|l| l.split(',').nth(i).expect("field").to_owned()).collect()
}

/// The kinetic energy per unit mass on d/dt of the block, step by step, from bodies.csv.
fn mean_kinetic_from_bodies(path: &Path, dt: f64) -> Vec<f64> {
    let num = |c: &str| column(path, c).iter().map(|s| s.parse::<f64>().expect("number")).collect::<Vec<_>>();
    let names = column(path, "body");
    let (x, y, r) = (num("x"), num("y"), num("rotation"));
    let rows: Vec<usize> = (0..names.len()).filter(|&i| names[i] == "block").collect();
    // I / m of a 1 x 0.5 rectangle about its centroid: (1 + 0.25) / 12
    let i_m = 1.25 / 12.0;
    let mut prev = (0.5, 0.25, 0.0);
    rows.iter()
        .map(|&i| {
            let (dx, dy, dr) = (x[i] - prev.0, y[i] - prev.1, r[i] - prev.2);
            prev = (x[i], y[i], r[i]);
            0.5 * (dx * dx + dy * dy + i_m * dr * dr) / (dt * dt)
        })
        .collect()
}

#[test]
fn until_kinetic_ends_a_stage_at_the_tenth_quiet_step() {
    let dir = scratch("quiet");
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, sliding("until_kinetic = 1e-6")).expect("scene");
    let out = dir.join("out");
    assert!(run_cli(&scene, &out, &[]));
    let stages = column(&out.join("steps.csv"), "stage");
    let energy = mean_kinetic_from_bodies(&out.join("bodies.csv"), 0.01);
    let first_quiet =
        (9..energy.len()).find(|&n| energy[n - 9..=n].iter().all(|&e| e < 1e-6)).expect("quiet");
    // steps are 1-based: step first_quiet + 1 is the stage's last
    let last_slide = stages.iter().rposition(|s| s == "slide").expect("slide rows") + 1;
    assert_eq!(last_slide, first_quiet + 1);
    assert!(last_slide < 60, "ended early: {last_slide}");
    // the run goes on to the next stage's end: 80 steps in all
    assert_eq!(stages.len(), 80);
    assert!(stages[last_slide..].iter().all(|s| s == "after"));
    let log = std::fs::read_to_string(out.join("run.log")).expect("run.log");
    assert!(
        log.contains(&format!("step {last_slide}: stage \"slide\" ended"))
            && log.contains("until_kinetic met")
    );
    assert!(log.contains(&format!("step {}: stage \"after\" starts", last_slide + 1)), "{log}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn an_unmet_until_kinetic_ends_the_stage_at_its_end_with_a_note() {
    let dir = scratch("unmet");
    let scene = dir.join("scene.toml");
    // the block slides until 0.204 s: never quiet before 0.1 s
    let text = sliding("until_kinetic = 1e-6").replace("end = 0.6", "end = 0.1");
    std::fs::write(&scene, text).expect("scene");
    let out = dir.join("out");
    assert!(run_cli(&scene, &out, &[]));
    let stages = column(&out.join("steps.csv"), "stage");
    assert_eq!(stages.iter().filter(|s| *s == "slide").count(), 10);
    let log = std::fs::read_to_string(out.join("run.log")).expect("run.log");
    assert!(
        log.contains("step 10: stage \"slide\" ended at t = 0.1: its end time; until_kinetic = 0.000001"),
        "{log}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A staged run with a removal and a bolt installed at a stage, resumed from a checkpoint at
/// step 70 (in its second stage), writes the same bytes as one that ran through (steps.csv but
/// its wall time). The interrupted run is made exactly: a finished run's folder with the
/// checkpoint `--checkpoint-every 35` writes at step 70 (the state of a world stepped 70 times);
/// `resume` cuts every CSV back to step 70, loads the state and goes on.
#[test]
fn a_resumed_staged_run_writes_the_same_bytes() {
    let dir = scratch("resume");
    let scene = dir.join("scene.toml");
    let loose = "[[body]]\nname = \"loose\"\nshape = \"polygon\"\nvertices = [[2.0, 0.0], [2.5, 0.0], [2.5, 0.5], [2.0, 0.5]]\nmaterial = \"rock\"\n";
    let text = INCLINE
        .replace("end = 1.5", "end = 1.5\nremove = [\"loose\"]")
        .replace("[[connector]]", &format!("{loose}[[connector]]"))
        + "[output]\nvtk = false\n";
    std::fs::write(&scene, &text).expect("scene");
    let (whole, cut) = (dir.join("whole"), dir.join("cut"));
    assert!(run_cli(&scene, &whole, &[]));
    assert!(run_cli(&scene, &cut, &[]));
    let mut world = World::new(pbdda::scene::load(&scene).expect("scene"));
    for _ in 0..70 {
        world.step().expect("step");
    }
    let mut checkpoint = pbdda::checkpoint::Checkpoint::new(&scene.display().to_string(), text, vec![], 35);
    checkpoint.save(&cut, &world).expect("checkpoint");
    assert_eq!((checkpoint.step, checkpoint.stage.as_deref()), (70, Some("support")));
    let status = Command::new(env!("CARGO_BIN_EXE_pbdda")).args(["resume", "-q"]).arg(&cut).status().unwrap();
    assert!(status.success());
    for file in ["bodies.csv", "contacts.csv", "monitors.csv", "connectors.csv"] {
        let (a, b) = (std::fs::read(whole.join(file)).unwrap(), std::fs::read(cut.join(file)).unwrap());
        assert!(a == b, "{file} differs after resume");
    }
    // value for value: the width of the wall-time column moves the row layout (scene-format.md)
    let without_wall = |p: &Path| -> Vec<Vec<String>> {
        let text = std::fs::read_to_string(p).unwrap();
        let value = |f: &str| f.parse::<f64>().map_or(f.to_owned(), |x| format!("{x:e}"));
        text.lines().map(|l| l.rsplit_once(',').unwrap().0.split(',').map(value).collect()).collect()
    };
    let (a, b) = (without_wall(&whole.join("steps.csv")), without_wall(&cut.join("steps.csv")));
    assert_eq!(a.len(), 151);
    assert!(a == b, "steps.csv differs after resume");
    // the removed block is in bodies.csv up to step 50 only (the hold stage's 50 steps)
    let bodies = std::fs::read_to_string(whole.join("bodies.csv")).unwrap();
    assert_eq!(bodies.lines().filter(|l| l.contains(",loose,")).count(), 50);
    assert_eq!(column(&whole.join("connectors.csv"), "step").first().map(String::as_str), Some("51"));
    std::fs::remove_dir_all(&dir).ok();
}

/// The scene reader's stages: ends in steps (ceil(end / dt)), the run's steps from the last
/// stage, the bolt installed at stage 2, and `set` entries cumulative (stage 3's friction change
/// keeps stage 2's cohesion of 0), each stage's carry in its physics. Expected values are the
/// literals of the scene text (mu = tan 20 deg and tan 30 deg to 1e-15).
#[test]
fn stages_read_with_cumulative_settings() {
    let text = INCLINE.to_owned()
        + "[[stage]]\nname = \"shake\"\nend = 2.0\nvelocity_carry = 1.0\nset = [\"interface[0].friction_angle=30.0\", \"physics.gravity_history=[[1.5, 1.0], [2.0, 2.0]]\"]\n";
    let m = parse(&text, "stages.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(m.time.steps, 200);
    let ends: Vec<usize> = m.stages.iter().map(|s| s.end_step).collect();
    assert_eq!(ends, [50, 150, 200]);
    assert_eq!(m.stages[1].connectors, [0]);
    assert!(m.stages[0].connectors.is_empty() && m.stages[2].connectors.is_empty());
    let cohesion: Vec<f64> = m.stages.iter().map(|s| s.settings.interfaces[0].cohesion).collect();
    assert_eq!(cohesion, [1.0e4, 0.0, 0.0]);
    let mu = |s: usize| m.stages[s].settings.interfaces[0].friction;
    assert!(
        (mu(1) - 20f64.to_radians().tan()).abs() < 1e-15 && (mu(2) - 30f64.to_radians().tan()).abs() < 1e-15
    );
    let carry: Vec<f64> = m.stages.iter().map(|s| s.settings.physics.velocity_carry).collect();
    assert_eq!(carry, [0.0, 0.0, 1.0]);
    assert_eq!(m.stages[2].settings.gravity_history.as_deref(), Some(&[(1.5, 1.0), (2.0, 2.0)][..]));
    assert_eq!(m.stages[1].settings.gravity_history, None);
}

/// `[time] steps` (or `--set time.steps=N`) may end a staged run before its last stage: the
/// run stops after exactly N steps, in the stage those steps reach (here 60 steps: the 50 of
/// "hold", then 10 of "support"); ending after the last stage is an error
/// (tests/bad_inputs/time_end_not_last_stage.toml).
#[test]
fn a_run_may_stop_before_its_last_stage() {
    let ov = pbdda::scene::Override::parse("time.steps=60").expect("override");
    let m = pbdda::scene::parse_with(INCLINE, "stages.toml", &[ov]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((m.time.steps, m.stages[1].end_step), (60, 150));
    let mut w = World::new(m);
    let mut steps = 0;
    while !w.finished() {
        w.step().unwrap_or_else(|e| panic!("{e}"));
        steps += 1;
    }
    assert_eq!(steps, 60);
    assert_eq!(w.stage_name(), Some("support"));
}
