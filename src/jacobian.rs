//! The contact Jacobian B in global DOF indices (math note §3.1): row r of B is the gap
//! direction `s n_kᵀ T_b(x_k)` (normal), `s τ_kᵀ T_b(x_k)` (tangent) or `s e_θᵀ` (rolling) of
//! contact k, with entries only in the DOFs the contact touches.
//!
//! B is stored as *segments*: the part of one row on one contiguous DOF range of at most six
//! entries (a body's DOFs; later a mesh node's). A contact between two bodies has two
//! segments per row; a contact on a mesh edge would have one per node. Every product with B
//! or Bᵀ runs over the segments in the order they were pushed, so results do not depend on
//! threads or hashing.

use crate::body::{Dofs, MAX_DOF};

/// The part of one row of B on one DOF range.
#[derive(Debug, Clone, Copy)]
pub struct Segment {
    pub row: usize,
    /// The cluster owning the DOFs.
    pub cluster: usize,
    /// First global DOF.
    pub start: usize,
    /// Number of DOFs (≤ 6); `vals` is zero beyond it.
    pub len: usize,
    pub vals: Dofs,
}

impl Segment {
    /// The segment's entries dotted with its range of `v` (a global vector, or a cluster-local
    /// one for segments with cluster-local starts). Over its own `len` entries, without padding
    /// them to six through a copy: the padding's products are zeros, so the sum is the same.
    pub fn dot(&self, v: &[f64]) -> f64 {
        dot(&self.vals.as_slice()[..self.len], &v[self.start..self.start + self.len])
    }
}

/// a · b over the shorter of the two, summed in order (B's products and the body form's share
/// it, so that their sums agree bit for bit).
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[derive(Debug, Clone, Default)]
pub struct Jacobian {
    pub rows: usize,
    pub segments: Vec<Segment>,
}

impl Jacobian {
    /// Clears the Jacobian for `rows` rows, keeping its storage.
    pub fn reset(&mut self, rows: usize) {
        self.rows = rows;
        self.segments.clear();
    }

    /// Adds the entries `vals[..len]` of row `row` at DOFs `start..start + len` of `cluster`.
    pub fn push(&mut self, row: usize, cluster: usize, start: usize, len: usize, vals: Dofs) {
        debug_assert!(len <= MAX_DOF);
        if len > 0 {
            self.segments.push(Segment { row, cluster, start, len, vals });
        }
    }

    /// `out = B v` for a global DOF vector `v`.
    pub fn apply(&self, v: &[f64], out: &mut Vec<f64>) {
        out.clear();
        out.resize(self.rows, 0.0);
        for s in &self.segments {
            out[s.row] += s.dot(v);
        }
    }

    /// `out += Bᵀ z` over the rows that `keep` selects.
    pub fn transpose_apply(&self, z: &[f64], keep: impl Fn(usize) -> bool, out: &mut [f64]) {
        for s in self.segments.iter().filter(|s| keep(s.row)) {
            for (i, x) in out[s.start..s.start + s.len].iter_mut().enumerate() {
                *x += s.vals[i] * z[s.row];
            }
        }
    }
}
