//! `pbdda resume` from a state snapshot (src/checkpoint.rs, src/world/snapshot.rs): a run
//! stopped at step S and resumed writes the same files as a run that was never stopped.
//!
//! Each case runs the scene through with `pbdda run` (the reference), copies its folder, and in
//! the copy saves a checkpoint of a world stepped S times by the library (what `pbdda run
//! --checkpoint-every` saves after step S: the motion does not depend on which steps write
//! output). `pbdda resume` on the copy cuts its CSVs back to step S, loads the state and runs
//! the rest. The expected value is the reference run itself: every CSV byte for byte, steps.csv
//! value for value without its wall-time column (the only column that depends on the clock; its
//! width moves the other digits, src/output/rows.rs). No tolerance: a step from the loaded
//! state must be the step the uninterrupted run took, bit for bit. A state that missed anything
//! the next step reads (a kept factor, the contact memory, a connector's plastic strain, the
//! solver's step-length guess, the stage) shows as a difference in some later row.
//!
//! Cases: every scene of examples/ (staged, meshed, bolted ones with bolts that break), a stop
//! at the end of a stage, a mesh whose factors are kept across steps (`factor_drift`), a bolt
//! stopped while it yields and breaking after the resume, and a scene whose steps are split
//! (math note §10.8).

use crate::common;

use pbdda::checkpoint::Checkpoint;
use pbdda::scene::Override;
use pbdda::world::{Event, World};
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("pbdda-resume-{}-{name}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

fn pbdda(args: &[&str]) {
    let o = Command::new(env!("CARGO_BIN_EXE_pbdda")).args(args).output().expect("the binary runs");
    assert!(o.status.success(), "pbdda {args:?}: {}", String::from_utf8_lossy(&o.stderr));
}

/// steps.csv's values without its last column (wall_seconds), one `Vec` per row.
fn without_wall_time(path: &Path) -> Vec<Vec<String>> {
    let text = fs::read_to_string(path).expect("steps.csv");
    let value = |f: &str| f.parse::<f64>().map_or(f.to_owned(), |x| format!("{x:e}"));
    text.lines().map(|l| l.rsplit_once(',').expect("columns").0.split(',').map(value).collect()).collect()
}

/// What a case saw: the world at the stop, and the reference run's folder.
struct Stopped {
    world: World,
    whole: PathBuf,
}

/// Runs `scene` with `sets` through, then stopped at step `stop` and resumed (module docs);
/// asserts that every file agrees and returns the world at the stop for the case's own checks.
fn stop_and_resume(name: &str, scene: &Path, sets: &[&str], stop: usize) -> Stopped {
    let dir = scratch(name);
    let (whole, cut) = (dir.join("whole"), dir.join("cut"));
    let mut sets: Vec<&str> = sets.to_vec();
    sets.push("output.vtk=false");
    let mut args = vec!["run", "-q", scene.to_str().unwrap(), "--out", whole.to_str().unwrap()];
    args.extend(sets.iter().flat_map(|s| ["--set", s]));
    pbdda(&args);
    fs::create_dir_all(&cut).expect("cut folder");
    let csvs: Vec<String> = fs::read_dir(&whole)
        .expect("run folder")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .filter(|f| f.ends_with(".csv") || f == "run.log")
        .collect();
    for f in &csvs {
        fs::copy(whole.join(f), cut.join(f)).expect("copy");
    }
    let overrides: Vec<Override> = sets.iter().map(|s| s.parse().expect("override")).collect();
    let mut world = World::new(pbdda::scene::load_with(scene, &overrides).expect("scene"));
    for _ in 0..stop {
        world.step().unwrap_or_else(|e| panic!("{name}: {e}"));
    }
    let text = fs::read_to_string(scene).expect("scene text");
    let mut checkpoint =
        Checkpoint::new(scene.to_str().unwrap(), text, sets.iter().map(|s| s.to_string()).collect(), stop);
    checkpoint.save(&cut, &world).expect("checkpoint");
    pbdda(&["resume", "-q", cut.to_str().unwrap()]);
    for f in csvs.iter().filter(|f| f.ends_with(".csv") && *f != "steps.csv") {
        let (a, b) = (fs::read(whole.join(f)).unwrap(), fs::read(cut.join(f)).unwrap());
        assert!(a == b, "{name}: {f} differs after a resume at step {stop}");
    }
    let (a, b) = (without_wall_time(&whole.join("steps.csv")), without_wall_time(&cut.join("steps.csv")));
    assert!(a == b, "{name}: steps.csv differs after a resume at step {stop}");
    let log = fs::read_to_string(cut.join("run.log")).expect("run.log");
    assert!(log.contains(&format!("resumed at step {stop} ")), "{name}: {log}");
    // a finished run keeps no restart files
    let left: Vec<_> = fs::read_dir(&cut)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|f| f.starts_with("checkpoint") || f.starts_with("state-"))
        .collect();
    assert!(left.is_empty(), "{name}: {left:?} left after the run finished");
    Stopped { world, whole }
}

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples").join(name)
}

/// The last step of steps.csv.
fn last_step(dir: &Path) -> usize {
    let text = fs::read_to_string(dir.join("steps.csv")).expect("steps.csv");
    text.lines().last().and_then(|l| l.split(',').next()).and_then(|s| s.parse().ok()).expect("a step")
}

/// Every scene of examples/ (28, the count tests/io/vtk_output.rs asserts), stopped half way (the
/// collapse, whose steps take seconds, is cut to 2 steps; the bolted slope is stopped at step
/// 300, after two of its bolts broke at step 53 and before the other two break at 507, its
/// run.log says; the staged slope at step 115, in its third stage, with bodies removed and
/// bolts installed).
#[test]
fn every_example_resumes_to_the_same_bytes() {
    let mut names: Vec<String> = fs::read_dir(example(""))
        .expect("examples/")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .filter(|f| f.ends_with(".toml"))
        .collect();
    names.sort();
    assert_eq!(names.len(), 28);
    for name in &names {
        let sets: &[&str] = if name == "rock_column_collapse.toml" { &["time.steps=2"] } else { &[] };
        let steps = pbdda::scene::load_with(&example(name), &[]).expect("example").time.steps;
        let steps = if sets.is_empty() { steps } else { 2 };
        let stop = if name == "bolted_slope.toml" { 300 } else { steps / 2 };
        let s = stop_and_resume(name.trim_end_matches(".toml"), &example(name), sets, stop);
        if name == "bolted_slope.toml" {
            assert_eq!(s.world.connectors.iter().filter(|c| c.broken).count(), 2, "{name}");
            let log = fs::read_to_string(s.whole.join("run.log")).expect("run.log");
            assert_eq!(log.matches("step 507: connector").count(), 2, "{log}");
        }
        fs::remove_dir_all(s.whole.parent().unwrap()).ok();
    }
}

/// Stopped at the last step of a stage (the staged slope's "excavate" ends at step 30, so the
/// resumed run's first step starts "support" and installs its bolts), and at the end of the
/// in-situ tunnel's first stage, which ends early by `until_kinetic` (step 10, run.log).
#[test]
fn a_run_stopped_at_the_end_of_a_stage_resumes() {
    let s = stop_and_resume("stage-end", &example("staged_slope.toml"), &[], 30);
    assert_eq!(s.world.stage_name(), Some("excavate"));
    let s = stop_and_resume("quiet-end", &example("tunnel_insitu.toml"), &[], 10);
    assert_eq!(s.world.stage_name(), Some("equilibrium"));
    let log = fs::read_to_string(s.whole.join("run.log")).expect("run.log");
    assert!(log.contains("step 10: stage \"equilibrium\" ended"), "{log}");
}

/// A meshed block whose sparse factor is kept while no element turns or strains by more than
/// `factor_drift` (math note §9.3): the factor the resumed steps use was formed steps before the
/// stop, on an older geometry, with a cache of K⁻¹ entries filled in the order contacts asked
/// for them. Asserted as well: the drift keeps factors (fewer factorizations than steps at the
/// stop; without it there is one per step).
#[test]
fn kept_factors_resume_bit_for_bit() {
    let scene = example("mesh_block_on_slope.toml");
    let s = stop_and_resume("drift", &scene, &["solver.factor_drift=0.01", "time.steps=200"], 120);
    let factorizations = s.world.sparse_factorizations();
    assert!(factorizations < 120, "{factorizations} factorizations in 120 steps");
    assert_eq!(last_step(&s.whole), 200);
}

/// The pull test of tests/rock/bolt_yield.rs (F = 2e4 N × t/1 s on a bolt of yield force Y = 1e4 N,
/// ultimate strain 0.05): stopped at step 60, while the bolt yields with a plastic strain
/// (asserted), it breaks after the resume; connectors.csv holds its yield and break rows.
#[test]
fn a_yielding_bolt_resumes_and_breaks() {
    let dir = scratch("pull-scene");
    let path = dir.join("pull.toml");
    fs::write(&path, common::scenes::pull::scene("[[0.0, 0.0], [1.0, 2.0e4]]", Some(0.05), 100))
        .expect("scene");
    let s = stop_and_resume("pull", &path, &[], 60);
    let bolt = &s.world.connectors[0];
    assert!(bolt.is_yielding() && bolt.plastic_strain > 0.0 && !bolt.broken, "{bolt:?}");
    let csv = fs::read_to_string(s.whole.join("connectors.csv")).expect("connectors.csv");
    assert!(csv.contains(",broken,"), "{csv}");
    fs::remove_dir_all(&dir).ok();
}

/// The `settling` scene of tests/paper/adaptive_step.rs (disks, blocks and a deformable slab dropped
/// into a box at dt = 0.01 s): some of its first 60 steps are split (asserted). Stopped just
/// before the first split step, the resumed run splits it (and the later ones) as the
/// uninterrupted run does.
#[test]
fn a_run_with_split_steps_resumes() {
    let dir = scratch("settling-scene");
    let path = dir.join("settling.toml");
    fs::write(&path, common::scenes::settling_text()).expect("scene");
    let sixty: Override = "time.steps=60".parse().expect("override");
    let mut world = World::new(pbdda::scene::load_with(&path, &[sixty]).expect("scene"));
    let first_split = (1..=60).find(|_| {
        let rec = world.step().expect("step");
        rec.events.iter().any(|e| matches!(e, Event::StepSplit { .. }))
    });
    let first_split = first_split.expect("a split step in the first 60");
    assert!(first_split > 1, "the stop must be after step 0");
    let s = stop_and_resume("settling", &path, &["time.steps=60"], first_split - 1);
    let log = fs::read_to_string(s.whole.join("run.log")).expect("run.log");
    assert!(log.contains(&format!("step {first_split}: ")), "{log}");
    fs::remove_dir_all(&dir).ok();
}

fn fails(args: &[&str]) -> String {
    let o = Command::new(env!("CARGO_BIN_EXE_pbdda")).args(args).output().expect("the binary runs");
    assert!(!o.status.success(), "pbdda {args:?} should fail");
    common::one_line(&String::from_utf8_lossy(&o.stderr))
}

/// Checkpoints `resume` must refuse, each with the reason: one of format version 1 (which held
/// no state), a state file of another scene (the FNV-1a hash of the scene text in its header
/// differs), a state file cut short, and a state file that is not one.
#[test]
fn foreign_checkpoints_are_refused() {
    let dir = scratch("foreign");
    let scene = example("7_1_disk_heap.toml");
    let (out, d) = (dir.join("out"), dir.to_str().unwrap().to_owned());
    pbdda(&[
        "run",
        "-q",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--set",
        "output.vtk=false",
    ]);
    let mut world = World::new(pbdda::scene::load(&scene).expect("scene"));
    world.step().expect("step");
    let text = fs::read_to_string(&scene).expect("scene text");
    let mut c = Checkpoint::new(scene.to_str().unwrap(), text.clone(), vec![], 1);
    c.save(&out, &world).expect("checkpoint");
    let o = out.to_str().unwrap();
    let good = fs::read_to_string(out.join("checkpoint.toml")).expect("checkpoint.toml");
    fs::write(out.join("checkpoint.toml"), good.replace("version = 2", "version = 1")).expect("write");
    let e = fails(&["resume", o]);
    assert!(e.contains("not a pbdda checkpoint: version 1 (this pbdda reads version 2)"), "{e}");
    let state = out.join(&c.state);
    let bytes = fs::read(&state).expect("state");
    let other = Checkpoint { scene: text.replace("[scene]", "[scene]\n# edited"), ..c.clone() };
    other.write(&out).expect("checkpoint.toml");
    let e = fails(&["resume", o]);
    assert!(e.contains("the state is of another scene"), "{e}");
    c.write(&out).expect("checkpoint.toml");
    fs::write(&state, &bytes[..bytes.len() / 2]).expect("cut state");
    let e = fails(&["resume", o]);
    assert!(e.contains("not a pbdda checkpoint: the state cannot be decoded"), "{e}");
    fs::write(&state, b"[scene]\n").expect("not a state");
    let e = fails(&["resume", o]);
    assert!(e.contains("not a pbdda checkpoint: no pbdda state header"), "{e}");
    fs::remove_dir_all(&d).ok();
}
