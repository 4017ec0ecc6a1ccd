//! [`VtkWriter`]: `DIR/vtk/scene.pvd` and the `.vtu` files of the written steps.

use super::{Grid, LEGEND, step_grid};
use crate::output::csv::OutputError;
use crate::world::{StepRecord, World};
use std::fs::{self, File};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// Writes `DIR/vtk/` as the run goes.
pub struct VtkWriter {
    dir: PathBuf,
    every: usize,
    last_step: usize,
    /// (time, file name) of the written steps.
    written: Vec<(f64, String)>,
    /// The last step's grid, whose storage the next one reuses.
    grid: Grid,
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> OutputError + '_ {
    move |source| OutputError::Io { path: path.to_path_buf(), source }
}

impl VtkWriter {
    /// Creates `DIR/vtk/` and removes the `.vtu`/`.pvd` files of an earlier run in it (call
    /// after [`crate::output::csv::CsvWriter::create`], which refuses to mix runs unless told to
    /// overwrite). Writes the empty time series.
    pub fn create(dir: &Path, world: &World) -> Result<VtkWriter, OutputError> {
        let dir = dir.join("vtk");
        fs::create_dir_all(&dir).map_err(io_err(&dir))?;
        for entry in fs::read_dir(&dir).map_err(io_err(&dir))? {
            let path = entry.map_err(io_err(&dir))?.path();
            let ours = path.extension().is_some_and(|e| e == "vtu" || e == "pvd" || e == "tmp");
            if ours {
                fs::remove_file(&path).map_err(io_err(&path))?;
            }
        }
        let out = &world.model.output;
        let w = VtkWriter {
            dir,
            every: out.every.max(1),
            last_step: world.model.time.steps,
            written: vec![],
            grid: Grid::default(),
        };
        w.write_pvd()?;
        Ok(w)
    }

    /// Path of the time series file.
    pub fn pvd_path(&self) -> PathBuf {
        self.dir.join("scene.pvd")
    }

    /// Writes the step's `.vtu` on every N-th and the last step (as the CSVs), then the
    /// updated `.pvd`.
    pub fn write_step(&mut self, world: &World, rec: &StepRecord) -> Result<(), OutputError> {
        let s = rec.step;
        if !self.writes(s) {
            return Ok(());
        }
        let mut grid = std::mem::take(&mut self.grid);
        step_grid(&mut grid, world, rec);
        let name = format!("step_{s:06}.vtu");
        let written = self.write_vtu(&grid, &name);
        self.grid = grid;
        written?;
        self.written.push((rec.time, name));
        self.write_pvd()
    }

    /// Makes `step` the last step, always written (a run whose last stage ended early).
    pub fn finish_at(&mut self, step: usize) {
        self.last_step = step;
    }

    /// Whether step `step` gets a file: every `every`-th step and the last.
    pub fn writes(&self, step: usize) -> bool {
        crate::output::written(step, self.every, self.last_step)
    }

    fn write_vtu(&self, grid: &Grid, name: &str) -> Result<(), OutputError> {
        let path = self.dir.join(name);
        let tmp = self.dir.join(format!("{name}.tmp"));
        let file = File::create(&tmp).map_err(io_err(&tmp))?;
        let mut w = BufWriter::with_capacity(1 << 16, file);
        grid.write_vtu(&mut w).map_err(io_err(&tmp))?;
        w.flush().map_err(io_err(&tmp))?;
        fs::rename(&tmp, &path).map_err(io_err(&path))
    }

    /// The collection file, written to a temporary file and renamed (atomic on one file
    /// system), so a reader never sees a half-written index.
    fn write_pvd(&self) -> Result<(), OutputError> {
        let path = self.pvd_path();
        let tmp = self.dir.join("scene.pvd.tmp");
        let mut text = String::from("<?xml version=\"1.0\"?>\n");
        text.push_str(&format!("<!-- pbdda time series; {LEGEND} -->\n"));
        text.push_str("<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n");
        text.push_str("  <Collection>\n");
        for (t, name) in &self.written {
            text.push_str(&format!(
                "    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{name}\"/>\n",
                crate::output::csv::Num(*t)
            ));
        }
        text.push_str("  </Collection>\n</VTKFile>\n");
        fs::write(&tmp, text).map_err(io_err(&tmp))?;
        fs::rename(&tmp, &path).map_err(io_err(&path))
    }
}
