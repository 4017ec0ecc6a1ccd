//! Connectors: bolts, springs and beams joining two bodies (paper §5, eqs. 75-92; math note §6).
//!
//! Every kind is one small *element*, rebuilt at each step start from the current anchors:
//! element quantities `e = G_1 d_1 + G_2 d_2` (m of them) with element stiffness `k` (m×m), so
//! the connector adds `G_pᵀ k G_q` to the (p, q) block of the global stiffness and the force it
//! carried into the step adds `−G_pᵀ F` to body p's load (math note §6, "forces carried").
//!
//! | kind | m | e | k |
//! |---|---|---|---|
//! | bolt, finite spring | 1 | elongation `lᵀ(u(A2) − u(A1))` | `EA/l` or `k` (eqs. 75-84; typo 16) |
//! | zero-length spring | 2 | `u(A2) − u(A1)` | `k I` (eqs. 85-86) |
//! | beam | 6 | `(u(A1), θ_1, u(A2), θ_2)` | corrected Timoshenko 6×6, ccw (typos 12-15) |
//!
//! Rotation of a material point, `E_b` (eq. 90): the DDA first-order map `u = T(x) d` (paper
//! eqs. 3, 5, 7) has the displacement gradient `[[εx, γxy/2 − θ], [γxy/2 + θ, εy]]` (`ε I` for a
//! particle), whose skew part, the rotation, is `θ` at every point. So `E_b` picks the rotation
//! DOF `r0 = θ` (index 2) for rigid and deformable bodies alike; the strain DOFs do not rotate.
//!
//! A fixed body has no DOFs: its `G` has no columns, so a connector anchored in it acts on the
//! free body alone. A broken connector contributes nothing.
//!
//! `G_p` acts on the DOFs of body p that the anchor moves with, listed in `cols` (body-local
//! indices): all of a block's or particle's DOFs, and for a mesh body the free DOFs of the three
//! nodes of the triangle holding the anchor, weighted by its area coordinates (math note §9.2,
//! as a point load), so a connector couples a mesh through six DOFs, never densely. A beam's end
//! on a mesh turns with the triangle holding it (its infinitesimal rotation, a combination of the
//! same six DOFs: [`anchor_rows`]).

use nalgebra::{DMatrix, DVector, Matrix6, Vector6};

use crate::body::{Body, Dofs};
use crate::geometry::Vec2;
#[cfg(doc)]
use crate::mesh::body::MeshBody;
pub use crate::model::ConnectorKind;
use crate::model::ConnectorSpec;

mod plastic;

/// Whether two anchors coincide (relative to their distance from the origin; exact zero for two
/// anchors at the origin). A zero-length spring is isotropic; a zero-length bolt or beam is an
/// input error.
pub fn is_zero_length(a: Vec2, b: Vec2) -> bool {
    (b - a).norm() <= 1e-12 * a.norm().max(b.norm())
}

/// The force a connector carries from one step into the next (math note §6).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum ConnectorForce {
    /// Bolt or finite spring: axial force N [N], tension positive, along the anchors' line.
    Axial(f64),
    /// Zero-length spring: the force on anchor 1's body [N], global axes (anchor 2's body gets
    /// the opposite); `k (x2 − x1)` for a spring that started at zero length.
    Isotropic(Vec2),
    /// Beam: the forces on the element's ends in its local frame (x from anchor 1 to anchor 2,
    /// y = x turned ccw): `(fx1, fy1, m1, fx2, fy2, m2) = k_local u_local`. The beam exerts the
    /// opposite on the bodies.
    Beam(Vector6<f64>),
}

/// A bolt, spring or beam between two bodies, in its state at the start of the current step.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Connector {
    pub name: String,
    pub kind: ConnectorKind,
    /// Indices of the bodies holding anchor 1 and anchor 2.
    pub bodies: [usize; 2],
    /// Current positions of the anchors (material points of their bodies).
    pub anchors: [Vec2; 2],
    pub force: ConnectorForce,
    /// Axial tension beyond which it breaks [N]; `None`: never.
    pub strength: Option<f64>,
    /// Broken for good: no stiffness, no force.
    pub broken: bool,
    /// The step it broke in (it is written to `connectors.csv` once more, at that step).
    pub broken_at: Option<usize>,
    /// Bolt and finite spring: the unstressed length, so that the axial force after each step is
    /// recomputed from the anchors' true distance (math note §10.7).
    rest_length: Option<f64>,
    /// Per anchor on a mesh body: its triangle and area coordinates, fixed from t = 0 (the
    /// anchor is a material point; see [`Connector::held_in`]).
    held: [Option<(usize, [f64; 3])>; 2],
    /// Bolt: yield force [N] and ultimate strain (math note §6.1); `None`: elastic, unbreakable.
    yield_force: Option<f64>,
    ultimate_strain: Option<f64>,
    /// Bolt: accumulated plastic strain ε_p, carried between steps (math note §6.1).
    pub plastic_strain: f64,
    /// Bolt: `Some(±Y)` while it is yielding, solved as the constant axial force ±Y with no
    /// axial stiffness (the active set of math note §6.1); `None`: elastic.
    plastic: Option<f64>,
    /// The last step in which it started to yield (written to `connectors.csv` whatever
    /// `[output] every` is).
    pub yielded_at: Option<usize>,
    /// The axial force it broke at [N] (written in its `broken` row).
    pub broke_with: Option<f64>,
    /// Whether it ended the last step yielding, and whether it started to yield in that step.
    ended_yielding: bool,
    began_yielding: bool,
}

/// One step's element: `e = G[0] d_1[cols[0]] + G[1] d_2[cols[1]]`, stiffness `k`, carried
/// force `force` (all in global axes).
struct Element {
    g: [DMatrix<f64>; 2],
    cols: [Vec<usize>; 2],
    k: DMatrix<f64>,
    force: DVector<f64>,
}

/// A stiffness block of a connector: `block` adds to the global K̃ at rows `ra` of body `a` and
/// columns `rb` of body `b` (body-local DOF indices).
#[derive(Debug, Clone)]
pub struct Coupling {
    pub a: usize,
    pub b: usize,
    pub ra: Vec<usize>,
    pub rb: Vec<usize>,
    pub block: DMatrix<f64>,
}

impl Connector {
    /// The connector at t = 0: anchors at the spec's points (the bodies' initial configuration),
    /// carrying its pretension (math note §6: P0 is the bolt's N0 at t = 0).
    pub fn from_spec(spec: &ConnectorSpec) -> Connector {
        let zero = is_zero_length(spec.points[0], spec.points[1]);
        let force = match spec.kind {
            ConnectorKind::Spring { .. } if zero => ConnectorForce::Isotropic(Vec2::zeros()),
            ConnectorKind::Spring { .. } | ConnectorKind::Bolt { .. } => {
                ConnectorForce::Axial(spec.pretension)
            }
            ConnectorKind::Beam { .. } => ConnectorForce::Beam(Vector6::zeros()),
        };
        Connector {
            name: spec.name.clone(),
            kind: spec.kind,
            bodies: spec.bodies,
            anchors: spec.points,
            force,
            strength: spec.strength,
            broken: false,
            broken_at: None,
            rest_length: None,
            held: [None, None],
            yield_force: spec.yield_force,
            ultimate_strain: spec.ultimate_strain,
            plastic_strain: 0.0,
            plastic: None,
            yielded_at: None,
            broke_with: None,
            ended_yielding: false,
            began_yielding: false,
        }
        .with_rest_length()
    }

    /// Records the triangle and area coordinates of each anchor inside a mesh body, once: the
    /// anchor then moves with those three nodes without a search per use. Without it an anchor
    /// on a mesh is located again at every use.
    pub fn held_in(mut self, bodies: &[Body]) -> Connector {
        for k in 0..2 {
            self.held[k] = bodies[self.bodies[k]].mesh.as_ref().and_then(|fe| fe.locate(self.anchors[k]));
        }
        self
    }

    /// Anchor k's map `u(A_k) = G d[cols]` ([`end_map`]).
    fn end(&self, bodies: &[Body], k: usize) -> (Vec<usize>, DMatrix<f64>) {
        end_map(&bodies[self.bodies[k]], self.anchors[k], self.held[k])
    }

    /// The rest length that gives the pretension at the initial length: l_r = l0 − P0/k for a
    /// spring, l_r = l0 EA/(EA + P0) for a bolt (N = EA (l − l_r)/l_r).
    fn with_rest_length(mut self) -> Connector {
        let (ConnectorForce::Axial(p0), l0) = (self.force, self.length()) else { return self };
        self.rest_length = match self.kind {
            ConnectorKind::Spring { stiffness } => Some(l0 - p0 / stiffness),
            ConnectorKind::Bolt { young, area } => Some(l0 * young * area / (young * area + p0)),
            ConnectorKind::Beam { .. } => None,
        };
        self
    }

    /// Axial force of a bolt or finite spring at the anchors' current distance (math note
    /// §10.7); `None` for the other kinds.
    fn axial_from_length(&self) -> Option<f64> {
        let (rest, l) = (self.rest_length?, self.length());
        match self.kind {
            ConnectorKind::Spring { stiffness } => Some(stiffness * (l - rest)),
            ConnectorKind::Bolt { young, area } => {
                Some(young * area * ((l - rest) / rest - self.plastic_strain))
            }
            ConnectorKind::Beam { .. } => None,
        }
    }

    /// Current distance between the anchors.
    pub fn length(&self) -> f64 {
        (self.anchors[1] - self.anchors[0]).norm()
    }

    /// Stiffness blocks for this step (step-start geometry), `G_pᵀ k G_q` for (1,1), (1,2),
    /// (2,1), (2,2) at the anchors' DOFs, skipping fixed bodies; empty once broken.
    pub fn stiffness(&self, bodies: &[Body]) -> Vec<Coupling> {
        if self.broken {
            return Vec::new();
        }
        let el = self.element(bodies);
        let mut blocks = Vec::with_capacity(4);
        for p in 0..2 {
            for q in 0..2 {
                if el.g[p].ncols() > 0 && el.g[q].ncols() > 0 {
                    blocks.push(Coupling {
                        a: self.bodies[p],
                        b: self.bodies[q],
                        ra: el.cols[p].clone(),
                        rb: el.cols[q].clone(),
                        block: el.g[p].transpose() * &el.k * &el.g[q],
                    });
                }
            }
            if let Some(k) = self.load_stiffness(bodies, p) {
                let b = self.bodies[p];
                let block = DMatrix::from_element(1, 1, k);
                blocks.push(Coupling { a: b, b, ra: vec![2], rb: vec![2], block });
            }
        }
        blocks
    }

    /// The rotational stiffness of the force F_p the connector applies at anchor p, r_p from the
    /// body's centroid: F_p · r_p (math note §10.7). Turning the body by θ swings the anchor and
    /// with it the moment of F_p about the centroid, −θ F_p · r_p to second order: the restoring
    /// moment of a block hanging from a bolt, which left explicit (to the anchors' update) made a
    /// block hanging 1 mm off-centre tumble under static relaxation. Only the stabilizing part
    /// (F_p · r_p > 0) is implicit, as for the tension's geometric stiffness; blocks and
    /// particles only (a mesh has no rotation DOF), beams not.
    fn load_stiffness(&self, bodies: &[Body], p: usize) -> Option<f64> {
        let body = &bodies[self.bodies[p]];
        if body.fixed || body.mesh.is_some() {
            return None;
        }
        // force on body 1 at anchor 1 (body 2 gets the opposite)
        let f1 = match self.force {
            ConnectorForce::Axial(n) => self.axis().0 * self.plastic.unwrap_or(n),
            ConnectorForce::Isotropic(f) => f,
            ConnectorForce::Beam(_) => return None,
        };
        let f = if p == 0 { f1 } else { -f1 };
        let k = f.dot(&(self.anchors[p] - body.centroid));
        (k > 0.0).then_some(k)
    }

    /// The step-start force as loads on the bodies' DOFs, `f_p = −G_pᵀ F` (math note §6: for a
    /// bolt `f_1 = T_1(A1)ᵀ l N0`, `f_2 = −T_2(A2)ᵀ l N0`): `(body, DOFs, values)`; fixed
    /// bodies and broken connectors get nothing.
    pub fn carried_load(&self, bodies: &[Body]) -> Vec<(usize, Vec<usize>, DVector<f64>)> {
        if self.broken {
            return Vec::new();
        }
        let el = self.element(bodies);
        let mut loads = Vec::with_capacity(2);
        for p in 0..2 {
            if el.g[p].ncols() > 0 {
                loads.push((self.bodies[p], el.cols[p].clone(), -(el.g[p].transpose() * &el.force)));
            }
        }
        loads
    }

    /// After the step: `F += k e(d)` from the bodies' DOF increments (math note §6:
    /// `N1 = N0 + (EA/l0) lᵀ(u(A2) − u(A1))`). `bodies_before` is the step-start state the
    /// stiffness was built on; `d(b, i)` is DOF i of body b's increment (not called for fixed
    /// bodies).
    pub fn update(&mut self, bodies_before: &[Body], d: &dyn Fn(usize, usize) -> f64) {
        if self.broken {
            return;
        }
        let el = self.element(bodies_before);
        let mut e = DVector::zeros(el.k.nrows());
        for p in 0..2 {
            let b = self.bodies[p];
            let dp = DVector::from_iterator(el.cols[p].len(), el.cols[p].iter().map(|&i| d(b, i)));
            e += &el.g[p] * dp;
        }
        let df = &el.k * e;
        self.force = match self.force {
            ConnectorForce::Axial(n) => {
                let (l, _) = self.axis();
                ConnectorForce::Axial(n + l.x * df[0] + l.y * df[1])
            }
            ConnectorForce::Isotropic(f) => ConnectorForce::Isotropic(f + Vec2::new(df[0], df[1])),
            ConnectorForce::Beam(f) => {
                let global = Vector6::from_iterator(df.iter().copied());
                ConnectorForce::Beam(f + self.to_local() * global)
            }
        };
    }

    /// Moves the anchors with their bodies (they are material points): `d(b, i)` is DOF i of
    /// the increment body b's geometry is updated with (the post-adjusted map of paper eqs.
    /// 16-18); an anchor on a mesh keeps its triangle and area coordinates.
    pub fn move_anchors(&mut self, bodies_before: &[Body], d: &dyn Fn(usize, usize) -> f64) {
        self.move_points(bodies_before, d);
        if let (false, Some(n)) = (self.broken, self.axial_from_length()) {
            self.force = ConnectorForce::Axial(n);
            self.return_to_yield();
        }
    }

    /// The anchors' motion of [`Connector::move_anchors`], the force left as it is.
    fn move_points(&mut self, bodies_before: &[Body], d: &dyn Fn(usize, usize) -> f64) {
        for k in 0..2 {
            let b = self.bodies[k];
            let body = &bodies_before[b];
            if body.fixed {
                continue;
            }
            let x = self.anchors[k];
            self.anchors[k] = if body.mesh.is_some() {
                let (cols, g) = self.end(bodies_before, k);
                let u = &g * DVector::from_iterator(cols.len(), cols.iter().map(|&i| d(b, i)));
                x + Vec2::new(u[0], u[1])
            } else {
                body.moved_point(x, &Dofs::from_fn(|i, _| if i < body.ndof() { d(b, i) } else { 0.0 }))
            };
        }
    }

    /// Axial force [N], tension positive (for a zero-length spring, the magnitude of its force).
    pub fn axial_force(&self) -> f64 {
        match self.force {
            ConnectorForce::Axial(n) => n,
            ConnectorForce::Isotropic(f) => f.norm(),
            ConnectorForce::Beam(f) => f[3],
        }
    }

    /// Beam only: the transverse force on the beam's end 2, along the axis turned ccw [N].
    pub fn shear_force(&self) -> Option<f64> {
        match self.force {
            ConnectorForce::Beam(f) => Some(f[4]),
            _ => None,
        }
    }

    /// Beam only: the moments the beam exerts on body 1 and body 2, ccw positive [N·m].
    pub fn end_moments(&self) -> Option<[f64; 2]> {
        match self.force {
            ConnectorForce::Beam(f) => Some([-f[2], -f[5]]),
            _ => None,
        }
    }

    /// Whether the axial tension exceeds the strength: the connector must break and its step be
    /// solved again without it (math note §6).
    pub fn exceeds_strength(&self) -> bool {
        !self.broken && self.strength.is_some_and(|s| self.axial_force() > s)
    }

    /// Breaks the connector for good: from now on it has no stiffness and carries nothing.
    pub fn break_off(&mut self) {
        self.broken = true;
    }

    /// Unit axis from anchor 1 to anchor 2 and its length (step-start geometry).
    fn axis(&self) -> (Vec2, f64) {
        let v = self.anchors[1] - self.anchors[0];
        let l = v.norm();
        (v / l, l)
    }

    /// Global-to-local rotation of the beam's 6-vector: blockdiag(Q, 1, Q, 1), Q = [[c, s], [−s, c]].
    fn to_local(&self) -> Matrix6<f64> {
        let (a, _) = self.axis();
        let mut r = Matrix6::identity();
        for o in [0, 3] {
            r[(o, o)] = a.x;
            r[(o, o + 1)] = a.y;
            r[(o + 1, o)] = -a.y;
            r[(o + 1, o + 1)] = a.x;
        }
        r
    }

    /// This step's element (see the module table).
    fn element(&self, bodies: &[Body]) -> Element {
        let b = [&bodies[self.bodies[0]], &bodies[self.bodies[1]]];
        match (self.kind, self.force) {
            (ConnectorKind::Spring { stiffness }, ConnectorForce::Isotropic(f)) => {
                let ((c1, g1), (c2, g2)) = (self.end(bodies, 0), self.end(bodies, 1));
                Element {
                    g: [-g1, g2],
                    cols: [c1, c2],
                    k: DMatrix::identity(2, 2) * stiffness,
                    force: DVector::from_column_slice(&[f.x, f.y]),
                }
            }
            (_, ConnectorForce::Axial(n)) => {
                let (l, len) = self.axis();
                // a yielding bolt: the constant force ±Y, no axial stiffness (math note §6.1)
                let n = self.plastic.unwrap_or(n);
                let k = match self.kind {
                    ConnectorKind::Bolt { .. } if self.plastic.is_some() => 0.0,
                    ConnectorKind::Bolt { young, area } => young * area / len,
                    ConnectorKind::Spring { stiffness } => stiffness,
                    ConnectorKind::Beam { .. } => unreachable!("a beam carries ConnectorForce::Beam"),
                };
                // axial stiffness k l lᵀ plus the geometric stiffness of the tension,
                // (N/l)(I − l lᵀ): a taut connector that turns keeps its force along the new
                // axis, and treating that explicitly makes stiff rotating chains unstable
                // (math note §10.7)
                let ll = nalgebra::Matrix2::new(l.x * l.x, l.x * l.y, l.x * l.y, l.y * l.y);
                let km = ll * k + (nalgebra::Matrix2::identity() - ll) * (n.max(0.0) / len);
                let ((c1, g1), (c2, g2)) = (self.end(bodies, 0), self.end(bodies, 1));
                Element {
                    g: [-g1, g2],
                    cols: [c1, c2],
                    k: DMatrix::from_column_slice(2, 2, km.as_slice()),
                    force: DVector::from_column_slice(&[n * l.x, n * l.y]),
                }
            }
            (ConnectorKind::Beam { .. }, ConnectorForce::Beam(f)) => self.beam_element(b, f),
            _ => unreachable!("from_spec pairs each kind with its force"),
        }
    }

    /// Beam element: `T_be = [[T_1(A1), 0], [E_1, 0], [0, T_2(A2)], [0, E_2]]` (eq. 90 corrected,
    /// typo 14; [`anchor_rows`]) and the corrected 6×6 of math note §6.
    fn beam_element(&self, b: [&Body; 2], local: Vector6<f64>) -> Element {
        let ends = [0, 1].map(|p| anchor_rows(b[p], self.anchors[p], self.held[p], true));
        let g = [0, 1].map(|p| {
            let (cols, rows) = &ends[p];
            let mut g = DMatrix::zeros(6, cols.len());
            g.view_mut((3 * p, 0), (3, cols.len())).copy_from(rows);
            g
        });
        let (axis, len) = self.axis();
        let global = self.to_local().transpose() * local;
        let [(c1, _), (c2, _)] = ends;
        Element {
            g,
            cols: [c1, c2],
            k: DMatrix::from_column_slice(6, 6, beam_matrix(&self.kind, len, axis).as_slice()),
            force: DVector::from_column_slice(global.as_slice()),
        }
    }
}

/// How the material point x of a body moves, `u(x) = G d[cols]` (body-local DOFs): `T_b(x)`
/// over all DOFs for a block or particle (paper eqs. 3, 5, 7); for a mesh body the area
/// coordinates of the triangle holding x (`held`, else located now) on its nodes' free DOFs
/// (math note §9.2).
fn end_map(body: &Body, x: Vec2, held: Option<(usize, [f64; 3])>) -> (Vec<usize>, DMatrix<f64>) {
    let (cols, g) = anchor_rows(body, x, held, false);
    (cols, g.rows(0, 2).into_owned())
}

/// How anchor x moves, `u(x) = G d[cols]` (rows 0 and 1, [`end_map`]), and with `turn` how a
/// beam's end there turns, `θ` (row 2, else 0): a block or particle turns by its rotation DOF r0
/// (`E_b`, module docs); on a mesh the anchor turns with the triangle holding it, whose rotation
/// ω = ½(∂u_y/∂x − ∂u_x/∂y) is a combination of the same three nodes' DOFs
/// ([`MeshBody::rotation_dofs`]), so the beam's end moment reaches the mesh as a couple of nodal
/// forces on that triangle (math note §9.2).
fn anchor_rows(
    body: &Body,
    x: Vec2,
    held: Option<(usize, [f64; 3])>,
    turn: bool,
) -> (Vec<usize>, DMatrix<f64>) {
    let Some(fe) = body.mesh.as_ref().filter(|_| !body.fixed) else {
        let n = body.ndof();
        let mut g = DMatrix::zeros(3, n);
        g.view_mut((0, 0), (2, n)).copy_from(&t_rows(body, x));
        if turn && n > 0 {
            g[(2, 2)] = 1.0; // E_b: the rotation DOF r0 (module docs)
        }
        return ((0..n).collect(), g);
    };
    let Some((e, l)) = held.or_else(|| fe.locate(x)) else { return (Vec::new(), DMatrix::zeros(3, 0)) };
    let mut cols = Vec::with_capacity(6);
    let mut g = DMatrix::zeros(3, 6);
    for (j, (d, c, w)) in fe.point_dofs(e, l).enumerate() {
        cols.push(d);
        g[(c, j)] = w;
    }
    if turn {
        // rotation_dofs lists the triangle's free DOFs in point_dofs' order
        for (j, (_, w)) in fe.rotation_dofs(e).enumerate() {
            g[(2, j)] = w;
        }
    }
    let n = cols.len();
    (cols, g.columns(0, n).into_owned())
}

/// `T_b(x)`: 2 × ndof (paper eqs. 3, 5, 7).
fn t_rows(body: &Body, x: Vec2) -> DMatrix<f64> {
    let n = body.ndof();
    let (rx, ry) = (body.shape_row(x, Vec2::x()), body.shape_row(x, Vec2::y()));
    DMatrix::from_fn(2, n, |i, j| if i == 0 { rx[j] } else { ry[j] })
}

/// The corrected 2-node Timoshenko beam in global axes, DOFs `(u1x, u1y, θ1, u2x, u2y, θ2)` with
/// ccw rotations (math note §6; the printed eq. 88 has every A3 sign flipped, typo 12):
/// `b = 12 EI k_Be/(G A l²)` (eq. 89), `A1 = EA/l`, `A2 = 12EI/((1+b)l³)`, `A3 = 6EI/((1+b)l²)`,
/// `A4 = (4+b)EI/((1+b)l)`, `A5 = (2−b)EI/((1+b)l)`, `(c, s)` the unit axis from anchor 1 to 2.
fn beam_matrix(kind: &ConnectorKind, l: f64, axis: Vec2) -> Matrix6<f64> {
    let ConnectorKind::Beam { young: e, area, inertia: i, shear_modulus: g, shear_factor } = *kind else {
        return Matrix6::zeros();
    };
    let b = 12.0 * e * i * shear_factor / (g * area * l * l);
    let a1 = e * area / l;
    let a2 = 12.0 * e * i / ((1.0 + b) * l.powi(3));
    let a3 = 6.0 * e * i / ((1.0 + b) * l * l);
    let a4 = (4.0 + b) * e * i / ((1.0 + b) * l);
    let a5 = (2.0 - b) * e * i / ((1.0 + b) * l);
    let (c, s) = (axis.x, axis.y);
    let xx = a1 * c * c + a2 * s * s;
    let xy = (a1 - a2) * c * s;
    let yy = a1 * s * s + a2 * c * c;
    #[rustfmt::skip]
    let k = Matrix6::new(
         xx,      xy,     -a3 * s, -xx,     -xy,     -a3 * s,
         xy,      yy,      a3 * c, -xy,     -yy,      a3 * c,
        -a3 * s,  a3 * c,  a4,      a3 * s, -a3 * c,  a5,
        -xx,     -xy,      a3 * s,  xx,      xy,      a3 * s,
        -xy,     -yy,     -a3 * c,  xy,      yy,     -a3 * c,
        -a3 * s,  a3 * c,  a5,      a3 * s, -a3 * c,  a4,
    );
    k
}
