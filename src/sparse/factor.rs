//! A sparse SPD matrix factorized by faer's sparse Cholesky, the symbolic analysis kept while
//! the pattern stays the same, and the block of its inverse over the DOFs contacts touch
//! (math note §9.3).

use super::inverse::{InverseCache, Tree};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{LltRef, SymbolicCholesky, factorize_symbolic_cholesky};
use faer::sparse::{Argsort, Pair, SparseColMat, SymbolicSparseColMat, Triplet};
use faer::{Conj, MatMut, Side};
use std::sync::{Arc, Mutex};

/// Size, pattern and numeric values of a sparse factor ([`SparseFactor::parts`]).
pub(crate) type SparseParts<'a> = (usize, &'a [(usize, usize)], Option<&'a Vec<f64>>);

/// Columns solved at once by [`SparseFactor::inverse_block_by_solves`] (16 columns of 100k
/// DOF take 13 MB).
const COLUMN_BATCH: usize = 16;

/// A sparse SPD matrix factorized by faer's supernodal/simplicial Cholesky, with the
/// symbolic analysis kept while the sparsity pattern stays the same.
#[derive(Debug)]
pub struct SparseFactor {
    n: usize,
    /// Sparsity pattern (sorted, deduplicated (row, col) of the lower triangle) of the last
    /// symbolic analysis.
    pattern: Arc<Vec<(usize, usize)>>,
    symbolic: Option<Arc<(SymbolicCholesky<usize>, Tree)>>,
    /// How the last triplets were gathered into compressed columns, kept for the next ones.
    assembly: Option<Arc<Assembly>>,
    /// The factor's values (faer's layout for `symbolic`) after a successful factorization.
    numeric: Option<Vec<f64>>,
    /// Entries of K⁻¹ among the DOFs that contacts have touched since the last numeric
    /// factorization (math note §9.3).
    inverse: Mutex<InverseCache>,
}

/// The compressed columns of a list of triplets and where each triplet's value goes in them
/// (faer's argsort: the order in which duplicates are summed), for the triplets' positions
/// `keys`. Triplets that come again with the same positions in the same order are gathered
/// through it, without sorting them again, into the same matrix, bit for bit.
#[derive(Debug)]
struct Assembly {
    keys: Vec<(usize, usize)>,
    columns: SymbolicSparseColMat<usize>,
    argsort: Argsort<usize>,
}

impl Clone for SparseFactor {
    /// A clone keeps the factorization (and so the symbolic analysis) and the cached block.
    fn clone(&self) -> Self {
        SparseFactor {
            n: self.n,
            pattern: self.pattern.clone(),
            symbolic: self.symbolic.clone(),
            assembly: self.assembly.clone(),
            numeric: self.numeric.clone(),
            inverse: Mutex::new(self.inverse.lock().map(|c| c.clone()).unwrap_or_default()),
        }
    }
}

/// The sparse factorization failed (matrix not positive definite, or out of memory).
#[derive(Debug, Clone, thiserror::Error)]
#[error("sparse Cholesky factorization failed: {0}")]
pub struct SparseError(String);

impl SparseFactor {
    pub fn new(n: usize) -> SparseFactor {
        SparseFactor {
            n,
            pattern: Arc::default(),
            symbolic: None,
            assembly: None,
            numeric: None,
            inverse: Mutex::new(InverseCache::default()),
        }
    }

    /// An unfactored matrix of the same size that reuses this one's symbolic analysis (its
    /// numeric factor and cached block are not copied: at 100k DOF the factor is ~100 MB).
    pub fn renewed(&self) -> SparseFactor {
        SparseFactor {
            pattern: self.pattern.clone(),
            symbolic: self.symbolic.clone(),
            assembly: self.assembly.clone(),
            ..SparseFactor::new(self.n)
        }
    }

    /// Number of symbolic analyses done so far is observable through this: the symbolic
    /// factorization is reused while the pattern of `triplets` does not change.
    pub fn has_symbolic(&self) -> bool {
        self.symbolic.is_some()
    }

    /// Numeric factorization of the symmetric matrix given by its lower-triangle `triplets`
    /// (duplicates are summed), into the values of the last factorization when it has them;
    /// symbolic analysis (faer's defaults: AMD ordering) only when the pattern changed.
    /// Triplets at the same positions as the last ones are gathered into compressed columns
    /// without sorting them again ([`Assembly`]).
    pub fn factorize(&mut self, triplets: &[(usize, usize, f64)]) -> Result<(), SparseError> {
        let error = |e: &dyn std::fmt::Debug| SparseError(format!("{e:?}"));
        let same = self.assembly.as_ref().is_some_and(|a| {
            a.keys.len() == triplets.len() && a.keys.iter().zip(triplets).all(|(k, t)| *k == (t.0, t.1))
        });
        if !same || self.symbolic.is_none() {
            self.assemble(triplets)?;
        }
        let assembly = self.assembly.as_ref().ok_or_else(|| SparseError("no assembly".into()))?;
        let values: Vec<f64> = triplets.iter().map(|t| t.2).collect();
        let mat = SparseColMat::new_from_argsort(assembly.columns.clone(), &assembly.argsort, &values)
            .map_err(|e| error(&e))?;
        let symbolic = &self.symbolic.as_ref().ok_or_else(|| SparseError("no symbolic factor".into()))?.0;
        self.inverse = Mutex::new(InverseCache::default());
        let mut values = self.numeric.take().filter(|v| v.len() == symbolic.len_val()).unwrap_or_default();
        if values.is_empty() {
            values.try_reserve_exact(symbolic.len_val()).map_err(|e| error(&e))?;
            values.resize(symbolic.len_val(), 0.0);
        }
        let par = faer::get_global_parallelism();
        let scratch = symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default());
        let mut buffer = MemBuffer::try_new(scratch).map_err(|e| error(&e))?;
        symbolic
            .factorize_numeric_llt(
                &mut values,
                mat.as_ref(),
                Side::Lower,
                Default::default(),
                par,
                MemStack::new(&mut buffer),
                Default::default(),
            )
            .map_err(|e| error(&e))?;
        self.numeric = Some(values);
        Ok(())
    }

    /// The compressed columns of `triplets` ([`Assembly`]), and the symbolic analysis of their
    /// pattern when it differs from the last one.
    fn assemble(&mut self, triplets: &[(usize, usize, f64)]) -> Result<(), SparseError> {
        let error = |e: &dyn std::fmt::Debug| SparseError(format!("{e:?}"));
        let at: Vec<Pair<usize, usize>> = triplets.iter().map(|&(r, c, _)| Pair::new(r, c)).collect();
        let (columns, argsort) =
            SymbolicSparseColMat::try_new_from_indices(self.n, self.n, &at).map_err(|e| error(&e))?;
        let pattern: Vec<(usize, usize)> =
            (0..self.n).flat_map(|j| columns.row_idx_of_col(j).map(move |i| (i, j))).collect();
        if self.symbolic.is_none() || *pattern != **self.pattern {
            let symbolic = factorize_symbolic_cholesky(
                columns.as_ref(),
                Side::Lower,
                Default::default(),
                Default::default(),
            )
            .map_err(|e| error(&e))?;
            let tree = Tree::new(&symbolic);
            self.symbolic = Some(Arc::new((symbolic, tree)));
            self.pattern = Arc::new(pattern);
            self.numeric = None;
        }
        let keys = triplets.iter().map(|t| (t.0, t.1)).collect();
        self.assembly = Some(Arc::new(Assembly { keys, columns, argsort }));
        Ok(())
    }

    /// Size, pattern and numeric values (a checkpoint's state, `snapshot.rs`).
    pub(crate) fn parts(&self) -> SparseParts<'_> {
        (self.n, &self.pattern, self.numeric.as_ref())
    }

    /// A copy of the cached block of K⁻¹ (a checkpoint's state, `snapshot.rs`).
    pub(crate) fn inverse_cache(&self) -> InverseCache {
        self.inverse.lock().map(|c| c.clone()).unwrap_or_else(|e| e.into_inner().clone())
    }

    /// The symbolic analysis of an `n × n` lower-triangle `pattern` (sorted, deduplicated), as
    /// [`Self::factorize`] does it for a matrix of that pattern.
    pub(crate) fn analyse(
        n: usize,
        pattern: &[(usize, usize)],
    ) -> Result<Arc<(SymbolicCholesky<usize>, Tree)>, SparseError> {
        let error = |e: &dyn std::fmt::Debug| SparseError(format!("{e:?}"));
        let entries: Vec<Triplet<usize, usize, f64>> =
            pattern.iter().map(|&(r, c)| Triplet::new(r, c, 1.0)).collect();
        let mat = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &entries).map_err(|e| error(&e))?;
        let symbolic =
            factorize_symbolic_cholesky(mat.symbolic(), Side::Lower, Default::default(), Default::default())
                .map_err(|e| error(&e))?;
        let tree = Tree::new(&symbolic);
        Ok(Arc::new((symbolic, tree)))
    }

    /// A factor from its parts (`snapshot.rs`).
    pub(crate) fn from_parts(
        n: usize,
        pattern: Vec<(usize, usize)>,
        symbolic: Option<Arc<(SymbolicCholesky<usize>, Tree)>>,
        numeric: Option<Vec<f64>>,
        inverse: Mutex<InverseCache>,
    ) -> SparseFactor {
        SparseFactor { n, pattern: Arc::new(pattern), symbolic, assembly: None, numeric, inverse }
    }

    /// `(K⁻¹)_SS` for the DOFs `dofs` (distinct), column-major `|S| × |S|`: read from the
    /// cached block, after the forward solves of the DOFs not in it yet along their paths in
    /// the factor (math note §9.3). Zeros before a successful factorization.
    pub fn inverse_block(&self, dofs: &[usize]) -> Vec<f64> {
        let m = dofs.len();
        let (Some(symbolic), Some(values)) = (&self.symbolic, &self.numeric) else { return vec![0.0; m * m] };
        let mut guard = self.inverse.lock().unwrap_or_else(|e| e.into_inner());
        let cache = &mut *guard;
        let missing: Vec<usize> = dofs.iter().copied().filter(|d| !cache.slot.contains_key(d)).collect();
        if !missing.is_empty() {
            cache.extend(&symbolic.1, &symbolic.0, values, &missing);
        }
        let at: Vec<usize> = dofs.iter().map(|d| cache.slot[d]).collect();
        let mut block = vec![0.0; m * m];
        for (j, &b) in at.iter().enumerate() {
            for (i, &a) in at.iter().enumerate() {
                block[j * m + i] = if a >= b { cache.lower[a][b] } else { cache.lower[b][a] };
            }
        }
        block
    }

    /// `(K⁻¹)_SS` by full solves of the unit vectors of `dofs` (all at once as one
    /// multi-column right-hand side), without the cache: the reference
    /// [`Self::inverse_block`] is checked against (tests, `benches/mesh.rs`).
    #[doc(hidden)]
    pub fn inverse_block_by_solves(&self, dofs: &[usize]) -> Vec<f64> {
        let n = self.n;
        let mut block = Vec::with_capacity(dofs.len() * dofs.len());
        for batch in dofs.chunks(COLUMN_BATCH) {
            let mut x = vec![0.0; n * batch.len()];
            for (j, &d) in batch.iter().enumerate() {
                x[j * n + d] = 1.0;
            }
            self.solve_columns(&mut x, batch.len());
            for j in 0..batch.len() {
                block.extend(dofs.iter().map(|&d| x[j * n + d]));
            }
        }
        block
    }

    /// Whether the factor is supernodal (faer picks simplicial for small, very sparse ones).
    #[doc(hidden)]
    pub fn is_supernodal(&self) -> bool {
        let raw = self.symbolic.as_ref().map(|s| s.0.raw());
        matches!(raw, Some(faer::sparse::linalg::cholesky::SymbolicCholeskyRaw::Supernodal(_)))
    }

    /// `x ← K⁻¹ x` (no-op before a successful factorization).
    pub fn solve_in_place(&self, x: &mut [f64]) {
        self.solve_columns(x, 1);
    }

    /// `X ← K⁻¹ X` for `k` columns of length n, column-major.
    fn solve_columns(&self, x: &mut [f64], k: usize) {
        if let (Some(symbolic), Some(values)) = (&self.symbolic, &self.numeric) {
            let par = faer::get_global_parallelism();
            let mut buffer = MemBuffer::new(symbolic.0.solve_in_place_scratch::<f64>(k, par));
            LltRef::new(&symbolic.0, values).solve_in_place_with_conj(
                Conj::No,
                MatMut::from_column_major_slice_mut(x, self.n, k),
                par,
                MemStack::new(&mut buffer),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cached block of K⁻¹ (math note §9.3) against nalgebra's dense inverse of the same
    /// matrix: a 40 × 40 SPD band matrix (diagonal 4, off-diagonals -1 at distances 1 and 7),
    /// asked for S = {3, 17, 30} and then for S = {30, 5, 3, 39} (two DOFs join the cache, the
    /// others are read from it). Entries agree within 1e-14 (the inverse's entries are below 1;
    /// a few roundings of the solve), and the block is exactly symmetric (each entry is stored
    /// once). A numeric refactorization empties the cache.
    #[test]
    fn inverse_block_matches_the_dense_inverse() {
        let n = 40;
        let mut triplets = Vec::new();
        let mut dense = nalgebra::DMatrix::<f64>::zeros(n, n);
        for i in 0..n {
            triplets.push((i, i, 4.0));
            dense[(i, i)] = 4.0;
            for d in [1, 7] {
                if i + d < n {
                    triplets.push((i + d, i, -1.0));
                    dense[(i + d, i)] = -1.0;
                    dense[(i, i + d)] = -1.0;
                }
            }
        }
        let inv = dense.cholesky().expect("SPD").inverse();
        let mut f = SparseFactor::new(n);
        f.factorize(&triplets).expect("SPD");
        for set in [vec![3, 17, 30], vec![30, 5, 3, 39]] {
            let m = set.len();
            let block = f.inverse_block(&set);
            for (j, &b) in set.iter().enumerate() {
                for (i, &a) in set.iter().enumerate() {
                    assert!((block[j * m + i] - inv[(a, b)]).abs() < 1e-14, "({a}, {b})");
                    assert_eq!(block[j * m + i], block[i * m + j]);
                }
            }
        }
        assert_eq!(f.inverse.lock().expect("cache").lower.len(), 5);
        f.factorize(&triplets).expect("SPD");
        assert!(f.inverse.lock().expect("cache").lower.is_empty());
    }

    /// The block built in one call for 40 DOFs against the same block built by DOFs joining
    /// one at a time (each later DOF's entries against the earlier ones from their kept
    /// pieces) and against full solves of the 40 unit vectors: the three agree within 1e-15
    /// (the inverse of this tridiagonal matrix, diagonal 3, off-diagonal -1, has entries below
    /// 0.5; each way sums the same products, in other groupings).
    #[test]
    fn one_call_equals_one_dof_at_a_time() {
        let n = 60;
        let triplets: Vec<_> = (0..n)
            .flat_map(|i| [(i, i, 3.0)].into_iter().chain((i + 1 < n).then_some((i + 1, i, -1.0))))
            .collect();
        let mut at_once = SparseFactor::new(n);
        at_once.factorize(&triplets).expect("SPD");
        let mut single = at_once.clone();
        single.factorize(&triplets).expect("SPD");
        let set: Vec<usize> = (0..40).map(|k| (k * 7) % n).collect();
        let all = at_once.inverse_block(&set);
        for k in 0..set.len() {
            single.inverse_block(&set[..=k]);
        }
        let one_by_one = single.inverse_block(&set);
        let solved = at_once.inverse_block_by_solves(&set);
        for ((a, b), c) in all.iter().zip(&one_by_one).zip(&solved) {
            assert!((a - b).abs() < 1e-15 && (a - c).abs() < 1e-15, "{a} {b} {c}");
        }
    }

    /// The block built with the forward solves and the products on one thread and on two (a
    /// pool without workers runs the two closures of `micropool::join` one after the other, the
    /// second first, so this also shows that the products never wait for a pass that has not
    /// started; math note §9.8): the same bits. Both against full solves of the unit vectors
    /// within 1e-12 of the largest entry, the bound of math note §9.7 (two ways of rounding;
    /// condition number below 350 here). The matrix: two DOFs per node of an 80 × 80 grid,
    /// -1 between the DOFs of a node and between every DOF of neighbouring nodes (9-point
    /// stencil), 17.1 on the diagonal (strictly diagonally dominant, so SPD; supernodal), with
    /// 120 DOFs in S joining in two batches.
    #[test]
    fn block_on_two_threads_is_the_block_on_one() {
        let side = 80;
        let n = 2 * side * side;
        let mut triplets = Vec::new();
        for i in 0..side * side {
            let (x, y) = (i % side, i / side);
            triplets.extend([(2 * i, 2 * i, 17.1), (2 * i + 1, 2 * i + 1, 17.1), (2 * i + 1, 2 * i, -1.0)]);
            for (dx, dy) in [(1, 0), (0, 1), (1, 1)] {
                let (x2, y2) = (x + dx, y + dy);
                if x2 < side && y2 < side {
                    let j = y2 * side + x2;
                    for (a, b) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                        triplets.push((2 * j + a, 2 * i + b, -1.0));
                    }
                }
            }
            if x > 0 && y + 1 < side {
                let j = (y + 1) * side + x - 1;
                for (a, b) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                    triplets.push((2 * j + a, 2 * i + b, -1.0));
                }
            }
        }
        let mut f = SparseFactor::new(n);
        f.factorize(&triplets).expect("SPD");
        assert!(f.is_supernodal());
        let set: Vec<usize> = (0..120).map(|k| (k * 97) % n).collect();
        let on = |threads: usize| {
            let mut g = f.clone();
            g.factorize(&triplets).expect("SPD");
            let pool = micropool::ThreadPoolBuilder::default().num_threads(threads - 1).build();
            pool.install(|| {
                g.inverse_block(&set[..70]);
                g.inverse_block(&set)
            })
        };
        let (one, two) = (on(1), on(2));
        assert!(one.iter().zip(&two).all(|(a, b)| a.to_bits() == b.to_bits()));
        let solved = f.inverse_block_by_solves(&set);
        let scale = solved.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        assert!(two.iter().zip(&solved).all(|(a, b)| (a - b).abs() <= 1e-12 * scale));
    }
}
