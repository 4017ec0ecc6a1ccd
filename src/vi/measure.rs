//! The convergence measure (math note §4.3, §4.9): the scaled natural residual in force units,
//! and, when the caller gives a gap tolerance, the same residual in gap units.
//!
//! Row i's natural residual is `r_i = |z_i − P[z_i − G_i / D_ii]|` (force units). The force
//! part of the measure is `max_i r_i / max(1, ||z||_inf)`: relative to the largest force, it
//! cannot see a light body's contact when a heavy body's contacts carry 1e12 times more. The
//! gap part, `tolerance · max_i D_ii r_i / (gap_tol + ROUND · eps · D_ii |z_i|)`, is what row
//! i's gap or slip is still wrong by, in units of `gap_tol`, scaled so that both parts meet
//! the same threshold (`tolerance`). The second term of the denominator is the round-off
//! floor of G_i itself, whose largest term is typically D_ii z_i: a gap cannot be asked to be
//! more accurate than it can be computed.

use super::{BoundRule, Options, Problem};

/// Multiple of the unit round-off in the floor of the gap part (about the number of terms
/// summed into one G_i, with margin).
const ROUND: f64 = 16.0;

/// The measure's settings for one call.
#[derive(Debug, Clone, Copy)]
pub(super) struct Measure {
    /// tolerance, or 0 without a gap tolerance.
    weight: f64,
    gap_tol: f64,
}

impl Measure {
    pub fn new(opts: &Options) -> Measure {
        let g = opts.gap_tolerance;
        if g > 0.0 && g.is_finite() && opts.tolerance > 0.0 {
            Measure { weight: opts.tolerance, gap_tol: g }
        } else {
            Measure { weight: 0.0, gap_tol: 1.0 }
        }
    }

    /// Row i's (force, gap) parts from its iterate z, D⁻¹G (`dg`), bounds and diagonal `d`.
    #[inline(always)]
    pub fn row(&self, z: f64, dg: f64, lo: f64, hi: f64, d: f64) -> (f64, f64) {
        let r = (z - super::pc::clip(z - dg, lo, hi)).abs();
        if self.weight == 0.0 {
            return (r, 0.0);
        }
        let floor = ROUND * f64::EPSILON * d * z.abs();
        (r, self.weight * d * r / (self.gap_tol + floor))
    }

    /// The reported residual from the maxima of the parts and ||z||_inf.
    #[inline(always)]
    pub fn combine(force: f64, gap: f64, znorm: f64) -> f64 {
        (force / znorm.max(1.0)).max(gap)
    }
}

/// The running maxima of the measure over the rows (force part, gap part, ||z||_inf) with a
/// detector of NaN and infinity: the loop body of the whole-vector measures (NSGS's checks,
/// [`Check`], `residual_again`). PC's sweeps keep their own, fused and split in halves.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Tally {
    force: f64,
    gap: f64,
    pub znorm: f64,
    bad: f64,
}

impl Tally {
    /// Adds row i: its iterate z, D⁻¹G (`dg`), bounds and diagonal `d` ([`Measure::row`]).
    #[inline(always)]
    pub fn add(&mut self, measure: &Measure, z: f64, dg: f64, lo: f64, hi: f64, d: f64) {
        let (r, rg) = measure.row(z, dg, lo, hi, d);
        self.force = super::pc::larger(r, self.force);
        self.gap = super::pc::larger(rg, self.gap);
        self.znorm = super::pc::larger(z.abs(), self.znorm);
        self.bad += z * 0.0 + dg * 0.0;
    }

    /// The reported residual ([`Measure::combine`]); `None` when a value was not finite.
    pub fn value(&self) -> Option<f64> {
        self.bad.is_finite().then(|| Measure::combine(self.force, self.gap, self.znorm))
    }
}

/// The residual of an answer measured on its own, from one product with W (math note §4.3): G
/// = q + W z, the bounds the rule gives at z, and [`Measure`] row by row, D the diagonal of W
/// (1 where it is not positive, as the scaling takes it). For the answers PC and MPRGP leave
/// unconverged: their passes measure the iterate against the box of the pass's start, which a
/// QVI's iterate has moved from, and unscale it into that box. The storage is kept between
/// calls.
#[derive(Debug, Clone, Default)]
pub(super) struct Check {
    g: Vec<f64>,
    d: Vec<f64>,
    lo: Vec<f64>,
    hi: Vec<f64>,
}

impl Check {
    /// The measure at z; +inf when the bounds are invalid or a value is not finite.
    pub fn residual(&mut self, p: &Problem, rule: &dyn BoundRule, z: &[f64], opts: &Options) -> f64 {
        let n = p.q.len();
        for v in [&mut self.g, &mut self.d, &mut self.lo, &mut self.hi] {
            v.clear();
            v.resize(n, 0.0);
        }
        p.w.apply(z, &mut self.g);
        p.w.diagonal(&mut self.d);
        rule.all_bounds(p.blocks, z, &mut self.lo, &mut self.hi);
        let (measure, mut tally) = (Measure::new(opts), Tally::default());
        let rows = z.iter().zip(p.q).zip(&self.g).zip(&self.d).zip(self.lo.iter().zip(&self.hi));
        for ((((&zi, &qi), &wz), &d), (&l, &h)) in rows {
            if l > h || l.is_nan() || h.is_nan() {
                return f64::INFINITY;
            }
            let d = if d > 0.0 && d.is_finite() { d } else { 1.0 };
            tally.add(&measure, zi, (qi + wz) / d, l, h, d);
        }
        tally.value().unwrap_or(f64::INFINITY)
    }
}

/// Where a run may stop (math note §4.11), shared by PC, MPRGP and NSGS: at its start if that
/// is within `tol` (a start within the tolerance is kept); else at `aim`, or within `tol` one
/// count after it first met `tol`, the count being iterations (PC, MPRGP) or residual checks
/// (NSGS). A problem whose floor lies between the two pays that one count.
#[derive(Debug, Clone, Copy)]
pub(super) struct Goal {
    pub tol: f64,
    aim: f64,
    /// No state was judged yet: the next one is the run's start.
    start: bool,
    /// The count at which a state within `tol` ends the run, once one was met.
    deadline: Option<usize>,
}

impl Goal {
    /// A run down to `tol`, and on to `aim` (at most `tol`) for one count.
    pub fn new(tol: f64, aim: f64) -> Goal {
        Goal { tol, aim: aim.min(tol), start: true, deadline: None }
    }

    /// Whether the run may stop at a state of residual `res` after `count` iterations or checks.
    pub fn reached(&mut self, res: f64, count: usize) -> bool {
        let start = std::mem::replace(&mut self.start, false);
        if res <= self.aim || (start && res <= self.tol) {
            true
        } else if res <= self.tol {
            count >= *self.deadline.get_or_insert(count + 1)
        } else {
            false
        }
    }
}

impl super::Solver {
    /// The residual a solve of `q` on the W of the last [`Self::solve`] would measure at the z
    /// that solve returned (`z`), with the same bounds (the same rule at the same z): from the
    /// product its last sweep made, as [`Self::gaps`], without a new product; `None` when there
    /// is no such product. The world uses it to skip a velocity solve that its warm start
    /// already meets (math note §10.5). Equal to what that solve would measure up to the
    /// rounding of that product.
    pub fn residual_again(&self, q: &[f64], z: &[f64], opts: &Options) -> Option<f64> {
        let (v, s) = (&self.vectors, &self.scaling);
        let n = q.len();
        if !(self.exact && [z.len(), v.wy.len(), v.lo.len(), v.hi.len(), s.sc.len()].iter().all(|&m| m == n))
        {
            return None;
        }
        let (measure, gs, mut tally) = (Measure::new(opts), s.gs(), Tally::default());
        for i in 0..n {
            let f = s.sc[i] * q[i] + v.wy[i];
            tally.add(&measure, z[i], gs[i] * f, v.lo[i], v.hi[i], s.dd[i]);
        }
        tally.value()
    }
}
