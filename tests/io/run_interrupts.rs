//! Runs that are stopped: nothing written is lost or cut (issue 11, point 6).
//!
//! - `kill -9` at pseudo-random moments (20 times, alternately the staircase and the bolt scene
//!   with a row every step): every CSV file holds whole rows only (each
//!   ends with a newline and has the header's number of fields), and `steps.csv` never names a
//!   step later than the last step in `bodies.csv` (rows of a step are written state files
//!   first, `steps.csv` last).
//! - SIGTERM: the run finishes its step, writes `interrupted at step N` to run.log, where N is
//!   the last step of steps.csv and bodies.csv, and exits with a non-zero code.
//! - `pbdda resume` after a `kill -9` continues from the checkpoint: bodies.csv, contacts.csv,
//!   monitors.csv (and connectors.csv) equal those of an uninterrupted run byte for byte, and
//!   steps.csv too, value for value, with its wall-time column removed (the only column that
//!   depends on the clock; its width moves the digits of the others, see `without_wall_time`).
//!
//! The scene is the paper's block staircase (§7.2), run longer: every step has contacts; the
//! connector case runs `examples/connector_bolt.toml`.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Child, Command};
use std::time::Duration;

fn scene() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/7_2_block_staircase.toml")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("pbdda-interrupts-{}-{name}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    dir
}

fn start(out: &Path, steps: usize, extra: &[&str]) -> Child {
    start_scene(&scene(), out, steps, extra)
}

fn start_scene(scene: &Path, out: &Path, steps: usize, extra: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_pbdda"))
        .args(["run", "-q", "--overwrite", "--set", "output.vtk=false"])
        .args(["--set", &format!("time.steps={steps}")])
        .arg(scene)
        .arg("--out")
        .arg(out)
        .args(extra)
        .spawn()
        .expect("spawn pbdda")
}

fn signal(child: &Child, name: &str) {
    let status = Command::new("kill").args([name, &child.id().to_string()]).status().expect("kill");
    assert!(status.success());
}

/// The step of the last row of a CSV file (None: header only or missing).
fn last_step(path: &Path) -> Option<usize> {
    let text = fs::read_to_string(path).ok()?;
    text.lines().skip(1).last().map(|row| row.split(',').next().unwrap().parse().expect("step number"))
}

/// Every row of the CSV at `path` is whole: newline-terminated, as many fields as the header.
/// (A write can stop at a 4096-byte boundary of the file under SIGKILL; the writer lays rows out
/// so that none straddles one: `src/output/rows.rs`.)
fn assert_whole_rows(path: &Path) {
    let Ok(text) = fs::read(path) else { return };
    let text = String::from_utf8(text).expect("UTF-8");
    assert!(
        text.is_empty() || text.ends_with('\n'),
        "{}: cut last row …{:?} (file length {})",
        path.display(),
        &text[text.len().saturating_sub(80)..],
        text.len()
    );
    let mut lines = text.lines();
    let Some(header) = lines.next() else { return };
    let fields = header.split(',').count();
    for row in lines {
        assert_eq!(row.split(',').count(), fields, "{}: partial row {row:?}", path.display());
    }
}

fn wait_for(what: impl Fn() -> bool) {
    for _ in 0..12_000 {
        if what() {
            return;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    panic!("the run did not get there in 60 s");
}

#[test]
fn kill_9_never_leaves_a_partial_row() {
    let out = scratch("kill9");
    let bolt = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/connector_bolt.toml");
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    for i in 0..20 {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        // every other run: the bolt scene, a connectors.csv row every step
        let mut child = match i % 2 {
            0 => start(&out, 1_000_000, &[]),
            _ => start_scene(&bolt, &out, 10_000_000, &["--set", "output.every=1"]),
        };
        std::thread::sleep(Duration::from_millis(10 + seed % 150));
        child.kill().expect("SIGKILL");
        child.wait().expect("wait");
        for name in ["bodies.csv", "contacts.csv", "monitors.csv", "steps.csv", "connectors.csv"] {
            assert_whole_rows(&out.join(name));
        }
        if let Some(s) = last_step(&out.join("steps.csv")) {
            let b = last_step(&out.join("bodies.csv")).expect("steps.csv has rows, bodies.csv none");
            assert!(s <= b, "steps.csv at step {s} runs ahead of bodies.csv at {b}");
        }
    }
    fs::remove_dir_all(&out).unwrap();
}

#[test]
fn sigterm_finishes_the_step_and_says_so() {
    let out = scratch("term");
    let mut child = start(&out, 1_000_000, &[]);
    wait_for(|| last_step(&out.join("steps.csv")).is_some_and(|s| s >= 10));
    signal(&child, "-TERM");
    let status = child.wait().expect("wait");
    assert!(!status.success(), "an interrupted run must not exit 0");
    let (s, b) = (last_step(&out.join("steps.csv")).unwrap(), last_step(&out.join("bodies.csv")).unwrap());
    assert_eq!(s, b);
    let log = fs::read_to_string(out.join("run.log")).unwrap();
    assert!(log.contains(&format!("interrupted at step {s}\n")), "run.log: {log}");
    fs::remove_dir_all(&out).unwrap();
}

/// The values of steps.csv without its last column (wall_seconds), one `Vec` per row: the
/// wall time also changes the layout of the other columns (a row before a 4096-byte boundary
/// is written with more digits, `src/output/rows.rs`), so numbers are compared as `f64`.
fn without_wall_time(path: &Path) -> Vec<Vec<String>> {
    let text = fs::read_to_string(path).unwrap();
    let value = |f: &str| f.parse::<f64>().map_or(f.to_owned(), |x| format!("{x:e}"));
    text.lines().map(|l| l.rsplit_once(',').unwrap().0.split(',').map(value).collect()).collect()
}

/// A run of `scene` killed (SIGKILL) once it has a checkpoint and has written past step
/// `kill_after`, then resumed, writes the same files as an uninterrupted run: `files` byte for
/// byte, steps.csv without its wall-time column.
fn kill_and_resume(
    name: &str,
    scene: &Path,
    steps: usize,
    every: &[&str],
    kill_after: usize,
    files: &[&str],
) {
    let (whole, cut) = (scratch(&format!("{name}-whole")), scratch(&format!("{name}-cut")));
    assert!(start_scene(scene, &whole, steps, every).wait().expect("uninterrupted run").success());
    let mut child = start_scene(scene, &cut, steps, every);
    wait_for(|| {
        cut.join("checkpoint.toml").exists() && last_step(&cut.join("steps.csv")).unwrap_or(0) > kill_after
    });
    child.kill().expect("SIGKILL");
    child.wait().expect("wait");
    assert!(last_step(&cut.join("steps.csv")).unwrap() < steps, "the run ended before the kill");
    let status = Command::new(env!("CARGO_BIN_EXE_pbdda")).args(["resume", "-q"]).arg(&cut).status().unwrap();
    assert!(status.success());
    for file in files {
        let (a, b) = (fs::read(whole.join(file)).unwrap(), fs::read(cut.join(file)).unwrap());
        assert!(a == b, "{file} differs after resume");
    }
    let (a, b) = (without_wall_time(&whole.join("steps.csv")), without_wall_time(&cut.join("steps.csv")));
    assert!(a == b, "steps.csv differs after resume (wall_seconds aside)");
    fs::remove_dir_all(&whole).unwrap();
    fs::remove_dir_all(&cut).unwrap();
}

#[test]
fn resume_matches_an_uninterrupted_run() {
    let files = ["bodies.csv", "contacts.csv", "monitors.csv"];
    kill_and_resume("staircase", &scene(), 6000, &["--checkpoint-every", "700"], 1500, &files);
}

/// The same for a scene with a connector (`examples/connector_bolt.toml`, 400 000 steps of about
/// 12 µs, rows every 1 000th): `connectors.csv` too equals the uninterrupted run's byte for byte.
#[test]
fn resume_with_connectors_matches_an_uninterrupted_run() {
    let bolt = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/connector_bolt.toml");
    let every = ["--set", "output.every=1000", "--checkpoint-every", "20000"];
    let files = ["bodies.csv", "contacts.csv", "monitors.csv", "connectors.csv"];
    kill_and_resume("bolt", &bolt, 400_000, &every, 100_000, &files);
}
