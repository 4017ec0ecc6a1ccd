//! Stage 3: the contact rows, the VI's only input (math note §3.1, §4.4, §10.1, §10.3).
//!
//! Each contact's gap is linearized as `offset + Σ_b s_b nᵀ T_b(anchor_b) d_b` (plus the
//! tangent and rolling rows). On the first pass the anchors are the contact point, n the
//! detected normal and offset = g0; the refinement of math note §10.1 makes new
//! linearizations on the mid-step configuration, and so new rows. Rows are immutable once
//! built.

use super::World;
use super::detect::{Brief, Detected};
use crate::body::{Body, MAX_DOF, rigid_row};
use crate::contact::ContactGeom;
use crate::delassus;
use crate::dofs::DofMap;
use crate::geometry::{Vec2, cw};
use crate::jacobian::{Frame, Jacobian};
use crate::vi::Method;

/// The linearization of one contact's gap.
#[derive(Debug, Clone, Copy)]
pub(super) struct Linearization {
    pub normal: Vec2,
    /// Where the gap direction acts on body A and on body B.
    pub anchor: [Vec2; 2],
    pub offset: f64,
}

impl Linearization {
    /// The step-start linearization: contact point, detected normal, offset = g0 as the
    /// solver sees it.
    pub fn initial(geom: &ContactGeom, start_gap: f64) -> Linearization {
        Linearization { normal: geom.normal, anchor: [geom.point; 2], offset: start_gap }
    }
}

/// What a contact frame reads of one of its bodies, in 24 bytes: the body's step-start centroid
/// and, for a rigid body, its first DOF and cluster. Made in detection's pass over the bodies.
/// The rows read two per contact, scattered. Read through the bodies (336 bytes apiece) and the
/// DOF map's three tables, that would be four or five cache lines per body, which on a large
/// pile do not stay in the caches between the contacts that share a body.
#[derive(Debug, Clone, Copy)]
pub(super) struct Site {
    centroid: Vec2,
    /// First DOF of a rigid body alone in its cluster; [`Site::NONE`] for a fixed body, one with
    /// more DOFs, or one in a cluster of several.
    dof: u32,
    /// Cluster of a body with DOFs; [`Site::NONE`] for a fixed body.
    cluster: u32,
}

/// What a contact frame does with a body ([`Site::role`]).
enum Role {
    /// No DOFs: no column.
    Fixed,
    Rigid {
        dof: usize,
        cluster: usize,
    },
    /// Strain or mesh DOFs, or a body in a cluster of several: the contact is no frame.
    Other,
}

impl Site {
    const NONE: u32 = u32::MAX;

    /// Body `b`'s site: a rigid body alone in its cluster gives frames (the body form reads
    /// them, each body's K̃⁻¹ a 3 × 3 block of its own), any other body segments (a rigid body
    /// joined to others by a connector shares its cluster's K̃⁻¹: a dense block over the
    /// cluster's DOFs in body form, or the assembly's above 48 DOFs).
    pub fn of(body: &Body, b: usize, dofs: &DofMap) -> Site {
        let (range, cluster) = (dofs.range(b), dofs.cluster_of(b));
        let alone = cluster.is_some_and(|c| dofs.cluster_range(c) == range);
        let dof = if range.len() == 3 && alone { range.start as u32 } else { Site::NONE };
        Site { centroid: body.centroid, dof, cluster: cluster.map_or(Site::NONE, |c| c as u32) }
    }

    fn role(&self) -> Role {
        match (self.cluster, self.dof) {
            (Site::NONE, _) => Role::Fixed,
            (_, Site::NONE) => Role::Other,
            (cluster, dof) => Role::Rigid { dof: dof as usize, cluster: cluster as usize },
        }
    }
}

/// Storage the rows reuse across passes and steps (kept by the world's pipeline).
#[derive(Debug, Clone, Default)]
pub(super) struct Scratch {
    pub assembly: delassus::Scratch,
    /// Jacobians of rows no longer needed (`Pipeline::recycle`).
    pub spare: Vec<Jacobian>,
}

/// The VI's input: B (kept by W), q = offsets + B d^f, W = B K̃⁻¹ Bᵀ and the per-contact row
/// blocks.
pub(super) struct Rows {
    pub lin: Vec<Linearization>,
    pub q: Vec<f64>,
    pub w: delassus::ContactOperator,
    /// Contact k owns rows blocks[k]..blocks[k + 1].
    pub blocks: Vec<usize>,
}

impl Rows {
    /// B.
    pub fn jac(&self) -> &Jacobian {
        self.w.jacobian()
    }
}

impl World {
    /// Builds the rows of the contacts for the linearizations `lin`. Contacts for which
    /// `rigid(k)` holds act on the rigid-body DOFs only: their strain columns are zero (math
    /// note §10.3).
    pub(super) fn rows(
        &self,
        found: &Detected,
        lin: Vec<Linearization>,
        df: &[f64],
        rigid: impl Fn(usize) -> bool,
        scratch: &mut Scratch,
    ) -> Rows {
        let contacts = &found.brief;
        let mut blocks: Vec<usize> = contacts.iter().map(Brief::row).collect();
        let total = contacts.last().map_or(0, |c| c.rows().end);
        blocks.push(total);
        let mut jac = scratch.spare.pop().unwrap_or_default();
        jac.reset(total);
        let mut q = vec![0.0; total];
        // q = B d^f + offsets
        for (k, (c, l)) in contacts.iter().zip(&lin).enumerate() {
            match frame(c, l, &found.sites) {
                Some((frame, clusters)) => jac.push_frame(frame, clusters, df, &mut q),
                None => self.push_contact(&mut jac, c, l, rigid(k), df, &mut q),
            }
            q[c.row()] += l.offset;
        }
        let limit = delassus::EXPLICIT_LIMIT;
        // single bodies in body form, except for NSGS, whose sweeps read W's rows (math note §3.3)
        let bodies = self.model.solver.method.first() != Method::Nsgs;
        let w = delassus::ContactOperator::with_scratch(
            jac,
            &self.flex,
            self.dof_map(),
            limit,
            bodies,
            &mut scratch.assembly,
        );
        Rows { lin, q, w, blocks }
    }

    /// Rows normal, tangent and rolling of one contact on its two bodies (math note §3.1,
    /// §4.4: the rolling couple acts on θ alone, on a block too), with their share of q = B d^f,
    /// as segments: a contact that is no [`frame`].
    fn push_contact(
        &self,
        jac: &mut Jacobian,
        c: &Brief,
        l: &Linearization,
        rigid: bool,
        df: &[f64],
        q: &mut [f64],
    ) {
        let (n, tau, r) = (l.normal, cw(l.normal), c.row());
        for ((body, sign), x) in c.bodies().into_iter().zip([1.0, -1.0]).zip(l.anchor) {
            let b = &self.bodies[body];
            let Some(cluster) = self.dof_map().cluster_of(body) else { continue };
            let range = self.dof_map().range(body);
            let len = range.len();
            // (a body of 3 DOFs is rigid, never a mesh, whose DOFs come in pairs: its `mesh`
            // field stays unread)
            if len != 3
                && let Some(fe) = &b.mesh
            {
                // math note §9.2: the column has entries at the two nodes of the edge holding x,
                // c = s [(1 - t) e_i + t e_j] (x) [n, tau]; the full nodal column in solve 2 as well
                for (node, w) in fe.edge_weights(x).into_iter().filter(|&(_, w)| w != 0.0) {
                    if let Some(d) = fe.pattern.dof(node) {
                        for (row, dir) in [(r, n), (r + 1, tau)] {
                            let vals = [sign * w * dir.x, sign * w * dir.y];
                            jac.push_apply(row, cluster, range.start + d, &vals, df, q);
                        }
                        continue;
                    }
                    // a roller: its free component alone
                    for (c, d) in fe.pattern.dofs(node).into_iter().enumerate() {
                        let Some(d) = d else { continue };
                        for (row, dir) in [(r, n), (r + 1, tau)] {
                            jac.push_apply(row, cluster, range.start + d, &[sign * w * dir[c]], df, q);
                        }
                    }
                }
                continue;
            }
            for (row, dir) in [(r, n), (r + 1, tau)] {
                if len == 3 {
                    // a rigid body (no strain columns to zero), unrolled
                    jac.push_apply(row, cluster, range.start, &b.rigid_row(x, dir, sign), df, q);
                    continue;
                }
                let mut vals = [0.0; MAX_DOF];
                b.scaled_shape_row(x, dir, sign, &mut vals);
                if rigid {
                    vals[3..].fill(0.0); // the strain columns
                }
                jac.push_apply(row, cluster, range.start, &vals[..len], df, q);
            }
            if c.rolling() {
                let mut couple = [0.0; MAX_DOF];
                couple[2] = sign;
                jac.push_apply(r + 2, cluster, range.start, &couple[..len], df, q);
            }
        }
    }
}

/// The contact frame of a contact with no rolling row whose moving bodies are rigid (at least
/// one), and their clusters: the rows `push_contact` pushes for it, as one frame
/// (`jacobian::Frame`); `None` for any other contact. Inlined: returned through memory, the
/// result can be written by stores that the caller's wider loads cannot forward from (a
/// store-forwarding stall; math note §3.3, "Per-body tables").
#[inline(always)]
fn frame(c: &Brief, l: &Linearization, sites: &[Site]) -> Option<(Frame, [usize; 2])> {
    if c.rolling() {
        return None;
    }
    let (n, tau) = (l.normal, cw(l.normal));
    let mut frame: Option<(Frame, [usize; 2])> = None;
    for ((body, sign), x) in c.bodies().into_iter().zip([1.0, -1.0]).zip(l.anchor) {
        let site = &sites[body];
        let (dof, cluster) = match site.role() {
            Role::Fixed => continue,
            Role::Other => return None,
            Role::Rigid { dof, cluster } => (dof, cluster),
        };
        let (rn, rt) = (rigid_row(site.centroid, x, n, sign), rigid_row(site.centroid, x, tau, sign));
        frame = Some(match frame {
            None => (Frame::new(c.row(), dof, rn, rt), [cluster, cluster]),
            Some((f, [first, _])) => (f.with_second(dof, rn, rt), [first, cluster]),
        });
    }
    frame
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Vec2;
    use crate::model::{BodyModel, BodySpec, Material, Plane, Shape};

    /// Which bodies give contact frames (`Site::role`): of four disks, a rigid one alone in its
    /// cluster gives frames (its first DOF and cluster); a deformable one (4 DOFs) and two rigid
    /// ones joined into one cluster (by a connector between bodies 2 and 3) give segments; a fixed
    /// one has no column. A rigid body in a cluster of several has no 3 × 3 K̃⁻¹ of its own, which
    /// a frame reads, so its contacts must not be frames (math note §3.3, "Frames beside
    /// segments").
    #[test]
    fn frames_only_for_rigid_bodies_alone_in_their_clusters() {
        let material = Material { name: "m".into(), density: 2.0, young: Some(1e8), poisson: Some(0.3) };
        let (rigid, deformable) = (BodyModel::Rigid, BodyModel::Deformable);
        let kinds = [(rigid, false), (deformable, false), (rigid, false), (rigid, false), (rigid, true)];
        let bodies: Vec<Body> = kinds
            .iter()
            .enumerate()
            .map(|(i, &(model, fixed))| {
                let shape = Shape::Disk { center: Vec2::new(i as f64, 0.0), radius: 0.5 };
                Body::new(&BodySpec::at_rest(format!("b{i}"), shape, model, fixed), &material, Plane::Stress)
            })
            .collect();
        let map = DofMap::new(&bodies, &[(2, 3)]);
        let roles: Vec<String> = (0..5)
            .map(|b| match Site::of(&bodies[b], b, &map).role() {
                Role::Fixed => "fixed".to_string(),
                Role::Other => "segments".to_string(),
                Role::Rigid { dof, cluster } => format!("frame at {dof} in {cluster}"),
            })
            .collect();
        assert_eq!(roles, ["frame at 0 in 0", "segments", "segments", "segments", "fixed"]);
    }
}
