//! Helpers shared by the paper-example tests.
#![allow(dead_code)]

use pbdda::model::Model;
use pbdda::world::{ContactRecord, StepRecord, World};
use std::path::Path;

pub mod disk_7_7;
pub mod scenes;

/// Loads `examples/NAME` through the scene reader, as a user's run would.
pub fn example(name: &str) -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples").join(name);
    match pbdda::scene::load(&path) {
        Ok(m) => m,
        Err(e) => panic!("example {name} does not load: {e}"),
    }
}

pub fn body(world: &World, name: &str) -> usize {
    world.bodies.iter().position(|b| b.name == name).unwrap_or_else(|| panic!("no body {name}"))
}

/// Contacts of the step between the named bodies (either order).
pub fn between<'a>(world: &World, rec: &'a StepRecord, a: &str, b: &str) -> Vec<&'a ContactRecord> {
    let (ia, ib) = (body(world, a), body(world, b));
    rec.contacts
        .iter()
        .filter(|c| (c.body_a == ia && c.body_b == ib) || (c.body_a == ib && c.body_b == ia))
        .collect()
}

/// Runs `steps` steps, handing every record to `check`.
pub fn run(world: &mut World, steps: usize, mut check: impl FnMut(&World, &StepRecord)) {
    for _ in 0..steps {
        let rec = world.step().unwrap_or_else(|e| panic!("{e}"));
        check(world, &rec);
    }
}

/// The step met the solver's tolerance (the scene's, `tolerance`).
pub fn assert_converged(rec: &StepRecord, tolerance: f64) {
    let (step, res, its) = (rec.step, rec.residual, rec.inner_iterations);
    assert!(rec.converged && res <= tolerance, "step {step}: {res} after {its}");
}

/// The triangle wave of math note §7.3: position of a point moving at unit rate `s` in
/// [-a, a] with elastic reflections.
pub fn fold(s: f64, a: f64) -> f64 {
    let sp = (s + a).rem_euclid(4.0 * a);
    if sp < 2.0 * a { sp - a } else { 3.0 * a - sp }
}

/// Number of reflections of the triangle wave `fold(v t, a)` (see [`fold`]) in the run time
/// `t_end`: the point starts at 0 and meets a wall (±a) at v t = a, 3a, 5a, ..., so the
/// count is the number of k >= 0 with (2k + 1) a < v t_end. Panics when a reflection falls
/// within `dt` of the end of the run, where the count would hinge on rounding.
pub fn reflections(v: f64, a: f64, t_end: f64, dt: f64) -> usize {
    let s = v * t_end;
    if s < a {
        assert!(a - s > v * dt, "a reflection at the very end of the run");
        return 0;
    }
    let since = (s - a).rem_euclid(2.0 * a);
    assert!(
        since > v * dt && 2.0 * a - since > v * dt,
        "a reflection within one step of the end of the run (v = {v}, a = {a}, t = {t_end})"
    );
    ((s - a) / (2.0 * a)).floor() as usize + 1
}

/// Counts the sign reversals of the velocity components (vx, vy) of one body from step to
/// step: in a frictionless frame each reversal of vx is a hit on a side wall, of vy on the
/// floor or roof.
#[derive(Debug, Default)]
pub struct WallHits {
    last: Option<(f64, f64)>,
    pub x: usize,
    pub y: usize,
}

impl WallHits {
    pub fn starting_at(vx: f64, vy: f64) -> Self {
        WallHits { last: Some((vx, vy)), x: 0, y: 0 }
    }

    pub fn observe(&mut self, vx: f64, vy: f64) {
        if let Some((px, py)) = self.last {
            self.x += usize::from(px * vx < 0.0);
            self.y += usize::from(py * vy < 0.0);
        }
        self.last = Some((vx, vy));
    }
}

/// A number of meshes/reference.json (written by meshes/reference.py, scikit-fem): the value of
/// the last of `keys`, each looked up after the one before (`["cantilever_1.msh", "tip_uy"]`).
pub fn reference(keys: &[&str]) -> f64 {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/reference.json");
    let text = std::fs::read_to_string(path).expect("reference.json");
    let mut at = 0;
    for key in keys {
        let quoted = format!("\"{key}\":");
        at += text[at..].find(&quoted).unwrap_or_else(|| panic!("{key} in reference.json")) + quoted.len();
    }
    let v = &text[at..];
    v[..v.find(['\n', ',', '}']).expect("end of number")].trim().parse().expect("a number")
}

/// Tip deflection and rotation of a Timoshenko cantilever of length `l` under a tip load `p`
/// (a beam connector's defaults: shear modulus E/(2(1 + 0.3)), shear factor 1.2):
/// `p l³/(3EI) + 1.2 p l/(GA)` and `p l²/(2EI)`.
pub fn timoshenko_tip(e: f64, area: f64, inertia: f64, p: f64, l: f64) -> (f64, f64) {
    let g = e / (2.0 * 1.3);
    (p * l.powi(3) / (3.0 * e * inertia) + 1.2 * p * l / (g * area), p * l * l / (2.0 * e * inertia))
}

/// A CLI error report as one line: miette wraps long messages at 80 columns and draws a margin
/// (`│`), wherever the message's paths put the breaks.
pub fn one_line(text: &str) -> String {
    text.replace('│', " ").split_whitespace().collect::<Vec<_>>().join(" ")
}
