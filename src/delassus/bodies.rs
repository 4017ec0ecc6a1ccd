//! W's part over the closed-form clusters in *body form* (math note §3.3): never assembled,
//! applied through the bodies instead. Such a cluster is a single body, or bodies joined by
//! connectors with at most 48 DOFs between them (math note §6); "body" below means either. `W z` adds `B_c K̃_c⁻¹ B_cᵀ z` for every such cluster c by
//! accumulating each body's generalized force `u_c = Σ_r B_r|cᵀ z_r` over its rows, one closed-form
//! product `v_c = K̃_c⁻¹ u_c` over the body's n_c DOFs, and each row's `B_r|c · v_c`: about
//! 2 n_c multiply-adds per row and body plus n_c² per body, against the ~20 nonzeros per row of
//! an assembled W on a pile of disks, and no assembly at all. The diagonal is formed exactly
//! (the segments of a row on one body paired), and the bound of ‖Ŵ‖ that MPRGP's step length
//! needs comes per body from an n_c × n_c matrix ([`BodyPart::row_bounds`]), not from W's
//! entries.
//!
//! The products keep B's own entries (the segments as pushed) and K̃_c⁻¹, not B_c R_c with a
//! square root R_c R_cᵀ = K̃_c⁻¹, which would spare the per-body product: on the heavy-on-light
//! stack of 1e12 (`tests/paper/mass_ratio.rs`) the irrational entries of B R add rounding to the
//! cancelling contact forces of the light block, and two of its steps do not converge.

use super::blocks::{Blocks, NONE};
use super::cut::{Cut, cut_of};
use super::frames::{self, Half};
use crate::body::MAX_DOF;
use crate::cluster::{DENSE_MAX, block_times};
use crate::jacobian::{Frame, Jacobian, Piece, Segment, dot, dot_n, range_n, range_n_mut};
use std::ops::Range;
use std::sync::{Arc, Mutex};

/// From this many segments on, a product over a scene of single bodies runs in two halves on
/// both cores ([`BodyPart::apply`], [`BodyPart::response`]). The 1,000-disk pile has about
/// 12,000 segments, which stay in one core's cache; the 10,000-disk pile about 120,000, whose
/// 5 MB do not (`benches/vi.rs`, group `body_form_product`, times one thread against two).
const HALVES_FROM: usize = 40_000;

/// The body-form clusters' part of W (see the module docs). Its products run over the
/// operator's own Jacobian (passed in): over B's contact frames (`jacobian::Frame`, a third of
/// the bytes of their segments, the same sums) and its segments on body-form clusters, in push
/// order, which fixes every sum's order; its body vectors are indexed by global DOF, so a
/// segment's DOFs are its own (math note §3.3). Every frame's bodies must be rigid bodies in
/// body form (`ContactOperator::with_scratch` turns the frames into segments otherwise).
#[derive(Debug, Default)]
pub(super) struct BodyPart {
    /// The bodies' ranges and blocks, shared with the scratch that keeps them across steps.
    blocks: Arc<Blocks>,
    /// How many of B's segments (the frames' included) are on body-form clusters.
    count: usize,
    /// Where B splits into two halves whose rows do not overlap, at about half of it; `None`
    /// when it does not split so.
    split: Option<Cut>,
    /// When a cluster joins several bodies: per segment of B's own, the last one before it of its
    /// row on its cluster, or `NONE` ([`Self::same_row_before`]); the diagonal and the row
    /// bounds pair a row's segments on one cluster through it.
    before: Option<Vec<u32>>,
    /// Work storage of the products.
    work: Mutex<Vec<f64>>,
}

impl BodyPart {
    /// The part over the bodies of `blocks`, adding its share of diag(W) to `diagonal`: from
    /// [`HALVES_FROM`] segments on, over the products' two halves (`split`), one per core, when
    /// B has them (their rows are apart, so each half adds to its own rows).
    pub fn new(jac: &Jacobian, blocks: Arc<Blocks>, diagonal: &mut [f64]) -> Self {
        debug_assert!(jac.frame_clusters().iter().flatten().all(|&c| blocks.rigid[c as usize] != NONE));
        let mut part = BodyPart { blocks, ..Default::default() };
        part.before = part.blocks.joined.iter().any(|&j| j).then(|| part.same_row_before(jac));
        part.split = if jac.len() >= HALVES_FROM { cut_of(jac) } else { None };
        part.count = match part.split {
            None => part.half_diagonal(jac, 0, diagonal, 0),
            Some(cut) => {
                let (d1, d2) = diagonal.split_at_mut(cut.row);
                let part = &part;
                let (c1, c2) = micropool::join(
                    || part.half_diagonal(jac, 0, d1, 0),
                    || part.half_diagonal(jac, 1, d2, cut.row),
                );
                c1 + c2
            }
        };
        part
    }

    /// Half `half` of B's share of diag(W), into `diagonal` (whose rows start at row `row0`),
    /// over its segments ([`Self::add_diagonal`]) and its frames (each body's K̃⁻¹ found by its
    /// first DOF when the blocks are `dense`, else by its cluster); the number of its segments
    /// on body-form clusters.
    fn half_diagonal(&self, jac: &Jacobian, half: usize, diagonal: &mut [f64], row0: usize) -> usize {
        let Half { frames, segs } = self.half(jac, half);
        let mut count = self.add_diagonal(jac, segs, diagonal, row0);
        let Blocks { rigid, kinv, dense, .. } = &*self.blocks;
        for (f, c) in jac.frames()[frames.clone()].iter().zip(&jac.frame_clusters()[frames]) {
            let at = match dense {
                true => [f.a, f.b].map(|a| 3 * a as usize),
                false => c.map(|c| rigid[c as usize] as usize),
            };
            frames::add_diagonal(f, at, kinv, diagonal, row0);
            count += f.segments();
        }
        count
    }

    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// Whether segment s is on a body-form cluster.
    fn on_body(&self, s: &Segment) -> bool {
        self.blocks.compact[s.cluster()] != NONE
    }

    /// Segment s's body.
    fn body(&self, s: &Segment) -> usize {
        self.blocks.compact[s.cluster()] as usize
    }

    /// out[..n_b] = K̃_b⁻¹ u[..n_b].
    fn solve(&self, b: usize, u: &[f64], out: &mut [f64]) {
        let Blocks { n, kinv, square, .. } = &*self.blocks;
        let n = n[b];
        let k = &kinv[square[b]..square[b] + n * n];
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

    /// Segment s's first DOF within its body.
    fn local(&self, s: &Segment) -> usize {
        s.start() - self.blocks.start[self.body(s)]
    }

    /// K̃_b⁻¹ sᵀ of segment s over its body's DOFs (into `out[..n_b]`). Over the segment's own
    /// columns of K̃_b⁻¹ on a cluster of more than 6 DOFs (n_b · width multiply-adds, not n_b²:
    /// the other columns' products with sᵀ's zeros add nothing); through [`Self::solve`], which
    /// unrolls a body's 3, 4 or 6, otherwise.
    fn column(&self, jac: &Jacobian, s: &Segment, u: &mut [f64], out: &mut [f64]) {
        let (b, local) = (self.body(s), self.local(s));
        let n = self.blocks.n[b];
        if n > MAX_DOF {
            let Blocks { kinv, square, .. } = &*self.blocks;
            let k = &kinv[square[b] + local * n..square[b] + (local + s.width()) * n];
            out[..n].fill(0.0);
            for (column, &v) in k.chunks_exact(n).zip(jac.vals(s)) {
                out[..n].iter_mut().zip(column).for_each(|(o, kij)| *o += kij * v);
            }
            return;
        }
        u[..n].fill(0.0);
        u[local..local + s.width()].copy_from_slice(jac.vals(s));
        self.solve(b, u, out);
    }

    /// s · v over the segment's DOFs, v a body-local vector.
    fn dot(&self, jac: &Jacobian, s: &Segment, v: &[f64]) -> f64 {
        let local = self.local(s);
        dot(jac.vals(s), &v[local..local + s.width()])
    }

    /// W_rr += Σ_c (Σ_{s of row r on c} s) K̃_c⁻¹ (Σ_s s)ᵀ over B's own segments `segs` (not its
    /// frames': `Jacobian::own_segments`), whose rows are those of `diagonal`, which starts at
    /// row `row0`: each segment's s K̃⁻¹ sᵀ, plus twice its products with the earlier segments of
    /// its row on its cluster (`before`; only a cluster joining several bodies has them, since a
    /// contact joins two bodies). A rigid body's segment (3 DOFs, the whole body) has its K̃⁻¹
    /// found by one load (`Blocks::rigid`). Returns the number of those segments on body-form
    /// clusters.
    fn add_diagonal(&self, jac: &Jacobian, segs: Range<usize>, diagonal: &mut [f64], row0: usize) -> usize {
        let Blocks { rigid, kinv, .. } = &*self.blocks;
        let all = jac.own_segments();
        let (mut u, mut x) = ([0.0; DENSE_MAX], [0.0; DENSE_MAX]);
        let mut count = 0;
        for i in segs {
            let s = &all[i];
            let k = rigid[s.cluster()];
            if k != NONE && s.width() == 3 {
                // unrolled, over arrays (one bounds check each)
                let v = jac.vals_n::<3>(s);
                solve_n::<3>(range_n::<9>(kinv, k as usize), v, &mut x);
                diagonal[s.row() - row0] += dot_n::<3>(v, &x);
                count += 1;
                continue;
            }
            if !self.on_body(s) {
                continue;
            }
            count += 1;
            self.column(jac, s, &mut u, &mut x);
            let mut d = self.dot(jac, s, &x);
            if let Some(before) = &self.before {
                let mut j = before[i];
                while j != NONE {
                    d += 2.0 * self.dot(jac, &all[j as usize], &x);
                    j = before[j as usize];
                }
            }
            diagonal[s.row() - row0] += d;
        }
        count
    }

    /// Whether every segment of B is on a body (a scene of single bodies).
    fn whole(&self, jac: &Jacobian) -> bool {
        self.count == jac.len()
    }

    /// Half `half` (0 or 1) of B over the halves of `split`; without a split, half 0 is all of
    /// B and half 1 nothing.
    fn half(&self, jac: &Jacobian, half: usize) -> Half {
        let all = Half::all(jac);
        match (self.split, half) {
            (None, 0) => all,
            (None, _) => Half { frames: 0..0, segs: 0..0 },
            (Some(cut), 0) => Half { frames: 0..cut.frames, segs: 0..cut.segs },
            (Some(cut), _) => Half { frames: cut.frames..all.frames.end, segs: cut.segs..all.segs.end },
        }
    }

    /// out += W_bodies z, or out = W_bodies z with `clear`: v = K̃⁻¹ Bᵀ z over the bodies
    /// ([`Self::respond`]), then each row's B v, over the two halves of `split` (each core
    /// clearing and summing into its own rows) when B has them.
    pub fn apply(&self, jac: &Jacobian, z: &[f64], out: &mut [f64], clear: bool) {
        // a scene of single bodies: no filter, which would cost each product a load per segment
        let whole = self.whole(jac);
        let mut guard = self.work.lock().unwrap_or_else(|e| e.into_inner());
        let n = self.blocks.dofs;
        guard.resize(3 * n, 0.0);
        let (u, v) = guard.split_at_mut(2 * n);
        self.respond(jac, whole, z, u, v);
        let v = &*v;
        if let Some(cut) = self.split.filter(|_| whole) {
            let (o1, o2) = out.split_at_mut(cut.row);
            let read = |half: usize, out: &mut [f64], offset| {
                if clear {
                    out.fill(0.0);
                }
                self.half(jac, half).gather(jac, |_| true, v, out, offset);
            };
            micropool::join(|| read(0, o1, 0), || read(1, o2, cut.row));
            return;
        }
        if clear {
            out.fill(0.0);
        }
        let all = Half::all(jac);
        match whole {
            true => all.gather(jac, |_| true, v, out, 0),
            false => all.gather(jac, |s| self.on_body(s), v, out, 0),
        }
    }

    /// out = K̃⁻¹ Bᵀ z on the bodies' DOFs (out's other entries untouched) when every segment of
    /// B is on a body, over the two halves of `split` when it has them; `false` (out untouched)
    /// otherwise. The sums of B's transpose product and the flexibility's body solves without
    /// halves (`Jacobian::transpose_apply`, `Flexibility::solve_in_place`); with them, a body
    /// with segments in both halves adds its two partial sums.
    pub fn response(&self, jac: &Jacobian, z: &[f64], out: &mut [f64]) -> bool {
        if !self.whole(jac) {
            return false;
        }
        let mut guard = self.work.lock().unwrap_or_else(|e| e.into_inner());
        guard.resize(2 * self.blocks.dofs, 0.0);
        self.respond(jac, true, z, &mut guard, out);
        true
    }

    /// v = K̃⁻¹ Bᵀ z on every body (v's other entries untouched) over B's frames and its segments
    /// on the bodies (`whole` when they are all of B's, so that every DOF is a body's), with `u`
    /// (twice the bodies' DOFs) for Bᵀ z. For a whole scene in two halves of B whose rows do not
    /// overlap (`split`): each half's generalized forces on a core of its own, and half the
    /// bodies' solves on each. Each half sums into its own u, and a body adds the two, so that
    /// no sum depends on the threads that ran it (one thread gives the same bits).
    fn respond(&self, jac: &Jacobian, whole: bool, z: &[f64], u: &mut [f64], v: &mut [f64]) {
        let Blocks { start, n: ns, dofs: n, .. } = &*self.blocks;
        let (u, u2) = u.split_at_mut(*n);
        if self.split.is_some() && whole {
            let sum = |half: usize, u: &mut [f64]| {
                u.fill(0.0);
                self.half(jac, half).scatter(jac, |_| true, z, u);
            };
            micropool::join(|| sum(0, u), || sum(1, u2));
            let (u1, u2) = (&*u, &*u2);
            let half = start.len() / 2;
            let at = start.get(half).copied().unwrap_or(*n);
            let (v1, v2) = v.split_at_mut(at);
            micropool::join(
                || self.solve_sums(0..half, u1, u2, v1, 0),
                || self.solve_sums(half..start.len(), u1, u2, v2, at),
            );
            return;
        }
        // u accumulates and starts at zero over the bodies' DOFs (not over a large mesh's)
        if whole {
            u.fill(0.0);
            Half::all(jac).scatter(jac, |_| true, z, u);
        } else {
            start.iter().zip(ns).for_each(|(&start, &n)| u[start..start + n].fill(0.0));
            Half::all(jac).scatter(jac, |s| self.on_body(s), z, u);
        }
        if self.blocks.all_rigid {
            // the rigid bodies' blocks in turn, without the call and the size test per body
            for (&start, k) in start.iter().zip(self.blocks.kinv.chunks_exact(9)) {
                solve_n::<3>(k, range_n::<3>(u, start), range_n_mut::<3>(v, start));
            }
        } else {
            // a rigid body's block unrolled here too, as in the all-rigid loop
            let Blocks { kinv, square, .. } = &*self.blocks;
            for (b, &start) in start.iter().enumerate() {
                match ns[b] {
                    3 => solve_n::<3>(
                        range_n::<9>(kinv, square[b]),
                        range_n::<3>(u, start),
                        range_n_mut::<3>(v, start),
                    ),
                    n => self.solve(b, &u[start..start + n], &mut v[start..start + n]),
                }
            }
        }
    }

    /// v[start_b - offset..] = K̃_b⁻¹ (u1 + u2)[start_b..] for the bodies b of `bodies`.
    fn solve_sums(
        &self,
        bodies: std::ops::Range<usize>,
        u1: &[f64],
        u2: &[f64],
        v: &mut [f64],
        offset: usize,
    ) {
        let Blocks { start, n: ns, .. } = &*self.blocks;
        let mut x = [0.0; DENSE_MAX];
        for b in bodies {
            let (s, n) = (start[b], ns[b]);
            for i in 0..n {
                x[i] = u1[s + i] + u2[s + i];
            }
            self.solve(b, &x, &mut v[s - offset..s - offset + n]);
        }
    }

    /// Pushes `(r, s, s_r K̃_c⁻¹ t_sᵀ)` for every pair of segments (s_r, t_s) on one body whose
    /// rows are both kept: W_bodies entry by entry, duplicates to be summed.
    pub fn entries(&self, jac: &Jacobian, keep: &[bool], out: &mut Vec<(usize, usize, f64)>) {
        let bodies = self.blocks.n.len();
        let all = jac.segments();
        let mine: Vec<usize> = (0..all.len()).filter(|&i| self.on_body(&all[i])).collect();
        let (order, start) = group(mine.iter().map(|&i| self.body(&all[i])), bodies);
        let (mut u, mut x) = ([0.0; DENSE_MAX], [0.0; DENSE_MAX]);
        for b in 0..bodies {
            let segs = || order[start[b]..start[b + 1]].iter().map(|&k| &all[mine[k]]);
            for s in segs().filter(|s| keep[s.row()]) {
                self.column(jac, s, &mut u, &mut x);
                for t in segs().filter(|t| keep[t.row()]) {
                    out.push((t.row(), s.row(), self.dot(jac, t, &x)));
                }
            }
        }
    }

    /// out_r += Σ_{clusters c of row r} λ_c, with λ_c >= λ_max(M_c), M_c = Σ_{rows r on c}
    /// sc_r² t_r t_rᵀ and t_r = R_cᵀ (Σ_{segments s of row r on c} s)ᵀ (n_c × n_c): then
    /// xᵀ Ŵ_bodies x <= Σ_r out_r x_r² for every x, Ŵ = S W S, S = diag(sc). (Cluster c adds
    /// |Σ_r sc_r x_r t_r|² = |T_cᵀ y|² <= λ_max(T_cᵀ T_c) |y|², T_c's rows sc_r t_rᵀ and y_r = x_r,
    /// and T_cᵀ T_c = M_c.) λ_c is exact for 3 DOFs (rigid bodies) and Gershgorin's bound of M_c
    /// otherwise. Costs about 2 n_c² multiply-adds per segment, where Gershgorin's bound of W
    /// reads W's m_c² entries per cluster.
    ///
    /// A row with two segments on one cluster (a contact between two bodies joined by a bolt)
    /// sums them first: taken one by one, each segment's rigid motion (compliance dt²/2m) would
    /// count against the row's scale, which only their difference sets (the bolt's much smaller
    /// compliance), and the bound would be tens of times ‖Ŵ‖ (`joined_cluster_in_body_form`).
    pub fn row_bounds(&self, jac: &Jacobian, sc: &[f64], out: &mut [f64]) {
        let Blocks { n: ns, square, packed, root, .. } = &*self.blocks;
        let bodies = ns.len();
        let mut guard = self.work.lock().unwrap_or_else(|e| e.into_inner());
        let work = &mut *guard;
        // m accumulates and starts at zero; every body's λ is written below
        work.resize(packed[bodies] + bodies, 0.0);
        let (m, lambda) = work.split_at_mut(packed[bodies]);
        m.fill(0.0);
        // a rigid body's row s: t = Rᵀ s, M += w t tᵀ, unrolled over arrays (cheaper than the
        // general loop below; `benches/vi.rs` measures the warm step)
        let rigid = |m: &mut [f64], b: usize, v: &[f64; 3], w: f64| {
            rigid_term(range_n::<9>(root, square[b]), v, w, range_n_mut::<6>(m, packed[b]))
        };
        // each segment of a frame, with its body (the one whose DOFs start at a is body a / 3
        // when the blocks are `dense`, else its cluster's) and its row's offset in the frame
        let Blocks { dense, compact, .. } = &*self.blocks;
        let frame_segments = |f: &Frame, c: &[u32; 2]| {
            let [a, b] = match dense {
                true => [f.a, f.b].map(|a| a as usize / 3),
                false => c.map(|c| compact[c as usize] as usize),
            };
            [a, a, b, b].into_iter().enumerate().take(f.segments())
        };
        let frames = |r: Range<usize>| jac.frames()[r.clone()].iter().zip(&jac.frame_clusters()[r]);
        let own = jac.own_segments();
        let before = self.before.as_deref();
        // in push order, as the sums of M over the segments made from the frames
        for piece in jac.pieces() {
            match piece {
                Piece::Frames(r) => {
                    for (f, c) in frames(r) {
                        let (r, e) = (f.row(), f.entries());
                        for (k, b) in frame_segments(f, c) {
                            rigid(m, b, &e[k], sc[r + k % 2] * sc[r + k % 2]);
                        }
                    }
                }
                Piece::Segments(r) => self.add_row_terms(jac, r, before, sc, m, rigid),
            }
        }
        for (b, l) in lambda.iter_mut().enumerate() {
            *l = largest_eigenvalue(&m[packed[b]..packed[b + 1]], ns[b]);
        }
        for (f, c) in frames(0..jac.frames().len()) {
            frame_segments(f, c).for_each(|(k, b)| out[f.row() + k % 2] += lambda[b]);
        }
        for (i, s) in own.iter().enumerate().filter(|(_, s)| self.on_body(s)) {
            if before.is_none_or(|b| b[i] == NONE) {
                out[s.row()] += lambda[self.body(s)]; // once per row and cluster
            }
        }
    }

    /// Per segment of B's own, the last one before it of its row on its cluster when that
    /// cluster joins several bodies, else `NONE`: through a chain per row of such segments
    /// (`last` per row, `prev` per segment).
    fn same_row_before(&self, jac: &Jacobian) -> Vec<u32> {
        let own = jac.own_segments();
        let (mut last, mut prev, mut before) =
            (vec![NONE; jac.rows], vec![NONE; own.len()], vec![NONE; own.len()]);
        for (i, s) in own.iter().enumerate() {
            if !self.on_body(s) || !self.blocks.joined[self.body(s)] {
                continue;
            }
            let mut j = last[s.row()];
            while j != NONE && own[j as usize].cluster() != s.cluster() {
                j = prev[j as usize];
            }
            (before[i], prev[i], last[s.row()]) = (j, last[s.row()], i as u32);
        }
        before
    }

    /// `row_bounds`' M_c += w t_s t_sᵀ over B's own segments `segs` on the bodies (`rigid` for a
    /// rigid body's row, unrolled), plus w (t_s t_uᵀ + t_u t_sᵀ) for each earlier segment u of
    /// s's row on its cluster (`before`, [`Self::same_row_before`]): w t_r t_rᵀ for the row's sum.
    fn add_row_terms(
        &self,
        jac: &Jacobian,
        segs: Range<usize>,
        before: Option<&[u32]>,
        sc: &[f64],
        m: &mut [f64],
        rigid: impl Fn(&mut [f64], usize, &[f64; 3], f64),
    ) {
        let Blocks { n: ns, packed, .. } = &*self.blocks;
        let own = jac.own_segments();
        let (mut t, mut u) = ([0.0; DENSE_MAX], [0.0; DENSE_MAX]);
        for i in segs {
            let s = &own[i];
            if !self.on_body(s) {
                continue;
            }
            let (b, w) = (self.body(s), sc[s.row()] * sc[s.row()]);
            let n = ns[b];
            if n == 3 && s.width() == 3 {
                rigid(m, b, jac.vals_n::<3>(s), w);
                continue;
            }
            let mb = &mut m[packed[b]..packed[b + 1]];
            self.root_times(jac, s, &mut t);
            add_outer(mb, w, &t[..n], &t[..n]);
            let Some(before) = before else { continue };
            let mut j = before[i];
            while j != NONE {
                self.root_times(jac, &own[j as usize], &mut u);
                add_outer(mb, w, &t[..n], &u[..n]);
                add_outer(mb, w, &u[..n], &t[..n]);
                j = before[j as usize];
            }
        }
    }

    /// t = R_cᵀ sᵀ over segment s's cluster's n_c DOFs (R column-major).
    fn root_times(&self, jac: &Jacobian, s: &Segment, t: &mut [f64; DENSE_MAX]) {
        let Blocks { n: ns, square, root, .. } = &*self.blocks;
        let (b, local) = (self.body(s), self.local(s));
        let (n, r) = (ns[b], &root[square[b]..]);
        for (j, tj) in t[..n].iter_mut().enumerate() {
            *tj = dot(&r[j * n + local..j * n + local + s.width()], jac.vals(s));
        }
    }
}

/// m += w a bᵀ over the packed lower triangle m (row by row, m_ij at i(i+1)/2 + j).
fn add_outer(m: &mut [f64], w: f64, a: &[f64], b: &[f64]) {
    let mut k = 0;
    for (i, ai) in a.iter().enumerate() {
        let wa = w * ai;
        for (mij, bj) in m[k..k + i + 1].iter_mut().zip(b) {
            *mij += wa * bj;
        }
        k += i + 1;
    }
}

/// m += w t tᵀ with t = Rᵀ v (R column-major 3 × 3, m the packed lower triangle).
#[inline(always)]
fn rigid_term(r: &[f64; 9], v: &[f64; 3], w: f64, m: &mut [f64; 6]) {
    let t = [
        r[0] * v[0] + r[1] * v[1] + r[2] * v[2],
        r[3] * v[0] + r[4] * v[1] + r[5] * v[2],
        r[6] * v[0] + r[7] * v[1] + r[8] * v[2],
    ];
    let wt = [w * t[0], w * t[1], w * t[2]];
    (m[0], m[1], m[2]) = (m[0] + wt[0] * t[0], m[1] + wt[1] * t[0], m[2] + wt[1] * t[1]);
    (m[3], m[4], m[5]) = (m[3] + wt[2] * t[0], m[4] + wt[2] * t[1], m[5] + wt[2] * t[2]);
}

/// out[..N] = K u[..N], K column-major N × N (the same sums as the general loop).
#[inline(always)]
fn solve_n<const N: usize>(k: &[f64], u: &[f64], out: &mut [f64]) {
    out[..N].copy_from_slice(&block_times::<N>(k, N, u));
}

/// An upper bound of the largest eigenvalue of the symmetric n × n matrix whose lower triangle is
/// packed row by row in `m` (m_ij at i(i+1)/2 + j, j <= i): exact (to round-off) for n = 3 by the
/// trigonometric solution of the characteristic cubic, Gershgorin's max_i Σ_j |m_ij| otherwise.
fn largest_eigenvalue(m: &[f64], n: usize) -> f64 {
    let a = |i: usize, j: usize| if j <= i { m[i * (i + 1) / 2 + j] } else { m[j * (j + 1) / 2 + i] };
    if n != 3 {
        return (0..n).map(|i| (0..n).map(|j| a(i, j).abs()).sum::<f64>()).fold(0.0, f64::max);
    }
    let off = a(1, 0) * a(1, 0) + a(2, 0) * a(2, 0) + a(2, 1) * a(2, 1);
    let q = (a(0, 0) + a(1, 1) + a(2, 2)) / 3.0;
    let (d0, d1, d2) = (a(0, 0) - q, a(1, 1) - q, a(2, 2) - q);
    let p = ((d0 * d0 + d1 * d1 + d2 * d2 + 2.0 * off) / 6.0).sqrt();
    if p == 0.0 {
        return q; // a multiple of the identity
    }
    // det(B)/2 with B = (M − qI)/p, clamped against round-off; λ_max = q + 2p cos(acos(r)/3)
    let det = d0 * (d1 * d2 - a(2, 1) * a(2, 1)) - a(1, 0) * (a(1, 0) * d2 - a(2, 1) * a(2, 0))
        + a(2, 0) * (a(1, 0) * a(2, 1) - d1 * a(2, 0));
    let r = (det / (2.0 * p * p * p)).clamp(-1.0, 1.0);
    q + 2.0 * p * (r.acos() / 3.0).cos()
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

#[cfg(test)]
#[path = "tests_bodies.rs"]
mod tests;
