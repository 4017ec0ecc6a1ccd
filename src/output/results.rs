//! Reading a results folder back (finished or still running): the CSVs of the output
//! contract, and `geometry.csv`, the bodies' outlines at the start of the run, which
//! [`write_geometry`] writes once before the first step (the CSVs hold centroids and rotations
//! only; `pbdda render` needs the shapes).
//!
//! `geometry.csv`: `body,shape,fixed,deformable,radius,inner_radius,cx,cy,x,y` — one row per
//! disk or ring (`x,y` empty) and one row per polygon vertex, in order; `cx,cy` is the centroid
//! at the start. A body's outline at a written step is the start outline moved by the step's
//! centroid, rotation and (deformable bodies) accumulated strain: exact for rigid bodies, the
//! first-order DDA displacement field (paper eqs. 3–4) for deformable ones, which is what a
//! picture needs.

use super::csv::{Num, OutputError};
use crate::body::Outline;
use crate::geometry::Vec2;
use crate::world::World;
use std::collections::HashMap;
use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// Name of the geometry file in a results folder.
pub const GEOMETRY_FILE: &str = "geometry.csv";

/// Problems reading a results folder.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum ResultsError {
    #[error("{path}: {source}")]
    Io { path: PathBuf, source: io::Error },
    #[error("{path}, line {line}: {message}")]
    #[diagnostic(help("is this a results folder written by `pbdda run`?"))]
    Format { path: PathBuf, line: usize, message: String },
    #[error("{path}: no step {step} was written (written steps: {first} to {last})")]
    NoStep { path: PathBuf, step: usize, first: usize, last: usize },
    #[error("{path}: no body `{name}` (bodies: {known})")]
    UnknownBody { path: PathBuf, name: String, known: String },
    #[error("{path}: no steps written yet")]
    Empty { path: PathBuf },
    #[error("{0}")]
    Draw(String),
    #[error(transparent)]
    Output(#[from] OutputError),
}

/// Writes `DIR/geometry.csv` from the world's current bodies (call once at run start).
pub fn write_geometry(dir: &Path, world: &World) -> Result<(), OutputError> {
    let path = dir.join(GEOMETRY_FILE);
    let mut text = String::from("body,shape,fixed,deformable,radius,inner_radius,cx,cy,x,y\n");
    for b in &world.bodies {
        let (c, f, d) = (b.centroid, b.fixed, b.deformable);
        let head = |shape: &str| format!("{},{shape},{f},{d}", b.name);
        match &b.outline {
            Outline::Disk { radius } => {
                text += &format!("{},{},,{},{},,\n", head("disk"), Num(*radius), Num(c.x), Num(c.y));
            }
            Outline::Ring { outer, inner } => {
                let (o, i) = (Num(*outer), Num(*inner));
                text += &format!("{},{o},{i},{},{},,\n", head("ring"), Num(c.x), Num(c.y));
            }
            Outline::Polygon { vertices, .. } => {
                for v in vertices {
                    let (x, y) = (Num(v.x), Num(v.y));
                    text += &format!("{},,,{},{},{x},{y}\n", head("polygon"), Num(c.x), Num(c.y));
                }
            }
        }
    }
    let tmp = dir.join("geometry.csv.tmp");
    let io = |p: &Path| {
        let p = p.to_path_buf();
        move |source| OutputError::Io { path: p, source }
    };
    let mut f = fs::File::create(&tmp).map_err(io(&tmp))?;
    f.write_all(text.as_bytes()).map_err(io(&tmp))?;
    fs::rename(&tmp, &path).map_err(io(&path))
}

/// A CSV file as text cells with a header.
#[derive(Debug, Clone)]
pub struct Table {
    pub path: PathBuf,
    pub header: Vec<String>,
    /// (line number, cells) of every complete row.
    pub rows: Vec<(usize, Vec<String>)>,
}

impl Table {
    /// Reads a CSV file. A last line without its newline (a run still writing) is dropped.
    pub fn read(path: &Path) -> Result<Table, ResultsError> {
        let text = fs::read_to_string(path)
            .map_err(|source| ResultsError::Io { path: path.to_path_buf(), source })?;
        let complete = match text.rfind('\n') {
            Some(i) => &text[..=i],
            None => "",
        };
        let mut lines = complete.lines().enumerate();
        let header = match lines.next() {
            Some((_, h)) => h.split(',').map(str::to_string).collect::<Vec<_>>(),
            None => return Err(format_err(path, 1, "no header line".into())),
        };
        let mut rows = Vec::new();
        for (i, line) in lines {
            let cells: Vec<String> = line.split(',').map(str::to_string).collect();
            if cells.len() != header.len() {
                let msg = format!("{} fields, the header has {}", cells.len(), header.len());
                return Err(format_err(path, i + 1, msg));
            }
            rows.push((i + 1, cells));
        }
        Ok(Table { path: path.to_path_buf(), header, rows })
    }

    /// Index of a column.
    pub fn col(&self, name: &str) -> Result<usize, ResultsError> {
        self.header
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| format_err(&self.path, 1, format!("no column `{name}`")))
    }

    /// A column as numbers (an empty cell is an error).
    pub fn numbers(&self, name: &str) -> Result<Vec<f64>, ResultsError> {
        let c = self.col(name)?;
        self.rows.iter().map(|(line, r)| number(&self.path, *line, name, &r[c])).collect()
    }

    /// A column as optional numbers (empty cells are `None`).
    pub fn optional(&self, name: &str) -> Result<Vec<Option<f64>>, ResultsError> {
        let c = self.col(name)?;
        self.rows
            .iter()
            .map(|(line, r)| match r[c].as_str() {
                "" => Ok(None),
                s => number(&self.path, *line, name, s).map(Some),
            })
            .collect()
    }

    /// A column as text.
    pub fn text(&self, name: &str) -> Result<Vec<String>, ResultsError> {
        let c = self.col(name)?;
        Ok(self.rows.iter().map(|(_, r)| r[c].clone()).collect())
    }
}

fn format_err(path: &Path, line: usize, message: String) -> ResultsError {
    ResultsError::Format { path: path.to_path_buf(), line, message }
}

fn number(path: &Path, line: usize, key: &str, s: &str) -> Result<f64, ResultsError> {
    s.parse().map_err(|_| format_err(path, line, format!("`{key}` is `{s}`, not a number")))
}

/// The start outline of one body, from `geometry.csv`.
#[derive(Debug, Clone)]
pub struct BodyGeometry {
    pub name: String,
    pub fixed: bool,
    pub deformable: bool,
    pub centroid: Vec2,
    pub outline: Outline,
}

/// Reads `DIR/geometry.csv`.
pub fn read_geometry(dir: &Path) -> Result<Vec<BodyGeometry>, ResultsError> {
    let t = Table::read(&dir.join(GEOMETRY_FILE))?;
    let (names, shapes) = (t.text("body")?, t.text("shape")?);
    let (fixed, deformable) = (t.text("fixed")?, t.text("deformable")?);
    let (radius, inner) = (t.optional("radius")?, t.optional("inner_radius")?);
    let (cx, cy, x, y) = (t.numbers("cx")?, t.numbers("cy")?, t.optional("x")?, t.optional("y")?);
    let mut out: Vec<BodyGeometry> = Vec::new();
    for i in 0..t.rows.len() {
        let line = t.rows[i].0;
        let need =
            |v: Option<f64>, key: &str| v.ok_or_else(|| format_err(&t.path, line, format!("`{key}` empty")));
        let outline = match shapes[i].as_str() {
            "disk" => Outline::Disk { radius: need(radius[i], "radius")? },
            "ring" => {
                Outline::Ring { outer: need(radius[i], "radius")?, inner: need(inner[i], "inner_radius")? }
            }
            "polygon" => {
                let v = Vec2::new(need(x[i], "x")?, need(y[i], "y")?);
                if let Some(last) = out.last_mut().filter(|b| b.name == names[i])
                    && let Outline::Polygon { vertices, .. } = &mut last.outline
                {
                    vertices.push(v);
                    continue;
                }
                Outline::Polygon { vertices: vec![v], convex: vec![] }
            }
            other => return Err(format_err(&t.path, line, format!("unknown shape `{other}`"))),
        };
        out.push(BodyGeometry {
            name: names[i].clone(),
            fixed: fixed[i] == "true",
            deformable: deformable[i] == "true",
            centroid: Vec2::new(cx[i], cy[i]),
            outline,
        });
    }
    Ok(out)
}

/// One body's row of `bodies.csv` at a step.
#[derive(Debug, Clone)]
pub struct BodyState {
    pub name: String,
    pub centroid: Vec2,
    pub rotation: f64,
    /// Accumulated (εx, εy, γxy); zero for rigid bodies.
    pub strain: [f64; 3],
}

/// One row of `contacts.csv`.
#[derive(Debug, Clone)]
pub struct ContactRow {
    pub step: usize,
    pub time: f64,
    pub body_a: String,
    pub body_b: String,
    pub point: Vec2,
    pub normal: Vec2,
    pub normal_force: f64,
    pub shear_force: f64,
    pub gap: f64,
    pub state: String,
    /// The interface whose law the contact takes (empty: unnamed, or a file without the column).
    pub interface: String,
}

/// Step numbers of a table's `step` column.
pub fn steps_of(t: &Table) -> Result<Vec<usize>, ResultsError> {
    Ok(t.numbers("step")?.into_iter().map(|s| s as usize).collect())
}

/// The written step to show: `step`, or the last one written in full (`n_bodies` rows: a
/// running job may have written part of its current step).
pub fn pick_step(bodies: &Table, step: Option<usize>, n_bodies: usize) -> Result<usize, ResultsError> {
    let steps = steps_of(bodies)?;
    let (first, last) = match (steps.first(), steps.last()) {
        (Some(f), Some(l)) => (*f, *l),
        _ => return Err(ResultsError::Empty { path: bodies.path.clone() }),
    };
    let complete = |s: usize| steps.iter().filter(|&&t| t == s).count() == n_bodies;
    match step {
        None if complete(last) => Ok(last),
        None => steps
            .iter()
            .rev()
            .copied()
            .find(|&s| s != last && complete(s))
            .ok_or(ResultsError::Empty { path: bodies.path.clone() }),
        Some(s) if steps.contains(&s) => Ok(s),
        Some(s) => Err(ResultsError::NoStep { path: bodies.path.clone(), step: s, first, last }),
    }
}

/// Rows of `bodies.csv` at a step, by body name.
pub fn body_states(bodies: &Table, step: usize) -> Result<HashMap<String, BodyState>, ResultsError> {
    let steps = steps_of(bodies)?;
    let names = bodies.text("body")?;
    let (x, y, rot) = (bodies.numbers("x")?, bodies.numbers("y")?, bodies.numbers("rotation")?);
    let strain: Vec<_> =
        ["strain_x", "strain_y", "strain_xy"].iter().map(|k| bodies.optional(k)).collect::<Result<_, _>>()?;
    let mut out = HashMap::new();
    for i in (0..steps.len()).filter(|&i| steps[i] == step) {
        let e = |k: usize| strain[k][i].unwrap_or(0.0);
        let state = BodyState {
            name: names[i].clone(),
            centroid: Vec2::new(x[i], y[i]),
            rotation: rot[i],
            strain: [e(0), e(1), e(2)],
        };
        out.insert(names[i].clone(), state);
    }
    Ok(out)
}

/// All rows of `contacts.csv`.
pub fn contact_rows(t: &Table) -> Result<Vec<ContactRow>, ResultsError> {
    let steps = steps_of(t)?;
    let (time, a, b) = (t.numbers("time")?, t.text("body_a")?, t.text("body_b")?);
    let (x, y, nx, ny) = (t.numbers("x")?, t.numbers("y")?, t.numbers("nx")?, t.numbers("ny")?);
    let (pn, pt, gap, state) =
        (t.numbers("normal_force")?, t.numbers("shear_force")?, t.numbers("gap")?, t.text("state")?);
    let interface = t.text("interface").unwrap_or_else(|_| vec![String::new(); steps.len()]);
    Ok((0..steps.len())
        .map(|i| ContactRow {
            step: steps[i],
            time: time[i],
            body_a: a[i].clone(),
            body_b: b[i].clone(),
            point: Vec2::new(x[i], y[i]),
            normal: Vec2::new(nx[i], ny[i]),
            normal_force: pn[i],
            shear_force: pt[i],
            gap: gap[i],
            state: state[i].clone(),
            interface: interface[i].clone(),
        })
        .collect())
}

/// A body's outline at a step: disks and rings as (centre, radii), polygons as vertices,
/// moved from the start geometry (see the module notes).
#[derive(Debug, Clone)]
pub enum Placed {
    Circle { center: Vec2, outer: f64, inner: Option<f64> },
    Polygon(Vec<Vec2>),
}

/// Places a start outline at a step's state: x = c + (I + E) R(θ) (X − c0) with E the
/// accumulated strain tensor (εx, γ/2; γ/2, εy).
pub fn place(g: &BodyGeometry, s: &BodyState) -> Placed {
    let (sin, cos) = s.rotation.sin_cos();
    let [ex, ey, gxy] = s.strain;
    let map = |p: Vec2| {
        let d = p - g.centroid;
        let r = Vec2::new(cos * d.x - sin * d.y, sin * d.x + cos * d.y);
        s.centroid + r + Vec2::new(ex * r.x + 0.5 * gxy * r.y, 0.5 * gxy * r.x + ey * r.y)
    };
    match &g.outline {
        Outline::Disk { radius } => {
            Placed::Circle { center: s.centroid, outer: radius * (1.0 + ex), inner: None }
        }
        Outline::Ring { outer, inner } => {
            Placed::Circle { center: s.centroid, outer: outer * (1.0 + ex), inner: Some(inner * (1.0 + ex)) }
        }
        Outline::Polygon { vertices, .. } => Placed::Polygon(vertices.iter().map(|v| map(*v)).collect()),
    }
}
