//! Mesh bodies in scene files (scene-format contract, `shape = "mesh"`): the keys are read, and
//! every mesh error is a scene error at the scene line and key that led to it whose message names
//! the mesh file and the mesh file's own line. Line numbers are counted in the texts below and in
//! `tests/bad_meshes/*.msh`.

use pbdda::model::Shape;
use pbdda::scene::{SceneError, parse};
use std::path::Path;

/// The scene "file" sits in `tests/`, so mesh paths are relative to it.
fn scene_path() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests").join("scene.toml").display().to_string()
}

/// A scene whose only body is a mesh with the `extra` keys; `extra` starts on line 16.
fn mesh_scene(extra: &str) -> String {
    format!(
        r#"[scene]
name = "t"
[time]
step = 0.001
steps = 10
[[material]]
name = "rock"
density = 2500.0
young = 1.0e9
poisson = 0.25
[[body]]
name = "m"
shape = "mesh"
material = "rock"
file = "../meshes/square.msh"
{extra}"#
    )
}

fn rejected(source: &str) -> SceneError {
    match parse(source, &scene_path()) {
        Ok(_) => panic!("should be rejected:\n{source}"),
        Err(e) => e,
    }
}

/// `place` is "LINE KEY"; the message contains every one of `words`.
#[track_caller]
fn fails(source: &str, place: &str, words: &[&str]) {
    let e = rejected(source);
    assert_eq!(format!("{} {}", e.line, e.key), place, "{e}");
    for w in words {
        assert!(e.message.contains(w), "{e}\nlacks {w:?}");
    }
}

/// The keys of the contract: `physical` selects the surface, `fixed_nodes` the clamped nodes,
/// `scale` then `offset` place it. `square.msh` is 1.0 x 0.8 with its `left` side at x = 0, so
/// scaled by 2 and offset by (1, 0) it spans x in [1, 3], y in [0, 1.6], and its clamped nodes are
/// those with x = 1.
#[test]
fn mesh_keys_build_the_shape() {
    let text =
        mesh_scene("physical = \"block\"\nfixed_nodes = [\"left\"]\nscale = 2.0\noffset = [1.0, 0.0]\n");
    let model = parse(&text, &scene_path()).unwrap_or_else(|e| panic!("{e}"));
    let Shape::Mesh(m) = &model.bodies[0].shape else { panic!("not a mesh") };
    let (min, max) =
        m.mesh.nodes.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.x), b.max(p.x)));
    assert_eq!((min, max), (1.0, 3.0));
    let top = m.mesh.nodes.iter().fold(0.0f64, |a, p| a.max(p.y));
    assert!((top - 1.6).abs() < 1e-15);
    assert!(!m.fixed_nodes.is_empty());
    assert!(m.fixed_nodes.iter().all(|&n| m.mesh.nodes[n].x == 1.0));
    let on_left = m.mesh.nodes.iter().filter(|p| p.x == 1.0).count();
    assert_eq!(m.fixed_nodes.len(), on_left);
}

/// A degenerate triangle (element 2 of `bad_meshes/degenerate.msh`, on its line 20, has the
/// collinear nodes 1, 2, 5): the error is at the scene's `file` key (line 15) and names the mesh
/// file's line.
#[test]
fn mesh_file_errors_name_the_scene_key_and_the_mesh_line() {
    let text = mesh_scene("").replace("../meshes/square.msh", "bad_meshes/degenerate.msh");
    fails(&text, "15 body[0].file", &["degenerate.msh:20:", "zero area"]);
    let missing = mesh_scene("").replace("../meshes/square.msh", "bad_meshes/no_such.msh");
    fails(&missing, "15 body[0].file", &["no_such.msh", "cannot read"]);
}

/// Groups that do not exist: `physical` and `fixed_nodes` errors sit on their own keys and list
/// the groups the file has.
#[test]
fn unknown_groups_are_errors_at_their_keys() {
    fails(&mesh_scene("physical = \"slab\"\n"), "16 body[0].physical", &["\"slab\"", "\"block\""]);
    fails(
        &mesh_scene("fixed_nodes = [\"left\", \"nowhere\"]\n"),
        "16 body[0].fixed_nodes[1]",
        &["\"nowhere\""],
    );
}

/// Mesh keys on other shapes, a mesh without `file`, a rigid mesh, and a material without
/// elastic constants are errors at the offending key.
#[test]
fn misplaced_and_missing_mesh_keys() {
    let disk =
        mesh_scene("").replace("shape = \"mesh\"", "shape = \"disk\"\ncenter = [0.0, 0.0]\nradius = 1.0");
    fails(&disk, "17 body[0].file", &["mesh bodies"]);
    let no_file = mesh_scene("").replace("file = \"../meshes/square.msh\"\n", "");
    fails(&no_file, "11 body[0].file", &["needs `file`"]);
    fails(&mesh_scene("model = \"rigid\"\n"), "16 body[0].model", &["always finite elements"]);
    let soft = mesh_scene("").replace("young = 1.0e9\n", "");
    fails(&soft, "13 body[0].material", &["young"]);
}

/// Every kind of connector may be anchored on a mesh (`tests/mesh/mesh_connectors.rs`), but an anchor
/// given to a mesh body by `bodies` must lie inside it: an error at that point (line 24 here)
/// naming the mesh body.
#[test]
fn connectors_on_meshes() {
    let disk =
        "[[body]]\nname = \"d\"\nshape = \"disk\"\ncenter = [3.0, 0.4]\nradius = 0.5\nmaterial = \"rock\"\n";
    let spring = "[[connector]]\nkind = \"spring\"\npoints = [[0.5, 0.4], [3.0, 0.4]]\nstiffness = 1.0e6\n";
    assert!(parse(&mesh_scene(&format!("{disk}{spring}")), &scene_path()).is_ok());
    let beam = "[[connector]]\nkind = \"beam\"\npoints = [[0.5, 0.4], [3.0, 0.4]]\nyoung = 1e9\narea = 0.01\n\
        inertia = 1e-5\nshear_modulus = 4e8\nshear_factor = 1.2\n";
    assert!(parse(&mesh_scene(&format!("{disk}{beam}")), &scene_path()).is_ok());
    let outside = "[[connector]]\nkind = \"spring\"\npoints = [[1.5, 0.4], [3.0, 0.4]]\nstiffness = 1.0e6\n\
        bodies = [\"m\", \"d\"]\n";
    fails(
        &mesh_scene(&format!("{disk}{outside}")),
        "24 connector[0].points[0]",
        &["outside mesh body \"m\""],
    );
}
