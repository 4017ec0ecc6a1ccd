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

/// A number as CSV text: shortest round-trip form, with an exponent for very small or very
/// large magnitudes (`1e-28` rather than 28 zeros), and no negative zero.
pub struct Num(pub f64);

impl std::fmt::Display for Num {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let x = self.0 + 0.0;
        let a = x.abs();
        if a != 0.0 && a.is_finite() && !(1e-4..1e15).contains(&a) {
            write!(f, "{x:e}")
        } else {
            write!(f, "{x}")
        }
    }
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
    pub fn create(
        dir: &Path,
        every: usize,
        last_step: usize,
        overwrite: bool,
    ) -> Result<CsvWriter, OutputError> {
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
        let (s, t) = (rec.step, Num(rec.time));
        writeln!(
            self.steps,
            "{s},{t},{},{},{},{},{},{},{}",
            Num(rec.dt),
            rec.contacts.len(),
            rec.outer_iterations,
            rec.inner_iterations,
            Num(rec.residual),
            Num(rec.kinetic_energy),
            Num(rec.wall_seconds)
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
        let (s, t) = (rec.step, Num(rec.time));
        for b in &world.bodies {
            let (c, v) = (b.centroid, b.velocity);
            let (x, y, rot) = (Num(c.x), Num(c.y), Num(b.rotation));
            write!(
                self.bodies,
                "{s},{t},{},{x},{y},{rot},{},{},{}",
                b.name,
                Num(v[0]),
                Num(v[1]),
                Num(v[2])
            )?;
            // a mesh body: centroid, mean rotation and velocity only (its elements go to VTK)
            if b.deformable && b.mesh.is_none() {
                for x in b.strain.iter().chain(b.stress.iter()) {
                    write!(self.bodies, ",{}", Num(*x))?;
                }
                writeln!(self.bodies)?;
            } else {
                writeln!(self.bodies, ",,,,,,")?;
            }
        }
        for c in &rec.contacts {
            let (a, b) = (&world.bodies[c.body_a].name, &world.bodies[c.body_b].name);
            let rolling = c.rolling_moment.map_or(String::new(), |m| Num(m).to_string());
            writeln!(
                self.contacts,
                "{s},{t},{a},{b},{},{},{},{},{},{},{},{rolling},{},{}",
                c.kind.as_str(),
                Num(c.point.x),
                Num(c.point.y),
                Num(c.normal.x),
                Num(c.normal.y),
                Num(c.normal_force),
                Num(c.shear_force),
                Num(c.gap),
                c.state.as_str()
            )?;
        }
        for (m, p) in world.model.monitors.iter().zip(&world.monitors) {
            let body = &world.bodies[p.body];
            let (u, v) = (p.current - p.initial, body.point_velocity(p.current));
            let (x, y) = (Num(p.current.x), Num(p.current.y));
            writeln!(
                self.monitors,
                "{s},{t},{},{x},{y},{},{},{},{}",
                m.name,
                Num(u.x),
                Num(u.y),
                Num(v.x),
                Num(v.y)
            )?;
        }
        Ok(())
    }

    /// Appends a line to `run.log`.
    pub fn log(&mut self, line: &str) -> Result<(), OutputError> {
        writeln!(self.log, "{line}").and_then(|_| self.log.flush()).map_err(io_err(&self.dir))
    }
}
