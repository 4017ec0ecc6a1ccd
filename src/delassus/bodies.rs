//! W's part over single-body clusters in *body form* (math note §3.3): never assembled, applied
//! through the bodies instead. `W z` adds `B_c K̃_c⁻¹ B_cᵀ z` for every such cluster c by
//! accumulating each body's generalized force `u_c = Σ_r B_r|cᵀ z_r` over its rows, one closed-form
//! product `v_c = K̃_c⁻¹ u_c` over the body's n_c DOFs, and each row's `B_r|c · v_c`: about
//! 2 n_c multiply-adds per row and body plus n_c² per body, against the ~20 nonzeros per row of
//! an assembled W on a pile of disks, and no assembly at all. The diagonal is formed exactly
//! (each row's segments on one body paired), and so is a bound of |W| per body for Gershgorin's
//! bound.

use crate::cluster::Flexibility;
use crate::dofs::DofMap;
use crate::jacobian::Jacobian;
use std::sync::Mutex;

/// One segment of B on a body-form cluster.
#[derive(Debug, Clone)]
struct Seg {
    row: usize,
    /// Its body (compact index).
    body: usize,
    /// Its first DOF in the compact body vectors (the body's offset + the local DOF).
    at: usize,
    /// Its range of `vals`.
    val: usize,
    len: usize,
}

/// The body-form clusters' part of W (see the module docs).
#[derive(Debug, Default)]
pub(super) struct BodyPart {
    /// Segments in push order (which fixes every sum's order); their values in `vals`.
    segs: Vec<Seg>,
    vals: Vec<f64>,
    /// Per body (compact order): its first DOF in the compact vectors (`bodies + 1` offsets),
    /// and its K̃_c⁻¹ (n_c × n_c, column-major) from `kinv[kinv_at[b]..]`.
    offset: Vec<usize>,
    kinv_at: Vec<usize>,
    kinv: Vec<f64>,
    /// The segments body by body (`body_start` has `bodies + 1` offsets into `by_body`).
    by_body: Vec<usize>,
    body_start: Vec<usize>,
    /// Work storage of the products.
    work: Mutex<Vec<f64>>,
}

impl BodyPart {
    /// The part over the clusters with `body[c]` (each a single body with a closed-form K̃⁻¹),
    /// adding its share of diag(W) to `diagonal`.
    pub fn new(
        jac: &Jacobian,
        flex: &Flexibility,
        map: &DofMap,
        body: &[bool],
        diagonal: &mut [f64],
    ) -> Self {
        let mut part = BodyPart { offset: vec![0], ..Default::default() };
        let mut compact = vec![usize::MAX; body.len()];
        for (c, _) in body.iter().enumerate().filter(|(_, b)| **b) {
            if let Some(k) = flex.body_inverse(c) {
                let n = map.cluster_range(c).len();
                compact[c] = part.kinv_at.len();
                part.kinv_at.push(part.kinv.len());
                part.kinv.extend((0..n).flat_map(|j| (0..n).map(move |i| k[(i, j)])));
                part.offset.push(part.offset[compact[c]] + n);
            }
        }
        for s in jac.segments.iter().filter(|s| compact[s.cluster] != usize::MAX) {
            let b = compact[s.cluster];
            let at = part.offset[b] + (s.start - map.cluster_range(s.cluster).start);
            part.segs.push(Seg { row: s.row, body: b, at, val: part.vals.len(), len: s.len });
            part.vals.extend_from_slice(&s.vals.as_slice()[..s.len]);
        }
        (part.by_body, part.body_start) = group(part.segs.iter().map(|s| s.body), part.kinv_at.len());
        part.add_diagonal(jac.rows, diagonal);
        part
    }

    pub fn is_empty(&self) -> bool {
        self.segs.is_empty()
    }

    fn vals(&self, s: &Seg) -> &[f64] {
        &self.vals[s.val..s.val + s.len]
    }

    /// out[..n_b] = K̃_b⁻¹ u[..n_b].
    fn solve(&self, b: usize, u: &[f64], out: &mut [f64]) {
        let n = self.offset[b + 1] - self.offset[b];
        let k = &self.kinv[self.kinv_at[b]..self.kinv_at[b] + n * n];
        // the common sizes with their loops unrolled (rigid bodies 3, deformable 4 and 6)
        match n {
            3 => solve_n::<3>(k, u, out),
            4 => solve_n::<4>(k, u, out),
            6 => solve_n::<6>(k, u, out),
            _ => {
                out[..n].fill(0.0);
                for (j, &uj) in u[..n].iter().enumerate() {
                    for (o, kij) in out[..n].iter_mut().zip(&k[j * n..(j + 1) * n]) {
                        *o += kij * uj;
                    }
                }
            }
        }
    }

    /// K̃_b⁻¹ sᵀ of segment s over its body's DOFs (into `out[..n_b]`).
    fn column(&self, s: &Seg, u: &mut [f64], out: &mut [f64]) {
        let n = self.offset[s.body + 1] - self.offset[s.body];
        u[..n].fill(0.0);
        let local = s.at - self.offset[s.body];
        u[local..local + s.len].copy_from_slice(self.vals(s));
        self.solve(s.body, u, out);
    }

    /// s · v over the segment's DOFs, v a body-local vector.
    fn dot(&self, s: &Seg, v: &[f64]) -> f64 {
        let local = s.at - self.offset[s.body];
        self.vals(s).iter().zip(&v[local..local + s.len]).map(|(a, b)| a * b).sum()
    }

    /// W_rr += Σ over pairs (s, t) of row r's segments on one body of s K̃⁻¹ tᵀ.
    fn add_diagonal(&self, rows: usize, diagonal: &mut [f64]) {
        let (by_row, start) = group(self.segs.iter().map(|s| s.row), rows);
        let (mut u, mut x) = ([0.0; crate::body::MAX_DOF], [0.0; crate::body::MAX_DOF]);
        for r in 0..rows {
            let mine = &by_row[start[r]..start[r + 1]];
            for &i in mine {
                let s = &self.segs[i];
                self.column(s, &mut u, &mut x);
                for t in mine.iter().map(|&j| &self.segs[j]).filter(|t| t.body == s.body) {
                    diagonal[r] += self.dot(t, &x);
                }
            }
        }
    }

    /// out += W_bodies z.
    pub fn apply(&self, z: &[f64], out: &mut [f64]) {
        let n = self.offset[self.offset.len() - 1];
        let mut guard = self.work.lock().unwrap_or_else(|e| e.into_inner());
        let work = &mut *guard;
        work.clear();
        work.resize(2 * n, 0.0);
        let (u, v) = work.split_at_mut(n);
        for s in &self.segs {
            let zr = z[s.row];
            for (ui, a) in u[s.at..s.at + s.len].iter_mut().zip(self.vals(s)) {
                *ui += a * zr;
            }
        }
        for b in 0..self.kinv_at.len() {
            let r = self.offset[b]..self.offset[b + 1];
            self.solve(b, &u[r.clone()], &mut v[r]);
        }
        for s in &self.segs {
            out[s.row] += self.vals(s).iter().zip(&v[s.at..s.at + s.len]).map(|(a, b)| a * b).sum::<f64>();
        }
    }

    /// Pushes `(r, s, s_r K̃_c⁻¹ t_sᵀ)` for every pair of segments (s_r, t_s) on one body whose
    /// rows are both kept: W_bodies entry by entry, duplicates to be summed.
    pub fn entries(&self, keep: &[bool], out: &mut Vec<(usize, usize, f64)>) {
        let (mut u, mut x) = ([0.0; crate::body::MAX_DOF], [0.0; crate::body::MAX_DOF]);
        for b in 0..self.kinv_at.len() {
            let mine = &self.by_body[self.body_start[b]..self.body_start[b + 1]];
            for s in mine.iter().map(|&i| &self.segs[i]).filter(|s| keep[s.row]) {
                self.column(s, &mut u, &mut x);
                for t in mine.iter().map(|&j| &self.segs[j]).filter(|t| keep[t.row]) {
                    out.push((t.row, s.row, self.dot(t, &x)));
                }
            }
        }
    }

    /// out += M x with M = Σ_c Σ_{segments s, t on c} |s K̃_c⁻¹ tᵀ| (rows of s, t) >= |W_bodies|
    /// entrywise: the absolute values are taken per pair of segments, so for disks (one
    /// segment per row and body) M_rs differs from |W_rs| only where rows r and s share both
    /// bodies, and then by the triangle inequality. Costs Σ_c m_c² short dot products, m_c
    /// the segments on body c.
    pub fn abs_apply(&self, x: &[f64], out: &mut [f64]) {
        const M: usize = crate::body::MAX_DOF;
        let mut guard = self.work.lock().unwrap_or_else(|e| e.into_inner());
        let work = &mut *guard;
        for b in 0..self.kinv_at.len() {
            let mine = &self.by_body[self.body_start[b]..self.body_start[b + 1]];
            let (m, n) = (mine.len(), self.offset[b + 1] - self.offset[b]);
            // rows: the segments padded to the body's DOFs; cols: K̃⁻¹ of each; xs: x at their rows
            work.clear();
            work.resize(2 * m * M + m, 0.0);
            let (rows, rest) = work.split_at_mut(m * M);
            let (cols, xs) = rest.split_at_mut(m * M);
            for (j, &t) in mine.iter().enumerate() {
                let seg = &self.segs[t];
                let local = seg.at - self.offset[b];
                rows[j * M + local..j * M + local + seg.len].copy_from_slice(self.vals(seg));
                self.solve(b, &rows[j * M..j * M + n], &mut cols[j * M..j * M + n]);
                xs[j] = x[seg.row];
            }
            for (i, &s) in mine.iter().enumerate() {
                let r = &rows[i * M..i * M + n];
                let mut acc = 0.0;
                for (c, xj) in cols.chunks_exact(M).zip(xs.iter()) {
                    let w: f64 = r.iter().zip(&c[..n]).map(|(a, b)| a * b).sum();
                    acc += w.abs() * xj;
                }
                out[self.segs[s].row] += acc;
            }
        }
    }
}

/// out[..N] = K u[..N], K column-major N × N (the same sums as the general loop).
#[inline(always)]
fn solve_n<const N: usize>(k: &[f64], u: &[f64], out: &mut [f64]) {
    let (k, u): (&[f64], &[f64]) = (&k[..N * N], &u[..N]);
    let mut o = [0.0; N];
    for j in 0..N {
        for i in 0..N {
            o[i] += k[j * N + i] * u[j];
        }
    }
    out[..N].copy_from_slice(&o);
}

/// Indices 0..n grouped by key (keys < `groups`), each group in index order (a counting
/// sort): the order and `groups + 1` offsets into it.
fn group(keys: impl Iterator<Item = usize> + Clone, groups: usize) -> (Vec<usize>, Vec<usize>) {
    let mut start = vec![0usize; groups + 1];
    for k in keys.clone() {
        start[k + 1] += 1;
    }
    for g in 0..groups {
        start[g + 1] += start[g];
    }
    let mut order = vec![0usize; start[groups]];
    let mut next = start[..groups].to_vec();
    for (i, k) in keys.enumerate() {
        order[next[k]] = i;
        next[k] += 1;
    }
    (order, start)
}
