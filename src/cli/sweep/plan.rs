//! A sweep beyond one process: `--plan DIR` writes the cases, `--run-plan DIR --shard I/N`
//! runs the cases whose index % N == I, `--collect DIR` merges their results.
//!
//! DIR holds `plan.toml` (the study: scene path, keys, values, options; the number of cases;
//! an FNV-1a 64-bit hash of the scene text and one of the scene text with the study), one
//! scene file per case `cases/case-NNNN.toml` (the scene with the case's overrides applied;
//! relative paths in it, such as a mesh's `file`, are those of the base scene's folder, where
//! it is read), and `results/case-NNNN.toml` for each finished case, written to a temporary
//! name and renamed, so that a file that exists is complete. A running case saves its state
//! every `--checkpoint-every` steps (default [`CHECKPOINT_EVERY`]) to `results/.case-NNNN.state`
//! (`crate::checkpoint`'s state file, with the case's running table), removed once its result
//! is written. A shard skips the cases that have a result and goes on with an interrupted case
//! from its state, so a shard that was stopped is completed by running it again, and its
//! results are those of a shard that was never stopped. Every shard
//! and the collector check the hashes: a plan whose scene changed since it was written is
//! refused. The collected report is computed from the result files exactly as the sequential
//! sweep computes it from its runs (the numbers are written with Rust's shortest round-trip
//! formatting and read back to the same bits), so sweep.csv is the same byte for byte except
//! the wall-time column.

use super::measure::{CaseCheckpoint, CaseResult, run_case};
use super::{Plan, Study, SweepReport};
use miette::{IntoDiagnostic, Result, miette};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// plan.toml.
#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct PlanFile {
    /// FNV-1a 64 of the scene text, hexadecimal.
    scene_hash: String,
    /// FNV-1a 64 of the scene text followed by the study as written here.
    plan_hash: String,
    /// Cases to run (the grid, and the reference case if it is not in the grid).
    cases: usize,
    study: Study,
}

/// FNV-1a, 64 bits (Fowler, Noll, Vo): a stable hash with no dependency.
fn fnv1a(bytes: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

fn plan_hash(source: &str, study: &Study) -> Result<String> {
    let text = toml::to_string(study).into_diagnostic()?;
    Ok(fnv1a(format!("{source}\n{text}").as_bytes()))
}

fn case_file(dir: &Path, i: usize) -> PathBuf {
    dir.join("cases").join(format!("case-{i:04}.toml"))
}

/// The state a running case saves (hidden: not a result).
fn state_file(dir: &Path, i: usize) -> PathBuf {
    dir.join("results").join(format!(".case-{i:04}.state"))
}

fn result_file(dir: &Path, i: usize) -> PathBuf {
    dir.join("results").join(format!("case-{i:04}.toml"))
}

/// Writes the plan of `study` into `dir`.
pub fn write_plan(dir: &Path, study: &Study) -> Result<()> {
    let scene = std::fs::canonicalize(&study.scene)
        .map_err(|e| miette!("{}: cannot read the scene: {e}", study.scene))?;
    let mut study = study.clone();
    study.scene = scene.display().to_string();
    let file = study.scene.clone();
    let source =
        std::fs::read_to_string(&scene).map_err(|e| crate::scene::SceneError::unreadable(&file, &e))?;
    let plan = Plan::new(&source, &file, &study.base()?, &study.sweep, &study.options(true)?)?;
    if dir.join("plan.toml").exists() {
        return Err(miette!("{}: holds a plan already; remove it or choose another folder", dir.display()));
    }
    std::fs::create_dir_all(dir.join("cases")).into_diagnostic()?;
    std::fs::create_dir_all(dir.join("results")).into_diagnostic()?;
    for (i, case) in plan.cases.iter().enumerate() {
        let text = crate::scene::overridden_text(&source, &file, &plan.overrides(i))?;
        let head = format!(
            "# case {i} of the sweep of {file}: {}\n# relative paths are those of the base scene's folder\n",
            case.label()
        );
        std::fs::write(case_file(dir, i), head + &text).into_diagnostic()?;
    }
    let plan_file = PlanFile {
        scene_hash: fnv1a(source.as_bytes()),
        plan_hash: plan_hash(&source, &study)?,
        cases: plan.cases.len(),
        study,
    };
    std::fs::write(dir.join("plan.toml"), toml::to_string(&plan_file).into_diagnostic()?)
        .into_diagnostic()?;
    outln!("wrote {} cases into {}", plan.cases.len(), dir.display());
    Ok(())
}

/// Reads plan.toml, checks the scene against its hashes, and rebuilds the plan.
fn load(dir: &Path) -> Result<(PlanFile, String, Plan)> {
    let path = dir.join("plan.toml");
    let text =
        std::fs::read_to_string(&path).map_err(|e| miette!("{}: not a sweep plan: {e}", path.display()))?;
    let plan_file: PlanFile = toml::from_str(&text).map_err(|e| miette!("{}: {e}", path.display()))?;
    let file = plan_file.study.scene.clone();
    let source =
        std::fs::read_to_string(&file).map_err(|e| crate::scene::SceneError::unreadable(&file, &e))?;
    let now = fnv1a(source.as_bytes());
    if now != plan_file.scene_hash {
        return Err(miette!(
            "{}: the plan was made from another scene: {file} has hash {now}, the plan {}; write the plan again",
            path.display(),
            plan_file.scene_hash
        ));
    }
    if plan_hash(&source, &plan_file.study)? != plan_file.plan_hash {
        return Err(miette!("{}: the study in it was changed after the plan was written", path.display()));
    }
    let s = &plan_file.study;
    let plan = Plan::new(&source, &file, &s.base()?, &s.sweep, &s.options(true)?)?;
    if plan.cases.len() != plan_file.cases {
        return Err(miette!(
            "{}: {} cases, but the study gives {}",
            path.display(),
            plan_file.cases,
            plan.cases.len()
        ));
    }
    Ok((plan_file, file, plan))
}

/// Number of cases of the plan in `dir` (checked as a shard checks it).
pub fn cases(dir: &Path) -> Result<usize> {
    Ok(load(dir)?.2.cases.len())
}

/// A running case saves its state every this many steps by default (`--checkpoint-every`).
pub const CHECKPOINT_EVERY: usize = 1000;

/// Runs the cases of shard `(i, n)` of the plan in `dir` that have no result yet, each saving
/// its state every [`CHECKPOINT_EVERY`] steps.
pub fn run_plan(dir: &Path, shard: (usize, usize), quiet: bool) -> Result<()> {
    run_plan_every(dir, shard, quiet, CHECKPOINT_EVERY)
}

/// [`run_plan`], the cases saving their state every `every` steps: a case interrupted after it
/// saved one goes on from it when the shard runs again.
pub fn run_plan_every(dir: &Path, (i, n): (usize, usize), quiet: bool, every: usize) -> Result<()> {
    if every == 0 {
        return Err(miette!("--checkpoint-every must be at least 1"));
    }
    let (_, file, plan) = load(dir)?;
    let (mut ran, mut skipped) = (0, 0);
    for (k, case) in plan.cases.iter().enumerate().filter(|(k, _)| k % n == i) {
        let target = result_file(dir, k);
        if target.exists() {
            skipped += 1;
            continue;
        }
        let path = case_file(dir, k);
        let text = std::fs::read_to_string(&path).map_err(|e| miette!("{}: {e}", path.display()))?;
        let model = crate::scene::parse(&text, &file)?;
        let state = state_file(dir, k);
        let checkpoint = CaseCheckpoint { path: state.clone(), every, scene: &text };
        let result = run_case(model, k, &case.label(), quiet, Some(&checkpoint));
        let tmp = dir.join("results").join(format!(".case-{k:04}.toml.{}", std::process::id()));
        std::fs::write(&tmp, toml::to_string(&result).into_diagnostic()?).into_diagnostic()?;
        std::fs::rename(&tmp, &target).into_diagnostic()?;
        match std::fs::remove_file(&state) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(e).into_diagnostic(),
            _ => {}
        }
        ran += 1;
    }
    if !quiet {
        errln!("shard {i}/{n} of {}: ran {ran} cases, skipped {skipped} finished", dir.display());
    }
    Ok(())
}

/// The report of the plan in `dir` from its result files; every case must have one.
pub fn collect(dir: &Path) -> Result<SweepReport> {
    let (_, _, plan) = load(dir)?;
    let mut results = Vec::new();
    let mut missing = Vec::new();
    for k in 0..plan.cases.len() {
        let path = result_file(dir, k);
        match std::fs::read_to_string(&path) {
            Ok(text) => {
                let r: CaseResult = toml::from_str(&text).map_err(|e| miette!("{}: {e}", path.display()))?;
                if r.index != k {
                    return Err(miette!("{}: holds case {}, not {k}", path.display(), r.index));
                }
                results.push(r);
            }
            Err(_) => missing.push(k.to_string()),
        }
    }
    if !missing.is_empty() {
        return Err(miette!(
            "{}: cases {} have no result yet; run `pbdda sweep --run-plan {} --shard I/N` for them",
            dir.display(),
            missing.join(", "),
            dir.display()
        ));
    }
    Ok(SweepReport::new(&plan, results))
}
