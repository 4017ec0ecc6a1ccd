//! The `pbdda` command line, end to end: `run` writes the four CSV files of the output
//! contract (docs/scene-format.md) with their exact headers and a completed run.log, refuses
//! to mix with an earlier run unless --overwrite, and a bad scene fails before any output is
//! created, with an error naming the file, line and key; `check` prints the scene summary.
//! Progress (src/cli/progress.rs): nothing at all with --quiet; when stderr is not a terminal
//! (here: a pipe) plain lines at every 10 % of the steps, without ANSI escapes or carriage
//! returns, and the closing summary.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn pbdda(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pbdda")).args(args).output().expect("the binary runs")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("pbdda-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn example(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples").join(name).display().to_string()
}

fn header(path: &Path) -> String {
    std::fs::read_to_string(path).expect("file").lines().next().unwrap_or_default().to_string()
}

#[test]
fn run_writes_the_output_contract() {
    let out = scratch("run");
    let o = pbdda(&["run", &example("7_1_disk_heap.toml"), "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        header(&out.join("bodies.csv")),
        "step,time,body,x,y,rotation,vx,vy,omega,strain_x,strain_y,strain_xy,stress_x,stress_y,stress_xy"
    );
    assert_eq!(
        header(&out.join("contacts.csv")),
        "step,time,body_a,body_b,kind,x,y,nx,ny,normal_force,shear_force,rolling_moment,gap,state,interface"
    );
    assert_eq!(
        header(&out.join("monitors.csv")),
        "step,time,monitor,x,y,ux,uy,vx,vy,stress_x,stress_y,stress_xy"
    );
    assert_eq!(
        header(&out.join("steps.csv")),
        "step,time,dt,contacts,outer_iterations,inner_iterations,residual,method,kinetic_energy,stage,wall_seconds"
    );
    // steps.csv: one row per step (100), bodies.csv: every step x 4 bodies (every = 1)
    let rows = |f: &str| std::fs::read_to_string(out.join(f)).unwrap().lines().count() - 1;
    assert_eq!(rows("steps.csv"), 100);
    assert_eq!(rows("bodies.csv"), 400);
    assert_eq!(rows("contacts.csv"), 300);
    let contacts = std::fs::read_to_string(out.join("contacts.csv")).unwrap();
    let last = contacts.lines().last().unwrap();
    assert!(last.starts_with("100,0.1,"), "{last}");
    assert!(std::fs::read_to_string(out.join("run.log")).unwrap().contains("completed 100 steps"));

    // a second run into the same directory is refused, and leaves the files alone
    let again = pbdda(&["run", &example("7_1_disk_heap.toml"), "--out", out.to_str().unwrap()]);
    assert!(!again.status.success());
    assert!(String::from_utf8_lossy(&again.stderr).contains("--overwrite"));
    assert_eq!(rows("steps.csv"), 100);
    let over =
        pbdda(&["run", &example("7_1_disk_heap.toml"), "--out", out.to_str().unwrap(), "--overwrite", "-q"]);
    assert!(over.status.success());
    assert_eq!(rows("steps.csv"), 100);
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn bad_scene_fails_before_writing_anything() {
    let dir = scratch("bad");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("bad.toml");
    let text = std::fs::read_to_string(example("7_1_disk_heap.toml"))
        .unwrap()
        .replace("radius = 10.0", "radius = -10.0");
    std::fs::write(&scene, &text).unwrap();
    let line = text.lines().position(|l| l.contains("radius = -10.0")).unwrap() + 1;
    let out = dir.join("out");
    let o = pbdda(&["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains(&format!("bad.toml:{line}:")) && err.contains("radius"), "{err}");
    assert!(!out.exists(), "no output directory for a scene that does not validate");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn check_prints_a_summary() {
    let o = pbdda(&["check", &example("7_2_block_staircase.toml")]);
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("bodies: 5 (0 disks, 0 rings, 5 polygons; 1 fixed, 0 deformable)"), "{text}");
    // d0 estimated as a tenth of the smallest feature: the 5 m floor edge
    assert!(text.contains("contact threshold d0: 0.5 m"), "{text}");
}

#[test]
fn quiet_run_prints_nothing() {
    let out = scratch("quiet");
    let o = pbdda(&["run", &example("7_1_disk_heap.toml"), "--out", out.to_str().unwrap(), "-q"]);
    assert!(o.status.success());
    assert_eq!(String::from_utf8_lossy(&o.stderr), "", "stderr with --quiet");
    assert_eq!(String::from_utf8_lossy(&o.stdout), "", "stdout with --quiet");
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn progress_is_plain_when_not_on_a_terminal() {
    let out = scratch("plain");
    let o = pbdda(&["run", &example("7_1_disk_heap.toml"), "--out", out.to_str().unwrap()]);
    assert!(o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!err.contains('\u{1b}') && !err.contains('\r'), "escape codes in piped output: {err:?}");
    // 100 steps: one line at each tenth, each shown once (a step prints at most one line)
    for k in 1..=10 {
        let tag = format!("step {}/100 ({} %)", 10 * k, 10 * k);
        assert_eq!(err.matches(&tag).count(), 1, "{tag} in {err}");
    }
    assert!(err.contains("completed 100 steps to t = 0.1 s"), "{err}");
    assert!(err.contains("warnings and events: none"), "{err}");
    assert!(err.contains(&format!("results in {}", out.display())), "{err}");
    let _ = std::fs::remove_dir_all(&out);
}

/// A reader of the terminal output that goes away (`pbdda run … 2>&1 | head -1`) does not stop
/// the run: with stdout and stderr pipes closed before it starts, `run` still takes all 100
/// steps of the §7.1 example, exits 0 and ends run.log with its `completed` line (before, the
/// first progress line panicked on the closed pipe: exit code 101, an empty run.log and a
/// truncated steps.csv).
#[test]
fn closed_output_pipes_do_not_stop_a_run() {
    use std::process::Stdio;
    let out = scratch("closed-pipes");
    let mut child = Command::new(env!("CARGO_BIN_EXE_pbdda"))
        .args(["run", &example("7_1_disk_heap.toml"), "--out", out.to_str().unwrap()])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    drop(child.stdout.take());
    drop(child.stderr.take());
    let status = child.wait().expect("it ends");
    assert!(status.success(), "exit status {status}");
    let log = std::fs::read_to_string(out.join("run.log")).expect("run.log");
    assert!(log.lines().last().is_some_and(|l| l.starts_with("completed 100 steps")), "run.log: {log}");
    let steps = std::fs::read_to_string(out.join("steps.csv")).expect("steps.csv");
    assert_eq!(steps.lines().count(), 101, "header and 100 steps");
}

/// The world makes contact records only for the steps whose state a run writes
/// (`Settings::contact_records`, set by `run` before each step). The §7.1 example (100 steps)
/// run with `output.every = 7` and with every step written: the sparse run's contacts.csv
/// holds exactly the rows the full run wrote for steps 7, 14, …, 98 and the last, 100 (15
/// steps); its bodies.csv and VTK file of step 7 are the full run's, and steps.csv's contacts
/// column (counted whether the records are made or not) is the same on all 100 steps. The
/// records do not feed the motion, so the rows agree byte for byte. (`steps_every = 1`: steps.csv
/// would otherwise follow `every`.)
#[test]
fn contact_records_only_on_written_steps() {
    let run = |name: &str, every: &str| {
        let out = scratch(name);
        let set = format!("output.every={every}");
        let o = pbdda(&[
            "run",
            &example("7_1_disk_heap.toml"),
            "--out",
            out.to_str().unwrap(),
            "-q",
            "--set",
            &set,
            "--set",
            "output.steps_every=1",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        out
    };
    let (full, sparse) = (run("records-full", "1"), run("records-sparse", "7"));
    let read = |dir: &Path, f: &str| std::fs::read_to_string(dir.join(f)).expect("file");
    let written = |step: usize| step.is_multiple_of(7) || step == 100;
    let rows_of = |text: String, keep: &dyn Fn(usize) -> bool| -> Vec<String> {
        let step = |l: &str| l.split(',').next().unwrap().parse::<usize>().unwrap();
        text.lines().skip(1).filter(|l| keep(step(l))).map(str::to_string).collect()
    };
    for file in ["contacts.csv", "bodies.csv"] {
        let want = rows_of(read(&full, file), &written);
        assert_eq!(rows_of(read(&sparse, file), &|_| true), want, "{file}");
    }
    assert_eq!(rows_of(read(&sparse, "contacts.csv"), &|_| true).len(), 15 * 3);
    let counts = |dir: &Path| -> Vec<String> {
        read(dir, "steps.csv").lines().skip(1).map(|l| l.split(',').nth(3).unwrap().to_string()).collect()
    };
    assert_eq!(counts(&sparse), counts(&full));
    assert_eq!(counts(&full).len(), 100);
    let vtu = |dir: &Path| std::fs::read(dir.join("vtk").join("step_000007.vtu")).expect("step 7's file");
    assert_eq!(vtu(&sparse), vtu(&full));
    for dir in [full, sparse] {
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// `pbdda cut` writes the expanded scene (which `check` accepts, with the same block count) and
/// the picture; it prints the block count and the smallest block. The tunnel example's count
/// is the model's number of bodies, which the expanded scene must keep.
#[test]
fn cut_writes_an_expanded_scene_and_a_picture() {
    let dir = scratch("cut");
    std::fs::create_dir_all(&dir).unwrap();
    let (out, png) = (dir.join("tunnel.toml"), dir.join("tunnel.png"));
    let o = pbdda(&[
        "cut",
        &example("tunnel_bolted.toml"),
        "--out",
        out.to_str().unwrap(),
        "--png",
        png.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let printed = String::from_utf8_lossy(&o.stdout).to_string();
    let model = pbdda::scene::load(Path::new(&example("tunnel_bolted.toml"))).unwrap();
    assert!(printed.contains(&format!("blocks: {}\n", model.bodies.len())), "{printed}");
    assert!(printed.contains("smallest block: blk-"), "{printed}");
    let expanded = pbdda::scene::load(&out).unwrap();
    assert_eq!(expanded.bodies.len(), model.bodies.len());
    assert_eq!(expanded.connectors.len(), model.connectors.len());
    assert!(std::fs::metadata(&png).unwrap().len() > 0);
    let o = pbdda(&["check", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}
