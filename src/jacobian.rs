//! The contact Jacobian B in global DOF indices (math note §3.1): row r of B is the gap
//! direction `s n_kᵀ T_b(x_k)` (normal), `s τ_kᵀ T_b(x_k)` (tangent) or `s e_θᵀ` (rolling) of
//! contact k, with entries only in the DOFs the contact touches.
//!
//! B is stored as *segments*: the part of one row on one contiguous DOF range of at most six
//! entries (a body's DOFs; later a mesh node's). A contact between two bodies has two
//! segments per row; a contact on a mesh edge would have one per node. Every product with B
//! or Bᵀ runs over the segments in the order they were pushed, so results do not depend on
//! threads or hashing.

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

/// B as segments in push order, their entries packed in `vals`.
#[derive(Debug, Clone, Default)]
pub struct Jacobian {
    pub rows: usize,
    segments: Vec<Segment>,
    vals: Vec<f64>,
}

impl Jacobian {
    /// An empty Jacobian of `rows` rows.
    pub fn with_rows(rows: usize) -> Jacobian {
        Jacobian { rows, ..Default::default() }
    }

    /// Clears the Jacobian for `rows` rows, keeping its storage.
    pub fn reset(&mut self, rows: usize) {
        self.rows = rows;
        self.segments.clear();
        self.vals.clear();
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
        // the u32 fields (see `Segment`)
        debug_assert!(row.max(cluster).max(start + vals.len()).max(self.vals.len()) < u32::MAX as usize);
        let (row, cluster, start) = (row as u32, cluster as u32, start as u32);
        let (width, val) = (vals.len() as u32, self.vals.len() as u32);
        self.segments.push(Segment { row, cluster, start, width, val });
        extend_small(&mut self.vals, vals);
    }

    pub fn segments(&self) -> &[Segment] {
        &self.segments
    }

    /// The entries of segment s.
    #[inline(always)]
    pub fn vals(&self, s: &Segment) -> &[f64] {
        &self.vals[s.val as usize..s.val as usize + s.width()]
    }

    /// The entries of a segment of width N, as an array: one bounds check where a slice and its
    /// first N entries take three (`N` must be the segment's width).
    #[inline(always)]
    pub fn vals_n<const N: usize>(&self, s: &Segment) -> &[f64; N] {
        debug_assert_eq!(s.width(), N);
        range_n::<N>(&self.vals, s.val as usize)
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
        for s in self.segments.iter().filter(|s| keep(s.row())) {
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
