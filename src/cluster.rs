//! Flexibility of the bodies and the contact operator W = B K⁻¹ Bᵀ (math note §3).
//!
//! Every body is its own cluster here: K is at most 6×6, inverted once in closed form /
//! small dense Cholesky and cached while dt does not change. Clusters of bodies joined by
//! connectors (one sparse K per cluster) come with the connector work.

use crate::body::{Body, BodyMatrix, Dofs};
use sprs::CsMat;

/// K⁻¹ per body, K = K_e + (2/dt²) M (math note eq. 1.2).
#[derive(Debug, Clone)]
pub struct Flexibility {
    dt: f64,
    kinv: Vec<BodyMatrix>,
}

impl Flexibility {
    pub fn new(bodies: &[Body], dt: f64) -> Flexibility {
        let kinv = bodies.iter().map(|b| body_flexibility(b, dt)).collect();
        Flexibility { dt, kinv }
    }

    /// Recomputes K⁻¹ of the deformable bodies, whose mass and stiffness follow their
    /// current geometry; rigid bodies keep their cached K⁻¹.
    pub fn refresh(&mut self, bodies: &[Body]) {
        for (k, b) in self.kinv.iter_mut().zip(bodies) {
            if b.deformable {
                *k = body_flexibility(b, self.dt);
            }
        }
    }

    /// K⁻¹ of body `b` (zero for a fixed body).
    pub fn of(&self, b: usize) -> &BodyMatrix {
        &self.kinv[b]
    }
}

/// K⁻¹ of one body; the n×n leading block of the padded matrix.
fn body_flexibility(body: &Body, dt: f64) -> BodyMatrix {
    let n = body.ndof();
    let k = body.elastic_stiffness() + body.mass_matrix() * (2.0 / (dt * dt));
    let mut out = BodyMatrix::zeros();
    if n == 0 {
        return out;
    }
    let block = k.view((0, 0), (n, n)).clone_owned();
    // K is SPD (the mass term guarantees it, math note §3.2).
    let inv = block.cholesky().map(|c| c.inverse()).unwrap_or_else(|| {
        // Unreachable for positive mass; fall back to a pseudo-inverse-free zero response.
        nalgebra::DMatrix::zeros(n, n)
    });
    out.view_mut((0, 0), (n, n)).copy_from(&inv);
    out
}

/// The contact Jacobian B, stored per body: for each body the rows of B that touch it,
/// as (row index, row restricted to the body's DOFs). Row `r` of B is the gap direction
/// `s n_kᵀ T_b(x_k)` (normal), `s τ_kᵀ T_b(x_k)` (tangent) of math note §3.1.
#[derive(Debug, Clone, Default)]
pub struct Jacobian {
    pub rows: usize,
    pub per_body: Vec<Vec<(usize, Dofs)>>,
}

impl Jacobian {
    pub fn new(bodies: usize, rows: usize) -> Jacobian {
        Jacobian { rows, per_body: vec![Vec::new(); bodies] }
    }

    pub fn push(&mut self, body: usize, row: usize, entry: Dofs) {
        self.per_body[body].push((row, entry));
    }

    /// `B d` for per-body DOF vectors `d`.
    pub fn apply(&self, d: &[Dofs]) -> Vec<f64> {
        let mut out = vec![0.0; self.rows];
        for (b, entries) in self.per_body.iter().enumerate() {
            for (r, j) in entries {
                out[*r] += j.dot(&d[b]);
            }
        }
        out
    }

    /// Response `K⁻¹ Bᵀ z` per body (paper eq. 22: d^p = K⁻¹ C p). `keep(row)` selects rows.
    pub fn response(&self, flex: &Flexibility, z: &[f64], keep: impl Fn(usize) -> bool) -> Vec<Dofs> {
        self.per_body
            .iter()
            .enumerate()
            .map(|(b, entries)| {
                let load = entries
                    .iter()
                    .filter(|(r, _)| keep(*r))
                    .fold(Dofs::zeros(), |acc, (r, j)| acc + j * z[*r]);
                flex.of(b) * load
            })
            .collect()
    }

    /// W = B K⁻¹ Bᵀ, sparse and symmetric (both triangles stored): block (k, l) is non-zero
    /// only when contacts k and l share a body (math note eq. 3.2). Built row by row straight
    /// into CSR: row r collects J_r · K_b⁻¹ J_s over the (at most two) bodies b of row r and
    /// the rows s on b, so there is no global triplet sort.
    pub fn operator(&self, flex: &Flexibility) -> CsMat<f64> {
        // K_b⁻¹ J_s for every entry, and where each row sits in the per-body lists
        let cols: Vec<Vec<Dofs>> = self
            .per_body
            .iter()
            .enumerate()
            .map(|(b, entries)| entries.iter().map(|(_, j)| flex.of(b) * j).collect())
            .collect();
        let mut at: Vec<Vec<(usize, usize)>> = vec![Vec::new(); self.rows];
        for (b, entries) in self.per_body.iter().enumerate() {
            for (p, (r, _)) in entries.iter().enumerate() {
                at[*r].push((b, p));
            }
        }
        let (mut indptr, mut indices, mut data) = (Vec::with_capacity(self.rows + 1), Vec::new(), Vec::new());
        indptr.push(0);
        let mut row: Vec<(usize, f64)> = Vec::new();
        for places in &at {
            row.clear();
            for &(b, p) in places {
                let jr = &self.per_body[b][p].1;
                row.extend(self.per_body[b].iter().zip(&cols[b]).map(|((s, _), f)| (*s, jr.dot(f))));
            }
            row.sort_unstable_by_key(|e| e.0);
            for &(s, v) in &row {
                if indices.last() == Some(&s) && indices.len() > indptr[indptr.len() - 1] {
                    *data.last_mut().expect("entry pushed with its index") += v;
                } else {
                    indices.push(s);
                    data.push(v);
                }
            }
            indptr.push(indices.len());
        }
        CsMat::new((self.rows, self.rows), indptr, indices, data)
    }
}

/// Checks a DOF vector for NaN or infinity.
pub fn is_finite(d: &Dofs) -> bool {
    d.iter().all(|x| x.is_finite())
}
