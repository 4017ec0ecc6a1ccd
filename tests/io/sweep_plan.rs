//! `pbdda sweep --plan / --run-plan --shard / --collect` and `--study` through the binary
//! (src/cli/sweep/plan.rs): the sharded sweep's sweep.csv equals the sequential one byte for
//! byte except the wall-time column (the cases are deterministic and their results are stored
//! with round-trip formatting); bad input is an error naming what is wrong.

use crate::common;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn example(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples").join(name).display().to_string()
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("pbdda-sweep-plan-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

fn pbdda(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pbdda")).args(args).output().expect("the binary runs")
}

fn ok(args: &[&str]) -> String {
    let o = pbdda(args);
    assert!(o.status.success(), "{args:?}: {}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn fails(args: &[&str]) -> String {
    let o = pbdda(args);
    assert!(!o.status.success(), "{args:?} should fail");
    common::one_line(&String::from_utf8_lossy(&o.stderr))
}

/// sweep.csv without its wall_seconds column.
fn without_wall(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let head: Vec<&str> = text.lines().next().expect("header").split(',').collect();
    let wall = head.iter().position(|c| *c == "wall_seconds").expect("a wall_seconds column");
    text.lines()
        .map(|l| {
            l.split(',').enumerate().filter(|(i, _)| *i != wall).map(|(_, c)| c).collect::<Vec<_>>().join(",")
        })
        .collect::<Vec<_>>()
        .join("\n")
}

const SWEEP: [&str; 5] = ["--set", "connector[*].strength=1e5,2e5,5e5", "--set", "time.steps=60", "-q"];

/// Three cases of the bolted slope over two shards (cases 0 and 2, then case 1) equal the
/// sequential sweep; a shard whose result was lost (as if killed before its rename) runs
/// that case alone again and the collection is unchanged.
#[test]
fn two_shards_equal_the_sequential_sweep() {
    let dir = tmp("shards");
    let scene = example("bolted_slope.toml");
    let (seq, plan) = (dir.join("seq"), dir.join("plan"));
    let mut args = vec!["sweep", &scene];
    args.extend(SWEEP);
    ok(&[&args[..], &["--out", seq.to_str().unwrap()]].concat());
    ok(&[&args[..], &["--plan", plan.to_str().unwrap()]].concat());
    assert_eq!(std::fs::read_dir(plan.join("cases")).expect("cases").count(), 3);
    let p = plan.to_str().unwrap();
    for shard in ["0/2", "1/2"] {
        ok(&["sweep", "--run-plan", p, "--shard", shard, "-q"]);
    }
    ok(&["sweep", "--collect", p]);
    let expected = without_wall(&seq.join("sweep.csv"));
    assert_eq!(expected.lines().count(), 4, "{expected}");
    assert_eq!(without_wall(&plan.join("sweep.csv")), expected);
    std::fs::remove_file(plan.join("results").join("case-0002.toml")).expect("a result");
    let log = ok(&["sweep", "--run-plan", p, "--shard", "0/2"]);
    assert!(log.contains("ran 1 cases, skipped 1 finished"), "{log}");
    ok(&["sweep", "--collect", p, "--out", dir.join("again").to_str().unwrap()]);
    assert_eq!(without_wall(&dir.join("again").join("sweep.csv")), expected);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A study file gives the same sweep as the command line.
#[test]
fn study_file_equals_the_command_line() {
    let dir = tmp("study");
    let study = dir.join("sweep.toml");
    let scene = example("bolted_slope.toml");
    let text = format!(
        "scene = {scene:?}\nout = \"from-study\"\nset = [\"time.steps=60\"]\n\n\
         [[sweep]]\nkey = \"connector[*].strength\"\nvalues = [1e5, 2e5, 5e5]\n"
    );
    std::fs::write(&study, text).expect("study file");
    ok(&["sweep", "--study", study.to_str().unwrap(), "-q"]);
    let cli = dir.join("cli");
    let mut args = vec!["sweep", &scene];
    args.extend(SWEEP);
    ok(&[&args[..], &["--out", cli.to_str().unwrap()]].concat());
    // the values column holds the TOML float 100000.0 where the command line has 1e5
    let from_study = without_wall(&dir.join("from-study").join("sweep.csv"));
    let from_cli = without_wall(&cli.join("sweep.csv"))
        .replace(",1e5,", ",100000.0,")
        .replace(",2e5,", ",200000.0,")
        .replace(",5e5,", ",500000.0,");
    assert_eq!(from_study, from_cli);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Bad input: each error names what is wrong.
#[test]
fn bad_plans_and_grids_are_errors() {
    let dir = tmp("bad");
    let scene = dir.join("slope.toml");
    std::fs::copy(example("bolted_slope.toml"), &scene).expect("copy");
    let (s, plan) = (scene.to_str().unwrap(), dir.join("plan"));
    let p = plan.to_str().unwrap();
    ok(&["sweep", s, "--set", "connector[*].strength=1e5,2e5", "--set", "time.steps=5", "--plan", p]);
    let e = fails(&["sweep", "--run-plan", p, "--shard", "2/2"]);
    assert!(e.contains("shard index 2 is out of range for 2 shards (0 to 1)"), "{e}");
    let e = fails(&["sweep", "--collect", p]);
    assert!(e.contains("cases 0, 1 have no result yet"), "{e}");
    std::fs::write(&scene, std::fs::read_to_string(&scene).unwrap() + "# edited\n").expect("edit");
    let e = fails(&["sweep", "--run-plan", p, "--shard", "0/1"]);
    assert!(e.contains("the plan was made from another scene"), "{e}");
    let e = fails(&["sweep", s, "--set", "time.steps=5"]);
    assert!(e.contains("empty grid"), "{e}");
    let e = fails(&["sweep", s, "--set", "time.steps=5,x"]);
    assert!(e.contains("case 1 (time.steps=x)") && e.contains("time.steps"), "{e}");
    let e = fails(&["sweep", s, "--set", "time.steps=5,6", "--set", "time.step=1e-3,2e-3,3e-3", "--zip"]);
    assert!(e.contains("`time.steps` has 2 values and `time.step` has 3"), "{e}");
    let e = fails(&["sweep", s, "--set", "material[*].density=1,2", "--set", "region[*].x=1,2"]);
    assert!(e.contains("`region[*]` matches nothing"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The shell lines of docs/studies.md's code block that follows `marker` (the recipes).
fn recipe(marker: &str) -> Vec<String> {
    let docs = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/studies.md"))
        .expect("docs/studies.md");
    let after = &docs[docs.find(marker).unwrap_or_else(|| panic!("no `{marker}` in docs/studies.md"))..];
    let block = after.split("```sh\n").nth(1).expect("a code block").split("```").next().expect("its end");
    block
        .lines()
        .map(|l| l.split(" #").next().unwrap_or(l).trim().to_owned())
        .filter(|l| !l.is_empty())
        .collect()
}

/// The number of finished cases of a plan (result files; not a killed shard's temporary file).
fn results(plan: &Path) -> usize {
    let names = std::fs::read_dir(plan.join("results")).expect("results").filter_map(|e| e.ok());
    names.filter(|e| e.file_name().to_string_lossy().starts_with("case-")).count()
}

/// Runs `line` with `sh -c` in `dir`, the binary's folder first on the PATH.
fn shell(dir: &Path, line: &str, env: &[(&str, String)]) {
    let bin = Path::new(env!("CARGO_BIN_EXE_pbdda")).parent().expect("bin dir").to_owned();
    let path = format!("{}:{}", bin.display(), std::env::var("PATH").unwrap_or_default());
    let o = Command::new("sh")
        .arg("-c")
        .arg(line)
        .current_dir(dir)
        .env("PATH", path)
        .envs(env.iter().map(|(k, v)| (k, v)))
        .output()
        .expect("sh runs");
    assert!(o.status.success(), "{line}: {}", String::from_utf8_lossy(&o.stderr));
}

/// The plan `dir/plan` of four bolt strengths (the recipes' shard counts divide the cases
/// unevenly or leave shards empty, both allowed) and the sequential sweep's sweep.csv.
fn plan_and_sequential(dir: &Path) -> String {
    let scene = example("bolted_slope.toml");
    let args =
        ["sweep", &scene, "--set", "connector[*].strength=1e5,2e5,5e5,1e6", "--set", "time.steps=60", "-q"];
    ok(&[&args[..], &["--out", dir.join("seq").to_str().unwrap()]].concat());
    ok(&[&args[..], &["--plan", dir.join("plan").to_str().unwrap()]].concat());
    without_wall(&dir.join("seq").join("sweep.csv"))
}

/// docs/studies.md's GNU parallel recipe, as written (with `parallel` when it is installed;
/// else its four shards as background jobs of a shell loop, what `parallel -j4` runs), and its
/// Slurm recipe's `--wrap` command once per array task (the variables Slurm sets): the
/// collected sweep.csv equals the sequential one but for wall times.
#[test]
fn documented_recipes_give_the_sequential_sweep() {
    let dir = tmp("recipes");
    let expected = plan_and_sequential(&dir);
    assert_eq!(expected.lines().count(), 5, "{expected}");
    let lines = recipe("GNU parallel on one machine");
    assert_eq!(lines.len(), 2, "{lines:?}");
    assert!(lines[0].starts_with("parallel -j4 ") && lines[0].ends_with("::: 0 1 2 3"), "{lines:?}");
    let has_parallel =
        Command::new("sh").args(["-c", "command -v parallel"]).output().is_ok_and(|o| o.status.success());
    let run = if has_parallel {
        lines[0].clone()
    } else {
        let command =
            lines[0].trim_start_matches("parallel -j4 ").trim_end_matches(" ::: 0 1 2 3").replace("{}", "$i");
        format!("for i in 0 1 2 3; do {command} & done; wait")
    };
    shell(&dir, &run, &[]);
    assert_eq!(results(&dir.join("plan")), 4);
    shell(&dir, &lines[1], &[]);
    assert_eq!(without_wall(&dir.join("plan").join("sweep.csv")), expected);

    // Slurm: the array's tasks each run the --wrap command with their task id
    let slurm = recipe("A Slurm job");
    let wrap = slurm[1].split("--wrap '").nth(1).and_then(|w| w.strip_suffix('\'')).expect("--wrap '...'");
    std::fs::remove_dir_all(dir.join("plan/results")).expect("clear results");
    std::fs::create_dir_all(dir.join("plan/results")).expect("results dir");
    for task in 0..3 {
        let env = [("SLURM_ARRAY_TASK_ID", task.to_string()), ("SLURM_ARRAY_TASK_COUNT", "3".to_owned())];
        shell(&dir, wrap, &env);
    }
    shell(&dir, "pbdda sweep --collect plan --out slurm -q", &[]);
    assert_eq!(without_wall(&dir.join("slurm").join("sweep.csv")), expected);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A shard killed (SIGKILL) while a case runs, after the first case finished, and run again:
/// it skips the finished case, runs the others, and the collection equals the sequential sweep
/// but for wall times. (The killed case left no result: results are renamed into place whole.)
#[test]
fn killed_shard_rerun_completes() {
    let dir = tmp("killed");
    let expected = plan_and_sequential(&dir);
    let plan = dir.join("plan");
    let p = plan.to_str().unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_pbdda"))
        .args(["sweep", "--run-plan", p, "--shard", "0/1", "-q"])
        .spawn()
        .expect("spawn");
    let first = plan.join("results").join("case-0000.toml");
    while !first.exists() {
        assert!(child.try_wait().expect("wait").is_none(), "the shard ended before its first result");
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    child.kill().expect("kill");
    child.wait().expect("reap");
    let done = results(&plan);
    assert!(done < 4, "the shard finished before it was killed");
    let log = ok(&["sweep", "--run-plan", p, "--shard", "0/1"]);
    assert!(log.contains(&format!("ran {} cases, skipped {done} finished", 4 - done)), "{log}");
    ok(&["sweep", "--collect", p, "-q"]);
    assert_eq!(without_wall(&plan.join("sweep.csv")), expected);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A case killed (SIGKILL) after it saved its state (`--checkpoint-every 20`) goes on from that
/// state when the shard runs again (its progress line names the step), and the collection
/// equals the sequential sweep but for wall times: the resumed case's monitors, peak forces,
/// connector states and iteration counts are those of a case that ran through (the state is
/// the world's, bit for bit, plus the running maxima; src/cli/sweep/measure.rs). A kill that
/// lands after the case finished proves nothing, so the shard is started again until one lands
/// while the case runs (400 steps of the bolted slope against a state every 20).
#[test]
fn a_killed_case_resumes_from_its_state() {
    let dir = tmp("resumed");
    let scene = example("bolted_slope.toml");
    let args = ["sweep", &scene, "--set", "connector[*].strength=1e5,5e5", "--set", "time.steps=400", "-q"];
    ok(&[&args[..], &["--out", dir.join("seq").to_str().unwrap()]].concat());
    ok(&[&args[..], &["--plan", dir.join("plan").to_str().unwrap()]].concat());
    let expected = without_wall(&dir.join("seq").join("sweep.csv"));
    let plan = dir.join("plan");
    let p = plan.to_str().unwrap();
    let (state, result) = (plan.join("results/.case-0000.state"), plan.join("results/case-0000.toml"));
    let mut landed = false;
    for _ in 0..5 {
        let mut child = Command::new(env!("CARGO_BIN_EXE_pbdda"))
            .args(["sweep", "--run-plan", p, "--shard", "0/1", "--checkpoint-every", "20", "-q"])
            .spawn()
            .expect("spawn");
        while !state.exists() && child.try_wait().expect("wait").is_none() {
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        child.kill().ok();
        child.wait().expect("reap");
        if state.exists() && !result.exists() {
            landed = true;
            break;
        }
        std::fs::remove_dir_all(plan.join("results")).expect("clear results");
        std::fs::create_dir_all(plan.join("results")).expect("results dir");
    }
    assert!(landed, "no kill landed while case 0 ran");
    let log = ok(&["sweep", "--run-plan", p, "--shard", "0/1", "--checkpoint-every", "20"]);
    assert!(log.contains("case 0 (") && log.contains("400 steps, resumed at step "), "{log}");
    assert!(log.contains("ran 2 cases, skipped 0 finished"), "{log}");
    assert!(!state.exists(), "the state of a finished case is removed");
    ok(&["sweep", "--collect", p, "-q"]);
    assert_eq!(without_wall(&plan.join("sweep.csv")), expected);
    let _ = std::fs::remove_dir_all(&dir);
}
