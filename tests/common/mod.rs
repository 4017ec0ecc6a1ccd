//! Helpers shared by the paper-example tests.
#![allow(dead_code)]

use pbdda::model::Model;
use pbdda::world::{ContactRecord, StepRecord, World};
use std::path::Path;

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

/// The triangle wave of design note §7.3: position of a point moving at unit rate `s` in
/// [-a, a] with elastic reflections.
pub fn fold(s: f64, a: f64) -> f64 {
    let sp = (s + a).rem_euclid(4.0 * a);
    if sp < 2.0 * a { sp - a } else { 3.0 * a - sp }
}
