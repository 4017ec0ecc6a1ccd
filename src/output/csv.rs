//! The four CSV files of the output contract, written as the run goes. Each step's rows are
//! formatted into one buffer per file and written with one write, laid out so that a killed run
//! leaves no cut row ([`super::rows`]), in the order bodies.csv, contacts.csv, monitors.csv and
//! steps.csv last: `steps.csv` never runs ahead of the state files, so its last row names a
//! step whose rows are all written.

use super::rows::RowFile;
use crate::body::Body;
use crate::world::{ContactRecord, StepRecord, World};
use std::fs;
use std::io::{self, Write};
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
/// large magnitudes (`1e-28` rather than 28 zeros), and no negative zero (a row may be written
/// with more digits of the same values: [`super::rows`]).
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
    bodies: RowFile,
    contacts: RowFile,
    monitors: RowFile,
    steps: RowFile,
    log: RowFile,
    every: usize,
    steps_every: usize,
    last_step: usize,
    /// The second half's rows while they are formatted ([`in_halves`]).
    spare: Vec<u8>,
}

/// Column headers of the four CSV files.
pub(crate) const HEADERS: [(&str, &str); 4] = [
    (
        "bodies.csv",
        "step,time,body,x,y,rotation,vx,vy,omega,strain_x,strain_y,strain_xy,stress_x,stress_y,stress_xy",
    ),
    (
        "contacts.csv",
        "step,time,body_a,body_b,kind,x,y,nx,ny,normal_force,shear_force,rolling_moment,gap,state,interface",
    ),
    ("monitors.csv", "step,time,monitor,x,y,ux,uy,vx,vy,stress_x,stress_y,stress_xy"),
    (
        "steps.csv",
        "step,time,dt,contacts,outer_iterations,inner_iterations,residual,method,kinetic_energy,stage,wall_seconds",
    ),
];

impl CsvWriter {
    /// Creates `dir` if needed and the files with their headers. Refuses a directory that
    /// holds an earlier run's files unless `overwrite`. `every` is the `[output]` key (see
    /// [`CsvWriter::steps_every`] for `steps.csv`); `last_step` is always written.
    pub fn create(
        dir: &Path,
        every: usize,
        last_step: usize,
        overwrite: bool,
    ) -> Result<CsvWriter, OutputError> {
        fs::create_dir_all(dir).map_err(io_err(dir))?;
        let earlier: Vec<&str> = OUTPUT_FILES.into_iter().filter(|name| dir.join(name).exists()).collect();
        if let (Some(name), false) = (earlier.first(), overwrite) {
            return Err(OutputError::WouldMix { dir: dir.to_path_buf(), file: name.to_string() });
        }
        // steps.csv before the state files: a run killed while replacing them never leaves an
        // earlier steps.csv beside newer, shorter state files
        for name in earlier.into_iter().rev() {
            let path = dir.join(name);
            fs::remove_file(&path).map_err(io_err(&path))?;
        }
        let open = |name: &str, header: &str| -> Result<RowFile, OutputError> {
            let path = dir.join(name);
            RowFile::create(&path, header).map_err(io_err(&path))
        };
        let [bodies, contacts, monitors, steps] = HEADERS.map(|(name, header)| open(name, header));
        Ok(CsvWriter {
            dir: dir.to_path_buf(),
            bodies: bodies?,
            contacts: contacts?,
            monitors: monitors?,
            steps: steps?,
            log: open("run.log", "")?,
            every: every.max(1),
            steps_every: 1,
            last_step,
            spare: Vec::new(),
        })
    }

    /// Writes a `steps.csv` row every `n`-th step only (`[output] steps_every`; default 1).
    pub fn steps_every(mut self, n: usize) -> CsvWriter {
        self.steps_every = n.max(1);
        self
    }

    /// Reopens the files of an interrupted run for appending (`pbdda resume`), first cutting
    /// each CSV back to its rows of steps up to `step`, the checkpoint's step (a run killed
    /// after its checkpoint wrote later rows, which the resumed run writes again).
    pub fn reopen(
        dir: &Path,
        (every, steps_every): (usize, usize),
        last_step: usize,
        step: usize,
    ) -> Result<CsvWriter, OutputError> {
        let open = |name: &str, cut: bool| -> Result<RowFile, OutputError> {
            let path = dir.join(name);
            RowFile::reopen(&path, cut.then_some(step)).map_err(io_err(&path))
        };
        Ok(CsvWriter {
            dir: dir.to_path_buf(),
            bodies: open("bodies.csv", true)?,
            contacts: open("contacts.csv", true)?,
            monitors: open("monitors.csv", true)?,
            steps: open("steps.csv", true)?,
            log: open("run.log", false)?,
            every: every.max(1),
            steps_every: steps_every.max(1),
            last_step,
            spare: Vec::new(),
        })
    }

    /// Writes one step: to `steps.csv` on every `steps_every`-th step, to the other files on every
    /// `every`-th step, both on the last step.
    pub fn write_step(&mut self, world: &World, rec: &StepRecord) -> Result<(), OutputError> {
        self.format_step(world, rec)?;
        self.commit_step()
    }

    /// [`CsvWriter::write_step`]'s first half: the step's rows, formatted and not yet written.
    pub fn format_step(&mut self, world: &World, rec: &StepRecord) -> Result<(), OutputError> {
        self.format_rows(world, rec).map_err(io_err(&self.dir))
    }

    /// [`CsvWriter::write_step`]'s second half: writes the rows [`CsvWriter::format_step`]
    /// formatted, `steps.csv` last, so that it never names a step whose state rows are not all
    /// written.
    pub fn commit_step(&mut self) -> Result<(), OutputError> {
        [&mut self.bodies, &mut self.contacts, &mut self.monitors, &mut self.steps, &mut self.log]
            .into_iter()
            .try_for_each(RowFile::commit)
            .map_err(io_err(&self.dir))
    }

    fn format_rows(&mut self, world: &World, rec: &StepRecord) -> io::Result<()> {
        let s = rec.step;
        if super::written(s, self.steps_every, self.last_step) {
            let stage = world.model.stages.get(rec.stage).map_or("", |s| s.name.as_str());
            self.steps_row(rec, stage)?;
        }
        for w in &rec.warnings {
            writeln!(self.log.rows, "warning: {w}")?;
        }
        for e in &rec.events {
            writeln!(self.log.rows, "event: {e}")?;
        }
        for h in &rec.handovers {
            writeln!(self.log.rows, "hand-over: {h}")?;
        }
        if self.writes_state(s) {
            self.write_state(world, rec)?;
        }
        Ok(())
    }

    /// Whether step `step`'s state (bodies, contacts, monitors) is written: every `every`-th
    /// step and the last.
    pub fn writes_state(&self, step: usize) -> bool {
        super::written(step, self.every, self.last_step)
    }

    fn steps_row(&mut self, rec: &StepRecord, stage: &str) -> io::Result<()> {
        let (s, t) = (rec.step, Num(rec.time));
        writeln!(
            self.steps.rows,
            "{s},{t},{},{},{},{},{},{},{},{stage},{}",
            Num(rec.dt),
            rec.contact_count,
            rec.outer_iterations,
            rec.inner_iterations,
            Num(rec.residual),
            rec.method.map_or("none", |m| m.name()),
            Num(rec.kinetic_energy),
            Num(rec.wall_seconds)
        )
    }

    fn write_state(&mut self, world: &World, rec: &StepRecord) -> io::Result<()> {
        // the step and time open every row: formatted once
        let head = format!("{},{},", rec.step, Num(rec.time));
        let head = head.as_bytes();
        let spare = &mut self.spare;
        if world.stage.removed.is_empty() {
            in_halves(&world.bodies, &mut self.bodies.rows, spare, |out, b| body_row(out, head, b))?;
        } else {
            // bodies removed by a stage are no longer written (math note §10.14)
            let live: Vec<&Body> = (world.bodies.iter().enumerate())
                .filter(|&(b, _)| !world.is_removed(b))
                .map(|(_, body)| body)
                .collect();
            in_halves(&live, &mut self.bodies.rows, spare, |out, b| body_row(out, head, b))?;
        }
        in_halves(&rec.contacts, &mut self.contacts.rows, spare, |out, c| contact_row(out, head, world, c))?;
        monitor_rows(&mut self.monitors.rows, head, world)
    }

    /// Makes `step` the last step, always written (a run whose last stage ended early).
    pub fn finish_at(&mut self, step: usize) {
        self.last_step = step;
    }

    /// Appends a line to `run.log`.
    pub fn log(&mut self, line: &str) -> Result<(), OutputError> {
        writeln!(self.log.rows, "{line}").and_then(|_| self.log.commit()).map_err(io_err(&self.dir))
    }
}

/// Rows from `HALVES_FROM` items on are formatted in two halves, one per core: the first into
/// `out`, the second into `spare`, then appended, so the text is the same either way.
const HALVES_FROM: usize = 2048;

/// Appends `row(item)` for every item to `out`, in order.
fn in_halves<T: Sync>(
    items: &[T],
    out: &mut Vec<u8>,
    spare: &mut Vec<u8>,
    row: impl Fn(&mut Vec<u8>, &T) -> io::Result<()> + Sync,
) -> io::Result<()> {
    if items.len() < HALVES_FROM {
        return items.iter().try_for_each(|it| row(out, it));
    }
    let (first, second) = items.split_at(items.len() / 2);
    spare.clear();
    let (a, b) = micropool::join(
        || first.iter().try_for_each(|it| row(out, it)),
        || second.iter().try_for_each(|it| row(spare, it)),
    );
    a.and(b)?;
    out.extend_from_slice(spare);
    Ok(())
}

/// One row of `bodies.csv` after `head` (step and time).
pub(crate) fn body_row(out: &mut Vec<u8>, head: &[u8], b: &Body) -> io::Result<()> {
    let (c, v) = (b.centroid, b.velocity);
    out.extend_from_slice(head);
    write!(
        out,
        "{},{},{},{},{},{},{}",
        b.name,
        Num(c.x),
        Num(c.y),
        Num(b.rotation),
        Num(v[0]),
        Num(v[1]),
        Num(v[2])
    )?;
    // a mesh body: centroid, mean rotation and velocity only (its elements go to VTK)
    if b.deformable && b.mesh.is_none() {
        for x in b.strain.iter().chain(b.stress.iter()) {
            write!(out, ",{}", Num(*x))?;
        }
        writeln!(out)
    } else {
        writeln!(out, ",,,,,,")
    }
}

/// One row of `contacts.csv` after `head` (step and time).
pub(crate) fn contact_row(
    out: &mut Vec<u8>,
    head: &[u8],
    world: &World,
    c: &ContactRecord,
) -> io::Result<()> {
    let (a, b) = (&world.bodies[c.body_a].name, &world.bodies[c.body_b].name);
    out.extend_from_slice(head);
    write!(
        out,
        "{a},{b},{},{},{},{},{},{},{},",
        c.kind.as_str(),
        Num(c.point.x),
        Num(c.point.y),
        Num(c.normal.x),
        Num(c.normal.y),
        Num(c.normal_force),
        Num(c.shear_force)
    )?;
    if let Some(m) = c.rolling_moment {
        write!(out, "{}", Num(m))?;
    }
    let interface = c.interface.and_then(|i| world.model.interfaces[i].name.as_deref()).unwrap_or("");
    writeln!(out, ",{},{},{interface}", Num(c.gap), c.state.as_str())
}

/// monitors.csv's rows of the current state, each starting with `head` (`step,time,`).
pub fn monitor_rows(out: &mut Vec<u8>, head: &[u8], world: &World) -> io::Result<()> {
    for (m, p) in world.model.monitors.iter().zip(&world.monitors) {
        let body = &world.bodies[p.body];
        let (u, v) = (p.current - p.initial, body.point_velocity(p.current));
        let (x, y) = (Num(p.current.x), Num(p.current.y));
        out.extend_from_slice(head);
        write!(out, "{},{x},{y},{},{},{},{}", m.name, Num(u.x), Num(u.y), Num(v.x), Num(v.y))?;
        // the stress of the mesh element holding the point (scene-format: monitors.csv)
        match &body.mesh {
            Some(fe) => {
                let st = fe.stress_at(p.current);
                writeln!(out, ",{},{},{}", Num(st[0]), Num(st[1]), Num(st[2]))?
            }
            None => writeln!(out, ",,,")?,
        }
    }
    Ok(())
}
