//! The contact Jacobian B in global DOF indices (math note §3.1): row r of B is the gap
//! direction `s n_kᵀ T_b(x_k)` (normal), `s τ_kᵀ T_b(x_k)` (tangent) or `s e_θᵀ` (rolling) of
//! contact k, with entries only in the DOFs the contact touches.
//!
//! B is stored as *segments*: the part of one row on one contiguous DOF range of at most six
//! entries (a body's DOFs; later a mesh node's). A contact between two bodies has two
//! segments per row; a contact on a mesh edge would have one per node. Every product with B
//! or Bᵀ runs over the segments in the order they were pushed, so results do not depend on
//! threads or hashing.
//!
//! While every contact pushed is one between rigid bodies with no rolling row, B is stored as
//! *contact frames* instead ([`Frame`], math note §3.3, "Contact frames from the rows"): 64 bytes a contact
//! where its four segments take 176. The body form reads the frames; any other reader gets the
//! segments, made from the frames on its first call ([`Jacobian::segments`]), and a segment
//! pushed after frames turns them into segments first. Either way the segments are those the
//! contacts would have pushed, in the same order.

use crate::body::{Dofs, MAX_DOF};

/// The part of one row of B on one DOF range, in 20 bytes: its entries are the Jacobian's
/// `vals[val..val + width]` ([`Jacobian::vals`]). The products stream over every segment several
/// times a step, and from about 10,000 disks B no longer fits the caches (math note §3.3); with
/// usize fields and the six entries inline a segment took 80 bytes. u32 indices hold every
/// problem that fits in memory: 2³² segments would take 86 GB, 2³² values 34 GB.
#[derive(Debug, Clone, Copy)]
pub struct Segment {
    row: u32,
    /// The cluster owning the DOFs.
    cluster: u32,
    /// First DOF (global, or cluster-local in a cluster's own copy).
    start: u32,
    /// Number of DOFs (1 to 6).
    width: u32,
    val: u32,
}

impl Segment {
    pub fn row(&self) -> usize {
        self.row as usize
    }
    pub fn cluster(&self) -> usize {
        self.cluster as usize
    }
    pub fn start(&self) -> usize {
        self.start as usize
    }
    pub fn width(&self) -> usize {
        self.width as usize
    }
    /// Its DOFs.
    pub fn dofs(&self) -> std::ops::Range<usize> {
        self.start()..self.start() + self.width()
    }
}

/// One contact's rows `row` (normal n) and `row + 1` (tangent cw(n)) on the rigid bodies whose
/// DOFs start at `a` and `b`: on A the entries (n, p_A) and (cw(n), q_A), on B (−n, p_B) and
/// (−cw(n), q_B), with `arm` = [p_A, q_A, p_B, q_B]; `b` is [`NO_BODY`] for a contact with one
/// moving body. The segments' entries as pushed, since negating is exact: a contact's rows on a
/// rigid body are `Body::rigid_row`'s (s n.x, s n.y, s p) with s = ±1.
#[derive(Debug, Clone, Copy)]
pub struct Frame {
    pub(crate) row: u32,
    pub(crate) a: u32,
    pub(crate) b: u32,
    pub(crate) n: [f64; 2],
    pub(crate) arm: [f64; 4],
}

/// A [`Frame`]'s `b` when the contact has one moving body.
pub const NO_BODY: u32 = u32::MAX;

impl Frame {
    /// The frame of a contact at rows `row`, `row + 1` with rows `na`, `ta` (normal and tangent,
    /// as `Body::rigid_row` gives them) on the rigid body whose DOFs start at `a`.
    pub fn new(row: usize, a: usize, na: [f64; 3], ta: [f64; 3]) -> Frame {
        debug_assert!(ta[0].to_bits() == na[1].to_bits() && ta[1].to_bits() == (-na[0]).to_bits());
        Frame { row: row as u32, a: a as u32, b: NO_BODY, n: [na[0], na[1]], arm: [na[2], ta[2], 0.0, 0.0] }
    }

    /// Adds the second body, whose DOFs start at `b`, with its rows `nb`, `tb` (the first's
    /// negated but for the arms).
    pub fn with_second(mut self, b: usize, nb: [f64; 3], tb: [f64; 3]) -> Frame {
        debug_assert!(nb[0].to_bits() == (-self.n[0]).to_bits() && tb[0].to_bits() == (-self.n[1]).to_bits());
        (self.b, self.arm[2], self.arm[3]) = (b as u32, nb[2], tb[2]);
        self
    }

    /// Its segments' entries in push order: A's n and t rows, then B's.
    #[inline(always)]
    pub fn entries(&self) -> [[f64; 3]; 4] {
        let [nx, ny] = self.n;
        let [pa, qa, pb, qb] = self.arm;
        [[nx, ny, pa], [ny, -nx, qa], [-nx, -ny, pb], [-ny, nx, qb]]
    }

    /// Its number of segments: 2 on one body, 4 on two.
    pub fn segments(&self) -> usize {
        if self.b == NO_BODY { 2 } else { 4 }
    }

    /// Its first row.
    pub fn row(&self) -> usize {
        self.row as usize
    }
}

/// a · b over the shorter of the two, summed in order (B's products and the body form's share
/// it, so that their sums agree bit for bit).
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// v[start..start + N] as an array (one bounds check).
#[inline(always)]
pub fn range_n<const N: usize>(v: &[f64], start: usize) -> &[f64; N] {
    v[start..start + N].try_into().expect("a slice of N entries")
}

/// [`range_n`], mutable.
#[inline(always)]
pub fn range_n_mut<const N: usize>(v: &mut [f64], start: usize) -> &mut [f64; N] {
    (&mut v[start..start + N]).try_into().expect("a slice of N entries")
}

/// [`dot`] over a[..N] and b[..N], unrolled (the same sum).
#[inline(always)]
pub fn dot_n<const N: usize>(a: &[f64], b: &[f64]) -> f64 {
    let (a, b) = (&a[..N], &b[..N]);
    (0..N).map(|i| a[i] * b[i]).sum()
}

/// Appends `v` (at most six values) to `to`, a rigid body's three as three stores:
/// `extend_from_slice` calls memcpy, whose call cost more than the copy (1.7 % of a warm step
/// of the 1,000-disk pile, perf).
#[inline(always)]
pub fn extend_small(to: &mut Vec<f64>, v: &[f64]) {
    match v.len() {
        3 => to.extend([v[0], v[1], v[2]]),
        _ => to.extend_from_slice(v),
    }
}

/// `to.copy_from_slice(v)` for the few values of a body's DOFs or a contact's rows, two or three
/// as stores: `copy_from_slice` calls memcpy, whose call costs more than such a copy (about
/// 11,000 calls a warm step of the 1,000-disk pile, callgrind).
#[inline(always)]
pub fn copy_small(to: &mut [f64], v: &[f64]) {
    match (to, v) {
        ([a, b], [x, y]) => (*a, *b) = (*x, *y),
        ([a, b, c], [x, y, z]) => (*a, *b, *c) = (*x, *y, *z),
        (to, v) => to.copy_from_slice(v),
    }
}

/// B as segments in push order, their entries packed in `vals`, or as contact frames (see the
/// module docs).
#[derive(Debug, Clone, Default)]
pub struct Jacobian {
    pub rows: usize,
    segments: Vec<Segment>,
    vals: Vec<f64>,
    /// B as frames, while `framed`, with their bodies' clusters (the second unused for a frame
    /// of one body), which only the segments made from them read.
    framed: bool,
    frames: Vec<Frame>,
    clusters: Vec<[u32; 2]>,
    /// The segments the frames give, made on first need.
    made: std::sync::OnceLock<(Vec<Segment>, Vec<f64>)>,
    /// The number of segments, whether as segments or as frames.
    len: usize,
}

impl Jacobian {
    /// An empty Jacobian of `rows` rows.
    pub fn with_rows(rows: usize) -> Jacobian {
        let mut jac = Jacobian::default();
        jac.reset(rows);
        jac
    }

    /// Clears the Jacobian for `rows` rows, keeping its storage: frames until a segment is pushed.
    pub fn reset(&mut self, rows: usize) {
        self.rows = rows;
        self.segments.clear();
        self.vals.clear();
        self.frames.clear();
        self.clusters.clear();
        self.made = Default::default();
        (self.framed, self.len) = (true, 0);
    }

    /// Adds the entries `vals[..len]` of row `row` at DOFs `start..start + len` of `cluster`.
    #[inline(always)]
    pub fn push(&mut self, row: usize, cluster: usize, start: usize, len: usize, vals: Dofs) {
        debug_assert!(len <= MAX_DOF);
        self.push_slice(row, cluster, start, &vals.as_slice()[..len]);
    }

    /// Adds the entries `vals` of row `row` at DOFs `start..start + vals.len()` of `cluster`.
    #[inline(always)]
    pub fn push_slice(&mut self, row: usize, cluster: usize, start: usize, vals: &[f64]) {
        if vals.is_empty() {
            return;
        }
        if self.framed {
            self.unframe();
        }
        // the u32 fields (see `Segment`)
        debug_assert!(row.max(cluster).max(start + vals.len()).max(self.vals.len()) < u32::MAX as usize);
        let (row, cluster, start) = (row as u32, cluster as u32, start as u32);
        let (width, val) = (vals.len() as u32, self.vals.len() as u32);
        self.segments.push(Segment { row, cluster, start, width, val });
        extend_small(&mut self.vals, vals);
        self.len += 1;
    }

    /// Adds contact frame `f`, whose bodies are in the clusters `clusters` (the second unused
    /// for a frame of one body), and `out[row] += s · v[start..]` for each of its segments s in
    /// push order (the sums of [`Self::push_apply`]). Stored as a frame while B is framed and the
    /// frames come in row order (the body form cuts them into halves anywhere: `delassus`),
    /// else as its segments.
    pub fn push_frame(&mut self, f: Frame, clusters: [usize; 2], v: &[f64], out: &mut [f64]) {
        let (r, e) = (f.row(), f.entries());
        let starts = [f.a, f.a, f.b, f.b];
        for (k, e) in e.iter().enumerate().take(f.segments()) {
            out[r + k % 2] += dot_n::<3>(e, &v[starts[k] as usize..]);
        }
        if !self.framed || self.frames.last().is_some_and(|last| last.row() >= r) {
            return self.push_segments(&f, clusters.map(|c| c as u32));
        }
        debug_assert!(r + 1 < u32::MAX as usize && clusters[0].max(clusters[1]) < u32::MAX as usize);
        self.frames.push(f);
        self.clusters.push(clusters.map(|c| c as u32));
        self.len += f.segments();
    }

    /// Pushes frame `f`'s segments.
    fn push_segments(&mut self, f: &Frame, clusters: [u32; 2]) {
        let e = f.entries();
        let on = [(f.a, clusters[0]), (f.a, clusters[0]), (f.b, clusters[1]), (f.b, clusters[1])];
        for (k, (start, cluster)) in on.into_iter().enumerate().take(f.segments()) {
            self.push_slice(f.row() + k % 2, cluster as usize, start as usize, &e[k]);
        }
    }

    /// Turns the frames into their segments (a segment is pushed after them).
    #[cold]
    fn unframe(&mut self) {
        self.framed = false;
        let (frames, clusters) = (std::mem::take(&mut self.frames), std::mem::take(&mut self.clusters));
        self.len = 0;
        for (f, c) in frames.iter().zip(clusters) {
            self.push_segments(f, c);
        }
        self.made = Default::default();
    }

    /// B's contact frames, while B is stored so (see the module docs).
    pub fn frames(&self) -> Option<&[Frame]> {
        self.framed.then_some(&self.frames[..])
    }

    /// The number of segments (made from the frames or not).
    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The segments and their entries: B's own, or made once from its frames.
    #[inline(always)]
    fn parts(&self) -> (&[Segment], &[f64]) {
        if !self.framed {
            return (&self.segments, &self.vals);
        }
        let (segments, vals) = self.made.get_or_init(|| {
            let mut made = Jacobian { rows: self.rows, ..Default::default() };
            for (f, &c) in self.frames.iter().zip(&self.clusters) {
                made.push_segments(f, c);
            }
            (made.segments, made.vals)
        });
        (segments, vals)
    }

    /// The segments in push order (made from the frames on the first call while B is framed).
    pub fn segments(&self) -> &[Segment] {
        self.parts().0
    }

    /// The entries of segment s.
    #[inline(always)]
    pub fn vals(&self, s: &Segment) -> &[f64] {
        &self.parts().1[s.val as usize..s.val as usize + s.width()]
    }

    /// The entries of a segment of width N, as an array: one bounds check where a slice and its
    /// first N entries take three (`N` must be the segment's width).
    #[inline(always)]
    pub fn vals_n<const N: usize>(&self, s: &Segment) -> &[f64; N] {
        debug_assert_eq!(s.width(), N);
        range_n::<N>(self.parts().1, s.val as usize)
    }

    /// Segment s's entries dotted with its range of `v` (a global vector, or a cluster-local
    /// one for segments with cluster-local starts).
    #[inline(always)]
    pub fn dot(&self, s: &Segment, v: &[f64]) -> f64 {
        match s.width() {
            // a rigid body's segment, unrolled
            3 => dot_n::<3>(self.vals_n::<3>(s), range_n::<3>(v, s.start())),
            _ => dot(self.vals(s), &v[s.dofs()]),
        }
    }

    /// Sorts the segments by row, stably: a row's segments become consecutive, in push order.
    pub fn sort_by_row(&mut self) {
        if self.framed {
            self.unframe();
        }
        self.segments.sort_by_key(|s| s.row);
    }

    /// [`Self::push_slice`], then `out[row] += vals · v[start..]`: B v summed as B is built, a
    /// row's terms in push order (the sums of [`Self::dot`] segment by segment). A pass of its
    /// own over B cost 50 µs of a warm step on the 1,000-disk pile, one over each contact's new
    /// segments 0.3 M instructions.
    #[inline(always)]
    pub fn push_apply(
        &mut self,
        row: usize,
        cluster: usize,
        start: usize,
        vals: &[f64],
        v: &[f64],
        out: &mut [f64],
    ) {
        self.push_slice(row, cluster, start, vals);
        out[row] += match vals.len() {
            3 => dot_n::<3>(vals, &v[start..]),
            0 => return, // no segment
            n => dot(vals, &v[start..start + n]),
        };
    }

    /// `out += Bᵀ z` over the rows that `keep` selects.
    pub fn transpose_apply(&self, z: &[f64], keep: impl Fn(usize) -> bool, out: &mut [f64]) {
        for s in self.segments().iter().filter(|s| keep(s.row())) {
            let (zr, vals) = (z[s.row()], self.vals(s));
            match s.width() {
                // a rigid body's segment, unrolled
                3 => {
                    let x = &mut out[s.start()..s.start() + 3];
                    (0..3).for_each(|i| x[i] += vals[i] * zr);
                }
                _ => out[s.dofs()].iter_mut().zip(vals).for_each(|(x, v)| *x += v * zr),
            }
        }
    }
}
