//! Import of classic DDA input: the geometry and analysis files of ntdda (Shi's DDA as kept by
//! Doolin), in its original text format and in DDAML (XML), turned into a pbdda rock-mass scene
//! (`pbdda import-ntdda`, docs/scene-format.md "Importing ntdda input").
//!
//! Reading follows ntdda's own readers field by field (`geomreader.c`, `geomddaml.c`,
//! `analysisreader.c`, `analysisddaml.c`); [`text`] and [`ddaml`] cite them. The block geometry
//! that ntdda's DC cutter would make from the joint lines is found by [`arrange`] (the planar
//! arrangement of the joint lines with the pieces that close no block removed), so that the
//! outline, the blocks that hole points delete and the blocks that points name are known before
//! pbdda's own cutter runs. [`scene`] writes the TOML.
//!
//! Nothing is dropped silently: whatever has no meaning in pbdda is listed, one line each, in
//! [`Import::ignored`]; how a field was mapped where the mapping is not one to one is in
//! [`Import::notes`]. Both lists head the written scene as comments.

pub mod arrange;
pub mod ddaml;
pub mod scene;
pub mod text;

use std::path::Path;

/// A malformed or unusable ntdda file. Displays as `FILE:LINE: FIELD: MESSAGE`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}:{line}: {field}: {message}")]
pub struct ImportError {
    /// The file as given on the command line.
    pub file: String,
    /// 1-based line of the offending field; 0 when the file could not be read.
    pub line: usize,
    /// The field, named as ntdda's readers name it (e.g. `joint line 2: y1`, `Numtimesteps`).
    pub field: String,
    /// What is wrong.
    pub message: String,
}

impl ImportError {
    pub(crate) fn new(file: &str, line: usize, field: impl Into<String>, message: impl Into<String>) -> Self {
        Self { file: file.to_owned(), line, field: field.into(), message: message.into() }
    }
}

/// A straight line of the geometry file: a joint line (`kind` = joint type), a material line
/// (`kind` = block material number), a fixed line (`kind` 0) or a bolt (`kind` = bolt type).
#[derive(Debug, Clone, PartialEq)]
pub struct Line {
    pub a: [f64; 2],
    pub b: [f64; 2],
    pub kind: i64,
    /// Line of the file it was read from.
    pub line: usize,
}

/// A point of the geometry file (load, measured or hole point).
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    pub p: [f64; 2],
    pub line: usize,
}

/// Everything of a geometry file that pbdda uses.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Geometry {
    pub file: String,
    /// DC's edge-node distance e00 (vertex merge radius 1.25 e00 w0).
    pub e00: f64,
    /// The first `boundary_lines` joint lines are DC's boundary lines.
    pub boundary_lines: usize,
    pub joints: Vec<Line>,
    pub material_lines: Vec<Line>,
    /// Fixed lines; a fixed point is a line whose two ends coincide (ntdda stores both so).
    pub fixed: Vec<Line>,
    pub loads: Vec<Point>,
    pub measured: Vec<Point>,
    pub holes: Vec<Point>,
    pub bolts: Vec<Line>,
    /// Fields read but without meaning here, one line each.
    pub ignored: Vec<String>,
    /// How a field was read where ntdda's reader substitutes a default.
    pub notes: Vec<String>,
}

/// A block material: ntdda's 13 (text) or 14 (DDAML) numbers.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockMaterial {
    /// Mass per unit volume (ntdda's "unit mass", `ma`).
    pub density: f64,
    /// Weight per unit volume (`we`).
    pub unit_weight: f64,
    pub young: f64,
    pub poisson: f64,
    pub initial_stress: [f64; 3],
    pub initial_strain: [f64; 3],
    pub initial_velocity: [f64; 3],
    /// DDAML only.
    pub damping: Option<f64>,
    pub line: usize,
}

/// A joint material: friction angle [deg], cohesion, tensile strength.
#[derive(Debug, Clone, PartialEq)]
pub struct JointMaterial {
    pub friction_angle: f64,
    pub cohesion: f64,
    pub tensile_strength: f64,
    pub line: usize,
}

/// A bolt material (DDAML `Boltproperties`): spring stiffness [N/m], strength [N], pretension [N].
#[derive(Debug, Clone, PartialEq)]
pub struct BoltMaterial {
    pub stiffness: f64,
    pub strength: f64,
    pub pretension: f64,
    pub line: usize,
}

/// A load point's time history (DDAML `Loadpoint`): rows of (t, fx, fy).
#[derive(Debug, Clone, PartialEq)]
pub struct LoadHistory {
    pub rows: Vec<[f64; 3]>,
    pub line: usize,
}

/// Everything of an analysis file that pbdda uses.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Analysis {
    pub file: String,
    /// ntdda's analysis type: 1 dynamic, 0 static (velocities not carried over).
    pub dynamic: bool,
    pub steps: usize,
    /// ntdda's maximum time step g1 [s].
    pub time_step: f64,
    /// Gravitational acceleration [m/s^2], downwards.
    pub gravity: f64,
    pub block_materials: Vec<BlockMaterial>,
    pub joint_materials: Vec<JointMaterial>,
    pub bolt_materials: Vec<BoltMaterial>,
    /// DDAML only; the text format has no load histories.
    pub load_histories: Vec<LoadHistory>,
    /// DDAML `Planestrain`; `None` when the file does not say.
    pub plane_strain: Option<bool>,
    /// ntdda's automatic time step (`Autotimestep`; always on in the text format).
    pub auto_step: Option<bool>,
    /// DDAML `Saveinterval`.
    pub save_every: Option<usize>,
    pub ignored: Vec<String>,
    pub notes: Vec<String>,
}

/// The imported scene: its TOML text and the lists that head it.
#[derive(Debug, Clone, PartialEq)]
pub struct Import {
    pub toml: String,
    /// What has no meaning in pbdda, one line each.
    pub ignored: Vec<String>,
    /// How fields were mapped where the mapping is not one to one.
    pub notes: Vec<String>,
}

/// True when the text is DDAML: its first non-blank character opens an XML tag (ntdda tells the
/// formats apart by the XML header).
pub fn is_ddaml(source: &str) -> bool {
    source.trim_start_matches('\u{feff}').trim_start().starts_with('<')
}

fn read(path: &Path) -> Result<(String, String), ImportError> {
    let name = path.display().to_string();
    let source = std::fs::read_to_string(path)
        .map_err(|e| ImportError::new(&name, 0, "file", format!("cannot read it: {e}")))?;
    Ok((name, source))
}

/// Reads a geometry file in either format.
pub fn read_geometry(path: &Path) -> Result<Geometry, ImportError> {
    let (name, source) = read(path)?;
    if is_ddaml(&source) { ddaml::geometry(&name, &source) } else { text::geometry(&name, &source) }
}

/// Reads an analysis file in either format. `loads` is the number of load points of the geometry
/// (ntdda's text analysis reader is told it too).
pub fn read_analysis(path: &Path) -> Result<Analysis, ImportError> {
    let (name, source) = read(path)?;
    if is_ddaml(&source) { ddaml::analysis(&name, &source) } else { text::analysis(&name, &source) }
}

/// Imports a geometry file and, optionally, its analysis file into a pbdda scene.
pub fn import(geometry: &Path, analysis: Option<&Path>) -> Result<Import, ImportError> {
    let geometry = read_geometry(geometry)?;
    let analysis = analysis.map(read_analysis).transpose()?;
    scene::build(&geometry, analysis.as_ref())
}
