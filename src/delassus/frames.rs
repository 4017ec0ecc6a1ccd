//! The body form's passes over B (math note §3.3): over its segments, or over its rows of rigid
//! contacts packed per contact ("Contact frames"). A contact between two rigid bodies pushes
//! four segments of three entries (`World::push_contact`): on A, rows n and t = cw(n) with
//! moment arms p_A and q_A; on B, the same rows negated with its own arms. As segments these
//! take 4 × (20 + 24) = 176 bytes, read twice a product; as a frame (the rows, both bodies'
//! first DOFs, n and the four arms) 64 bytes. A contact on one body (a wall's) is the first half
//! of that. The frames give back each entry bit for bit (a negation is exact, and [`pack`]
//! checks every entry), and the passes visit them in push order, so their sums are the
//! segments' sums.

use crate::cluster::block_times;
use crate::jacobian::{Jacobian, Segment, dot_n, range_n, range_n_mut};

/// A frame's `b` when the contact has one body.
const NONE: u32 = u32::MAX;

/// One contact's rows `row` (normal n) and `row + 1` (tangent cw(n)) on the rigid bodies whose
/// DOFs start at `a` and `b`: on A the entries (n, p_A) and (cw(n), q_A), on B (−n, p_B) and
/// (−cw(n), q_B), with `arm` = [p_A, q_A, p_B, q_B].
#[derive(Debug, Clone, Copy)]
pub(super) struct Frame {
    row: u32,
    a: u32,
    b: u32,
    n: [f64; 2],
    arm: [f64; 4],
}

impl Frame {
    /// Its segments' entries in push order: A's n and t rows, then B's.
    #[inline(always)]
    fn entries(&self) -> [[f64; 3]; 4] {
        let [nx, ny] = self.n;
        let [pa, qa, pb, qb] = self.arm;
        [[nx, ny, pa], [ny, -nx, qa], [-nx, -ny, pb], [-ny, nx, qb]]
    }
}

/// Packs the segments `segs` of B into `frames` (cleared first: the storage of an earlier step,
/// [`super::Scratch`]) as far as they are rigid contacts' as described above, calling `each`
/// on every frame as it is made; returns how many segments it packed, all of them unless one
/// is not such a contact's (widths other than 3, a rolling row, entries that a frame would not
/// give back bit for bit) or not `dense` (its body's K̃⁻¹ at three times its first DOF in the
/// blocks: [`add_diagonal`]). Every segment before that point is a rigid body's.
pub(super) fn pack(
    jac: &Jacobian,
    segs: &[Segment],
    dense: impl Fn(&Segment) -> bool,
    frames: &mut Vec<Frame>,
    mut each: impl FnMut(&Frame),
) -> usize {
    frames.clear();
    let mut i = 0;
    while let Some((frame, count)) = next_frame(jac, &segs[i..], &dense) {
        each(&frame);
        frames.push(frame);
        i += count;
    }
    i
}

/// The frame of the contact whose segments start `segs`, and its number of segments, or `None`
/// (see [`pack`]).
fn next_frame(jac: &Jacobian, segs: &[Segment], dense: impl Fn(&Segment) -> bool) -> Option<(Frame, usize)> {
    let (s, t) = (segs.first()?, segs.get(1)?);
    let (r, a) = (s.row(), s.start());
    if s.width() != 3 || t.width() != 3 || t.row() != r + 1 || t.start() != a || !dense(s) {
        return None;
    }
    let (vs, vt) = (jac.vals_n::<3>(s), jac.vals_n::<3>(t));
    let mut frame =
        Frame { row: r as u32, a: a as u32, b: NONE, n: [vs[0], vs[1]], arm: [vs[2], vt[2], 0.0, 0.0] };
    if let Some([u, w]) = segs.get(2..4).filter(|b| b[0].row() == r && b[1].row() == r + 1) {
        if u.width() != 3 || w.width() != 3 || w.start() != u.start() || !dense(u) {
            return None;
        }
        (frame.b, frame.arm[2], frame.arm[3]) =
            (u.start() as u32, jac.vals_n::<3>(u)[2], jac.vals_n::<3>(w)[2]);
    }
    let count = if frame.b == NONE { 2 } else { 4 };
    let same = |k: usize| {
        let v = jac.vals_n::<3>(&segs[k]);
        frame.entries()[k].iter().zip(v).all(|(x, y)| x.to_bits() == y.to_bits())
    };
    (0..count).all(same).then_some((frame, count))
}

/// diagonal[row - row0] += s K̃⁻¹ sᵀ for each segment s of frame f, in push order (the sums of
/// `BodyPart::add_diagonal`), a body's K̃⁻¹ at 3 times its first DOF in `kinv` (`pack`'s `dense`).
pub(super) fn add_diagonal(f: &Frame, kinv: &[f64], diagonal: &mut [f64], row0: usize) {
    let (r, e) = (f.row as usize - row0, f.entries());
    let term =
        |s: &[f64; 3], at: u32| dot_n::<3>(s, &block_times::<3>(range_n::<9>(kinv, 3 * at as usize), 3, s));
    diagonal[r] += term(&e[0], f.a);
    diagonal[r + 1] += term(&e[1], f.a);
    if f.b != NONE {
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
        if f.b != NONE {
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
        if f.b != NONE {
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
