//! `pbdda validate [--markdown FILE]`: runs the paper's examples §7.1-7.10 (scene and mesh files
//! built into the binary) and tabulates, per quantity, the paper's PB-DDA value, the exact value,
//! pbdda's value, the error and whether it is within the row's tolerance.
//!
//! The exact values are the closed forms of the design note §7 (`docs/math.md`), in [`exact`],
//! shared with the tests. The paper values are copied from the paper's tables and text (cited
//! per row); "-" where the paper gives a figure only. Runs are shortened where the quantity is
//! reached early: 7.5 stops after the second peak (3 700 of 4 000 steps), 7.4 after 6 000 of
//! 10 000 steps (five wall impacts), 7.6-7.8 after 20 steps (statics, constant from step 1).
//! §7.9 and §7.10 (`validate/later.rs`) run in full (1 000 and 3 000 steps).
//!
//! Beyond the paper: the connectors (`validate/connectors.rs`: a bolted block at limit
//! equilibrium, a spring's period, a beam cantilever against Timoshenko) and the mesh
//! convergence of the meshed cantilever (`validate/convergence.rs`: its three shipped meshes
//! against scikit-fem's values in `meshes/reference.json`, the observed order and the
//! Richardson-extrapolated tip deflection of `cli::sweep::richardson`).

use crate::scene::{Override, load_with, parse_with};
use crate::world::{ContactRecord, StepRecord, World};
use miette::{IntoDiagnostic, Result};
use std::path::Path;

mod connectors;
mod convergence;
pub mod exact;
mod later;
mod paper;

/// One line of the report.
#[derive(Debug, Clone)]
pub struct Row {
    pub example: &'static str,
    pub quantity: String,
    /// The paper's PB-DDA value (table or text cited in `source`); None for a figure.
    pub paper: Option<f64>,
    pub exact: f64,
    pub pbdda: f64,
    /// Largest accepted |pbdda - exact|.
    pub tolerance: f64,
    /// Where the paper value comes from, and why the tolerance.
    pub note: &'static str,
}

impl Row {
    pub fn error(&self) -> f64 {
        (self.pbdda - self.exact).abs()
    }

    pub fn within(&self) -> bool {
        self.error() <= self.tolerance
    }
}

const SCENES: [(&str, &str); 8] = [
    ("7_1_disk_heap.toml", include_str!("../../../examples/7_1_disk_heap.toml")),
    ("7_2_block_staircase.toml", include_str!("../../../examples/7_2_block_staircase.toml")),
    (
        "7_2_block_staircase_deformable.toml",
        include_str!("../../../examples/7_2_block_staircase_deformable.toml"),
    ),
    ("7_3_ring_in_frame.toml", include_str!("../../../examples/7_3_ring_in_frame.toml")),
    ("7_4_block_in_frame.toml", include_str!("../../../examples/7_4_block_in_frame.toml")),
    ("7_5_disk_in_ring.toml", include_str!("../../../examples/7_5_disk_in_ring.toml")),
    ("7_6_sliding_block_cohesion.toml", include_str!("../../../examples/7_6_sliding_block_cohesion.toml")),
    ("7_8_cemented_interface.toml", include_str!("../../../examples/7_8_cemented_interface.toml")),
];

const SCENES_7_7: [(&str, &str); 3] = [
    ("7_7_rolling_disk.toml", include_str!("../../../examples/7_7_rolling_disk.toml")),
    ("7_7_rolling_resistance.toml", include_str!("../../../examples/7_7_rolling_resistance.toml")),
    ("7_7_trajectories.toml", include_str!("../../../examples/7_7_trajectories.toml")),
];

thread_local! {
    /// Overrides [`rows_with`] adds to every scene.
    static EXTRA: std::cell::RefCell<Vec<Override>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// [`rows`] with `extra` overrides on every scene (e.g. `solver.method=nsgs`).
pub fn rows_with(extra: &[Override]) -> Result<Vec<Row>> {
    EXTRA.with(|e| *e.borrow_mut() = extra.to_vec());
    let rows = rows();
    EXTRA.with(|e| e.borrow_mut().clear());
    rows
}

/// A world of the built-in scene `name` with `sets` (KEY, VALUE) overrides.
fn world(name: &str, sets: &[(&str, String)]) -> Result<World> {
    let (file, text) = SCENES
        .iter()
        .chain(&SCENES_7_7)
        .find(|(f, _)| *f == name)
        .ok_or_else(|| miette::miette!("no built-in scene {name}"))?;
    scene_world(file, text, sets)
}

/// A world of the scene `text` (reported as `examples/FILE`) with `sets` overrides and those of
/// [`rows_with`].
fn scene_world(file: &str, text: &str, sets: &[(&str, String)]) -> Result<World> {
    let mut overrides: Vec<Override> =
        sets.iter().map(|(k, v)| Override { key: (*k).to_owned(), value: v.clone() }).collect();
    overrides.extend(EXTRA.with(|e| e.borrow().clone()));
    Ok(World::new(parse_with(text, &format!("examples/{file}"), &overrides)?))
}

/// A world of a built-in scene that reads further files (meshes): the scene and `files`
/// (paths relative to the repository root) are written to a fresh temporary directory laid out
/// like the repository, read from there, and the directory removed.
fn world_from_disk(
    name: &str,
    text: &str,
    files: &[(&str, &[u8])],
    sets: &[(&str, String)],
) -> Result<World> {
    static RUN: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = RUN.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
    let dir = std::env::temp_dir().join(format!("pbdda-validate-{}-{n}", std::process::id()));
    let scene = dir.join("examples").join(name);
    let written =
        std::iter::once((scene.clone(), text.as_bytes())).chain(files.iter().map(|(p, b)| (dir.join(p), *b)));
    for (path, bytes) in written {
        std::fs::create_dir_all(path.parent().unwrap_or(&dir)).into_diagnostic()?;
        std::fs::write(&path, bytes).into_diagnostic()?;
    }
    let mut overrides: Vec<Override> =
        sets.iter().map(|(k, v)| Override { key: (*k).to_owned(), value: v.clone() }).collect();
    overrides.extend(EXTRA.with(|e| e.borrow().clone()));
    let model = load_with(&scene, &overrides);
    std::fs::remove_dir_all(&dir).into_diagnostic()?;
    Ok(World::new(model?))
}

/// Runs `steps` steps, handing each record to `each`; returns the last record.
fn run(world: &mut World, steps: usize, mut each: impl FnMut(&World, &StepRecord)) -> Result<StepRecord> {
    let mut last = None;
    for _ in 0..steps {
        let rec = world.step()?;
        each(world, &rec);
        last = Some(rec);
    }
    last.ok_or_else(|| miette::miette!("no steps run"))
}

fn index(world: &World, name: &str) -> Result<usize> {
    world.bodies.iter().position(|b| b.name == name).ok_or_else(|| miette::miette!("no body {name}"))
}

/// Contacts of `rec` between the named bodies.
fn between<'a>(world: &World, rec: &'a StepRecord, a: &str, b: &str) -> Result<Vec<&'a ContactRecord>> {
    let (ia, ib) = (index(world, a)?, index(world, b)?);
    Ok(rec
        .contacts
        .iter()
        .filter(|c| (c.body_a, c.body_b) == (ia, ib) || (c.body_a, c.body_b) == (ib, ia))
        .collect())
}

fn row(example: &'static str, quantity: String, paper: Option<f64>, exact: f64, pbdda: f64) -> Row {
    Row { example, quantity, paper, exact, pbdda, tolerance: 0.0, note: "" }
}

impl Row {
    fn tol(self, tolerance: f64, note: &'static str) -> Row {
        Row { tolerance, note, ..self }
    }
}

type Part = fn() -> Result<Vec<Row>>;

/// The paper's examples §7.1-7.10, in the order of the paper.
const PAPER: [Part; 9] = [
    paper::heap,
    paper::staircase,
    paper::billiards,
    paper::pendulum,
    paper::sliding_block,
    paper::rolling_disk,
    paper::cemented,
    later::undulation,
    later::chain,
];

/// The connector and mesh-convergence rows.
const BEYOND: [Part; 4] =
    [connectors::bolted_block, connectors::spring, connectors::cantilever, convergence::cantilever_meshes];

/// Runs every example: the paper's rows in its order, then the connectors and mesh convergence.
pub fn rows() -> Result<Vec<Row>> {
    let mut rows = Vec::new();
    for part in PAPER.iter().chain(&BEYOND) {
        rows.extend(part()?);
    }
    Ok(rows)
}

/// The paper's rows only (§7.1-7.10), with `extra` overrides on every scene.
pub fn paper_rows_with(extra: &[Override]) -> Result<Vec<Row>> {
    EXTRA.with(|e| *e.borrow_mut() = extra.to_vec());
    let rows: Result<Vec<Vec<Row>>> = PAPER.iter().map(|part| part()).collect();
    EXTRA.with(|e| e.borrow_mut().clear());
    Ok(rows?.into_iter().flatten().collect())
}

fn number(x: f64) -> String {
    let x = x + 0.0; // no "-0"
    let a = x.abs();
    if a != 0.0 && !(1e-3..1e9).contains(&a) { format!("{x:.6e}") } else { format!("{x:.6}") }
}

fn cells(r: &Row) -> [String; 7] {
    [
        r.example.to_owned(),
        r.quantity.clone(),
        r.paper.map_or("-".to_owned(), number),
        number(r.exact),
        number(r.pbdda),
        format!("{:.2e}", r.error()),
        format!("{} (tol {:.0e})", if r.within() { "ok" } else { "FAIL" }, r.tolerance),
    ]
}

const HEADER: [&str; 7] = ["example", "quantity", "paper PB-DDA", "exact", "pbdda", "error", "within"];

/// The table as aligned text.
pub fn table(rows: &[Row]) -> String {
    let all: Vec<[String; 7]> =
        std::iter::once(HEADER.map(str::to_owned)).chain(rows.iter().map(cells)).collect();
    let width: Vec<usize> =
        (0..7).map(|c| all.iter().map(|r| r[c].chars().count()).max().unwrap_or(0)).collect();
    let mut s = String::new();
    for r in &all {
        let line: Vec<String> = r.iter().zip(&width).map(|(c, w)| format!("{c:<w$}")).collect();
        s += line.join("  ").trim_end();
        s.push('\n');
    }
    s
}

/// The table as a Markdown report, with each row's source and tolerance reason.
pub fn markdown(rows: &[Row]) -> String {
    let mut s = String::from(
        "# pbdda validation: the paper's examples (Fan, Zhao & Zheng 2018, §7), connectors and mesh convergence\n\n\
         Exact values: closed forms of `docs/math.md` §7 (the paper's examples), §6 (connectors) and §9.5 (the \
         meshed cantilever; peer values from `meshes/reference.json`). Error = |pbdda - exact|.\n\n",
    );
    s += &format!("| {} | tolerance basis |\n|{}\n", HEADER.join(" | "), "---|".repeat(8));
    for r in rows {
        s += &format!("| {} | {} |\n", cells(r).join(" | "), r.note);
    }
    let failed = rows.iter().filter(|r| !r.within()).count();
    s += &format!("\n{} rows, {failed} outside their tolerance.\n", rows.len());
    s
}

pub(super) fn command(markdown_file: Option<&Path>) -> Result<()> {
    let rows = rows()?;
    out!("{}", table(&rows));
    if let Some(path) = markdown_file {
        std::fs::write(path, markdown(&rows)).into_diagnostic()?;
    }
    let failed = rows.iter().filter(|r| !r.within()).count();
    if failed > 0 {
        return Err(miette::miette!("{failed} of {} rows outside their tolerance", rows.len()));
    }
    outln!("all {} rows within their tolerance", rows.len());
    Ok(())
}
