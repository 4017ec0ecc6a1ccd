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
//! A contact between rigid bodies with no rolling row is stored as a *contact frame* instead
//! ([`Frame`], math note §3.3, "Contact frames from the rows"): 64 bytes a contact where its
//! four segments take 176. Frames and segments are kept side by side, each in push order, with
//! where the push order changes from one to the other ([`Jacobian::pieces`]). The body form
//! reads the frames and the segments in that order; any other reader gets all the segments,
//! made from the frames on its first call ([`Jacobian::segments`]), or turns the frames into
//! segments for good ([`Jacobian::unframe`]). Either way the segments are those the contacts
//! would have pushed, in the same order.

use crate::body::{Dofs, MAX_DOF};
use std::ops::Range;

/// The part of one row of B on one DOF range, in 20 bytes: its entries are the Jacobian's
/// `vals[val..val + width]` ([`Jacobian::vals`]). The products stream over every segment several
/// times a step, and from about 10,000 disks B does not fit the caches (math note §3.3), so a
/// segment is kept small (usize fields and six inline entries would take 80 bytes). u32 indices
/// hold every problem that fits in memory: 2³² segments would take 86 GB, 2³² values 34 GB.
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
/// `extend_from_slice` calls memcpy, whose call costs more than so small a copy.
#[inline(always)]
pub fn extend_small(to: &mut Vec<f64>, v: &[f64]) {
    match v.len() {
        3 => to.extend([v[0], v[1], v[2]]),
        _ => to.extend_from_slice(v),
    }
}

/// `to.copy_from_slice(v)` for the few values of a body's DOFs or a contact's rows, two or three
/// as stores: `copy_from_slice` calls memcpy, whose call costs more than such a copy.
#[inline(always)]
pub fn copy_small(to: &mut [f64], v: &[f64]) {
    match (to, v) {
        ([a, b], [x, y]) => (*a, *b) = (*x, *y),
        ([a, b, c], [x, y, z]) => (*a, *b, *c) = (*x, *y, *z),
        (to, v) => to.copy_from_slice(v),
    }
}

/// B as segments and contact frames, each in push order, their segments' entries packed in
/// `vals` (see the module docs).
#[derive(Debug, Clone, Default)]
pub struct Jacobian {
    pub rows: usize,
    segments: Vec<Segment>,
    vals: Vec<f64>,
    /// The frames, with their bodies' clusters (the second unused for a frame of one body),
    /// which only the segments made from them read.
    frames: Vec<Frame>,
    clusters: Vec<[u32; 2]>,
    /// The push order: (frames, segments) pushed before each change from one to the other
    /// ([`Self::pieces`]), and whether the last push was a frame.
    switches: Vec<[u32; 2]>,
    last_framed: bool,
    /// The segments the frames give, made on first need, their entries past `vals`.
    made: std::sync::OnceLock<(Vec<Segment>, Vec<f64>)>,
    /// The number of segments, pushed as segments or as frames.
    len: usize,
}

/// A run of B in push order ([`Jacobian::pieces`]): a range of its frames, or of the segments
/// pushed as segments.
#[derive(Debug, Clone, PartialEq)]
pub enum Piece {
    Frames(Range<usize>),
    Segments(Range<usize>),
}

impl Jacobian {
    /// An empty Jacobian of `rows` rows.
    pub fn with_rows(rows: usize) -> Jacobian {
        let mut jac = Jacobian::default();
        jac.reset(rows);
        jac
    }

    /// Clears the Jacobian for `rows` rows, keeping its storage.
    pub fn reset(&mut self, rows: usize) {
        self.rows = rows;
        self.segments.clear();
        self.vals.clear();
        self.frames.clear();
        self.clusters.clear();
        self.switches.clear();
        self.made = Default::default();
        (self.last_framed, self.len) = (false, 0);
    }

    /// Notes a push of a frame (`framed`) or a segment: where the push order changes kind.
    #[inline(always)]
    fn note_push(&mut self, framed: bool) {
        if framed != self.last_framed {
            self.switches.push([self.frames.len() as u32, self.segments.len() as u32]);
            self.last_framed = framed;
        }
        if self.made.get().is_some() {
            self.made = Default::default();
        }
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
        self.note_push(false);
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
    /// push order (the sums of [`Self::push_apply`]). Stored as a frame while the frames come in
    /// row order (the body form cuts them into halves anywhere: `delassus`), else as its
    /// segments.
    pub fn push_frame(&mut self, f: Frame, clusters: [usize; 2], v: &[f64], out: &mut [f64]) {
        let (r, e) = (f.row(), f.entries());
        let starts = [f.a, f.a, f.b, f.b];
        for (k, e) in e.iter().enumerate().take(f.segments()) {
            out[r + k % 2] += dot_n::<3>(e, &v[starts[k] as usize..]);
        }
        if self.frames.last().is_some_and(|last| last.row() >= r) {
            return Self::push_segments(&f, clusters.map(|c| c as u32), &mut |row, c, start, e| {
                self.push_slice(row, c, start, e)
            });
        }
        debug_assert!(r + 1 < u32::MAX as usize && clusters[0].max(clusters[1]) < u32::MAX as usize);
        self.note_push(true);
        self.frames.push(f);
        self.clusters.push(clusters.map(|c| c as u32));
        self.len += f.segments();
    }

    /// Frame `f`'s segments, as `push(row, cluster, start, entries)` in push order.
    fn push_segments(f: &Frame, clusters: [u32; 2], push: &mut impl FnMut(usize, usize, usize, &[f64])) {
        let e = f.entries();
        let on = [(f.a, clusters[0]), (f.a, clusters[0]), (f.b, clusters[1]), (f.b, clusters[1])];
        for (k, (start, cluster)) in on.into_iter().enumerate().take(f.segments()) {
            push(f.row() + k % 2, cluster as usize, start as usize, &e[k]);
        }
    }

    /// Turns the frames into their segments, in push order (for a reader of segments only).
    pub fn unframe(&mut self) {
        if self.frames.is_empty() {
            return;
        }
        let old = std::mem::replace(self, Jacobian::with_rows(self.rows));
        for piece in old.pieces() {
            match piece {
                Piece::Frames(r) => {
                    for (f, c) in old.frames[r.clone()].iter().zip(&old.clusters[r]) {
                        Self::push_segments(f, *c, &mut |row, c, start, e| self.push_slice(row, c, start, e));
                    }
                }
                Piece::Segments(r) => old.segments[r]
                    .iter()
                    .for_each(|s| self.push_slice(s.row(), s.cluster(), s.start(), old.vals(s))),
            }
        }
    }

    /// B in push order: runs of frames and of segments in turn.
    pub fn pieces(&self) -> impl Iterator<Item = Piece> + '_ {
        self.pieces_within(0..self.frames.len(), 0..self.segments.len())
    }

    /// [`Self::pieces`] within frames `frames` and segments `segs` (ranges of [`Self::frames`]
    /// and [`Self::own_segments`]).
    pub fn pieces_within(
        &self,
        frames: Range<usize>,
        segs: Range<usize>,
    ) -> impl Iterator<Item = Piece> + '_ {
        let ends = [self.frames.len() as u32, self.segments.len() as u32];
        let bounds = std::iter::once([0, 0]).chain(self.switches.iter().copied()).chain([ends]);
        let mut last = [0, 0];
        bounds.skip(1).filter_map(move |at| {
            let [f0, s0] = std::mem::replace(&mut last, at).map(|x| x as usize);
            let [f1, s1] = at.map(|x| x as usize);
            let (f, s) = (f0.max(frames.start)..f1.min(frames.end), s0.max(segs.start)..s1.min(segs.end));
            match () {
                _ if f.start < f.end => Some(Piece::Frames(f)),
                _ if s.start < s.end => Some(Piece::Segments(s)),
                _ => None,
            }
        })
    }

    /// How many segments were pushed before frame `frame` (as segments, not frames').
    pub fn segments_before(&self, frame: usize) -> usize {
        let mut at = 0;
        for piece in self.pieces() {
            match piece {
                Piece::Frames(r) if r.contains(&frame) => return at,
                Piece::Segments(r) => at = r.end,
                Piece::Frames(_) => {}
            }
        }
        at
    }

    /// B's contact frames, in push order (see the module docs).
    pub fn frames(&self) -> &[Frame] {
        &self.frames
    }

    /// The clusters of each frame's bodies (the second unused for a frame of one body).
    pub fn frame_clusters(&self) -> &[[u32; 2]] {
        &self.clusters
    }

    /// The segments pushed as segments, in push order (not the frames').
    pub fn own_segments(&self) -> &[Segment] {
        &self.segments
    }

    /// The number of segments (the frames' included).
    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Every segment in push order, the frames' included: B's own, or made once from the frames
    /// on the first call (their entries past `vals`, so that a segment's `val` finds its
    /// entries either way).
    pub fn segments(&self) -> &[Segment] {
        if self.frames.is_empty() {
            return &self.segments;
        }
        &self
            .made
            .get_or_init(|| {
                let (own, mut segments, mut vals) = (self.vals.len() as u32, Vec::new(), Vec::new());
                for piece in self.pieces() {
                    match piece {
                        Piece::Segments(r) => segments.extend_from_slice(&self.segments[r]),
                        Piece::Frames(r) => {
                            for (f, c) in self.frames[r.clone()].iter().zip(&self.clusters[r]) {
                                Self::push_segments(f, *c, &mut |row, c, start, e: &[f64]| {
                                    let val = own + vals.len() as u32;
                                    let (row, cluster, start, width) =
                                        (row as u32, c as u32, start as u32, 3);
                                    segments.push(Segment { row, cluster, start, width, val });
                                    extend_small(&mut vals, e);
                                });
                            }
                        }
                    }
                }
                (segments, vals)
            })
            .0
    }

    /// The entries of B from `s.val` on: pushed as segments, or made from a frame.
    #[inline(always)]
    fn vals_from(&self, s: &Segment) -> &[f64] {
        let (at, own) = (s.val as usize, self.vals.len());
        match at < own {
            true => &self.vals[at..],
            false => &self.made.get().expect("a frame's segment comes from `segments`").1[at - own..],
        }
    }

    /// The entries of segment s.
    #[inline(always)]
    pub fn vals(&self, s: &Segment) -> &[f64] {
        &self.vals_from(s)[..s.width()]
    }

    /// The entries of a segment of width N, as an array: one bounds check where a slice and its
    /// first N entries take three (`N` must be the segment's width).
    #[inline(always)]
    pub fn vals_n<const N: usize>(&self, s: &Segment) -> &[f64; N] {
        debug_assert_eq!(s.width(), N);
        range_n::<N>(self.vals_from(s), 0)
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
        self.unframe();
        self.segments.sort_by_key(|s| s.row);
    }

    /// [`Self::push_slice`], then `out[row] += vals · v[start..]`: B v summed as B is built, a
    /// row's terms in push order (the sums of [`Self::dot`] segment by segment), which spares a
    /// pass of its own over B.
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

    /// `out += B v` for a global vector `v`, in push order (the sums of [`Self::push_apply`]).
    pub fn apply(&self, v: &[f64], out: &mut [f64]) {
        for piece in self.pieces() {
            match piece {
                Piece::Segments(r) => self.segments[r].iter().for_each(|s| out[s.row()] += self.dot(s, v)),
                Piece::Frames(r) => {
                    for f in &self.frames[r] {
                        let starts = [f.a, f.a, f.b, f.b];
                        for (k, e) in f.entries().iter().enumerate().take(f.segments()) {
                            out[f.row() + k % 2] += dot_n::<3>(e, &v[starts[k] as usize..]);
                        }
                    }
                }
            }
        }
    }

    /// `out += Bᵀ z` over the rows that `keep` selects.
    /// `out += Bᵀ z` over the rows that `keep` selects, in push order (the frames read as they
    /// are, with their segments' sums).
    pub fn transpose_apply(&self, z: &[f64], keep: impl Fn(usize) -> bool, out: &mut [f64]) {
        let add = |out: &mut [f64], start: usize, vals: &[f64], zr: f64| match vals.len() {
            // a rigid body's segment, unrolled
            3 => {
                let x = range_n_mut::<3>(out, start);
                (0..3).for_each(|i| x[i] += vals[i] * zr);
            }
            n => out[start..start + n].iter_mut().zip(vals).for_each(|(x, v)| *x += v * zr),
        };
        for piece in self.pieces() {
            match piece {
                Piece::Segments(r) => {
                    for s in self.segments[r].iter().filter(|s| keep(s.row())) {
                        add(out, s.start(), self.vals(s), z[s.row()]);
                    }
                }
                Piece::Frames(r) => {
                    for f in &self.frames[r] {
                        let (e, starts) = (f.entries(), [f.a, f.a, f.b, f.b]);
                        for (k, e) in e.iter().enumerate().take(f.segments()) {
                            let row = f.row() + k % 2;
                            if keep(row) {
                                add(out, starts[k] as usize, e, z[row]);
                            }
                        }
                    }
                }
            }
        }
    }
}
