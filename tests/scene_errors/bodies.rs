//! Bodies: shapes and their geometry, and the keys the reader does not support yet.

use super::*;

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

// mesh bodies: tests/mesh/mesh_scene.rs

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
