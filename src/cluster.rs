//! The step stiffness K̃ = K_e + (2/dt²) M per cluster and its solves (math note eq. 1.2,
//! §3.1 "coupled K", §10.6).
//!
//! A cluster of one body keeps the closed-form path: K is at most 6×6, factorized by a small
//! dense Cholesky and inverted (the reference path, nalgebra). A cluster of several bodies
//! (joined by connectors) or a meshed body assembles a sparse K̃ and factorizes it with faer's
//! sparse Cholesky: the symbolic analysis is done once while the sparsity pattern is
//! unchanged, the numeric factorization whenever the values change. Nothing bigger than one
//! body is ever inverted explicitly.
//!
//! ```
//! use pbdda::cluster::SparseFactor;
//! // K = [[4, 1], [1, 3]] as (row, col, value) triplets of the lower triangle and diagonal
//! let mut f = SparseFactor::new(2);
//! f.factorize(&[(0, 0, 4.0), (1, 0, 1.0), (1, 1, 3.0)]).unwrap();
//! let mut x = [1.0, 2.0];
//! f.solve_in_place(&mut x);
//! assert!((4.0 * x[0] + x[1] - 1.0).abs() < 1e-14 && (x[0] + 3.0 * x[1] - 2.0).abs() < 1e-14);
//! ```

use crate::body::{Body, BodyMatrix};
use crate::dofs::DofMap;
use faer::linalg::solvers::SolveCore;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, MatMut, Side};
use rayon::prelude::*;
use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

/// The next factor's stamp ([`Flexibility::stamps`]).
static STAMPS: AtomicU64 = AtomicU64::new(0);

/// A stiffness block coupling two bodies' DOFs (a connector's contribution).
pub use crate::connector::Coupling as CouplingBlock;

/// Why a step matrix could not be factorized.
#[derive(Debug, Clone, thiserror::Error, miette::Diagnostic)]
#[error(
    "the step stiffness of bodies {bodies:?} is not positive definite (zero or negative mass or stiffness?)"
)]
pub struct FactorError {
    pub bodies: Vec<String>,
}

/// The factorized step stiffness of every cluster.
#[derive(Debug, Clone, Default)]
pub struct Flexibility {
    factors: Vec<Arc<Factor>>,
    /// Per cluster, the stamp of its factor ([`Flexibility::stamps`]).
    stamps: Vec<u64>,
    /// Route single bodies through the sparse path too (a reference check of that path).
    sparse_only: bool,
    /// The step length the factors are for (K̃ = K + 2M/dt²): a new one refactors them all.
    dt: f64,
    /// Refactor policy of sparse clusters (`[solver] factor_drift`, math note §9.3): 0 refactors
    /// every step; a positive value keeps a factor while no element of the cluster has turned or
    /// strained by more than it since the factor was formed.
    factor_drift: f64,
    /// Per cluster, the geometry of each member its factor was formed on (only with
    /// `factor_drift > 0`).
    formed: Vec<Option<Vec<Formed>>>,
    /// Numeric factorizations of sparse clusters so far.
    sparse_factorizations: usize,
}

/// The geometry a sparse cluster's factor was formed on: each member's mesh nodes, or its
/// rotation for a block or particle (whose connector blocks turn with it).
#[derive(Debug, Clone)]
enum Formed {
    Mesh(Vec<crate::geometry::Vec2>),
    Rotation(f64),
}

// One per cluster, behind an `Arc`: most clusters are single bodies, and boxing their matrices
// would add an indirection to every body solve for the few sparse clusters' sake.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone)]
pub(crate) enum Factor {
    /// K⁻¹ of one body and a square root R of it (R Rᵀ = K⁻¹), padded to 6×6 (closed-form
    /// reference path).
    Body {
        inverse: BodyMatrix,
        root: BodyMatrix,
    },
    Sparse(SparseFactor),
}

impl Flexibility {
    /// An empty flexibility; [`Self::refresh`] factorizes. With `sparse_only`, every cluster,
    /// single bodies included, goes through the sparse Cholesky.
    pub fn new(sparse_only: bool) -> Flexibility {
        Flexibility {
            factors: Vec::new(),
            stamps: Vec::new(),
            sparse_only,
            dt: f64::NAN,
            factor_drift: 0.0,
            formed: Vec::new(),
            sparse_factorizations: 0,
        }
    }

    /// Sets the refactor policy of sparse clusters (see the field `factor_drift`).
    pub fn with_factor_drift(mut self, drift: f64) -> Flexibility {
        self.factor_drift = drift;
        self
    }

    /// Numeric factorizations of sparse clusters since this flexibility was made.
    pub fn sparse_factorizations(&self) -> usize {
        self.sparse_factorizations
    }

    /// Whether sparse cluster `c`'s factor can be kept: the largest turn or strain of an element
    /// edge (a block's turn) since it was formed is within `factor_drift`.
    fn keeps(&self, c: usize, members: &[usize], bodies: &[Body]) -> bool {
        let Some(Some(formed)) = self.formed.get(c) else { return false };
        let drift = members.iter().zip(formed).map(|(&b, f)| f.drift(&bodies[b]));
        formed.len() == members.len() && drift.fold(0.0, f64::max) <= self.factor_drift
    }

    /// Factorizes the clusters whose K̃ changed: all of them on the first call (or when the
    /// cluster count or the step length changed), then those holding a deformable body (their mass and stiffness
    /// follow the geometry) or a coupling (connector blocks follow the anchors).
    pub fn refresh(
        &mut self,
        map: &DofMap,
        bodies: &[Body],
        couplings: &[CouplingBlock],
        dt: f64,
        damping: f64,
    ) -> Result<(), FactorError> {
        let first = self.factors.len() != map.clusters() || self.dt != dt;
        if first {
            self.factors.clear();
            self.stamps.clear();
            self.formed.clear();
            self.dt = dt;
        }
        self.formed.resize(map.clusters(), None);
        for c in 0..map.clusters() {
            let members = map.members(c);
            let coupled = couplings.iter().any(|cp| map.cluster_of(cp.a) == Some(c));
            let changes = coupled || members.iter().any(|&b| bodies[b].deformable);
            if !first && !changes {
                continue;
            }
            let failed = || FactorError { bodies: members.iter().map(|&b| bodies[b].name.clone()).collect() };
            let single = members.len() == 1 && bodies[members[0]].mesh.is_none();
            let sparse = !single || self.sparse_only;
            if sparse && !first && self.keeps(c, members, bodies) {
                continue; // math note §9.3: the kept factor (and its cached columns) serves on
            }
            if sparse && self.factor_drift > 0.0 {
                self.formed[c] = Some(members.iter().map(|&b| Formed::of(&bodies[b])).collect());
            }
            let factor = if !sparse {
                // a single body, possibly tied to fixed bodies: closed form with its own blocks
                let b = members[0];
                let own = couplings.iter().filter(|cp| cp.a == b && cp.b == b);
                let (inverse, root) = body_flexibility(&bodies[b], own, dt, damping).ok_or_else(failed)?;
                Factor::Body { inverse, root }
            } else {
                let triplets = cluster_triplets(map, c, bodies, couplings, dt, damping);
                // reuse the symbolic analysis of the last factor of this cluster
                let mut sparse = match self.factors.get(c).filter(|_| !first).map(|f| f.as_ref()) {
                    Some(Factor::Sparse(s)) => s.renewed(),
                    _ => SparseFactor::new(map.cluster_range(c).len()),
                };
                sparse.factorize(&triplets).map_err(|_| failed())?;
                self.sparse_factorizations += 1;
                Factor::Sparse(sparse)
            };
            let stamp = STAMPS.fetch_add(1, Ordering::Relaxed);
            if first {
                self.factors.push(Arc::new(factor));
                self.stamps.push(stamp);
            } else {
                self.factors[c] = Arc::new(factor);
                self.stamps[c] = stamp;
            }
        }
        Ok(())
    }

    /// Per cluster, a stamp that changes exactly when its factor is replaced: no two factors
    /// formed in one process, in any world, share one. What is derived from the factors can be
    /// kept while the stamps stay the same (the body form's packed blocks, math note §3.3).
    pub fn stamps(&self) -> &[u64] {
        &self.stamps
    }

    /// `v ← K̃⁻¹ v` for a vector over cluster `c`'s DOF range.
    pub fn solve_cluster(&self, c: usize, v: &mut [f64]) {
        self.factors[c].solve(v);
    }

    /// `v ← K̃⁻¹ v` for a global DOF vector (clusters are independent).
    pub fn solve_in_place(&self, map: &DofMap, v: &mut [f64]) {
        for c in 0..map.clusters() {
            self.solve_cluster(c, &mut v[map.cluster_range(c)]);
        }
    }

    /// A shared handle on cluster `c`'s factor (for a factor-backed W, `delassus.rs`).
    pub fn solver(&self, c: usize) -> ClusterSolver {
        ClusterSolver(Arc::clone(&self.factors[c]))
    }

    /// `(K̃_c⁻¹)_SS` of sparse cluster `c` for its cluster-local DOFs `dofs`, column-major (see
    /// [`SparseFactor::inverse_block`]); `None` for a single body's closed form.
    pub fn inverse_block(&self, c: usize, dofs: &[usize]) -> Option<Vec<f64>> {
        let Factor::Sparse(f) = self.factors[c].as_ref() else { return None };
        Some(f.inverse_block(dofs))
    }

    /// K̃⁻¹ of cluster `c` when it is a single body's closed form (padded to 6×6).
    pub fn body_inverse(&self, c: usize) -> Option<&BodyMatrix> {
        match self.factors[c].as_ref() {
            Factor::Body { inverse, .. } => Some(inverse),
            Factor::Sparse(_) => None,
        }
    }

    /// A square root R of K̃_c⁻¹ (R Rᵀ = K̃_c⁻¹; upper triangular, padded to 6×6) when cluster `c`
    /// is a single body's closed form: the body form's bound of ‖Ŵ‖ works with B R
    /// (`delassus/bodies.rs`, math note §3.3).
    pub fn body_root(&self, c: usize) -> Option<&BodyMatrix> {
        match self.factors[c].as_ref() {
            Factor::Body { root, .. } => Some(root),
            Factor::Sparse(_) => None,
        }
    }

    /// Whether cluster `c` goes through the sparse factorization.
    pub fn is_sparse(&self, c: usize) -> bool {
        matches!(self.factors[c].as_ref(), Factor::Sparse(_))
    }
}

/// A cluster's factor, shared: `K̃_c⁻¹ v` without holding the whole [`Flexibility`].
#[derive(Debug, Clone)]
pub struct ClusterSolver(Arc<Factor>);

impl ClusterSolver {
    /// `v ← K̃_c⁻¹ v`.
    pub fn solve(&self, v: &mut [f64]) {
        self.0.solve(v);
    }
}

impl Factor {
    fn solve(&self, v: &mut [f64]) {
        match self {
            Factor::Body { inverse, .. } => {
                // over the body's own n DOFs, not the padded 6×6 (column by column, as a product,
                // from the column-major storage); a rigid body's three values written back as
                // three stores, not a call to memcpy (3 % of a warm step of the 10,000-disk pile
                // went to this function, perf)
                const M: usize = crate::body::MAX_DOF;
                let (n, k) = (v.len(), inverse.as_slice());
                let mut x = [0.0; M];
                for (j, &vj) in v.iter().enumerate() {
                    for (i, xi) in x[..n].iter_mut().enumerate() {
                        *xi += k[j * M + i] * vj;
                    }
                }
                match n {
                    3 => (v[0], v[1], v[2]) = (x[0], x[1], x[2]),
                    _ => v.copy_from_slice(&x[..n]),
                }
            }
            Factor::Sparse(f) => f.solve_in_place(v),
        }
    }
}

/// K⁻¹ of one body, K = K_e + (2/dt²) M (math note eq. 1.2) plus the body's own coupling
/// blocks (connectors to fixed bodies), and its square root R = L⁻ᵀ (L K's Cholesky factor, so
/// R Rᵀ = (L Lᵀ)⁻¹ = K⁻¹), both padded to 6×6; `None` when K is not positive definite (a body
/// without mass).
fn body_flexibility<'a>(
    body: &Body,
    own: impl Iterator<Item = &'a CouplingBlock>,
    dt: f64,
    damping: f64,
) -> Option<(BodyMatrix, BodyMatrix)> {
    let n = body.ndof();
    let mut k = body.step_matrix(dt, damping);
    for cp in own {
        for (i, &ri) in cp.ra.iter().enumerate() {
            for (j, &rj) in cp.rb.iter().enumerate() {
                k[(ri, rj)] += cp.block[(i, j)];
            }
        }
    }
    let chol = k.view((0, 0), (n, n)).clone_owned().cholesky()?;
    let inv = chol.inverse();
    let root = chol.l().solve_lower_triangular(&nalgebra::DMatrix::identity(n, n))?.transpose();
    if !inv.iter().chain(root.iter()).all(|x| x.is_finite()) {
        return None;
    }
    let (mut inverse, mut padded) = (BodyMatrix::zeros(), BodyMatrix::zeros());
    inverse.view_mut((0, 0), (n, n)).copy_from(&inv);
    padded.view_mut((0, 0), (n, n)).copy_from(&root);
    Some((inverse, padded))
}

impl Formed {
    fn of(body: &Body) -> Formed {
        match &body.mesh {
            Some(fe) => Formed::Mesh(fe.nodes.clone()),
            None => Formed::Rotation(body.rotation),
        }
    }

    /// How far `body` has moved from this geometry, rigid translation aside: the largest relative
    /// change of an element edge vector |Δ(x_j − x_i)| / |x_j − x_i| (rotation plus strain) for a
    /// mesh, the rotation for a block or particle.
    fn drift(&self, body: &Body) -> f64 {
        match (self, &body.mesh) {
            (Formed::Mesh(then), Some(fe)) if then.len() == fe.nodes.len() => {
                let edge = |i: usize, j: usize| {
                    let (a, b) = (fe.nodes[j] - fe.nodes[i], then[j] - then[i]);
                    (a - b).norm() / b.norm()
                };
                fe.triangles
                    .iter()
                    .map(|t| edge(t[0], t[1]).max(edge(t[1], t[2])).max(edge(t[2], t[0])))
                    .fold(0.0, f64::max)
            }
            (Formed::Rotation(r), None) => (body.rotation - r).abs(),
            _ => f64::INFINITY,
        }
    }
}

/// Lower-triangle triplets (cluster-local indices) of cluster `c`'s K̃: the bodies' blocks
/// plus the coupling blocks between its bodies.
fn cluster_triplets(
    map: &DofMap,
    c: usize,
    bodies: &[Body],
    couplings: &[CouplingBlock],
    dt: f64,
    damping: f64,
) -> Vec<(usize, usize, f64)> {
    let base = map.cluster_range(c).start;
    let mut t = Vec::new();
    let mut push = |r: usize, col: usize, v: f64| {
        if r >= col {
            t.push((r - base, col - base, v));
        }
    };
    for &b in map.members(c) {
        if let Some(fe) = &bodies[b].mesh {
            // a mesh body: its assembled K̄ = Σ K_e + (2/dt²) M_e (math note §9.1)
            let at = map.range(b).start;
            for (i, j, v) in fe.step_triplets(dt) {
                push(at + i, at + j, v);
            }
            continue;
        }
        let k = bodies[b].step_matrix(dt, damping);
        let r = map.range(b);
        for i in 0..r.len() {
            for j in 0..r.len() {
                push(r.start + i, r.start + j, k[(i, j)]);
            }
        }
    }
    for cp in couplings.iter().filter(|cp| map.cluster_of(cp.a) == Some(c)) {
        let (a0, b0) = (map.range(cp.a).start, map.range(cp.b).start);
        for (i, &ri) in cp.ra.iter().enumerate() {
            for (j, &rj) in cp.rb.iter().enumerate() {
                push(a0 + ri, b0 + rj, cp.block[(i, j)]);
            }
        }
    }
    t
}

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
