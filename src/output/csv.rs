//! The four CSV files of the output contract, written as the run goes: every row of a step
//! is flushed before the next step starts, so a crash loses at most the current step.

use crate::world::{StepRecord, World};
use std::fs::{self, File};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

/// Files a run writes into its output directory (`run.log` holds warnings and the outcome).
pub const OUTPUT_FILES: [&str; 5] = ["bodies.csv", "contacts.csv", "monitors.csv", "steps.csv", "run.log"];

#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum OutputError {
    #[error("{dir}: holds results of an earlier run ({file}); pass --overwrite to replace them")]
    #[diagnostic(help("choose another --out directory, or pass --overwrite"))]
    WouldMix { dir: PathBuf, file: String },
    #[error("{path}: {source}")]
    Io { path: PathBuf, source: io::Error },
}

fn io_err(path: &Path) -> impl FnOnce(io::Error) -> OutputError + '_ {
    move |source| OutputError::Io { path: path.to_path_buf(), source }
}

/// Writers for one run.
pub struct CsvWriter {
    dir: PathBuf,
    bodies: BufWriter<File>,
    contacts: BufWriter<File>,
    monitors: BufWriter<File>,
    steps: BufWriter<File>,
    log: BufWriter<File>,
    every: usize,
    last_step: usize,
}

impl CsvWriter {
    /// Creates `dir` if needed and the files with their headers. Refuses a directory that
    /// holds an earlier run's files unless `overwrite`.
    pub fn create(dir: &Path, every: usize, last_step: usize, overwrite: bool) -> Result<CsvWriter, OutputError> {
        fs::create_dir_all(dir).map_err(io_err(dir))?;
        for name in OUTPUT_FILES {
            let path = dir.join(name);
            if path.exists() {
                if !overwrite {
                    return Err(OutputError::WouldMix { dir: dir.to_path_buf(), file: name.to_string() });
                }
                fs::remove_file(&path).map_err(io_err(&path))?;
            }
        }
        let open = |name: &str, header: &str| -> Result<BufWriter<File>, OutputError> {
            let path = dir.join(name);
            let mut w = BufWriter::new(File::create(&path).map_err(io_err(&path))?);
            if !header.is_empty() {
                writeln!(w, "{header}").map_err(io_err(&path))?;
            }
            Ok(w)
        };
        Ok(CsvWriter {
            dir: dir.to_path_buf(),
            bodies: open(
                "bodies.csv",
                "step,time,body,x,y,rotation,vx,vy,omega,strain_x,strain_y,strain_xy,stress_x,stress_y,stress_xy",
            )?,
            contacts: open(
                "contacts.csv",
                "step,time,body_a,body_b,kind,x,y,nx,ny,normal_force,shear_force,rolling_moment,gap,state",
            )?,
            monitors: open("monitors.csv", "step,time,monitor,x,y,ux,uy,vx,vy")?,
            steps: open(
                "steps.csv",
                "step,time,dt,contacts,outer_iterations,inner_iterations,residual,kinetic_energy,wall_seconds",
            )?,
            log: open("run.log", "")?,
            every: every.max(1),
            last_step,
        })
    }

    /// Writes one step: always to `steps.csv`, to the other files on every N-th and the last step.
    pub fn write_step(&mut self, world: &World, rec: &StepRecord) -> Result<(), OutputError> {
        self.write_step_rows(world, rec).map_err(io_err(&self.dir))
    }

    fn write_step_rows(&mut self, world: &World, rec: &StepRecord) -> io::Result<()> {
        let (s, t) = (rec.step, rec.time);
        writeln!(
            self.steps,
            "{s},{t},{},{},{},{},{},{},{}",
            rec.dt,
            rec.contacts.len(),
            rec.outer_iterations,
            rec.inner_iterations,
            rec.residual,
            rec.kinetic_energy,
            rec.wall_seconds
        )?;
        for w in &rec.warnings {
            writeln!(self.log, "warning: {w}")?;
        }
        for e in &rec.events {
            writeln!(self.log, "event: {e}")?;
        }
        if s % self.every == 0 || s == self.last_step {
            self.write_state(world, rec)?;
        }
        for w in [&mut self.steps, &mut self.log, &mut self.bodies, &mut self.contacts, &mut self.monitors] {
            w.flush()?;
        }
        Ok(())
    }

    fn write_state(&mut self, world: &World, rec: &StepRecord) -> io::Result<()> {
        let (s, t) = (rec.step, rec.time);
        for b in &world.bodies {
            let (c, v) = (b.centroid, b.velocity);
            write!(self.bodies, "{s},{t},{},{},{},{},{},{},{}", b.name, c.x, c.y, b.rotation, v[0], v[1], v[2])?;
            if b.deformable {
                let (e, sg) = (b.strain, b.stress);
                writeln!(self.bodies, ",{},{},{},{},{},{}", e[0], e[1], e[2], sg[0], sg[1], sg[2])?;
            } else {
                writeln!(self.bodies, ",,,,,,")?;
            }
        }
        for c in &rec.contacts {
            let (a, b) = (&world.bodies[c.body_a].name, &world.bodies[c.body_b].name);
            let rolling = c.rolling_moment.map_or(String::new(), |m| m.to_string());
            writeln!(
                self.contacts,
                "{s},{t},{a},{b},{},{},{},{},{},{},{},{rolling},{},{}",
                c.kind.as_str(),
                c.point.x,
                c.point.y,
                c.normal.x,
                c.normal.y,
                c.normal_force,
                c.shear_force,
                c.gap,
                c.state.as_str()
            )?;
        }
        for (m, p) in world.model.monitors.iter().zip(&world.monitors) {
            let body = &world.bodies[p.body];
            let (u, v) = (p.current - p.initial, body.point_velocity(p.current));
            writeln!(self.monitors, "{s},{t},{},{},{},{},{},{},{}", m.name, p.current.x, p.current.y, u.x, u.y, v.x, v.y)?;
        }
        Ok(())
    }

    /// Appends a line to `run.log`.
    pub fn log(&mut self, line: &str) -> Result<(), OutputError> {
        writeln!(self.log, "{line}").and_then(|_| self.log.flush()).map_err(io_err(&self.dir))
    }
}
