//! The inner solver: self-adaptive projection-contraction (math note §4.2) on the scaled
//! variables y = D^{1/2} z, with the fused sweeps that carry its products.

use super::measure::{Goal, Measure};
use super::par::{self, BLOCK, Partial};
use super::scaling::{Rows, Scaling};
use super::{Correction, Stats, Status};

const NU: f64 = 0.9;
const MU_S: f64 = 0.4;
const GAMMA: f64 = 1.8;
const SHRINK: f64 = 0.7;
const ENLARGE: f64 = 1.5;
/// beta stays within [1e-30, 1e30] * beta_0.
const BETA_RANGE: f64 = 1e30;

/// Read-only inputs of one call: the scaled W, the scaling vectors and the settings.
pub(super) struct Ctx<'a, R: Rows> {
    pub rows: R,
    /// Sweeps run on both cores (`par.rs`).
    pub par: bool,
    pub correction: Correction,
    pub sd: &'a [f64],
    pub sc: &'a [f64],
    pub gs: &'a [f64],
    pub qs: &'a [f64],
    /// D (guarded), for the gap part of the residual.
    pub dd: &'a [f64],
    pub measure: Measure,
    /// Rows of W that are entirely zero.
    pub zero_rows: &'a [usize],
    /// Inner solver of the passes: PC, or MPRGP with its step length ᾱ (`mprgp.rs`).
    pub mprgp: Option<super::mprgp::StepLength>,
}

impl<'a, R: Rows> Ctx<'a, R> {
    pub fn new(rows: R, s: &'a Scaling, par: bool, correction: Correction, measure: Measure) -> Self {
        Ctx {
            rows,
            par,
            correction,
            sd: &s.sd,
            sc: &s.sc,
            gs: s.gs(),
            qs: &s.qs,
            dd: &s.dd,
            measure,
            zero_rows: &s.zero_rows,
            mprgp: None,
        }
    }
}

/// Work vectors of length n (reused across calls).
#[derive(Debug, Clone, Default)]
pub(super) struct Vectors {
    pub y: Vec<f64>,
    /// Ŵ y.
    pub wy: Vec<f64>,
    /// Trial point P[y − beta (q̂ + Ŵ y)].
    pub yt: Vec<f64>,
    /// Ŵ yt.
    pub wyt: Vec<f64>,
    /// Box of the current pass (unscaled) and of the previous one.
    pub lo: Vec<f64>,
    pub hi: Vec<f64>,
    pub lo_prev: Vec<f64>,
    pub hi_prev: Vec<f64>,
    /// Box of the current pass in y.
    pub ylo: Vec<f64>,
    pub yhi: Vec<f64>,
    /// Warm start, restored on failure.
    pub z0: Vec<f64>,
    /// Scratch for matrix-free products.
    pub tmp: Vec<f64>,
    /// y and Ŵy before the last MPRGP expansion (`mprgp::expand`; swapped with `y` and `wy`).
    pub y_before: Vec<f64>,
    pub wy_before: Vec<f64>,
    pub parts: Vec<Partial>,
}

impl Vectors {
    /// Sizes everything for n rows and starts from the warm start z (y = sd z). Only `y` and
    /// `z0` are set here: every other vector is written before it is read (the first pass
    /// writes the box and sweeps; MPRGP and PC write their directions and products), so its
    /// entries from an earlier call are kept rather than zeroed (3 % of a warm step of the
    /// 1,000-disk pile went to zeroing them).
    pub fn start(&mut self, z: &[f64], sd: &[f64], par: bool) {
        let n = z.len();
        for v in [
            &mut self.y,
            &mut self.wy,
            &mut self.yt,
            &mut self.wyt,
            &mut self.lo,
            &mut self.hi,
            &mut self.lo_prev,
            &mut self.hi_prev,
            &mut self.ylo,
            &mut self.yhi,
            &mut self.z0,
            &mut self.tmp,
            &mut self.y_before,
            &mut self.wy_before,
        ] {
            v.resize(n, 0.0);
        }
        self.parts.clear();
        self.parts.resize(n.div_ceil(BLOCK), Partial::default());
        let (z0, y) = (&mut self.z0[..n], &mut self.y[..n]);
        par::run2(par, z0, y, &mut self.parts, |r0, z0, y| {
            let b = r0..r0 + z0.len();
            let (z, sd, y) = (&z[b.clone()], &sd[b], &mut y[..z0.len()]);
            for i in 0..z0.len() {
                z0[i] = z[i];
                y[i] = if z[i].is_finite() { z[i] * sd[i] } else { 0.0 };
            }
            Partial::default()
        });
    }
}

/// Iteration state shared by the outer loop and the PC runs.
#[derive(Debug, Clone, Copy)]
pub(super) struct State {
    pub beta: f64,
    pub beta_min: f64,
    pub beta_max: f64,
    pub inner: usize,
    pub outer: usize,
    /// Results of the last sweep over y: residual, ||z||_inf, ||y − yt||².
    pub res: f64,
    pub znorm: f64,
    pub ee: f64,
    /// A sweep has been made (its results above are those of the current y unless y moved).
    pub fresh: bool,
    /// MPRGP steps since the last sweep: each updates `wy` along with y ([`Self::exact`]).
    pub steps: u32,
    /// y lay outside the box at the last sweep (contraction step only).
    pub last_infeasible: bool,
    /// A valid box exists (from an earlier pass).
    pub have_prev: bool,
    /// max(0, max |finite bound|) of the current box.
    pub bmax: f64,
    /// y is still the scaled warm start at the last box (`outer::new_box`): the answer is the
    /// warm start itself.
    pub kept: bool,
    pub stats: Stats,
}

impl State {
    pub fn new(beta0: f64) -> Self {
        State {
            beta: beta0,
            beta_min: beta0 / BETA_RANGE,
            beta_max: beta0 * BETA_RANGE,
            inner: 0,
            outer: 0,
            res: f64::INFINITY,
            znorm: 0.0,
            ee: 0.0,
            fresh: false,
            steps: 0,
            last_infeasible: false,
            have_prev: false,
            bmax: 0.0,
            kept: false,
            stats: Stats::default(),
        }
    }

    /// `wy` is Ŵy of the current y to the rounding of a full product: a sweep's product, or
    /// one updated along with a single MPRGP step since. One update, wy − α Ŵp with Ŵp itself
    /// a full product, adds the rounding of one more term to each row's sum, inside the margin
    /// of the measure's round-off floor (`measure::ROUND`); more updates accumulate, and
    /// MPRGP's own refresh bounds them only against drift.
    pub fn exact(&self) -> bool {
        self.fresh && self.steps <= 1
    }
}

/// Projection onto [lo, hi] (lo <= hi checked by the caller). Unlike `f64::clamp` it never
/// panics; a NaN x gives lo, as `x.max(lo).min(hi)` would.
#[inline(always)]
pub(super) fn clip(x: f64, lo: f64, hi: f64) -> f64 {
    smaller(larger(x, lo), hi)
}

/// The larger of a and b, by one comparison (x86's `maxsd`): b when they are equal or a is NaN,
/// so that `acc = larger(x, acc)` skips a NaN x as `acc.max(x)` does. For the row loops:
/// `f64::max` adds a NaN fix-up to every call (math note §3.3, "The VI's own loops"). On numbers
/// the results are the same, bit for bit.
#[inline(always)]
pub(super) fn larger(a: f64, b: f64) -> f64 {
    if a > b { a } else { b }
}

/// The smaller of a and b (see [`larger`]): b when they are equal or a is NaN.
#[inline(always)]
pub(super) fn smaller(a: f64, b: f64) -> f64 {
    if a < b { a } else { b }
}

/// The unscaled iterate z = D^{-1/2} y, snapped so that an active scaled bound maps to the
/// exact unscaled bound and lo <= z <= hi holds exactly.
#[inline(always)]
pub(super) fn unscale(y: f64, ylo: f64, yhi: f64, lo: f64, hi: f64, sc: f64) -> f64 {
    if y <= ylo {
        lo
    } else if y >= yhi {
        hi
    } else {
        clip(sc * y, lo, hi)
    }
}

/// z = the unscaled y (see [`unscale`]).
pub(super) fn unscale_into<R: Rows>(c: &Ctx<R>, v: &mut Vectors, z: &mut [f64]) {
    let Vectors { y, lo, hi, ylo, yhi, parts, .. } = v;
    let sc = c.sc;
    par::run1(c.par, z, parts, |r0, zo| {
        // the block's rows of every vector, so that the loop's indexing needs no bounds checks
        let b = || r0..r0 + zo.len();
        let (y, ylo, yhi, lo, hi, sc) = (&y[b()], &ylo[b()], &yhi[b()], &lo[b()], &hi[b()], &sc[b()]);
        for (k, zk) in zo.iter_mut().enumerate() {
            *zk = unscale(y[k], ylo[k], yhi[k], lo[k], hi[k], sc[k]);
        }
        par::Partial::default()
    });
}

/// Clips y into the scaled box.
pub(super) fn project<R: Rows>(c: &Ctx<R>, v: &mut Vectors) {
    let Vectors { y, ylo, yhi, parts, .. } = v;
    par::map(c.par, y, parts, |i, yi| *yi = clip(*yi, ylo[i], yhi[i]));
}

/// One fused pass over the rows: `wy = Ŵ y`, the residual of z = D^{-1/2} y with
/// D⁻¹ G(z) = gs ∘ (q̂ + Ŵ y) (math note §4.3), and the trial point
/// `yt = P[y − beta (q̂ + Ŵ y)]`. Counts the product and stores the results in `st`;
/// returns false when a NaN or infinity appeared in y or G(y).
pub(super) fn sweep<R: Rows>(c: &Ctx<R>, v: &mut Vectors, st: &mut State) -> bool {
    st.stats.products += 1;
    measure_rows::<R, true>(c, v, st)
}

/// The sweep's measurements without its product, when `wy` already is Ŵy of the current y
/// (`st.exact()`) and only the box changed: the results of [`sweep`] without its product (the
/// same bit for bit when no MPRGP step updated `wy` since the last sweep).
pub(super) fn remeasure<R: Rows>(c: &Ctx<R>, v: &mut Vectors, st: &mut State) -> bool {
    debug_assert!(st.exact());
    measure_rows::<R, false>(c, v, st)
}

/// The fused pass of [`sweep`]; `PRODUCT` false reuses `wy` (a constant, so that the sweep's
/// loop carries no branch for it).
fn measure_rows<R: Rows, const PRODUCT: bool>(c: &Ctx<R>, v: &mut Vectors, st: &mut State) -> bool {
    let Vectors { y, wy, yt, lo, hi, ylo, yhi, tmp, parts, .. } = v;
    if PRODUCT {
        c.rows.prepare(y, wy, tmp);
    }
    let (sc, gs, qs, dd, beta) = (c.sc, c.gs, c.qs, c.dd, st.beta);
    let pt = par::run2(c.par, wy, yt, parts, |r0, wo, to| {
        let mut pt = Partial::default();
        let mut bad = 0.0;
        // the block's rows of every vector, so that the loop's indexing needs no bounds checks
        let m = wo.len();
        let b = || r0..r0 + m;
        let (yb, ylo, yhi, lo, hi) = (&y[b()], &ylo[b()], &yhi[b()], &lo[b()], &hi[b()]);
        let (sc, gs, qs, dd, to) = (&sc[b()], &gs[b()], &qs[b()], &dd[b()], &mut to[..m]);
        for k in 0..m {
            let yi = yb[k];
            let w = if PRODUCT { c.rows.row(r0 + k, y, wo[k]) } else { wo[k] };
            wo[k] = w;
            let f = qs[k] + w;
            let zi = unscale(yi, ylo[k], yhi[k], lo[k], hi[k], sc[k]);
            let (r, rg) = c.measure.row(zi, gs[k] * f, lo[k], hi[k], dd[k]);
            let t = clip(yi - beta * f, ylo[k], yhi[k]);
            to[k] = t;
            let e = yi - t;
            pt.s0 += e * e;
            // Infeasibility of y: a max per block; `reduce` sums the blocks, which keeps
            // "> 0" intact.
            pt.s1 = larger(larger(yi - yhi[k], ylo[k] - yi), pt.s1);
            pt.m0 = larger(r, pt.m0);
            pt.m1 = larger(zi.abs(), pt.m1);
            pt.m2 = larger(rg, pt.m2);
            // NaN/inf detector: `clip` and `max` would swallow a NaN.
            bad += yi * 0.0 + f * 0.0;
        }
        pt.s2 = bad;
        pt
    });
    st.fresh = true;
    st.steps = 0;
    st.last_infeasible = pt.s1 > 0.0;
    st.res = Measure::combine(pt.m0, pt.m2, pt.m1);
    st.znorm = pt.m1;
    st.ee = pt.s0;
    pt.s2.is_finite() && pt.s0.is_finite()
}

/// Where an inner run stops, from the state last measured: divergence (|z| beyond `limit`),
/// the goal reached, or the iteration budget used (shared by PC and MPRGP).
pub(super) fn stop(
    st: &State,
    goal: &mut Goal,
    limit: f64,
    max_iterations: usize,
) -> Option<Result<(), Status>> {
    if st.znorm > limit {
        Some(Err(Status::Diverged))
    } else if goal.reached(st.res, st.inner) {
        Some(Ok(()))
    } else if st.inner >= max_iterations {
        Some(Err(Status::IterationLimit))
    } else {
        None
    }
}

/// One PC run (math note §4.2) down to its goal. Invariant at the loop head: the sweep
/// over y is fresh (wy = Ŵy, yt = P[y − beta F(y)], ee = ||y − yt||², res, znorm).
/// `Ok` when the tolerance is met; `Err` with the reason to stop the whole solve otherwise.
pub(super) fn run<R: Rows>(
    c: &Ctx<R>,
    v: &mut Vectors,
    st: &mut State,
    goal: &mut Goal,
    limit: f64,
    max_iterations: usize,
) -> Result<(), Status> {
    loop {
        if let Some(end) = stop(st, goal, limit, max_iterations) {
            return end;
        }
        let (r, edf, dfdf) = predictor(c, v, st)?;
        correct(c, v, st, edf, dfdf);
        if r <= MU_S {
            st.beta = (st.beta * ENLARGE).min(st.beta_max);
        }
        st.inner += 1;
        if !sweep(c, v, st) {
            return Err(Status::NonFinite);
        }
        if st.last_infeasible && goal.reached(st.res, st.inner) {
            // Contraction step only: accept a point only after projecting it, so the
            // returned z is feasible and the residual is its own.
            project(c, v);
            if !sweep(c, v, st) {
                return Err(Status::NonFinite);
            }
        }
    }
}

/// Predictor with step-size control: wyt = Ŵ yt, shrinking beta (and recomputing yt) until
/// r = beta ||F(y) − F(yt)|| / ||y − yt|| <= nu. Returns (r, eᵀ(F − Ft), |F − Ft|²).
fn predictor<R: Rows>(c: &Ctx<R>, v: &mut Vectors, st: &mut State) -> Result<(f64, f64, f64), Status> {
    loop {
        if st.ee <= 0.0 {
            return Err(Status::Stalled);
        }
        let Vectors { y, wy, yt, wyt, ylo, yhi, tmp, parts, .. } = v;
        c.rows.prepare(yt, wyt, tmp);
        let (y_r, wy_r, yt_r) = (&y[..], &wy[..], &yt[..]);
        let pt = par::run1(c.par, wyt, parts, |r0, wo| {
            let mut pt = Partial::default();
            for (k, wk) in wo.iter_mut().enumerate() {
                let i = r0 + k;
                let w = c.rows.row(i, yt_r, *wk);
                *wk = w;
                let d = wy_r[i] - w; // F(y) − F(yt)
                let e = y_r[i] - yt_r[i];
                pt.s0 += e * d;
                pt.s1 += d * d;
            }
            pt
        });
        st.stats.products += 1;
        if !(pt.s0.is_finite() && pt.s1.is_finite()) {
            return Err(Status::NonFinite);
        }
        let r = st.beta * (pt.s1 / st.ee).sqrt();
        if r <= NU {
            return Ok((r, pt.s0, pt.s1));
        }
        st.beta *= SHRINK * (1.0 / r).min(1.0);
        st.stats.shrinks += 1;
        if st.beta < st.beta_min {
            return Err(Status::Stalled);
        }
        let (beta, qs) = (st.beta, c.qs);
        st.ee = par::run1(c.par, yt, parts, |r0, to| {
            let mut s = 0.0;
            for (k, tk) in to.iter_mut().enumerate() {
                let i = r0 + k;
                let t = clip(y_r[i] - beta * (qs[i] + wy_r[i]), ylo[i], yhi[i]);
                *tk = t;
                s += (y_r[i] - t) * (y_r[i] - t);
            }
            Partial { s0: s, ..Partial::default() }
        })
        .s0;
    }
}

/// Correction step ([`Correction`]): d = e − beta (F − Ft), alpha = eᵀd / dᵀd (> 1/2 since
/// r <= nu < 1), then either the projected extragradient-type step or the plain PC step.
fn correct<R: Rows>(c: &Ctx<R>, v: &mut Vectors, st: &State, edf: f64, dfdf: f64) {
    let (ee, beta) = (st.ee, st.beta);
    let ed = ee - beta * edf;
    let dd = ee - 2.0 * beta * edf + beta * beta * dfdf;
    let alpha = ed / dd;
    let Vectors { y, wy, yt, wyt, ylo, yhi, parts, .. } = v;
    let qs = c.qs;
    match c.correction {
        Correction::Extragradient => {
            let step = GAMMA * alpha * beta;
            par::map(c.par, y, parts, |i, yi| {
                *yi = clip(*yi - step * (qs[i] + wyt[i]), ylo[i], yhi[i]);
            });
        }
        Correction::Contraction => {
            let step = GAMMA * alpha;
            par::map(c.par, y, parts, |i, yi| {
                let d = (*yi - yt[i]) - beta * (wy[i] - wyt[i]);
                *yi -= step * d;
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{clip, larger, smaller};

    /// `larger`, `smaller` and `clip` stand in for `f64::max`, `f64::min` and `x.max(lo).min(hi)`
    /// in the row loops (their doc comments): on numbers they agree with the standard library's
    /// values (±0 compare equal), an accumulator `acc = larger(x, acc)` skips a NaN x as
    /// `acc.max(x)` does (std's documented rule: a NaN argument yields the other one), and `clip`
    /// maps a NaN to lo. Checked over every pair of a set with zeros, infinities and NaN.
    #[test]
    fn comparisons_agree_with_std_on_numbers_and_skip_nan() {
        let values = [f64::NEG_INFINITY, -3.5, -0.0, 0.0, 1e-300, 2.0, f64::INFINITY, f64::NAN];
        for &a in &values {
            for &b in values.iter().filter(|b| !b.is_nan()) {
                assert_eq!(larger(a, b), b.max(a), "larger({a}, {b})");
                assert_eq!(smaller(a, b), b.min(a), "smaller({a}, {b})");
            }
        }
        for &x in &values {
            for (lo, hi) in [(-1.0, 1.0), (0.0, f64::INFINITY), (f64::NEG_INFINITY, -0.0), (2.0, 2.0)] {
                let want = if x.is_nan() { lo } else { x.max(lo).min(hi) };
                assert_eq!(clip(x, lo, hi), want, "clip({x}, {lo}, {hi})");
            }
        }
    }
}
