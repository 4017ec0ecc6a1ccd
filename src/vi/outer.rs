//! The outer compatibility loop (math note §4.3): each pass asks the bound rule for the box of
//! the current iterate, block by block, clips the iterate into it and runs the PC solver from
//! there, until the box settles and the iterate solves the VI of its own box.

use super::measure::Goal;
use super::pc::{self, Ctx, State, Vectors, clip, larger};
use super::scaling::Rows;
use super::{BoundRule, Options, Report, Status};

/// Everything a pass needs besides the work storage.
pub(super) struct Pass<'a> {
    pub rule: &'a dyn BoundRule,
    pub blocks: &'a [usize],
    /// The unscaled q (zero-row test).
    pub q: &'a [f64],
    pub opts: &'a Options,
    /// Inner accuracy factor of the passes after the first (`Solver::inexact`, sanitized).
    pub inexact: f64,
    /// max(1, ||D⁻¹q||_inf, Options::force_scale): the divergence test's scale.
    pub dq: f64,
}

/// The new box measured against the previous one.
struct NewBox {
    /// Largest change of a bound (0 at the first pass).
    change: f64,
    /// max(0, max |finite bound|).
    bmax: f64,
    /// Bit-identical to the previous box.
    same: bool,
}

/// Runs the passes from the warm start in `v.y`; writes the result (or the restored warm
/// start) into `z` and the counters into `st`.
pub(super) fn solve<R: Rows>(c: &Ctx<R>, p: &Pass, v: &mut Vectors, st: &mut State, z: &mut [f64]) -> Report {
    let status = match passes(c, p, v, st, z) {
        Ok(()) => Status::Converged,
        Err(s) => s,
    };
    finish(c, v, st, z, status)
}

/// The pass loop; `Ok` once converged.
fn passes<R: Rows>(
    c: &Ctx<R>,
    p: &Pass,
    v: &mut Vectors,
    st: &mut State,
    z: &mut [f64],
) -> Result<(), Status> {
    let tol = p.opts.tolerance;
    let growth = if tol > 0.0 { (1e-2 / tol).clamp(1e4, 1e8) } else { 1e8 };
    // an inner run cut short of its aim (math note §4.11) with the tolerance met: the next
    // pass's test decides, and the cut's reason stands if it fails
    let mut short = None;
    loop {
        let nb = new_box(c, p, v, st, z)?;
        let moved = clip_into_box(c, v);
        // Unchanged box and iterate: the last sweep is still valid. A box that moved under an
        // iterate that did not (on a warm start that needs no iteration, by rounding only: its
        // friction bounds recomputed from the unscaled answer) needs the measurements again,
        // not the product.
        let stale = !(nb.same && moved == 0.0 && st.fresh);
        let ok = match (stale, moved == 0.0 && st.exact()) {
            (false, _) => true,
            (true, true) => pc::remeasure(c, v, st),
            (true, false) => pc::sweep(c, v, st),
        };
        if !ok {
            return Err(Status::NonFinite);
        }
        let limit = growth * p.dq.max(st.znorm).max(nb.bmax);
        st.have_prev = true;
        if st.outer > 0 && nb.change <= tol * nb.bmax.max(1.0) && st.res <= tol {
            return Ok(());
        }
        if let Some(reason) = short {
            return Err(reason);
        }
        if st.outer >= p.opts.max_outer {
            return Err(Status::OuterLimit);
        }
        // Inexact passes (see `Solver::inexact`): while the box still moves, solving the VI of
        // a box that is about to change far below that change is wasted work. Pass m >= 1
        // stops at max(tol, inexact * change / max(1, max|bound|)); the stopping test above
        // still demands the full tolerance with a settled box. A run to the tolerance itself
        // that has to iterate aims below it, within its budget (math note §4.11).
        let inner_tol = if st.outer == 0 { tol } else { tol.max(p.inexact * nb.change / nb.bmax.max(1.0)) };
        let aim = if inner_tol == tol { p.opts.aim * tol } else { inner_tol };
        let goal = &mut Goal::new(inner_tol, aim);
        st.outer += 1;
        let run = match &c.mprgp {
            Some(abar) => super::mprgp::run(c, v, st, goal, limit, p.opts.max_iterations, abar),
            None => pc::run(c, v, st, goal, limit, p.opts.max_iterations),
        };
        match run {
            Err(reason @ (Status::IterationLimit | Status::Stalled)) if st.res <= tol => short = Some(reason),
            run => run?,
        }
    }
}

/// Clips the iterate into the box just set; the number of rows it moved.
fn clip_into_box<R: Rows>(c: &Ctx<R>, v: &mut Vectors) -> f64 {
    let Vectors { y, ylo, yhi, parts, .. } = v;
    super::par::run1(c.par, y, parts, |r0, yo| {
        let mut moved = 0.0;
        let (ylo, yhi) = (&ylo[r0..r0 + yo.len()], &yhi[r0..r0 + yo.len()]);
        for (k, yk) in yo.iter_mut().enumerate() {
            let cl = clip(*yk, ylo[k], yhi[k]);
            if cl != *yk {
                moved += 1.0;
                *yk = cl;
            }
        }
        super::par::Partial { s0: moved, ..Default::default() }
    })
    .s0
}

/// Asks the rule for the box of the current iterate (z itself at the first pass, else the
/// unscaled y), validates it, measures its change and scales it. Errors: `InvalidBounds`
/// (the last valid box is kept for the final unscaling) and `Diverged` (a zero row pushed
/// toward an infinite bound).
///
/// While y is still the scaled warm start (no pass has moved it: a warm start that meets the
/// tolerance), its iterate is the warm start z0 itself, whose box is the first pass's: the box
/// is kept, and the answer is z0 bit for bit (`State::kept`). Unscaling y instead would give
/// z0 to rounding (D^{-1/2} D^{1/2} z0), a box that moved by rounding, and a pass to measure it
/// again (math note §4.8).
fn new_box<R: Rows>(
    c: &Ctx<R>,
    p: &Pass,
    v: &mut Vectors,
    st: &mut State,
    z: &mut [f64],
) -> Result<NewBox, Status> {
    st.kept = st.have_prev && kept_start(c, v);
    if st.kept {
        answer_into(c, v, st, z);
        return Ok(NewBox { change: 0.0, bmax: st.bmax, same: true });
    }
    if st.have_prev {
        pc::unscale_into(c, v, z);
        std::mem::swap(&mut v.lo, &mut v.lo_prev);
        std::mem::swap(&mut v.hi, &mut v.hi_prev);
    }
    p.rule.all_bounds_par(p.blocks, z, &mut v.lo, &mut v.hi, c.par);

    let have_prev = st.have_prev;
    let (change, bmax, same, valid) = scale_box(v, c.sd, have_prev, c.par);
    let Vectors { lo, hi, lo_prev, hi_prev, ylo, yhi, .. } = &mut *v;
    let sd = c.sd;
    if !valid {
        if have_prev {
            // Keep the last valid box for the final unscaling.
            std::mem::swap(lo, lo_prev);
            std::mem::swap(hi, hi_prev);
            for i in 0..lo.len() {
                ylo[i] = lo[i] * sd[i];
                yhi[i] = hi[i] * sd[i];
            }
        }
        return Err(Status::InvalidBounds);
    }
    // Zero rows: G_j = q_j is constant; it needs a finite bound on the side q pushes to.
    let q = p.q;
    if c.zero_rows
        .iter()
        .any(|&j| (q[j] > 0.0 && lo[j] == f64::NEG_INFINITY) || (q[j] < 0.0 && hi[j] == f64::INFINITY))
    {
        return Err(Status::Diverged);
    }
    st.bmax = bmax;
    Ok(NewBox { change, bmax, same })
}

/// The scaled box `ylo, yhi` of `lo, hi`, and the box's largest change against `lo_prev, hi_prev`
/// (with `have_prev`), its largest finite bound, whether it is bit-identical to the previous one
/// and whether it is valid (lo <= hi, no infinite bound on the wrong side). Over the sweeps'
/// blocks (maxima and counts, the same in any order).
fn scale_box(v: &mut Vectors, sd: &[f64], have_prev: bool, par: bool) -> (f64, f64, bool, bool) {
    let n = v.lo.len();
    let Vectors { lo, hi, lo_prev, hi_prev, ylo, yhi, parts, .. } = v;
    let (lo, hi, lo_prev, hi_prev) = (&lo[..n], &hi[..n], &lo_prev[..n], &hi_prev[..n]);
    let t = super::par::run2(par, &mut ylo[..n], &mut yhi[..n], parts, |r0, ylo, yhi| {
        let (mut change, mut bmax, mut differ, mut invalid) = (0.0f64, 0.0f64, 0.0, 0.0);
        // every vector cut to the block's rows, so that the loop's indexing needs no bounds checks
        let b = || r0..r0 + ylo.len();
        let (lo, hi, lo_prev, hi_prev, sd) = (&lo[b()], &hi[b()], &lo_prev[b()], &hi_prev[b()], &sd[b()]);
        let yhi = &mut yhi[..ylo.len()];
        for i in 0..ylo.len() {
            let (l, h) = (lo[i], hi[i]);
            if !(l <= h && l < f64::INFINITY && h > f64::NEG_INFINITY) {
                invalid += 1.0;
            }
            if l.is_finite() {
                bmax = larger(l.abs(), bmax);
            }
            if h.is_finite() {
                bmax = larger(h.abs(), bmax);
            }
            if have_prev {
                change = larger(bound_diff(h, hi_prev[i]), larger(bound_diff(l, lo_prev[i]), change));
                if l.to_bits() != lo_prev[i].to_bits() || h.to_bits() != hi_prev[i].to_bits() {
                    differ += 1.0;
                }
            }
            ylo[i] = l * sd[i];
            yhi[i] = h * sd[i];
        }
        super::par::Partial { m0: change, m1: bmax, s0: differ, s1: invalid, ..Default::default() }
    });
    (t.m0, t.m1, have_prev && t.s0 == 0.0, t.s1 == 0.0)
}

/// z = the unscaled iterate: the warm start itself while y is still it (`State::kept`).
fn answer_into<R: Rows>(c: &Ctx<R>, v: &mut Vectors, st: &State, z: &mut [f64]) {
    if st.kept {
        z.copy_from_slice(&v.z0);
    } else {
        pc::unscale_into(c, v, z);
    }
}

/// y is bit for bit the scaled warm start of [`Vectors::start`] (y = sd z0, z0 finite).
fn kept_start<R: Rows>(c: &Ctx<R>, v: &Vectors) -> bool {
    v.y.iter().zip(&v.z0).zip(c.sd).all(|((&y, &z), &sd)| z.is_finite() && y == z * sd)
}

/// Stores the status, writes z (the solution, the last iterate, or the restored warm start)
/// and builds the report.
fn finish<R: Rows>(c: &Ctx<R>, v: &mut Vectors, st: &mut State, z: &mut [f64], status: Status) -> Report {
    st.stats.status = status;
    let keeps_iterate = !matches!(status, Status::Diverged | Status::NonFinite)
        && (status != Status::InvalidBounds || st.have_prev);
    if status != Status::Converged && keeps_iterate && st.last_infeasible {
        // Contraction step only: report the residual of the projected iterate.
        pc::project(c, v);
        pc::sweep(c, v, st);
    }
    let residual = match status {
        Status::Diverged | Status::NonFinite => {
            z.copy_from_slice(&v.z0);
            f64::INFINITY
        }
        // No valid box was ever returned: z was not touched.
        Status::InvalidBounds if !st.have_prev => f64::INFINITY,
        _ => {
            answer_into(c, v, st, z);
            if status == Status::InvalidBounds { f64::INFINITY } else { st.res }
        }
    };
    Report {
        outer_iterations: st.outer,
        inner_iterations: st.inner,
        residual,
        converged: status == Status::Converged,
    }
}

/// |a − b| for two bounds; 0 for equal infinities, +inf when only one is infinite.
fn bound_diff(a: f64, b: f64) -> f64 {
    if a == b {
        0.0
    } else if a.is_finite() && b.is_finite() {
        (a - b).abs()
    } else {
        f64::INFINITY
    }
}
