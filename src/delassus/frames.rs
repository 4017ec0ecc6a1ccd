//! The body form's passes over B (math note §3.3): over its segments and its contact frames
//! (`jacobian::Frame`), in push order ([`Half`]). A contact between two rigid bodies has four
//! segments of three entries: on A, rows n and t = cw(n) with moment arms p_A and q_A; on B, the
//! same rows negated with its own arms. As segments these take 4 × (20 + 24) = 176 bytes, read
//! twice a product; as a frame (the rows, both bodies' first DOFs, n and the four arms) 64 bytes.
//! A contact on one body (a wall's) is the first half of that. The frames give back each entry
//! bit for bit (a negation is exact), and the passes visit them in push order, so their sums are
//! the segments' sums.

use crate::cluster::block_times;
use crate::jacobian::{Frame, Jacobian, NO_BODY, Piece, Segment, dot_n, range_n, range_n_mut};
use std::ops::Range;

/// A part of B as the body form's passes read it: its frames `frames` and its own segments
/// `segs` (`Jacobian::own_segments`), in push order (`Jacobian::pieces`).
pub(super) struct Half {
    pub frames: Range<usize>,
    pub segs: Range<usize>,
}

impl Half {
    /// All of B.
    pub fn all(jac: &Jacobian) -> Half {
        Half { frames: 0..jac.frames().len(), segs: 0..jac.own_segments().len() }
    }

    /// u += Bᵀ z over the part's frames and its segments that `keep` selects, in push order (u
    /// indexed by global DOF; the sums of the segments made from the frames).
    pub fn scatter(&self, jac: &Jacobian, keep: impl Fn(&Segment) -> bool, z: &[f64], u: &mut [f64]) {
        for piece in jac.pieces_within(self.frames.clone(), self.segs.clone()) {
            match piece {
                Piece::Frames(r) => scatter_frames(&jac.frames()[r], z, u),
                Piece::Segments(r) => scatter(jac, jac.own_segments()[r].iter().filter(|s| keep(s)), z, u),
            }
        }
    }

    /// out[row - offset] += (B v)_row over the part's frames and its segments that `keep`
    /// selects.
    pub fn gather(
        &self,
        jac: &Jacobian,
        keep: impl Fn(&Segment) -> bool,
        v: &[f64],
        out: &mut [f64],
        offset: usize,
    ) {
        for piece in jac.pieces_within(self.frames.clone(), self.segs.clone()) {
            match piece {
                Piece::Frames(r) => gather_frames(&jac.frames()[r], v, out, offset),
                // (`gather` without an offset: cheaper than adding a zero offset per entry)
                Piece::Segments(r) if offset == 0 => jac.own_segments()[r]
                    .iter()
                    .filter(|s| keep(s))
                    .for_each(|s| out[s.row()] += jac.dot(s, v)),
                Piece::Segments(r) => {
                    gather(jac, jac.own_segments()[r].iter().filter(|s| keep(s)), v, out, offset)
                }
            }
        }
    }
}

/// diagonal[row - row0] += s K̃⁻¹ sᵀ for each segment s of frame f, in push order (the sums of
/// `BodyPart::add_diagonal`), the K̃⁻¹ of its bodies at `at` in `kinv`.
pub(super) fn add_diagonal(f: &Frame, at: [usize; 2], kinv: &[f64], diagonal: &mut [f64], row0: usize) {
    let (r, e) = (f.row as usize - row0, f.entries());
    let term = |s: &[f64; 3], at: usize| dot_n::<3>(s, &block_times::<3>(range_n::<9>(kinv, at), 3, s));
    diagonal[r] += term(&e[0], at[0]);
    diagonal[r + 1] += term(&e[1], at[0]);
    if f.b != NO_BODY {
        diagonal[r] += term(&e[2], at[1]);
        diagonal[r + 1] += term(&e[3], at[1]);
    }
}

/// u += Bᵀ z over the frames (u indexed by global DOF), in push order ([`scatter`]'s sums).
fn scatter_frames(frames: &[Frame], z: &[f64], u: &mut [f64]) {
    for f in frames {
        let (r, e) = (f.row as usize, f.entries());
        let (zn, zt) = (z[r], z[r + 1]);
        let ua = range_n_mut::<3>(u, f.a as usize);
        axpy::<3>(zn, &e[0], ua);
        axpy::<3>(zt, &e[1], ua);
        if f.b != NO_BODY {
            let ub = range_n_mut::<3>(u, f.b as usize);
            axpy::<3>(zn, &e[2], ub);
            axpy::<3>(zt, &e[3], ub);
        }
    }
}

/// out[row - offset] += B v over the frames, in push order ([`gather`]'s sums).
fn gather_frames(frames: &[Frame], v: &[f64], out: &mut [f64], offset: usize) {
    for f in frames {
        let (r, e) = (f.row as usize - offset, f.entries());
        let va = range_n::<3>(v, f.a as usize);
        out[r] += dot_n::<3>(&e[0], va);
        out[r + 1] += dot_n::<3>(&e[1], va);
        if f.b != NO_BODY {
            let vb = range_n::<3>(v, f.b as usize);
            out[r] += dot_n::<3>(&e[2], vb);
            out[r + 1] += dot_n::<3>(&e[3], vb);
        }
    }
}

/// u += Σ_s sᵀ z_row(s) over the segments `segs` (u indexed by global DOF).
fn scatter<'a>(jac: &Jacobian, segs: impl IntoIterator<Item = &'a Segment>, z: &[f64], u: &mut [f64]) {
    for s in segs {
        let zr = z[s.row()];
        match s.width() {
            3 => axpy::<3>(zr, jac.vals_n::<3>(s), range_n_mut::<3>(u, s.start())),
            _ => u[s.dofs()].iter_mut().zip(jac.vals(s)).for_each(|(ui, a)| *ui += a * zr),
        }
    }
}

/// out[row(s) - offset] += s · v over the segments `segs`.
fn gather<'a>(
    jac: &Jacobian,
    segs: impl IntoIterator<Item = &'a Segment>,
    v: &[f64],
    out: &mut [f64],
    offset: usize,
) {
    for s in segs {
        out[s.row() - offset] += jac.dot(s, v);
    }
}

/// u[..N] += x t[..N], unrolled.
#[inline(always)]
fn axpy<const N: usize>(x: f64, t: &[f64], u: &mut [f64]) {
    let (t, u) = (&t[..N], &mut u[..N]);
    for i in 0..N {
        u[i] += x * t[i];
    }
}
