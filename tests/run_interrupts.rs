//! Runs that are stopped: nothing written is lost or cut (issue 11, point 6).
//!
//! - `kill -9` at pseudo-random moments (20 times): every CSV file holds whole rows only (each
//!   ends with a newline and has the header's number of fields; see `assert_whole_rows` for the
//!   one cut the kernel can make), and `steps.csv` never names a
//!   step later than the last step in `bodies.csv` (rows of a step are written state files
//!   first, `steps.csv` last).
//! - SIGTERM: the run finishes its step, writes `interrupted at step N` to run.log, where N is
//!   the last step of steps.csv and bodies.csv, and exits with a non-zero code.
//! - `pbdda resume` after a `kill -9` continues from the checkpoint: bodies.csv, contacts.csv,
//!   monitors.csv (and connectors.csv) equal those of an uninterrupted run byte for byte, and
//!   steps.csv too with its wall-time column removed (the only column that depends on the clock).
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
///
/// One exception the kernel imposes: a step's rows go out in one `write`, but Linux copies a
/// write into the page cache page by page and stops between pages when the process has a
/// fatal signal (SIGKILL), so a write that straddles a 4096-byte page boundary of the file can
/// end at that boundary. A cut last row is therefore allowed only when the file's length is a
/// multiple of 4096 (never seen in 80 manual kills; seen once in the test loop); anywhere else
/// it is a bug of the writer. `pbdda resume` drops such a row.
fn assert_whole_rows(path: &Path) {
    let Ok(text) = fs::read(path) else { return };
    if text.is_empty() {
        return; // created, header not yet written
    }
    let text = String::from_utf8_lossy(&text);
    let whole = match text.rfind('\n') {
        Some(end) if !text.ends_with('\n') => {
            let cut = &text[end + 1..];
            assert_eq!(
                text.len() % 4096,
                0,
                "{}: cut last row {cut:?} not at a page boundary",
                path.display()
            );
            &text[..=end]
        }
        _ => &text[..],
    };
    let mut lines = whole.lines();
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
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    for _ in 0..20 {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        let mut child = start(&out, 1_000_000, &[]);
        std::thread::sleep(Duration::from_millis(10 + seed % 150));
        child.kill().expect("SIGKILL");
        child.wait().expect("wait");
        for name in ["bodies.csv", "contacts.csv", "monitors.csv", "steps.csv"] {
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

/// steps.csv without its last column (wall_seconds).
fn without_wall_time(path: &Path) -> String {
    let text = fs::read_to_string(path).unwrap();
    text.lines().map(|l| l.rsplit_once(',').unwrap().0.to_owned() + "\n").collect()
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
    assert_eq!(without_wall_time(&whole.join("steps.csv")), without_wall_time(&cut.join("steps.csv")));
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
