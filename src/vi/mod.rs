//! Box-constrained affine variational inequality solver (math note §4). Pure mathematics:
//! it knows nothing about bodies or contacts.
//!
//! Find z in Ω = [lo, hi] with (z' − z)ᵀ G(z) >= 0 for all z' in Ω, G(z) = q + W z,
//! W symmetric positive semidefinite, seen as an [`Operator`] (products and diagonal, plus
//! its CSR storage when it is explicit). The rows come in blocks (one per contact); the
//! bounds may depend on z (a QVI) and a [`BoundRule`] recomputes them block by block in the
//! outer compatibility loop.
//!
//! # Algorithm
//!
//! * **Outer loop** (math note §4.3, compatibility iteration; `outer.rs`). Pass m asks the
//!   [`BoundRule`] for the box of the current iterate (one [`BoundRule::block_bounds`] call
//!   per block), clips the iterate into it and runs the inner solver from there. It stops at
//!   the first pass m >= 1 whose bounds differ from those of pass m − 1 by at most
//!   `eps_out * max(1, max|finite bound|)` (`eps_out = tolerance`) *and* whose clipped
//!   iterate already has a scaled natural residual of at most `tolerance` with these bounds.
//!   [`Report::outer_iterations`] counts PC runs (a plain VI reports 1: one run, then a
//!   confirming pass that finds the same box) and `max_outer` caps them. The first PC run
//!   goes down to `tolerance`; later runs stop earlier while the box still moves
//!   ([`Solver::inexact`], the math note leaves the inner accuracy per pass open).
//! * **Inner solver** (math note §4.2; `pc.rs`): the self-adaptive projection-contraction
//!   (PC) method with nu = 0.9, mu_s = 0.4, gamma = 1.8, beta_0 = 1 / max_j W_jj (1 in
//!   Jacobi-scaled variables), shrink beta ← 0.7 min(1, 1/r) beta, enlarge beta ← 1.5 beta
//!   when r <= mu_s. `W z` is stored, so an iteration costs two products with W (one for
//!   the trial point, one for the new iterate) plus one per rejected trial step; each PC
//!   run adds one product for its starting point. (A single product per iteration is not
//!   possible: both G(zt) and G(z_new) are needed, at points that are not linear
//!   combinations of stored products.)
//! * **Correction step**: both variants of §4.2 exist ([`Correction`]); the default is the
//!   extragradient-type step z = P_Ω[z − gamma alpha beta G(zt)], which keeps the iterate
//!   feasible and needed fewer W-products on every problem set measured (see
//!   `benches/vi.rs`).
//! * **Residual** (math note §4.3):
//!   `res = ||z − P_Ω[z − D⁻¹ G(z)]||_inf / max(1, ||z||_inf)`, `D = diag(W)`. It is the
//!   inner stopping test (except for the inexact passes above) and the reported value. It is
//!   evaluated on the unscaled iterate (`z = D^{-1/2} y`, `D⁻¹ G = D^{-1/2} Ĝ`) inside each
//!   sweep, so the reported residual is that of the returned `z`. With
//!   [`Options::gap_tolerance`] it also measures every row in gap units (math note §4.9,
//!   `measure.rs`), so a light body's contact is solved next to forces 1e12 times larger.
//! * **Zero diagonals.** A row with `W_jj <= 0` (or non-finite) uses `D_jj = 1` in the
//!   residual and in the Jacobi scaling. For a PSD W, `W_jj = 0` forces the whole row and
//!   column to vanish, so `G_j = q_j` is constant: such a row has a solution only if the bound
//!   that `q_j` pushes toward is finite. This is checked at every pass and reported as
//!   [`Status::Diverged`] instead of iterating.
//! * **Jacobi scaling** (`Options::jacobi`; `scaling.rs`): `z = D^{-1/2} y`, so
//!   `Ŵ = D^{-1/2} W D^{-1/2}` has unit diagonal, `q̂ = D^{-1/2} q` and the bounds become
//!   `D^{1/2} lo, D^{1/2} hi` (infinite bounds stay infinite). It is not optional in practice
//!   when rows involving only heavy bodies carry force: with two 1e12-kg bodies in contact
//!   (`vi_kkt`, `jacobi_needed_for_heavy_heavy_contact`) the unscaled solver does not
//!   converge in 20 000 iterations while the scaled one needs a few hundred.
//!
//! # Methods
//!
//! [`Solver::chain`] lists the methods a solve runs ([`Chain`] of [`Method`]s; math note
//! §4.17, `chain.rs`): the PC method below (the reference); nonsmooth block Gauss-Seidel
//! (`nsgs.rs`, `local.rs`; math note §4.7), which solves each block exactly in closed form
//! ([`BoundRule::block_law`]) with the bounds taken at the current iterate (no outer passes)
//! and reports the same §4.3 residual; the outer loop of PC with MPRGP (`mprgp.rs`, math note
//! §4.8) as the inner solver of each pass; a semismooth Newton method on the natural map
//! (`newton.rs`, §4.16); Lemke's pivoting (`lemke.rs`, §4.12) and the cell program
//! (`cell.rs`, §4.13) on small Coulomb problems. Each method that takes the problem runs in
//! turn until one answers; all draw on one budget, [`Options::max_iterations`].
//! [`Stats::method`] names the method that answered and [`Solver::handovers`] lists the
//! hand-overs.
//!
//! # Performance
//!
//! * An explicit W ([`Operator::as_csr`]) is copied once per call with the scaling folded
//!   into its values and `u32` column indices, about the cost of one product; each sweep
//!   then fuses its product with the vector work of the PC step (residual, projection, dot
//!   products), so an iteration makes three passes over the rows. The row loop reads the
//!   iterate without bounds checks (the column indices are checked once, in the copy).
//! * A matrix-free W is applied through [`Operator::apply`] with the Jacobi scaling done by
//!   vectors around each product (two extra passes over the rows per product); it solves
//!   the same problems as the explicit path (`tests/solver/vi_networks.rs`,
//!   `operator_path_matches_csr`), and `benches/vi.rs` (group `vi_products`) times both.
//! * [`Solver`] keeps its work storage across calls: it allocates only when a problem is
//!   larger than every previous one, never inside the iterations.
//! * Rows are processed in blocks of 2 048 (`par.rs`); from [`Solver::parallel_min_rows`]
//!   rows on (default 20 000) the blocks run in two halves, one per core (`micropool::join`).
//!   Block partial sums are reduced in block order, so serial and parallel results are
//!   bit-identical. The body form's product over a scene of single bodies runs in halves from
//!   40,000 segments on (`delassus/bodies.rs`, `HALVES_FROM`, `BodyPart::apply`). Both use
//!   `micropool::join`, whose cost per join is small enough for a second core to pay (math
//!   note §3.3, "Both cores at a join's true cost"; `benches/vi.rs`, `body_form_product`).
//!
//! # Failure modes (never a panic)
//!
//! `converged = false`, with the reason in [`Solver::stats`], when the iteration or outer
//! cap is reached, when a NaN or infinity appears, when the bound rule returns `lo > hi` or
//! NaN, when the input is inconsistent ([`Status::InvalidInput`]), or when the iterates
//! diverge. Divergence test: for a solvable problem the PC iterates are Fejér-monotone (math
//! note §4.2), hence bounded; they are declared divergent when `||z||_inf` exceeds
//! `growth * S`, `S = max(1, ||D⁻¹q||_inf, ||z_start||_inf, max|finite bound|,
//! Options::force_scale)` (the last one: math note §4.9),
//! `growth = clamp(1e-2 / tolerance, 1e4, 1e8)`. The residual is relative to `||z||`, so a
//! ray `z = t d` with `W d = 0`, `qᵀd < 0` (e.g. a particle jammed between two walls closer
//! than its diameter) would eventually pass the residual test; the growth test fires first
//! whenever the violated gap is at least `1e-2 S` in force units. Rays along which beta
//! grows are caught within a few dozen iterations; a ray that advances only linearly (beta
//! held back by the bounded part of the problem) uses up `max_iterations` and ends as
//! [`Status::IterationLimit`]. On divergence or non-finite values the warm start is
//! restored in `z` and the reported residual is `+inf`.
//!
//! # Requirements on the input
//!
//! `W` square, symmetric, PSD, `n = W.dim() = q.len() = z.len()`, blocks a partition of the
//! rows. An explicit W stores both triangles; CSC storage is accepted too (for a symmetric
//! matrix its compressed storage reads the same as CSR). Symmetry and semidefiniteness are
//! not checked (PC only needs monotonicity of G).

mod cell;
mod chain;
mod face;
mod lemke;
mod local;
mod measure;
mod method;
mod mprgp;
mod newton;
mod nsgs;
mod operator;
mod outer;
mod par;
mod pc;
mod scaling;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_aim;
#[cfg(test)]
mod tests_chain;
#[cfg(test)]
mod tests_mprgp;
#[cfg(test)]
mod tests_nsgs;

pub use chain::{HANDOVER_SHARE, HandOver};
pub use method::{Chain, MAX_METHODS, Method};
pub use nsgs::{STALL_SHARE, STALL_SWEEPS};
pub use operator::Operator;
pub use par::all_bounds_in_halves;

/// G(z) = q + W z, with the rows grouped in per-contact blocks: block k is rows
/// `blocks[k]..blocks[k+1]` (`blocks.len()` = number of blocks + 1, `blocks[0] = 0`, last =
/// `q.len()`).
pub struct Problem<'a> {
    pub w: &'a dyn Operator,
    pub q: &'a [f64],
    pub blocks: &'a [usize],
}

impl Problem<'_> {
    /// Dimensions agree and `blocks` partitions the rows (for n = 0, `[]` and `[0]` both do).
    pub fn is_consistent(&self, z: &[f64]) -> bool {
        let n = self.q.len();
        let blocks_ok = match self.blocks {
            [] => n == 0,
            b => b[0] == 0 && b[b.len() - 1] == n && b.windows(2).all(|w| w[0] <= w[1]),
        };
        blocks_ok && self.w.dim() == n && z.len() == n
    }
}

/// Recomputes the box from the current iterate (math note §4.3), block by block.
pub trait BoundRule {
    /// Bounds of block k for the iterate z: lo, hi have the block's length (±inf allowed). A
    /// function of z: the same z gives the same bounds (a warm start that no pass moves keeps
    /// its first box without asking again, `outer::new_box`).
    fn block_bounds(&self, k: usize, z: &[f64], lo: &mut [f64], hi: &mut [f64]);

    /// Bounds of every block (lo, hi of full length). The default calls
    /// [`Self::block_bounds`] for each block in order.
    fn all_bounds(&self, blocks: &[usize], z: &[f64], lo: &mut [f64], hi: &mut [f64]) {
        for (k, b) in blocks.windows(2).enumerate() {
            self.block_bounds(k, z, &mut lo[b[0]..b[1]], &mut hi[b[0]..b[1]]);
        }
    }

    /// [`Self::all_bounds`], which the solver calls once per pass through this method: a rule
    /// that can run on both cores may fill the blocks of the sweeps' two halves at once when
    /// `par` ([`all_bounds_in_halves`]), giving the same bounds. The default calls `all_bounds`.
    fn all_bounds_par(&self, blocks: &[usize], z: &[f64], lo: &mut [f64], hi: &mut [f64], _par: bool) {
        self.all_bounds(blocks, z, lo, hi);
    }

    /// The bounds of block k in closed form as functions of its own first row, with every
    /// other dependence frozen at z ([`BlockLaw`]); `None` (the default) when the rule has no
    /// such form, and the NSGS local solver then uses [`Self::block_bounds`] at z as a fixed
    /// box. It may be a different description of the same constraint, but every z that solves
    /// the local problems of this form for all blocks must solve the VI of the boxes
    /// `block_bounds` gives at z: the residual, and so convergence, is always judged with
    /// `block_bounds`.
    fn block_law(&self, _k: usize, _z: &[f64]) -> Option<BlockLaw> {
        None
    }
}

/// A contact block's bounds as functions of its normal value p (row 0), for the exact local
/// solves of NSGS (math note §4.7): `p >= −tension`; row 1 + i (tangential, rolling) has
/// `|z| <= a[i] + b[i] p` when p > 0 and `|z| <= a_open[i]` when p <= 0.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BlockLaw {
    pub tension: f64,
    pub a: [f64; 2],
    pub b: [f64; 2],
    pub a_open: [f64; 2],
}

/// Bounds that do not depend on z: a plain VI. `lo`, `hi` cover all rows.
pub struct FixedBounds {
    pub lo: Vec<f64>,
    pub hi: Vec<f64>,
}

impl BoundRule for FixedBounds {
    /// Block k taken as rows `k L .. (k + 1) L`, L = `lo.len()`: right for blocks of equal
    /// length. The solver does not use it: [`Self::all_bounds`] copies the whole box, for any
    /// blocks.
    fn block_bounds(&self, k: usize, _z: &[f64], lo: &mut [f64], hi: &mut [f64]) {
        let a = k * lo.len();
        lo.copy_from_slice(&self.lo[a..a + lo.len()]);
        hi.copy_from_slice(&self.hi[a..a + hi.len()]);
    }

    fn all_bounds(&self, _blocks: &[usize], _z: &[f64], lo: &mut [f64], hi: &mut [f64]) {
        lo.copy_from_slice(&self.lo);
        hi.copy_from_slice(&self.hi);
    }
}

/// The default [`Options::aim`] (math note §4.11).
pub const AIM: f64 = 0.5;

#[derive(Debug, Clone, Copy)]
pub struct Options {
    /// Scaled natural residual to reach (math note §4.3).
    pub tolerance: f64,
    /// The budget of work of the whole chain of methods, in the units of math note §4.17
    /// (iterations, sweeps, steps, pivots; one unit each).
    pub max_iterations: usize,
    /// Cap on outer (bound-update) iterations.
    pub max_outer: usize,
    /// Jacobi scaling z = D^{-1/2} y (math note §4.2).
    pub jacobi: bool,
    /// Accuracy asked of every row's gap G_i, in the units of G (math note §4.9): the
    /// residual also measures each row in gap units against it, so a light body's contact is
    /// solved even when other contacts carry forces 1e12 times larger. `f64::INFINITY`
    /// (default) leaves the force part alone.
    pub gap_tolerance: f64,
    /// A force the solution may legitimately reach (e.g. the weight and momentum of all the
    /// bodies the contacts carry); the divergence test's scale S includes it (default 0).
    pub force_scale: f64,
    /// Where a solve that has to iterate stops, as a fraction of the tolerance (math note
    /// §4.11): a start already within `tolerance` is kept as it is; a run that is not stops at
    /// `aim * tolerance` or one iteration after it first met `tolerance`, whichever comes first,
    /// so that the next warm-started steps have room before their drift reaches the tolerance.
    /// A run cut short by the iteration cap or a stall within the tolerance still converges.
    /// 1 stops at the tolerance itself.
    pub aim: f64,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            tolerance: 1e-8,
            max_iterations: 200_000,
            max_outer: 50,
            jacobi: true,
            gap_tolerance: f64::INFINITY,
            force_scale: 0.0,
            aim: AIM,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Report {
    pub outer_iterations: usize,
    pub inner_iterations: usize,
    /// Final scaled natural residual with the final bounds.
    pub residual: f64,
    pub converged: bool,
}

/// The correction step of the PC method (math note §4.2). The extragradient-type step needed
/// fewer W-products than the contraction step on every set measured (random box VIs,
/// three-disk Coulomb QVIs, a contact grid cold and warm started; see `tests/solver/vi_networks.rs`,
/// `correction_comparison`, and `benches/vi.rs`) and keeps every iterate inside the box, so
/// it is the default.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Correction {
    /// z = P_Ω[z − gamma alpha beta G(zt)]: iterates stay feasible.
    #[default]
    Extragradient,
    /// z = z − gamma alpha d, d = e − beta (G(z) − G(zt)): the plain PC step.
    Contraction,
}

/// Why the last solve stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Status {
    /// Residual and bound change below tolerance (also: empty problem).
    #[default]
    Converged,
    /// `max_iterations` inner iterations used up; `z` is the last iterate.
    IterationLimit,
    /// `max_outer` PC runs done without the bounds settling; `z` is the last iterate.
    OuterLimit,
    /// No bounded solution (zero row pushed toward an infinite bound, or growing iterates);
    /// `z` holds the warm start again.
    Diverged,
    /// A NaN or infinity appeared (in q, W or an iterate); `z` holds the warm start again.
    NonFinite,
    /// The bound rule returned `lo > hi`, NaN, `lo = +inf` or `hi = -inf`; `z` is the last
    /// iterate (clipped to the last valid box).
    InvalidBounds,
    /// The step size collapsed (beta below 1e-30 beta_0, or a zero predictor step without
    /// a small residual); only round-off can cause this. `z` is the last iterate.
    Stalled,
    /// Inconsistent input: dimensions of W, q, z or the blocks disagree, or an explicit W
    /// has a column index out of range. `z` is untouched.
    InvalidInput,
}

/// Counters of the last solve (see [`Solver::stats`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Stats {
    pub status: Status,
    /// Products with W (scaled or not), the dominant cost.
    pub products: usize,
    /// Rejected trial steps (beta shrinks).
    pub shrinks: usize,
    /// Whether a method of the chain handed over (0 or 1; [`Solver::handovers`]).
    pub fallbacks: usize,
    /// MPRGP's face solves (sparse factorizations of the free rows' block, math note §4.10).
    pub face_solves: usize,
    /// Pivots of Lemke's method (math note §4.12).
    pub pivots: usize,
    /// The method of the chain whose answer the solve returned (`None`: no method ran, the
    /// problem was empty or the input invalid).
    pub method: Option<Method>,
}

/// The solver with its workspace, reused across calls and steps: allocation only when a
/// problem is larger than every previous one, never inside the iterations.
#[derive(Debug, Clone)]
pub struct Solver {
    /// Correction step of the PC method (default: extragradient).
    pub correction: Correction,
    /// Sweeps run on both cores from this many rows on (default 20 000); `usize::MAX`
    /// keeps everything on the calling thread. Results do not depend on this setting.
    pub parallel_min_rows: usize,
    /// Inner accuracy of the outer passes after the first (default 0.1): pass m >= 1 stops
    /// its PC run at `max(tolerance, inexact * change_m / max(1, max|bound|))`, where
    /// change_m is the bound change that started the pass. 0 gives the exact compatibility
    /// iteration of math note §4.3. The final pass always meets `tolerance` with a settled
    /// box, so the accepted solutions are the same; only the work differs: on random
    /// three-disk Coulomb QVIs 0.1 needed about a fifth of the W-products of the exact
    /// iteration and failed to settle less often, and on a frictional square packing it
    /// converged where the exact iteration ran out of iterations.
    pub inexact: f64,
    /// The chain of methods (math note §4.17). [`Solver::new`] gives PC alone, the reference
    /// (the world sets the scene's `[solver] method`, default MPRGP's chain, before every
    /// solve).
    pub chain: Chain,
    stats: Stats,
    /// The last solve converged and its work vectors hold a full product of its answer.
    exact: bool,
    /// The last MPRGP step length ᾱ a solve computed: the next solves' guess for their
    /// proportioning test (`mprgp::StepLength`).
    step_length: Option<f64>,
    nsgs: nsgs::Work,
    newton: newton::Work,
    /// The caller's warm start of the running solve, where the chain's methods start.
    warm: Vec<f64>,
    /// The hand-overs of the last solve.
    handovers: Vec<HandOver>,
    /// The best answer of the chain's methods (`chain.rs`).
    best: chain::Best,
    /// Storage of the residual of unconverged answers (`measure.rs`).
    check: measure::Check,
    scaling: scaling::Scaling,
    vectors: pc::Vectors,
}

impl Default for Solver {
    fn default() -> Self {
        Self::new()
    }
}

impl Solver {
    pub fn new() -> Solver {
        Solver {
            correction: Correction::default(),
            parallel_min_rows: 20_000,
            inexact: 0.1,
            chain: Chain::named(Method::Pc),
            stats: Stats::default(),
            exact: false,
            step_length: None,
            nsgs: nsgs::Work::default(),
            newton: Default::default(),
            warm: Vec::new(),
            handovers: Vec::new(),
            best: chain::Best::default(),
            check: measure::Check::default(),
            scaling: scaling::Scaling::default(),
            vectors: pc::Vectors::default(),
        }
    }

    /// Sets [`Self::correction`].
    pub fn with_correction(mut self, correction: Correction) -> Solver {
        self.correction = correction;
        self
    }

    /// Sets [`Self::parallel_min_rows`].
    pub fn with_parallel_min_rows(mut self, rows: usize) -> Solver {
        self.parallel_min_rows = rows;
        self
    }

    /// Sets [`Self::chain`] to the chain `method`'s scene name stands for ([`Chain::named`]).
    pub fn with_method(mut self, method: Method) -> Solver {
        self.chain = Chain::named(method);
        self
    }

    /// Sets [`Self::chain`].
    pub fn with_chain(mut self, chain: Chain) -> Solver {
        self.chain = chain;
        self
    }

    /// The hand-overs between the chain's methods in the last [`Self::solve`] call, in order.
    pub fn handovers(&self) -> &[HandOver] {
        &self.handovers
    }

    /// Sets [`Self::inexact`].
    pub fn with_inexact(mut self, inexact: f64) -> Solver {
        self.inexact = inexact;
        self
    }

    /// Counters and stop reason of the last [`Self::solve`] call.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// The MPRGP step length the next solve takes as its guess: what the solver carries from
    /// one step to the next (a checkpoint keeps it; the rest of the workspace is scratch).
    pub fn step_length(&self) -> Option<f64> {
        self.step_length
    }

    /// Sets [`Self::step_length`] (a run resumed from a checkpoint).
    pub fn set_step_length(&mut self, step_length: Option<f64>) {
        self.step_length = step_length;
    }

    /// G = q + W z at the z the last [`Self::solve`] returned, from the full product W z its
    /// last sweep made (W z = D^{1/2} Ŵ y), without a new product; `None` when there is no such
    /// product: the solve did not converge, ran NSGS, or its answer moved by more than one
    /// MPRGP step after its last sweep (a step updates Ŵy along with y; `pc::State::exact`).
    /// `q` must be the problem's. Equal to q + W z up to rounding: the returned z snaps rows at
    /// a bound to the bound exactly.
    pub fn gaps(&self, q: &[f64]) -> Option<Vec<f64>> {
        let (wy, sd) = (&self.vectors.wy, &self.scaling.sd);
        (self.exact && q.len() == wy.len() && q.len() == sd.len())
            .then(|| q.iter().zip(wy).zip(sd).map(|((q, w), s)| q + w * s).collect())
    }

    /// Solves the (Q)VI, starting from and overwriting `z` (warm start); see the module
    /// documentation for the method. Afterwards [`Self::stats`] tells why it stopped and how
    /// many W-products it used. Never panics on bad input ([`Status::InvalidInput`]).
    pub fn solve(&mut self, p: &Problem, rule: &dyn BoundRule, z: &mut [f64], opts: &Options) -> Report {
        let n = p.q.len();
        self.stats = Stats::default();
        self.handovers.clear();
        self.exact = false;
        let csr = p.w.as_csr();
        let csr_ok = csr.as_ref().is_none_or(|w| w.rows() == n && w.cols() == n);
        if !p.is_consistent(z) || !csr_ok {
            return self.invalid_input();
        }
        if n == 0 {
            return Report { outer_iterations: 0, inner_iterations: 0, residual: 0.0, converged: true };
        }
        self.solve_chain(p, rule, z, opts)
    }

    /// The PC path (math note §4.2–4.3), with MPRGP as the inner solver of the passes when
    /// `mprgp` (§4.8).
    fn solve_pc(
        &mut self,
        p: &Problem,
        rule: &dyn BoundRule,
        z: &mut [f64],
        opts: &Options,
        mprgp: bool,
    ) -> Report {
        let n = p.q.len();
        let par = n >= self.parallel_min_rows;
        let csr = p.w.as_csr();
        let explicit = csr.is_some();
        let max_diag = match csr {
            Some(w) => match self.scaling.setup_csr(w, opts.jacobi) {
                Some(d) => d,
                None => return self.invalid_input(),
            },
            None => self.scaling.setup_operator(p.w, opts.jacobi, &mut self.vectors.tmp, par),
        };
        let beta0 = if max_diag > 0.0 && max_diag.is_finite() { 1.0 / max_diag } else { 1.0 };
        let dq = self.scaling.scale_q(p.q, par);
        self.vectors.start(z, &self.scaling.sd, par);
        let pass = outer::Pass {
            rule,
            blocks: p.blocks,
            q: p.q,
            opts,
            inexact: if self.inexact.is_finite() { self.inexact.max(0.0) } else { 0.0 },
            dq: dq.max(opts.force_scale),
        };
        let mut st = pc::State::new(beta0);
        let s = &self.scaling;
        let correction = self.correction;
        let measure = measure::Measure::new(opts);
        let v = &mut self.vectors;
        let step = mprgp.then(|| mprgp::StepLength::new(self.step_length));
        let (report, known) = if explicit {
            let rows = scaling::Csr { rowptr: &s.rowptr, cols: &s.cols, vals: &s.vals };
            outer_run(pc::Ctx::new(rows, s, par, correction, measure), &pass, v, &mut st, z, step)
        } else {
            let rows = scaling::Scaled { w: p.w, sc: &s.sc, par };
            outer_run(pc::Ctx::new(rows, s, par, correction, measure), &pass, v, &mut st, z, step)
        };
        if known.is_some() {
            self.step_length = known;
        }
        self.stats = st.stats;
        self.exact = report.converged && st.exact();
        // an unconverged answer is measured on its own (math note §4.3): the passes measure
        // their iterate against the box of the pass's start, and unscale it into that box
        let residual = match chain::kept_iterate(self.stats.status) {
            true => self.check.residual(p, rule, z, opts),
            false => report.residual,
        };
        Report { residual, ..report }
    }

    fn invalid_input(&mut self) -> Report {
        self.stats.status = Status::InvalidInput;
        Report { outer_iterations: 0, inner_iterations: 0, residual: f64::INFINITY, converged: false }
    }
}

/// The outer loop with PC, or with MPRGP passes given their step length (computed when first
/// needed, a guess standing in for it until then: `mprgp::StepLength`). Returns the report and
/// the step length a later solve may take as its guess.
fn outer_run<R: scaling::Rows>(
    mut c: pc::Ctx<R>,
    pass: &outer::Pass,
    v: &mut pc::Vectors,
    st: &mut pc::State,
    z: &mut [f64],
    step: Option<mprgp::StepLength>,
) -> (Report, Option<f64>) {
    c.mprgp = step;
    let report = outer::solve(&c, pass, v, st, z);
    (report, c.mprgp.and_then(|s| s.known()))
}

/// Convenience for tests: a fresh [`Solver`] per call.
pub fn solve(p: &Problem, rule: &dyn BoundRule, z: &mut [f64], opts: &Options) -> Report {
    Solver::new().solve(p, rule, z, opts)
}
