//! The methods' hand-overs (math note §4.7, §4.8, §4.12, §4.13): NSGS to Lemke (on small
//! Coulomb problems), the cell program (on Coulomb problems Lemke does not solve) and then PC
//! when its stall guard stops it; MPRGP to NSGS on W's entries, then to the same, when its
//! passes stop short of the tolerance.

use super::{BoundRule, Options, Problem, Report, Solver, Stats, Status, cell, lemke, newton, nsgs};

/// The share of the budget MPRGP leaves for its hand-overs (1/2) when NSGS can take them: on
/// the 1,000 deformable disks' cold steps MPRGP's passes spent the whole budget and ended at
/// 7e-2, where NSGS from the warm start reaches 5e-6 with the same budget (math note §4.8,
/// "MPRGP's fallbacks").
pub const HANDOVER_SHARE: usize = 2;

impl Solver {
    pub(super) fn solve_nsgs(
        &mut self,
        w: sprs::CsMatView<f64>,
        p: &Problem,
        rule: &dyn BoundRule,
        z: &mut [f64],
        opts: &Options,
    ) -> Report {
        let mut stats = Stats::default();
        match self.nsgs.run(w, p.q, p.blocks, rule, z, opts, &mut stats) {
            nsgs::End::Done { sweeps, residual, converged } => {
                self.stats = stats;
                Report { outer_iterations: 1, inner_iterations: sweeps, residual, converged }
            }
            nsgs::End::Fallback { sweeps, residual } => {
                self.best.start();
                self.best.offer(residual, z);
                let mut r = self.fallback(w, p, rule, z, opts, sweeps);
                r.inner_iterations += sweeps;
                self.stats.products += stats.products;
                self.stats.fallbacks = 1;
                r
            }
        }
    }

    /// MPRGP with the iteration budget, less a [`HANDOVER_SHARE`] of it when W has entries for
    /// NSGS; if it stops short of the tolerance (the pass limit, a stalled step or its share:
    /// not on a divergent or non-finite problem, which PC would report the same), NSGS from the
    /// caller's warm start on W's entries with what is left (its answer kept if it uses that
    /// up), and if its stall guard stops it, Lemke's method on problems it takes (math note
    /// §4.12), then PC from the warm start with the rest (math note §4.8, "MPRGP's fallbacks").
    pub(super) fn solve_mprgp(
        &mut self,
        p: &Problem,
        rule: &dyn BoundRule,
        z: &mut [f64],
        opts: &Options,
    ) -> Report {
        let reserve = match p.w.as_csr().is_some() || p.w.has_entries() {
            true => opts.max_iterations / HANDOVER_SHARE,
            false => 0,
        };
        let share = Options { max_iterations: opts.max_iterations - reserve, ..*opts };
        let r = self.solve_pc(p, rule, z, &share, true);
        let hopeless =
            matches!(self.stats.status, Status::Diverged | Status::NonFinite | Status::InvalidInput);
        if r.converged || hopeless || r.inner_iterations >= opts.max_iterations {
            return r;
        }
        let (mut spent, mut products) = (r.inner_iterations, self.stats.products);
        self.best.start();
        self.best.offer_run(&r, self.stats.status, z);
        // the caller's warm start, which the run kept (it reaches here only past its setup)
        z.copy_from_slice(&self.vectors.z0);
        let owned = p.w.as_csr().is_none().then(|| from_entries(p)).flatten();
        let w = p.w.as_csr().or(owned.as_ref().map(|w| w.view()));
        if let Some(w) = w.filter(|w| nsgs::applicable(w, p.blocks)) {
            let mut stats = Stats::default();
            let budget = Options { max_iterations: opts.max_iterations - spent, ..*opts };
            match self.nsgs.run(w, p.q, p.blocks, rule, z, &budget, &mut stats) {
                nsgs::End::Done { sweeps, residual, converged } => {
                    self.stats = Stats { products: products + stats.products, fallbacks: 1, ..stats };
                    let (outer_iterations, inner_iterations) = (r.outer_iterations + 1, spent + sweeps);
                    let mut r2 = Report { outer_iterations, inner_iterations, residual, converged };
                    self.best.keep(&mut r2, self.stats.status, z);
                    return r2;
                }
                nsgs::End::Fallback { sweeps, residual } => {
                    self.best.offer(residual, z);
                    (spent, products) = (spent + sweeps, products + stats.products);
                    if let Some(r2) = self.pivot(w, p, rule, z, opts, (r.outer_iterations, spent), products) {
                        return r2;
                    }
                    z.copy_from_slice(self.nsgs.warm_start());
                }
            }
        }
        let rest = Options { max_iterations: opts.max_iterations.saturating_sub(spent), ..*opts };
        let mut r2 = self.solve_pc(p, rule, z, &rest, false);
        r2.inner_iterations += spent;
        r2.outer_iterations += r.outer_iterations;
        self.stats.products += products;
        self.stats.fallbacks = 1;
        self.best.keep(&mut r2, self.stats.status, z);
        r2
    }

    /// Semismooth Newton (math note §4.16) on W's entries from the warm start; when it fails,
    /// or W has no entries or blocks it takes, the chain of `method = "mprgp"` from the warm
    /// start with what is left of the budget (`Stats.fallbacks` = 1).
    pub(super) fn solve_newton(
        &mut self,
        p: &Problem,
        rule: &dyn BoundRule,
        z: &mut [f64],
        opts: &Options,
    ) -> Report {
        let owned = p.w.as_csr().is_none().then(|| from_entries(p)).flatten();
        let w = p.w.as_csr().or(owned.as_ref().map(|w| w.view()));
        let Some(w) = w.filter(|w| nsgs::applicable(w, p.blocks)) else {
            return self.solve_mprgp(p, rule, z, opts);
        };
        let mut products = 0;
        let (steps, residual) = match self.newton.run(w, p.q, p.blocks, rule, z, opts, &mut products) {
            newton::End::Done { steps, residual } => (steps, residual),
            newton::End::Failed { steps } => (steps, f64::INFINITY),
        };
        if residual <= opts.tolerance {
            self.stats = Stats { status: Status::Converged, products, ..Stats::default() };
            return Report { outer_iterations: 1, inner_iterations: steps, residual, converged: true };
        }
        let rest = Options { max_iterations: opts.max_iterations.saturating_sub(steps), ..*opts };
        let mut r = self.solve_mprgp(p, rule, z, &rest);
        r.inner_iterations += steps;
        r.outer_iterations += 1;
        self.stats.products += products;
        self.stats.fallbacks = 1;
        r
    }

    /// Stall guard (math note §4.7): Lemke's method and the cell program on problems they take
    /// (§4.12, §4.13); else PC from
    /// the NSGS iterate with half of what is left of the iteration budget; if that fails, PC
    /// from the caller's warm start with the rest, which is what `method = "pc"` would have run
    /// (a ray of an unbounded problem, say, is judged against the warm start's scale, not
    /// against the grown NSGS iterate).
    fn fallback(
        &mut self,
        w: sprs::CsMatView<f64>,
        p: &Problem,
        rule: &dyn BoundRule,
        z: &mut [f64],
        opts: &Options,
        sweeps: usize,
    ) -> Report {
        let left = opts.max_iterations.saturating_sub(sweeps);
        if let Some(r) = self.pivot(w, p, rule, z, &Options { max_iterations: left, ..*opts }, (0, 0), 0) {
            return r;
        }
        let first = Options { max_iterations: left / 2, ..*opts };
        let r = self.solve_pc(p, rule, z, &first, false);
        if r.converged {
            return r;
        }
        self.best.offer_run(&r, self.stats.status, z);
        let products = self.stats.products;
        z.copy_from_slice(self.nsgs.warm_start());
        let rest = Options { max_iterations: left - r.inner_iterations.min(left), ..*opts };
        let mut r2 = self.solve_pc(p, rule, z, &rest, false);
        r2.inner_iterations += r.inner_iterations;
        r2.outer_iterations += r.outer_iterations;
        self.stats.products += products;
        self.best.keep(&mut r2, self.stats.status, z);
        r2
    }

    /// Lemke's method (math note §4.12) after the other methods, on problems it takes, and where
    /// it gives no answer the cell program from z (§4.13, while the budget has iterations
    /// left, unless `opts.cell` is off): the report when one meets the tolerance, z then its answer, counting the passes and
    /// iterations `before` it (one pass more, Lemke's pivots as iterations, within what is left
    /// of the budget; the program counts none) and the products made before it; `None`
    /// otherwise, with z and the stats untouched.
    #[allow(clippy::too_many_arguments)]
    fn pivot(
        &mut self,
        w: sprs::CsMatView<f64>,
        p: &Problem,
        rule: &dyn BoundRule,
        z: &mut [f64],
        opts: &Options,
        before: (usize, usize),
        products: usize,
    ) -> Option<Report> {
        let budget = opts.max_iterations.saturating_sub(before.1);
        let check = &mut self.check;
        let mut measure = |x: &[f64]| check.residual(p, rule, x, opts);
        let limits = (opts.tolerance, budget);
        let (pivots, residual) = match lemke::solve(w, p, rule, z, limits, &mut measure, &mut self.best) {
            Some(done) => done,
            None if budget > 0 && opts.cell => {
                (0, cell::solve(w, p, rule, z, opts, &mut measure, &mut self.best)?)
            }
            None => return None,
        };
        self.stats = Stats { status: Status::Converged, fallbacks: 1, pivots, products, ..Stats::default() };
        let (outer_iterations, inner_iterations) = (before.0 + 1, before.1 + pivots);
        Some(Report { outer_iterations, inner_iterations, residual, converged: true })
    }
}

/// W in CSR from the operator's entries (all rows; duplicates summed), or `None` when it has
/// none at hand (factored clusters): for NSGS, whose sweeps read W's rows.
fn from_entries(p: &Problem) -> Option<sprs::CsMat<f64>> {
    let n = p.q.len();
    let mut entries = Vec::new();
    if !p.w.entries(&vec![true; n], &mut entries) {
        return None;
    }
    let mut w = sprs::TriMat::with_capacity((n, n), entries.len());
    entries.into_iter().for_each(|(i, j, v)| w.add_triplet(i, j, v));
    Some(w.to_csr())
}

/// The answer of smallest residual a chain of methods has reached (math note §4.7, "The best
/// answer of a failed chain"). A method that hands over leaves an iterate the next one may
/// not improve on: on the 1,000-disk slump's wall strike (§4.8) NSGS stalls at 5.4e-4 and PC,
/// started afresh, ends at 4.3e-3. A chain that ends unconverged returns the best of them.
#[derive(Debug, Clone, Default)]
pub(super) struct Best {
    residual: f64,
    z: Vec<f64>,
}

impl Best {
    /// Forgets the last chain's answer (no allocation: the storage is kept).
    pub fn start(&mut self) {
        self.residual = f64::INFINITY;
    }

    /// Keeps z if its residual is smaller than the best so far (not NaN).
    pub fn offer(&mut self, residual: f64, z: &[f64]) {
        if residual < self.residual {
            self.residual = residual;
            self.z.clear();
            self.z.extend_from_slice(z);
        }
    }

    /// Offers a run's answer if it is an iterate ([`kept_iterate`]).
    pub fn offer_run(&mut self, r: &Report, status: Status, z: &[f64]) {
        if kept_iterate(status) {
            self.offer(r.residual, z);
        }
    }

    /// Ends the chain: an unconverged answer that is an iterate gives way to the best one if
    /// that has a smaller residual (z and the report's residual then are the best one's).
    pub fn keep(&self, r: &mut Report, status: Status, z: &mut [f64]) {
        if !r.converged && kept_iterate(status) && self.residual < r.residual && self.z.len() == z.len() {
            z.copy_from_slice(&self.z);
            r.residual = self.residual;
        }
    }
}

/// Statuses whose z is an unconverged iterate of the problem: not the warm start handed back
/// with a diverged or non-finite problem, nor an answer to invalid bounds or input, which must
/// stay as the status describes them.
pub(super) fn kept_iterate(status: Status) -> bool {
    matches!(status, Status::IterationLimit | Status::OuterLimit | Status::Stalled)
}
