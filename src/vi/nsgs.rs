//! Nonsmooth block Gauss-Seidel (NSGS) over the blocks, as in LMGC90 and Siconos (math note
//! §4.7): block k in turn is solved exactly ([`super::local`]) with the other blocks' values
//! fixed, its bounds taken from the bound rule at the current iterate (so a joint partner's
//! latest forces are seen at once, and no outer passes are needed). Every few sweeps the
//! scaled natural residual of math note §4.3 is evaluated with the bounds of the current
//! iterate: the same test and reported value as PC. A stall guard hands slow runs to the next
//! method of the chain (math note §4.17); a run that uses up its budget keeps its iterate.

// NaN-safe `!(a <= b)` tests.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::local::{Local, MAX};
use super::measure::{Goal, Measure, Tally};
use super::{BoundRule, Options, Stats, Status};
use crate::sparse::CsrView;

/// Sweeps between residual checks once the first few are done.
pub(super) const CHECK_EVERY: usize = 8;
/// Stall guard (math note §4.7): the residual must halve within this many sweeps, or within
/// a [`STALL_SHARE`]th of the run's budget if that is more, else the chain's next method
/// takes over.
pub const STALL_SWEEPS: usize = 400;
/// The share of its budget a run may spend on one plateau: NSGS on a pile that moves sits on
/// plateaus of up to some 5,000 sweeps before a contact changes state and it converges
/// (math note §4.8, "Piles that move").
pub const STALL_SHARE: usize = 20;

/// Work storage, reused across calls.
#[derive(Debug, Clone, Default)]
pub(super) struct Work {
    /// Per block: its m×m diagonal block of W (stride MAX).
    diag: Vec<[[f64; MAX]; MAX]>,
    /// Bounds of the current iterate (residual) and the warm start.
    lo: Vec<f64>,
    hi: Vec<f64>,
    z0: Vec<f64>,
}

/// How an NSGS run ended.
pub(super) enum End {
    /// The residual met the tolerance (`converged`), or the budget is used up short of it:
    /// z holds the last iterate, of this residual (nothing is left for another method to
    /// start from the warm start).
    Done { sweeps: usize, residual: f64, converged: bool },
    /// Hand over to PC from the current z (stall, or a block it cannot solve); z holds the
    /// iterate to warm-start from, of this residual (+inf when it was not measured or z is
    /// the warm start again).
    Fallback { sweeps: usize, residual: f64 },
}

/// Can NSGS take this problem? Blocks of 1..=MAX rows with positive finite diagonals.
pub(super) fn applicable(w: &CsrView<'_>, blocks: &[usize]) -> bool {
    let ok_blocks = blocks.windows(2).all(|b| (1..=MAX).contains(&(b[1] - b[0])));
    ok_blocks && w.is_csr()
}

impl Work {
    #[allow(clippy::too_many_arguments)]
    /// Runs NSGS from z (overwritten). `stats.products` counts sweeps and residual checks
    /// (each one pass over W).
    pub fn run(
        &mut self,
        w: CsrView<'_>,
        q: &[f64],
        blocks: &[usize],
        rule: &dyn BoundRule,
        z: &mut [f64],
        opts: &Options,
        stats: &mut Stats,
    ) -> End {
        let n = q.len();
        self.z0.clear();
        self.z0.extend_from_slice(z);
        if !self.setup(w, blocks, n) {
            return End::Fallback { sweeps: 0, residual: f64::INFINITY };
        }
        let (indptr, cols, vals) = (w.indptr(), w.indices(), w.data());
        let indptr = indptr.as_slice().unwrap_or(&[]);
        if indptr.len() != n + 1 {
            return End::Fallback { sweeps: 0, residual: f64::INFINITY };
        }
        let cap = opts.max_iterations;
        // Growth test as in PC (module docs of `vi`): iterates beyond growth * S run along a
        // ray of an unbounded problem; PC from the warm start then reports it.
        let tol = opts.tolerance;
        let growth = if tol > 0.0 { (1e-2 / tol).clamp(1e4, 1e8) } else { 1e8 };
        let limit = growth * self.start_scale(indptr, cols, vals, q, z).max(opts.force_scale);
        let measure = Measure::new(opts);
        let (mut ref_res, mut ref_at) = (f64::INFINITY, 0usize);
        // counted in residual checks (math note §4.11); a stall or the cap with the tolerance
        // met converges
        let mut goal = Goal::new(tol, opts.aim * tol);
        let (mut sweeps, mut checks) = (0, 0);
        let window = STALL_SWEEPS.max(cap / STALL_SHARE);
        loop {
            if sweeps <= 4 || sweeps % CHECK_EVERY == 0 || sweeps >= cap {
                stats.products += 1;
                let (res, zn) = self.residual(indptr, cols, vals, q, blocks, rule, z, measure);
                if !res.is_finite() || zn > limit {
                    z.copy_from_slice(&self.z0);
                    return End::Fallback { sweeps, residual: f64::INFINITY };
                }
                let met = res <= tol;
                let stalled = res > 0.5 * ref_res && sweeps - ref_at >= window;
                if goal.reached(res, checks) || (met && (stalled || sweeps >= cap)) {
                    stats.status = Status::Converged;
                    return End::Done { sweeps, residual: res, converged: true };
                }
                if sweeps >= cap {
                    stats.status = Status::IterationLimit;
                    return End::Done { sweeps, residual: res, converged: false };
                }
                if res <= 0.5 * ref_res {
                    (ref_res, ref_at) = (res, sweeps);
                } else if stalled {
                    return End::Fallback { sweeps, residual: res };
                }
                checks += 1;
            }
            stats.products += 1;
            self.sweep(indptr, cols, vals, q, blocks, rule, z);
            sweeps += 1;
        }
    }

    /// Extracts the diagonal blocks; false when a block has a non-positive or non-finite
    /// diagonal entry or a column index out of range.
    fn setup(&mut self, w: CsrView<'_>, blocks: &[usize], n: usize) -> bool {
        self.diag.clear();
        for b in blocks.windows(2) {
            let mut a = [[0.0; MAX]; MAX];
            for i in b[0]..b[1] {
                let Some(row) = w.outer_view(i) else { return false };
                for (j, &v) in row.iter() {
                    if j >= n {
                        return false;
                    }
                    if (b[0]..b[1]).contains(&j) {
                        a[i - b[0]][j - b[0]] += v;
                    }
                }
                let d = a[i - b[0]][i - b[0]];
                if !(d > 0.0 && d.is_finite()) {
                    return false;
                }
            }
            self.diag.push(a);
        }
        for v in [&mut self.lo, &mut self.hi] {
            v.clear();
            v.resize(n, 0.0);
        }
        true
    }

    /// One Gauss-Seidel sweep over the blocks in order (math note §4.7).
    #[allow(clippy::too_many_arguments)]
    fn sweep(
        &mut self,
        indptr: &[usize],
        cols: &[usize],
        vals: &[f64],
        q: &[f64],
        blocks: &[usize],
        rule: &dyn BoundRule,
        z: &mut [f64],
    ) {
        // Rules without a closed form: the box of the iterate at the start of the sweep.
        let mut have_box = false;
        for (k, b) in blocks.windows(2).enumerate() {
            let (r0, m) = (b[0], b[1] - b[0]);
            let mut l = Local { m, a: self.diag[k], r: [0.0; MAX] };
            let mut zk = [0.0; MAX];
            zk[..m].copy_from_slice(&z[r0..r0 + m]);
            // r = q_k + (W z)_k − A z_k
            for i in 0..m {
                let row = r0 + i;
                let mut acc = q[row];
                for p in indptr[row]..indptr[row + 1] {
                    acc += vals[p] * z[cols[p]];
                }
                l.r[i] = acc - (0..m).map(|j| l.a[i][j] * zk[j]).sum::<f64>();
            }
            let _exact = match rule.block_law(k, z).filter(|_| m >= 2) {
                Some(law) => l.solve_law(&law, &mut zk),
                None => {
                    if !have_box {
                        rule.all_bounds(blocks, z, &mut self.lo, &mut self.hi);
                        have_box = true;
                    }
                    l.solve_box(&self.lo[r0..r0 + m], &self.hi[r0..r0 + m], &mut zk)
                }
            };
            z[r0..r0 + m].copy_from_slice(&zk[..m]);
        }
    }

    /// The scaled natural residual of math note §4.3 with the bounds of z:
    /// ||z − P[z − D⁻¹ G(z)]||_inf / max(1, ||z||_inf); +inf when a NaN appears or the bounds
    /// are invalid.
    #[allow(clippy::too_many_arguments)]
    fn residual(
        &mut self,
        indptr: &[usize],
        cols: &[usize],
        vals: &[f64],
        q: &[f64],
        blocks: &[usize],
        rule: &dyn BoundRule,
        z: &[f64],
        measure: Measure,
    ) -> (f64, f64) {
        rule.all_bounds(blocks, z, &mut self.lo, &mut self.hi);
        let mut tally = Tally::default();
        for b in blocks.windows(2) {
            for i in b[0]..b[1] {
                let (mut g, mut d) = (q[i], 0.0);
                for p in indptr[i]..indptr[i + 1] {
                    g += vals[p] * z[cols[p]];
                    if cols[p] == i {
                        d += vals[p];
                    }
                }
                let (l, h) = (self.lo[i], self.hi[i]);
                if !(l <= h) {
                    return (f64::INFINITY, 0.0);
                }
                tally.add(&measure, z[i], g / d, l, h, d);
            }
        }
        (tally.value().unwrap_or(f64::INFINITY), tally.znorm)
    }

    /// S = max(1, ||D⁻¹q||_inf, ||z_start||_inf) of the growth test.
    fn start_scale(&self, indptr: &[usize], cols: &[usize], vals: &[f64], q: &[f64], z: &[f64]) -> f64 {
        let mut s = 1.0f64;
        for i in 0..q.len() {
            let d: f64 = (indptr[i]..indptr[i + 1]).filter(|&p| cols[p] == i).map(|p| vals[p]).sum();
            s = s.max((q[i] / d).abs()).max(z[i].abs());
        }
        s
    }
}
