//! Inner solver of a pass, alternative to PC: MPRGP (modified proportioning with reduced
//! gradient projections; Dostál & Schöberl 2005, Dostál, *Optimal Quadratic Programming
//! Algorithms*, 2009, §8.2), for the box-constrained quadratic program that one pass of the
//! outer loop solves: with the box fixed, the VI of G(y) = q̂ + Ŵ y on [ylo, yhi] is the
//! optimality condition of min ½ yᵀŴy + q̂ᵀy on the box (Ŵ symmetric PSD). Math note §4.8.
//!
//! Conjugate-gradient steps run on the free rows while the active set is "proportional"
//! (the chopped gradient of the rows at a bound is small against the free gradient);
//! otherwise a proportioning step frees rows, and a CG step that would leave the box is
//! replaced by an expansion step (to the box boundary, then a projected gradient step of
//! length ᾱ <= 2/||Ŵ||). On a pile of disks, whose W behaves like a discrete Laplacian
//! over the contact network, CG needs about the square root of the iterations of a
//! projection method (PC) or of Gauss-Seidel; a slow run also gets face solves (one sparse
//! factorization of the free rows' block, `face.rs`, math note §4.10).
//!
//! Vector use (`Vectors`): `y` the iterate, `wy` = Ŵy (kept up to date by the step updates
//! and recomputed by a full product every [`REFRESH`] iterations and after each expansion),
//! `yt` the search direction p, `wyt` = Ŵp. Every pass of an iteration (the measure, the
//! direction, the product's row loop, the step, the expansion and the cost) runs over the row
//! blocks of `par.rs`, in two halves from `parallel_min_rows` on, so each core keeps to its own
//! half of the rows in every pass; sums are reduced in block order (math note §3.3, "MPRGP's
//! passes in halves").

// NaN-safe `!(a <= b)` tests.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::Status;
use super::face::{self, Face};
use super::measure::{Goal, Measure};
use super::par::{self, Partial};
use super::pc::{Ctx, State, Vectors, clip, larger, smaller, stop, sweep, unscale};
use super::scaling::Rows;

/// Proportioning constant Γ (Dostál's usual choice).
const GAMMA: f64 = 1.0;
/// ᾱ = ABAR_GERSHGORIN / Gershgorin's bound of an explicit Ŵ. That bound exceeds ‖Ŵ‖ by a
/// factor the solver does not know (1.5 on the disk piles), so the factor is the largest the
/// method allows (measured on the cold steps of the 10,000-disk pile, `benches/vi.rs`).
const ABAR_GERSHGORIN: f64 = 1.9;
/// ᾱ = ABAR_OPERATOR / the operator's row bound ([`crate::vi::Operator::row_bounds`]), which the
/// body form keeps close to ‖Ŵ‖ (4.48 against 4.0 on the disk piles): ᾱ ≈ 1/‖Ŵ‖, where
/// Dostál's bound of the rate stops improving (it is flat on [1, 2]/‖Ŵ‖), and the steps near
/// 2/‖Ŵ‖ do not damp the stiffest modes. Of the factors 0.76–1.9, 0.95 needed the fewest warm
/// iterations on piles of 1,000, 2,400 and 4,000 disks (math note §4.8).
const ABAR_OPERATOR: f64 = 0.95;

/// An upper bound of ‖Ŵ‖ for the step length.
pub(super) enum Bound {
    /// Gershgorin's max_i Σ_j |Ŵ_ij| of an explicit Ŵ.
    Gershgorin(f64),
    /// max_r of [`crate::vi::Operator::row_bounds`].
    Operator(f64),
}
/// Full product Ŵy every this many iterations, against drift of the updated `wy`.
const REFRESH: usize = 50;

/// Free gradient φ_i: g_i on a free row, 0 at a bound.
#[inline(always)]
fn free(y: f64, lo: f64, hi: f64, g: f64) -> f64 {
    if y > lo && y < hi { g } else { 0.0 }
}

/// Chopped gradient β_i: at the lower bound min(g, 0), at the upper bound max(g, 0); 0 on a
/// row whose box is a point (lo = hi: it cannot move).
#[inline(always)]
fn chopped(y: f64, lo: f64, hi: f64, g: f64) -> f64 {
    if !(lo < hi) {
        0.0
    } else if y <= lo {
        g.min(0.0)
    } else if y >= hi {
        g.max(0.0)
    } else {
        0.0
    }
}

/// ᾱ of one solve. The proportioning test needs a value from the first iteration on, and there
/// only weighs the free gradient (φ̃ of the module docs): until this solve has computed ᾱ, the
/// test uses the last one a solve of the same [`Solver`] computed (`guess`), and computes it only
/// when there is none. An expansion takes the guess too, and keeps its step when the step
/// decreased the cost; else it is done again with this solve's bound of ‖Ŵ‖ (`exact`, computed
/// then and kept for the solve's later passes: [`expand_step`]). A warm step thus skips the
/// bound of ‖Ŵ‖, the costliest part of a warm solve that expands, as does a solve whose start
/// already meets its tolerance (math note §4.8).
#[derive(Debug)]
pub(super) struct StepLength {
    guess: Option<f64>,
    exact: std::sync::OnceLock<f64>,
}

impl StepLength {
    pub fn new(guess: Option<f64>) -> Self {
        StepLength { guess, exact: std::sync::OnceLock::new() }
    }

    /// ᾱ for the proportioning test.
    fn for_test<R: Rows>(&self, c: &Ctx<R>, v: &mut Vectors, st: &mut State) -> f64 {
        match (self.exact.get(), self.guess) {
            (Some(&a), _) | (None, Some(a)) => a,
            (None, None) => self.exact(c, v, st),
        }
    }

    /// ᾱ from this solve's bound of ‖Ŵ‖, computed on the first call.
    fn exact<R: Rows>(&self, c: &Ctx<R>, v: &mut Vectors, st: &mut State) -> f64 {
        *self.exact.get_or_init(|| step_length(c, v, st))
    }

    /// The value a later solve may take as its guess.
    pub fn known(&self) -> Option<f64> {
        self.exact.get().copied().or(self.guess)
    }
}

/// The sums one iteration takes from y, by [`measure`].
struct Sums {
    /// βᵀβ and φ̃ᵀφ, for the proportioning test.
    bb: f64,
    ff: f64,
    /// φᵀŴp, p the last direction (with `CONJ`; else 0), for the next conjugate one.
    fap: f64,
}

/// The state of y: residual (math note §4.3, as PC reports it) and ||z||_inf into `st`;
/// returns the [`Sums`], or None on a NaN. Without `RESIDUAL`, only the sums: for an iteration
/// whose y a sweep has measured with the same sums (the run's first, by the contract of
/// [`run`], and the one after an expansion), so `st` keeps them. With `CONJ`, also φᵀŴp
/// (`wyt` = Ŵp of the last CG step), in the same order as a pass of its own would sum it.
fn measure<R: Rows, const RESIDUAL: bool, const CONJ: bool>(
    c: &Ctx<R>,
    v: &mut Vectors,
    st: &mut State,
    abar: f64,
) -> Option<Sums> {
    let n = v.y.len();
    let Vectors { y: ys, ylo, yhi, wy, wyt, lo: zlo, hi: zhi, parts, .. } = v;
    let (ys, ylo, yhi, wy, wyt, zlo, zhi) =
        (&ys[..], &ylo[..], &yhi[..], &wy[..], &wyt[..], &zlo[..], &zhi[..]);
    let (qs, sc, gs, dd) = (c.qs, c.sc, c.gs, c.dd);
    let t = par::fold(c.par, n, parts, |r0, m| {
        let (mut res, mut gap, mut zn, mut bad) = (0.0f64, 0.0f64, 0.0f64, 0.0);
        let (mut bb, mut ff, mut fap) = (0.0, 0.0, 0.0);
        // the block's rows of every vector, so that the loop's indexing needs no bounds checks
        let b = || r0..r0 + m;
        let (ys, ylo, yhi, wy, wyt) = (&ys[b()], &ylo[b()], &yhi[b()], &wy[b()], &wyt[b()]);
        let (zlo, zhi, qs, sc, gs, dd) = (&zlo[b()], &zhi[b()], &qs[b()], &sc[b()], &gs[b()], &dd[b()]);
        for i in 0..m {
            let (y, lo, hi) = (ys[i], ylo[i], yhi[i]);
            let g = qs[i] + wy[i];
            if RESIDUAL {
                let z = unscale(y, lo, hi, zlo[i], zhi[i], sc[i]);
                let (r, rg) = c.measure.row(z, gs[i] * g, zlo[i], zhi[i], dd[i]);
                res = larger(r, res);
                gap = larger(rg, gap);
                zn = larger(z.abs(), zn);
            }
            let b = chopped(y, lo, hi, g);
            bb += b * b;
            let f = free(y, lo, hi, g);
            // Reduced free gradient: no longer than the step ᾱ φ that stays in the box.
            let fr = if f > 0.0 { smaller((y - lo) / abar, f) } else { larger((y - hi) / abar, f) };
            ff += fr * f;
            if CONJ {
                fap += f * wyt[i];
            }
            bad += y * 0.0 + g * 0.0;
        }
        Partial { s0: bb, s1: ff, s2: fap, s3: bad, m0: res, m1: gap, m2: zn, ..Partial::default() }
    });
    if RESIDUAL {
        st.res = Measure::combine(t.m0, t.m1, t.m2);
        st.znorm = t.m2;
        st.fresh = true;
        st.last_infeasible = false;
    }
    (t.s3 == 0.0).then_some(Sums { bb: t.s0, ff: t.s1, fap: t.s2 })
}

/// The next direction p: φ(y), or β(y) for a proportioning step (`Direction::Chopped`), or
/// φ − γ p conjugate to the last one (γ = φᵀŴp / pᵀŴp).
#[derive(Clone, Copy)]
enum Direction {
    Free,
    Chopped,
    Conjugate(f64),
}

fn set_direction(c: &Ctx<impl Rows>, v: &mut Vectors, direction: Direction) {
    let Vectors { y, wy, yt, ylo, yhi, parts, .. } = v;
    let (y, wy, ylo, yhi, qs) = (&y[..], &wy[..], &ylo[..], &yhi[..], c.qs);
    par::run1(c.par, yt, parts, |r0, p| {
        // the block's rows of every vector, so that the loop's indexing needs no bounds checks
        let b = || r0..r0 + p.len();
        let (y, wy, ylo, yhi, qs) = (&y[b()], &wy[b()], &ylo[b()], &yhi[b()], &qs[b()]);
        for i in 0..p.len() {
            let (yi, lo, hi, g) = (y[i], ylo[i], yhi[i], qs[i] + wy[i]);
            p[i] = match direction {
                Direction::Free => free(yi, lo, hi, g),
                Direction::Chopped => chopped(yi, lo, hi, g),
                Direction::Conjugate(gamma) => free(yi, lo, hi, g) - gamma * p[i],
            };
        }
        Partial::default()
    });
}

/// wyt = Ŵp; returns (pᵀŴp, gᵀp, α_f), α_f the largest step y − αp that stays in the box.
fn product(c: &Ctx<impl Rows>, v: &mut Vectors, st: &mut State) -> (f64, f64, f64) {
    st.stats.products += 1;
    let Vectors { y, wy, yt, wyt, ylo, yhi, tmp, parts, .. } = v;
    c.rows.prepare(yt, wyt, tmp);
    let (y, wy, ylo, yhi, yt, qs) = (&y[..], &wy[..], &ylo[..], &yhi[..], &yt[..], c.qs);
    let t = par::run1(c.par, wyt, parts, |r0, wo| {
        let (mut pap, mut gp, mut af) = (0.0, 0.0, f64::INFINITY);
        let m = wo.len();
        let b = || r0..r0 + m;
        let (y, wy, ylo, yhi, p, qs) = (&y[b()], &wy[b()], &ylo[b()], &yhi[b()], &yt[b()], &qs[b()]);
        for i in 0..m {
            let ap = c.rows.row(r0 + i, yt, wo[i]);
            wo[i] = ap;
            pap += p[i] * ap;
            gp += (qs[i] + wy[i]) * p[i];
            if p[i] > 0.0 {
                af = smaller((y[i] - ylo[i]) / p[i], af);
            } else if p[i] < 0.0 {
                af = smaller((y[i] - yhi[i]) / p[i], af);
            }
        }
        Partial { s0: pap, s1: gp, lo: af, ..Partial::default() }
    });
    (t.s0, t.s1, t.lo.max(0.0))
}

/// y −= α p, Ŵy −= α Ŵp.
fn step(c: &Ctx<impl Rows>, v: &mut Vectors, st: &mut State, alpha: f64) {
    st.steps = st.steps.saturating_add(1);
    let Vectors { y, wy, yt, wyt, ylo, yhi, parts, .. } = v;
    let (yt, wyt, ylo, yhi) = (&yt[..], &wyt[..], &ylo[..], &yhi[..]);
    par::run2(c.par, y, wy, parts, |r0, y, wy| {
        let b = || r0..r0 + y.len();
        let (yt, wyt, ylo, yhi, wy) = (&yt[b()], &wyt[b()], &ylo[b()], &yhi[b()], &mut wy[..y.len()]);
        for i in 0..y.len() {
            y[i] = clip(y[i] - alpha * yt[i], ylo[i], yhi[i]);
            wy[i] -= alpha * wyt[i];
        }
        Partial::default()
    });
}

/// Expansion: y = P[y − ᾱ φ(y)], then a full product. The y and Ŵy it started from are kept in
/// `y_before` and `wy_before` (the vectors' storage swapped, not copied: [`swap_before`]).
fn expand<R: Rows>(c: &Ctx<R>, v: &mut Vectors, st: &mut State, abar: f64) -> bool {
    swap_before(v);
    let Vectors { y, y_before: y0, wy_before: wy, ylo, yhi, parts, .. } = v;
    let (y0, wy, ylo, yhi, qs) = (&y0[..], &wy[..], &ylo[..], &yhi[..], c.qs);
    par::run1(c.par, y, parts, |r0, y| {
        let b = || r0..r0 + y.len();
        let (y0, wy, ylo, yhi, qs) = (&y0[b()], &wy[b()], &ylo[b()], &yhi[b()], &qs[b()]);
        for i in 0..y.len() {
            let (lo, hi) = (ylo[i], yhi[i]);
            y[i] = clip(y0[i] - abar * free(y0[i], lo, hi, qs[i] + wy[i]), lo, hi);
        }
        Partial::default()
    });
    sweep(c, v, st)
}

/// Swaps y and Ŵy with `y_before` and `wy_before`: before an [`expand`], which then writes the
/// new y from the old; after one, to undo it.
fn swap_before(v: &mut Vectors) {
    std::mem::swap(&mut v.y, &mut v.y_before);
    std::mem::swap(&mut v.wy, &mut v.wy_before);
}

/// The expansion (after the step to the box boundary), with the step length ᾱ it used: this
/// solve's exact ᾱ once it has one; before that the guess, whose step is kept when it decreased
/// the cost f(y) = ½ yᵀŴy + q̂ᵀy. That is what the expansion needs of ᾱ <= 2/‖Ŵ‖: along the step
/// d of a projected gradient step, f(y + d) − f(y) <= −|d|²/ᾱ + ½ dᵀŴd (math note §4.8). A
/// step that did not decrease f is undone (y and Ŵy restored) and done again with the exact ᾱ.
/// (Restored by swapping storage back: copying y and Ŵy before each try was 2 % of a warm step
/// of the 40,000-disk pile, perf, all of it on one core.)
fn expand_step<R: Rows>(
    c: &Ctx<R>,
    v: &mut Vectors,
    st: &mut State,
    length: &StepLength,
) -> Result<f64, Status> {
    let expanded = |v: &mut Vectors, st: &mut State, a: f64| {
        if expand(c, v, st, a) { Ok(a) } else { Err(Status::NonFinite) }
    };
    let guess = match (length.exact.get(), length.guess) {
        (None, Some(g)) => g,
        _ => {
            let a = length.exact(c, v, st);
            return expanded(v, st, a);
        }
    };
    let before = cost(c, v);
    if expand(c, v, st, guess) && cost(c, v) <= before {
        return Ok(guess);
    }
    swap_before(v);
    let a = length.exact(c, v, st);
    expanded(v, st, a)
}

/// f(y) = ½ yᵀŴy + q̂ᵀy from `wy` = Ŵy.
fn cost<R: Rows>(c: &Ctx<R>, v: &mut Vectors) -> f64 {
    let Vectors { y, wy, parts, .. } = v;
    let (y, wy, qs) = (&y[..], &wy[..], c.qs);
    par::fold(c.par, y.len(), parts, |r0, m| {
        let b = || r0..r0 + m;
        let (y, wy, qs) = (&y[b()], &wy[b()], &qs[b()]);
        Partial { s0: (0..m).map(|i| y[i] * (0.5 * wy[i] + qs[i])).sum(), ..Partial::default() }
    })
    .s0
}

/// When a run's face solves come (math note §4.10).
struct Faces {
    next: usize,
    interval: usize,
    /// The run's faces need `face::EPS` (`face::solve` sets it).
    regularize: bool,
}

impl Faces {
    /// The first after `face::first` iterations of the run.
    fn new(st: &State, rows: usize, inner_tol: f64) -> Faces {
        let first = face::first(rows, st.res, inner_tol);
        Faces { next: st.inner + first, interval: face::EVERY, regularize: false }
    }

    /// A face solve when one is due: its outcome (`v.wy` fresh after it), else `None`.
    fn due<R: Rows>(&mut self, c: &Ctx<R>, v: &mut Vectors, st: &mut State) -> Result<Option<Face>, Status> {
        if st.inner < self.next {
            return Ok(None);
        }
        let outcome = face::solve(c, v, st, &mut self.regularize)?;
        self.interval = match outcome {
            Face::Unavailable => usize::MAX,
            Face::Taken(alpha) if alpha >= face::GOOD => face::EVERY,
            Face::Taken(_) | Face::Declined => self.interval.saturating_mul(face::BACKOFF),
        };
        self.next = st.inner.saturating_add(self.interval);
        Ok(Some(outcome))
    }
}

/// One MPRGP run down to its goal, with the same contract as `pc::run`: the sweep over y
/// is fresh on entry (wy = Ŵy), y lies in the box; `Ok` when the tolerance is met.
///
/// Passes over the rows are made only where their results are used, with the same results bit
/// for bit as a pass per quantity:
/// - a CG step's next direction is made at the top of the next iteration, after the stop test,
///   with φᵀŴp summed by that iteration's measure: a run that a CG step ends (a warm step of
///   the 1,000-disk pile) makes no direction it does not use;
/// - when a sweep has measured y (the caller's before the run, an expansion's, a refresh's, a
///   taken face solve's), the stop test reads it, and the measure computes only the sums.
pub(super) fn run<R: Rows>(
    c: &Ctx<R>,
    v: &mut Vectors,
    st: &mut State,
    goal: &mut Goal,
    limit: f64,
    max_iterations: usize,
    step_length: &StepLength,
) -> Result<(), Status> {
    let mut abar = None; // a start that meets the tolerance stops without ᾱ
    let mut since_refresh = 0;
    let mut cg = None; // p is a CG direction, with this pᵀŴp (else it restarts from φ)
    let mut faces = Faces::new(st, v.y.len(), goal.tol);
    let mut swept = true; // a sweep measured y: its results are in `st`
    loop {
        if swept && let Some(end) = stop(st, goal, limit, max_iterations) {
            return end;
        }
        let a = *abar.get_or_insert_with(|| step_length.for_test(c, v, st));
        debug_assert!(!swept || cg.is_none(), "every sweep restarts the directions");
        let sums = match (swept, cg.is_some()) {
            (true, _) => measure::<R, false, false>(c, v, st, a),
            (false, true) => measure::<R, true, true>(c, v, st, a),
            (false, false) => measure::<R, true, false>(c, v, st, a),
        };
        let Some(sums) = sums else { return Err(Status::NonFinite) };
        if !swept && let Some(end) = stop(st, goal, limit, max_iterations) {
            return end;
        }
        swept = false;
        match faces.due(c, v, st)? {
            Some(Face::Taken(_)) => {
                (since_refresh, cg, swept) = (0, None, true);
                continue;
            }
            // a declined solve's last sweep (after its trials) overwrote p with PC's trial point
            Some(Face::Declined) => cg = None,
            _ => {}
        }
        st.inner += 1;
        let proportional = sums.bb <= GAMMA * GAMMA * sums.ff;
        let direction = match cg {
            _ if !proportional => Direction::Chopped,
            Some(pap) => Direction::Conjugate(sums.fap / pap),
            None => Direction::Free,
        };
        set_direction(c, v, direction);
        match step_along(c, v, st, proportional, step_length)? {
            Stepped::Conjugate(pap) => {
                since_refresh += 1;
                cg = Some(pap);
            }
            Stepped::Restart => cg = None,
            Stepped::Expanded(a) => {
                abar = Some(a);
                (since_refresh, cg, swept) = (0, None, true);
            }
        }
        if since_refresh >= REFRESH {
            // (`sweep` also overwrites p with PC's trial point: restart the directions.)
            if !sweep(c, v, st) {
                return Err(Status::NonFinite);
            }
            (since_refresh, cg, swept) = (0, None, true);
        }
    }
}

/// What a step along −p left behind: CG may go on (with this pᵀŴp), the directions restart
/// (after a proportioning step), or an expansion step moved y (with ᾱ for the next one); its
/// projected step ended in a sweep, so its results are in `st`.
enum Stepped {
    Conjugate(f64),
    Restart,
    Expanded(f64),
}

/// One step of `run` along −p: a proportioning step (not `proportional`) kept inside the box,
/// a CG step to the exact minimizer along −p when the box allows it, else a step to the box
/// followed by an expansion step.
fn step_along<R: Rows>(
    c: &Ctx<R>,
    v: &mut Vectors,
    st: &mut State,
    proportional: bool,
    step_length: &StepLength,
) -> Result<Stepped, Status> {
    let (pap, gp, af) = product(c, v, st);
    if !(pap.is_finite() && gp.is_finite()) {
        return Err(Status::NonFinite);
    }
    // Exact minimizer along −p (+inf on a direction of zero curvature).
    let acg = if pap > 0.0 { gp / pap } else { f64::INFINITY };
    if gp <= 0.0 && !(pap > 0.0) {
        return Err(Status::Stalled);
    }
    if acg.min(af) == f64::INFINITY {
        // A descent direction of zero curvature that the box does not stop: a ray.
        return Err(Status::Diverged);
    }
    Ok(if !proportional {
        // Proportioning step, kept inside the box.
        step(c, v, st, acg.min(af));
        Stepped::Restart
    } else if acg <= af {
        step(c, v, st, acg);
        Stepped::Conjugate(pap)
    } else {
        step(c, v, st, af);
        Stepped::Expanded(expand_step(c, v, st, step_length)?)
    })
}

/// ᾱ, the expansion step length, below 2/||Ŵ|| as the method needs: from the bound >= ||Ŵ||
/// of `Rows::norm_bound` (see the constants); without one (an operator with factored
/// clusters), 1 / λ, λ the estimate of ||Ŵ|| by 10 power iterations from the all-ones vector
/// (an estimate from below, safe while it is above ||Ŵ|| / 2, which 10 iterations reach on W's
/// of contact networks: λ = 3.99998 on the 1 000-disk pile, whose Gershgorin bound is 6).
fn step_length<R: Rows>(c: &Ctx<R>, v: &mut Vectors, st: &mut State) -> f64 {
    let from_bound = c.rows.norm_bound(&mut v.tmp).map(|b| match b {
        Bound::Gershgorin(g) => (ABAR_GERSHGORIN, g),
        Bound::Operator(b) => (ABAR_OPERATOR, b),
    });
    if let Some((factor, b)) = from_bound.filter(|(_, b)| *b > 0.0 && b.is_finite()) {
        return factor / b;
    }
    let n = v.y.len();
    let Vectors { yt, wyt, tmp, .. } = v;
    yt.iter_mut().for_each(|x| *x = 1.0);
    let mut lambda = 0.0;
    for _ in 0..10 {
        st.stats.products += 1;
        c.rows.prepare(yt, wyt, tmp);
        let mut norm = 0.0f64;
        for (i, w) in wyt.iter_mut().enumerate() {
            *w = c.rows.row(i, yt, *w);
            norm = norm.max(w.abs());
        }
        if !(norm > 0.0 && norm.is_finite()) {
            break;
        }
        lambda = norm;
        for i in 0..n {
            yt[i] = wyt[i] / norm;
        }
    }
    if lambda > 0.0 { 1.0 / lambda } else { 1.0 }
}
