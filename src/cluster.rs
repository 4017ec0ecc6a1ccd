//! The step stiffness K̃ = K_e + (2/dt²) M per cluster and its solves (math note eq. 1.2,
//! §3.1 "coupled K", §10.6).
//!
//! A cluster without meshes of at most `DENSE_MAX` = 48 DOFs (a single body, or a few bodies
//! joined by connectors) takes the closed-form path: K̃ dense, factorized by a dense Cholesky
//! and inverted (nalgebra; `dense.rs`, math note §6). A larger cluster or a meshed body
//! assembles a sparse K̃ and factorizes it with faer's sparse Cholesky: the symbolic analysis
//! is done once while the sparsity pattern is unchanged, the numeric factorization whenever
//! the values change; such a cluster is never inverted explicitly.
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

use crate::body::{Body, BodyMatrix, MAX_DOF};
use crate::dofs::DofMap;
use std::sync::atomic::{AtomicU64, Ordering};

mod dense;
mod snapshot;
/// The sparse factor is the leaf module [`crate::sparse`]'s; re-exported under its old path.
pub use crate::sparse::{SparseError, SparseFactor};
pub use dense::DENSE_MAX;
pub(crate) use dense::block_times;
use dense::{Dense, body_solve};
pub use snapshot::FlexState;
use std::sync::Arc;

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
    /// The clusters holding a deformable body, whose mass and stiffness follow the geometry:
    /// found on the first refresh (a new cluster layout makes a new flexibility), so that a
    /// later one visits only them and the coupled clusters, not every body.
    deforming: Vec<usize>,
    /// Per cluster, where its closed-form K̃_c⁻¹ (n_c × n_c, column-major) starts in `closed`,
    /// or `NONE` for a sparse cluster. The global solves (the prediction, each response) read
    /// these packed blocks in cluster order, 72 bytes a rigid body, instead of each factor
    /// through its own allocation (two padded 6×6 matrices), which a large pile reads with a
    /// cache miss per cluster. The body form's products read them too
    /// (`delassus::bodies::Blocks`, which shares them while they stay current).
    closed_at: Vec<u32>,
    closed: Arc<Vec<f64>>,
}

/// A cluster's entry in `Flexibility::closed_at` when it is sparse.
const NONE: u32 = u32::MAX;

/// The geometry a sparse cluster's factor was formed on: each member's mesh nodes, or its
/// rotation for a block or particle (whose connector blocks turn with it).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
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
    /// The same for a cluster of more than 6 and at most `DENSE_MAX` DOFs without meshes,
    /// n × n (`dense.rs`).
    Dense(Dense),
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
            deforming: Vec::new(),
            closed_at: Vec::new(),
            closed: Arc::default(),
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
            self.closed_at.clear();
            self.closed = Arc::default();
            self.dt = dt;
            self.deforming = (0..map.clusters())
                .filter(|&c| map.members(c).iter().any(|&b| bodies[b].deformable))
                .collect();
        }
        self.formed.resize(map.clusters(), None);
        // the coupling blocks of each cluster, by cluster and then in coupling order: a cluster's
        // are found by two binary searches, not by a scan of every coupling per cluster
        // (O(clusters × couplings) on the first refresh, and every step over the coupled ones)
        let mut by_cluster: Vec<(usize, usize)> =
            couplings.iter().enumerate().filter_map(|(i, cp)| map.cluster_of(cp.a).map(|c| (c, i))).collect();
        by_cluster.sort_unstable();
        let inside = |c: usize| {
            let at =
                by_cluster.partition_point(|&(x, _)| x < c)..by_cluster.partition_point(|&(x, _)| x <= c);
            by_cluster[at].iter().map(|&(_, i)| &couplings[i])
        };
        // after the first refresh, the clusters whose K̃ changes: those deforming and those a
        // coupling acts in (connector blocks follow the anchors), each once, in cluster order
        let changing: Vec<usize> = if first {
            (0..map.clusters()).collect()
        } else {
            let mut cs: Vec<usize> =
                self.deforming.iter().copied().chain(by_cluster.iter().map(|&(c, _)| c)).collect();
            cs.sort_unstable();
            cs.dedup();
            cs
        };
        for c in changing {
            let members = map.members(c);
            let failed = || FactorError { bodies: members.iter().map(|&b| bodies[b].name.clone()).collect() };
            // a single body, or bodies joined by connectors with at most DENSE_MAX DOFs between
            // them (a chain of bolted disks), without meshes: closed form (math note §6)
            let sparse = !dense::is_closed(map, c, bodies) || self.sparse_only;
            if sparse && !first && self.keeps(c, members, bodies) {
                continue; // math note §9.3: the kept factor (and its cached columns) serves on
            }
            if sparse && self.factor_drift > 0.0 {
                self.formed[c] = Some(members.iter().map(|&b| Formed::of(&bodies[b])).collect());
            }
            let k = StepStiffness { map, c, bodies, inside: inside(c), dt, damping };
            let factor = if !sparse {
                dense::closed_factor(k).ok_or_else(failed)?
            } else {
                let triplets = k.lower_triplets();
                let mut sparse = self.take_sparse(c, map.cluster_range(c).len(), first);
                sparse.factorize(&triplets).map_err(|_| failed())?;
                self.sparse_factorizations += 1;
                Factor::Sparse(sparse)
            };
            self.pack(c, &factor, map.cluster_range(c).len(), first);
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

    /// The sparse factor to refactorize cluster `c` (`n` DOFs) into: the last one's symbolic
    /// analysis, and its storage when nothing else holds it (math note §9.8); a new one on the
    /// first refresh.
    fn take_sparse(&mut self, c: usize, n: usize, first: bool) -> SparseFactor {
        match self.factors.get_mut(c).filter(|_| !first) {
            Some(f) => match Arc::get_mut(f) {
                Some(Factor::Sparse(s)) => std::mem::replace(s, SparseFactor::new(0)),
                _ => match f.as_ref() {
                    Factor::Sparse(s) => s.renewed(),
                    _ => SparseFactor::new(n),
                },
            },
            None => SparseFactor::new(n),
        }
    }

    /// Keeps cluster `c`'s closed-form K̃⁻¹ over its `n` DOFs in `closed` (a new entry on the
    /// first refresh, in cluster order; else over the old one, which has the same size).
    fn pack(&mut self, c: usize, factor: &Factor, n: usize, first: bool) {
        let Some((inverse, stride)) = factor.closed() else {
            if first {
                self.closed_at.push(NONE);
            }
            return;
        };
        // (a copy only while body-form blocks made from the old values still share them)
        let closed = Arc::make_mut(&mut self.closed);
        if first {
            self.closed_at.push(closed.len() as u32);
            closed.resize(closed.len() + n * n, 0.0);
        }
        let at = self.closed_at[c] as usize;
        for (j, column) in closed[at..at + n * n].chunks_exact_mut(n).enumerate() {
            column.copy_from_slice(&inverse[j * stride..j * stride + n]);
        }
    }

    /// Per cluster, a stamp that changes exactly when its factor is replaced: no two factors
    /// formed in one process, in any world, share one. What is derived from the factors can be
    /// kept while the stamps stay the same (the body form's packed blocks, math note §3.3).
    pub fn stamps(&self) -> &[u64] {
        &self.stamps
    }

    /// `v ← K̃⁻¹ v` for a vector over cluster `c`'s DOF range.
    pub fn solve_cluster(&self, c: usize, v: &mut [f64]) {
        match self.closed_at[c] {
            NONE => self.factors[c].solve(v),
            at => body_solve(&self.closed[at as usize..], v.len(), v),
        }
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

    /// The closed-form clusters' K̃_c⁻¹, n_c × n_c column-major, in cluster order, and where
    /// cluster `c`'s starts in them (`None` for a sparse cluster).
    pub(crate) fn closed(&self, c: usize) -> (&Arc<Vec<f64>>, Option<usize>) {
        (&self.closed, (self.closed_at[c] != NONE).then_some(self.closed_at[c] as usize))
    }

    /// K̃⁻¹ of cluster `c` when it is in closed form on the fixed 6×6 (a single body, or at most
    /// 6 DOFs; padded).
    pub fn body_inverse(&self, c: usize) -> Option<&BodyMatrix> {
        match self.factors[c].as_ref() {
            Factor::Body { inverse, .. } => Some(inverse),
            Factor::Dense(_) | Factor::Sparse(_) => None,
        }
    }

    /// A square root R of K̃_c⁻¹ (R Rᵀ = K̃_c⁻¹; upper triangular, column-major) and its column
    /// stride (6, padded, or the cluster's DOF count) when cluster `c` is in closed form: the
    /// body form's bound of ‖Ŵ‖ works with B R (`delassus/bodies.rs`, math note §3.3).
    pub fn body_root(&self, c: usize) -> Option<(&[f64], usize)> {
        match self.factors[c].as_ref() {
            Factor::Body { root, .. } => Some((root.as_slice(), MAX_DOF)),
            Factor::Dense(d) => Some((&d.root, d.n)),
            Factor::Sparse(_) => None,
        }
    }

    /// Whether cluster `c` goes through the sparse factorization.
    pub fn is_sparse(&self, c: usize) -> bool {
        // (from the packing's offsets, one load, not a pointer chase through the factor)
        self.closed_at[c] == NONE
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
            Factor::Body { inverse, .. } => body_solve(inverse.as_slice(), MAX_DOF, v),
            Factor::Dense(d) => body_solve(&d.inverse, d.n, v),
            Factor::Sparse(f) => f.solve_in_place(v),
        }
    }

    /// A closed form's K̃⁻¹, column-major, and its column stride; `None` for a sparse factor.
    fn closed(&self) -> Option<(&[f64], usize)> {
        match self {
            Factor::Body { inverse, .. } => Some((inverse.as_slice(), MAX_DOF)),
            Factor::Dense(d) => Some((&d.inverse, d.n)),
            Factor::Sparse(_) => None,
        }
    }
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

/// Cluster `c`'s step stiffness K̃ as its entries come ([`Self::entries`]): its bodies, and its
/// coupling blocks `inside` (the cluster's, in coupling order), at step `dt` with the
/// stiffness-proportional `damping`. What the closed form (`dense.rs`) and the sparse factor
/// are built from.
struct StepStiffness<'a, I> {
    map: &'a DofMap,
    c: usize,
    bodies: &'a [Body],
    inside: I,
    dt: f64,
    damping: f64,
}

impl<'a, I: Iterator<Item = &'a CouplingBlock>> StepStiffness<'a, I> {
    /// The cluster's DOF count.
    fn dofs(&self) -> usize {
        self.map.cluster_range(self.c).len()
    }

    /// Lower-triangle triplets (cluster-local indices) of K̃ ([`Self::entries`]). A cluster of
    /// one mesh and no coupling takes the mesh's own, which are already these, in this order
    /// (not copied: ~700,000 at 100k DOF).
    fn lower_triplets(self) -> Vec<(usize, usize, f64)> {
        let mut inside = self.inside.peekable();
        if let [b] = self.map.members(self.c)
            && let Some(fe) = &self.bodies[*b].mesh
            && inside.peek().is_none()
            && self.map.range(*b).start == self.map.cluster_range(self.c).start
        {
            return fe.step_triplets(self.dt);
        }
        let (map, c, bodies, dt, damping) = (self.map, self.c, self.bodies, self.dt, self.damping);
        let k = StepStiffness { map, c, bodies, inside, dt, damping };
        let mut t = Vec::new();
        k.entries(|r, col, v| {
            if r >= col {
                t.push((r, col, v));
            }
        });
        t
    }

    /// `visit(row, column, value)` for the entries of K̃ (cluster-local indices, duplicates to
    /// be summed): each body's block (a mesh's assembled K̄ = Σ K_e + (2/dt²) M_e, math note
    /// §9.1; else K = K_e + (2/dt²) M, eq. 1.2), then the coupling blocks between its bodies in
    /// order.
    fn entries(self, mut visit: impl FnMut(usize, usize, f64)) {
        let base = self.map.cluster_range(self.c).start;
        for &b in self.map.members(self.c) {
            let at = self.map.range(b).start - base;
            if let Some(fe) = &self.bodies[b].mesh {
                for (i, j, v) in fe.step_triplets(self.dt) {
                    visit(at + i, at + j, v);
                }
                continue;
            }
            let (k, n) = (self.bodies[b].step_matrix(self.dt, self.damping), self.bodies[b].ndof());
            for i in 0..n {
                for j in 0..n {
                    visit(at + i, at + j, k[(i, j)]);
                }
            }
        }
        for cp in self.inside {
            let (a0, b0) = (self.map.range(cp.a).start - base, self.map.range(cp.b).start - base);
            for (i, &ri) in cp.ra.iter().enumerate() {
                for (j, &rj) in cp.rb.iter().enumerate() {
                    visit(a0 + ri, b0 + rj, cp.block[(i, j)]);
                }
            }
        }
    }
}

/// Test helper: a bolt (E = 1e8 Pa, A = 0.01 m²) from each of the first `count` bodies to the
/// next, anchored at (i − 1, 0) and (i, 0) (the centres of a row of disks one apart): the
/// coupling blocks and the joined pairs.
#[cfg(test)]
pub(crate) fn bolted_row(bodies: &[Body], count: usize) -> (Vec<CouplingBlock>, Vec<(usize, usize)>) {
    use crate::connector::Connector;
    use crate::geometry::Vec2;
    use crate::model::{ConnectorKind, ConnectorSpec};
    let couplings = (1..count)
        .flat_map(|i| {
            let spec = ConnectorSpec {
                name: format!("bolt{i}"),
                kind: ConnectorKind::Bolt { young: 1e8, area: 0.01 },
                bodies: [i - 1, i],
                points: [Vec2::new(i as f64 - 1.0, 0.0), Vec2::new(i as f64, 0.0)],
                pretension: 0.0,
                strength: None,
                yield_force: None,
                ultimate_strain: None,
            };
            Connector::from_spec(&spec).stiffness(bodies)
        })
        .collect();
    (couplings, (1..count).map(|i| (i - 1, i)).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Vec2;
    use crate::model::{BodyModel, BodySpec, Material, Plane, Shape};

    /// `count` rigid disks (radius 0.5, density 2) in a row, one apart, each joined to the next
    /// by a bolt (E = 1e8 Pa, A = 0.01 m²): one cluster of 3 `count` DOFs. Its flexibility in
    /// the closed form where it applies, and through the sparse factor (`Flexibility::new(true)`:
    /// every cluster sparse).
    fn bolted_chain(count: usize) -> (DofMap, Flexibility, Flexibility) {
        let material = Material { name: "m".into(), density: 2.0, young: Some(1e8), poisson: Some(0.3) };
        let bodies: Vec<Body> = (0..count)
            .map(|i| {
                let shape = Shape::Disk { center: Vec2::new(i as f64, 0.0), radius: 0.5 };
                let spec = BodySpec::at_rest(format!("b{i}"), shape, BodyModel::Rigid, false);
                Body::new(&spec, &material, Plane::Stress)
            })
            .collect();
        let (couplings, pairs) = bolted_row(&bodies, count);
        let map = DofMap::new(&bodies, &pairs);
        let (mut closed, mut sparse) = (Flexibility::new(false), Flexibility::new(true));
        closed.refresh(&map, &bodies, &couplings, 0.01, 0.0).expect("K̃ is SPD");
        sparse.refresh(&map, &bodies, &couplings, 0.01, 0.0).expect("K̃ is SPD");
        assert_eq!((map.clusters(), map.cluster_range(0).len()), (1, 3 * count));
        (map, closed, sparse)
    }

    /// The columns K̃⁻¹ e_i of cluster 0 (column-major, n × n).
    fn columns(flex: &Flexibility, n: usize) -> Vec<f64> {
        (0..n)
            .flat_map(|i| {
                let mut e = vec![0.0; n];
                e[i] = 1.0;
                flex.solve_cluster(0, &mut e);
                e
            })
            .collect()
    }

    /// Bolted chains ([`bolted_chain`]) of 2, 3 and 16 disks (6, 9 and 48 DOFs) get a closed
    /// form (`dense::closed_factor`: the fixed 6 × 6 for 6, n × n above) whose K̃⁻¹ applied to
    /// each unit vector equals the sparse factor's solve of the same K̃ to 1e-12 of the largest
    /// entry, and whose square root R (`body_root`) gives R Rᵀ = K̃⁻¹ to 1e-12 of it; a chain of
    /// 17 (51 DOFs, above `DENSE_MAX`) goes through the sparse factor. Both factor the same
    /// symmetric positive definite matrix by Cholesky. Its condition number (mass terms
    /// 2m/dt² ≈ 3e4 and 2I/dt² ≈ 4e3 against each bolt's EA/l = 1e6) is 517, 772 and 1,017 for
    /// 2, 3 and 16 disks (computed once from the closed form's eigenvalues), so the two agree to
    /// about 1e-16 times that of the largest entry; 1e-12 leaves the margin. Both closed forms
    /// are symmetric bit for bit (the n × n one formed as R Rᵀ: entries (i, j) and (j, i) sum the
    /// same products in the same order).
    #[test]
    fn chain_closed_form_equals_the_sparse_factor() {
        for count in [2, 3, 16] {
            let n = 3 * count;
            let (_, closed, sparse) = bolted_chain(count);
            assert!(closed.closed(0).1.is_some() && !closed.is_sparse(0) && sparse.is_sparse(0), "{count}");
            let (got, want) = (columns(&closed, n), columns(&sparse, n));
            let scale = want.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let near = |a: f64, b: f64| (a - b).abs() <= 1e-12 * scale;
            assert!(got.iter().zip(&want).all(|(a, b)| near(*a, *b)), "{count}: {got:?} vs {want:?}");
            let (root, stride) = closed.body_root(0).expect("a closed form");
            let r = |i: usize, j: usize| root[j * stride + i];
            for (i, j) in (0..n).flat_map(|i| (0..n).map(move |j| (i, j))) {
                let rrt: f64 = (0..n).map(|k| r(i, k) * r(j, k)).sum();
                assert!(near(rrt, want[j * n + i]), "{count}: R Rᵀ at ({i}, {j})");
                assert_eq!(got[j * n + i].to_bits(), got[i * n + j].to_bits(), "{count}: symmetric");
            }
        }
        let (_, closed, _) = bolted_chain(17);
        assert!(closed.is_sparse(0) && closed.body_root(0).is_none());
    }
}
