//! Bodies: kinds, DOF layouts, the shape matrix T(x), mass, and the post-adjusted geometry
//! update. Part 1 of the engine: rigid bodies (3 DOF: u0, v0, θ) and fixed bodies (no DOF).

use crate::contact::BodyShape;
use crate::geometry::{Vec2, cross, perp, polygon_moments};
use crate::model::{BodySpec, Shape};
use nalgebra::{SMatrix, SVector};

/// Largest DOF count of any body kind (deformable polygon: u0, v0, θ, εx, εy, γxy).
pub const MAX_DOF: usize = 6;
/// A per-body DOF vector, padded with zeros beyond the body's DOF count.
pub type Dofs = SVector<f64, MAX_DOF>;
/// A per-body matrix (mass, stiffness, flexibility), padded with zeros.
pub type BodyMatrix = SMatrix<f64, MAX_DOF, MAX_DOF>;

/// The body's outline in the current configuration.
#[derive(Debug, Clone)]
pub enum Outline {
    Disk { radius: f64 },
    /// `outer` is R_E, `inner` is R_I.
    Ring { outer: f64, inner: f64 },
    /// Counter-clockwise vertices, current positions; `convex[k]`: interior angle < 180°.
    Polygon { vertices: Vec<Vec2>, convex: Vec<bool> },
}

/// One body: its constant properties and its state at the start of the current step.
#[derive(Debug, Clone)]
pub struct Body {
    pub name: String,
    pub material: usize,
    /// No degrees of freedom (math note §2.4: the exact limit of the papers' huge density).
    pub fixed: bool,
    pub outline: Outline,
    /// Current centroid.
    pub centroid: Vec2,
    /// Accumulated rotation [rad], ccw positive.
    pub rotation: f64,
    /// m = ρ A [kg/m].
    pub mass: f64,
    /// J = ρ ∫ r² dA about the centroid [kg m²/m].
    pub inertia: f64,
    /// Largest distance from the centroid to the outline (for motion bounds).
    pub reach: f64,
    /// Velocity at the start of the step, per DOF (v0 in math note §1).
    pub velocity: Dofs,
}

impl Body {
    /// Builds a body in its initial configuration from its validated spec.
    pub fn new(spec: &BodySpec, density: f64) -> Body {
        let (outline, centroid, area, polar) = match &spec.shape {
            Shape::Disk { center, radius } => {
                let r = *radius;
                let area = std::f64::consts::PI * r * r;
                (Outline::Disk { radius: r }, *center, area, 0.5 * area * r * r)
            }
            Shape::Ring { center, outer, inner } => (
                Outline::Ring { outer: *outer, inner: *inner },
                *center,
                std::f64::consts::PI * (outer * outer - inner * inner),
                0.5 * std::f64::consts::PI * (outer.powi(4) - inner.powi(4)),
            ),
            Shape::Polygon { vertices } => {
                let m = polygon_moments(vertices);
                let convex = convex_flags(vertices);
                let outline = Outline::Polygon { vertices: vertices.clone(), convex };
                (outline, m.centroid, m.area, m.sxx + m.syy)
            }
        };
        // math note §2.2: rigid M = ρ diag(S, S, Sxx + Syy), disk/ring J = ρ π (RE⁴ − RI⁴)/2;
        // `polar` is the polar second moment of area ∫ r² dA about the centroid.
        let inertia = density * polar;
        let mut velocity = Dofs::zeros();
        velocity[0] = spec.velocity.x;
        velocity[1] = spec.velocity.y;
        velocity[2] = spec.angular_velocity;
        let mut body = Body {
            name: spec.name.clone(),
            material: spec.material,
            fixed: spec.fixed,
            outline,
            centroid,
            rotation: 0.0,
            mass: density * area,
            inertia,
            reach: 0.0,
            velocity: if spec.fixed { Dofs::zeros() } else { velocity },
        };
        body.reach = body.compute_reach();
        body
    }

    fn compute_reach(&self) -> f64 {
        match &self.outline {
            Outline::Disk { radius } => *radius,
            Outline::Ring { outer, .. } => *outer,
            Outline::Polygon { vertices, .. } => {
                vertices.iter().map(|v| (v - self.centroid).norm()).fold(0.0, f64::max)
            }
        }
    }

    /// Number of degrees of freedom (0 for fixed bodies).
    pub fn ndof(&self) -> usize {
        if self.fixed { 0 } else { 3 }
    }

    pub fn is_particle(&self) -> bool {
        !matches!(self.outline, Outline::Polygon { .. })
    }

    /// Consistent mass matrix M = ρ ∫ Tᵀ T dA about the centroid (math note §2.2).
    pub fn mass_matrix(&self) -> BodyMatrix {
        let mut m = BodyMatrix::zeros();
        if !self.fixed {
            m[(0, 0)] = self.mass;
            m[(1, 1)] = self.mass;
            m[(2, 2)] = self.inertia;
        }
        m
    }

    /// Elastic stiffness K_e (zero for rigid bodies; math note §2.3).
    pub fn elastic_stiffness(&self) -> BodyMatrix {
        BodyMatrix::zeros()
    }

    /// Row `dirᵀ T(x)` of the shape matrix (paper eq. 3): the generalized direction of a
    /// unit force `dir` applied at `x`. For a rigid body `[dir_x, dir_y, r × dir]`.
    pub fn shape_row(&self, x: Vec2, dir: Vec2) -> Dofs {
        let mut row = Dofs::zeros();
        if !self.fixed {
            row[0] = dir.x;
            row[1] = dir.y;
            row[2] = cross(x - self.centroid, dir);
        }
        row
    }

    /// Displacement `T(x) d` of the material point at `x` (linearized, paper eq. 3).
    pub fn displacement(&self, x: Vec2, d: &Dofs) -> Vec2 {
        if self.fixed {
            return Vec2::zeros();
        }
        Vec2::new(d[0], d[1]) + perp(x - self.centroid) * d[2]
    }

    /// Velocity of the material point at `x` (same map as [`Self::displacement`]).
    pub fn point_velocity(&self, x: Vec2) -> Vec2 {
        self.displacement(x, &self.velocity)
    }

    /// Upper bound of |T(x) d| over the body.
    pub fn max_displacement(&self, d: &Dofs) -> f64 {
        if self.fixed { 0.0 } else { Vec2::new(d[0], d[1]).norm() + d[2].abs() * self.reach }
    }

    /// Moves a material point by the increment `d` with the post-adjusted rigid rotation of
    /// paper eq. 16: x' = c + (u0, v0) + R(θ)(x − c), exact for any θ.
    pub fn moved_point(&self, x: Vec2, d: &Dofs) -> Vec2 {
        if self.fixed {
            return x;
        }
        let (s, c) = d[2].sin_cos();
        let r = x - self.centroid;
        self.centroid + Vec2::new(d[0], d[1]) + Vec2::new(c * r.x - s * r.y, s * r.x + c * r.y)
    }

    /// Applies the increment `d` (the post-adjusted `dbar` of math note §1.3) to the geometry.
    pub fn apply_increment(&mut self, d: &Dofs) {
        if self.fixed {
            return;
        }
        if let Outline::Polygon { vertices, .. } = &self.outline {
            let moved: Vec<Vec2> = vertices.iter().map(|&v| self.moved_point(v, d)).collect();
            if let Outline::Polygon { vertices, .. } = &mut self.outline {
                *vertices = moved;
            }
        }
        self.centroid += Vec2::new(d[0], d[1]);
        self.rotation += d[2];
    }

    /// The geometry contact detection sees.
    pub fn shape(&self) -> BodyShape {
        match &self.outline {
            Outline::Disk { radius } => BodyShape::Disk { center: self.centroid, radius: *radius },
            Outline::Ring { outer, inner } => {
                BodyShape::Ring { center: self.centroid, outer: *outer, inner: *inner }
            }
            Outline::Polygon { vertices, convex } => {
                BodyShape::Polygon { vertices: vertices.clone(), convex: convex.clone() }
            }
        }
    }

    /// Smallest feature size: particle radius (inner radius of a ring) or shortest edge.
    pub fn feature_size(&self) -> f64 {
        match &self.outline {
            Outline::Disk { radius } => *radius,
            Outline::Ring { outer, inner } => inner.min(outer - inner),
            Outline::Polygon { vertices, .. } => (0..vertices.len())
                .map(|i| (vertices[(i + 1) % vertices.len()] - vertices[i]).norm())
                .fold(f64::INFINITY, f64::min),
        }
    }

    /// Kinetic energy ½ vᵀ M v.
    pub fn kinetic_energy(&self) -> f64 {
        0.5 * self.velocity.dot(&(self.mass_matrix() * self.velocity))
    }
}

/// Convex flags of a counter-clockwise polygon's vertices (interior angle below 180°).
pub fn convex_flags(v: &[Vec2]) -> Vec<bool> {
    let n = v.len();
    (0..n).map(|i| cross(v[i] - v[(i + n - 1) % n], v[(i + 1) % n] - v[i]) > 0.0).collect()
}
