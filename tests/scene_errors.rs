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

/// The smallest valid scene; line numbers of the tests below refer to it.
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

// ------------------------------------------------------------------ valid scenes

#[test]
fn full_scene_gives_expected_model() {
    let m = ok(FULL);
    assert_eq!(m.name, "full");
    assert_eq!((m.time.step, m.time.steps), (0.001, 100));
    assert_eq!(m.physics.gravity, v(0.0, -10.0));
    assert_eq!(m.physics.plane, Plane::Strain);
    assert_eq!(m.physics.velocity_carry, 0.5);
    assert_eq!(m.contact.threshold, Some(0.05));
    assert_eq!((m.solver.tolerance, m.solver.max_iterations), (1e-10, 5000));
    assert_eq!(m.output.every, 10);

    assert_eq!(m.materials.len(), 2);
    let rock = &m.materials[0];
    assert_eq!((rock.name.as_str(), rock.density), ("rock", 2500.0));
    assert_eq!((rock.young, rock.poisson), (Some(1.0e10), Some(0.25)));
    let steel = &m.materials[1];
    assert_eq!((steel.name.as_str(), steel.density), ("steel", 7800.0));
    assert_eq!((steel.young, steel.poisson), (None, None));

    assert_eq!(m.interfaces.len(), 2);
    let default = &m.interfaces[0];
    assert_eq!(default.materials, None);
    assert_eq!((default.friction, default.cohesion), (0.3, 1.0));
    assert_eq!((default.tensile_strength, default.rolling), (2.0, 0.01));
    let pair = &m.interfaces[1];
    assert_eq!(pair.materials, Some([1, 0]));
    assert!((pair.friction - 1.0).abs() < 1e-15, "tan 45° = {}", pair.friction);
    assert_eq!((pair.cohesion, pair.tensile_strength, pair.rolling), (0.0, 0.0, 0.0));
}

#[test]
fn full_scene_bodies_loads_monitors() {
    let m = ok(FULL);
    assert_eq!(m.bodies.len(), 3);
    let d1 = &m.bodies[0];
    assert_eq!(d1.name, "d1");
    assert_eq!(d1.shape, Shape::Disk { center: v(0.0, 10.0), radius: 10.0 });
    assert_eq!((d1.model, d1.material, d1.fixed), (BodyModel::Rigid, 0, false));
    assert_eq!((d1.velocity, d1.angular_velocity), (v(1.0, -2.0), 0.5));
    assert_eq!(d1.initial_stress, None);

    let r1 = &m.bodies[1];
    assert_eq!(r1.shape, Shape::Ring { center: v(30.0, 10.0), outer: 5.0, inner: 4.0 });
    assert_eq!((r1.model, r1.material, r1.fixed), (BodyModel::Rigid, 1, false));
    assert_eq!((r1.velocity, r1.angular_velocity), (Vec2::zeros(), 0.0));

    // the concave floor is given clockwise and must come back counter-clockwise
    let floor = &m.bodies[2];
    let ccw = vec![v(0.0, -1.0), v(1.0, -1.0), v(1.0, -0.5), v(2.0, -0.5), v(2.0, 0.0), v(0.0, 0.0)];
    assert_eq!(floor.shape, Shape::Polygon { vertices: ccw });
    assert_eq!((floor.material, floor.fixed), (0, true));

    assert_eq!(m.loads.len(), 2);
    let l = &m.loads[0];
    assert_eq!((l.body, l.point, l.force), (0, v(0.0, 10.0), v(1000.0, 0.0)));
    assert_eq!(l.history, Some(vec![(0.0, 1.0), (1.0, 0.0)]));
    let l = &m.loads[1];
    assert_eq!((l.body, l.point, l.force, l.history.clone()), (1, v(30.0, 15.0), v(0.0, -5.0), None));

    assert_eq!(m.monitors.len(), 1);
    let o = &m.monitors[0];
    assert_eq!((o.name.as_str(), o.body, o.point), ("O", 0, v(0.0, 10.0)));
}

#[test]
fn minimal_scene_gets_the_contract_defaults() {
    let m = ok(MINIMAL);
    assert_eq!((m.physics.gravity, m.physics.plane), (Vec2::zeros(), Plane::Stress));
    assert_eq!(m.physics.velocity_carry, 1.0);
    assert_eq!(m.contact.threshold, None);
    assert_eq!((m.solver.tolerance, m.solver.max_iterations), (1e-8, 200_000));
    assert_eq!(m.output.every, 1);
    assert!(m.interfaces.is_empty() && m.loads.is_empty() && m.monitors.is_empty());
}

#[test]
fn end_gives_the_number_of_steps() {
    // 0.07 / 0.01 = 7.000000000000001 in f64: the 1e-9 tolerance keeps it at 7 steps
    assert_eq!(ok(&edit(5, "end = 0.07").replace("0.001", "0.01")).time.steps, 7);
    // a partial last step is a whole step: 0.0105 / 0.001 -> 11
    assert_eq!(ok(&edit(5, "end = 0.0105")).time.steps, 11);
}

#[test]
fn integer_literals_are_accepted_for_reals() {
    assert_eq!(
        ok(&edit(13, "radius = 2")).bodies[0].shape,
        Shape::Disk { center: Vec2::zeros(), radius: 2.0 }
    );
}

// ------------------------------------------------------------------ generic rules

#[test]
fn unknown_key_in_a_table() {
    fails(&edit(13, "radiuss = 1.0"), "13 body[0].radiuss: unknown key `radiuss`");
}

#[test]
fn unknown_table() {
    fails(&append("[physic]\n"), "15 physic: unknown key `physic`");
}

#[test]
fn wrong_type_string_for_number() {
    fails(&edit(13, "radius = \"big\""), "13 body[0].radius: expected a number");
}

#[test]
fn wrong_type_float_for_integer() {
    fails(&edit(5, "steps = 2.5"), "5 time.steps: expected a whole number");
}

#[test]
fn wrong_type_number_for_array() {
    fails(&edit(12, "center = 3.0"), "12 body[0].center: expected an array");
}

#[test]
fn wrong_type_integer_for_boolean() {
    fails(&body_with("fixed = 1"), "15 body[0].fixed: invalid type");
}

#[test]
fn nan_is_an_error() {
    fails(&edit(13, "radius = nan"), "13 body[0].radius: finite");
}

#[test]
fn infinity_is_an_error() {
    fails(&edit(4, "step = inf"), "4 time.step: finite");
    fails(&edit(12, "center = [0.0, -inf]"), "12 body[0].center: finite");
    fails(&append("[physics]\ngravity = [nan, 0.0]\n"), "16 physics.gravity: finite");
}

#[test]
fn vectors_need_exactly_two_numbers() {
    fails(&edit(12, "center = [0.0, 0.0, 1.0]"), "12 body[0].center: 2 numbers (got 3)");
}

#[test]
fn scene_table_is_required() {
    let source = MINIMAL.replace("[scene]\nname = \"t\"\n", "");
    fails(&source, "1 scene: missing key `scene`");
}

#[test]
fn time_table_is_required() {
    let source = MINIMAL.replace("[time]\nstep = 0.001\nsteps = 10\n", "");
    fails(&source, "1 time: missing key `time`");
}

#[test]
fn a_body_is_required() {
    let no_body = MINIMAL.split("[[body]]").next().unwrap_or_default();
    fails(no_body, "1 body: missing key `body`");
    fails(&format!("body = []\n{no_body}"), "1 body: at least one");
}

#[test]
fn required_keys_are_reported_at_their_table() {
    fails(&edit(4, ""), "3 time.step: missing key `step`");
    fails(&edit(14, ""), "9 body[0].material: missing key `material`");
}

#[test]
fn toml_syntax_errors_name_the_line() {
    let e = rejected(&edit(13, "radius = = 1"));
    assert_eq!((e.line, e.column), (13, 10), "{e}");
    // a TOML-level error has no key path, only the position
    let e = rejected(&edit(13, "radius = 1.0\nradius = 2.0"));
    assert_eq!((e.line, e.column, e.key.as_str()), (14, 1, ""), "{e}");
    assert!(e.message.contains("duplicate key `radius`"), "{e}");
}

// ------------------------------------------------------------------ settings

#[test]
fn step_must_be_positive() {
    fails(&edit(4, "step = 0.0"), "4 time.step: must be positive (got 0)");
}

#[test]
fn steps_must_be_at_least_one() {
    fails(&edit(5, "steps = 0"), "5 time.steps: at least 1 (got 0)");
    fails(&edit(5, "steps = -3"), "5 time.steps: at least 1 (got -3)");
}

#[test]
fn steps_and_end_not_both() {
    fails(&edit(5, "steps = 10\nend = 1.0"), "6 time.end: not both");
}

#[test]
fn steps_or_end_required() {
    fails(&edit(5, ""), "3 time.steps: `steps` or `end`");
}

#[test]
fn end_must_be_positive_and_reach_a_step() {
    fails(&edit(5, "end = -1.0"), "5 time.end: positive");
    fails(&edit(5, "end = 1e-15"), "5 time.end: less than one step");
}

#[test]
fn velocity_carry_in_zero_one() {
    let source = append("[physics]\nvelocity_carry = 1.5\n");
    fails(&source, "16 physics.velocity_carry: between 0 and 1 (got 1.5)");
}

#[test]
fn plane_is_stress_or_strain() {
    let source = append("[physics]\nplane = \"plain\"\n");
    fails(&source, "16 physics.plane: one of \"stress\", \"strain\" (got \"plain\")");
}

#[test]
fn contact_threshold_must_be_positive() {
    fails(&append("[contact]\nthreshold = 0.0\n"), "16 contact.threshold: positive");
}

#[test]
fn solver_tolerance_must_be_positive() {
    fails(&append("[solver]\ntolerance = -1e-8\n"), "16 solver.tolerance: positive");
}

#[test]
fn solver_max_iterations_at_least_one() {
    fails(&append("[solver]\nmax_iterations = 0\n"), "16 solver.max_iterations: at least 1");
}

#[test]
fn output_every_at_least_one() {
    fails(&append("[output]\nevery = 0\n"), "16 output.every: at least 1");
}

// ------------------------------------------------------------------ materials

#[test]
fn density_must_be_positive() {
    fails(&edit(8, "density = 0.0"), "8 material[0].density: positive");
}

#[test]
fn young_must_be_positive() {
    fails(&edit(8, "density = 1.0\nyoung = -5.0"), "9 material[0].young: positive");
}

#[test]
fn poisson_in_zero_to_half() {
    fails(&edit(8, "density = 1.0\npoisson = 0.5"), "9 material[0].poisson: below 0.5");
    fails(&edit(8, "density = 1.0\npoisson = -0.1"), "9 material[0].poisson: at least 0");
}

#[test]
fn duplicate_material_name_names_the_second() {
    let source = append("[[material]]\nname = \"rock\"\ndensity = 1.0\n");
    fails(&source, "16 material[1].name: duplicate material name \"rock\"");
}

// ------------------------------------------------------------------ interfaces

#[test]
fn at_most_one_default_interface() {
    let source = interface("friction = 0.1\n[[interface]]\nfriction = 0.2\n");
    fails(&source, "17 interface[1]: second default");
}

#[test]
fn one_interface_per_unordered_material_pair() {
    let sand = "[[material]]\nname = \"sand\"\ndensity = 1600.0\n"; // lines 15-17
    let pairs = "[[interface]]\nmaterials = [\"rock\", \"sand\"]\n\
                 [[interface]]\nmaterials = [\"sand\", \"rock\"]\n"; // lines 18-21
    fails(&append(&format!("{sand}{pairs}")), "21 interface[1].materials: same pair");
}

#[test]
fn interface_materials_must_exist() {
    let source = interface("materials = [\"rock\", \"clay\"]\n");
    fails(&source, "16 interface[0].materials[1]: unknown material \"clay\"");
}

#[test]
fn interface_materials_are_a_pair() {
    let source = interface("materials = [\"rock\", \"rock\", \"rock\"]\n");
    fails(&source, "16 interface[0].materials: 2 materials (got 3)");
}

#[test]
fn friction_and_friction_angle_not_both() {
    let source = interface("friction = 0.5\nfriction_angle = 30.0\n");
    fails(&source, "17 interface[0].friction_angle: not both");
}

#[test]
fn friction_angle_below_ninety_degrees() {
    fails(&interface("friction_angle = 90.0\n"), "16 interface[0].friction_angle: below 90");
}

#[test]
fn interface_coefficients_not_negative() {
    for key in ["friction", "cohesion", "tensile_strength", "rolling"] {
        let source = interface(&format!("{key} = -1.0\n"));
        fails(&source, &format!("16 interface[0].{key}: must not be negative (got -1)"));
    }
}

// ------------------------------------------------------------------ bodies

#[test]
fn duplicate_body_name_names_the_second() {
    let source = second_body("disk", "center = [5.0, 0.0]\nradius = 1.0\n").replace("b2", "d1");
    fails(&source, "16 body[1].name: duplicate body name \"d1\"");
}

#[test]
fn body_material_must_exist() {
    let source = edit(14, "material = \"granite\"");
    fails(&source, "14 body[0].material: unknown material \"granite\"");
}

#[test]
fn unknown_shape() {
    fails(&edit(11, "shape = \"square\""), "11 body[0].shape: must be one of");
}

#[test]
fn unknown_model() {
    fails(&body_with("model = \"elastic\""), "15 body[0].model: must be one of");
}

#[test]
fn disk_radius_must_be_positive() {
    fails(&edit(13, "radius = -1"), "13 body[0].radius: radius must be positive (got -1)");
}

#[test]
fn disk_needs_radius() {
    fails(&edit(13, ""), "9 body[0].radius: a disk body needs `radius`");
}

#[test]
fn vertices_on_a_disk() {
    let source = edit(13, "radius = 1.0\nvertices = [[0, 0], [1, 0], [0, 1]]");
    fails(&source, "14 body[0].vertices: `vertices` is not used by a disk body");
}

#[test]
fn inner_radius_on_a_disk() {
    let source = edit(13, "radius = 1.0\ninner_radius = 0.5");
    fails(&source, "14 body[0].inner_radius: not used by a disk");
}

#[test]
fn ring_inner_radius_below_radius() {
    assert!(parse(&ring("1.0", "0.5"), "scene.toml").is_ok());
    fails(&ring("1.0", "1.0"), "21 body[1].inner_radius: less than radius");
}

#[test]
fn ring_inner_radius_positive() {
    fails(&ring("1.0", "0.0"), "21 body[1].inner_radius: positive");
}

#[test]
fn ring_needs_inner_radius() {
    let source = second_body("ring", "center = [5.0, 0.0]\nradius = 1.0\n");
    fails(&source, "15 body[1].inner_radius: a ring body needs `inner_radius`");
}

#[test]
fn counter_clockwise_polygon_is_kept() {
    // beside the unit disk at the origin, not inside it
    let kept = ok(&polygon("[[5, 0], [6, 0], [5, 1]]")).bodies[1].shape.clone();
    let ccw = vec![v(5.0, 0.0), v(6.0, 0.0), v(5.0, 1.0)];
    assert_eq!(kept, Shape::Polygon { vertices: ccw });
}

#[test]
fn self_intersecting_polygon() {
    let bow_tie = polygon("[[0, 0], [1, 1], [1, 0], [0, 1]]");
    fails(&bow_tie, "19 body[1].vertices: intersects itself");
    // a flat triangle folds back on itself
    fails(&polygon("[[0, 0], [1, 0], [2, 0]]"), "19 body[1].vertices: intersects itself");
}

#[test]
fn polygon_needs_three_vertices() {
    fails(&polygon("[[0, 0], [1, 0]]"), "19 body[1].vertices: at least 3 vertices (got 2)");
}

#[test]
fn polygon_zero_length_edge() {
    let source = polygon("[[0, 0], [1, 0], [1, 0], [0, 1]]");
    fails(&source, "19 body[1].vertices: zero-length edge vertices[1]-vertices[2]");
}

#[test]
fn polygon_zero_area() {
    // a sliver: simple, edges about 1 long, but twice the area is 7e-13, below the area
    // tolerance of geometry::check_simple_polygon (1e-12 times the squared size)
    let sliver = polygon("[[1, 1], [2, 1], [1.5, 1.0000000000007]]");
    fails(&sliver, "19 body[1].vertices: zero area");
}

#[test]
fn polygon_vertices_are_finite_pairs() {
    let source = polygon("[[0, 0], [1, 0], [1, 1, 1]]");
    fails(&source, "19 body[1].vertices: vertices[2] must have 2 numbers");
    fails(&polygon("[[0, 0], [1, 0], [0, nan]]"), "19 body[1].vertices: finite");
}

#[test]
fn center_on_a_polygon() {
    let source = second_body("polygon", "center = [0, 0]\nvertices = [[0, 0], [1, 0], [0, 1]]\n");
    fails(&source, "19 body[1].center: not used by a polygon");
}

#[test]
fn polygon_needs_vertices() {
    fails(&second_body("polygon", ""), "15 body[1].vertices: needs `vertices`");
}

#[test]
fn initial_stress_only_for_deformable_bodies() {
    let source = body_with("initial_stress = [1.0, 2.0, 0.0]");
    fails(&source, "15 body[0].initial_stress: only for deformable bodies");
}

#[test]
fn velocity_is_a_finite_pair() {
    fails(&body_with("velocity = [1.0]"), "15 body[0].velocity: 2 numbers (got 1)");
    fails(&body_with("angular_velocity = nan"), "15 body[0].angular_velocity: finite");
}

// ------------------------------------------------------------------ not supported yet

// mesh bodies: tests/mesh_scene.rs

#[test]
fn deformable_body_needs_young_and_poisson() {
    // MINIMAL's material "rock" has a density only
    fails(
        &body_with("model = \"deformable\""),
        "15 body[0].model: a deformable body needs `young` and `poisson`",
    );
}

#[test]
fn deformable_body_with_initial_stress_parses() {
    let elastic = edit(8, "density = 2500.0\nyoung = 1.0e9\npoisson = 0.25");
    let source = format!("{elastic}model = \"deformable\"\ninitial_stress = [-1.0, -2.0, 0.5]\n");
    let m = ok(&source);
    assert_eq!(m.bodies[0].model, pbdda::model::BodyModel::Deformable);
    assert_eq!(m.bodies[0].initial_stress, Some([-1.0, -2.0, 0.5]));
    let bad = format!("{elastic}model = \"deformable\"\ninitial_stress = [1.0, nan, 0.0]\n");
    fails(&bad, "18 body[0].initial_stress: finite");
    let bad = format!("{elastic}model = \"elastic\"\n");
    fails(&bad, "17 body[0].model");
}

// ------------------------------------------------------------------ loads and monitors

#[test]
fn load_body_must_exist() {
    assert!(parse(&load_on("d1", ""), "scene.toml").is_ok());
    fails(&load_on("d9", ""), "16 load[0].body: unknown body \"d9\"");
}

#[test]
fn load_history_times_increase_strictly() {
    let equal = load_on("d1", "history = [[0, 1], [0, 2]]\n");
    fails(&equal, "19 load[0].history: history[1] has time 0 after 0");
    let decreasing = load_on("d1", "history = [[1, 1], [0.5, 2]]\n");
    fails(&decreasing, "19 load[0].history: increase strictly");
}

#[test]
fn load_history_is_pairs_at_least_one() {
    fails(&load_on("d1", "history = []\n"), "19 load[0].history: at least one");
    let triple = load_on("d1", "history = [[0, 1, 2]]\n");
    fails(&triple, "19 load[0].history: history[0] must have 2");
}

#[test]
fn monitor_body_must_exist() {
    let source = append(&monitor("O", "nobody"));
    fails(&source, "17 monitor[0].body: unknown body \"nobody\"");
}

#[test]
fn duplicate_monitor_name_names_the_second() {
    let source = append(&(monitor("O", "d1") + &monitor("O", "d1")));
    fails(&source, "20 monitor[1].name: duplicate monitor name \"O\"");
}

// ------------------------------------------------------------------ the error itself

#[test]
fn display_reads_file_line_column_key_message() {
    let e = rejected(&edit(13, "radius = -1"));
    assert_eq!(e.to_string(), "scene.toml:13:1: body[0].radius: radius must be positive (got -1)");
    assert_eq!((e.file.as_str(), e.column), ("scene.toml", 1));
    let e = rejected(&edit(13, "  radius = -1"));
    assert_eq!((e.line, e.column), (13, 3));
}

#[test]
fn diagnostic_points_at_the_offending_line() {
    use miette::{Diagnostic, GraphicalReportHandler, GraphicalTheme};
    let e = rejected(&edit(13, "radius = -1"));
    let labels: Vec<_> = e.labels().into_iter().flatten().collect();
    assert_eq!(labels.len(), 1);
    let offset: usize = MINIMAL.lines().take(12).map(|l| l.len() + 1).sum();
    assert_eq!((labels[0].offset(), labels[0].len()), (offset, "radius = -1".len()));
    let mut out = String::new();
    let handler = GraphicalReportHandler::new_themed(GraphicalTheme::unicode_nocolor());
    handler.render_report(&mut out, &e).expect("render to a String");
    assert!(out.contains("radius = -1") && out.contains("scene.toml:13:1"), "{out}");
}

#[test]
fn load_reads_files_and_names_unreadable_ones() {
    let dir = std::env::temp_dir().join(format!("pbdda-scene-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("scene.toml");
    std::fs::write(&path, MINIMAL).expect("write scene");
    assert_eq!(load(&path).map(|m| m.name).ok().as_deref(), Some("t"));
    std::fs::write(&path, edit(13, "radius = -1")).expect("write scene");
    let e = load(&path).expect_err("rejected");
    assert_eq!((e.file, e.line), (path.display().to_string(), 13));
    let missing = dir.join("missing.toml");
    let e = load(&missing).expect_err("unreadable");
    assert!(e.to_string().starts_with(&format!("{}: cannot read", missing.display())), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

proptest! {
    /// Any prefix of a valid scene, and any insertion into it, parses or fails with a
    /// positioned error; never a panic.
    #[test]
    fn malformed_files_never_panic(cut in 0usize..2000, insert in "[\\[\\]{}=,.\"a-z0-9 \n-]{0,8}") {
        let cut = cut.min(FULL.len());
        let cut = (0..=cut).rev().find(|&i| FULL.is_char_boundary(i)).unwrap_or(0);
        for source in [FULL[..cut].to_owned(), format!("{}{insert}{}", &FULL[..cut], &FULL[cut..])] {
            if let Err(e) = parse(&source, "scene.toml") {
                prop_assert!(e.line >= 1 && e.line <= source.lines().count() + 1, "{}", e);
            }
        }
    }
}

/// Names go unquoted into the CSV outputs (docs/scene-format.md): no commas or quotes.
#[test]
fn names_must_be_csv_safe() {
    fails(&edit(10, "name = \"d,1\""), "10 body[0].name: without commas");
}

// ---------------------------------------------------------------- scenes that cannot run
// (issue 11, point 3): the rule, its line and its key; the numbers are the scene's own.

/// 1e300 s in steps of 1 ms is 1e303 steps, not a saturated 1.8e19; 1e9 steps is the bound,
/// and half a step is not one step.
#[test]
fn step_counts_are_bounded() {
    fails(&edit(5, "end = 1e300"), "5 time.end: is 1e303 steps, more than 1e9");
    fails(&edit(5, "steps = 1000000001"), "5 time.steps: more than 1e9");
    assert_eq!(ok(&edit(5, "steps = 1000000000")).time.steps, 1_000_000_000);
    fails(&edit(5, "end = 0.0005"), "5 time.end: less than one step");
}

/// Radius 1e308 makes the area πr² infinite; 1e-320 makes it zero; a density of 1e-320 makes
/// the mass subnormal; dt = 1e-160 makes 2m/dt² infinite; |g| = 1e307 makes m·g infinite
/// (m = 2500π).
#[test]
fn first_step_magnitudes_must_be_finite_and_normal() {
    fails(&edit(13, "radius = 1e308"), "13 body[0].radius: area");
    fails(&edit(13, "radius = 1e-320"), "13 body[0].radius: underflows");
    fails(&edit(8, "density = 1e-320"), "14 body[0].material: mass");
    fails(&edit(4, "step = 1e-160"), "4 time.step: 2m/dt²");
    fails(&edit(5, "steps = 10\n[physics]\ngravity = [0.0, -1e307]"), "7 physics.gravity: m·g");
}

/// A load on a fixed body would be dropped; a monitor 10 m from a unit disk is a typo.
#[test]
fn loads_and_monitors_must_fit_their_body() {
    let fixed = edit(
        14,
        "material = \"rock\"\nfixed = true\n[[load]]\nbody = \"d1\"\npoint = [0.0, 0.0]\nforce = [1.0, 0.0]",
    );
    fails(&fixed, "17 load[0].body: fixed body \"d1\"");
    let far = append("[[monitor]]\nname = \"m\"\nbody = \"d1\"\npoint = [10.0, 0.0]\n");
    fails(&far, "18 monitor[0].point: outside body \"d1\"");
    // 1 m beyond the rim of a disk of diameter 2 is near enough
    assert_eq!(
        ok(&append("[[monitor]]\nname = \"m\"\nbody = \"d1\"\npoint = [2.0, 0.0]\n")).monitors.len(),
        1
    );
}

/// A small disk inside the unit disk, and a second unit disk at the same place.
#[test]
fn body_inside_another_is_rejected() {
    let inner = second_body("disk", "center = [0.1, 0.0]\nradius = 0.5\n");
    fails(&inner, "19 body[1].center: body \"b2\" lies inside body \"d1\"");
    let twin = second_body("disk", "center = [0.0, 0.0]\nradius = 1.0\n");
    fails(&twin, "19 body[1].center: lies inside body");
    // touching disks are a contact, not an overlap
    assert_eq!(ok(&second_body("disk", "center = [2.0, 0.0]\nradius = 1.0\n")).bodies.len(), 2);
}

/// A byte that is not UTF-8 (Latin-1 'é') on line 2 is reported on line 2.
#[test]
fn utf8_errors_name_the_line() {
    let mut bytes = MINIMAL.replacen("\n", " # caf\u{e9}\n", 2).into_bytes();
    let at = bytes.windows(2).rposition(|w| w == [0xc3, 0xa9]).unwrap();
    bytes.splice(at..at + 2, [0xe9]);
    let e = pbdda::scene::parse_bytes(&bytes, "scene.toml").expect_err("not UTF-8");
    assert_eq!(e.line, 2, "{e}");
    assert!(e.message.contains("not valid UTF-8 (byte 0xe9"), "{e}");
}
