//! The validated input of a simulation: what a scene file describes, after every check of
//! `scene.rs` has passed. Bodies are in their initial configuration; names are resolved to
//! indices. Nothing here changes during a run (that is `World`'s job).

use crate::geometry::Vec2;

/// A whole scene, ready to be turned into a [`crate::world::World`].
#[derive(Debug, Clone)]
pub struct Model {
    /// Free text from `[scene] name`.
    pub name: String,
    pub time: TimeSettings,
    pub physics: Physics,
    pub contact: ContactSettings,
    pub solver: SolverSettings,
    pub materials: Vec<Material>,
    pub interfaces: Vec<Interface>,
    pub bodies: Vec<BodySpec>,
    pub loads: Vec<Load>,
    /// Distributed loads on boundaries (`[[traction]]`, math note §2.5).
    pub tractions: Vec<Traction>,
    /// Bolts, springs and beams joining pairs of bodies (math note §6).
    pub connectors: Vec<ConnectorSpec>,
    pub monitors: Vec<Monitor>,
    pub output: OutputSettings,
    /// `[[stage]]` in file order (math note §10.14); empty: one stage, the whole run.
    pub stages: Vec<Stage>,
    /// `[[excavation]]`: named groups of bodies a stage may remove.
    pub excavations: Vec<Excavation>,
    /// `[physics] gravity_history`: (time, factor) pairs on the gravity, piecewise linear and
    /// constant outside (as a load's `history`); `None`: factor 1.
    pub gravity_history: Option<Vec<(f64, f64)>>,
}

/// Piecewise-linear factor of (time, factor) pairs with increasing times at time `t`, constant
/// beyond the first and last ones; 1 without pairs.
pub fn history_factor(h: Option<&[(f64, f64)]>, t: f64) -> f64 {
    let Some(h) = h else { return 1.0 };
    match h.iter().position(|&(ti, _)| ti > t) {
        None => h.last().map_or(1.0, |p| p.1),
        Some(0) => h[0].1,
        Some(i) => {
            let (t0, f0) = h[i - 1];
            let (t1, f1) = h[i];
            f0 + (f1 - f0) * (t - t0) / (t1 - t0)
        }
    }
}

/// A named group of bodies removed together (an excavation cut from a rock mass).
#[derive(Debug, Clone, PartialEq)]
pub struct Excavation {
    pub name: String,
    /// Indices into `Model::bodies`.
    pub bodies: Vec<usize>,
}

/// One `[[stage]]` of a staged run (math note §10.14).
#[derive(Debug, Clone)]
pub struct Stage {
    pub name: String,
    /// Simulated time [s] at which the stage ends at the latest.
    pub end: f64,
    /// The step after which it ends at the latest: ceil(end / dt), as `[time] end`.
    pub end_step: usize,
    /// [J/kg]: the stage ends once the kinetic energy per unit mass on the steps' mean velocity
    /// d/dt has stayed below this for [`QUIET_STEPS`] steps.
    pub until_kinetic: Option<f64>,
    /// Indices into `Model::bodies` removed at the stage's start (from `remove`, excavations
    /// expanded), sorted, without repeats.
    pub remove: Vec<usize>,
    /// Indices into `Model::connectors` that come into being at the stage's start.
    pub connectors: Vec<usize>,
    /// The `set` entries of this stage, as written (`KEY=VALUE`).
    pub set: Vec<String>,
    /// The settings in force during the stage: the scene's, with the `set` entries of this and
    /// every earlier stage applied, and the stage's `velocity_carry` (if given) in `physics`.
    pub settings: StageSettings,
}

/// How many consecutive quiet steps end a stage with `until_kinetic`.
pub const QUIET_STEPS: usize = 10;

/// The part of a [`Model`] a stage's `set` may change.
#[derive(Debug, Clone)]
pub struct StageSettings {
    pub physics: Physics,
    pub solver: SolverSettings,
    pub interfaces: Vec<Interface>,
    pub loads: Vec<Load>,
    pub gravity_history: Option<Vec<(f64, f64)>>,
}

#[derive(Debug, Clone, Copy)]
pub struct TimeSettings {
    /// dt [s] (the paper's Δ).
    pub step: f64,
    /// Number of steps to run (from `steps`, or `ceil(end / step)` when `end` is given).
    pub steps: usize,
    /// A step that fails (math note §10.8) is repeated as two of half the length (`[time]
    /// adaptive`, default true).
    pub adaptive: bool,
    /// The most times a step may be halved (`[time] max_halvings`, 0–30, default 6).
    pub max_halvings: u32,
}

impl TimeSettings {
    /// `steps` steps of `step` with the default step policy (adaptive, 6 halvings).
    pub fn new(step: f64, steps: usize) -> TimeSettings {
        TimeSettings { step, steps, adaptive: true, max_halvings: 6 }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Plane {
    Stress,
    Strain,
}

#[derive(Debug, Clone, Copy)]
pub struct Physics {
    /// Body acceleration [m/s²].
    pub gravity: Vec2,
    pub plane: Plane,
    /// DDA dynamic ratio k: v0(next) = k v1 (math note §1.1). 1 = dynamic, 0 = static relaxation.
    pub velocity_carry: f64,
}

#[derive(Debug, Clone, Copy)]
pub struct ContactSettings {
    /// d0 [m]; `None`: derived from the scene (math note §5).
    pub threshold: Option<f64>,
}

#[derive(Debug, Clone, Copy)]
pub struct SolverSettings {
    /// Scaled natural residual of the VI (math note §4.3).
    pub tolerance: f64,
    /// The budget of work of a step, all its VI solves and methods together (math note §4.17).
    pub max_iterations: usize,
    /// The chain of VI methods (`[solver] method`; math note §4.17).
    pub method: crate::vi::Chain,
    /// Accept a step whose VI did not converge with a warning (`[solver] allow_unconverged`,
    /// default false: such a step fails, math note §10.8).
    pub allow_unconverged: bool,
    /// Refactor policy of sparse clusters (`[solver] factor_drift`, math note §9.3): 0 (default)
    /// refactors every step; a positive value keeps a factor while no element has turned or
    /// strained by more than it since the factor was formed.
    pub factor_drift: f64,
    /// Solve 2 holds the friction rows whose slip solve 1 stops (`[solver] friction_stops`,
    /// math note §10.15), so a body friction stops has zero velocity; default false (they cost
    /// repeated solve 2s on jammed piles).
    pub friction_stops: bool,
}

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            tolerance: 1e-8,
            max_iterations: 200_000,
            method: crate::vi::Chain::named(crate::vi::Method::Mprgp),
            allow_unconverged: false,
            factor_drift: 0.0,
            friction_stops: false,
        }
    }
}

#[derive(Debug, Clone)]
pub struct Material {
    pub name: String,
    /// ρ [kg/m³].
    pub density: f64,
    /// E [Pa]; required by deformable bodies only.
    pub young: Option<f64>,
    /// ν; required by deformable bodies only.
    pub poisson: Option<f64>,
}

/// A contact law. `materials: None` is the default for all pairs.
#[derive(Debug, Clone)]
pub struct Interface {
    /// `[[interface]] name`, unique when given; edges tagged with it (joints of a cut rock
    /// mass, [`BodySpec::edge_interfaces`]) select it.
    pub name: Option<String>,
    /// Indices into `Model::materials` (unordered pair), or `None` for the default entry.
    pub materials: Option<[usize; 2]>,
    /// Coulomb coefficient μ (from `friction`, or tan of `friction_angle`).
    pub friction: f64,
    /// Cohesion stress [Pa]; times the edge-edge overlap length gives a joint's capacity.
    pub cohesion: f64,
    /// Tensile strength [Pa]; > 0 cements contacts closed at t = 0.
    pub tensile_strength: f64,
    /// Rolling friction length δ [m] for particle contacts.
    pub rolling: f64,
    /// Newton's normal coefficient of restitution e in [0, 1] (math note §10.15); 1: elastic.
    pub restitution: f64,
}

impl Interface {
    /// The frictionless, cohesionless law used when a scene gives no default interface.
    pub const SMOOTH: Interface = Interface {
        name: None,
        materials: None,
        friction: 0.0,
        cohesion: 0.0,
        tensile_strength: 0.0,
        rolling: 0.0,
        restitution: 1.0,
    };
}

#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    Disk {
        center: Vec2,
        radius: f64,
    },
    /// `outer` is R_E and `inner` is R_I (radii, math note §2.2).
    Ring {
        center: Vec2,
        outer: f64,
        inner: f64,
    },
    /// Simple polygon, vertices in counter-clockwise order (normalized by `scene.rs`).
    Polygon {
        vertices: Vec<Vec2>,
    },
    /// A triangle mesh from gmsh, always finite elements (math note §9).
    Mesh(Box<MeshShape>),
}

/// A mesh body's geometry (defined in [`crate::mesh`], which owns the mesh types).
pub use crate::mesh::MeshShape;

impl Shape {
    /// Whether `p` lies in the shape, the boundary included (within 1e-9 of the shape's size, so
    /// that an anchor typed on an edge or a rim counts as inside). Rings are annuli: the hole is
    /// outside.
    pub fn contains(&self, p: Vec2) -> bool {
        match self {
            Shape::Disk { center, radius } => (p - center).norm() <= radius * (1.0 + 1e-9),
            Shape::Ring { center, outer, inner } => {
                let r = (p - center).norm();
                r <= outer * (1.0 + 1e-9) && r >= inner * (1.0 - 1e-9)
            }
            Shape::Polygon { vertices } => polygon_contains(vertices, p),
            Shape::Mesh(m) => m.mesh.locate(p, 1e-9).is_some(),
        }
    }
}

/// Point in a simple polygon (either orientation), boundary included: on an edge within 1e-9 of
/// the polygon's size, else the crossing-number rule.
fn polygon_contains(v: &[Vec2], p: Vec2) -> bool {
    let n = v.len();
    let size = (0..n).map(|i| (v[i] - v[0]).norm()).fold(0.0, f64::max);
    let edges = || (0..n).map(|i| (v[i], v[(i + 1) % n]));
    let on_edge = |(a, b): (Vec2, Vec2)| {
        let ab = b - a;
        let t = ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0);
        (a + ab * t - p).norm() <= 1e-9 * size
    };
    if edges().any(on_edge) {
        return true;
    }
    let crosses = |(a, b): &(Vec2, Vec2)| {
        (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y)
    };
    edges().filter(crosses).count() % 2 == 1
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BodyModel {
    Rigid,
    Deformable,
}

#[derive(Debug, Clone)]
pub struct BodySpec {
    pub name: String,
    pub shape: Shape,
    pub model: BodyModel,
    /// Index into `Model::materials`.
    pub material: usize,
    /// No degrees of freedom at all (math note §2.4).
    pub fixed: bool,
    /// Initial velocity of the centroid [m/s].
    pub velocity: Vec2,
    /// Initial angular velocity [rad/s], ccw positive.
    pub angular_velocity: f64,
    /// Initial stress (σx, σy, τxy) [Pa], deformable bodies only.
    pub initial_stress: Option<[f64; 3]>,
    /// Polygons: per edge (edge i from vertex i to i + 1), the interface its joint carries
    /// (index into `Model::interfaces`), or `None`; empty for untagged bodies. A contact
    /// between two edges tagged with the same interface takes that interface's law instead of
    /// the material pair's (math note §4.14).
    pub edge_interfaces: Vec<Option<usize>>,
}

impl BodySpec {
    /// A body of material 0 at rest, without initial stress (the generated scenes' bodies).
    pub fn at_rest(name: impl Into<String>, shape: Shape, model: BodyModel, fixed: bool) -> BodySpec {
        BodySpec {
            name: name.into(),
            shape,
            model,
            material: 0,
            fixed,
            velocity: Vec2::zeros(),
            angular_velocity: 0.0,
            initial_stress: None,
            edge_interfaces: Vec::new(),
        }
    }
}

/// A point force, optionally scaled by a piecewise-linear factor in time.
#[derive(Debug, Clone)]
pub struct Load {
    pub body: usize,
    /// Point of application in the initial configuration (moves with the body).
    pub point: Vec2,
    pub force: Vec2,
    /// (time, factor) pairs with strictly increasing times; `None` means factor 1.
    pub history: Option<Vec<(f64, f64)>>,
}

impl Load {
    /// Load factor at time `t`: piecewise linear between the history points, constant
    /// beyond the first and last ones.
    pub fn factor(&self, t: f64) -> f64 {
        history_factor(self.history.as_deref(), t)
    }
}

// Boundary tractions (`[[traction]]`): the data; the loads they give are in `crate::traction`
// (math note §2.5).

/// How the traction vector follows from the boundary's outward normal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TractionLaw {
    /// Normal pressure [Pa] (positive pushes into the body) and shear [Pa] along the boundary,
    /// positive in the direction that keeps the body on the left (counter-clockwise around the
    /// outline).
    Pressure { pressure: f64, shear: f64 },
    /// A stress (σx, σy, τxy) [Pa], tension positive: t = σ n.
    Stress([f64; 3]),
}

/// A loaded piece of one boundary edge: `nodes` are the edge's ends `a → b` (polygon vertex or
/// mesh node indices, the body on the left), loaded from parameter `s[0]` to `s[1]` (0 at a,
/// 1 at b).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Piece {
    pub nodes: [usize; 2],
    pub s: [f64; 2],
}

/// A traction on one body.
#[derive(Debug, Clone, PartialEq)]
pub struct Traction {
    /// Index into `Model::bodies`.
    pub body: usize,
    pub pieces: Vec<Piece>,
    pub law: TractionLaw,
    /// (time, factor) pairs, as a point load's; `None`: factor 1.
    pub history: Option<Vec<(f64, f64)>>,
}

/// What a connector is, with its constants (paper §5; math note §6).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum ConnectorKind {
    /// Axial spring `k l lᵀ` of finite length; isotropic `k I` at zero length (typo 16).
    Spring {
        /// k [N/m].
        stiffness: f64,
    },
    /// Link EA/l along the anchors' line (paper eqs. 75-84).
    Bolt {
        /// E [Pa].
        young: f64,
        /// A [m²] per unit thickness.
        area: f64,
    },
    /// 2-node Timoshenko beam, corrected (math note §6, typos 12-15).
    Beam {
        /// E [Pa].
        young: f64,
        /// A [m²] per unit thickness.
        area: f64,
        /// Second moment of area I [m⁴] (typo 13).
        inertia: f64,
        /// G [Pa].
        shear_modulus: f64,
        /// k_Be = 1/κ of eq. 89 (1.2 rectangle, 10/9 circle); 0 = Euler-Bernoulli.
        shear_factor: f64,
    },
}

impl ConnectorKind {
    /// The scene-file word: "spring", "bolt" or "beam" (also the `kind` column of connectors.csv).
    pub fn as_str(&self) -> &'static str {
        match self {
            ConnectorKind::Spring { .. } => "spring",
            ConnectorKind::Bolt { .. } => "bolt",
            ConnectorKind::Beam { .. } => "beam",
        }
    }
}

/// A validated `[[connector]]`: two anchors, each held by a body (resolved from `bodies` or from
/// the shape that contains it). The bodies differ and at most one of them is fixed.
#[derive(Debug, Clone, PartialEq)]
pub struct ConnectorSpec {
    /// Unique; `connector-N` (N from 1 in file order) when the scene gives none.
    pub name: String,
    pub kind: ConnectorKind,
    /// Indices into `Model::bodies` of the bodies holding anchor 1 and anchor 2.
    pub bodies: [usize; 2],
    /// The anchors in the initial configuration (material points of their bodies).
    pub points: [Vec2; 2],
    /// Axial tension at t = 0 [N] (bolt, finite spring); 0 when not given.
    pub pretension: f64,
    /// Axial tension beyond which the connector breaks for good [N]; `None`: never.
    pub strength: Option<f64>,
    /// Bolt: the axial force [N] at which it yields (elastic-perfectly-plastic, math note §6.1);
    /// `None`: elastic.
    pub yield_force: Option<f64>,
    /// Bolt: the axial (total) strain beyond which it breaks for good; `None`: never.
    pub ultimate_strain: Option<f64>,
}

#[derive(Debug, Clone)]
pub struct Monitor {
    pub name: String,
    pub body: usize,
    /// Material point in the initial configuration.
    pub point: Vec2,
}

#[derive(Debug, Clone, Copy)]
pub struct OutputSettings {
    /// Write every N-th step (the last step is always written).
    pub every: usize,
    /// Write a `steps.csv` row every N-th step (the last step always); default `every`.
    pub steps_every: usize,
    /// Write the ParaView time series `DIR/vtk/` (default true).
    pub vtk: bool,
}
