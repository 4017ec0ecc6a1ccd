//! `[[connector]]` input (scene-format contract; math note §6): valid connectors become the
//! expected `ConnectorSpec` (values are the literals of the scene text, defaults the contract's:
//! name "connector-N", G = E/(2(1 + 0.3)), k_Be = 1.2), and every rejection rule fails with the
//! right line (1-based, counted in the test's own text), key path and words.

use pbdda::geometry::Vec2;
use pbdda::model::{ConnectorKind, Model};
use pbdda::scene::{SceneError, parse};

/// Three bodies: a fixed 2×1 block "a", a free disk "b", a fixed ring "c" (its hole is not
/// material). `[[connector]]` is line 29 and its keys start on line 30 (see `scene`).
const BASE: &str = r#"[scene]
name = "t"
[time]
step = 0.001
steps = 10
[[material]]
name = "rock"
density = 2500.0
[[body]]
name = "a"
shape = "polygon"
vertices = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]]
material = "rock"
fixed = true
[[body]]
name = "b"
shape = "disk"
center = [4.0, 0.5]
radius = 1.0
material = "rock"
[[body]]
name = "c"
shape = "ring"
center = [8.0, 0.5]
radius = 1.0
inner_radius = 0.5
material = "rock"
fixed = true
"#;

/// BASE and one connector: `[[connector]]` on line 29, `keys` from line 30 on.
fn scene(keys: &str) -> String {
    format!("{BASE}[[connector]]\n{keys}")
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

/// `expected` is "LINE KEY: WORDS": the error is on LINE, its key path is KEY, its message
/// contains WORDS, and its Display starts with `scene.toml:LINE:` and names the key.
#[track_caller]
fn fails(source: &str, expected: &str) {
    let e = rejected(source);
    let (place, words) = expected.split_once(": ").unwrap_or((expected, ""));
    assert_eq!(format!("{} {}", e.line, e.key), place, "{e}");
    assert!(e.message.contains(words), "{e}\nlacks {words:?}");
    assert!(e.to_string().starts_with(&format!("scene.toml:{}:", e.line)), "{e}");
    assert!(e.to_string().contains(&e.key), "{e}");
}

const BOLT: &str = "kind = \"bolt\"\nyoung = 2.0e11\narea = 5.0e-4\n";

// ------------------------------------------------------------------ valid input

#[test]
fn bolt_anchors_go_to_the_bodies_that_contain_them() {
    // (2.0, 0.5) is on block a's edge: the boundary counts as inside
    let m = ok(&scene(&format!("{BOLT}points = [[2.0, 0.5], [3.5, 0.5]]\npretension = 1.0e4\n")));
    let c = &m.connectors[0];
    assert_eq!(c.name, "connector-1");
    assert_eq!(c.kind, ConnectorKind::Bolt { young: 2.0e11, area: 5.0e-4 });
    assert_eq!(c.bodies, [0, 1]);
    assert_eq!(c.points, [Vec2::new(2.0, 0.5), Vec2::new(3.5, 0.5)]);
    assert_eq!((c.pretension, c.strength), (1.0e4, None));
}

#[test]
fn beam_defaults_and_ring_anchor() {
    let keys = "name = \"bm\"\nkind = \"beam\"\npoints = [[4.5, 0.5], [8.0, 1.25]]\nyoung = 2.6e10\n\
                area = 0.1\ninertia = 1.0e-4\nstrength = 5.0e5\n";
    let m = ok(&scene(keys));
    let c = &m.connectors[0];
    assert_eq!(c.name, "bm");
    // contract defaults: G = E / (2 (1 + 0.3)) = 1e10, k_Be = 1.2
    let ConnectorKind::Beam { young, area, inertia, shear_modulus, shear_factor } = c.kind else {
        panic!("a beam: {:?}", c.kind)
    };
    assert_eq!((young, area, inertia, shear_factor), (2.6e10, 0.1, 1.0e-4, 1.2));
    assert!((shear_modulus - 1.0e10).abs() <= 1e-15 * 1.0e10);
    assert_eq!(c.bodies, [1, 2]);
    assert_eq!(c.strength, Some(5.0e5));
}

#[test]
fn spring_with_named_bodies_and_zero_length() {
    let keys =
        "kind = \"spring\"\nstiffness = 1.0e6\npoints = [[3.0, 0.5], [3.0, 0.5]]\nbodies = [\"b\", \"a\"]\n";
    let m = ok(&scene(keys));
    assert_eq!(m.connectors[0].bodies, [1, 0]);
    assert_eq!(m.connectors[0].kind, ConnectorKind::Spring { stiffness: 1.0e6 });
}

// ------------------------------------------------------------------ anchors and bodies

#[test]
fn anchor_inside_no_body() {
    // (8.0, 0.5) is the centre of ring c's hole
    let source = scene(&format!("{BOLT}points = [[3.5, 0.5], [8.0, 0.5]]\n"));
    fails(&source, "33 connector[0].points[1]: lies inside no body");
}

#[test]
fn anchor_inside_two_bodies() {
    // a fourth disk "d" overlapping b (declared after the connector: TOML appends it to body[])
    let extra =
        "[[body]]\nname = \"d\"\nshape = \"disk\"\ncenter = [4.5, 0.5]\nradius = 1.0\nmaterial = \"rock\"\n";
    let source = scene(&format!("{BOLT}points = [[1.0, 0.5], [4.2, 0.5]]\n{extra}"));
    fails(&source, "33 connector[0].points[1]: inside two bodies, \"b\" and \"d\"");
}

#[test]
fn both_anchors_on_the_same_body() {
    let source = scene(&format!("{BOLT}points = [[3.5, 0.5], [4.5, 0.5]]\n"));
    fails(
        &source,
        "33 connector[0].points: both anchors of connector \"connector-1\" are on the same body \"b\"",
    );
    let source = scene(&format!("{BOLT}points = [[1.0, 0.5], [4.5, 0.5]]\nbodies = [\"b\", \"b\"]\n"));
    fails(&source, "34 connector[0].bodies: same body \"b\"");
}

#[test]
fn both_bodies_fixed() {
    let source = scene(&format!("{BOLT}points = [[1.0, 0.5], [8.0, 1.25]]\n"));
    fails(&source, "33 connector[0].points: joins two fixed bodies, \"a\" and \"c\"");
}

#[test]
fn unknown_body_name() {
    let source = scene(&format!("{BOLT}points = [[1.0, 0.5], [4.5, 0.5]]\nbodies = [\"a\", \"zz\"]\n"));
    fails(&source, "34 connector[0].bodies[1]: unknown body \"zz\"");
}

#[test]
fn zero_length_bolt_and_beam() {
    let source = scene(&format!("{BOLT}points = [[3.0, 0.5], [3.0, 0.5]]\nbodies = [\"a\", \"b\"]\n"));
    fails(&source, "33 connector[0].points: a bolt needs two distinct points");
    let beam = "kind = \"beam\"\nyoung = 1.0\narea = 1.0\ninertia = 1.0\npoints = [[3.0, 0.5], [3.0, 0.5]]\n\
                bodies = [\"a\", \"b\"]\n";
    fails(&scene(beam), "34 connector[0].points: a beam needs two distinct points");
}

// ------------------------------------------------------------------ constants

#[test]
fn missing_stiffness_young_area_inertia() {
    let at = "points = [[1.0, 0.5], [3.5, 0.5]]\n";
    fails(&scene(&format!("kind = \"spring\"\n{at}")), "29 connector[0].stiffness: a spring connector needs");
    fails(
        &scene(&format!("kind = \"bolt\"\narea = 1.0\n{at}")),
        "29 connector[0].young: a bolt connector needs",
    );
    fails(&scene(&format!("kind = \"bolt\"\nyoung = 1.0\n{at}")), "29 connector[0].area: needs `area`");
    let beam = format!("kind = \"beam\"\nyoung = 1.0\narea = 1.0\n{at}");
    fails(&scene(&beam), "29 connector[0].inertia: a beam connector needs `inertia`");
}

#[test]
fn non_positive_stiffness_young_area_inertia() {
    let at = "points = [[1.0, 0.5], [3.5, 0.5]]\n";
    fails(
        &scene(&format!("kind = \"spring\"\nstiffness = 0.0\n{at}")),
        "31 connector[0].stiffness: positive",
    );
    fails(
        &scene(&format!("kind = \"bolt\"\nyoung = -1.0\narea = 1.0\n{at}")),
        "31 connector[0].young: positive",
    );
    fails(
        &scene(&format!("kind = \"bolt\"\nyoung = 1.0\narea = 0.0\n{at}")),
        "32 connector[0].area: positive",
    );
    let beam = format!("kind = \"beam\"\nyoung = 1.0\narea = 1.0\ninertia = -2.0\n{at}");
    fails(&scene(&beam), "33 connector[0].inertia: inertia must be positive");
}

#[test]
fn key_of_another_kind() {
    let at = "points = [[1.0, 0.5], [3.5, 0.5]]\n";
    fails(&scene(&format!("{BOLT}inertia = 1.0\n{at}")), "33 connector[0].inertia: not used by a bolt");
    let beam = format!("kind = \"beam\"\nyoung = 1.0\narea = 1.0\ninertia = 1.0\npretension = 5.0\n{at}");
    fails(&scene(&beam), "34 connector[0].pretension: `pretension` is not used by a beam connector");
    fails(&scene(&format!("kind = \"spring\"\nstiffness = 1.0\nyoung = 1.0\n{at}")), "32 connector[0].young");
}

#[test]
fn strength_below_pretension() {
    let source =
        scene(&format!("{BOLT}points = [[1.0, 0.5], [3.5, 0.5]]\npretension = 2.0e5\nstrength = 1.0e5\n"));
    fails(&source, "35 connector[0].strength: strength (100000) is below the pretension (200000)");
}

#[test]
fn duplicate_connector_names() {
    let one = format!("name = \"x\"\n{BOLT}points = [[1.0, 0.5], [3.5, 0.5]]\n");
    // the second `[[connector]]` is line 35, its name line 36
    let source = scene(&format!("{one}[[connector]]\n{one}"));
    fails(&source, "36 connector[1].name: duplicate connector name \"x\"");
    // an explicit name equal to a later connector's default
    let named = format!("name = \"connector-2\"\n{BOLT}points = [[1.0, 0.5], [3.5, 0.5]]\n");
    let unnamed = format!("{BOLT}points = [[1.0, 0.5], [3.5, 0.5]]\n");
    fails(&scene(&format!("{named}[[connector]]\n{unnamed}")), "30 connector[0].name: \"connector-2\"");
}

#[test]
fn unknown_kind_and_wrong_point_count() {
    fails(&scene("kind = \"rope\"\npoints = [[1.0, 0.5], [3.5, 0.5]]\n"), "30 connector[0].kind: \"rope\"");
    fails(&scene(&format!("{BOLT}points = [[1.0, 0.5]]\n")), "33 connector[0].points: 2 anchors (got 1)");
}

// ------------------------------------------------------------------ shipped examples

/// The connector examples are accepted, with the connectors their files list (counted in the
/// scene texts: 10 springs, 5 bolts, 10 beams, one per kind in the small scenes).
#[test]
fn connector_examples_are_accepted() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    for (file, kind, count) in [
        ("7_10_particle_chain.toml", "spring", 10),
        ("bolted_slope.toml", "bolt", 5),
        ("bonded_beam.toml", "beam", 10),
        ("connector_spring.toml", "spring", 1),
        ("connector_bolt.toml", "bolt", 1),
        ("connector_beam.toml", "beam", 1),
    ] {
        let m = pbdda::scene::load(&dir.join(file)).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(m.connectors.len(), count, "{file}");
        assert!(m.connectors.iter().all(|c| c.kind.as_str() == kind), "{file}");
    }
}
