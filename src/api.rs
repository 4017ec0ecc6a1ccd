//! A simulation stepped by its caller, for scripting (the Python package in `python/`): the
//! state as the rows of the CSV tables of the output contract (docs/scene-format.md, Outputs),
//! formatted by the same functions that write `bodies.csv`, `contacts.csv` and
//! `connectors.csv`, and, when asked, the results folder that `pbdda run` writes.
//!
//! ```no_run
//! use pbdda::api::{Simulation, Table};
//! let mut sim = Simulation::load(std::path::Path::new("examples/7_1_disk_heap.toml"), &[])?;
//! sim.step()?;
//! println!("{}", sim.table(Table::Bodies));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::cli::RunSummary;
use crate::cli::run::Writers;
use crate::error::SceneError;
use crate::model::Model;
use crate::output::csv::{HEADERS, OutputError, body_row, contact_row, monitor_rows};
use crate::scene::{self, Override};
use crate::world::{StepError, StepRecord, World};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// A table of the output contract.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Table {
    /// `bodies.csv`: one row per body (bodies removed by a stage are not listed).
    Bodies,
    /// `contacts.csv`: one row per contact of the last step (none before the first step).
    Contacts,
    /// `connectors.csv`: one row per connector; a broken one only in the step it broke, as
    /// the file lists it.
    Connectors,
    /// `monitors.csv`: one row per `[[monitor]]` point.
    Monitors,
}

impl Table {
    /// The table of a file name without `.csv`: `bodies`, `contacts` or `connectors`.
    pub fn named(name: &str) -> Option<Table> {
        match name {
            "bodies" => Some(Table::Bodies),
            "contacts" => Some(Table::Contacts),
            "connectors" => Some(Table::Connectors),
            "monitors" => Some(Table::Monitors),
            _ => None,
        }
    }

    /// The CSV header row (column names, comma separated).
    pub fn header(self) -> &'static str {
        match self {
            Table::Bodies => HEADERS[0].1,
            Table::Contacts => HEADERS[1].1,
            Table::Connectors => crate::output::connectors::HEADER,
            Table::Monitors => HEADERS[2].1,
        }
    }
}

/// Why a step of a [`Simulation`] failed.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum ApiError {
    #[error(transparent)]
    Step(#[from] StepError),
    #[error(transparent)]
    Output(#[from] OutputError),
}

/// What a simulation that writes its results keeps: the writers of `pbdda run`'s files and
/// the totals of run.log's last line.
struct Output {
    writers: Writers,
    summary: RunSummary,
    dir: PathBuf,
    /// Wall time of the steps so far.
    wall: f64,
    /// run.log has its closing line.
    closed: bool,
}

/// A world and its last step's record; optionally writing the results folder as it steps.
pub struct Simulation {
    pub world: World,
    last: Option<StepRecord>,
    output: Option<Output>,
    /// The overrides the scene was read with, as `--set` takes them (logged in run.log).
    overrides: Vec<String>,
}

impl Simulation {
    pub fn new(model: Model) -> Simulation {
        Simulation { world: World::new(model), last: None, output: None, overrides: Vec::new() }
    }

    /// The scene file at `path` with `--set` overrides.
    pub fn load(path: &Path, set: &[Override]) -> Result<Simulation, SceneError> {
        let mut sim = Simulation::new(scene::load_with(path, set)?);
        sim.overrides = set.iter().map(|o| o.to_string()).collect();
        Ok(sim)
    }

    /// The scene text `source` (named `file` in errors; relative paths in it are those of
    /// `file`'s folder) with `--set` overrides.
    pub fn parse(source: &str, file: &str, set: &[Override]) -> Result<Simulation, SceneError> {
        let mut sim = Simulation::new(scene::parse_with(source, file, set)?);
        sim.overrides = set.iter().map(|o| o.to_string()).collect();
        Ok(sim)
    }

    /// From now on, write every step into `dir` as `pbdda run --out dir` does (the CSVs,
    /// geometry.csv, run.log and the ParaView series). Only before the first step, so that
    /// the folder holds the whole run; `overwrite` as `--overwrite`.
    pub fn write_to(&mut self, dir: &Path, overwrite: bool) -> Result<(), String> {
        if self.world.step_index > 0 {
            return Err(format!(
                "{}: results are written from the first step on, and this simulation is at step {}",
                dir.display(),
                self.world.step_index
            ));
        }
        if self.output.is_some() {
            return Err(format!("{}: this simulation writes its results already", dir.display()));
        }
        let mut writers = Writers::create(dir, &self.world, overwrite).map_err(|e| e.to_string())?;
        if !self.overrides.is_empty() {
            // run.log's record of the overrides, as `pbdda run` writes it
            let line = format!("overrides: --set {}", self.overrides.join(" --set "));
            writers.log(&line).map_err(|e| e.to_string())?;
        }
        let output =
            Output { writers, summary: RunSummary::default(), dir: dir.into(), wall: 0.0, closed: false };
        self.output = Some(output);
        Ok(())
    }

    /// Whether the run has reached its end (`time.steps`, or a last stage that ended early).
    pub fn finished(&self) -> bool {
        self.world.finished()
    }

    /// One step (nothing once [`Simulation::finished`]); returns whether a step was taken.
    /// A failed step is written to run.log as `pbdda run` writes it; a failed write of the
    /// results is an error too.
    pub fn step(&mut self) -> Result<bool, ApiError> {
        if self.world.finished() {
            return Ok(false);
        }
        self.world.settings.contact_records = true;
        let started = Instant::now();
        let rec = match self.world.step() {
            Ok(rec) => rec,
            Err(e) => {
                if let Some(out) = &mut self.output {
                    let _ = out.writers.log(&format!("failed: {e}"));
                    out.closed = true;
                }
                return Err(e.into());
            }
        };
        if let Some(out) = &mut self.output {
            out.summary.record(&rec);
            if self.world.finished() {
                out.writers.finish_at(rec.step);
            }
            out.writers.write_step(&self.world, &rec)?;
            out.wall += started.elapsed().as_secs_f64();
        }
        self.last = Some(rec);
        if self.world.finished() {
            self.close()?;
        }
        Ok(true)
    }

    /// Writes run.log's closing line (`completed N steps ...`) if the results are written and
    /// it is not there yet; done by the last step at the end of the run.
    pub fn close(&mut self) -> Result<(), OutputError> {
        let Some(out) = &mut self.output else { return Ok(()) };
        if out.closed {
            return Ok(());
        }
        out.closed = true;
        out.summary.wall_seconds = out.wall;
        let line = out.summary.log_line();
        out.writers.log(&line)
    }

    /// The results folder, if the simulation writes one.
    pub fn output_dir(&self) -> Option<&Path> {
        self.output.as_ref().map(|o| o.dir.as_path())
    }

    /// The last step's record (none before the first step).
    pub fn last_record(&self) -> Option<&StepRecord> {
        self.last.as_ref()
    }

    /// The table's rows for the current state, with its header: the text `pbdda run` writes
    /// for this step into the table's file (the digits of a row may differ where the file
    /// pads a row to a 4096-byte boundary, `output::rows`, never the values).
    pub fn table(&self, table: Table) -> String {
        let world = &self.world;
        let (step, time) = (world.step_index, world.time);
        let mut out = Vec::new();
        out.extend_from_slice(table.header().as_bytes());
        out.push(b'\n');
        let head = format!("{step},{},", crate::output::csv::Num(time));
        // writes into a Vec<u8> cannot fail
        let _ = match table {
            Table::Bodies => (world.bodies.iter().enumerate())
                .filter(|&(b, _)| !world.is_removed(b))
                .try_for_each(|(_, body)| body_row(&mut out, head.as_bytes(), body)),
            Table::Contacts => (self.last.iter().flat_map(|r| &r.contacts))
                .try_for_each(|c| contact_row(&mut out, head.as_bytes(), world, c)),
            Table::Connectors => (world.connectors.iter())
                .filter(|c| !c.broken || c.broken_at == Some(step))
                .try_for_each(|c| crate::output::connectors::row(&mut out, world, (step, time), c)),
            Table::Monitors => monitor_rows(&mut out, head.as_bytes(), world),
        };
        String::from_utf8_lossy(&out).into_owned()
    }
}
