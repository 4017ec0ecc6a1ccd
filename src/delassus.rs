//! The contact operator W = B K̃⁻¹ Bᵀ (paper eqs. 31–38 and 110–112; math note §3.1, §10.6),
//! the one thing the VI solver sees of the mechanics.
//!
//! W is assembled explicitly in CSR from *columns*: for every cluster c and every row s of B
//! that touches c, the column `K̃_c⁻¹ B_sᵀ` restricted to c (one closed-form 6×6 product for
//! a single body, one pair of triangular solves for a sparse cluster), and then
//! `W_rs = Σ_c B_r|c · K̃_c⁻¹ B_sᵀ|c`. Two rows are coupled only when they touch a common
//! cluster, so W stays sparse between clusters (never a dense N×N matrix). Each row is built
//! straight into CSR (no global triplet sort).
//!
//! A cluster whose explicit block would be too big — `rows_c² + rows_c · n_c` numbers above
//! [`EXPLICIT_LIMIT`], e.g. a long chain lying on the floor with one contact per body — is kept
//! in operator form instead: `W z` adds `B_c K̃_c⁻¹ B_cᵀ z` by one pair of triangular solves per
//! product, and only the diagonal `W_rr` is formed (one solve per row, as the columns would take).
//! The switch is by memory: both forms need one solve per row per step for the diagonal, so the
//! explicit form is cheaper whenever it fits (a product with a stored block costs far less than a
//! solve).

use crate::cluster::{ClusterSolver, Flexibility};
use crate::dofs::DofMap;
use crate::jacobian::{Jacobian, Segment};
use crate::vi::Operator;
use sprs::CsMat;

/// Where each cluster's rows sit: for cluster c, the distinct rows of B touching it, with the
/// indices of their segments on c, and their columns K̃_c⁻¹ B_sᵀ|c (cluster-local, row-major).
#[derive(Debug, Default)]
struct ClusterRows {
    rows: Vec<usize>,
    segments: Vec<Vec<usize>>,
    columns: Vec<f64>,
}

/// Above this many numbers (`rows_c² + rows_c · n_c`) a cluster's part of W is kept in operator
/// form (about 160 MB of f64).
pub const EXPLICIT_LIMIT: usize = 20_000_000;

/// W = B K̃⁻¹ Bᵀ, sparse and symmetric (both triangles stored), every cluster explicit.
pub fn assemble(jac: &Jacobian, flex: &Flexibility, map: &DofMap) -> CsMat<f64> {
    assemble_with(jac, flex, map, usize::MAX).explicit
}

/// W of one step as the VI sees it: the explicit CSR part, plus the clusters kept in operator form.
pub struct ContactOperator {
    pub explicit: CsMat<f64>,
    factored: Vec<FactoredCluster>,
    diagonal: Vec<f64>,
}

/// One cluster's part of W in operator form: its segments (cluster-local starts) and its factor.
struct FactoredCluster {
    n: usize,
    solver: ClusterSolver,
    segments: Vec<Segment>,
}

impl ContactOperator {
    /// W with every cluster explicit below `limit` numbers and in operator form above it.
    pub fn new(jac: &Jacobian, flex: &Flexibility, map: &DofMap, limit: usize) -> ContactOperator {
        assemble_with(jac, flex, map, limit)
    }

    /// Whether some cluster is in operator form.
    pub fn has_factored(&self) -> bool {
        !self.factored.is_empty()
    }
}

impl Operator for ContactOperator {
    fn dim(&self) -> usize {
        self.diagonal.len()
    }

    fn apply(&self, z: &[f64], out: &mut [f64]) {
        self.explicit.apply(z, out);
        for f in &self.factored {
            let mut t = vec![0.0; f.n];
            for s in &f.segments {
                for i in 0..s.len {
                    t[s.start + i] += s.vals[i] * z[s.row];
                }
            }
            f.solver.solve(&mut t);
            for s in &f.segments {
                out[s.row] += s.vals.dot(&s.gather(&t));
            }
        }
    }

    fn diagonal(&self, out: &mut [f64]) {
        out.copy_from_slice(&self.diagonal);
    }

    fn as_csr(&self) -> Option<sprs::CsMatView<'_, f64>> {
        self.factored.is_empty().then(|| self.explicit.view())
    }
}

fn assemble_with(jac: &Jacobian, flex: &Flexibility, map: &DofMap, limit: usize) -> ContactOperator {
    let factored_clusters: Vec<bool> = cluster_row_counts(jac, map)
        .iter()
        .enumerate()
        .map(|(c, &rows)| {
            let n = map.cluster_range(c).len();
            rows.saturating_mul(rows).saturating_add(rows.saturating_mul(n)) > limit
        })
        .collect();
    let mut diagonal = vec![0.0; jac.rows];
    let factored = factored_parts(jac, flex, map, &factored_clusters, &mut diagonal);
    let (per_cluster, at) = columns(jac, flex, map, &factored_clusters);
    let mut indptr = Vec::with_capacity(jac.rows + 1);
    let (mut indices, mut data) = (Vec::new(), Vec::new());
    indptr.push(0);
    let mut row: Vec<(usize, f64)> = Vec::new();
    for places in &at {
        row.clear();
        for &(c, p) in places {
            let cr = &per_cluster[c];
            let range = map.cluster_range(c);
            let n = range.len();
            for &si in &cr.segments[p] {
                let seg = &jac.segments[si];
                for (q, &s) in cr.rows.iter().enumerate() {
                    let col = &cr.columns[q * n..(q + 1) * n];
                    row.push((s, seg.vals.dot(&local(seg, col, range.start))));
                }
            }
        }
        row.sort_unstable_by_key(|e| e.0);
        let first = indices.len();
        for &(s, v) in &row {
            if indices.len() > first && indices.last() == Some(&s) {
                if let Some(last) = data.last_mut() {
                    *last += v;
                }
            } else {
                indices.push(s);
                data.push(v);
            }
        }
        indptr.push(indices.len());
    }
    let explicit = CsMat::new((jac.rows, jac.rows), indptr, indices, data);
    for (r, d) in diagonal.iter_mut().enumerate() {
        *d += explicit.get(r, r).copied().unwrap_or(0.0);
    }
    ContactOperator { explicit, factored, diagonal }
}

/// Rows of B touching each cluster (a row with two segments on one cluster counts twice: an
/// upper bound is enough for the switch).
fn cluster_row_counts(jac: &Jacobian, map: &DofMap) -> Vec<usize> {
    let mut counts = vec![0usize; map.clusters()];
    for s in &jac.segments {
        counts[s.cluster] += 1;
    }
    counts
}

/// The clusters in operator form: their segments and factors, and their part of diag(W).
fn factored_parts(
    jac: &Jacobian,
    flex: &Flexibility,
    map: &DofMap,
    factored: &[bool],
    diagonal: &mut [f64],
) -> Vec<FactoredCluster> {
    let mut parts: Vec<Option<FactoredCluster>> = (0..map.clusters())
        .map(|c| {
            factored[c].then(|| FactoredCluster {
                n: map.cluster_range(c).len(),
                solver: flex.solver(c),
                segments: Vec::new(),
            })
        })
        .collect();
    for s in jac.segments.iter().filter(|s| factored[s.cluster]) {
        let base = map.cluster_range(s.cluster).start;
        if let Some(part) = &mut parts[s.cluster] {
            part.segments.push(Segment { start: s.start - base, ..*s });
        }
    }
    let mut parts: Vec<FactoredCluster> = parts.into_iter().flatten().collect();
    for part in &mut parts {
        part.segments.sort_by_key(|s| s.row); // stable: a row's segments become consecutive
    }
    for part in &parts {
        // W_rr = B_r|c · K̃_c⁻¹ B_rᵀ|c, one solve per row (its segments are consecutive)
        let mut k = 0;
        while k < part.segments.len() {
            let row = part.segments[k].row;
            let end = k + part.segments[k..].iter().take_while(|s| s.row == row).count();
            let mut col = vec![0.0; part.n];
            for s in &part.segments[k..end] {
                for i in 0..s.len {
                    col[s.start + i] += s.vals[i];
                }
            }
            part.solver.solve(&mut col);
            diagonal[row] += part.segments[k..end].iter().map(|s| s.vals.dot(&s.gather(&col))).sum::<f64>();
            k = end;
        }
    }
    parts
}

/// The segment's range of a cluster-local vector, padded.
fn local(seg: &Segment, col: &[f64], base: usize) -> crate::body::Dofs {
    let mut d = crate::body::Dofs::zeros();
    let start = seg.start - base;
    d.as_mut_slice()[..seg.len].copy_from_slice(&col[start..start + seg.len]);
    d
}

/// Groups the segments by cluster and computes each row's column K̃_c⁻¹ B_sᵀ|c. Also
/// returns, for every row, the (cluster, position) pairs it appears at, clusters ascending.
fn columns(
    jac: &Jacobian,
    flex: &Flexibility,
    map: &DofMap,
    factored: &[bool],
) -> (Vec<ClusterRows>, Vec<Vec<(usize, usize)>>) {
    let mut per_cluster: Vec<ClusterRows> = (0..map.clusters()).map(|_| ClusterRows::default()).collect();
    let mut at: Vec<Vec<(usize, usize)>> = vec![Vec::new(); jac.rows];
    for (si, seg) in jac.segments.iter().enumerate().filter(|(_, s)| !factored[s.cluster]) {
        let cr = &mut per_cluster[seg.cluster];
        match at[seg.row].iter().find(|(c, _)| *c == seg.cluster) {
            Some(&(_, p)) => cr.segments[p].push(si),
            None => {
                at[seg.row].push((seg.cluster, cr.rows.len()));
                cr.rows.push(seg.row);
                cr.segments.push(vec![si]);
            }
        }
    }
    for places in &mut at {
        places.sort_unstable();
    }
    for (c, cr) in per_cluster.iter_mut().enumerate() {
        let range = map.cluster_range(c);
        let n = range.len();
        cr.columns = vec![0.0; cr.rows.len() * n];
        for (p, segs) in cr.segments.iter().enumerate() {
            let col = &mut cr.columns[p * n..(p + 1) * n];
            if flex.is_sparse(c) {
                // from the cached unit columns of the DOFs touched (math note §9.3)
                for &si in segs {
                    let s = &jac.segments[si];
                    flex.add_columns(c, s.start - range.start, &s.vals.as_slice()[..s.len], col);
                }
                continue;
            }
            for &si in segs {
                let s = &jac.segments[si];
                for i in 0..s.len {
                    col[s.start - range.start + i] += s.vals[i];
                }
            }
            flex.solve_cluster(c, col);
        }
    }
    (per_cluster, at)
}
