//! `pbdda run SCENE --out DIR [--set KEY=VALUE]...`: run a scene, writing results as it goes.

use super::progress::{Progress, ProgressMode, RunSummary};
use crate::output::connectors::ConnectorWriter;
use crate::output::csv::{CsvWriter, OutputError};
use crate::output::results::write_geometry;
use crate::output::vtk::VtkWriter;
use crate::scene::{self, Override};
use crate::world::{StepRecord, World};
use miette::Result;
use std::path::Path;
use std::time::Instant;

/// Everything a run writes as it goes: the CSVs, the starting geometry (`geometry.csv`, for
/// `pbdda render`) and the ParaView time series (`vtk/`, unless `[output] vtk = false`).
struct Writers {
    csv: CsvWriter,
    connectors: ConnectorWriter,
    vtk: Option<VtkWriter>,
}

impl Writers {
    /// Creates the output directory's files; refuses an earlier run's files unless `overwrite`.
    fn create(out: &Path, world: &World, overwrite: bool) -> Result<Writers, OutputError> {
        let model = &world.model;
        let csv = CsvWriter::create(out, model.output.every, model.time.steps, overwrite)?;
        // after the CSV writer's overwrite check: the VTK writer clears DIR/vtk
        let connectors = ConnectorWriter::create(out, world, overwrite)?;
        write_geometry(out, world)?;
        let vtk = if model.output.vtk { Some(VtkWriter::create(out, world)?) } else { None };
        Ok(Writers { csv, connectors, vtk })
    }

    fn write_step(&mut self, world: &World, rec: &StepRecord) -> Result<(), OutputError> {
        self.csv.write_step(world, rec)?;
        self.connectors.write_step(world, rec)?;
        match &mut self.vtk {
            Some(vtk) => vtk.write_step(world, rec),
            None => Ok(()),
        }
    }

    fn log(&mut self, line: &str) -> Result<(), OutputError> {
        self.csv.log(line)
    }
}

pub(super) fn run(
    scene_path: &Path,
    out: &Path,
    overwrite: bool,
    quiet: bool,
    set: &[Override],
) -> Result<()> {
    // Validate everything before the first file is created.
    let model = scene::load_with(scene_path, set)?;
    let steps = model.time.steps;
    let mut world = World::new(model);
    let mut writers = Writers::create(out, &world, overwrite)?;
    if !set.is_empty() {
        let list: Vec<String> = set.iter().map(|o| o.to_string()).collect();
        writers.log(&format!("overrides: --set {}", list.join(" --set ")))?;
    }
    let mut progress = Progress::new(steps, ProgressMode::detect(quiet));
    let mut summary = RunSummary::default();
    let started = Instant::now();
    for _ in 0..steps {
        let rec = match world.step() {
            Ok(rec) => rec,
            Err(e) => {
                progress.finish();
                writers.log(&format!("failed: {e}"))?;
                return Err(e.into());
            }
        };
        summary.record(&rec);
        let events = rec.events.iter().map(|e| e.to_string());
        for line in rec.warnings.iter().map(|w| format!("warning: {w}")).chain(events) {
            progress.println(&line);
        }
        writers.write_step(&world, &rec)?;
        progress.step(&rec);
    }
    progress.finish();
    summary.wall_seconds = started.elapsed().as_secs_f64();
    writers.log(&summary.log_line())?;
    if !quiet {
        eprint!("{}", summary.text(out));
    }
    Ok(())
}
