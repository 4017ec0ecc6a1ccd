//! Bodies: kinds, DOF layouts, the shape matrix T(x), mass, elastic stiffness, loads and the
//! post-adjusted geometry update (paper eqs. 3–7, 16–18; math note §2).
//!
//! DOF layouts (math note §0): rigid `(u0, v0, θ)`; deformable particle `(u0, v0, θ, ε)`;
//! deformable polygon `(u0, v0, θ, εx, εy, γxy)`; a fixed body has none.

use crate::contact::{BodyShape, HoleLoop};
use crate::geometry::{Vec2, cross, loop_contact_flags, polygon_contact_flags, polygon_moments};
use crate::mesh::body::MeshBody;
use crate::model::{BodyModel, BodySpec, Material, Plane, Shape};
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// Largest DOF count of any body kind (deformable polygon).
pub const MAX_DOF: usize = 6;
/// A per-body DOF vector, padded with zeros beyond the body's DOF count.
pub type Dofs = SVector<f64, MAX_DOF>;
/// A per-body matrix (mass, stiffness, flexibility), padded with zeros.
pub type BodyMatrix = SMatrix<f64, MAX_DOF, MAX_DOF>;

/// The rigid-body entries (u, v, θ) of the row of direction `dir` at `x`, scaled by `s`, of a
/// body whose centroid is `centroid` ([`Body::rigid_row`]).
#[inline(always)]
pub fn rigid_row(centroid: Vec2, x: Vec2, dir: Vec2, s: f64) -> [f64; 3] {
    [dir.x * s, dir.y * s, cross(x - centroid, dir) * s]
}

/// Upper bound of |T(x) d| over a body that is no mesh, of reach `reach`, for its DOFs `d`
/// (none: fixed; rigid 3; particle 4, its strain ε isotropic; polygon 6):
/// |(u0, v0)| + (|θ| + |εx| + |εy| + |γxy|) reach.
pub fn max_displacement(d: &[f64], reach: f64) -> f64 {
    let strain = match d.len() {
        0 => return 0.0,
        4 => 2.0 * d[3].abs(),
        6 => d[3].abs() + d[4].abs() + d[5].abs(),
        _ => 0.0,
    };
    Vec2::new(d[0], d[1]).norm() + (d[2].abs() + strain) * reach
}

/// The body's outline in the current configuration.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub enum Outline {
    Disk {
        radius: f64,
    },
    /// `outer` is R_E, `inner` is R_I.
    Ring {
        outer: f64,
        inner: f64,
    },
    /// Counter-clockwise vertices, current positions; `convex[k]`: interior angle < 180°.
    Polygon {
        vertices: Vec<Vec2>,
        convex: Vec<bool>,
    },
}

/// Area and central second moments of the current outline (math note §2.1).
#[derive(Debug, Clone, Copy, serde::Serialize, serde::Deserialize)]
struct Moments {
    area: f64,
    sxx: f64,
    syy: f64,
    sxy: f64,
}

/// One body: its constant properties and its state at the start of the current step.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct Body {
    pub name: String,
    pub material: usize,
    /// No degrees of freedom (math note §2.4: the exact limit of the papers' huge density).
    pub fixed: bool,
    pub deformable: bool,
    pub outline: Outline,
    /// Current centroid.
    pub centroid: Vec2,
    /// Accumulated rotation [rad], ccw positive.
    pub rotation: f64,
    /// m = ρ A [kg/m], conserved while the body deforms.
    pub mass: f64,
    /// Largest distance from the centroid to the outline (for motion bounds).
    pub reach: f64,
    /// Velocity per DOF: the initial velocity, then v1 of the last step (math note eq. 1.1).
    pub velocity: Dofs,
    /// Accumulated strain (εx, εy, γxy), engineering shear; zero for rigid bodies.
    pub strain: Vector3<f64>,
    /// Accumulated stress (σx, σy, τxy) [Pa], tension positive; zero for rigid bodies.
    pub stress: Vector3<f64>,
    /// Constitutive matrix D (math note §2.3); zero for rigid bodies.
    elastic: Matrix3<f64>,
    moments: Moments,
    /// The finite-element state of a mesh body (math note §9); `None` for every other body. The
    /// fields above then summarize it: outline = outer boundary loop, centroid, mean rotation,
    /// mean velocity and angular velocity (`velocity[0..3]`), mass.
    pub mesh: Option<Box<MeshBody>>,
}

impl Body {
    /// Builds a body in its initial configuration from its validated spec.
    pub fn new(spec: &BodySpec, material: &Material, plane: Plane) -> Body {
        if let Shape::Mesh(m) = &spec.shape {
            return Body::mesh(spec, m, material, plane);
        }
        let (outline, centroid) = match &spec.shape {
            Shape::Disk { center, radius } => (Outline::Disk { radius: *radius }, *center),
            Shape::Ring { center, outer, inner } => (Outline::Ring { outer: *outer, inner: *inner }, *center),
            Shape::Polygon { vertices } => {
                let convex = polygon_contact_flags(vertices, &spec.edge_interfaces);
                let outline = Outline::Polygon { vertices: vertices.clone(), convex };
                (outline, polygon_moments(vertices).centroid)
            }
            Shape::Mesh(_) => unreachable!("mesh bodies are built by Body::mesh"),
        };
        let deformable = spec.model == BodyModel::Deformable && !spec.fixed;
        let elastic = match (deformable, material.young, material.poisson) {
            (true, Some(e), Some(nu)) => constitutive(e, nu, plane),
            _ => Matrix3::zeros(),
        };
        let mut body = Body {
            name: spec.name.clone(),
            material: spec.material,
            fixed: spec.fixed,
            deformable,
            outline,
            centroid,
            rotation: 0.0,
            mass: 0.0,
            reach: 0.0,
            velocity: Dofs::zeros(),
            strain: Vector3::zeros(),
            stress: Vector3::from(spec.initial_stress.unwrap_or([0.0; 3])),
            elastic,
            moments: Moments { area: 0.0, sxx: 0.0, syy: 0.0, sxy: 0.0 },
            mesh: None,
        };
        body.refresh_geometry();
        body.mass = material.density * body.moments.area;
        if !spec.fixed {
            body.velocity[0] = spec.velocity.x;
            body.velocity[1] = spec.velocity.y;
            body.velocity[2] = spec.angular_velocity;
        }
        if body.deformable && body.is_particle() {
            // a particle carries an isotropic stress σ0 (math note §2.4)
            let s0 = 0.5 * (body.stress[0] + body.stress[1]);
            body.stress = Vector3::new(s0, s0, 0.0);
        }
        body
    }

    /// A mesh body (math note §9): always finite elements, whatever `model` says; a material
    /// without `young`/`poisson` (rejected by the scene) gives a zero D.
    fn mesh(spec: &BodySpec, shape: &crate::model::MeshShape, material: &Material, plane: Plane) -> Body {
        let elastic = match (material.young, material.poisson) {
            (Some(e), Some(nu)) => constitutive(e, nu, plane),
            _ => Matrix3::zeros(),
        };
        let fe = MeshBody::new(
            shape,
            material.density,
            elastic,
            spec.initial_stress.unwrap_or([0.0; 3]),
            spec.velocity,
            spec.angular_velocity,
        );
        let vertices = fe.outline();
        let mut body = Body {
            name: spec.name.clone(),
            material: spec.material,
            fixed: spec.fixed,
            deformable: !spec.fixed,
            outline: Outline::Polygon { convex: loop_contact_flags(&vertices), vertices },
            centroid: fe.centroid(),
            rotation: 0.0,
            mass: fe.mass(),
            reach: 0.0,
            velocity: Dofs::zeros(),
            strain: Vector3::zeros(),
            stress: Vector3::zeros(),
            elastic: Matrix3::zeros(),
            moments: Moments { area: 0.0, sxx: 0.0, syy: 0.0, sxy: 0.0 },
            mesh: Some(Box::new(fe)),
        };
        body.sync_mesh();
        body
    }

    /// Refreshes the summary fields of a mesh body from its nodes (outline, centroid, mean
    /// rotation and velocity).
    fn sync_mesh(&mut self) {
        let Some(fe) = &self.mesh else { return };
        let vertices = fe.outline();
        self.outline = Outline::Polygon { convex: loop_contact_flags(&vertices), vertices };
        self.centroid = fe.centroid();
        self.rotation = fe.rotation;
        let (v, omega) = if self.fixed { (Vec2::zeros(), 0.0) } else { fe.mean_motion() };
        self.velocity = Dofs::zeros();
        (self.velocity[0], self.velocity[1], self.velocity[2]) = (v.x, v.y, omega);
        self.refresh_geometry();
    }

    /// Applies a mesh body's step (math note §1.3, §9.4) from its parts `dbar`, `dvel` of the
    /// global vectors; `v0_scale` is the factor v0 = v0_scale × v of this step. No-op for others.
    pub fn apply_mesh_step(&mut self, dbar: &[f64], dvel: &[f64], v0_scale: f64, dt: f64) {
        if self.fixed {
            return;
        }
        if let Some(fe) = &mut self.mesh {
            fe.apply(dbar, dvel, v0_scale, dt);
            self.sync_mesh();
        }
    }

    /// Upper bound of the displacement of any point of the body under its part `d` of a global
    /// DOF vector (any body kind).
    pub fn max_motion(&self, d: &[f64]) -> f64 {
        match &self.mesh {
            Some(fe) => fe.max_motion(d),
            None => max_displacement(d, self.reach),
        }
    }

    /// Recomputes the moments and reach of the current outline.
    fn refresh_geometry(&mut self) {
        use std::f64::consts::PI;
        self.moments = match &self.outline {
            Outline::Disk { radius: r } => {
                let j = PI * r.powi(4) / 4.0;
                Moments { area: PI * r * r, sxx: j, syy: j, sxy: 0.0 }
            }
            Outline::Ring { outer, inner } => {
                let j = PI * (outer.powi(4) - inner.powi(4)) / 4.0;
                Moments { area: PI * (outer * outer - inner * inner), sxx: j, syy: j, sxy: 0.0 }
            }
            Outline::Polygon { vertices, .. } => {
                let m = polygon_moments(vertices);
                Moments { area: m.area, sxx: m.sxx, syy: m.syy, sxy: m.sxy }
            }
        };
        self.reach = match &self.outline {
            Outline::Disk { radius } => *radius,
            Outline::Ring { outer, .. } => *outer,
            Outline::Polygon { vertices, .. } => {
                vertices.iter().map(|v| (v - self.centroid).norm()).fold(0.0, f64::max)
            }
        };
    }

    /// Number of degrees of freedom.
    pub fn ndof(&self) -> usize {
        if let (Some(fe), false) = (&self.mesh, self.fixed) {
            return fe.ndof();
        }
        match (self.fixed, self.deformable, self.is_particle()) {
            (true, _, _) => 0,
            (false, false, _) => 3,
            (false, true, true) => 4,
            (false, true, false) => 6,
        }
    }

    pub fn is_particle(&self) -> bool {
        !matches!(self.outline, Outline::Polygon { .. })
    }

    /// Current area S.
    pub fn area(&self) -> f64 {
        self.moments.area
    }

    /// Current density: mass over current area (mass is conserved as the body deforms).
    fn density(&self) -> f64 {
        self.mass / self.moments.area
    }

    /// Consistent mass matrix M = ρ ∫ Tᵀ T dA about the centroid (math note §2.2).
    pub fn mass_matrix(&self) -> BodyMatrix {
        let mut m = BodyMatrix::zeros();
        let n = self.ndof();
        if n == 0 {
            return m;
        }
        let Moments { sxx, syy, sxy, .. } = self.moments;
        let rho = self.density();
        m[(0, 0)] = self.mass;
        m[(1, 1)] = self.mass;
        m[(2, 2)] = rho * (sxx + syy);
        if n == 4 {
            m[(3, 3)] = rho * (sxx + syy);
        } else if n == 6 {
            let entries = [
                (2, 3, -sxy),
                (2, 4, sxy),
                (2, 5, (sxx - syy) / 2.0),
                (3, 3, sxx),
                (3, 5, sxy / 2.0),
                (4, 4, syy),
                (4, 5, sxy / 2.0),
                (5, 5, (sxx + syy) / 4.0),
            ];
            for (i, j, v) in entries {
                m[(i, j)] = rho * v;
                m[(j, i)] = rho * v;
            }
        }
        m
    }

    /// The strain map B: strain (εx, εy, γxy) = B d (math note §2.3; a particle's ε acts on
    /// εx and εy alike), column j the strain of the unit increment e_j ([`Self::strain_of`],
    /// the one place the map is written).
    fn strain_map(&self) -> SMatrix<f64, 3, MAX_DOF> {
        SMatrix::from_columns(&std::array::from_fn::<_, MAX_DOF, _>(|j| self.strain_of(&Dofs::ith(j, 1.0))))
    }

    /// The strain B d of the increment d (math note §2.3), read off the strain DOFs: the product
    /// with [`Self::strain_map`] adds only exact zeros to them for finite d, so this is the same
    /// number without building and multiplying a 3 × 6 matrix for every body and every point
    /// moved (the product spread a non-finite rigid DOF into NaN strains; this keeps an
    /// infinite motion infinite).
    fn strain_of(&self, d: &Dofs) -> Vector3<f64> {
        match self.ndof() {
            4 => Vector3::new(d[3], d[3], 0.0),
            6 => Vector3::new(d[3], d[4], d[5]),
            _ => Vector3::zeros(),
        }
    }

    /// Elastic stiffness K_e = S Bᵀ D B (math note §2.3; for a particle K_44 =
    /// 2πE(RE² − RI²)/(1 − ν) in plane stress). Zero for rigid bodies.
    pub fn elastic_stiffness(&self) -> BodyMatrix {
        let b = self.strain_map();
        b.transpose() * self.elastic * b * self.moments.area
    }

    /// The body's step matrix K̃ = (1 + 2c) K + (2/dt²) M (math note §1.2, §10.9): the strain
    /// DOFs carry the numerical damping C = c dt K of §10.9 (c = `damping`, 0 for none).
    pub fn step_matrix(&self, dt: f64, damping: f64) -> BodyMatrix {
        self.elastic_stiffness() * (1.0 + 2.0 * damping) + self.mass_matrix() * (2.0 / (dt * dt))
    }

    /// The damping load C v0 = c dt K v0 of math note §10.9 for the coming step's v0.
    pub fn damping_load(&self, v0: &Dofs, dt: f64, damping: f64) -> Dofs {
        if damping == 0.0 || !self.deformable {
            return Dofs::zeros();
        }
        self.elastic_stiffness() * v0 * (damping * dt)
    }

    /// Initial-stress load f_σ = −S Bᵀ σ (math note §2.4; for a particle −2Aσ0).
    pub fn stress_load(&self) -> Dofs {
        -(self.strain_map().transpose() * self.stress) * self.moments.area
    }

    /// Row `dirᵀ T(x)` of the shape matrix (paper eqs. 3, 5, 7): the generalized direction
    /// of a unit force `dir` applied at `x`.
    pub fn shape_row(&self, x: Vec2, dir: Vec2) -> Dofs {
        let mut row = Dofs::zeros();
        self.scaled_shape_row(x, dir, 1.0, row.as_mut_slice());
        row
    }

    /// [`Self::shape_row`] times `s` into `out[..ndof]` (each entry computed as there, then
    /// multiplied by s): B's rows go straight into the Jacobian this way, with no six-vector
    /// built, scaled and copied per row.
    pub fn scaled_shape_row(&self, x: Vec2, dir: Vec2, s: f64, out: &mut [f64]) {
        let n = self.ndof();
        if n == 0 {
            return;
        }
        out[..3].copy_from_slice(&self.rigid_row(x, dir, s));
        let r = x - self.centroid;
        if n == 4 {
            out[3] = r.dot(&dir) * s;
        } else if n == 6 {
            out[3] = (r.x * dir.x) * s;
            out[4] = (r.y * dir.y) * s;
            out[5] = (0.5 * (r.y * dir.x + r.x * dir.y)) * s;
        }
    }

    /// The rigid-body entries (u, v, θ) of [`Self::scaled_shape_row`]: all of a rigid body's row.
    #[inline(always)]
    pub fn rigid_row(&self, x: Vec2, dir: Vec2, s: f64) -> [f64; 3] {
        rigid_row(self.centroid, x, dir, s)
    }

    /// Displacement `T(x) d` of the material point at `x` (linearized).
    pub fn displacement(&self, x: Vec2, d: &Dofs) -> Vec2 {
        Vec2::new(self.shape_row(x, Vec2::x()).dot(d), self.shape_row(x, Vec2::y()).dot(d))
    }

    /// Velocity of the material point at `x` (same map as [`Self::displacement`]).
    pub fn point_velocity(&self, x: Vec2) -> Vec2 {
        if let Some(fe) = &self.mesh {
            return fe.point_velocity(x);
        }
        self.displacement(x, &self.velocity)
    }

    /// Where the material point `x` goes under the increment `d`, with the post-adjusted
    /// rotation of paper eqs. 16–18: x' = c + (u0, v0) + R(θ)(x − c) + E (x − c), with
    /// E = [[εx, γxy/2], [γxy/2, εy]] (E = ε I for a particle).
    pub fn moved_point(&self, x: Vec2, d: &Dofs) -> Vec2 {
        if self.fixed {
            return x;
        }
        let (s, c) = d[2].sin_cos();
        let r = x - self.centroid;
        let e = self.strain_of(d);
        let rotated = Vec2::new(c * r.x - s * r.y, s * r.x + c * r.y);
        let strained = Vec2::new(e[0] * r.x + 0.5 * e[2] * r.y, 0.5 * e[2] * r.x + e[1] * r.y);
        self.centroid + Vec2::new(d[0], d[1]) + rotated + strained
    }

    /// Applies the increment `d` (the post-adjusted `dbar` of math note §1.3) to the geometry,
    /// and for a deformable body accumulates strain and stress, σ += D Δε (math note §2.4).
    pub fn apply_increment(&mut self, d: &Dofs) {
        if self.fixed {
            return;
        }
        let de = self.strain_of(d);
        let moved: Option<Vec<Vec2>> = match &self.outline {
            Outline::Polygon { vertices, .. } => {
                Some(vertices.iter().map(|&v| self.moved_point(v, d)).collect())
            }
            _ => None,
        };
        match &mut self.outline {
            Outline::Polygon { vertices, .. } => *vertices = moved.unwrap_or_default(),
            Outline::Disk { radius } => *radius *= 1.0 + de[0],
            Outline::Ring { outer, inner } => {
                *outer *= 1.0 + de[0];
                *inner *= 1.0 + de[0];
            }
        }
        self.centroid += Vec2::new(d[0], d[1]);
        self.rotation += d[2];
        if self.deformable {
            self.strain += de;
            self.stress += self.elastic * de;
            self.refresh_geometry();
        }
    }

    /// The geometry contact detection would see after the step's increment, without moving
    /// the body: `d` is the body's part of the global d̄ (as [`Self::apply_increment`] and
    /// [`Self::apply_mesh_step`] take it), and the shape has the bits those give it.
    pub fn moved_shape(&self, d: &[f64]) -> BodyShape {
        if self.fixed {
            return self.shape();
        }
        if let Some(fe) = &self.mesh {
            let nodes = fe.moved_nodes(d);
            let at = |ring: &[usize]| ring.iter().map(|&n| nodes[n]).collect::<Vec<_>>();
            let vertices = at(&fe.outer);
            let holes = fe.holes.iter().map(|h| at(h));
            return BodyShape::Polygon {
                convex: loop_contact_flags(&vertices),
                vertices,
                nodes: true,
                holes: holes.map(|v| HoleLoop { convex: loop_contact_flags(&v), vertices: v }).collect(),
            };
        }
        let d = Dofs::from_fn(|i, _| d.get(i).copied().unwrap_or(0.0));
        let center = self.centroid + Vec2::new(d[0], d[1]);
        let grow = 1.0 + self.strain_of(&d)[0];
        match &self.outline {
            Outline::Disk { radius } => BodyShape::Disk { center, radius: radius * grow },
            Outline::Ring { outer, inner } => {
                BodyShape::Ring { center, outer: outer * grow, inner: inner * grow }
            }
            Outline::Polygon { vertices, convex } => BodyShape::Polygon {
                vertices: vertices.iter().map(|&v| self.moved_point(v, &d)).collect(),
                convex: convex.clone(),
                nodes: false,
                holes: Vec::new(),
            },
        }
    }

    /// The geometry contact detection sees.
    pub fn shape(&self) -> BodyShape {
        match &self.outline {
            Outline::Disk { radius } => BodyShape::Disk { center: self.centroid, radius: *radius },
            Outline::Ring { outer, inner } => {
                BodyShape::Ring { center: self.centroid, outer: *outer, inner: *inner }
            }
            Outline::Polygon { vertices, convex } => BodyShape::Polygon {
                vertices: vertices.clone(),
                convex: convex.clone(),
                nodes: self.mesh.is_some(),
                holes: self.mesh.as_ref().map_or_else(Vec::new, |fe| {
                    let loops = fe.hole_outlines().into_iter();
                    loops.map(|v| HoleLoop { convex: loop_contact_flags(&v), vertices: v }).collect()
                }),
            },
        }
    }

    /// Smallest feature size: particle radius (ring wall or hole) or shortest edge (of a mesh's
    /// holes too).
    pub fn feature_size(&self) -> f64 {
        let shortest = |v: &[Vec2]| {
            (0..v.len()).map(|i| (v[(i + 1) % v.len()] - v[i]).norm()).fold(f64::INFINITY, f64::min)
        };
        match &self.outline {
            Outline::Disk { radius } => *radius,
            Outline::Ring { outer, inner } => inner.min(outer - inner),
            Outline::Polygon { vertices, .. } => {
                let holes = self.mesh.as_ref().map_or_else(Vec::new, |fe| fe.hole_outlines());
                holes.iter().map(|h| shortest(h)).fold(shortest(vertices), f64::min)
            }
        }
    }

    /// Kinetic energy ½ vᵀ M v.
    pub fn kinetic_energy(&self) -> f64 {
        if let Some(fe) = &self.mesh {
            return fe.kinetic_energy();
        }
        0.5 * self.velocity.dot(&self.mass_times(&self.velocity))
    }

    /// M v (`mass_matrix`). A rigid body's M is diag(m, m, ρ(sxx + syy)): its three products
    /// are the 6 × 6 product's nonzero terms, the same values (a sign of zero aside, which the
    /// sums that use them drop), which spares building the matrix and the product for each
    /// body, in the prediction and again in the kinetic energy. Inlined: called, it reads the
    /// caller's v, just stored by narrower stores, with 16-byte loads that cannot forward from
    /// them (a store-forwarding stall; math note §3.3, "Per-body tables").
    #[inline(always)]
    pub fn mass_times(&self, v: &Dofs) -> Dofs {
        if self.ndof() == 3 {
            let (m, i) = (self.mass, self.density() * (self.moments.sxx + self.moments.syy));
            return Dofs::from([m * v[0], m * v[1], i * v[2], 0.0, 0.0, 0.0]);
        }
        self.mass_matrix() * v
    }
}

/// Plane-stress or plane-strain constitutive matrix, engineering shear (math note §2.3).
pub fn constitutive(e: f64, nu: f64, plane: Plane) -> Matrix3<f64> {
    match plane {
        Plane::Stress => {
            let k = e / (1.0 - nu * nu);
            Matrix3::new(k, k * nu, 0.0, k * nu, k, 0.0, 0.0, 0.0, k * (1.0 - nu) / 2.0)
        }
        Plane::Strain => {
            let k = e / ((1.0 + nu) * (1.0 - 2.0 * nu));
            Matrix3::new(
                k * (1.0 - nu),
                k * nu,
                0.0,
                k * nu,
                k * (1.0 - nu),
                0.0,
                0.0,
                0.0,
                k * (1.0 - 2.0 * nu) / 2.0,
            )
        }
    }
}

#[cfg(test)]
mod tests;
