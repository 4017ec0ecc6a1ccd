//! Where the body form's products cut B into two halves, one per core (`BodyPart::split`, math
//! note §3.3).

use crate::jacobian::{Jacobian, Segment};

/// Where B's two halves meet: the first half is its frames before `frames` and its own segments
/// (`Jacobian::own_segments`) before `segs`, every row of theirs below `row`; the second half
/// the rest, every row of theirs at or above `row`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Cut {
    pub frames: usize,
    pub segs: usize,
    pub row: usize,
}

/// Where B cuts into two halves whose rows do not overlap, at about half of it, or `None`.
/// Segments alone cut at [`split_of`]; frames alone (they come in row order:
/// `Jacobian::push_frame`) at their middle. Both cut where the larger of the two would (the
/// segments pushed before the middle frame, or the frames below the segments' cut), kept
/// when no row of either half's frames or segments lies on the wrong side of the cut's row
/// (contacts pushed in row order always pass).
pub(super) fn cut_of(jac: &Jacobian) -> Option<Cut> {
    let (frames, segs) = (jac.frames(), jac.own_segments());
    let cut = if jac.len() - segs.len() >= segs.len() {
        let at = frames.len() / 2;
        Cut { frames: at, segs: jac.segments_before(at), row: frames[at].row() }
    } else {
        let at = split_of(segs);
        if at == 0 {
            return None;
        }
        let row = segs[at].row();
        Cut { frames: frames.partition_point(|f| f.row() < row), segs: at, row }
    };
    // frames in row order: the last of the first half, the first of the second; every segment
    let frames_apart = (cut.frames == 0 || frames[cut.frames - 1].row() + 1 < cut.row)
        && frames.get(cut.frames).is_none_or(|f| f.row() >= cut.row);
    let segs_apart = segs.is_empty()
        || frames.is_empty()
        || (segs[..cut.segs].iter().all(|s| s.row() < cut.row)
            && segs[cut.segs..].iter().all(|s| s.row() >= cut.row));
    (cut.frames + cut.segs > 0 && frames_apart && segs_apart).then_some(cut)
}

/// Segments past half that [`split_of`] reads one by one (the rest of the second half it reads
/// on the other core).
const CUT_WINDOW: usize = 256;

/// Where B's segments split into two halves whose rows do not overlap (`BodyPart::split`), or 0:
/// the first segment i at or past half (2i >= n, i > 0) whose row is above every earlier one and
/// at or below every later one (the products and the diagonal then cut their rows at its row).
/// The rows of the two halves are read on the two cores (the largest of the first half, the
/// least of the second past `CUT_WINDOW`); the segments near half then on this one, with their
/// suffix minima. Segments pushed contact by contact, as the rows are built, cut at the first
/// contact that starts past half, or inside a contact with one body (rows n, t of a wall
/// contact), but never at a two-body contact's second row (n on A, t on A, n on B, t on B):
/// a rule that took the first row above the first half and gave up when a later row lay below
/// it would find no cut when half falls there (`tests_bodies.rs`).
fn split_of(all: &[Segment]) -> usize {
    let n = all.len();
    let half = n.div_ceil(2).max(1);
    if half >= n {
        return 0;
    }
    let tail = (half + CUT_WINDOW).min(n);
    let (top, low_tail) = micropool::join(
        || all[..half].iter().map(Segment::row).fold(0, usize::max),
        || all[tail..].iter().map(Segment::row).fold(usize::MAX, usize::min),
    );
    let near = first_cut(&all[half..tail], top, low_tail);
    if let Some(k) = near {
        return half + k;
    }
    // past the window (contacts pushed far out of row order): the same rule over the rest
    let top = all[half..tail].iter().map(Segment::row).fold(top, usize::max);
    first_cut(&all[tail..], top, usize::MAX).map_or(0, |k| tail + k)
}

/// The first k whose row is above `top` and above every row of `segs` before it, and at or
/// below every row after it and `low`, the least row past `segs`.
fn first_cut(segs: &[Segment], mut top: usize, low: usize) -> Option<usize> {
    let mut suffix = vec![low; segs.len() + 1];
    for (k, s) in segs.iter().enumerate().rev() {
        suffix[k] = suffix[k + 1].min(s.row());
    }
    for (k, s) in segs.iter().enumerate() {
        if s.row() > top && s.row() <= suffix[k + 1] {
            return Some(k);
        }
        top = top.max(s.row());
    }
    None
}
