//! The state and mechanics of a mesh body (math note §9): nodal positions, per-DOF velocities,
//! accumulated element stresses; its step matrix K̄ = Σ (K_e + (2/dt²) M_e) (§9.1), step load,
//! the two-node contact column (§9.2) and the objective update (§9.4).
//!
//! DOFs are the free nodes' `(u_x, u_y)` in the order of [`Pattern`]; fixed nodes have none.

use nalgebra::{Matrix2, Matrix3, Vector3};

use super::MeshShape;
use super::loops::contact_loops;
use super::tri3::{Pattern, Tri3, Vec6};
use crate::geometry::{Vec2, cross};

/// Area coordinates closer than this count as a tie in [`MeshBody::locate`].
const LOCATE_TIE: f64 = 1e-12;

/// One mesh body in its current configuration.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct MeshBody {
    /// Node positions at t = 0.
    pub reference: Vec<Vec2>,
    /// Node positions now.
    pub nodes: Vec<Vec2>,
    /// Accumulated displacement of each node, summed from the step increments (more precise than
    /// `nodes - reference` when the displacements are small against the coordinates).
    pub displacement: Vec<Vec2>,
    /// Counter-clockwise triangles (node indices).
    pub triangles: Vec<[usize; 3]>,
    /// Sparse pattern over the free nodes' DOFs (a function of the mesh: not in a checkpoint's
    /// state, which takes it from the scene's body).
    #[serde(skip)]
    pub pattern: Pattern,
    /// Whether any node is fixed (then no rigid split in the update, §9.4).
    pub has_fixed: bool,
    /// Outer boundary loop (node indices, counter-clockwise): the polygon contacts see (§9.2).
    pub outer: Vec<usize>,
    /// The holes' boundary loops (node indices, clockwise, material on their left): contacts are
    /// detected on them as on the outer loop (§9.2).
    pub holes: Vec<Vec<usize>>,
    /// Velocity per DOF: the initial velocity, then v1 of the last step (math note eq. 1.1).
    pub velocity: Vec<f64>,
    /// Accumulated element strain (εx, εy, γxy).
    pub strain: Vec<Vector3<f64>>,
    /// Accumulated element stress (σx, σy, τxy) [Pa], tension positive.
    pub stress: Vec<Vector3<f64>>,
    /// Constitutive matrix D (math note §2.3).
    pub elastic: Matrix3<f64>,
    /// ρ [kg/m³] of the initial configuration.
    pub density: f64,
    /// Initial area of each element: its mass ρ A_e0 is conserved as it deforms.
    pub initial_area: Vec<f64>,
    /// Accumulated rigid rotation of the mesh (the mean rotation of §9.4) [rad].
    pub rotation: f64,
}

impl MeshBody {
    /// A mesh body at rest in its initial position, moving rigidly with `velocity` and `omega` about
    /// its centroid, every element carrying `initial_stress`.
    pub fn new(
        shape: &MeshShape,
        density: f64,
        elastic: Matrix3<f64>,
        initial_stress: [f64; 3],
        velocity: Vec2,
        omega: f64,
    ) -> MeshBody {
        let m = &shape.mesh;
        let pattern = Pattern::with_rollers(m.nodes.len(), &m.triangles, &shape.fixed_nodes, &shape.rollers);
        let (outer, holes) = contact_loops(&m.nodes, &m.triangles);
        let ne = m.triangles.len();
        let mut body = MeshBody {
            reference: m.nodes.clone(),
            nodes: m.nodes.clone(),
            displacement: vec![Vec2::zeros(); m.nodes.len()],
            triangles: m.triangles.clone(),
            has_fixed: !shape.fixed_nodes.is_empty() || !shape.rollers.is_empty(),
            outer,
            holes,
            velocity: vec![0.0; pattern.n_dof],
            pattern,
            strain: vec![Vector3::zeros(); ne],
            stress: vec![Vector3::from(initial_stress); ne],
            elastic,
            density,
            initial_area: m.triangles.iter().map(|&t| Tri3::of(&m.nodes, t).area).collect(),
            rotation: 0.0,
        };
        let c = body.centroid();
        for n in 0..body.nodes.len() {
            let r = body.nodes[n] - c;
            let v = [velocity.x - omega * r.y, velocity.y + omega * r.x];
            for (d, v) in body.pattern.dofs(n).into_iter().zip(v) {
                if let Some(d) = d {
                    body.velocity[d] = v;
                }
            }
        }
        body
    }

    /// Number of DOFs (twice the free nodes).
    pub fn ndof(&self) -> usize {
        self.pattern.n_dof
    }

    fn element(&self, e: usize) -> Tri3 {
        Tri3::of(&self.nodes, self.triangles[e])
    }

    /// Current density of element `e` (shape `t`): its mass ρ A_e0 over its current area.
    fn rho(&self, e: usize, t: &Tri3) -> f64 {
        self.density * self.initial_area[e] / t.area
    }

    /// Current area Σ A_e.
    pub fn area(&self) -> f64 {
        (0..self.triangles.len()).map(|e| self.element(e).area).sum()
    }

    /// Mass ρ Σ A_e of the initial configuration (conserved).
    pub fn mass(&self) -> f64 {
        self.density * self.initial_area.iter().sum::<f64>()
    }

    /// Area centroid of the current configuration.
    pub fn centroid(&self) -> Vec2 {
        let (mut a, mut s) = (0.0, Vec2::zeros());
        for (e, t) in self.triangles.iter().enumerate() {
            let ae = self.element(e).area;
            a += ae;
            s += (self.nodes[t[0]] + self.nodes[t[1]] + self.nodes[t[2]]) * (ae / 3.0);
        }
        s / a
    }

    /// Lumped nodal masses ρ A_e / 3 per node (weights of the rigid split, §9.4).
    pub fn nodal_masses(&self) -> Vec<f64> {
        let mut m = vec![0.0; self.nodes.len()];
        for (e, t) in self.triangles.iter().enumerate() {
            let me = self.density * self.initial_area[e] / 3.0;
            t.iter().for_each(|&n| m[n] += me);
        }
        m
    }

    /// Node `n`'s part of a DOF vector (zero for a fixed node or component, and for every node
    /// of a fixed body, whose DOF vector is empty).
    pub fn node_value(&self, v: &[f64], n: usize) -> Vec2 {
        let [x, y] = self.pattern.dofs(n).map(|d| d.and_then(|d| v.get(d)).copied().unwrap_or(0.0));
        Vec2::new(x, y)
    }

    /// Lower-triangle triplets `(row, col, value)` of K̄ = Σ (K_e + (2/dt²) M_e) on the current
    /// configuration (math note §9.1), in the body's DOF numbering.
    pub fn step_triplets(&self, dt: f64) -> Vec<(usize, usize, f64)> {
        let mut values = vec![0.0; self.pattern.nnz()];
        let c = 2.0 / (dt * dt);
        self.pattern.assemble(&mut values, |e| {
            let t = self.element(e);
            t.stiffness(&self.elastic) + t.mass(self.rho(e, &t)) * c
        });
        let p = &self.pattern;
        let mut out = Vec::with_capacity(p.nnz() / 2 + p.n_dof);
        for col in 0..p.n_dof {
            let span = p.indptr[col]..p.indptr[col + 1];
            for (&row, &v) in p.indices[span.clone()].iter().zip(&values[span]) {
                if row >= col {
                    out.push((row, col, v));
                }
            }
        }
        out
    }

    /// Step load f = (2/dt) M v0 + f_body + f_σ (math note §9.1), v0 = `v0_scale` × velocity.
    pub fn step_load(&self, gravity: Vec2, v0_scale: f64, dt: f64) -> Vec<f64> {
        let v0: Vec<f64> = self.velocity.iter().map(|v| v * v0_scale).collect();
        self.pattern.assemble_vector(|e| {
            let t = self.element(e);
            t.mass(self.rho(e, &t)) * self.pattern.gather(&v0, e) * (2.0 / dt)
                + t.body_force(self.rho(e, &t), gravity)
                + t.stress_load(&self.stress[e])
        })
    }

    /// The triangle holding `x` (current configuration) and its area coordinates: the first that
    /// holds it to within [`LOCATE_TIE`] in area coordinates ([`super::first_holding`], the
    /// rule of [`super::Mesh::locate`]), so that a point on an edge or node, which lies in every
    /// triangle that shares it, does not switch triangles (and a monitor stresses) by round-off
    /// from step to step; a point outside every triangle goes to the nearest by area coordinates.
    pub fn locate(&self, x: Vec2) -> Option<(usize, [f64; 3])> {
        super::first_holding(&self.nodes, &self.triangles, x, LOCATE_TIE).or_else(|| {
            let worst = |l: &[f64; 3]| l.iter().fold(f64::INFINITY, |m, &v| m.min(v));
            self.triangles
                .iter()
                .enumerate()
                .map(|(e, &t)| (e, super::area_coords(&self.nodes, t, x)))
                .max_by(|a, b| worst(&a.1).total_cmp(&worst(&b.1)))
        })
    }

    /// How the point with area coordinates `l` in triangle `e` moves: `(DOF, component, weight)`
    /// of each free DOF of the triangle's nodes (component 0 = x, 1 = y), `u = Σ L_i u_i` (math
    /// note §9.2, eqs. 99-101).
    pub fn point_dofs(&self, e: usize, l: [f64; 3]) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        self.triangles[e].iter().zip(l).flat_map(move |(&n, w)| {
            let [x, y] = self.pattern.dofs(n);
            [x.map(|d| (d, 0, w)), y.map(|d| (d, 1, w))].into_iter().flatten()
        })
    }

    /// How the material of triangle `e` turns: `(DOF, ∂ω/∂u)` of each free DOF of its nodes, in
    /// the order of [`MeshBody::point_dofs`], ω = ½(∂u_y/∂x − ∂u_x/∂y) the infinitesimal
    /// rotation, constant on a Tri3: `ω = Σ (β_i u_y,i − γ_i u_x,i) / (4A)` (math note §9.2,
    /// beams on a mesh).
    pub fn rotation_dofs(&self, e: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let t = Tri3::of(&self.nodes, self.triangles[e]);
        let s = 0.25 / t.area;
        self.triangles[e].iter().enumerate().flat_map(move |(i, &n)| {
            let [x, y] = self.pattern.dofs(n);
            [x.map(|d| (d, -s * t.gamma[i])), y.map(|d| (d, s * t.beta[i]))].into_iter().flatten()
        })
    }

    /// Adds a point force at `x` (current configuration) to `f`: `L_i F` on the nodes of the
    /// triangle holding x (math note §9.2, eqs. 99-101).
    pub fn add_point_load(&self, f: &mut [f64], x: Vec2, force: Vec2) {
        let Some((e, l)) = self.locate(x) else { return };
        for (d, c, w) in self.point_dofs(e, l) {
            f[d] += w * force[c];
        }
    }

    /// The material point at `x` interpolated from the DOF vector `v`: `Σ L_i v_i`.
    pub fn interpolate(&self, x: Vec2, v: &[f64]) -> Vec2 {
        let Some((e, l)) = self.locate(x) else { return Vec2::zeros() };
        self.triangles[e].iter().enumerate().map(|(k, &n)| self.node_value(v, n) * l[k]).sum()
    }

    /// Velocity of the material point at `x`.
    pub fn point_velocity(&self, x: Vec2) -> Vec2 {
        self.interpolate(x, &self.velocity)
    }

    /// Stress of the element holding `x`.
    pub fn stress_at(&self, x: Vec2) -> Vector3<f64> {
        self.locate(x).map_or(Vector3::zeros(), |(e, _)| self.stress[e])
    }

    /// The contact column's weights at `x` (math note §9.2): the nearest boundary edge `(i, j)`
    /// (outer loop or hole) and `[(i, 1 - s), (j, s)]` with `x ≈ (1 - s) x_i + s x_j`.
    pub fn edge_weights(&self, x: Vec2) -> [(usize, f64); 2] {
        let mut best = (f64::INFINITY, [(0, 1.0), (0, 0.0)]);
        let edges = std::iter::once(&self.outer).chain(&self.holes).flat_map(|l| {
            let n = l.len();
            (0..n).map(move |k| (l[k], l[(k + 1) % n]))
        });
        for (i, j) in edges {
            let (a, b) = (self.nodes[i], self.nodes[j]);
            let ab = b - a;
            let s = ((x - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0);
            let dist = (a + ab * s - x).norm();
            if dist < best.0 {
                best = (dist, [(i, 1.0 - s), (j, s)]);
            }
        }
        best.1
    }

    /// Largest nodal displacement under the DOF vector `d`.
    pub fn max_motion(&self, d: &[f64]) -> f64 {
        (0..self.nodes.len()).map(|n| self.node_value(d, n)).map(|v| v.x.hypot(v.y)).fold(0.0, f64::max)
    }

    /// Current positions of the outer loop (the polygon contacts see).
    pub fn outline(&self) -> Vec<Vec2> {
        self.outer.iter().map(|&n| self.nodes[n]).collect()
    }

    /// Current positions of each hole's loop.
    pub fn hole_outlines(&self) -> Vec<Vec<Vec2>> {
        self.holes.iter().map(|l| l.iter().map(|&n| self.nodes[n]).collect()).collect()
    }

    /// Kinetic energy ½ vᵀ M v with the consistent mass.
    pub fn kinetic_energy(&self) -> f64 {
        let mv = self.pattern.assemble_vector(|e| {
            let t = self.element(e);
            t.mass(self.rho(e, &t)) * self.pattern.gather(&self.velocity, e)
        });
        0.5 * mv.iter().zip(&self.velocity).map(|(a, b)| a * b).sum::<f64>()
    }

    /// Mass-weighted mean velocity and angular velocity about the centroid (bodies.csv).
    pub fn mean_motion(&self) -> (Vec2, f64) {
        let (t, theta) = self.rigid_part(&self.velocity);
        (t, theta)
    }

    /// Best rigid motion of the DOF vector `u` (math note §9.4): translation `t = Σ m_i u_i / Σ m_i`
    /// and rotation `θ = Σ m_i r_i × (u_i − t) / Σ m_i |r_i|²` about the centroid.
    fn rigid_part(&self, u: &[f64]) -> (Vec2, f64) {
        let m = self.nodal_masses();
        let c = self.centroid();
        let total: f64 = m.iter().sum();
        let t = (0..self.nodes.len()).map(|n| self.node_value(u, n) * m[n]).sum::<Vec2>() / total;
        let (mut num, mut den) = (0.0, 0.0);
        for (n, (&x, &mn)) in self.nodes.iter().zip(&m).enumerate() {
            let r = x - c;
            num += mn * cross(r, self.node_value(u, n) - t);
            den += mn * r.norm_squared();
        }
        (t, if den > 0.0 { num / den } else { 0.0 })
    }

    /// Applies the step (math note §1.3, §9.4): nodes move by `dbar`, element strains and stresses
    /// accumulate `D B_e dbar_e`, velocities follow v1 = 2 d_vel/dt − v0. A mesh without fixed nodes
    /// splits `dbar` into its best rigid motion, applied exactly (rotation R(θ)), and a remainder
    /// applied linearly in the rotated frame; velocities and element stresses are rotated with it
    /// (stresses by each element's own rotation increment: Jaumann-type update).
    pub fn apply(&mut self, dbar: &[f64], dvel: &[f64], v0_scale: f64, dt: f64) {
        // strains and rotations of the elements on the start configuration
        for e in 0..self.triangles.len() {
            let t = self.element(e);
            let u: Vec6 = self.pattern.gather(dbar, e);
            let de = t.strain(&u);
            // ω_e = ½(∂u_y/∂x − ∂u_x/∂y) from the shape-function derivatives β/2A, γ/2A
            let (mut duy_dx, mut dux_dy) = (0.0, 0.0);
            let s = 0.5 / t.area;
            for i in 0..3 {
                duy_dx += s * t.beta[i] * u[2 * i + 1];
                dux_dy += s * t.gamma[i] * u[2 * i];
            }
            let rot = rotation(0.5 * (duy_dx - dux_dy));
            let sig = self.stress[e];
            let tensor = Matrix2::new(sig[0], sig[2], sig[2], sig[1]);
            let turned = rot * tensor * rot.transpose();
            self.stress[e] = Vector3::new(turned[(0, 0)], turned[(1, 1)], turned[(0, 1)]) + self.elastic * de;
            self.strain[e] += de;
        }
        let (theta, steps) = self.node_steps(dbar);
        let r = rotation(theta);
        for (n, step) in steps {
            self.nodes[n] += step;
            self.displacement[n] += step;
            let v0 = self.node_value(&self.velocity, n) * v0_scale;
            let v1 = r * (self.node_value(dvel, n) * (2.0 / dt) - v0);
            for (d, v) in self.pattern.dofs(n).into_iter().zip([v1.x, v1.y]) {
                if let Some(d) = d {
                    self.velocity[d] = v;
                }
            }
        }
        self.rotation += theta;
    }
}

impl MeshBody {
    /// The node positions after the increment `dbar` ([`Self::apply`]'s, bit for bit), the
    /// mesh unchanged.
    pub fn moved_nodes(&self, dbar: &[f64]) -> Vec<Vec2> {
        let mut nodes = self.nodes.clone();
        for (n, step) in self.node_steps(dbar).1 {
            nodes[n] += step;
        }
        nodes
    }

    /// The rotation θ of the rigid part of `dbar` and the step of each node with DOFs
    /// (math note §9.4): x' = c + t + R (r + w), with w = u − t − θ ẑ × r the remainder
    /// carried with the rotation, as the increment t + (R − I) r + R w.
    fn node_steps(&self, dbar: &[f64]) -> (f64, Vec<(usize, Vec2)>) {
        let (t, theta) = if self.has_fixed { (Vec2::zeros(), 0.0) } else { self.rigid_part(dbar) };
        let c = self.centroid();
        let r = rotation(theta);
        let steps = (0..self.nodes.len())
            .filter(|&n| self.pattern.dofs(n) != [None; 2])
            .map(|n| {
                let u = self.node_value(dbar, n);
                let rel = self.nodes[n] - c;
                let w = u - t - Vec2::new(-theta * rel.y, theta * rel.x);
                (n, t + (r - Matrix2::identity()) * rel + r * w)
            })
            .collect();
        (theta, steps)
    }
}

fn rotation(theta: f64) -> Matrix2<f64> {
    let (s, c) = theta.sin_cos();
    Matrix2::new(c, -s, s, c)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit square split into four triangles around its centre node 4: the centre lies in all
    /// four, a corner node in two, an edge's midpoint (on a diagonal) in two. `locate` takes the
    /// first triangle that holds the point, whatever the round-off of the point: moved by
    /// ±1e-15 (a few ulps of 1) in either coordinate, the answer is the same triangle. The
    /// expected indices are the first triangles (in the list below) that contain each point.
    #[test]
    fn a_point_on_shared_nodes_and_edges_locates_to_the_first_triangle_holding_it() {
        let nodes = vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.0, 1.0),
            Vec2::new(0.5, 0.5),
        ];
        let triangles = vec![[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]];
        let mesh = crate::mesh::Mesh {
            file: "test".into(),
            node_tags: (1..=5).collect(),
            nodes,
            triangles,
            groups: Vec::new(),
        };
        let shape = MeshShape { mesh, fixed_nodes: Vec::new(), rollers: Vec::new() };
        let fe = MeshBody::new(&shape, 1.0, Matrix3::identity(), [0.0; 3], Vec2::zeros(), 0.0);
        let cases = [
            (Vec2::new(0.5, 0.5), 0),   // the centre: all four
            (Vec2::new(1.0, 0.0), 0),   // corner node 1: triangles 0 and 1
            (Vec2::new(1.0, 1.0), 1),   // corner node 2: triangles 1 and 2
            (Vec2::new(0.0, 1.0), 2),   // corner node 3: triangles 2 and 3
            (Vec2::new(0.75, 0.75), 1), // on the diagonal 2-4: triangles 1 and 2
            (Vec2::new(0.5, 0.1), 0),   // inside triangle 0 only
        ];
        for (x, want) in cases {
            for (dx, dy) in [(0.0, 0.0), (1e-15, 0.0), (-1e-15, 0.0), (0.0, 1e-15), (0.0, -1e-15)] {
                let p = x + Vec2::new(dx, dy);
                assert_eq!(fe.locate(p).map(|(e, _)| e), Some(want), "point {p:?}");
            }
        }
    }
}
