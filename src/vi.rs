//! Box-constrained affine variational inequality solver (math note §4). Pure mathematics:
//! it knows nothing about bodies or contacts.
//!
//! Find z in Ω = [lo, hi] with (z' - z)ᵀ G(z) >= 0 for all z' in Ω, G(z) = q + W z,
//! W symmetric positive semidefinite (sparse CSR). The bounds may depend on z (a QVI);
//! a [`BoundRule`] recomputes them in the outer compatibility loop.
//!
//! # Algorithm
//!
//! * **Outer loop** (math note §4.3, compatibility iteration). Pass m asks the
//!   [`BoundRule`] for the box of the current iterate, clips the iterate into it and runs the
//!   inner solver from there. It stops at the first pass m >= 1 whose bounds differ from
//!   those of pass m − 1 by at most `eps_out * max(1, max|finite bound|)` (`eps_out =
//!   tolerance`) *and* whose clipped iterate already has a scaled natural residual of at
//!   most `tolerance` with these bounds. [`Report::outer_iterations`] counts PC runs (a plain
//!   VI reports 1: one run, then a confirming pass that finds the same box) and `max_outer`
//!   caps them. The first PC run goes down to `tolerance`; later runs stop earlier while the
//!   box still moves ([`Workspace::inexact`], the math note leaves the inner accuracy per
//!   pass open).
//! * **Inner solver** (math note §4.2): the self-adaptive projection-contraction (PC)
//!   method with nu = 0.9, mu_s = 0.4, gamma = 1.8, beta_0 = 1 / max_j W_jj (1 in
//!   Jacobi-scaled variables), shrink beta ← 0.7 min(1, 1/r) beta, enlarge beta ← 1.5 beta
//!   when r <= mu_s. `W z` is stored, so an iteration costs two products with W (one for
//!   the trial point, one for the new iterate) plus one per rejected trial step; each PC
//!   run adds one product for its starting point. (A single product per iteration is not
//!   possible: both G(zt) and G(z_new) are needed, at points that are not linear
//!   combinations of stored products.)
//! * **Correction step**: both variants of §4.2 exist ([`Correction`]); the default is the
//!   extragradient-type step z = P_Ω[z − gamma alpha beta G(zt)], which keeps the iterate
//!   feasible and needed 16-69 % fewer W-products in the measurements quoted there.
//! * **Residual** (math note §4.3):
//!   `res = ||z − P_Ω[z − D⁻¹ G(z)]||_inf / max(1, ||z||_inf)`, `D = diag(W)`. It is the
//!   inner stopping test (except for the inexact passes above) and the reported value. It is
//!   evaluated on the unscaled iterate (`z = D^{-1/2} y`, `D⁻¹ G = D^{-1/2} Ĝ`) inside each
//!   sweep, so the reported residual is that of the returned `z`.
//! * **Zero diagonals.** A row with `W_jj <= 0` (or non-finite) uses `D_jj = 1` in the
//!   residual and in the Jacobi scaling. For a PSD W, `W_jj = 0` forces the whole row and
//!   column to vanish, so `G_j = q_j` is constant: such a row has a solution only if the bound
//!   that `q_j` pushes toward is finite. This is checked at every pass and reported as
//!   [`Status::Diverged`] instead of iterating.
//! * **Jacobi scaling** (`Options::jacobi`): `z = D^{-1/2} y`, so `Ŵ = D^{-1/2} W D^{-1/2}`
//!   has unit diagonal, `q̂ = D^{-1/2} q` and the bounds become `D^{1/2} lo, D^{1/2} hi`
//!   (infinite bounds stay infinite). It is not optional in practice when rows involving
//!   only heavy bodies carry force: with two 1e12-kg bodies in contact (`vi_kkt`,
//!   `jacobi_needed_for_heavy_heavy_contact`) the scaled solver needs 274 iterations and the
//!   unscaled one is still at residual 0.74 after 20 000.
//!
//! # Performance
//!
//! * Per call, W is copied once (scaled values, `u32` column indices: 12 instead of 16 bytes
//!   per nonzero), about the cost of one product. Nothing is allocated during the
//!   iterations; [`solve_with`] reuses the buffers of a [`Workspace`].
//! * Each sweep fuses a product with the vector work of the PC step (residual, projection,
//!   dot products), so an iteration makes three passes over the rows.
//! * Mat-vec (micro-benchmark, ~11 nonzeros per row, best of 7): the hand-written CSR loop
//!   with unchecked column access (indices checked once per call) took 0.5 ns per nonzero
//!   at 10k-20k rows and 1.0-1.2 ns at 50k-100k (memory-bound);
//!   `sprs::prod::mul_acc_mat_vec_csr` took 1.4-1.5 ns throughout, the bounds-checked loop
//!   0.7-1.1 ns. `u32` column indices were within noise of `usize` up to 50k rows and
//!   5-10 % faster at 100k.
//! * Rows are processed in blocks of 2 048; blocks run on rayon from
//!   [`Workspace::parallel_min_rows`] rows (default 20 000). Block partial sums are reduced
//!   in block order, so serial and parallel results are bit-identical. On the shared
//!   2-core test machine (another job on one core) rayon gave no measurable gain at
//!   40k-100k rows (about 0.9-1.0 ns per nonzero either way, `vi_kkt::timing_products`).
//!
//! # Failure modes (never a panic)
//!
//! `converged = false`, with the reason in [`Workspace::stats`], when the iteration or outer
//! cap is reached, when a NaN or infinity appears, when the bound rule returns `lo > hi` or
//! NaN, or when the iterates diverge. Divergence test: for a solvable problem the PC
//! iterates are Fejér-monotone (math note §4.2), hence bounded; they are declared divergent
//! when `||z||_inf` exceeds `growth * S`, `S = max(1, ||D⁻¹q||_inf, ||z_start||_inf,
//! max|finite bound|)`, `growth = clamp(1e-2 / tolerance, 1e4, 1e8)`. The residual is
//! relative to `||z||`, so a ray `z = t d` with `W d = 0`, `qᵀd < 0` (e.g. a particle jammed
//! between two walls closer than its diameter) would eventually pass the residual test;
//! the growth test fires first whenever the violated gap is at least `1e-2 S` in force
//! units. Rays along which beta grows are caught within a few dozen iterations; a ray that
//! advances only linearly (beta held back by the bounded part of the problem) uses up
//! `max_iterations` and ends as [`Status::IterationLimit`]. On divergence or non-finite
//! values the warm start is restored in `z` and the reported residual is `+inf`.
//!
//! # Requirements on the input
//!
//! `W` square, symmetric, PSD, `n = q.len() = z.len()`. Full storage of both triangles; a
//! CSC matrix is accepted too (for a symmetric matrix its compressed storage reads the same
//! as CSR). Symmetry and semidefiniteness are not checked (PC only needs monotonicity of G).

use rayon::prelude::*;
use sprs::CsMat;

/// The affine map G(z) = q + W z.
pub struct Problem<'a> {
    pub w: &'a CsMat<f64>,
    pub q: &'a [f64],
}

/// Recomputes the box from the current iterate (math note §4.3).
pub trait BoundRule {
    /// Writes the bounds valid for the iterate `z` into `lo`, `hi` (±inf allowed).
    fn bounds(&mut self, z: &[f64], lo: &mut [f64], hi: &mut [f64]);
}

/// Bounds that do not depend on z: a plain VI.
pub struct FixedBounds {
    pub lo: Vec<f64>,
    pub hi: Vec<f64>,
}

impl BoundRule for FixedBounds {
    fn bounds(&mut self, _z: &[f64], lo: &mut [f64], hi: &mut [f64]) {
        lo.copy_from_slice(&self.lo);
        hi.copy_from_slice(&self.hi);
    }
}

#[derive(Debug, Clone, Copy)]
pub struct Options {
    /// Scaled natural residual to reach (math note §4.3).
    pub tolerance: f64,
    /// Cap on inner PC iterations, all outer loops together.
    pub max_iterations: usize,
    /// Cap on outer (bound-update) iterations.
    pub max_outer: usize,
    /// Jacobi scaling z = D^{-1/2} y (math note §4.2).
    pub jacobi: bool,
}

impl Default for Options {
    fn default() -> Self {
        Self { tolerance: 1e-8, max_iterations: 200_000, max_outer: 50, jacobi: true }
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

/// The correction step of the PC method (math note §4.2).
///
/// Measured with Jacobi scaling on (W-products summed over each set; "EG" = extragradient,
/// "PC" = contraction; `tests/vi_kkt.rs`, tests `correction_comparison` and
/// `timing_contact_networks`):
///
/// | problem set | tolerance | EG | PC |
/// |---|---|---|---|
/// | 200 random box VIs (`W = B K⁻¹ Bᵀ`, m <= 30, n <= 12) | 1e-10 | 1 124 380 | 1 570 929 |
/// | 60 three-disk Coulomb QVIs, mu = 0.3 | 1e-10 | 10 718 | 34 248 |
/// | 9 900-row frictionless contact grid, cold start | 1e-8 | 70 022 | 83 111 |
/// | same grid, warm start, q perturbed by 1 % | 1e-8 | 49 641 | 59 911 |
///
/// The extragradient-type step was 16-69 % cheaper on every set (the math note reports
/// about 10 %) and keeps every iterate inside the box, so it is the default.
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
}

/// Counters of the last solve (see [`Workspace::stats`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Stats {
    pub status: Status,
    /// Products with W (scaled or not), the dominant cost.
    pub products: usize,
    /// Rejected trial steps (beta shrinks).
    pub shrinks: usize,
}

/// Rows per block of every sweep. Reductions are summed block by block in a fixed order, so
/// serial and parallel runs give bit-identical results.
const BLOCK: usize = 2048;
const NU: f64 = 0.9;
const MU_S: f64 = 0.4;
const GAMMA: f64 = 1.8;
const SHRINK: f64 = 0.7;
const ENLARGE: f64 = 1.5;
/// beta stays within [1e-30, 1e30] * beta_0.
const BETA_RANGE: f64 = 1e30;

/// Reusable storage for [`solve_with`]. Allocation happens only when a problem is larger
/// than every previous one; the iterations themselves never allocate.
#[derive(Debug, Clone)]
pub struct Workspace {
    /// Correction step of the PC method (default: extragradient).
    pub correction: Correction,
    /// Sweeps run on the rayon pool from this many rows on (default 20 000); `usize::MAX`
    /// keeps everything on the calling thread. Results do not depend on this setting.
    pub parallel_min_rows: usize,
    /// Inner accuracy of the outer passes after the first (default 0.1): pass m >= 1 stops
    /// its PC run at `max(tolerance, inexact * change_m / max(1, max|bound|))`, where
    /// change_m is the bound change that started the pass. 0 gives the exact compatibility
    /// iteration of math note §4.3. The final pass always meets `tolerance` with a settled
    /// box, so the accepted solutions are the same; only the work differs. Measured on 3 000
    /// random three-disk Coulomb QVIs (`vi_kkt`, tolerance 1e-10): total W-products
    /// 13.6 M (exact), 4.0 M (0.01), 2.6 M (0.1); runs needing more than 50 passes: 89, 84,
    /// 68. On a 1 560-row frictional square packing (mu = 0.3) the exact iteration hit
    /// 2 M inner iterations after 70 passes; 0.1 converged with 0.22 M in 222 passes.
    pub inexact: f64,
    stats: Stats,
    // Matrix copy: scaled values, u32 column indices (12 instead of 16 bytes per nonzero).
    rowptr: Vec<usize>,
    cols: Vec<u32>,
    vals: Vec<f64>,
    /// D^{1/2} (Jacobi) or 1: y = sd z.
    sd: Vec<f64>,
    /// D^{-1/2} (Jacobi) or 1: z = sc y.
    sc: Vec<f64>,
    /// Factor turning the scaled map into D⁻¹ G: D^{-1/2} (Jacobi) or D⁻¹.
    gs: Vec<f64>,
    qs: Vec<f64>,
    y: Vec<f64>,
    wy: Vec<f64>,
    yt: Vec<f64>,
    wyt: Vec<f64>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    lo_prev: Vec<f64>,
    hi_prev: Vec<f64>,
    ylo: Vec<f64>,
    yhi: Vec<f64>,
    z0: Vec<f64>,
    zero_rows: Vec<usize>,
    parts: Vec<Partial>,
}

impl Default for Workspace {
    fn default() -> Self {
        Self::new()
    }
}

impl Workspace {
    pub fn new() -> Self {
        Self {
            correction: Correction::default(),
            parallel_min_rows: 20_000,
            inexact: 0.1,
            stats: Stats::default(),
            rowptr: Vec::new(),
            cols: Vec::new(),
            vals: Vec::new(),
            sd: Vec::new(),
            sc: Vec::new(),
            gs: Vec::new(),
            qs: Vec::new(),
            y: Vec::new(),
            wy: Vec::new(),
            yt: Vec::new(),
            wyt: Vec::new(),
            lo: Vec::new(),
            hi: Vec::new(),
            lo_prev: Vec::new(),
            hi_prev: Vec::new(),
            ylo: Vec::new(),
            yhi: Vec::new(),
            z0: Vec::new(),
            zero_rows: Vec::new(),
            parts: Vec::new(),
        }
    }

    /// Counters and stop reason of the last [`solve_with`] call.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// Copies and (optionally) scales W and q; returns (beta_0, max(1, ||D⁻¹q||_inf)).
    fn setup(&mut self, w: &CsMat<f64>, q: &[f64], z: &[f64], jacobi: bool) -> (f64, f64) {
        let n = q.len();
        let indptr = w.proper_indptr();
        let (indices, data) = (w.indices(), w.data());
        let nnz = indptr[n];
        assert!(n <= u32::MAX as usize, "vi: too many rows for u32 column indices");

        for v in [
            &mut self.sd,
            &mut self.sc,
            &mut self.gs,
            &mut self.qs,
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
        ] {
            v.clear();
            v.resize(n, 0.0);
        }
        self.rowptr.clear();
        self.rowptr.extend_from_slice(&indptr);
        self.cols.clear();
        self.vals.clear();
        self.zero_rows.clear();
        self.parts.clear();
        self.parts.resize(n.div_ceil(BLOCK), Partial::default());

        // Diagonal (guarded) and the zero rows.
        for i in 0..n {
            let (a, b) = (indptr[i], indptr[i + 1]);
            let mut d = 0.0;
            let mut all_zero = true;
            for k in a..b {
                if indices[k] == i {
                    d += data[k];
                }
                all_zero &= data[k] == 0.0;
            }
            if all_zero {
                self.zero_rows.push(i);
            }
            let d = if d > 0.0 && d.is_finite() { d } else { 1.0 };
            let (sd, sc) = if jacobi { (d.sqrt(), 1.0 / d.sqrt()) } else { (1.0, 1.0) };
            self.sd[i] = sd;
            self.sc[i] = sc;
            self.gs[i] = if jacobi { sc } else { 1.0 / d };
        }

        let mut max_diag: f64 = 0.0;
        let mut dq: f64 = 0.0;
        self.cols.reserve(nnz);
        self.vals.reserve(nnz);
        for i in 0..n {
            let si = self.sc[i];
            for k in indptr[i]..indptr[i + 1] {
                let j = indices[k];
                assert!(j < n, "vi: column index out of range");
                let v = si * data[k] * self.sc[j];
                if j == i {
                    max_diag = max_diag.max(v);
                }
                self.cols.push(j as u32);
                self.vals.push(v);
            }
            self.qs[i] = si * q[i];
            // D⁻¹ q = gs * qs in both modes.
            dq = dq.max((self.gs[i] * self.qs[i]).abs());
            self.z0[i] = z[i];
            self.y[i] = if z[i].is_finite() { z[i] * self.sd[i] } else { 0.0 };
        }
        let beta0 = if max_diag > 0.0 && max_diag.is_finite() { 1.0 / max_diag } else { 1.0 };
        (beta0, dq.max(1.0))
    }
}

/// Per-block results of a sweep: three sums and two maxima.
#[derive(Debug, Clone, Copy, Default)]
struct Partial {
    s0: f64,
    s1: f64,
    s2: f64,
    m0: f64,
    m1: f64,
}

fn reduce(parts: &[Partial]) -> Partial {
    parts.iter().fold(Partial::default(), |acc, p| Partial {
        s0: acc.s0 + p.s0,
        s1: acc.s1 + p.s1,
        s2: acc.s2 + p.s2,
        m0: acc.m0.max(p.m0),
        m1: acc.m1.max(p.m1),
    })
}

/// Runs `f(first_row, out_block)` over the blocks of `out`, storing each block's partial.
fn run1<F>(par: bool, out: &mut [f64], parts: &mut [Partial], f: F) -> Partial
where
    F: Fn(usize, &mut [f64]) -> Partial + Sync,
{
    if par {
        out.par_chunks_mut(BLOCK)
            .zip(parts.par_iter_mut())
            .enumerate()
            .for_each(|(b, (o, p))| *p = f(b * BLOCK, o));
    } else {
        for (b, (o, p)) in out.chunks_mut(BLOCK).zip(parts.iter_mut()).enumerate() {
            *p = f(b * BLOCK, o);
        }
    }
    reduce(parts)
}

/// As [`run1`], with two output vectors.
fn run2<F>(par: bool, o1: &mut [f64], o2: &mut [f64], parts: &mut [Partial], f: F) -> Partial
where
    F: Fn(usize, &mut [f64], &mut [f64]) -> Partial + Sync,
{
    if par {
        o1.par_chunks_mut(BLOCK)
            .zip(o2.par_chunks_mut(BLOCK))
            .zip(parts.par_iter_mut())
            .enumerate()
            .for_each(|(b, ((a, c), p))| *p = f(b * BLOCK, a, c));
    } else {
        for (b, ((a, c), p)) in
            o1.chunks_mut(BLOCK).zip(o2.chunks_mut(BLOCK)).zip(parts.iter_mut()).enumerate()
        {
            *p = f(b * BLOCK, a, c);
        }
    }
    reduce(parts)
}

/// Projection onto [lo, hi] (lo <= hi checked by the caller). Unlike `f64::clamp` it never
/// panics.
#[inline(always)]
fn clip(x: f64, lo: f64, hi: f64) -> f64 {
    x.max(lo).min(hi)
}

/// The unscaled iterate z = D^{-1/2} y, snapped so that an active scaled bound maps to the
/// exact unscaled bound and lo <= z <= hi holds exactly.
#[inline(always)]
fn unscale(y: f64, ylo: f64, yhi: f64, lo: f64, hi: f64, sc: f64) -> f64 {
    if y <= ylo {
        lo
    } else if y >= yhi {
        hi
    } else {
        clip(sc * y, lo, hi)
    }
}

/// Read-only view of the (scaled) matrix copy.
#[derive(Clone, Copy)]
struct Csr<'a> {
    rowptr: &'a [usize],
    cols: &'a [u32],
    vals: &'a [f64],
}

impl Csr<'_> {
    /// (Ŵ x)_i. The caller guarantees `x.len() == n`.
    #[inline(always)]
    fn row_dot(&self, i: usize, x: &[f64]) -> f64 {
        let (a, b) = (self.rowptr[i], self.rowptr[i + 1]);
        let mut acc = 0.0;
        for (v, &j) in self.vals[a..b].iter().zip(&self.cols[a..b]) {
            // SAFETY: `Workspace::setup` asserted every column index < n, and every vector
            // passed as `x` has length n (checked by `debug_assert` in the callers and by
            // construction: all work vectors are resized to n in `setup`).
            acc += v * unsafe { *x.get_unchecked(j as usize) };
        }
        acc
    }
}

/// Solves the (Q)VI, starting from and overwriting `z` (warm start).
///
/// Allocates a fresh [`Workspace`]; use [`solve_with`] to reuse one across time steps.
pub fn solve(p: &Problem, bounds: &mut dyn BoundRule, z: &mut [f64], opts: &Options) -> Report {
    let mut ws = Workspace::new();
    solve_with(&mut ws, p, bounds, z, opts)
}

/// [`solve`] with caller-owned work storage; see the module documentation for the method.
/// After the call, [`Workspace::stats`] tells why it stopped and how many W-products it used.
///
/// Panics only on inconsistent dimensions (W not n×n with n = q.len() = z.len()).
pub fn solve_with(
    ws: &mut Workspace,
    p: &Problem,
    bounds: &mut dyn BoundRule,
    z: &mut [f64],
    opts: &Options,
) -> Report {
    let n = p.q.len();
    assert_eq!(p.w.rows(), n, "vi: W must be n×n with n = q.len()");
    assert_eq!(p.w.cols(), n, "vi: W must be n×n with n = q.len()");
    assert_eq!(z.len(), n, "vi: z.len() must equal q.len()");
    ws.stats = Stats::default();
    if n == 0 {
        return Report { outer_iterations: 0, inner_iterations: 0, residual: 0.0, converged: true };
    }

    let (beta0, dq) = ws.setup(p.w, p.q, z, opts.jacobi);
    let tol = opts.tolerance;
    let growth = if tol > 0.0 { (1e-2 / tol).clamp(1e4, 1e8) } else { 1e8 };
    let par = n >= ws.parallel_min_rows;
    let correction = ws.correction;
    let inexact = if ws.inexact.is_finite() { ws.inexact.max(0.0) } else { 0.0 };

    let Workspace {
        stats,
        rowptr,
        cols,
        vals,
        sd,
        sc,
        gs,
        qs,
        y,
        wy,
        yt,
        wyt,
        lo,
        hi,
        lo_prev,
        hi_prev,
        ylo,
        yhi,
        z0,
        zero_rows,
        parts,
        ..
    } = ws;
    let csr = Csr { rowptr, cols, vals };
    let (sd, sc, gs, qs) = (&sd[..], &sc[..], &gs[..], &qs[..]);

    let mut beta = beta0;
    let (beta_min, beta_max) = (beta0 / BETA_RANGE, beta0 * BETA_RANGE);
    let mut inner = 0usize;
    let mut outer = 0usize;
    // Results of the last sweep over y: residual, ||z||_inf, ||e||² (e = y − yt).
    let (mut res, mut znorm, mut ee) = (f64::INFINITY, 0.0f64, 0.0f64);
    let mut fresh = false;
    let mut last_infeasible = false;
    // A valid box exists (from an earlier pass).
    let mut have_prev = false;

    // One sweep over y (see `sweep_y`); counts the product.
    macro_rules! sweep {
        () => {{
            stats.products += 1;
            let inp = SweepIn { y, lo, hi, ylo, yhi, sc, gs, qs };
            sweep_y(par, csr, &inp, beta, wy, yt, parts)
        }};
    }
    // Stores a sweep's results in the loop state.
    macro_rules! take {
        ($sw:expr) => {{
            let sw: Sweep = $sw;
            fresh = true;
            last_infeasible = sw.infeasible;
            res = sw.res;
            znorm = sw.znorm;
            ee = sw.ee;
            sw.finite
        }};
    }

    let status = 'outer: loop {
        // The iterate the bound rule sees: z itself at pass 0, else the unscaled y.
        if have_prev {
            let (y, lo, hi, ylo, yhi) = (&y[..], &lo[..], &hi[..], &ylo[..], &yhi[..]);
            run1(par, z, parts, |r0, zo| {
                for (k, zk) in zo.iter_mut().enumerate() {
                    let i = r0 + k;
                    *zk = unscale(y[i], ylo[i], yhi[i], lo[i], hi[i], sc[i]);
                }
                Partial::default()
            });
        }
        if have_prev {
            std::mem::swap(lo, lo_prev);
            std::mem::swap(hi, hi_prev);
        }
        bounds.bounds(z, lo, hi);

        // Validate, measure the change, scale the box (math note §4.3).
        let (mut change, mut bmax, mut same, mut valid) = (0.0f64, 0.0f64, have_prev, true);
        for i in 0..n {
            let (l, h) = (lo[i], hi[i]);
            valid &= l <= h && l < f64::INFINITY && h > f64::NEG_INFINITY;
            if l.is_finite() {
                bmax = bmax.max(l.abs());
            }
            if h.is_finite() {
                bmax = bmax.max(h.abs());
            }
            if have_prev {
                change = change.max(bound_diff(l, lo_prev[i])).max(bound_diff(h, hi_prev[i]));
                same &= l.to_bits() == lo_prev[i].to_bits() && h.to_bits() == hi_prev[i].to_bits();
            }
            ylo[i] = l * sd[i];
            yhi[i] = h * sd[i];
        }
        if !valid {
            if have_prev {
                // Keep the last valid box for the final unscaling.
                std::mem::swap(lo, lo_prev);
                std::mem::swap(hi, hi_prev);
                for i in 0..n {
                    ylo[i] = lo[i] * sd[i];
                    yhi[i] = hi[i] * sd[i];
                }
            }
            break 'outer Status::InvalidBounds;
        }
        // Zero rows: G_j = q_j is constant; it needs a finite bound on the side q pushes to.
        if zero_rows.iter().any(|&j| {
            (p.q[j] > 0.0 && lo[j] == f64::NEG_INFINITY) || (p.q[j] < 0.0 && hi[j] == f64::INFINITY)
        }) {
            break 'outer Status::Diverged;
        }

        // Clip the iterate into the new box.
        let (ylo_r, yhi_r) = (&ylo[..], &yhi[..]);
        let moved = run1(par, y, parts, |r0, yo| {
            let mut moved = 0.0;
            for (k, yk) in yo.iter_mut().enumerate() {
                let c = clip(*yk, ylo_r[r0 + k], yhi_r[r0 + k]);
                if c != *yk {
                    moved += 1.0;
                    *yk = c;
                }
            }
            Partial { s0: moved, ..Partial::default() }
        })
        .s0;
        // Unchanged box and iterate: the last sweep is still valid.
        let stale = !(same && moved == 0.0 && fresh);
        if stale && !take!(sweep!()) {
            break 'outer Status::NonFinite;
        }
        let limit = growth * dq.max(znorm).max(bmax);
        // Inexact passes (see `Workspace::inexact`): while the box still moves, solving the
        // VI of a box that is about to change far below that change is wasted work. Pass
        // m >= 1 stops at max(tol, inexact * change / max(1, max|bound|)); the stopping test
        // below still demands the full tolerance with a settled box.
        let inner_tol = if outer == 0 { tol } else { tol.max(inexact * change / bmax.max(1.0)) };
        have_prev = true;

        if outer > 0 && change <= tol * bmax.max(1.0) && res <= tol {
            break 'outer Status::Converged;
        }
        if outer >= opts.max_outer {
            break 'outer Status::OuterLimit;
        }
        outer += 1;

        // Inner PC run (math note §4.2). Invariant at the loop head: the sweep over y is
        // fresh (wy = Ŵy, yt = P[y − beta F(y)], ee = ||y − yt||², res, znorm).
        loop {
            if znorm > limit {
                break 'outer Status::Diverged;
            }
            if res <= inner_tol {
                break;
            }
            if inner >= opts.max_iterations {
                break 'outer Status::IterationLimit;
            }
            // Predictor with step-size control.
            let (r, edf, dfdf) = loop {
                if ee <= 0.0 {
                    break 'outer Status::Stalled;
                }
                let (y_r, wy_r, yt_r) = (&y[..], &wy[..], &yt[..]);
                debug_assert_eq!(yt_r.len(), n);
                let pt = run1(par, wyt, parts, |r0, wo| {
                    let mut pt = Partial::default();
                    for (k, wk) in wo.iter_mut().enumerate() {
                        let i = r0 + k;
                        let w = csr.row_dot(i, yt_r);
                        *wk = w;
                        let d = wy_r[i] - w; // F(y) − F(yt)
                        let e = y_r[i] - yt_r[i];
                        pt.s0 += e * d;
                        pt.s1 += d * d;
                    }
                    pt
                });
                stats.products += 1;
                if !(pt.s0.is_finite() && pt.s1.is_finite()) {
                    break 'outer Status::NonFinite;
                }
                let r = beta * (pt.s1 / ee).sqrt();
                if r <= NU {
                    break (r, pt.s0, pt.s1);
                }
                beta *= SHRINK * (1.0 / r).min(1.0);
                stats.shrinks += 1;
                if beta < beta_min {
                    break 'outer Status::Stalled;
                }
                let (ylo, yhi) = (&ylo[..], &yhi[..]);
                ee = run1(par, yt, parts, |r0, to| {
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
            };
            // d = e − beta (F − Ft);  alpha = eᵀd / dᵀd  (> 1/2 since r <= nu < 1).
            let ed = ee - beta * edf;
            let dd = ee - 2.0 * beta * edf + beta * beta * dfdf;
            let alpha = ed / dd;
            let (ylo_r, yhi_r, wy_r, yt_r, wyt_r) = (&ylo[..], &yhi[..], &wy[..], &yt[..], &wyt[..]);
            match correction {
                Correction::Extragradient => {
                    let step = GAMMA * alpha * beta;
                    run1(par, y, parts, |r0, yo| {
                        for (k, yk) in yo.iter_mut().enumerate() {
                            let i = r0 + k;
                            *yk = clip(*yk - step * (qs[i] + wyt_r[i]), ylo_r[i], yhi_r[i]);
                        }
                        Partial::default()
                    });
                }
                Correction::Contraction => {
                    let step = GAMMA * alpha;
                    run1(par, y, parts, |r0, yo| {
                        for (k, yk) in yo.iter_mut().enumerate() {
                            let i = r0 + k;
                            let d = (*yk - yt_r[i]) - beta * (wy_r[i] - wyt_r[i]);
                            *yk -= step * d;
                        }
                        Partial::default()
                    });
                }
            }
            if r <= MU_S {
                beta = (beta * ENLARGE).min(beta_max);
            }
            inner += 1;
            if !take!(sweep!()) {
                break 'outer Status::NonFinite;
            }
            if last_infeasible && res <= inner_tol {
                // Contraction step only: accept a point only after projecting it, so the
                // returned z is feasible and the residual is its own.
                let (ylo_r, yhi_r) = (&ylo[..], &yhi[..]);
                run1(par, y, parts, |r0, yo| {
                    for (k, yk) in yo.iter_mut().enumerate() {
                        *yk = clip(*yk, ylo_r[r0 + k], yhi_r[r0 + k]);
                    }
                    Partial::default()
                });
                if !take!(sweep!()) {
                    break 'outer Status::NonFinite;
                }
            }
        }
    };

    stats.status = status;
    let keeps_iterate = !matches!(status, Status::Diverged | Status::NonFinite)
        && (status != Status::InvalidBounds || have_prev);
    if status != Status::Converged && keeps_iterate && last_infeasible {
        // Contraction step only: report the residual of the projected iterate.
        let (ylo_r, yhi_r) = (&ylo[..], &yhi[..]);
        run1(par, y, parts, |r0, yo| {
            for (k, yk) in yo.iter_mut().enumerate() {
                *yk = clip(*yk, ylo_r[r0 + k], yhi_r[r0 + k]);
            }
            Partial::default()
        });
        res = sweep!().res;
    }
    let residual = match status {
        Status::Diverged | Status::NonFinite => {
            z.copy_from_slice(z0);
            f64::INFINITY
        }
        // No valid box was ever returned: z was not touched.
        Status::InvalidBounds if !have_prev => f64::INFINITY,
        _ => {
            let (y, lo, hi, ylo, yhi) = (&y[..], &lo[..], &hi[..], &ylo[..], &yhi[..]);
            run1(par, z, parts, |r0, zo| {
                for (k, zk) in zo.iter_mut().enumerate() {
                    let i = r0 + k;
                    *zk = unscale(y[i], ylo[i], yhi[i], lo[i], hi[i], sc[i]);
                }
                Partial::default()
            });
            if status == Status::InvalidBounds { f64::INFINITY } else { res }
        }
    };
    Report {
        outer_iterations: outer,
        inner_iterations: inner,
        residual,
        converged: status == Status::Converged,
    }
}

/// Read-only inputs of [`sweep_y`].
struct SweepIn<'a> {
    y: &'a [f64],
    lo: &'a [f64],
    hi: &'a [f64],
    ylo: &'a [f64],
    yhi: &'a [f64],
    sc: &'a [f64],
    gs: &'a [f64],
    qs: &'a [f64],
}

/// Results of [`sweep_y`].
struct Sweep {
    /// Scaled natural residual of the unscaled iterate (math note §4.3).
    res: f64,
    /// ||z||_inf.
    znorm: f64,
    /// ||y − yt||².
    ee: f64,
    /// No NaN or infinity in y or G(y).
    finite: bool,
    /// y lies outside the box (possible only with the contraction step).
    infeasible: bool,
}

/// One fused pass over the rows: `wy = Ŵ y`, the residual of z = D^{-1/2} y with
/// D⁻¹ G(z) = gs ∘ (q̂ + Ŵ y), and the trial point `yt = P[y − beta (q̂ + Ŵ y)]`.
fn sweep_y(
    par: bool,
    csr: Csr,
    v: &SweepIn,
    beta: f64,
    wy: &mut [f64],
    yt: &mut [f64],
    parts: &mut [Partial],
) -> Sweep {
    let SweepIn { y, lo, hi, ylo, yhi, sc, gs, qs } = *v;
    assert_eq!(y.len(), csr.rowptr.len() - 1);
    let pt = run2(par, wy, yt, parts, |r0, wo, to| {
        let mut pt = Partial::default();
        let mut bad = 0.0;
        for (k, (wk, tk)) in wo.iter_mut().zip(to.iter_mut()).enumerate() {
            let i = r0 + k;
            let yi = y[i];
            let w = csr.row_dot(i, y);
            *wk = w;
            let f = qs[i] + w;
            let zi = unscale(yi, ylo[i], yhi[i], lo[i], hi[i], sc[i]);
            let r = (zi - clip(zi - gs[i] * f, lo[i], hi[i])).abs();
            let t = clip(yi - beta * f, ylo[i], yhi[i]);
            *tk = t;
            let e = yi - t;
            pt.s0 += e * e;
            // Infeasibility of y: a max per block; `reduce` sums the blocks, which keeps
            // "> 0" intact.
            pt.s1 = pt.s1.max((ylo[i] - yi).max(yi - yhi[i]));
            pt.m0 = pt.m0.max(r);
            pt.m1 = pt.m1.max(zi.abs());
            // NaN/inf detector: `clip` and `max` would swallow a NaN.
            bad += yi * 0.0 + f * 0.0;
        }
        pt.s2 = bad;
        pt
    });
    Sweep {
        res: pt.m0 / pt.m1.max(1.0),
        znorm: pt.m1,
        ee: pt.s0,
        finite: pt.s2.is_finite() && pt.s0.is_finite(),
        infeasible: pt.s1 > 0.0,
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

#[cfg(test)]
mod tests {
    //! Closed-form cases. Every expected value below is derived by hand in the comment above
    //! its test; tolerances are stated there.

    use super::*;
    use sprs::TriMat;

    const INF: f64 = f64::INFINITY;

    /// Dense row-major symmetric matrix -> CSR (both triangles, zeros dropped).
    fn csr(n: usize, dense: &[f64]) -> CsMat<f64> {
        let mut t = TriMat::new((n, n));
        for i in 0..n {
            for j in 0..n {
                if dense[i * n + j] != 0.0 {
                    t.add_triplet(i, j, dense[i * n + j]);
                }
            }
        }
        t.to_csr()
    }

    fn opts(tolerance: f64, jacobi: bool) -> Options {
        Options { tolerance, jacobi, ..Options::default() }
    }

    /// Solves a plain VI from a zero warm start; returns the report, z and the stats.
    fn fixed(w: &CsMat<f64>, q: &[f64], lo: &[f64], hi: &[f64], o: &Options) -> (Report, Vec<f64>, Stats) {
        let mut ws = Workspace::new();
        let mut z = vec![0.0; q.len()];
        let mut rule = FixedBounds { lo: lo.to_vec(), hi: hi.to_vec() };
        let rep = solve_with(&mut ws, &Problem { w, q }, &mut rule, &mut z, o);
        (rep, z, ws.stats())
    }

    /// Coulomb rule for one (normal, tangent) pair: tau = mu max(z_n, 0) (math note §4.1).
    struct Friction(f64);
    impl BoundRule for Friction {
        fn bounds(&mut self, z: &[f64], lo: &mut [f64], hi: &mut [f64]) {
            let tau = self.0 * z[0].max(0.0);
            (lo[0], hi[0], lo[1], hi[1]) = (0.0, INF, -tau, tau);
        }
    }

    /// Zero rows: nothing to do, converged, no call to the bound rule needed.
    #[test]
    fn empty_problem() {
        let w: CsMat<f64> = CsMat::zero((0, 0));
        let rep = solve(
            &Problem { w: &w, q: &[] },
            &mut FixedBounds { lo: vec![], hi: vec![] },
            &mut [],
            &Options::default(),
        );
        assert_eq!(rep, Report { outer_iterations: 0, inner_iterations: 0, residual: 0.0, converged: true });
    }

    /// min 1/2 w z² + q z on [lo, hi]: the solution is clip(−q/w, lo, hi) (the objective is
    /// a parabola with vertex −q/w). The scaled residual at the solution is 0 once the
    /// iterate reaches it; we ask 1e-12 and compare to 1e-12 relative (a 1-D PC iteration
    /// contracts exactly, so the only error is round-off and the residual bound
    /// |z − z*| <= 1e-12 max(1, |z|)).
    #[test]
    fn one_dimensional_closed_form() {
        let cases = [
            // (w, q, lo, hi)
            (2.0, -3.0, -INF, INF),  // free: 1.5
            (2.0, -3.0, 0.0, 1.0),   // upper active: 1
            (2.0, 3.0, 0.0, INF),    // lower active: 0
            (2.0, 3.0, -INF, INF),   // free, negative: −1.5
            (1e-6, -1.0, 0.0, INF),  // tiny w, large force: 1e6
            (1e6, -1.0, -2.0, 2.0),  // stiff: 1e-6
            (5.0, 0.0, -1.0, 1.0),   // q = 0: 0
            (3.0, -6.0, 2.0, 2.0),   // degenerate box: 2
            (3.0, 30.0, -4.0, -1.0), // lower active at a negative bound: −4
        ];
        for jacobi in [true, false] {
            for &(w, q, lo, hi) in &cases {
                let m = csr(1, &[w]);
                let (rep, z, _) = fixed(&m, &[q], &[lo], &[hi], &opts(1e-12, jacobi));
                let want = (-q / w).max(lo).min(hi);
                assert!(rep.converged && rep.residual <= 1e-12, "{w} {q} {lo} {hi}: {rep:?}");
                assert!(
                    (z[0] - want).abs() <= 1e-12 * want.abs().max(1.0),
                    "{w} {q} {lo} {hi}: {} vs {want}",
                    z[0]
                );
                assert!(lo <= z[0] && z[0] <= hi);
            }
        }
    }

    /// W = [[2, 1], [1, 2]], q = (1, −3), z >= 0. Unconstrained minimiser
    /// −W⁻¹q = (1/3)[[2, −1], [−1, 2]](−1, 3) = (−5/3, 7/3) violates z1 >= 0, so z1 = 0
    /// is active and z2 = 3/2 from 2 z2 − 3 = 0; then G1 = 1 + 3/2 = 5/2 >= 0 confirms the
    /// active set. Tolerance 1e-10: residual 1e-12 and cond(W) = 3.
    #[test]
    fn two_by_two_active_set() {
        let w = csr(2, &[2.0, 1.0, 1.0, 2.0]);
        for jacobi in [true, false] {
            for correction in [Correction::Extragradient, Correction::Contraction] {
                let mut ws = Workspace::new();
                ws.correction = correction;
                let mut z = vec![0.7, -3.0]; // infeasible warm start
                let mut rule = FixedBounds { lo: vec![0.0, 0.0], hi: vec![INF, INF] };
                let rep = solve_with(
                    &mut ws,
                    &Problem { w: &w, q: &[1.0, -3.0] },
                    &mut rule,
                    &mut z,
                    &opts(1e-12, jacobi),
                );
                assert!(rep.converged, "{rep:?}");
                if correction == Correction::Extragradient {
                    // projected iterates land on the active bound exactly
                    assert_eq!(z[0], 0.0);
                }
                assert!(z[0] >= 0.0 && z[0] < 1e-10 && (z[1] - 1.5).abs() < 1e-10, "{z:?}");
            }
        }
    }

    /// Singular W = B Bᵀ, B = [[1, 0], [0, 1], [1, 1]] (3 rows, 2 DOFs), q = −B c with
    /// c = (1, 1), z >= 0: the objective is 1/2 |Bᵀz − c|² − 1/2 |c|², minimised by every
    /// z >= 0 with Bᵀz = c: z = (1 − t, 1 − t, t), t in [0, 1]. z is not unique but
    /// W z = B c = (1, 1, 2) and the gaps G = 0 are (math note §3.2). Different warm
    /// starts must give the same W z to 1e-9 (residual 1e-12, ||W|| = 3).
    #[test]
    fn singular_w_unique_wz() {
        let w = csr(3, &[1.0, 0.0, 1.0, 0.0, 1.0, 1.0, 1.0, 1.0, 2.0]);
        let q = [-1.0, -1.0, -2.0];
        let mut seen = Vec::new();
        for (start, jacobi) in [([0.0, 0.0, 0.0], true), ([0.0, 0.0, 5.0], true), ([3.0, 0.0, 0.0], false)] {
            let mut z = start.to_vec();
            let mut rule = FixedBounds { lo: vec![0.0; 3], hi: vec![INF; 3] };
            let rep = solve(&Problem { w: &w, q: &q }, &mut rule, &mut z, &opts(1e-12, jacobi));
            assert!(rep.converged, "{rep:?}");
            let wz = [z[0] + z[2], z[1] + z[2], z[0] + z[1] + 2.0 * z[2]];
            for (a, b) in wz.iter().zip([1.0, 1.0, 2.0]) {
                assert!((a - b).abs() < 1e-9, "{start:?}: W z = {wz:?}");
            }
            seen.push(z);
        }
        // ... while z itself differs between warm starts (non-unique forces)
        assert!((seen[0][2] - seen[1][2]).abs() > 1e-3, "{seen:?}");
    }

    /// One contact, coupled W = [[2, 0.5], [0.5, 1]] (normal, tangent), mu = 0.5,
    /// tau = mu max(z_n, 0) (math note §4.1).
    /// Sticking, q = (−2, −0.2): W⁻¹ = [[1, −0.5], [−0.5, 2]] / 1.75, the unconstrained
    /// solution −W⁻¹q = (1.9, −0.6)/1.75 = (1.0857.., −0.3428..) has |z_t| = 0.343 <
    /// mu z_n = 0.543: both gaps close, z = (38/35, −12/35).
    /// Sliding, q = (−2, −2): −W⁻¹q = (1, 3)/1.75 has z_t > mu z_n, so z_t = mu z_n and
    /// the normal gap closes: −2 + 2 z_n + 0.5 (0.5 z_n) = 0, z_n = 8/9, z_t = 4/9; the
    /// tangent gap −2 + 0.5 (8/9) + 4/9 = −10/9 < 0 agrees with z_t at its upper bound.
    /// Tolerance 1e-9: tolerance 1e-12 on the residual, cond(W) < 3, and the outer loop
    /// stops once the bound moved by less than 1e-12 (1 + mu z_n).
    #[test]
    fn coulomb_stick_and_slide() {
        let w = csr(2, &[2.0, 0.5, 0.5, 1.0]);
        for jacobi in [true, false] {
            for (q, want) in
                [([-2.0, -0.2], [38.0 / 35.0, -12.0 / 35.0]), ([-2.0, -2.0], [8.0 / 9.0, 4.0 / 9.0])]
            {
                let mut z = vec![0.0, 0.0];
                let rep = solve(&Problem { w: &w, q: &q }, &mut Friction(0.5), &mut z, &opts(1e-12, jacobi));
                assert!(rep.converged, "{q:?}: {rep:?}");
                assert!(
                    (z[0] - want[0]).abs() < 1e-9 && (z[1] - want[1]).abs() < 1e-9,
                    "{q:?}: {z:?} vs {want:?}"
                );
                // sliding needs more than one bound update, sticking settles at once
                assert!(rep.outer_iterations >= if q[1] == -2.0 { 3 } else { 1 }, "{rep:?}");
            }
        }
    }

    /// CSC storage of a symmetric W reads the same as CSR: the 2×2 of
    /// `two_by_two_active_set` given as CSC must give the same bits.
    #[test]
    fn csc_input() {
        let w = csr(2, &[2.0, 1.0, 1.0, 2.0]);
        let wc = w.to_csc();
        let (a, za, _) = fixed(&w, &[1.0, -3.0], &[0.0, 0.0], &[INF, INF], &opts(1e-12, true));
        let (b, zb, _) = fixed(&wc, &[1.0, -3.0], &[0.0, 0.0], &[INF, INF], &opts(1e-12, true));
        assert!(a.converged);
        assert_eq!((a, za), (b, zb));
    }

    /// A warm start that already solves the VI costs no iteration: one outer pass (the PC
    /// run returns at its first residual check) and one confirming pass. Expected from the
    /// algorithm: inner = 0, outer = 1, z unchanged bit for bit.
    #[test]
    fn warm_start_at_solution() {
        let w = csr(2, &[2.0, 1.0, 1.0, 2.0]);
        let mut z = vec![0.0, 1.5];
        let mut rule = FixedBounds { lo: vec![0.0, 0.0], hi: vec![INF, INF] };
        let rep = solve(&Problem { w: &w, q: &[1.0, -3.0] }, &mut rule, &mut z, &opts(1e-12, true));
        assert_eq!((rep.outer_iterations, rep.inner_iterations, rep.converged), (1, 0, true));
        assert_eq!(z, vec![0.0, 1.5]);
    }

    /// A zero row (W_jj = 0, hence the whole row is 0 for a PSD W) with q_j < 0 and no upper
    /// bound has no solution (G_j = q_j < 0 pushes z_j to +inf): reported as Diverged at
    /// once, with the warm start restored. With a finite upper bound it is solvable:
    /// z_j = hi_j. The other row is an ordinary 1-D problem (z = 3/2, to 1e-11: residual
    /// 1e-12 times max(1, ||z||) = 7).
    #[test]
    fn zero_row() {
        let w = csr(2, &[0.0, 0.0, 0.0, 2.0]);
        let q = [-1.0, -3.0];
        let mut ws = Workspace::new();
        let mut z = vec![0.25, 0.5];
        let mut rule = FixedBounds { lo: vec![0.0, 0.0], hi: vec![INF, INF] };
        let rep = solve_with(&mut ws, &Problem { w: &w, q: &q }, &mut rule, &mut z, &Options::default());
        assert!(!rep.converged && ws.stats().status == Status::Diverged);
        assert_eq!((rep.inner_iterations, rep.residual), (0, INF));
        assert_eq!(z, vec![0.25, 0.5]);

        let (rep, z, _) = fixed(&w, &q, &[0.0, 0.0], &[7.0, INF], &opts(1e-12, true));
        assert!(rep.converged, "{rep:?}");
        assert_eq!(z[0], 7.0);
        assert!((z[1] - 1.5).abs() < 1e-11);
    }

    /// Unbounded problems (no solution): the iterates run along a ray d with W d = 0 and
    /// qᵀd < 0. (a) A particle jammed between two walls: rows n and −n of one body,
    /// W = [[1, −1], [−1, 1]], both gaps −1 (q = (−1, −1)), forces >= 0: d = (1, 1).
    /// (b) Two identical free rows, W = [[1, 1], [1, 1]], q = (1, −1): d = (−1, 1).
    /// Expected: converged = false with status Diverged (growth test), warm start restored,
    /// and no NaN; within a few hundred iterations (beta grows geometrically along the ray).
    #[test]
    fn unbounded_rays_are_reported() {
        let cases = [
            ([1.0, -1.0, -1.0, 1.0], [-1.0, -1.0], [0.0, 0.0]),
            ([1.0, 1.0, 1.0, 1.0], [1.0, -1.0], [-INF, -INF]),
        ];
        for (dense, q, lo) in cases {
            let w = csr(2, &dense);
            let (rep, z, st) = fixed(&w, &q, &lo, &[INF, INF], &Options::default());
            assert!(!rep.converged && st.status == Status::Diverged, "{rep:?} {st:?}");
            assert!(rep.inner_iterations < 1000, "{rep:?}");
            assert_eq!(z, vec![0.0, 0.0]);
        }
    }

    /// NaN in q: reported as NonFinite (never a panic, never NaN in z: the warm start is
    /// restored).
    #[test]
    fn nan_input_is_reported() {
        let w = csr(2, &[2.0, 1.0, 1.0, 2.0]);
        let (rep, z, st) = fixed(&w, &[f64::NAN, 1.0], &[0.0, 0.0], &[INF, INF], &Options::default());
        assert!(!rep.converged && st.status == Status::NonFinite, "{rep:?} {st:?}");
        assert_eq!(z, vec![0.0, 0.0]);
    }

    /// A bound rule returning lo > hi: InvalidBounds, z untouched (no valid box ever seen).
    #[test]
    fn invalid_bounds_are_reported() {
        let w = csr(1, &[1.0]);
        let mut ws = Workspace::new();
        let mut z = vec![0.5];
        let mut rule = FixedBounds { lo: vec![1.0], hi: vec![0.0] };
        let rep = solve_with(&mut ws, &Problem { w: &w, q: &[-1.0] }, &mut rule, &mut z, &Options::default());
        assert!(!rep.converged && ws.stats().status == Status::InvalidBounds);
        assert_eq!(z, vec![0.5]);
    }

    /// Iteration budget: with max_iterations = 3 on an ill-conditioned 2×2
    /// (W = [[1, 0.999], [0.999, 1]], free rows) PC cannot reach 1e-12, so converged =
    /// false with IterationLimit, exactly 3 inner iterations, a finite z inside the box and
    /// a residual above the tolerance.
    #[test]
    fn iteration_limit_is_reported() {
        let w = csr(2, &[1.0, 0.999, 0.999, 1.0]);
        let o = Options { max_iterations: 3, ..opts(1e-12, true) };
        let (rep, z, st) = fixed(&w, &[1.0, -1.0], &[-10.0, -10.0], &[10.0, 10.0], &o);
        assert!(!rep.converged && st.status == Status::IterationLimit, "{rep:?}");
        assert_eq!(rep.inner_iterations, 3);
        assert!(rep.residual > 1e-12 && rep.residual.is_finite());
        assert!(z.iter().all(|v| v.is_finite() && v.abs() <= 10.0));
    }

    /// A workspace reused for problems of different sizes gives the same results as fresh
    /// workspaces (no stale state): bit-identical z and reports.
    #[test]
    fn workspace_reuse() {
        let big = csr(3, &[1.0, 0.0, 1.0, 0.0, 1.0, 1.0, 1.0, 1.0, 2.0]);
        let small = csr(2, &[2.0, 0.5, 0.5, 1.0]);
        let mut ws = Workspace::new();
        for _ in 0..2 {
            for (w, q) in [(&big, vec![-1.0, -1.0, -2.0]), (&small, vec![-2.0, -2.0])] {
                let n = q.len();
                let run = |ws: &mut Workspace| {
                    let mut z = vec![0.0; n];
                    let rep = solve_with(
                        ws,
                        &Problem { w, q: &q },
                        &mut FixedBounds { lo: vec![0.0; n], hi: vec![INF; n] },
                        &mut z,
                        &opts(1e-12, true),
                    );
                    (rep, z)
                };
                let (a, b) = (run(&mut ws), run(&mut Workspace::new()));
                assert_eq!(a.0, b.0);
                assert!(a.1.iter().zip(&b.1).all(|(x, y)| x.to_bits() == y.to_bits()));
            }
        }
    }

    /// Products per iteration (math note §4.2: store W z, two products per iteration when
    /// the first trial step is accepted): products = 2 inner + shrinks + one sweep per
    /// outer pass that starts a PC run (here one pass) — checked on the 2×2.
    #[test]
    fn product_count() {
        let w = csr(2, &[2.0, 1.0, 1.0, 2.0]);
        let (rep, _, st) = fixed(&w, &[1.0, -3.0], &[-INF, -INF], &[INF, INF], &opts(1e-12, true));
        assert!(rep.converged);
        assert_eq!(st.products, 2 * rep.inner_iterations + st.shrinks + 1, "{rep:?} {st:?}");
    }
}
