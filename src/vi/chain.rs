//! The chain of methods (math note §4.17): [`Solver::solve`] runs the methods of its
//! [`Chain`] in order until one answers, all of them drawing on one budget of work
//! (`Options::max_iterations`, in the units of §4.17), and returns the answer of the method
//! that answered, or the best answer of the chain when none did (§4.7, "The best answer of a
//! failed chain").

use super::{BoundRule, Method, Options, Problem, Report, Solver, Stats, Status, cell, lemke, newton, nsgs};
use crate::sparse::{Csr, CsrView};

/// The share of what is left of the budget a method leaves to NSGS when NSGS follows it and W
/// has entries (one in `HANDOVER_SHARE`): on the 1,000 deformable disks' cold steps MPRGP's
/// passes spent the whole budget and ended at 7e-2, where NSGS from the warm start reaches
/// 5e-6 with the same budget (math note §4.8, "MPRGP's fallbacks").
pub const HANDOVER_SHARE: usize = 2;

/// A method of the chain that gave the problem to the next one (listed in `run.log`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HandOver {
    pub from: Method,
    pub to: Method,
    /// Why `from` did not answer.
    pub why: &'static str,
}

/// How one method's run ended.
enum End {
    /// Its answer is the chain's: it met the tolerance, or nothing is left to try (the budget
    /// is spent, the problem has no bounded solution, NSGS used its whole share).
    Answer(Report),
    /// It hands the problem over to the next method that takes it, for this reason.
    Over(Report, &'static str),
}

impl Solver {
    /// Runs the chain (math note §4.17): each method that takes the problem in turn, from the
    /// caller's warm start (Lemke and the cell program from where the method before left z),
    /// with what is left of the budget (less [`HANDOVER_SHARE`] when NSGS follows), until one
    /// answers. PC solves a problem that no method of the chain takes.
    pub(super) fn solve_chain(
        &mut self,
        p: &Problem,
        rule: &dyn BoundRule,
        z: &mut [f64],
        opts: &Options,
    ) -> Report {
        let chain = self.chain;
        let methods = chain.methods();
        self.warm.clear();
        self.warm.extend_from_slice(z);
        self.best.start();
        self.handovers.clear();
        let mut owned = None;
        let (mut outer, mut spent, mut products) = (0, 0, 0);
        // the method that handed over, its report and why
        let mut over: Option<(Method, Report, &'static str)> = None;
        let mut answer = None;
        for (i, &m) in methods.iter().enumerate() {
            let left = opts.max_iterations.saturating_sub(spent);
            let w = match m.needs_entries() {
                true => match entries(p, &mut owned).filter(|w| nsgs::applicable(w, p.blocks)) {
                    Some(w) => Some(w),
                    None => continue,
                },
                false => None,
            };
            if over.is_some() && left == 0 {
                continue;
            }
            if let Some((from, _, why)) = over {
                self.handovers.push(HandOver { from, to: m, why });
            }
            if !matches!(m, Method::Lemke | Method::Cell) {
                z.copy_from_slice(&self.warm);
            }
            let nsgs_next = methods.get(i + 1) == Some(&Method::Nsgs) && has_entries(p);
            let share = if nsgs_next { left - left / HANDOVER_SHARE } else { left };
            self.best.at(m);
            let end = self.run_method(m, w, p, rule, z, &Options { max_iterations: share, ..*opts });
            products += self.stats.products;
            let r = match end {
                End::Answer(r) | End::Over(r, _) => r,
            };
            (outer, spent) = (outer + r.outer_iterations, spent + r.inner_iterations);
            match end {
                End::Over(r, why) if spent < opts.max_iterations => over = Some((m, r, why)),
                _ => {
                    answer = Some((m, r));
                    break;
                }
            }
        }
        let Some((method, r)) = answer.or(over.map(|(m, r, _)| (m, r))) else {
            // no method of the chain takes the problem
            let r = self.solve_pc(p, rule, z, opts, false);
            self.stats.method = Some(Method::Pc);
            return r;
        };
        let mut report = Report { outer_iterations: outer, inner_iterations: spent, ..r };
        self.stats.products = products;
        self.stats.fallbacks = usize::from(!self.handovers.is_empty());
        let best = self.best.keep(&mut report, self.stats.status, z);
        self.stats.method = Some(best.unwrap_or(method));
        report
    }

    /// One method's run with the budget in `opts` (`w`: W's CSR for the methods that read its
    /// entries); `self.stats` then holds its counters.
    fn run_method(
        &mut self,
        m: Method,
        w: Option<CsrView>,
        p: &Problem,
        rule: &dyn BoundRule,
        z: &mut [f64],
        opts: &Options,
    ) -> End {
        let w = match (m, w) {
            (Method::Pc | Method::Mprgp, _) | (_, None) => {
                return self.run_pc(m == Method::Mprgp, p, rule, z, opts);
            }
            (_, Some(w)) => w,
        };
        let check = &mut self.check;
        let mut measure = |x: &[f64]| check.residual(p, rule, x, opts);
        let (work, residual, why) = match m {
            Method::Nsgs => return self.run_nsgs(w, p, rule, z, opts),
            Method::Newton => return self.run_newton(w, p, rule, z, opts),
            Method::Lemke => {
                let limits = (opts.tolerance, opts.max_iterations);
                match lemke::solve(w, p, rule, z, limits, &mut measure, &mut self.best) {
                    Ok((pivots, residual)) => (pivots, Some(residual), ""),
                    Err(pivots) => (pivots, None, "no answer"),
                }
            }
            _ => {
                let budget = opts.max_iterations;
                let (work, end) = cell::solve(w, p, rule, z, opts, budget, &mut measure, &mut self.best);
                (work, end, "no answer")
            }
        };
        let pivots = if m == Method::Lemke { work } else { 0 };
        self.stats = Stats { pivots, ..Stats::default() };
        match residual {
            Some(residual) => End::Answer(answered(work, residual)),
            None => self.no_answer(missed(work, f64::INFINITY), why),
        }
    }

    /// NSGS: its answer when it meets the tolerance or uses its whole share, else its stall
    /// guard hands over, its iterate offered to the chain's best.
    fn run_nsgs(
        &mut self,
        w: CsrView,
        p: &Problem,
        rule: &dyn BoundRule,
        z: &mut [f64],
        opts: &Options,
    ) -> End {
        let mut stats = Stats::default();
        let end = self.nsgs.run(w, p.q, p.blocks, rule, z, opts, &mut stats);
        self.stats = stats;
        match end {
            nsgs::End::Done { sweeps, residual, converged } => {
                End::Answer(Report { converged, ..answered(sweeps, residual) })
            }
            nsgs::End::Fallback { sweeps, residual } => {
                self.best.offer(residual, z);
                End::Over(missed(sweeps, residual), "stall guard")
            }
        }
    }

    /// Semismooth Newton: its answer when it meets the tolerance, else (z the warm start
    /// again) a hand-over.
    fn run_newton(
        &mut self,
        w: CsrView,
        p: &Problem,
        rule: &dyn BoundRule,
        z: &mut [f64],
        opts: &Options,
    ) -> End {
        let mut products = 0;
        let (steps, residual) = match self.newton.run(w, p.q, p.blocks, rule, z, opts, &mut products) {
            newton::End::Done { steps, residual } => (steps, residual),
            newton::End::Failed { steps } => (steps, f64::INFINITY),
        };
        self.stats = Stats { products, ..Stats::default() };
        match residual <= opts.tolerance {
            true => End::Answer(answered(steps, residual)),
            false => self.no_answer(missed(steps, residual), "failed"),
        }
    }

    /// A run of a method that ends without an answer of its own (z as it found it, or the
    /// warm start again): status [`Status::Stalled`].
    fn no_answer(&mut self, r: Report, why: &'static str) -> End {
        self.stats.status = Status::Stalled;
        End::Over(r, why)
    }

    /// PC's outer loop with PC or MPRGP (`mprgp`) passes: its answer when it meets the
    /// tolerance or the problem has no bounded solution (the next method would find the same),
    /// else a hand-over, its iterate offered to the chain's best.
    fn run_pc(
        &mut self,
        mprgp: bool,
        p: &Problem,
        rule: &dyn BoundRule,
        z: &mut [f64],
        opts: &Options,
    ) -> End {
        let r = self.solve_pc(p, rule, z, opts, mprgp);
        let status = self.stats.status;
        let why = match status {
            Status::Converged | Status::Diverged | Status::NonFinite | Status::InvalidInput => {
                return End::Answer(r);
            }
            Status::IterationLimit => "iteration limit of its share",
            Status::OuterLimit => "outer limit",
            Status::Stalled => "stalled",
            Status::InvalidBounds => "invalid bounds",
        };
        self.best.offer_run(&r, status, z);
        End::Over(r, why)
    }
}

/// The report of a method that met the tolerance after `work` units (one pass).
fn answered(work: usize, residual: f64) -> Report {
    Report { outer_iterations: 1, inner_iterations: work, residual, converged: true }
}

/// The report of a method that did not.
fn missed(work: usize, residual: f64) -> Report {
    Report { outer_iterations: 1, inner_iterations: work, residual, converged: false }
}

/// W has entries at hand (CSR storage, or an operator that lists them).
fn has_entries(p: &Problem) -> bool {
    p.w.as_csr().is_some() || p.w.has_entries()
}

/// W's CSR: its own storage, or `owned`, built from the operator's entries the first time a
/// method asks (`None` inside when the operator has none).
fn entries<'a>(p: &'a Problem, owned: &'a mut Option<Option<Csr>>) -> Option<CsrView<'a>> {
    match p.w.as_csr() {
        Some(w) => Some(w),
        None => owned.get_or_insert_with(|| from_entries(p)).as_ref().map(|w| w.view()),
    }
}

/// W in CSR from the operator's entries (all rows; duplicates summed), or `None` when it has
/// none at hand (factored clusters): for the methods that read W's rows.
fn from_entries(p: &Problem) -> Option<Csr> {
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
    /// The method whose iterate it is, and the method now running.
    method: Option<Method>,
    current: Option<Method>,
}

impl Best {
    /// Forgets the last chain's answer (no allocation: the storage is kept).
    pub fn start(&mut self) {
        self.residual = f64::INFINITY;
        self.method = None;
    }

    /// The method whose answers are offered next.
    pub fn at(&mut self, m: Method) {
        self.current = Some(m);
    }

    /// Keeps z if its residual is smaller than the best so far (not NaN).
    pub fn offer(&mut self, residual: f64, z: &[f64]) {
        if residual < self.residual {
            self.residual = residual;
            self.z.clear();
            self.z.extend_from_slice(z);
            self.method = self.current;
        }
    }

    /// Offers a run's answer if it is an iterate ([`kept_iterate`]).
    pub fn offer_run(&mut self, r: &Report, status: Status, z: &[f64]) {
        if kept_iterate(status) {
            self.offer(r.residual, z);
        }
    }

    /// Ends the chain: an unconverged answer that is an iterate gives way to the best one if
    /// that has a smaller residual (z and the report's residual then are the best one's); the
    /// method of the answer kept instead, if any.
    pub fn keep(&self, r: &mut Report, status: Status, z: &mut [f64]) -> Option<Method> {
        if !r.converged && kept_iterate(status) && self.residual < r.residual && self.z.len() == z.len() {
            z.copy_from_slice(&self.z);
            r.residual = self.residual;
            return self.method;
        }
        None
    }
}

/// Statuses whose z is an unconverged iterate of the problem: not the warm start handed back
/// with a diverged or non-finite problem, nor an answer to invalid bounds or input, which must
/// stay as the status describes them.
pub(super) fn kept_iterate(status: Status) -> bool {
    matches!(status, Status::IterationLimit | Status::OuterLimit | Status::Stalled)
}
