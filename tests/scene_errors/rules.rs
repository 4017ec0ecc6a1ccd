//! Rules of every table (unknown keys and tables, types, non-finite numbers, required tables and keys, TOML syntax), then the settings, materials and interfaces.

use super::*;

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
