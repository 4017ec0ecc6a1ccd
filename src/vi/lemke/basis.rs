//! The basis of Lemke's revised pivoting (math note §4.12, "A sparse basis"): B = B₀ E₁ … E_k,
//! B₀ factorized by faer's sparse LU (partial pivoting, COLAMD ordering) at the last refactor
//! and one elementary column matrix E per pivot since (the product form of the inverse).
//! B⁻¹ a is one LU solve and k eta updates; the LCP's own columns are sparse (a W row's
//! neighbours), so the cost of a pivot follows the factor's fill instead of the m² of a dense
//! inverse.

use super::Lcp;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::linalg::lu::{LuRef, NumericLu, SymbolicLu, factorize_symbolic_lu};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, MatMut, Par};

/// Pivots between refactorizations: each eta costs about its nonzeros in every later solve it
/// acts in, a refactor a sparse LU. 50 to 200 cost about the same on the deformable 10 × 10
/// pile, with the same answers; 400 is slower (math note §4.12, "A sparse basis").
const REFACTOR: usize = 100;

/// One pivot's elementary matrix: column `row` of the identity replaced by B⁻¹ a, the entering
/// column; its entries other than the pivot are `Basis::entries` from the previous eta's `end`
/// to its own.
struct Eta {
    row: usize,
    pivot: f64,
    end: usize,
}

/// B⁻¹ in product form over the LU of the last refactor (`symbolic` `None`: B₀ = I, the
/// first basis). The LU's values and the work space of its factorization and solves are kept
/// across refactors, so a pivot allocates nothing but its eta's entries; both run on one core
/// (`Par::Seq`), as every factorization here.
#[derive(Default)]
pub(super) struct Basis {
    symbolic: Option<SymbolicLu<usize>>,
    numeric: NumericLu<usize, f64>,
    stack: Option<(MemBuffer, StackReq)>,
    etas: Vec<Eta>,
    /// The etas' entries off their pivot, one after the other (kept across refactors).
    entries: Vec<(usize, f64)>,
    scratch: Vec<Triplet<usize, usize, f64>>,
}

impl Basis {
    /// The identity, the basis of the slack variables w that Lemke starts from.
    pub fn identity() -> Basis {
        Basis::default()
    }

    /// Whether enough pivots have accumulated to refactor.
    pub fn due(&self) -> bool {
        self.etas.len() >= REFACTOR
    }

    /// Factorizes B afresh from its variables (`basis[k]` is column k: see [`Lcp::column_of`]).
    /// `None` when B is singular (structurally, or a pivot that makes the solve non-finite
    /// shows it at the next solve). After `None` the product form describes no basis (the old
    /// factor's values are overwritten in place): both callers stop the path at once, and no
    /// solve may follow.
    pub fn refactor(&mut self, lcp: &Lcp, d: &[f64], basis: &[usize]) -> Option<()> {
        let m = lcp.m;
        self.scratch.clear();
        for (k, &j) in basis.iter().enumerate() {
            lcp.column_of(d, j, |i, v| self.scratch.push(Triplet::new(i, k, v)));
        }
        let b = SparseColMat::<usize, f64>::try_new_from_triplets(m, m, &self.scratch).ok()?;
        let symbolic = factorize_symbolic_lu(b.symbolic(), Default::default()).ok()?;
        let req = symbolic
            .factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default())
            .or(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        let stack = match self.stack.take() {
            Some((buffer, held)) if held.or(req) == held => (buffer, held),
            _ => (MemBuffer::new(req), req),
        };
        let stack = MemStack::new(&mut self.stack.insert(stack).0);
        let values =
            symbolic.factorize_numeric_lu(&mut self.numeric, b.as_ref(), Par::Seq, stack, Default::default());
        self.symbolic = values.is_ok().then_some(symbolic);
        self.symbolic.as_ref()?;
        self.etas.clear();
        self.entries.clear();
        Some(())
    }

    /// x ← B⁻¹ x.
    pub fn solve(&mut self, x: &mut [f64]) {
        if let (Some(symbolic), Some((buffer, _))) = (&self.symbolic, &mut self.stack) {
            let n = x.len();
            let rhs = MatMut::from_column_major_slice_mut(x, n, 1);
            let lu = LuRef::new_unchecked(symbolic, &self.numeric);
            lu.solve_in_place_with_conj(Conj::No, rhs, Par::Seq, MemStack::new(buffer));
        }
        let mut start = 0;
        for e in &self.etas {
            // an eta whose row of x is 0 leaves x as it is
            if x[e.row] != 0.0 {
                let t = x[e.row] / e.pivot;
                self.entries[start..e.end].iter().for_each(|&(i, c)| x[i] -= c * t);
                x[e.row] = t;
            }
            start = e.end;
        }
    }

    /// Records the pivot that put the column `col` (= B⁻¹ a, as [`Self::solve`] gave it) in
    /// place `row` of the basis.
    pub fn push(&mut self, row: usize, col: &[f64]) {
        let rest = col.iter().enumerate().filter(|&(i, c)| i != row && *c != 0.0);
        self.entries.extend(rest.map(|(i, &c)| (i, c)));
        self.etas.push(Eta { row, pivot: col[row], end: self.entries.len() });
    }
}

#[cfg(test)]
mod tests {
    //! The product form against its definition: after pivots recorded as Lemke records them,
    //! B⁻¹ b must solve B x = b for the basis the pivots made, and agree with a fresh LU of
    //! that basis. Both are exact up to rounding on a 6 × 6 system of entries of order one
    //! (pivots of at least 0.5 in magnitude are chosen), so 1e-12.
    use super::super::Lcp;
    use super::Basis;
    use sprs::TriMat;

    #[test]
    fn eta_updates_solve_the_basis_they_made() {
        let m = 6;
        let mut t = TriMat::new((m, m));
        for i in 0..m {
            t.add_triplet(i, i, 2.0 + i as f64 * 0.25);
            t.add_triplet(i, (i + 1) % m, -0.5 - 0.125 * i as f64);
            t.add_triplet((i + 2) % m, i, 0.75);
        }
        let lcp = Lcp { m, mat: t.to_csc(), q: vec![0.0; m], vars: Vec::new(), sc: Vec::new() };
        let d = vec![1.0; m];
        let mut basis: Vec<usize> = (0..m).collect();
        let mut inv = Basis::identity();
        // x_2, the artificial, x_0, x_5 and x_3 enter; w_0 (leaving for x_0) re-enters last
        for entering in [m + 2, 2 * m, m, m + 5, m + 3, 0] {
            let mut col = vec![0.0; m];
            lcp.column_of(&d, entering, |i, v| col[i] = v);
            inv.solve(&mut col);
            let r = (0..m)
                .filter(|&i| basis[i] != entering)
                .max_by(|&a, &b| col[a].abs().total_cmp(&col[b].abs()));
            let r = r.expect("a row");
            assert!(col[r].abs() >= 0.5, "pivot {} at row {r}", col[r]);
            inv.push(r, &col);
            basis[r] = entering;
        }
        let b: Vec<f64> = (0..m).map(|i| 1.0 + i as f64).collect();
        let mut x = b.clone();
        inv.solve(&mut x);
        let mut back = vec![0.0; m];
        for (k, &j) in basis.iter().enumerate() {
            lcp.column_of(&d, j, |i, v| back[i] += v * x[k]);
        }
        let err = back.iter().zip(&b).fold(0.0f64, |e, (a, b)| e.max((a - b).abs()));
        assert!(err < 1e-12, "|B x - b| = {err}");
        let mut fresh = Basis::identity();
        fresh.refactor(&lcp, &d, &basis).expect("nonsingular");
        let mut y = b.clone();
        fresh.solve(&mut y);
        let diff = x.iter().zip(&y).fold(0.0f64, |e, (a, b)| e.max((a - b).abs()));
        assert!(diff < 1e-12, "product form and fresh LU differ by {diff}");
    }
}
