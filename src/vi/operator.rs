//! The operator W the solver sees (math note §3): products and the diagonal, plus the explicit
//! CSR storage when there is one (the solver then copies it once per call, scaled, and fuses
//! the products with the vector work of each sweep).

use std::ops::Deref;

use crate::sparse::CsrView;
use sprs::CsMatBase;

/// A square, symmetric, positive semidefinite W, seen through its products.
pub trait Operator: Sync {
    /// Number of rows (= columns) of W.
    fn dim(&self) -> usize;
    /// out = W z (overwrites out).
    fn apply(&self, z: &[f64], out: &mut [f64]);
    /// `out[j] = W_jj`.
    fn diagonal(&self, out: &mut [f64]);
    /// The explicit CSR matrix, when there is one: the solver then uses its fused, scaled fast path.
    fn as_csr(&self) -> Option<CsrView<'_>> {
        None
    }
    /// Overwrites `out` with row weights of a diagonal bound of the scaled Ŵ = S W S,
    /// S = diag(sc): xᵀ Ŵ x <= Σ_r out_r x_r² for every x, so that ‖Ŵ‖ <= max_r out_r, when that
    /// is cheap (MPRGP's step length then comes from it instead of power iterations); false
    /// otherwise (the default), out unspecified. For an explicit W, Gershgorin's rows
    /// out_r = sc_r Σ_j |W_rj| sc_j (xᵀAx <= Σ_rj |A_rj| (x_r² + x_j²)/2 for a symmetric A).
    fn row_bounds(&self, _sc: &[f64], _out: &mut [f64]) -> bool {
        false
    }
    /// Pushes `(i, j, W_ij)` onto `out` for the entries of W in rows and columns with `keep`
    /// set, duplicates to be summed, when W can be had entry by entry cheaply (MPRGP's face
    /// solves, math note §4.10, factorize the kept block); false otherwise (the default).
    fn entries(&self, _keep: &[bool], _out: &mut Vec<(usize, usize, f64)>) -> bool {
        false
    }
    /// Whether [`Self::entries`] gives W's entries, without making them (the default: no).
    fn has_entries(&self) -> bool {
        false
    }
}

/// W stored explicitly with both triangles, owned (`CsMat`) or borrowed (`CsMatView`). CSC
/// storage is accepted too: [`Operator::as_csr`] then reads it as CSR, i.e. returns Wᵀ, which
/// is W for the symmetric matrices the solver takes (`apply` and `diagonal` use W itself).
impl<P, J, D> Operator for CsMatBase<f64, usize, P, J, D>
where
    P: Deref<Target = [usize]> + Sync,
    J: Deref<Target = [usize]> + Sync,
    D: Deref<Target = [f64]> + Sync,
{
    fn dim(&self) -> usize {
        self.rows()
    }
    fn apply(&self, z: &[f64], out: &mut [f64]) {
        apply_view(self.view(), z, out);
    }
    fn diagonal(&self, out: &mut [f64]) {
        diagonal_view(self.view(), out);
    }
    fn as_csr(&self) -> Option<CsrView<'_>> {
        Some(if self.is_csr() { self.view() } else { self.transpose_view() })
    }
    fn row_bounds(&self, sc: &[f64], out: &mut [f64]) -> bool {
        gershgorin_rows(self.view(), sc, out);
        true
    }
    fn entries(&self, keep: &[bool], out: &mut Vec<(usize, usize, f64)>) -> bool {
        entries_view(self.view(), keep, out);
        true
    }
    fn has_entries(&self) -> bool {
        true
    }
}

/// out = W z for CSR or CSC storage.
fn apply_view(w: CsrView<'_>, z: &[f64], out: &mut [f64]) {
    if w.nnz() == 0 {
        out.fill(0.0); // no rows to walk (W of a scene of single bodies in body form)
    } else if w.is_csr() {
        for (o, row) in out.iter_mut().zip(w.outer_iterator()) {
            *o = row.iter().map(|(j, &v)| v * z[j]).sum();
        }
    } else {
        out.fill(0.0);
        for (j, col) in w.outer_iterator().enumerate() {
            for (i, &v) in col.iter() {
                out[i] += v * z[j];
            }
        }
    }
}

/// out_r = sc_r Σ_j |W_rj| sc_j (Gershgorin's rows of S W S) for CSR or CSC storage.
fn gershgorin_rows(w: CsrView<'_>, sc: &[f64], out: &mut [f64]) {
    out.fill(0.0);
    if w.nnz() == 0 {
        return; // no rows to walk
    }
    for (i, vec) in w.outer_iterator().enumerate() {
        for (j, &v) in vec.iter() {
            let (r, c) = if w.is_csr() { (i, j) } else { (j, i) };
            out[r] += sc[r] * v.abs() * sc[c];
        }
    }
}

/// The kept entries (`Operator::entries`) for CSR or CSC storage.
pub(crate) fn entries_view(w: CsrView<'_>, keep: &[bool], out: &mut Vec<(usize, usize, f64)>) {
    for (i, vec) in w.outer_iterator().enumerate() {
        for (j, &v) in vec.iter().filter(|(j, _)| keep[i] && keep[*j]) {
            out.push(if w.is_csr() { (i, j, v) } else { (j, i, v) });
        }
    }
}

/// out[j] = W_jj (duplicate entries summed) for CSR or CSC storage.
fn diagonal_view(w: CsrView<'_>, out: &mut [f64]) {
    out.fill(0.0);
    for (i, vec) in w.outer_iterator().enumerate() {
        for (j, &v) in vec.iter() {
            if j == i {
                out[i] += v;
            }
        }
    }
}
