//! The contact operator W = B K̃⁻¹ Bᵀ (paper eqs. 31–38 and 110–112; math note §3.1, §10.6),
//! the one thing the VI solver sees of the mechanics.
//!
//! W is assembled explicitly in CSR from *columns*: for every cluster c and every row s of B
//! that touches c, the column `K̃_c⁻¹ B_sᵀ` restricted to c (one closed-form 6×6 product for
//! a single body, one pair of triangular solves for a sparse cluster), and then
//! `W_rs = Σ_c B_r|c · K̃_c⁻¹ B_sᵀ|c`. Two rows are coupled only when they touch a common
//! cluster, so W stays sparse between clusters (never a dense N×N matrix). Each row is built
//! straight into CSR (no global triplet sort).

use crate::cluster::Flexibility;
use crate::dofs::DofMap;
use crate::jacobian::{Jacobian, Segment};
use sprs::CsMat;

/// Where each cluster's rows sit: for cluster c, the distinct rows of B touching it, with the
/// indices of their segments on c, and their columns K̃_c⁻¹ B_sᵀ|c (cluster-local, row-major).
#[derive(Debug, Default)]
struct ClusterRows {
    rows: Vec<usize>,
    segments: Vec<Vec<usize>>,
    columns: Vec<f64>,
}

/// W = B K̃⁻¹ Bᵀ, sparse and symmetric (both triangles stored).
pub fn assemble(jac: &Jacobian, flex: &Flexibility, map: &DofMap) -> CsMat<f64> {
    let (per_cluster, at) = columns(jac, flex, map);
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
    CsMat::new((jac.rows, jac.rows), indptr, indices, data)
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
fn columns(jac: &Jacobian, flex: &Flexibility, map: &DofMap) -> (Vec<ClusterRows>, Vec<Vec<(usize, usize)>>) {
    let mut per_cluster: Vec<ClusterRows> = (0..map.clusters()).map(|_| ClusterRows::default()).collect();
    let mut at: Vec<Vec<(usize, usize)>> = vec![Vec::new(); jac.rows];
    for (si, seg) in jac.segments.iter().enumerate() {
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
