//! `connectors.csv` (scene-format contract): one row per written step and connector, only for a
//! scene with connectors. A broken connector is written once more, at the step it broke (state
//! `broken`, with the axial force it broke at; it transmits nothing in the step it breaks in),
//! then no longer. The row of the step in which a connector breaks or starts to yield is written
//! whatever `[output] every` is. A bolt's `plastic_strain` is its accumulated plastic strain
//! (math note §6.1; empty for other kinds). `anchor_a_x` .. `anchor_b_y` are the anchors'
//! positions in the current configuration (where the bodies are at the end of the step, for a
//! broken connector the step it broke in): the line to draw the connector on.

use super::csv::{Num, OutputError};
use super::rows::RowFile;
use crate::connector::Connector;
use crate::world::{StepRecord, World};
use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

pub const FILE: &str = "connectors.csv";
pub(crate) const HEADER: &str = "step,time,connector,kind,body_a,body_b,length,axial_force,shear_force,moment_a,moment_b,state,plastic_strain,anchor_a_x,anchor_a_y,anchor_b_x,anchor_b_y";

pub struct ConnectorWriter {
    path: PathBuf,
    out: Option<RowFile>,
    every: usize,
    last_step: usize,
}

impl ConnectorWriter {
    /// Creates `DIR/connectors.csv` when the world has connectors. An earlier run's file is
    /// refused unless `overwrite` (then removed, even when this scene has no connectors).
    pub fn create(dir: &Path, world: &World, overwrite: bool) -> Result<ConnectorWriter, OutputError> {
        let path = dir.join(FILE);
        let io_err = |source| OutputError::Io { path: path.clone(), source };
        if path.exists() {
            if !overwrite {
                return Err(OutputError::WouldMix { dir: dir.to_path_buf(), file: FILE.to_string() });
            }
            fs::remove_file(&path).map_err(io_err)?;
        }
        let out = if world.connectors.is_empty() {
            None
        } else {
            Some(RowFile::create(&path, HEADER).map_err(io_err)?)
        };
        let every = world.model.output.every.max(1);
        Ok(ConnectorWriter { path, out, every, last_step: world.model.time.steps })
    }

    /// Reopens `DIR/connectors.csv` of an interrupted run for `pbdda resume`: rows after `step`
    /// (and a cut last row) are dropped, and new rows are appended.
    pub fn reopen(dir: &Path, world: &World, step: usize) -> Result<ConnectorWriter, OutputError> {
        let path = dir.join(FILE);
        let io_err = |source| OutputError::Io { path: path.clone(), source };
        let out = if world.connectors.is_empty() {
            None
        } else {
            Some(RowFile::reopen(&path, Some(step)).map_err(io_err)?)
        };
        let every = world.model.output.every.max(1);
        Ok(ConnectorWriter { path, out, every, last_step: world.model.time.steps })
    }

    /// Makes `step` the last step, always written (a run whose last stage ended early).
    pub fn finish_at(&mut self, step: usize) {
        self.last_step = step;
    }

    pub fn write_step(&mut self, world: &World, rec: &StepRecord) -> Result<(), OutputError> {
        let Some(out) = &mut self.out else { return Ok(()) };
        let s = rec.step;
        // an event row: broke or started to yield in this step
        let event = |c: &&Connector| c.broken_at == Some(s) || c.yielded_at == Some(s);
        let every_row = super::written(s, self.every, self.last_step);
        if !every_row && !world.connectors.iter().any(|c| event(&c)) {
            return Ok(());
        }
        let io_err = |source| OutputError::Io { path: self.path.clone(), source };
        let listed = |c: &&Connector| if every_row { !c.broken || c.broken_at == Some(s) } else { event(c) };
        for c in world.connectors.iter().filter(listed) {
            row(&mut out.rows, world, (rec.step, rec.time), c).map_err(io_err)?;
        }
        out.commit().map_err(io_err)
    }
}

/// One row of `connectors.csv` for connector `c` at step and time `at`.
pub(crate) fn row(w: &mut Vec<u8>, world: &World, at: (usize, f64), c: &Connector) -> io::Result<()> {
    let name = |b: usize| world.bodies[b].name.as_str();
    let opt = |x: Option<f64>| x.map_or(String::new(), |v| Num(v).to_string());
    let (axial, shear, moments, state) = if c.broken {
        (c.broke_with.unwrap_or(0.0), None, None, "broken")
    } else {
        let state = if c.is_yielding() { "yielding" } else { "intact" };
        (c.axial_force(), c.shear_force(), c.end_moments(), state)
    };
    let plastic = c.strain().map(|_| c.plastic_strain);
    writeln!(
        w,
        "{},{},{},{},{},{},{},{},{},{},{},{state},{},{},{},{},{}",
        at.0,
        Num(at.1),
        c.name,
        c.kind.as_str(),
        name(c.bodies[0]),
        name(c.bodies[1]),
        Num(c.length()),
        Num(axial),
        opt(shear),
        opt(moments.map(|m| m[0])),
        opt(moments.map(|m| m[1])),
        opt(plastic),
        Num(c.anchors[0].x),
        Num(c.anchors[0].y),
        Num(c.anchors[1].x),
        Num(c.anchors[1].y),
    )
}
