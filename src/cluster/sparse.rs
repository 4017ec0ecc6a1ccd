//! A sparse SPD matrix factorized by faer's sparse Cholesky, the symbolic analysis kept while
//! the pattern stays the same, and the block of its inverse over the DOFs contacts touch
//! (math note §9.3).

use faer::linalg::solvers::SolveCore;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, MatMut, Side};
use rayon::prelude::*;
use std::collections::HashMap;
use std::sync::Mutex;

/// A sparse SPD matrix factorized by faer's supernodal/simplicial Cholesky, with the
/// symbolic analysis kept while the sparsity pattern stays the same.
#[derive(Debug)]
pub struct SparseFactor {
    n: usize,
    /// Sparsity pattern (sorted, deduplicated (row, col) of the lower triangle) of the last
    /// symbolic analysis.
    pattern: Vec<(usize, usize)>,
    symbolic: Option<SymbolicLlt<usize>>,
    numeric: Option<Llt<usize, f64>>,
    /// Entries of K⁻¹ among the DOFs that contacts have touched since the last numeric
    /// factorization (math note §9.3).
    inverse: Mutex<InverseCache>,
}

/// The symmetric block `(K⁻¹)_SS` over a growing set S of DOFs: a DOF joining S costs one solve
/// for its column, whose entries at S (old members and itself) are kept. Only S × S numbers
/// are stored, never a whole column: at 100k DOF, 640 full columns would take 0.5 GB.
#[derive(Debug, Clone, Default)]
struct InverseCache {
    /// DOF → its index in S (the order in which DOFs joined).
    slot: HashMap<usize, usize>,
    /// `lower[a][b] = (K⁻¹)_{S_a S_b}` for `b ≤ a`, from the column of S_a (the later one), so
    /// every entry is stored once and the block read from it is exactly symmetric.
    lower: Vec<Vec<f64>>,
}

/// Columns solved at once when DOFs join the cached block (one multi-column triangular solve
/// each, spread over the cores; 16 columns of 100k DOF take 13 MB).
const COLUMN_BATCH: usize = 16;

impl Clone for SparseFactor {
    /// A clone keeps the factorization (and so the symbolic analysis) and the cached block.
    fn clone(&self) -> Self {
        SparseFactor {
            n: self.n,
            pattern: self.pattern.clone(),
            symbolic: self.symbolic.clone(),
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
            pattern: Vec::new(),
            symbolic: None,
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
            ..SparseFactor::new(self.n)
        }
    }

    /// Number of symbolic analyses done so far is observable through this: the symbolic
    /// factorization is reused while the pattern of `triplets` does not change.
    pub fn has_symbolic(&self) -> bool {
        self.symbolic.is_some()
    }

    /// Numeric factorization of the symmetric matrix given by its lower-triangle `triplets`
    /// (duplicates are summed); symbolic analysis only when the pattern changed.
    pub fn factorize(&mut self, triplets: &[(usize, usize, f64)]) -> Result<(), SparseError> {
        let entries: Vec<Triplet<usize, usize, f64>> =
            triplets.iter().map(|&(r, c, v)| Triplet::new(r, c, v)).collect();
        let mat = SparseColMat::<usize, f64>::try_new_from_triplets(self.n, self.n, &entries)
            .map_err(|e| SparseError(format!("{e:?}")))?;
        let pattern: Vec<(usize, usize)> =
            (0..self.n).flat_map(|j| mat.symbolic().row_idx_of_col(j).map(move |i| (i, j))).collect();
        if self.symbolic.is_none() || pattern != self.pattern {
            self.symbolic = Some(
                SymbolicLlt::try_new(mat.symbolic(), Side::Lower)
                    .map_err(|e| SparseError(format!("{e:?}")))?,
            );
            self.pattern = pattern;
        }
        let symbolic = self.symbolic.clone().ok_or_else(|| SparseError("no symbolic factor".into()))?;
        self.numeric = Some(
            Llt::try_new_with_symbolic(symbolic, mat.as_ref(), Side::Lower)
                .map_err(|e| SparseError(format!("{e:?}")))?,
        );
        self.inverse = Mutex::new(InverseCache::default());
        Ok(())
    }

    /// `(K⁻¹)_SS` for the DOFs `dofs` (distinct), column-major `|S| × |S|`: read from the
    /// cached block, after solving the columns of the DOFs not in it yet (math note §9.3).
    pub fn inverse_block(&self, dofs: &[usize]) -> Vec<f64> {
        let mut guard = self.inverse.lock().unwrap_or_else(|e| e.into_inner());
        let cache = &mut *guard;
        let missing: Vec<usize> = dofs.iter().copied().filter(|d| !cache.slot.contains_key(d)).collect();
        if !missing.is_empty() {
            let known = cache.lower.len();
            let mut members = vec![0; known];
            for (&d, &a) in &cache.slot {
                members[a] = d;
            }
            members.extend_from_slice(&missing);
            let rows: Vec<Vec<f64>> = missing
                .par_chunks(COLUMN_BATCH)
                .enumerate()
                .flat_map_iter(|(chunk, batch)| {
                    self.column_rows(batch, &members, known + chunk * COLUMN_BATCH)
                })
                .collect();
            for (t, (d, row)) in missing.iter().zip(rows).enumerate() {
                cache.slot.insert(*d, known + t);
                cache.lower.push(row);
            }
        }
        let at: Vec<usize> = dofs.iter().map(|d| cache.slot[d]).collect();
        let m = dofs.len();
        let mut block = vec![0.0; m * m];
        for (j, &b) in at.iter().enumerate() {
            for (i, &a) in at.iter().enumerate() {
                block[j * m + i] = if a >= b { cache.lower[a][b] } else { cache.lower[b][a] };
            }
        }
        block
    }

    /// The columns of K⁻¹ for `batch` (which join S at indices `first..`), each gathered at the
    /// members of S up to and including itself.
    fn column_rows(&self, batch: &[usize], members: &[usize], first: usize) -> Vec<Vec<f64>> {
        let (n, k) = (self.n, batch.len());
        let mut x = vec![0.0; n * k];
        for (j, &d) in batch.iter().enumerate() {
            x[j * n + d] = 1.0;
        }
        if let Some(llt) = &self.numeric {
            llt.solve_in_place_with_conj(Conj::No, MatMut::from_column_major_slice_mut(&mut x, n, k));
        }
        (0..k).map(|j| members[..=first + j].iter().map(|&m| x[j * n + m]).collect()).collect()
    }

    /// `x ← K⁻¹ x` (no-op before a successful factorization).
    pub fn solve_in_place(&self, x: &mut [f64]) {
        if let Some(llt) = &self.numeric {
            let n = x.len();
            llt.solve_in_place_with_conj(Conj::No, MatMut::from_column_major_slice_mut(x, n, 1));
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

    /// More DOFs than one batch (40 > 16): three batches solved on rayon; the block is the same
    /// as the one built DOF by DOF, entry for entry (each column's solve does not depend on the
    /// batch it is in or on the thread).
    #[test]
    fn batched_columns_equal_single_ones() {
        let n = 60;
        let triplets: Vec<_> = (0..n)
            .flat_map(|i| [(i, i, 3.0)].into_iter().chain((i + 1 < n).then_some((i + 1, i, -1.0))))
            .collect();
        let mut batched = SparseFactor::new(n);
        batched.factorize(&triplets).expect("SPD");
        let mut single = batched.clone();
        single.factorize(&triplets).expect("SPD");
        let set: Vec<usize> = (0..40).map(|k| (k * 7) % n).collect();
        let all = batched.inverse_block(&set);
        for k in 0..set.len() {
            single.inverse_block(&set[..=k]);
        }
        let one_by_one = single.inverse_block(&set);
        assert_eq!(all, one_by_one);
    }
}
