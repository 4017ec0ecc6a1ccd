//! The scene file as serde reads it: one struct per TOML table of the scene-format contract
//! (version 1), field names exactly the contract's keys. Unknown keys are rejected here; values
//! keep their byte spans so that `check` can point at them. Nothing is validated yet.
//!
//! Vectors are read as `Vec<f64>` rather than `[f64; 2]`, because toml accepts a longer array
//! for a fixed-size one and silently drops the rest; `check` tests the length.

use serde::Deserialize;
use toml::Spanned;

/// The whole document.
#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct Scene {
    pub scene: SceneInfo,
    pub time: Spanned<Time>,
    #[serde(default)]
    pub physics: Physics,
    #[serde(default)]
    pub contact: Contact,
    #[serde(default)]
    pub solver: Solver,
    #[serde(default)]
    pub material: Vec<Material>,
    #[serde(default)]
    pub interface: Vec<Spanned<Interface>>,
    /// Absent: the `[domain]`'s blocks are the bodies (an empty list at no span otherwise).
    #[serde(default = "no_bodies")]
    pub body: Spanned<Vec<Spanned<Body>>>,
    #[serde(default)]
    pub load: Vec<Load>,
    #[serde(default)]
    pub connector: Vec<Spanned<Connector>>,
    #[serde(default)]
    pub traction: Vec<Spanned<Traction>>,
    #[serde(default)]
    pub monitor: Vec<Monitor>,
    #[serde(default)]
    pub output: Output,
    /// A rock mass cut from joints (scene::rockmass).
    pub domain: Option<Spanned<Domain>>,
    #[serde(default)]
    pub joint_set: Vec<Spanned<JointSet>>,
    #[serde(default)]
    pub joint: Vec<Spanned<Joint>>,
    #[serde(default)]
    pub excavation: Vec<Spanned<Excavation>>,
    #[serde(default)]
    pub region: Vec<Spanned<Region>>,
    #[serde(default)]
    pub bolt_pattern: Vec<Spanned<BoltPattern>>,
    #[serde(default)]
    pub stage: Vec<Spanned<Stage>>,
}

/// `[[stage]]`
#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct Stage {
    pub name: Spanned<String>,
    pub end: Spanned<f64>,
    pub until_kinetic: Option<Spanned<f64>>,
    pub velocity_carry: Option<Spanned<f64>>,
    pub remove: Option<Spanned<Vec<Spanned<String>>>>,
    pub set: Option<Spanned<Vec<Spanned<String>>>>,
}

fn no_bodies() -> Spanned<Vec<Spanned<Body>>> {
    Spanned::new(0..0, Vec::new())
}

/// `[scene]`
#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct SceneInfo {
    pub name: String,
}

/// `[time]`
#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct Time {
    pub step: Spanned<f64>,
    pub steps: Option<Spanned<i64>>,
    pub end: Option<Spanned<f64>>,
    pub adaptive: Option<bool>,
    pub max_halvings: Option<Spanned<i64>>,
}

/// `[physics]`
#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct Physics {
    pub gravity: Option<Spanned<Vec<f64>>>,
    pub plane: Option<Spanned<String>>,
    pub velocity_carry: Option<Spanned<f64>>,
    pub gravity_history: Option<Spanned<Vec<Vec<f64>>>>,
}

/// `[contact]`
#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct Contact {
    pub threshold: Option<Spanned<f64>>,
}

/// `[solver]`
#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct Solver {
    pub tolerance: Option<Spanned<f64>>,
    pub max_iterations: Option<Spanned<i64>>,
    pub method: Option<Spanned<toml::Value>>,
    pub allow_unconverged: Option<bool>,
    pub factor_drift: Option<Spanned<f64>>,
    pub friction_stops: Option<bool>,
}

/// `[[material]]`
#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct Material {
    pub name: Spanned<String>,
    pub density: Spanned<f64>,
    pub young: Option<Spanned<f64>>,
    pub poisson: Option<Spanned<f64>>,
}

/// `[[interface]]`
#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct Interface {
    pub name: Option<Spanned<String>>,
    pub materials: Option<Spanned<Vec<Spanned<String>>>>,
    pub friction: Option<Spanned<f64>>,
    pub friction_angle: Option<Spanned<f64>>,
    pub cohesion: Option<Spanned<f64>>,
    pub tensile_strength: Option<Spanned<f64>>,
    pub rolling: Option<Spanned<f64>>,
    pub restitution: Option<Spanned<f64>>,
}

/// `[[body]]`: one struct for every shape; `check` rejects keys the shape does not use.
#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct Body {
    pub name: Spanned<String>,
    pub shape: Spanned<String>,
    pub center: Option<Spanned<Vec<f64>>>,
    pub radius: Option<Spanned<f64>>,
    pub inner_radius: Option<Spanned<f64>>,
    pub vertices: Option<Spanned<Vec<Vec<f64>>>>,
    /// Mesh: the gmsh file, relative to the scene file.
    pub file: Option<Spanned<String>>,
    /// Mesh: physical surface group to take.
    pub physical: Option<Spanned<String>>,
    /// Mesh: physical curve or point groups whose nodes have no DOFs.
    pub fixed_nodes: Option<Spanned<Vec<Spanned<String>>>>,
    /// Mesh: physical groups whose nodes have no x DOF (rollers sliding along y).
    pub fixed_x_nodes: Option<Spanned<Vec<Spanned<String>>>>,
    /// Mesh: physical groups whose nodes have no y DOF (rollers sliding along x).
    pub fixed_y_nodes: Option<Spanned<Vec<Spanned<String>>>>,
    /// Mesh: factor on the file's coordinates.
    pub scale: Option<Spanned<f64>>,
    /// Mesh: translation after scaling.
    pub offset: Option<Spanned<Vec<f64>>>,
    pub model: Option<Spanned<String>>,
    pub material: Spanned<String>,
    #[serde(default)]
    pub fixed: bool,
    pub velocity: Option<Spanned<Vec<f64>>>,
    pub angular_velocity: Option<Spanned<f64>>,
    /// Deformable bodies only: (σx, σy, τxy) [Pa].
    pub initial_stress: Option<Spanned<Vec<f64>>>,
    /// Polygons: per edge, the name of the interface its joint carries ("" for none).
    pub edge_interfaces: Option<Spanned<Vec<Spanned<String>>>>,
    /// A block meshed by the rock-mass expansion (no file); never read from a scene.
    #[serde(skip)]
    pub generated_mesh: Option<crate::mesh::Mesh>,
}

/// `[[load]]`
#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct Load {
    pub body: Spanned<String>,
    pub point: Spanned<Vec<f64>>,
    pub force: Spanned<Vec<f64>>,
    pub history: Option<Spanned<Vec<Vec<f64>>>>,
}

/// `[[connector]]`: one struct for every kind; `check` rejects keys the kind does not use.
#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct Connector {
    pub name: Option<Spanned<String>>,
    pub kind: Spanned<String>,
    pub points: Spanned<Vec<Spanned<Vec<f64>>>>,
    pub bodies: Option<Spanned<Vec<Spanned<String>>>>,
    pub stiffness: Option<Spanned<f64>>,
    pub young: Option<Spanned<f64>>,
    pub area: Option<Spanned<f64>>,
    pub inertia: Option<Spanned<f64>>,
    pub shear_modulus: Option<Spanned<f64>>,
    pub shear_factor: Option<Spanned<f64>>,
    pub pretension: Option<Spanned<f64>>,
    pub strength: Option<Spanned<f64>>,
    /// Bolts: anchored in every block crossed (split into segments by the rock-mass expansion).
    pub grouted: Option<Spanned<bool>>,
    /// The `[[stage]]` at whose start the connector comes into being.
    pub stage: Option<Spanned<String>>,
    pub yield_force: Option<Spanned<f64>>,
    pub ultimate_strain: Option<Spanned<f64>>,
}

impl Connector {
    /// The numeric keys, by name (`check` rejects those the kind does not use; `cut` writes them).
    pub fn numbers(&self) -> [(&'static str, &Option<Spanned<f64>>); 10] {
        let c = self;
        [
            ("stiffness", &c.stiffness),
            ("young", &c.young),
            ("area", &c.area),
            ("inertia", &c.inertia),
            ("shear_modulus", &c.shear_modulus),
            ("shear_factor", &c.shear_factor),
            ("pretension", &c.pretension),
            ("strength", &c.strength),
            ("yield_force", &c.yield_force),
            ("ultimate_strain", &c.ultimate_strain),
        ]
    }
}

/// `[[traction]]`
#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct Traction {
    pub body: Spanned<String>,
    pub from: Option<Spanned<Vec<f64>>>,
    pub to: Option<Spanned<Vec<f64>>>,
    pub group: Option<Spanned<String>>,
    pub pressure: Option<Spanned<f64>>,
    pub shear: Option<Spanned<f64>>,
    pub stress: Option<Spanned<Vec<f64>>>,
    pub history: Option<Spanned<Vec<Vec<f64>>>>,
}

/// `[[monitor]]`
#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct Monitor {
    pub name: Spanned<String>,
    pub body: Spanned<String>,
    pub point: Spanned<Vec<f64>>,
}

/// `[output]`
#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct Output {
    pub every: Option<Spanned<i64>>,
    pub steps_every: Option<Spanned<i64>>,
    pub vtk: Option<bool>,
}

/// `[domain]`: the outline of a rock mass cut into blocks before t = 0.
#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct Domain {
    pub vertices: Spanned<Vec<Vec<f64>>>,
    pub material: Spanned<String>,
    pub model: Option<Spanned<String>>,
    pub mesh_size: Option<Spanned<f64>>,
    pub seed: Option<Spanned<i64>>,
    pub min_edge: Option<Spanned<f64>>,
    pub block_limit: Option<Spanned<i64>>,
    pub fixed_points: Option<Spanned<Vec<Vec<f64>>>>,
}

/// `[[joint_set]]`
#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct JointSet {
    #[allow(dead_code)] // names the set for the reader of the scene only
    pub name: Option<Spanned<String>>,
    pub angle: Spanned<f64>,
    pub spacing: Spanned<f64>,
    pub origin: Option<Spanned<Vec<f64>>>,
    pub trace: Option<Spanned<f64>>,
    pub gap: Option<Spanned<f64>>,
    pub angle_dev: Option<Spanned<f64>>,
    pub spacing_dev: Option<Spanned<f64>>,
    pub trace_dev: Option<Spanned<f64>>,
    pub gap_dev: Option<Spanned<f64>>,
    pub interface: Option<Spanned<String>>,
    pub bridges: Option<Spanned<String>>,
    pub bridge_interface: Option<Spanned<String>>,
}

/// `[[joint]]`
#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct Joint {
    pub points: Spanned<Vec<Vec<f64>>>,
    pub interface: Option<Spanned<String>>,
}

/// `[[excavation]]`
#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct Excavation {
    pub name: Spanned<String>,
    pub center: Option<Spanned<Vec<f64>>>,
    pub radius: Option<Spanned<f64>>,
    pub segments: Option<Spanned<i64>>,
    pub vertices: Option<Spanned<Vec<Vec<f64>>>>,
    pub stage: Option<Spanned<String>>,
    /// Without a `[domain]`: the bodies a staged excavation holds (as `pbdda cut` writes it).
    pub bodies: Option<Spanned<Vec<Spanned<String>>>>,
}

/// `[[region]]`
#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct Region {
    pub vertices: Spanned<Vec<Vec<f64>>>,
    pub material: Option<Spanned<String>>,
    pub fixed: Option<Spanned<bool>>,
}

/// `[[bolt_pattern]]`
#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct BoltPattern {
    pub name: Spanned<String>,
    pub excavation: Spanned<String>,
    pub spacing: Spanned<f64>,
    pub range: Option<Spanned<Vec<f64>>>,
    pub length: Spanned<f64>,
    pub young: Spanned<f64>,
    pub area: Spanned<f64>,
    pub pretension: Option<Spanned<f64>>,
    pub strength: Option<Spanned<f64>>,
    pub grouted: Option<Spanned<bool>>,
    pub yield_force: Option<Spanned<f64>>,
    pub ultimate_strain: Option<Spanned<f64>>,
    pub stage: Option<Spanned<String>>,
}
