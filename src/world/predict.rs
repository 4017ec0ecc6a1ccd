//! Stage 1: the contact-free prediction d^f = K̃⁻¹ f (math note eq. 1.3), with
//! f = f_ext(t1) + (2/dt) M v0 + f_σ (eq. 1.2; loads at the end of the step, where the
//! implicit scheme evaluates the equation of motion).

use super::World;
use crate::body::Body;
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
        let mut df = vec![0.0; self.dofs.total()];
        for (load, p) in self.model.loads.iter().zip(&self.load_points) {
            let body: &Body = &self.bodies[load.body];
            let force = load_force(load, t1);
            if let Some(fe) = body.mesh.as_ref().filter(|_| !body.fixed) {
                fe.add_point_load(&mut df[self.dofs.range(load.body)], p.current, force);
                continue;
            }
            f[load.body] += body.shape_row(p.current, Vec2::x()) * force.x
                + body.shape_row(p.current, Vec2::y()) * force.y;
        }
        self.add_connector_loads(&mut df);
        for (b, fb) in f.iter().enumerate() {
            match self.bodies[b].mesh.as_ref().filter(|_| !self.bodies[b].fixed) {
                // a mesh body's load (math note §9.1)
                Some(fe) => {
                    let v0_scale = self.v0_scale();
                    let fm = fe.step_load(g, v0_scale, dt);
                    df[self.dofs.range(b)].iter_mut().zip(fm).for_each(|(x, v)| *x += v);
                }
                None => self.dofs.scatter_add(&mut df, b, fb),
            }
        }
        self.flex.solve_in_place(&self.dofs, &mut df);
        df
    }
}

/// Point-load force at time t.
fn load_force(load: &Load, t: f64) -> Vec2 {
    load.force * load.factor(t)
}
