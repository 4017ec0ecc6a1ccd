//! Scene reader (`pbdda::scene`) against the scene-format contract, version 1: a full valid
//! scene gives the expected `Model` field by field, and every rejection rule of the contract
//! fails with the right line (1-based, counted in the test's own text) and key path.
//! Expected values are the literals of the scene text; μ = tan 45° = 1 within 1e-15 (two
//! roundings: the degree-to-radian conversion and tan).

use pbdda::geometry::Vec2;
use pbdda::model::{BodyModel, Model, Plane, Shape};
use pbdda::scene::{SceneError, load, parse};
use proptest::prelude::*;

/// A valid scene using every supported table and key.
const FULL: &str = r#"[scene]
name = "full"

[time]
step = 0.001
steps = 100

[physics]
gravity = [0.0, -10.0]
plane = "strain"
velocity_carry = 0.5

[contact]
threshold = 0.05

[solver]
tolerance = 1e-10
max_iterations = 5000

[[material]]
name = "rock"
density = 2500
young = 1.0e10
poisson = 0.25

[[material]]
name = "steel"
density = 7800.0

[[interface]]
friction = 0.3
cohesion = 1.0
tensile_strength = 2.0
rolling = 0.01

[[interface]]
materials = ["steel", "rock"]
friction_angle = 45.0

[[body]]
name = "d1"
shape = "disk"
center = [0.0, 10.0]
radius = 10
material = "rock"
velocity = [1.0, -2.0]
angular_velocity = 0.5

[[body]]
name = "r1"
shape = "ring"
center = [30.0, 10.0]
radius = 5.0
inner_radius = 4.0
material = "steel"
model = "rigid"

[[body]]
name = "floor"
shape = "polygon"
vertices = [[0.0, 0.0], [2.0, 0.0], [2.0, -0.5], [1.0, -0.5], [1.0, -1.0], [0.0, -1.0]]
material = "rock"
fixed = true

[[load]]
body = "d1"
point = [0.0, 10.0]
force = [1000.0, 0.0]
history = [[0.0, 1.0], [1.0, 0.0]]

[[load]]
body = "r1"
point = [30.0, 15.0]
force = [0.0, -5.0]

[[monitor]]
name = "O"
body = "d1"
point = [0.0, 10.0]

[output]
every = 10
"#;

/// The smallest valid scene; the line numbers of the tests in the modules refer to it.
const MINIMAL: &str = r#"[scene]
name = "t"
[time]
step = 0.001
steps = 10
[[material]]
name = "rock"
density = 2500.0
[[body]]
name = "d1"
shape = "disk"
center = [0.0, 0.0]
radius = 1.0
material = "rock"
"#;

fn v(x: f64, y: f64) -> Vec2 {
    Vec2::new(x, y)
}

fn ok(source: &str) -> Model {
    parse(source, "scene.toml").unwrap_or_else(|e| panic!("should parse, got: {e}"))
}

fn rejected(source: &str) -> SceneError {
    match parse(source, "scene.toml") {
        Ok(_) => panic!("should be rejected:\n{source}"),
        Err(e) => e,
    }
}

/// MINIMAL with its 1-based `line` replaced by `text` (which may hold several lines).
fn edit(line: usize, text: &str) -> String {
    let mut lines: Vec<&str> = MINIMAL.lines().collect();
    lines[line - 1] = text;
    lines.join("\n") + "\n"
}

/// MINIMAL followed by `text`, whose first line is line 15.
fn append(text: &str) -> String {
    format!("{MINIMAL}{text}")
}

/// `expected` is "LINE KEY: WORDS": the error is on LINE (1-based), its key path is KEY, its
/// message contains WORDS, and its Display starts with `scene.toml:LINE:`.
#[track_caller]
fn fails(source: &str, expected: &str) {
    let e = rejected(source);
    let (place, words) = expected.split_once(": ").unwrap_or((expected, ""));
    let got = format!("{} {}", e.line, e.key);
    assert_eq!(got, place, "{e}");
    assert!(e.message.contains(words), "{e}\nlacks {words:?}");
    assert!(e.to_string().starts_with(&format!("scene.toml:{}:", e.line)), "{e}");
}

/// A second body after MINIMAL: `[[body]]` is line 15, its name line 16, shape line 17,
/// material line 18, and `extra` starts on line 19.
fn second_body(shape: &str, extra: &str) -> String {
    append(&format!("[[body]]\nname = \"b2\"\nshape = \"{shape}\"\nmaterial = \"rock\"\n{extra}"))
}

/// A polygon as the second body: `vertices` is line 19.
fn polygon(vertices: &str) -> String {
    second_body("polygon", &format!("vertices = {vertices}\n"))
}

/// A ring as the second body: `center` line 19, `radius` line 20, `inner_radius` line 21.
fn ring(radius: &str, inner_radius: &str) -> String {
    let keys = format!("center = [5.0, 0.0]\nradius = {radius}\ninner_radius = {inner_radius}\n");
    second_body("ring", &keys)
}

/// An interface after MINIMAL: `[[interface]]` is line 15, `keys` start on line 16.
fn interface(keys: &str) -> String {
    append(&format!("[[interface]]\n{keys}"))
}

/// A load on `body` after MINIMAL: `[[load]]` line 15, `body` line 16, `history` line 19.
fn load_on(body: &str, history: &str) -> String {
    append(&format!("[[load]]\nbody = \"{body}\"\npoint = [0, 0]\nforce = [1, 0]\n{history}"))
}

/// A monitor table (4 lines: header, name, body, point).
fn monitor(name: &str, body: &str) -> String {
    format!("[[monitor]]\nname = \"{name}\"\nbody = \"{body}\"\npoint = [0, 0]\n")
}

/// MINIMAL's body with `key_value` added after its last line (so on line 15).
fn body_with(key_value: &str) -> String {
    edit(14, &format!("material = \"rock\"\n{key_value}"))
}

mod bodies;
mod loads;
mod rules;
mod valid;
