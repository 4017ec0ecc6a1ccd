//! W's part over single-body clusters in *body form* (math note §3.3): never assembled, applied
//! through the bodies instead. `W z` adds `B_c K̃_c⁻¹ B_cᵀ z` for every such cluster c by
//! accumulating each body's generalized force `u_c = Σ_r B_r|cᵀ z_r` over its rows, one closed-form
//! 6×6 product `v_c = K̃_c⁻¹ u_c`, and each row's `B_r|c · v_c`: about 2·(segment length) + 36/rows
//! multiply-adds per row and body, against the ~20 nonzeros per row of an assembled W on a pile
//! of disks, and no assembly at all. The diagonal is formed exactly (each row's segments on
//! one body paired), and so is a bound of |W| per body for Gershgorin's bound.

use crate::body::{BodyMatrix, Dofs};
use crate::cluster::Flexibility;
use crate::dofs::DofMap;
use crate::jacobian::Jacobian;
use std::sync::Mutex;

/// Numbers per body in the compact body vectors (the padded DOF count).
const STRIDE: usize = crate::body::MAX_DOF;

/// One segment of B on a body-form cluster.
#[derive(Debug, Clone)]
struct Seg {
    row: usize,
    /// Its first DOF in the compact body vector (body index × STRIDE + local DOF).
    at: usize,
    len: usize,
    vals: Dofs,
}

/// The body-form clusters' part of W (see the module docs).
#[derive(Debug, Default)]
pub(super) struct BodyPart {
    /// Segments in push order (which fixes every sum's order).
    segs: Vec<Seg>,
    /// K̃_c⁻¹ of each body-form cluster, in compact order.
    kinv: Vec<BodyMatrix>,
    /// The segments body by body (`body_start` has `bodies + 1` offsets into `by_body`).
    by_body: Vec<usize>,
    body_start: Vec<usize>,
    /// Work storage of `apply`: u and v, 2 × STRIDE per body.
    work: Mutex<Vec<f64>>,
}

impl BodyPart {
    /// The part over the clusters with `body[c]` (each a single body with a closed-form K̃⁻¹),
    /// adding its share of diag(W) to `diagonal`.
    pub fn new(
        jac: &Jacobian,
        flex: &Flexibility,
        map: &DofMap,
        body: &[bool],
        diagonal: &mut [f64],
    ) -> Self {
        let mut compact = vec![usize::MAX; body.len()];
        let mut kinv = Vec::new();
        for (c, _) in body.iter().enumerate().filter(|(_, b)| **b) {
            if let Some(k) = flex.body_inverse(c) {
                compact[c] = kinv.len();
                kinv.push(*k);
            }
        }
        let segs: Vec<Seg> = (jac.segments.iter())
            .filter(|s| compact[s.cluster] != usize::MAX)
            .map(|s| Seg {
                row: s.row,
                at: compact[s.cluster] * STRIDE + (s.start - map.cluster_range(s.cluster).start),
                len: s.len,
                vals: s.vals,
            })
            .collect();
        let (by_body, body_start) = group(segs.iter().map(|s| s.at / STRIDE), kinv.len());
        let part = BodyPart { segs, kinv, by_body, body_start, work: Mutex::new(Vec::new()) };
        part.add_diagonal(jac.rows, diagonal);
        part
    }

    pub fn is_empty(&self) -> bool {
        self.segs.is_empty()
    }

    /// W_rr += Σ over pairs (s, t) of row r's segments on one body of s K̃⁻¹ tᵀ.
    fn add_diagonal(&self, rows: usize, diagonal: &mut [f64]) {
        let (by_row, start) = group(self.segs.iter().map(|s| s.row), rows);
        for r in 0..rows {
            let mine = &by_row[start[r]..start[r + 1]];
            for &i in mine {
                let s = &self.segs[i];
                let body = s.at / STRIDE;
                let x = self.kinv[body] * self.padded(s);
                for t in mine.iter().map(|&j| &self.segs[j]).filter(|t| t.at / STRIDE == body) {
                    diagonal[r] += (0..t.len).map(|k| t.vals[k] * x[t.at % STRIDE + k]).sum::<f64>();
                }
            }
        }
    }

    /// A segment's values at its body's local DOFs.
    fn padded(&self, s: &Seg) -> Dofs {
        let mut d = Dofs::zeros();
        d.as_mut_slice()[s.at % STRIDE..s.at % STRIDE + s.len].copy_from_slice(&s.vals.as_slice()[..s.len]);
        d
    }

    /// out += W_bodies z.
    pub fn apply(&self, z: &[f64], out: &mut [f64]) {
        let n = self.kinv.len() * STRIDE;
        let mut guard = self.work.lock().unwrap_or_else(|e| e.into_inner());
        let work = &mut *guard;
        work.clear();
        work.resize(2 * n, 0.0);
        let (u, v) = work.split_at_mut(n);
        for s in &self.segs {
            let zr = z[s.row];
            for k in 0..s.len {
                u[s.at + k] += s.vals[k] * zr;
            }
        }
        for (b, k) in self.kinv.iter().enumerate() {
            let vb = k * Dofs::from_column_slice(&u[b * STRIDE..(b + 1) * STRIDE]);
            v[b * STRIDE..(b + 1) * STRIDE].copy_from_slice(vb.as_slice());
        }
        for s in &self.segs {
            out[s.row] += (0..s.len).map(|k| s.vals[k] * v[s.at + k]).sum::<f64>();
        }
    }

    /// out += M x with M = Σ_c Σ_{segments s, t on c} |s K̃_c⁻¹ tᵀ| (rows of s, t) >= |W_bodies|
    /// entrywise: the absolute values are taken per pair of segments, so for disks (one
    /// segment per row and body) M_rs differs from |W_rs| only where rows r and s share both
    /// bodies, and then by the triangle inequality. Costs Σ_c m_c² short dot products, m_c
    /// the segments on body c.
    pub fn abs_apply(&self, x: &[f64], out: &mut [f64]) {
        let mut guard = self.work.lock().unwrap_or_else(|e| e.into_inner());
        let cols = &mut *guard;
        for (b, k) in self.kinv.iter().enumerate() {
            let mine = &self.by_body[self.body_start[b]..self.body_start[b + 1]];
            cols.clear();
            for &t in mine {
                cols.extend_from_slice((k * self.padded(&self.segs[t])).as_slice());
            }
            for &s in mine {
                let (seg, local) = (&self.segs[s], self.segs[s].at % STRIDE);
                let mut acc = 0.0;
                for (j, &t) in mine.iter().enumerate() {
                    let col = &cols[j * STRIDE + local..j * STRIDE + local + seg.len];
                    let w: f64 = col.iter().zip(&seg.vals.as_slice()[..seg.len]).map(|(c, v)| c * v).sum();
                    acc += w.abs() * x[self.segs[t].row];
                }
                out[seg.row] += acc;
            }
        }
    }
}

/// Indices 0..n grouped by key (keys < `groups`), each group in index order (a counting
/// sort): the order and `groups + 1` offsets into it.
fn group(keys: impl Iterator<Item = usize> + Clone, groups: usize) -> (Vec<usize>, Vec<usize>) {
    let mut start = vec![0usize; groups + 1];
    for k in keys.clone() {
        start[k + 1] += 1;
    }
    for g in 0..groups {
        start[g + 1] += start[g];
    }
    let mut order = vec![0usize; start[groups]];
    let mut next = start[..groups].to_vec();
    for (i, k) in keys.enumerate() {
        order[next[k]] = i;
        next[k] += 1;
    }
    (order, start)
}
