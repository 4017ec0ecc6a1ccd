//! The body form's passes over B (math note §3.3): over its segments, or over its contact frames
//! (`jacobian::Frame`) when B is stored so. A contact between two rigid bodies has four
//! segments of three entries: on A, rows n and t = cw(n) with moment arms p_A and q_A; on B, the
//! same rows negated with its own arms. As segments these take 4 × (20 + 24) = 176 bytes, read
//! twice a product; as a frame (the rows, both bodies' first DOFs, n and the four arms) 64 bytes.
//! A contact on one body (a wall's) is the first half of that. The frames give back each entry
//! bit for bit (a negation is exact), and the passes visit them in push order, so their sums are
//! the segments' sums.

use crate::cluster::block_times;
use crate::jacobian::{Frame, Jacobian, NO_BODY, Segment, dot_n, range_n, range_n_mut};

/// diagonal[row - row0] += s K̃⁻¹ sᵀ for each segment s of frame f, in push order (the sums of
/// `BodyPart::add_diagonal`), a body's K̃⁻¹ at 3 times its first DOF in `kinv` (`Blocks::dense`).
pub(super) fn add_diagonal(f: &Frame, kinv: &[f64], diagonal: &mut [f64], row0: usize) {
    let (r, e) = (f.row as usize - row0, f.entries());
    let term =
        |s: &[f64; 3], at: u32| dot_n::<3>(s, &block_times::<3>(range_n::<9>(kinv, 3 * at as usize), 3, s));
    diagonal[r] += term(&e[0], f.a);
    diagonal[r + 1] += term(&e[1], f.a);
    if f.b != NO_BODY {
        diagonal[r] += term(&e[2], f.b);
        diagonal[r + 1] += term(&e[3], f.b);
    }
}

/// u += Bᵀ z over the frames (u indexed by global DOF), in push order ([`scatter`]'s sums).
pub(super) fn scatter_frames(frames: &[Frame], z: &[f64], u: &mut [f64]) {
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
pub(super) fn gather_frames(frames: &[Frame], v: &[f64], out: &mut [f64], offset: usize) {
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
pub(super) fn scatter<'a>(
    jac: &Jacobian,
    segs: impl IntoIterator<Item = &'a Segment>,
    z: &[f64],
    u: &mut [f64],
) {
    for s in segs {
        let zr = z[s.row()];
        match s.width() {
            3 => axpy::<3>(zr, jac.vals_n::<3>(s), range_n_mut::<3>(u, s.start())),
            _ => u[s.dofs()].iter_mut().zip(jac.vals(s)).for_each(|(ui, a)| *ui += a * zr),
        }
    }
}

/// out[row(s) - offset] += s · v over the segments `segs`.
pub(super) fn gather<'a>(
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
