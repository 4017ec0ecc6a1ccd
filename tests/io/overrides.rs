//! `--set KEY=VALUE` overrides (src/scene/overrides.rs), through the library and the binary.
//! Expected values are the overriding values themselves, the scene format's `end` rule
//! (steps = ceil(end / step)), and the lines of examples/7_1_disk_heap.toml, read from the
//! file here. Errors must name the key (and, for a wrong type, the expected type).

use pbdda::model::Shape;
use pbdda::scene::{Override, SceneError, load_with, parse_with};
use std::path::{Path, PathBuf};
use std::process::Command;

fn heap_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/7_1_disk_heap.toml")
}

fn set(pairs: &[&str]) -> Vec<Override> {
    pairs.iter().map(|p| Override::parse(p).expect("KEY=VALUE")).collect()
}

fn error(pairs: &[&str]) -> SceneError {
    match load_with(&heap_path(), &set(pairs)) {
        Ok(_) => panic!("{pairs:?} must be rejected"),
        Err(e) => e,
    }
}

fn radius(model: &pbdda::model::Model, name: &str) -> f64 {
    let body = model.bodies.iter().find(|b| b.name == name).expect("body");
    match body.shape {
        Shape::Disk { radius, .. } => radius,
        _ => panic!("{name} is not a disk"),
    }
}

/// 1-based line of the first line of the heap scene containing `needle`.
fn line_of(needle: &str) -> usize {
    let text = std::fs::read_to_string(heap_path()).unwrap();
    text.lines().position(|l| l.contains(needle)).expect("needle in file") + 1
}

#[test]
fn existing_and_absent_keys_are_set() {
    let m = load_with(&heap_path(), &set(&["time.step=2e-3", "solver.max_iterations=77", "output.every=10"]))
        .expect("valid overrides");
    assert_eq!(m.time.step, 2e-3);
    assert_eq!(m.time.steps, 100, "steps stays as written");
    assert_eq!(m.solver.max_iterations, 77, "absent key added to its table");
    assert_eq!(m.output.every, 10, "absent table added");
    assert_eq!(m.solver.tolerance, 1e-13, "other keys keep their values");
}

#[test]
fn array_entries_by_name_or_index() {
    let by_name = load_with(&heap_path(), &set(&["body.d1.radius=9.5"])).unwrap();
    // d1 is the fourth [[body]] of the file: index 3
    let by_index = load_with(&heap_path(), &set(&["body[3].radius=9.5"])).unwrap();
    for m in [&by_name, &by_index] {
        assert_eq!(radius(m, "d1"), 9.5);
        assert_eq!(radius(m, "d2"), 10.0);
    }
    let g = load_with(&heap_path(), &set(&["physics.gravity[1]=-9.81"])).unwrap();
    assert_eq!((g.physics.gravity.x, g.physics.gravity.y), (0.0, -9.81));
    let rigid = load_with(
        &heap_path(),
        &set(&["body.d2.model=deformable", "material.disk.young=1e9", "material.disk.poisson=0.25"]),
    )
    .unwrap();
    assert!(rigid.bodies.iter().any(|b| b.name == "d2" && b.model == pbdda::model::BodyModel::Deformable));
}

#[test]
fn end_replaces_steps() {
    // ceil(0.0505 / 0.001) = 51 steps (scene format: steps = ceil(end / step))
    let m = load_with(&heap_path(), &set(&["time.end=0.0505"])).expect("end replaces steps");
    assert_eq!(m.time.steps, 51);
    let back = load_with(&heap_path(), &set(&["time.end=0.0505", "time.steps=7"])).unwrap();
    assert_eq!(back.time.steps, 7);
}

#[test]
fn unknown_key_is_named() {
    let e = error(&["time.stpe=1e-3"]);
    assert_eq!(e.key, "time.stpe");
    assert!(e.message.contains("--set time.stpe=1e-3") && e.message.contains("unknown key `stpe`"), "{e}");
    let e = error(&["solvr.tolerance=1e-8"]);
    assert_eq!(e.key, "solvr");
    assert!(e.message.contains("unknown key `solvr`"), "{e}");
    let e = error(&["body.d9.radius=1"]);
    assert_eq!(e.key, "body");
    assert!(e.message.contains("no entry of `body` is named `d9`"), "{e}");
    let e = error(&["body[3].colour=1"]);
    assert_eq!(e.key, "body[3].colour");
    assert!(e.message.contains("unknown key `colour`"), "{e}");
}

#[test]
fn wrong_type_names_key_and_expected_type() {
    let e = error(&["output.every=1.5"]);
    assert_eq!(e.key, "output.every");
    assert!(e.message.contains("expected a whole number"), "{e}");
    let e = error(&["solver.tolerance=tight"]);
    assert_eq!(e.key, "solver.tolerance");
    assert!(e.message.contains("string \"tight\"") && e.message.contains("expected a number"), "{e}");
}

#[test]
fn range_checks_apply_at_the_overridden_line() {
    let e = error(&["time.step=-1"]);
    assert_eq!(e.key, "time.step");
    assert_eq!(e.line, line_of("step = 0.001"));
    assert!(e.message.contains("--set time.step=-1") && e.message.contains("must be positive"), "{e}");
}

#[test]
fn scene_errors_keep_their_own_line() {
    // a bad radius in the file, and an override that adds a line above it
    let text = std::fs::read_to_string(heap_path()).unwrap().replace("radius = 10.0", "radius = -10.0");
    let line = text.lines().position(|l| l.contains("radius = -10.0")).unwrap() + 1;
    let e = parse_with(&text, "heap.toml", &set(&["solver.max_iterations=5"])).expect_err("bad radius");
    assert_eq!((e.line, e.key.as_str()), (line, "body[1].radius"), "{e}");
    assert!(!e.message.contains("--set"), "not the override's fault: {e}");
}

#[test]
fn binary_accepts_set_on_run_and_check() {
    let bin = env!("CARGO_BIN_EXE_pbdda");
    let heap = heap_path();
    let o =
        Command::new(bin).args(["check", heap.to_str().unwrap(), "--set", "time.steps=7"]).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stdout).contains("7 steps"));
    let out = std::env::temp_dir().join(format!("pbdda-overrides-{}", std::process::id()));
    let o = Command::new(bin)
        .args(["run", heap.to_str().unwrap(), "--out", out.to_str().unwrap(), "--set", "time.stpe=1"])
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("time.stpe"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(!out.exists(), "nothing written for a rejected override");
    let o = Command::new(bin).args(["check", heap.to_str().unwrap(), "--set", "time.step"]).output().unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("KEY=VALUE"));
}

#[test]
fn syntax_error_of_the_file_is_reported_as_without_overrides() {
    let text = "[time]\nstep = = 1\n";
    let plain = parse_with(text, "bad.toml", &[]).expect_err("syntax error");
    let with = parse_with(text, "bad.toml", &set(&["time.step=1"])).expect_err("syntax error");
    assert_eq!(with.to_string(), plain.to_string());
    assert_eq!(with.line, 2);
}
