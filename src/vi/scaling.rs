//! Jacobi scaling (math note §4.2): z = D^{-1/2} y, Ŵ = D^{-1/2} W D^{-1/2} (unit diagonal),
//! q̂ = D^{-1/2} q, with D = diag(W) guarded (`D_jj = 1` where `W_jj <= 0` or is not finite).
//! Without Jacobi the same vectors hold ones and D⁻¹ (for the residual).
//!
//! An explicit W ([`crate::sparse::Csr`]) is copied once per call with the scaling folded into
//! its values and `u32` column indices (12 instead of 16 bytes per nonzero; the copy is Ŵ, the
//! sweeps' working form of W, not a second matrix type); a matrix-free W is scaled by
//! vectors around each product. [`Rows`] gives the sweeps one interface to both.

use super::Operator;
use super::par;
use super::pc::larger;
use crate::sparse::CsrView;

/// The scaled W and q of one call, plus the zero rows (all stored entries 0, or for a
/// matrix-free W a zero diagonal, which for a PSD W forces the whole row to vanish).
#[derive(Debug, Clone, Default)]
pub(super) struct Scaling {
    /// Copy of an explicit W: row pointers, column indices, scaled values.
    pub rowptr: Vec<usize>,
    pub cols: Vec<u32>,
    pub vals: Vec<f64>,
    /// D^{1/2} (Jacobi) or 1: y = sd z.
    pub sd: Vec<f64>,
    /// D^{-1/2} (Jacobi) or 1: z = sc y.
    pub sc: Vec<f64>,
    /// Factor turning the scaled map into D⁻¹ G without Jacobi scaling: D⁻¹ = 1/`dd` (see
    /// [`Self::gs`]); empty with it.
    gs: Vec<f64>,
    /// The Jacobi scaling is on.
    jacobi: bool,
    /// q̂ = sc q.
    pub qs: Vec<f64>,
    /// D (guarded as above), for the gap part of the residual.
    pub dd: Vec<f64>,
    pub zero_rows: Vec<usize>,
}

impl Scaling {
    /// Sizes the vectors for n rows without clearing them: `set_factors` then sets every row's
    /// sd, sc and dd, and `scale_q` every row's qs, so clearing them was a wasted pass over
    /// four row vectors per solve.
    fn resize(&mut self, n: usize, jacobi: bool) {
        for v in [&mut self.sd, &mut self.sc, &mut self.qs, &mut self.dd] {
            v.resize(n, 0.0);
        }
        self.jacobi = jacobi;
        self.rowptr.clear();
        self.cols.clear();
        self.vals.clear();
        self.zero_rows.clear();
    }

    /// Factor turning the scaled map into D⁻¹ G: D^{-1/2} = `sc` with Jacobi scaling, else D⁻¹.
    /// With Jacobi the sweeps read `sc` for both, one stream of memory instead of two (0.48 MB
    /// a pass on the 10,000-disk pile's 60,000 rows).
    pub fn gs(&self) -> &[f64] {
        gs_of(self.jacobi, &self.sc, &self.gs)
    }

    /// Scaling factors of row i from its diagonal entry d (guarded here).
    fn set_factors(&mut self, i: usize, d: f64) {
        (self.sd[i], self.sc[i], self.dd[i]) = factors(d, self.jacobi);
    }

    /// D⁻¹ from the guarded diagonal, once every row's factors are set; nothing with Jacobi
    /// scaling (`gs()` is `sc`).
    fn set_gs(&mut self) {
        self.gs.clear();
        if !self.jacobi {
            self.gs.extend(self.dd.iter().map(|d| 1.0 / d));
        }
    }

    /// Copies and scales an explicit n×n W. Returns max_j Ŵ_jj, or `None` when a column
    /// index is out of range or n does not fit the `u32` column indices.
    pub fn setup_csr(&mut self, w: CsrView<'_>, jacobi: bool) -> Option<f64> {
        let n = w.rows();
        if n > u32::MAX as usize {
            return None;
        }
        self.resize(n, jacobi);
        let indptr = w.proper_indptr();
        let (indices, data) = (w.indices(), w.data());
        self.rowptr.extend_from_slice(&indptr);
        // Diagonal (guarded) and the zero rows.
        for i in 0..n {
            let (a, b) = (indptr[i], indptr[i + 1]);
            let mut d = 0.0;
            let mut all_zero = true;
            for k in a..b {
                if indices[k] == i {
                    d += data[k];
                }
                all_zero &= data[k] == 0.0;
            }
            if all_zero {
                self.zero_rows.push(i);
            }
            self.set_factors(i, d);
        }
        self.set_gs();
        let mut max_diag: f64 = 0.0;
        self.cols.reserve(indptr[n]);
        self.vals.reserve(indptr[n]);
        for i in 0..n {
            let si = self.sc[i];
            for k in indptr[i]..indptr[i + 1] {
                let j = indices[k];
                if j >= n {
                    return None;
                }
                let v = si * data[k] * self.sc[j];
                if j == i {
                    max_diag = max_diag.max(v);
                }
                self.cols.push(j as u32);
                self.vals.push(v);
            }
        }
        Some(max_diag)
    }

    /// Scaling of a matrix-free W from its diagonal (`diag`: work storage of length n).
    /// Returns max_j Ŵ_jj.
    pub fn setup_operator(&mut self, w: &dyn Operator, jacobi: bool, diag: &mut Vec<f64>, par: bool) -> f64 {
        let n = w.dim();
        self.resize(n, jacobi);
        // (not cleared first: `Operator::diagonal` overwrites every entry)
        diag.resize(n, 0.0);
        w.diagonal(&mut diag[..n]);
        // the rows in the sweeps' two halves (`par::join`), each row's factors and the
        // largest scaled diagonal; the second half's zero rows follow the first's
        let at = par::split(n);
        let (sd, sc, dd) = (&mut self.sd[..n], &mut self.sc[..n], &mut self.dd[..n]);
        let ((sd1, sd2), (sc1, sc2), (dd1, dd2)) =
            (sd.split_at_mut(at), sc.split_at_mut(at), dd.split_at_mut(at));
        let (d1, d2) = diag[..n].split_at(at);
        let zero = &mut self.zero_rows;
        let mut zero2 = Vec::new();
        let half = |d: &[f64],
                    sd: &mut [f64],
                    sc: &mut [f64],
                    dd: &mut [f64],
                    first: usize,
                    zero: &mut Vec<usize>| {
            let mut max_diag: f64 = 0.0;
            // cut to the half's rows, so that the loop's indexing needs no bounds checks
            let (sd, sc, dd) = (&mut sd[..d.len()], &mut sc[..d.len()], &mut dd[..d.len()]);
            for (i, &d) in d.iter().enumerate() {
                if d == 0.0 {
                    zero.push(first + i);
                }
                (sd[i], sc[i], dd[i]) = factors(d, jacobi);
                max_diag = larger(sc[i] * d * sc[i], max_diag);
            }
            max_diag
        };
        let (m1, m2) =
            par::join(par, || half(d1, sd1, sc1, dd1, 0, zero), || half(d2, sd2, sc2, dd2, at, &mut zero2));
        self.zero_rows.extend(zero2);
        self.set_gs();
        larger(m2, m1)
    }

    /// q̂ = sc q; returns max(1, ||D⁻¹q||_inf) (D⁻¹ q = gs q̂ in both modes). In the sweeps'
    /// two halves (`par::join`).
    pub fn scale_q(&mut self, q: &[f64], par: bool) -> f64 {
        let n = q.len();
        let Scaling { jacobi, sc, gs, qs, .. } = self;
        let (gs, sc) = (&gs_of(*jacobi, sc, gs)[..n], &sc[..n]);
        let half = |first: usize, qs: &mut [f64]| {
            let mut dq: f64 = 0.0;
            // the vectors cut to the half's rows, so that the loop's indexing needs no bounds checks
            let b = first..first + qs.len();
            let (q, gs, sc) = (&q[b.clone()], &gs[b.clone()], &sc[b]);
            for i in 0..qs.len() {
                qs[i] = sc[i] * q[i];
                dq = larger((gs[i] * qs[i]).abs(), dq);
            }
            dq
        };
        let (a, b) = par::halves(par, &mut qs[..n], half);
        larger(b, a).max(1.0)
    }
}

/// [`Scaling::gs`] from its fields (`scale_q` writes `qs` while it reads them).
fn gs_of<'a>(jacobi: bool, sc: &'a [f64], gs: &'a [f64]) -> &'a [f64] {
    if jacobi { sc } else { gs }
}

/// A row's scaling factors (sd, sc, dd) from its diagonal entry d, guarded: d <= 0 or not
/// finite counts as 1 (module docs of `vi`, "Zero diagonals").
#[inline(always)]
fn factors(d: f64, jacobi: bool) -> (f64, f64, f64) {
    let d = if d > 0.0 && d.is_finite() { d } else { 1.0 };
    let (sd, sc) = if jacobi { (d.sqrt(), 1.0 / d.sqrt()) } else { (1.0, 1.0) };
    (sd, sc, d)
}

/// Ŵ as the sweeps see it: `prepare(x, out, tmp)` before a sweep, then `row(i, x, out[i])`
/// gives (Ŵ x)_i inside it. The CSR copy computes each row on the fly (fused with the vector
/// work); a matrix-free operator computes the whole product in `prepare`.
pub(super) trait Rows: Sync + Copy {
    fn prepare(&self, x: &[f64], out: &mut [f64], tmp: &mut [f64]);
    fn row(&self, i: usize, x: &[f64], prepared: f64) -> f64;
    /// Ŵ's entries in the kept rows and columns ([`Operator::entries`]); false when W has none.
    fn entries(&self, keep: &[bool], out: &mut Vec<(usize, usize, f64)>) -> bool;
    /// An upper bound of ||Ŵ|| for MPRGP's step length, when one is at hand (`tmp`: scratch).
    fn norm_bound(&self, tmp: &mut [f64]) -> Option<super::mprgp::Bound>;
}

/// Read-only view of the scaled CSR copy.
#[derive(Clone, Copy)]
pub(super) struct Csr<'a> {
    pub rowptr: &'a [usize],
    pub cols: &'a [u32],
    pub vals: &'a [f64],
}

impl Rows for Csr<'_> {
    /// Gershgorin's bound: max_i Σ_j |Ŵ_ij|.
    fn norm_bound(&self, _tmp: &mut [f64]) -> Option<super::mprgp::Bound> {
        let rows = self.rowptr.windows(2);
        let max =
            rows.map(|r| self.vals[r[0]..r[1]].iter().map(|v| v.abs()).sum::<f64>()).fold(0.0, f64::max);
        Some(super::mprgp::Bound::Gershgorin(max))
    }

    fn entries(&self, keep: &[bool], out: &mut Vec<(usize, usize, f64)>) -> bool {
        for (i, r) in self.rowptr.windows(2).enumerate().filter(|(i, _)| keep[*i]) {
            for (&j, &v) in self.cols[r[0]..r[1]].iter().zip(&self.vals[r[0]..r[1]]) {
                if keep[j as usize] {
                    out.push((i, j as usize, v));
                }
            }
        }
        true
    }

    #[inline(always)]
    fn prepare(&self, x: &[f64], _out: &mut [f64], _tmp: &mut [f64]) {
        assert_eq!(x.len() + 1, self.rowptr.len(), "vi: vector length differs from W");
    }

    /// (Ŵ x)_i.
    #[inline(always)]
    fn row(&self, i: usize, x: &[f64], _prepared: f64) -> f64 {
        let (a, b) = (self.rowptr[i], self.rowptr[i + 1]);
        let mut acc = 0.0;
        for (v, &j) in self.vals[a..b].iter().zip(&self.cols[a..b]) {
            // SAFETY: `Scaling::setup_csr` checked every column index < n, and `prepare`
            // (called before every sweep) asserted x.len() == n. The tests below fail without
            // either check. The unchecked read is the sweeps' innermost loop (benches/vi.rs).
            acc += v * unsafe { *x.get_unchecked(j as usize) };
        }
        acc
    }
}

/// A matrix-free W scaled by vectors: Ŵ x = sc ∘ W (sc ∘ x).
#[derive(Clone, Copy)]
pub(super) struct Scaled<'a> {
    pub w: &'a dyn Operator,
    pub sc: &'a [f64],
    /// Scale in the sweeps' two halves, one per core (`par.rs`).
    pub par: bool,
}

impl Rows for Scaled<'_> {
    /// ‖Ŵ‖ <= max_r of the operator's row bounds of Ŵ = S W S (none with factored clusters).
    fn norm_bound(&self, tmp: &mut [f64]) -> Option<super::mprgp::Bound> {
        self.w
            .row_bounds(self.sc, tmp)
            .then(|| super::mprgp::Bound::Operator(tmp.iter().copied().fold(0.0, f64::max)))
    }

    /// tmp = sc ∘ x (in the sweeps' halves, on both cores: math note §3.3, "MPRGP's passes in
    /// halves"), then out = W tmp.
    fn prepare(&self, x: &[f64], out: &mut [f64], tmp: &mut [f64]) {
        let scale = |r0: usize, t: &mut [f64]| {
            let (x, sc) = (&x[r0..r0 + t.len()], &self.sc[r0..r0 + t.len()]);
            for i in 0..t.len() {
                t[i] = sc[i] * x[i];
            }
        };
        par::halves(self.par, &mut tmp[..x.len()], scale);
        self.w.apply(tmp, out);
    }

    #[inline(always)]
    fn row(&self, i: usize, _x: &[f64], prepared: f64) -> f64 {
        self.sc[i] * prepared
    }

    fn entries(&self, keep: &[bool], out: &mut Vec<(usize, usize, f64)>) -> bool {
        let start = out.len();
        if !self.w.entries(keep, out) {
            out.truncate(start);
            return false;
        }
        for (i, j, v) in &mut out[start..] {
            *v *= self.sc[*i] * self.sc[*j];
        }
        true
    }
}

/// The invariant of the unchecked read in [`Csr::row`]: every column index of the copy is below
/// n (the rows of W), and every vector a sweep reads has length n. Each test fails when its check
/// is removed (`j >= n` in [`Scaling::setup_csr`], the assertion in [`Csr::prepare`]).
#[cfg(test)]
mod tests {
    use super::*;

    /// A 2×3 W with an entry in column 2 is refused (`None`): its column index 2 >= n = 2 would
    /// be read past the end of a length-2 vector. Its 2×2 part is copied, with column indices
    /// [0, 1, 1] (the entries as given) and values scaled to a unit diagonal (Jacobi: Ŵ_ii = 1).
    #[test]
    fn a_column_index_out_of_range_is_refused() {
        let mut wide = sprs::TriMat::new((2, 3));
        for (i, j, v) in [(0, 0, 4.0), (1, 1, 9.0), (0, 2, 1.0)] {
            wide.add_triplet(i, j, v);
        }
        let wide: crate::sparse::Csr = wide.to_csr();
        assert_eq!(Scaling::default().setup_csr(wide.view(), true), None);
        let mut square = sprs::TriMat::new((2, 2));
        for (i, j, v) in [(0, 0, 4.0), (0, 1, 1.0), (1, 1, 16.0)] {
            square.add_triplet(i, j, v);
        }
        let square: crate::sparse::Csr = square.to_csr();
        let mut s = Scaling::default();
        assert_eq!(s.setup_csr(square.view(), true), Some(1.0));
        assert_eq!((s.cols.as_slice(), s.vals[0], s.vals[2]), ([0, 1, 1].as_slice(), 1.0, 1.0));
    }

    /// A sweep over a vector of another length than n panics before any row is read.
    #[test]
    #[should_panic(expected = "vector length differs from W")]
    fn a_vector_of_another_length_is_refused() {
        let rows = Csr { rowptr: &[0, 1, 2], cols: &[0, 1], vals: &[1.0, 1.0] };
        rows.prepare(&[1.0], &mut [0.0], &mut [0.0]);
    }
}
