//! The contact operator W = B K̃⁻¹ Bᵀ (paper eqs. 31–38 and 110–112; math note §3.1, §10.6),
//! the one thing the VI solver sees of the mechanics.
//!
//! W is assembled explicitly in CSR from *columns*: for every cluster c and every row s of B
//! that touches c, the column `K̃_c⁻¹ B_sᵀ` (one closed-form 6×6 product over a single body's
//! DOFs; for a sparse cluster, over only the set S of its DOFs that rows touch, from the cached
//! block `(K̃_c⁻¹)_SS`, math note §9.3), and then `W_rs = Σ_c B_r|c · K̃_c⁻¹ B_sᵀ|c`. Two rows are
//! coupled only when they touch a common cluster, so W stays sparse between clusters (never a
//! dense N×N matrix). Each row is built straight into CSR by merging, column by column, the
//! rows of the clusters it touches (no sort).
//!
//! A cluster whose explicit block would be too big — `rows_c² + rows_c · len_c` numbers above
//! [`EXPLICIT_LIMIT`], `len_c` its column length (DOFs, or |S|) — is kept in operator form
//! instead: `W z` adds `B_c K̃_c⁻¹ B_cᵀ z` by one pair of triangular solves per product, and only
//! the diagonal `W_rr` is formed (one solve per row). The switch is by memory: a product with a
//! stored block costs far less than a solve.
//!
//! Clusters with a closed-form K̃_c⁻¹ (single bodies, and clusters of at most 48 DOFs without
//! meshes: math note §6) are in *body form* when the caller asks (every method but NSGS, whose sweeps read W's
//! rows): applied through their K̃_c⁻¹, never assembled (`bodies.rs`, math note §3.3).

use crate::cluster::{ClusterSolver, Flexibility};
use crate::dofs::DofMap;
use crate::jacobian::{Jacobian, Segment};
use crate::sparse::{Csr, CsrView};
use crate::vi::Operator;
use blocks::NONE;
use bodies::BodyPart;
use std::sync::Arc;

mod blocks;
mod bodies;
mod cut;
mod frames;

/// Work storage of the explicit assembly, kept across steps by the world's pipeline so that a
/// step allocates only the CSR arrays of its W.
///
/// A *place* is one (cluster, row) pair of B: the row's segments on that cluster and its
/// column K̃_c⁻¹ B_rᵀ|c over the cluster's DOF range.
#[derive(Debug, Clone, Default)]
pub struct Scratch {
    /// Explicit segments' indices, grouped by cluster (ascending) and by row within a cluster,
    /// in push order within a row (which fixes every sum's order).
    order: Vec<usize>,
    /// Per cluster, its range of `order` (`clusters + 1` offsets); reused as a counter.
    cluster_start: Vec<usize>,
    /// Per place: its row, first index into `order` (`places + 1` entries), cluster, and first
    /// index into `columns`.
    place_row: Vec<usize>,
    place_seg: Vec<usize>,
    place_cluster: Vec<usize>,
    place_col: Vec<usize>,
    /// Per cluster, its range of places (`clusters + 1` offsets).
    cluster_place: Vec<usize>,
    /// Per sparse cluster, the sorted cluster-local DOFs that rows touch (S); empty otherwise.
    sets: Vec<Vec<usize>>,
    /// The clusters whose sets are not empty.
    touched: Vec<usize>,
    /// Per cluster, the length of its columns: |S| for a sparse cluster (columns are kept at S
    /// only), its DOF count otherwise.
    col_len: Vec<usize>,
    /// Per segment of B, the position of its first DOF in its cluster's columns.
    seg_at: Vec<usize>,
    columns: Vec<f64>,
    /// Per place, its range of `term_at`/`term_val` (`places + 1` offsets): B_r|c as
    /// (position in the cluster's columns, value) pairs.
    place_term: Vec<usize>,
    term_at: Vec<usize>,
    term_val: Vec<f64>,
    /// Per row of W, its places (CSR: `row_place_start` has `rows + 1` offsets).
    row_place_start: Vec<usize>,
    row_places: Vec<usize>,
    /// The merge of one row of W: per place of the row, (place, cursor, end) over the places
    /// of its cluster.
    cursors: Vec<(usize, usize, usize)>,
    /// The body form's packed blocks, kept across steps while they stay current.
    blocks: Option<Arc<blocks::Blocks>>,
}

impl Scratch {
    /// The body form's blocks for the clusters with `body[c]`: the kept ones while their
    /// layout holds ([`blocks::Blocks::same_layout`]), as they are while no factor changed,
    /// else brought up to date in place ([`blocks::Blocks::update`], when no operator of an
    /// earlier step still holds them); else new ones, kept for the next call.
    fn blocks(&mut self, flex: &Flexibility, map: &DofMap, body: &[bool]) -> Arc<blocks::Blocks> {
        let current = |b: &mut Arc<blocks::Blocks>| {
            b.same_layout(map, body)
                && (b.stamps == flex.stamps() || Arc::get_mut(b).is_some_and(|b| b.update(flex)))
        };
        if let Some(kept) = self.blocks.as_mut()
            && current(kept)
        {
            return Arc::clone(kept);
        }
        Arc::clone(self.blocks.insert(Arc::new(blocks::Blocks::new(flex, map, body))))
    }
}

/// Above this many numbers (`rows_c² + rows_c · n_c`) a cluster's part of W is kept in operator
/// form (about 160 MB of f64).
pub const EXPLICIT_LIMIT: usize = 20_000_000;

/// W = B K̃⁻¹ Bᵀ, sparse and symmetric (both triangles stored), every cluster explicit (on a
/// copy of B, which the operator keeps).
pub fn assemble(jac: &Jacobian, flex: &Flexibility, map: &DofMap) -> Csr {
    ContactOperator::with_scratch(jac.clone(), flex, map, usize::MAX, false, &mut Scratch::default()).explicit
}

/// W of one step as the VI sees it: the explicit CSR part, plus the clusters kept in operator
/// form and the single bodies in body form, which are applied through B itself: the operator
/// owns B.
pub struct ContactOperator {
    jac: Jacobian,
    pub explicit: Csr,
    /// The rows of `explicit` with entries, when they are fewer than half of its rows (a few
    /// bolted or meshed clusters in a pile of single bodies): its products walk those only.
    explicit_rows: Option<Vec<usize>>,
    factored: Vec<FactoredCluster>,
    bodies: BodyPart,
    diagonal: Vec<f64>,
}

/// One cluster's part of W in operator form: its rows of B (cluster-local starts, sorted by
/// row) and its factor.
struct FactoredCluster {
    n: usize,
    solver: ClusterSolver,
    segments: Jacobian,
}

impl ContactOperator {
    /// W with every cluster explicit below `limit` numbers and in operator form above it.
    pub fn new(jac: Jacobian, flex: &Flexibility, map: &DofMap, limit: usize) -> ContactOperator {
        Self::with_scratch(jac, flex, map, limit, false, &mut Scratch::default())
    }

    /// [`Self::new`] with the work storage of earlier steps; with `bodies`, every cluster with a
    /// closed-form K̃⁻¹ (a single body, or at most 48 DOFs without meshes) is in body form (`bodies.rs`, math
    /// note §3.3) instead of explicit.
    pub fn with_scratch(
        mut jac: Jacobian,
        flex: &Flexibility,
        map: &DofMap,
        limit: usize,
        bodies: bool,
        scratch: &mut Scratch,
    ) -> ContactOperator {
        // (through the packed blocks' offsets: each factor behind its own allocation would cost a
        // cache miss per cluster)
        let body: Vec<bool> = (0..map.clusters()).map(|c| bodies && flex.closed(c).1.is_some()).collect();
        let blocks = scratch.blocks(flex, map, &body);
        // the body form reads the frames of rigid bodies in body form; a frame on any other
        // cluster (or without the body form) turns into segments, so that from here on every
        // frame is the body form's and the assembly reads B's own segments only. (With every
        // cluster in body form no pass over the frames: a frame's bodies are rigid and alone
        // in their clusters, `rows::Site`.)
        let rigid = |c: &u32| blocks.rigid[*c as usize] != NONE;
        if !blocks.every() && !jac.frame_clusters().iter().flatten().all(rigid) {
            jac.unframe();
        }
        let mut diagonal = vec![0.0; jac.rows];
        // (every cluster a body in body form answers for every segment without reading them)
        if body.iter().all(|&b| b) || jac.own_segments().iter().all(|s| body[s.cluster()]) {
            // a scene of single bodies: nothing to assemble, so the assembly's passes over every
            // segment and row (layout, places, CSR rows) are skipped
            let bodies = BodyPart::new(&jac, blocks, &mut diagonal);
            let explicit = Csr::zero((jac.rows, jac.rows));
            return ContactOperator {
                jac,
                explicit,
                explicit_rows: None,
                factored: Vec::new(),
                bodies,
                diagonal,
            };
        }
        scratch.layout(&jac, flex, map);
        let factored_clusters: Vec<bool> = cluster_row_counts(&jac, map)
            .iter()
            .zip(&scratch.col_len)
            .zip(&body)
            .map(|((&rows, &n), &b)| {
                !b && rows.saturating_mul(rows).saturating_add(rows.saturating_mul(n)) > limit
            })
            .collect();
        let factored = factored_parts(&jac, flex, map, &factored_clusters, &mut diagonal);
        let bodies = BodyPart::new(&jac, blocks, &mut diagonal);
        let outside: Vec<bool> = body.iter().zip(&factored_clusters).map(|(a, b)| *a || *b).collect();
        scratch.places(&jac, map, &outside);
        scratch.columns(&jac, flex);
        let explicit = scratch.csr(&jac);
        let ptr = explicit.indptr();
        let rows: Vec<usize> = (0..jac.rows).filter(|&r| !ptr.outer_inds(r).is_empty()).collect();
        for &r in &rows {
            diagonal[r] += explicit.get(r, r).copied().unwrap_or(0.0);
        }
        let explicit_rows = (2 * rows.len() < jac.rows).then_some(rows);
        ContactOperator { jac, explicit, explicit_rows, factored, bodies, diagonal }
    }

    /// B, as the rows built it.
    pub fn jacobian(&self) -> &Jacobian {
        &self.jac
    }

    /// B, for its storage to be reused (its frames' too).
    pub fn into_jacobian(self) -> Jacobian {
        self.jac
    }

    /// out = K̃⁻¹ Bᵀ z on the body form's bodies (out's other entries untouched) when every row
    /// of B is on them, with the sums of `Jacobian::transpose_apply` and the flexibility's
    /// solves below the body form's halves (`bodies.rs`); `false` (out untouched) otherwise.
    pub fn response(&self, z: &[f64], out: &mut [f64]) -> bool {
        self.bodies.response(&self.jac, z, out)
    }

    /// The largest entry of diag(W) (0 for no rows).
    pub fn largest_diagonal(&self) -> f64 {
        self.diagonal.iter().fold(0.0f64, |m, x| m.max(*x))
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
        // (with no explicit part the body form clears `out` itself, in its halves, on both
        // cores)
        let explicit = self.explicit.nnz() > 0;
        match &self.explicit_rows {
            _ if !explicit => {}
            // the other rows cleared, each listed row's sum as the CSR product sums it
            Some(rows) => {
                out.fill(0.0);
                for &r in rows {
                    let row = self.explicit.outer_view(r).expect("a row of W");
                    out[r] = row.iter().map(|(j, &v)| v * z[j]).sum();
                }
            }
            None => self.explicit.apply(z, out),
        }
        self.bodies.apply(&self.jac, z, out, !explicit);
        let mut t = Vec::with_capacity(self.factored.iter().map(|f| f.n).max().unwrap_or(0));
        for f in &self.factored {
            t.clear();
            t.resize(f.n, 0.0);
            f.segments.transpose_apply(z, |_| true, &mut t);
            f.solver.solve(&mut t);
            for s in f.segments.segments() {
                out[s.row()] += f.segments.dot(s, &t);
            }
        }
    }

    fn diagonal(&self, out: &mut [f64]) {
        out.copy_from_slice(&self.diagonal);
    }

    fn as_csr(&self) -> Option<CsrView<'_>> {
        (self.factored.is_empty() && self.bodies.is_empty()).then(|| self.explicit.view())
    }

    /// Gershgorin's rows for the explicit part, the bodies' eigenvalue bounds for the body form
    /// (`BodyPart::row_bounds`); not with factored clusters (their entries are not at hand).
    fn row_bounds(&self, sc: &[f64], out: &mut [f64]) -> bool {
        if !self.factored.is_empty() || !self.explicit.row_bounds(sc, out) {
            return false;
        }
        self.bodies.row_bounds(&self.jac, sc, out);
        true
    }

    fn has_entries(&self) -> bool {
        self.factored.is_empty()
    }

    /// Not with factored clusters (their entries would take a solve per row).
    fn entries(&self, keep: &[bool], out: &mut Vec<(usize, usize, f64)>) -> bool {
        if !self.factored.is_empty() || !self.explicit.entries(keep, out) {
            return false;
        }
        self.bodies.entries(&self.jac, keep, out);
        true
    }
}

/// Rows of B touching each cluster (a row with two segments on one cluster counts twice: an
/// upper bound is enough for the switch).
fn cluster_row_counts(jac: &Jacobian, map: &DofMap) -> Vec<usize> {
    let mut counts = vec![0usize; map.clusters()];
    for s in jac.own_segments() {
        counts[s.cluster()] += 1;
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
                segments: Jacobian::with_rows(jac.rows),
            })
        })
        .collect();
    for s in jac.own_segments().iter().filter(|s| factored[s.cluster()]) {
        let base = map.cluster_range(s.cluster()).start;
        if let Some(part) = &mut parts[s.cluster()] {
            part.segments.push_slice(s.row(), s.cluster(), s.start() - base, jac.vals(s));
        }
    }
    let mut parts: Vec<FactoredCluster> = parts.into_iter().flatten().collect();
    for part in &mut parts {
        part.segments.sort_by_row();
    }
    for part in &parts {
        // W_rr = B_r|c · K̃_c⁻¹ B_rᵀ|c, one solve per row (its segments are consecutive)
        let (b, segments) = (&part.segments, part.segments.segments());
        let mut k = 0;
        while k < segments.len() {
            let row = segments[k].row();
            let end = k + segments[k..].iter().take_while(|s| s.row() == row).count();
            let mut col = vec![0.0; part.n];
            for s in &segments[k..end] {
                col[s.dofs()].iter_mut().zip(b.vals(s)).for_each(|(x, v)| *x += v);
            }
            part.solver.solve(&mut col);
            diagonal[row] += segments[k..end].iter().map(|s| b.dot(s, &col)).sum::<f64>();
            k = end;
        }
    }
    parts
}

impl Scratch {
    /// The DOFs each sparse cluster's rows touch (S), the columns' lengths and each segment's
    /// place in them. A segment's DOFs are consecutive in S too (S holds all of them, sorted).
    fn layout(&mut self, jac: &Jacobian, flex: &Flexibility, map: &DofMap) {
        let clusters = map.clusters();
        // (the sets of the last call's touched clusters cleared, and this call's sorted: not
        // every cluster's, 10,000 of them on a pile with a few bolted clusters)
        self.sets.resize_with(clusters, Vec::new);
        for &c in &self.touched {
            if let Some(set) = self.sets.get_mut(c) {
                set.clear();
            }
        }
        self.touched.clear();
        let local = |s: &Segment| s.start() - map.cluster_range(s.cluster()).start;
        for s in jac.own_segments().iter().filter(|s| flex.is_sparse(s.cluster())) {
            let set = &mut self.sets[s.cluster()];
            if set.is_empty() {
                self.touched.push(s.cluster());
            }
            set.extend(local(s)..local(s) + s.width());
        }
        for &c in &self.touched {
            self.sets[c].sort_unstable();
            self.sets[c].dedup();
        }
        self.col_len.clear();
        self.col_len.extend(
            (0..clusters)
                .map(|c| if flex.is_sparse(c) { self.sets[c].len() } else { map.cluster_range(c).len() }),
        );
        self.seg_at.clear();
        for s in jac.own_segments() {
            let set = &self.sets[s.cluster()];
            self.seg_at.push(if flex.is_sparse(s.cluster()) {
                set.partition_point(|&d| d < local(s))
            } else {
                local(s)
            });
        }
    }

    /// Sorts the explicit segments by cluster and row (counting sort, then a stable sort of
    /// each cluster's few segments) and lists the places.
    fn places(&mut self, jac: &Jacobian, map: &DofMap, factored: &[bool]) {
        let clusters = map.clusters();
        let start = &mut self.cluster_start;
        start.clear();
        start.resize(clusters + 1, 0);
        for s in jac.own_segments().iter().filter(|s| !factored[s.cluster()]) {
            start[s.cluster() + 1] += 1;
        }
        for c in 0..clusters {
            start[c + 1] += start[c];
        }
        self.order.clear();
        self.order.resize(start[clusters], 0);
        let mut next = start[..clusters].to_vec();
        for (si, s) in jac.own_segments().iter().enumerate().filter(|(_, s)| !factored[s.cluster()]) {
            self.order[next[s.cluster()]] = si;
            next[s.cluster()] += 1;
        }
        self.place_row.clear();
        self.place_seg.clear();
        self.place_cluster.clear();
        self.cluster_place.clear();
        for c in 0..clusters {
            let part = &mut self.order[start[c]..start[c + 1]];
            part.sort_by_key(|&si| jac.own_segments()[si].row());
            self.cluster_place.push(self.place_row.len());
            for (k, &si) in part.iter().enumerate() {
                let row = jac.own_segments()[si].row();
                if k == 0 || self.place_row.last() != Some(&row) {
                    self.place_row.push(row);
                    self.place_seg.push(start[c] + k);
                    self.place_cluster.push(c);
                }
            }
        }
        self.cluster_place.push(self.place_row.len());
        self.place_seg.push(self.order.len());
        self.terms(jac);
    }

    /// Each place's row B_r|c flattened to (position in the cluster's columns, value) pairs,
    /// segment by segment in `order`: what [`Self::entry`] dots with a column.
    fn terms(&mut self, jac: &Jacobian) {
        self.place_term.clear();
        self.term_at.clear();
        self.term_val.clear();
        for p in 0..self.place_row.len() {
            self.place_term.push(self.term_at.len());
            for &si in &self.order[self.place_seg[p]..self.place_seg[p + 1]] {
                let (s, at) = (&jac.own_segments()[si], self.seg_at[si]);
                self.term_at.extend(at..at + s.width());
                self.term_val.extend_from_slice(jac.vals(s));
            }
        }
        self.place_term.push(self.term_at.len());
    }

    /// Each place's column K̃_c⁻¹ B_rᵀ|c: over the cluster's DOF range by one solve for a single
    /// body; for a sparse cluster over its set S only, from the cached block (K̃_c⁻¹)_SS (math
    /// note §9.3), since W reads the columns nowhere else.
    fn columns(&mut self, jac: &Jacobian, flex: &Flexibility) {
        self.place_col.clear();
        let mut total = 0;
        for &c in &self.place_cluster {
            self.place_col.push(total);
            total += self.col_len[c];
        }
        self.columns.clear();
        self.columns.resize(total, 0.0);
        let mut block: Option<(usize, Vec<f64>)> = None; // places come cluster by cluster
        for (p, &c) in self.place_cluster.iter().enumerate() {
            let len = self.col_len[c];
            let col = &mut self.columns[self.place_col[p]..self.place_col[p] + len];
            let segments = &self.order[self.place_seg[p]..self.place_seg[p + 1]];
            if block.as_ref().is_none_or(|b| b.0 != c) {
                block = flex.inverse_block(c, &self.sets[c]).map(|g| (c, g));
            }
            for &si in segments {
                let (s, at) = (&jac.own_segments()[si], self.seg_at[si]);
                for (i, &v) in jac.vals(s).iter().enumerate().filter(|(_, v)| **v != 0.0) {
                    match &block {
                        Some((_, g)) => {
                            let g = &g[(at + i) * len..(at + i + 1) * len];
                            col.iter_mut().zip(g).for_each(|(x, gi)| *x += v * gi);
                        }
                        None => col[at + i] += v,
                    }
                }
            }
            if block.is_none() {
                flex.solve_cluster(c, col);
            }
        }
    }

    /// B_r|c · K̃_c⁻¹ B_sᵀ|c for place p = (c, r) and place q = (c, s) of the same cluster.
    fn entry(&self, p: usize, q: usize) -> f64 {
        let col = &self.columns[self.place_col[q]..];
        let terms = self.place_term[p]..self.place_term[p + 1];
        self.term_at[terms.clone()].iter().zip(&self.term_val[terms]).map(|(&at, v)| v * col[at]).sum()
    }

    /// W's explicit part: row r gets, for every place (c, r), B_r|c · K̃_c⁻¹ B_sᵀ|c for every
    /// row s touching c; entries of a column reached through two clusters are summed, in
    /// cluster order.
    fn csr(&mut self, jac: &Jacobian) -> Csr {
        let starts = &mut self.row_place_start;
        starts.clear();
        starts.resize(jac.rows + 1, 0);
        for &r in &self.place_row {
            starts[r + 1] += 1;
        }
        for r in 0..jac.rows {
            starts[r + 1] += starts[r];
        }
        self.row_places.clear();
        self.row_places.resize(self.place_row.len(), 0);
        let mut next = starts[..jac.rows].to_vec();
        for (p, &r) in self.place_row.iter().enumerate() {
            self.row_places[next[r]] = p; // places ascend by cluster
            next[r] += 1;
        }
        // at most one entry per (place, place of its cluster): no regrowth of the arrays
        let bound: usize =
            self.place_cluster.iter().map(|&c| self.cluster_place[c + 1] - self.cluster_place[c]).sum();
        let mut indptr = Vec::with_capacity(jac.rows + 1);
        let (mut indices, mut data) = (Vec::with_capacity(bound), Vec::with_capacity(bound));
        indptr.push(0);
        for r in 0..jac.rows {
            // Row r merges, by column, the rows of the clusters it touches: each cluster's
            // places ascend by row, so a k-way merge (k = the row's places, ascending by
            // cluster) gives the columns in order, and a column reached through two clusters
            // is summed in cluster order. No sort, no allocation.
            let places = self.row_place_start[r]..self.row_place_start[r + 1];
            if places.is_empty() {
                indptr.push(indices.len()); // a row on body-form or factored clusters only
                continue;
            }
            self.cursors.clear();
            for &p in &self.row_places[places] {
                let c = self.place_cluster[p];
                self.cursors.push((p, self.cluster_place[c], self.cluster_place[c + 1]));
            }
            loop {
                let next = self.cursors.iter().filter(|k| k.1 < k.2).map(|k| self.place_row[k.1]).min();
                let Some(col) = next else { break };
                let mut v = 0.0;
                for k in 0..self.cursors.len() {
                    let (p, q, end) = self.cursors[k];
                    if q < end && self.place_row[q] == col {
                        v += self.entry(p, q);
                        self.cursors[k].1 += 1;
                    }
                }
                indices.push(col);
                data.push(v);
            }
            indptr.push(indices.len());
        }
        Csr::new((jac.rows, jac.rows), indptr, indices, data)
    }
}
