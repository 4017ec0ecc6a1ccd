//! MPRGP's face solves (math note §4.10): when a run is slow, minimize the quadratic exactly
//! on the current face (the rows strictly inside their box free, the others held) by one
//! sparse Cholesky factorization of the free rows' block of Ŵ, and step towards that minimizer
//! with the box projection, keeping the step only if it lowers the objective.
//!
//! On a pile of disks W behaves like a discrete Laplacian over the contact network, and its
//! condition number grows with the pile's height squared: CG on the face needs hundreds or
//! thousands of iterations where one factorization (the face block is as sparse as W, a
//! planar graph) gives the face's minimizer at once. Factorizations are not reused: the face
//! changes between solves, so each does its own symbolic analysis.

use super::Status;
use super::pc::{Ctx, State, Vectors, clip, sweep};
use super::scaling::Rows;
use crate::sparse::SparseFactor;

/// The first face solve of a run after this many of its iterations (warm-started steps of a
/// resting pile converge in 0 to 5), then one every [`EVERY`] iterations while they go at
/// least [`GOOD`] of the way to the face's minimizer; after a shorter step or a declined
/// solve, the interval grows [`BACKOFF`]-fold (the face was far from the final one).
pub(super) const FIRST: usize = 20;
/// A run that starts with its residual within this factor of its tolerance is *warm* (a resting
/// pile's step); its first face solve waits at least n / [`ROWS_PER_ITERATION`] iterations, n
/// the rows: about what a face solve costs in iterations (measured: ~25 at 58,000 rows, ~110
/// at 239,000, where a face solve took seconds). Cold runs keep [`FIRST`]: the cold steps of
/// the piles depend on early face solves (a size-scaled first solve made the 10,000-disk cold
/// step 660 iterations instead of 387), and their late face solves make the steps after them
/// cheap (math note §4.10).
pub(super) const WARM: f64 = 100.0;
/// Rows per iteration of a warm run's wait for its first face solve (see [`WARM`]).
pub(super) const ROWS_PER_ITERATION: usize = 1000;
pub(super) const EVERY: usize = 10;
pub(super) const GOOD: f64 = 0.25;
pub(super) const BACKOFF: usize = 4;
/// Added to the face block's diagonal (Ŵ's is 1) when the block alone does not factorize: a
/// hyperstatic face block is singular, and this picks the nearly minimum-norm minimizer while
/// keeping the factorization stable.
const EPS: f64 = 1e-9;
/// Problems with fewer rows get no face solves. The reason is a limit of the face step, not
/// of small problems: on the 1e12 heavy-on-light stack of `tests/paper/mass_ratio.rs` (8 rows, 6
/// DOFs) Ŵ_FF's smallest range eigenvalues (~1e-12) cannot be told from its null space (the
/// self-stress of the hyperstatic rows), so the factorization succeeds and the step adds a
/// self-stress that neither the objective nor the exact gaps of §10.10's polish see (they
/// measured 1e-28 m after it): corner forces 5.6e-6 off statics instead of 3.3e-7. MPRGP's
/// own steps move along gradients, which lie in Ŵ's range. Piles are far from that ratio;
/// a large problem with such a ratio would meet the same limit (math note §4.10).
pub(super) const MIN_ROWS: usize = 128;
/// Steps tried along the projected path: α = 1, 1/4, 1/16, ...
const TRIALS: usize = 6;

/// Iterations before a run's first face solve: [`FIRST`], or for a warm run (residual `res`
/// within [`WARM`] times `tol` at its start) at least one per [`ROWS_PER_ITERATION`] rows.
pub(super) fn first(rows: usize, res: f64, tol: f64) -> usize {
    if res <= WARM * tol { FIRST.max(rows / ROWS_PER_ITERATION) } else { FIRST }
}

/// What a face solve did.
pub(super) enum Face {
    /// The iterate moved (lower objective) by this fraction α of the way to the face's
    /// minimizer; `v.wy` is fresh.
    Taken(f64),
    /// No trial lowered the objective, or the factorization failed: the iterate is unchanged.
    Declined,
    /// Ŵ has no entries to factorize (factored clusters), or the problem is smaller than
    /// [`MIN_ROWS`]: no face solves in this run.
    Unavailable,
}

/// ½ yᵀŴy + q̂ᵀy with a fresh `wy`.
fn objective<R: Rows>(c: &Ctx<R>, v: &Vectors) -> f64 {
    v.y.iter().zip(&v.wy).zip(c.qs).map(|((y, wy), q)| y * (0.5 * wy + q)).sum()
}

/// One face solve from the current iterate (`v.wy` fresh on entry); `regularize`: the run's
/// faces need EPS (set here when one does).
pub(super) fn solve<R: Rows>(
    c: &Ctx<R>,
    v: &mut Vectors,
    st: &mut State,
    regularize: &mut bool,
) -> Result<Face, Status> {
    let n = v.y.len();
    if n < MIN_ROWS {
        return Ok(Face::Unavailable);
    }
    let keep: Vec<bool> = (0..n).map(|i| v.ylo[i] < v.y[i] && v.y[i] < v.yhi[i]).collect();
    let free: Vec<usize> = (0..n).filter(|&i| keep[i]).collect();
    if free.is_empty() {
        return Ok(Face::Declined);
    }
    let mut lower = Vec::new();
    if !c.rows.entries(&keep, &mut lower) {
        return Ok(Face::Unavailable);
    }
    st.stats.face_solves += 1;
    let mut local = vec![usize::MAX; n];
    for (a, &i) in free.iter().enumerate() {
        local[i] = a;
    }
    // the lower triangle of Ŵ_FF in face numbering
    lower.retain_mut(|e| {
        (e.0, e.1) = (local[e.0], local[e.1]);
        e.0 >= e.1
    });
    // Ŵ_FF itself when it is positive definite (an ill-conditioned face, as under a heavy body
    // on a light one, needs it unperturbed), else Ŵ_FF + EPS I (a hyperstatic face is
    // singular); once a run's face needed EPS, its later faces (mostly the same rows) get it
    // at once instead of a failed factorization first (40 % of a face solve on the piles)
    let eps = if *regularize { EPS } else { 0.0 };
    lower.extend((0..free.len()).map(|a| (a, a, eps)));
    let mut factor = SparseFactor::new(free.len());
    if factor.factorize(&lower).is_err() {
        if *regularize {
            return Ok(Face::Declined);
        }
        *regularize = true;
        let diagonal = lower.len() - free.len();
        lower[diagonal..].iter_mut().for_each(|e| e.2 = EPS);
        if factor.factorize(&lower).is_err() {
            return Ok(Face::Declined);
        }
    }
    // Newton step on the face: Ŵ_FF d = −g_F
    let mut d: Vec<f64> = free.iter().map(|&i| -(c.qs[i] + v.wy[i])).collect();
    factor.solve_in_place(&mut d);
    if !d.iter().all(|x| x.is_finite()) {
        return Ok(Face::Declined);
    }
    let f0 = objective(c, v);
    let y0: Vec<f64> = free.iter().map(|&i| v.y[i]).collect();
    let mut alpha = 1.0;
    for _ in 0..TRIALS {
        for ((&i, y), d) in free.iter().zip(&y0).zip(&d) {
            v.y[i] = clip(y + alpha * d, v.ylo[i], v.yhi[i]);
        }
        if sweep(c, v, st) && objective(c, v) < f0 {
            return Ok(Face::Taken(alpha));
        }
        alpha *= 0.25;
    }
    for (&i, y) in free.iter().zip(&y0) {
        v.y[i] = *y;
    }
    if !sweep(c, v, st) {
        return Err(Status::NonFinite);
    }
    Ok(Face::Declined)
}
