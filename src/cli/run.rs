//! `pbdda run SCENE --out DIR [--set KEY=VALUE]... [--checkpoint-every N]`: run a scene,
//! writing results as it goes; `pbdda resume DIR`: continue a run from its checkpoint.
//!
//! SIGINT (Ctrl-C) and SIGTERM do not kill the run mid-write: the current step finishes, its
//! rows are written, `interrupted at step N` goes to run.log and the exit code is non-zero.

use super::progress::{Progress, ProgressMode, RunSummary};
use crate::checkpoint::Checkpoint;
use crate::output::connectors::ConnectorWriter;
use crate::output::csv::{CsvWriter, OutputError};
use crate::output::results::write_geometry;
use crate::output::vtk::VtkWriter;
use crate::scene::{self, Override};
use crate::world::{StepRecord, World};
use miette::{IntoDiagnostic, Result, miette};
use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// Everything a run writes as it goes: the CSVs, the starting geometry (`geometry.csv`, for
/// `pbdda render`) and the ParaView time series (`vtk/`, unless `[output] vtk = false`).
pub(crate) struct Writers {
    csv: CsvWriter,
    connectors: ConnectorWriter,
    vtk: Option<VtkWriter>,
}

impl Writers {
    /// Creates the output directory's files; refuses an earlier run's files unless `overwrite`.
    pub(crate) fn create(out: &Path, world: &World, overwrite: bool) -> Result<Writers, OutputError> {
        let model = &world.model;
        let csv = CsvWriter::create(out, model.output.every, model.time.steps, overwrite)?
            .steps_every(model.output.steps_every);
        // after the CSV writer's overwrite check: the VTK writer clears DIR/vtk
        let connectors = ConnectorWriter::create(out, world, overwrite)?;
        write_geometry(out, world)?;
        let vtk = if model.output.vtk { Some(VtkWriter::create(out, world)?) } else { None };
        Ok(Writers { csv, connectors, vtk })
    }

    /// One step's rows; `connectors.csv` and the VTK file before the CSV writer's files, whose
    /// `steps.csv` comes last, so that `steps.csv` never names a step whose rows are not all
    /// written. The VTK file is written on the second core while the CSV rows are formatted
    /// (whose halves then share the calling core: `micropool::join` runs a half itself when no
    /// worker is free).
    pub(crate) fn write_step(&mut self, world: &World, rec: &StepRecord) -> Result<(), OutputError> {
        self.connectors.write_step(world, rec)?;
        let (csv, vtk) = (&mut self.csv, &mut self.vtk);
        let (rows, file) = micropool::join(
            || csv.format_step(world, rec),
            || vtk.as_mut().map_or(Ok(()), |vtk| vtk.write_step(world, rec)),
        );
        rows.and(file)?;
        self.csv.commit_step()
    }

    /// Makes `step` the last step, always written (a run whose last stage ended early).
    pub(crate) fn finish_at(&mut self, step: usize) {
        self.csv.finish_at(step);
        self.connectors.finish_at(step);
        if let Some(vtk) = &mut self.vtk {
            vtk.finish_at(step);
        }
    }

    pub(crate) fn log(&mut self, line: &str) -> Result<(), OutputError> {
        self.csv.log(line)
    }

    /// Whether step `step` writes contacts (`contacts.csv` or a VTK file): the world makes the
    /// contact records of those steps only (`Settings::contact_records`).
    pub(crate) fn writes_contacts(&self, step: usize) -> bool {
        self.csv.writes_state(step) || self.vtk.as_ref().is_some_and(|vtk| vtk.writes(step))
    }
}

/// Set by SIGINT or SIGTERM; the run loop stops after the current step.
fn stop_flag() -> Arc<AtomicBool> {
    let flag = Arc::new(AtomicBool::new(false));
    let handler_flag = flag.clone();
    // fails only if a handler is already installed (a second run in the same process, as in
    // tests): that run then simply cannot be interrupted gracefully
    let _ = ctrlc::set_handler(move || handler_flag.store(true, Ordering::SeqCst));
    flag
}

/// How a run goes on: checkpoints, terminal output.
struct Plan<'a> {
    out: &'a Path,
    quiet: bool,
    /// The checkpoint to update every `every` steps (`--checkpoint-every N`, and resumed runs).
    checkpoint: Option<Checkpoint>,
}

pub(super) fn run(
    scene_path: &Path,
    out: &Path,
    (overwrite, quiet): (bool, bool),
    set: &[Override],
    checkpoint_every: Option<usize>,
) -> Result<()> {
    // Validate everything before the first file is created.
    let model = scene::load_with(scene_path, set)?;
    if checkpoint_every == Some(0) {
        return Err(miette!("--checkpoint-every must be at least 1"));
    }
    // the text as read, for the checkpoint (load_with has just read it)
    let source = match checkpoint_every {
        Some(_) => std::fs::read_to_string(scene_path).into_diagnostic()?,
        None => String::new(),
    };
    let mut world = World::new(model);
    let mut writers = Writers::create(out, &world, overwrite)?;
    if !set.is_empty() {
        let list: Vec<String> = set.iter().map(|o| o.to_string()).collect();
        writers.log(&format!("overrides: --set {}", list.join(" --set ")))?;
    }
    let checkpoint = checkpoint_every.map(|every| {
        let overrides = set.iter().map(|o| o.to_string()).collect();
        Checkpoint::new(&scene_path.display().to_string(), source.clone(), overrides, every)
    });
    drive(&mut world, &mut writers, Plan { out, quiet, checkpoint })
}

/// `pbdda resume DIR`: rebuilds the scene of `DIR/checkpoint.toml`, loads the state saved with
/// it (see [`crate::checkpoint`]), cuts the CSVs back to the checkpoint's step and goes on.
pub(super) fn resume(dir: &Path, quiet: bool) -> Result<()> {
    let checkpoint = Checkpoint::read(dir)?;
    let overrides = checkpoint
        .overrides
        .iter()
        .map(|s| s.parse::<Override>().map_err(|e| miette!("{}: --set {s}: {e}", dir.display())))
        .collect::<Result<Vec<_>>>()?;
    let model = scene::parse_with(&checkpoint.scene, &checkpoint.scene_file, &overrides)?;
    let mut world = checkpoint.load(dir, model)?;
    let m = &world.model;
    let csv = CsvWriter::reopen(dir, (m.output.every, m.output.steps_every), m.time.steps, checkpoint.step)?;
    // the ParaView series is not continued: its index would need the earlier frames' times
    let connectors = ConnectorWriter::reopen(dir, &world, checkpoint.step)?;
    let mut writers = Writers { csv, connectors, vtk: None };
    writers.log(&format!("resumed at step {} (vtk/ not continued)", checkpoint.step))?;
    drive(&mut world, &mut writers, Plan { out: dir, quiet, checkpoint: Some(checkpoint) })
}

/// The step loop from the world's current step to the last, with output, checkpoints and the
/// stop flag.
fn drive(world: &mut World, writers: &mut Writers, mut plan: Plan) -> Result<()> {
    let steps = world.model.time.steps;
    let stop = stop_flag();
    let mut progress = Progress::new(steps - world.step_index, ProgressMode::detect(plan.quiet));
    let mut summary = RunSummary::default();
    let started = Instant::now();
    while !world.finished() {
        world.settings.contact_records = writers.writes_contacts(world.step_index + 1);
        let rec = match world.step() {
            Ok(rec) => rec,
            Err(e) => {
                progress.finish();
                writers.log(&format!("failed: {e}"))?;
                return Err(e.into());
            }
        };
        summary.record(&rec);
        if world.finished() {
            writers.finish_at(rec.step);
        }
        let events = rec.events.iter().map(|e| e.to_string());
        for line in rec.warnings.iter().map(|w| format!("warning: {w}")).chain(events) {
            progress.println(&line);
        }
        writers.write_step(world, &rec)?;
        progress.step(&rec);
        if let Some(c) = &mut plan.checkpoint
            && rec.step % c.every == 0
        {
            c.save(plan.out, world)?;
        }
        if stop.load(Ordering::SeqCst) && !world.finished() {
            progress.finish();
            if let Some(c) = &mut plan.checkpoint {
                // resume goes on from here, not from the last multiple of `every`
                c.save(plan.out, world)?;
            }
            let line = format!("interrupted at step {}", rec.step);
            writers.log(&line)?;
            return Err(miette!("{line} (results up to it are in {})", plan.out.display()));
        }
    }
    progress.finish();
    if let Some(c) = &plan.checkpoint {
        // a finished run needs no restart file
        c.remove(plan.out)?;
    }
    summary.wall_seconds = started.elapsed().as_secs_f64();
    writers.log(&summary.log_line())?;
    if !plan.quiet {
        err!("{}", summary.text(plan.out));
    }
    Ok(())
}
