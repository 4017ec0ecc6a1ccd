//! Stage 1: the contact-free prediction d^f = K̃⁻¹ f (math note eq. 1.3), with
//! f = f_ext(t1) + (2/dt) M v0 + f_σ (eq. 1.2; loads at the end of the step, where the
//! implicit scheme evaluates the equation of motion).

use super::World;
use crate::body::{Body, Dofs, Outline};
use crate::geometry::Vec2;
use crate::model::Load;

impl World {
    /// d^f as a global DOF vector.
    pub(super) fn predict(&self, t1: f64) -> Vec<f64> {
        let dt = self.h;
        let g = self.gravity(t1);
        let mut f: Vec<_> = self
            .bodies
            .iter()
            .map(|b| {
                let v0 = self.v0(b);
                let mut fb = b.mass_times(&v0) * (2.0 / dt)
                    + b.stress_load()
                    + b.damping_load(&v0, dt, self.damping());
                // body force, centroid reference (math note §2.4)
                fb[0] += b.mass * g.x;
                fb[1] += b.mass * g.y;
                fb
            })
            .collect();
        let mut df = vec![0.0; self.dof_map().total()];
        for (load, p) in self.model.loads.iter().zip(&self.load_points) {
            let body: &Body = &self.bodies[load.body];
            let force = load_force(load, t1);
            if let Some(fe) = body.mesh.as_ref().filter(|_| !body.fixed) {
                fe.add_point_load(&mut df[self.dof_map().range(load.body)], p.current, force);
                continue;
            }
            f[load.body] += body.shape_row(p.current, Vec2::x()) * force.x
                + body.shape_row(p.current, Vec2::y()) * force.y;
        }
        self.add_traction_loads(t1, &mut f, &mut df);
        self.add_connector_loads(&mut df);
        let dofs = self.dof_map();
        for (b, fb) in f.iter().enumerate() {
            match self.bodies[b].mesh.as_ref().filter(|_| !self.bodies[b].fixed) {
                // a mesh body's load (math note §9.1)
                Some(fe) => {
                    let v0_scale = self.v0_scale();
                    let fm = fe.step_load(g, v0_scale, dt);
                    df[dofs.range(b)].iter_mut().zip(fm).for_each(|(x, v)| *x += v);
                }
                None => dofs.scatter_add(&mut df, b, fb),
            }
        }
        self.flex.solve_in_place(dofs, &mut df);
        df
    }
}

impl World {
    /// The `[[traction]]` loads at time t1 on the step-start configuration (math note §2.5): a
    /// block's in `f` (the point load t ℓ at each piece's midpoint), a mesh's in `df` (its
    /// consistent nodal loads).
    fn add_traction_loads(&self, t1: f64, f: &mut [Dofs], df: &mut [f64]) {
        for tr in &self.model.tractions {
            let body = &self.bodies[tr.body];
            if body.fixed {
                continue;
            }
            if let Some(fe) = &body.mesh {
                let range = self.dof_map().range(tr.body);
                for (a, b, s, force) in tr.forces(|n| fe.nodes[n], t1) {
                    for (node, w) in [(a, 1.0 - s), (b, s)] {
                        for (d, c) in fe.pattern.dofs(node).into_iter().zip(0..2) {
                            if let Some(d) = d {
                                df[range.start + d] += w * force[c];
                            }
                        }
                    }
                }
                continue;
            }
            let Outline::Polygon { vertices, .. } = &body.outline else { continue };
            for (a, b, s, force) in tr.forces(|n| vertices[n], t1) {
                let x = vertices[a] + (vertices[b] - vertices[a]) * s;
                f[tr.body] += body.shape_row(x, Vec2::x()) * force.x + body.shape_row(x, Vec2::y()) * force.y;
            }
        }
    }
}

/// Point-load force at time t.
fn load_force(load: &Load, t: f64) -> Vec2 {
    load.force * load.factor(t)
}
