//! The contact pattern's cell as a linear program (math note §4.13): a method of the chain
//! (`chain.rs`), last but PC in the named chains, on Coulomb problems that Lemke's method does not solve
//! (too large for it, or its paths end without an answer).
//!
//! Row by row, the natural residual of §4.3, r_i = z_i − P[z_i − g_i] with g = D⁻¹(q + W z),
//! is one of a few affine functions of z, chosen by which side of the projection z_i − g_i
//! falls on: for a normal row, r = g (closed, z_n >= g_n) or r = z_n (open); for a row with
//! |z_i| <= B = a + b z_n, r = g_i (stick, |z_i − g_i| <= B), z_i − B (slide up,
//! z_i − g_i >= B) or z_i + B (slide down). A start z₀ fixes one choice per row, its *cell*;
//! on it the smallest max_i |r_i| is a linear program in (z, t):
//!
//! ```text
//!   min t   subject to   the cell's side conditions,   −t <= r_i(z) <= t,
//!                        z_n >= 0,   |z_i| <= ‖z₀‖∞   (every row),
//! ```
//!
//! solved by Clarabel's interior-point method. The cap keeps the measure's scale
//! max(1, ‖z‖∞) at most the start's: without it the program lowers the measure by raising
//! self-equilibrated forces, which cost nothing in W (math note §4.13). The iterative methods
//! stop at near-solutions whose cells hold points several times better; the program finds the
//! best point of the start's cell, a local minimum of the residual. It does not choose the
//! cell: [`solve`] tries two starts, the stalled iterate and NSGS's iterate from zero (§4.13,
//! "Two starts"), and a problem whose two cells both miss the tolerance still fails.

use super::chain::Best;
use super::{BoundRule, Operator, Options, Problem, Stats, lemke, nsgs};
use crate::sparse::CsrView;
use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettingsBuilder, DefaultSolver, IPSolver, NonnegativeConeT};
use sprs::TriMat;

/// Largest problem taken (rows of W): a program of the 1,000 deformable disks' 5,872 rows takes
/// about 10 s, one of 562 rows 0.1 s.
const MAX_ROWS: usize = 8_000;

/// NSGS sweeps from zero that make the second start (math note §4.13, "Two starts").
const COLD_SWEEPS: usize = 10_000;

/// Interior-point iterations at most: the 1,000-disk programs end in 55–80.
const MAX_ITER: u32 = 200;

/// The side of its projection each row is on at the start (its cell).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Side {
    /// Normal row: r = g (closed) or r = z (open).
    Closed,
    Open,
    /// Bounded row: r = g (stick), z − B (up), z + B (down).
    Stick,
    Up,
    Down,
}

/// One bounded row: its normal row and bound B = a + b z_n.
#[derive(Debug, Clone, Copy)]
struct Bounded {
    normal: usize,
    a: f64,
    b: f64,
}

/// The cell program from the stalled iterate z, and if its answer misses the tolerance, from
/// NSGS's iterate after [`COLD_SWEEPS`] sweeps from zero (math note §4.13), within `budget`
/// units of work (interior-point iterations and sweeps, one unit each; §4.17): the work done
/// and the residual of the first answer that meets `opts.tolerance` by `measure` (the solver's
/// measure, §4.3, §4.9), z then that answer; `None` otherwise, z untouched. Every answer is
/// offered to `best`.
#[allow(clippy::too_many_arguments)]
pub(super) fn solve(
    w: CsrView<'_>,
    p: &Problem,
    rule: &dyn BoundRule,
    z: &mut [f64],
    opts: &Options,
    budget: usize,
    measure: &mut dyn FnMut(&[f64]) -> f64,
    best: &mut Best,
) -> (usize, Option<f64>) {
    let mut start = z.to_vec();
    let mut work = 0;
    for second in [false, true] {
        if second {
            start = cold_start(w, p, rule, opts, budget.saturating_sub(work).min(COLD_SWEEPS), &mut work);
        }
        // a problem the program does not take (or gives no point for) costs no second start
        let Some(answer) = answer(w, p, rule, &start, budget, &mut work) else { return (work, None) };
        let residual = measure(&answer);
        best.offer(residual, &answer);
        if residual <= opts.tolerance {
            z.copy_from_slice(&answer);
            return (work, Some(residual));
        }
    }
    (work, None)
}

/// NSGS from zero for `sweeps` sweeps (added to `work`), its stall guard's hand-overs ignored
/// (each one restarts the run from its iterate); a run that converges or stops on a
/// non-finite or growing iterate ends it.
fn cold_start(
    w: CsrView<'_>,
    p: &Problem,
    rule: &dyn BoundRule,
    opts: &Options,
    sweeps: usize,
    work: &mut usize,
) -> Vec<f64> {
    let (mut z, mut done, mut run) = (vec![0.0; p.q.len()], 0, nsgs::Work::default());
    while done < sweeps {
        let left = Options { max_iterations: sweeps - done, ..*opts };
        match run.run(w, p.q, p.blocks, rule, &mut z, &left, &mut Stats::default()) {
            nsgs::End::Fallback { sweeps, residual } if residual.is_finite() => done += sweeps.max(1),
            nsgs::End::Fallback { sweeps, .. } | nsgs::End::Done { sweeps, .. } => {
                done += sweeps;
                break;
            }
        }
    }
    *work += done;
    z
}

/// The minimizer of the cell program of `start` (W given as its CSR), when every block has
/// Lemke's kind of law (math note §4.12), W has at most [`MAX_ROWS`] rows and the solver gives a
/// finite point within what `work` has left of `budget` (its interior-point iterations are
/// added to `work`); `None` otherwise.
pub(super) fn answer(
    w: CsrView<'_>,
    p: &Problem,
    rule: &dyn BoundRule,
    start: &[f64],
    budget: usize,
    work: &mut usize,
) -> Option<Vec<f64>> {
    let n = p.q.len();
    let cap = MAX_ITER.min(u32::try_from(budget.saturating_sub(*work)).unwrap_or(u32::MAX));
    if n > MAX_ROWS || cap == 0 || w.rows() != n || start.len() != n {
        return None;
    }
    let bounded = laws(p, rule, start)?;
    let mut d = vec![0.0; n];
    w.diagonal(&mut d);
    if !d.iter().all(|d| d.is_finite() && *d > 0.0) || !w.data().iter().all(|v| v.is_finite()) {
        return None;
    }
    let cell = Cell { w, q: p.q, d: &d, bounded: &bounded };
    let scale = start.iter().fold(1.0, |m: f64, v| m.max(v.abs()));
    cell.solve(&cell.sides(start), scale, cap, work)
}

/// Per row, `None` for a normal row, else its bound; `None` when a block's law is not of the
/// kind taken (no tension, nothing an open contact keeps, b >= 0, one to three rows).
fn laws(p: &Problem, rule: &dyn BoundRule, z: &[f64]) -> Option<Vec<Option<Bounded>>> {
    let mut out = vec![None; p.q.len()];
    for (k, b) in p.blocks.windows(2).enumerate() {
        let law = rule.block_law(k, z)?;
        let rows = b[1] - b[0];
        if !lemke::takes(&law, rows) {
            return None;
        }
        for i in 1..rows {
            out[b[0] + i] = Some(Bounded { normal: b[0], a: law.a[i - 1], b: law.b[i - 1] });
        }
    }
    Some(out)
}

struct Cell<'a> {
    w: CsrView<'a>,
    q: &'a [f64],
    d: &'a [f64],
    bounded: &'a [Option<Bounded>],
}

/// Constraints `sign Σ terms − [t] <= rhs` as triplets, the program's variables being (z, t).
#[derive(Default)]
struct Rows {
    at: (Vec<usize>, Vec<usize>, Vec<f64>),
    b: Vec<f64>,
}

impl Rows {
    /// Adds `sign Σ terms − t <= rhs` (without the t when `t` is `None`).
    fn push(&mut self, terms: &[(usize, f64)], sign: f64, t: Option<usize>, rhs: f64) {
        let r = self.b.len();
        let extra = t.map(|t| (t, -1.0 / sign));
        for &(j, v) in terms.iter().chain(&extra) {
            self.at.0.push(r);
            self.at.1.push(j);
            self.at.2.push(sign * v);
        }
        self.b.push(rhs);
    }

    /// [a; b] as Clarabel's CSC matrix (duplicates summed) and right-hand side.
    fn matrix(self, cols: usize) -> (CscMatrix<f64>, Vec<f64>) {
        let m = self.b.len();
        let a: sprs::CsMat<f64> = TriMat::from_triplets((m, cols), self.at.0, self.at.1, self.at.2).to_csc();
        let (indptr, indices, data) = a.into_raw_storage();
        (CscMatrix::new(m, cols, indptr, indices, data), self.b)
    }
}

impl Cell<'_> {
    fn g(&self, i: usize, z: &[f64]) -> f64 {
        let row = self.w.outer_view(i).expect("a row of W");
        (self.q[i] + row.iter().map(|(j, v)| v * z[j]).sum::<f64>()) / self.d[i]
    }

    /// Each row's side at z (a row on the boundary between two sides takes the first).
    fn sides(&self, z: &[f64]) -> Vec<Side> {
        (0..z.len())
            .map(|i| {
                let v = z[i] - self.g(i, z);
                match self.bounded[i] {
                    None if v >= 0.0 => Side::Closed,
                    None => Side::Open,
                    Some(c) => {
                        let bound = c.a + c.b * z[c.normal].max(0.0);
                        if v >= bound {
                            Side::Up
                        } else if v <= -bound {
                            Side::Down
                        } else {
                            Side::Stick
                        }
                    }
                }
            })
            .collect()
    }

    /// The program's minimizer's z, or `None` when the solver gives no finite point; its
    /// interior-point iterations are added to `work`.
    fn solve(&self, sides: &[Side], cap: f64, iterations: u32, work: &mut usize) -> Option<Vec<f64>> {
        let n = self.q.len();
        let t = n;
        let mut rows = Rows::default();
        for (i, side) in sides.iter().enumerate() {
            self.row(i, *side, t, &mut rows);
            rows.push(&[(i, 1.0)], 1.0, None, cap);
            rows.push(&[(i, 1.0)], -1.0, None, cap);
            if self.bounded[i].is_none() {
                rows.push(&[(i, 1.0)], -1.0, None, 0.0); // z_n >= 0
            }
        }
        rows.push(&[(t, 1.0)], -1.0, None, 0.0);
        let m = rows.b.len();
        let (a, b) = rows.matrix(n + 1);
        let p = CscMatrix::zeros((n + 1, n + 1));
        let mut c = vec![0.0; n + 1];
        c[t] = 1.0;
        let settings = DefaultSettingsBuilder::default()
            .verbose(false)
            .max_iter(iterations)
            .tol_gap_abs(1e-8)
            .tol_gap_rel(1e-8)
            .tol_feas(1e-8)
            .build()
            .ok()?;
        let mut solver = DefaultSolver::new(&p, &c, &a, &b, &[NonnegativeConeT(m)], settings).ok()?;
        solver.solve();
        *work += solver.solution.iterations as usize;
        let x = &solver.solution.x;
        x[..n].iter().all(|v| v.is_finite()).then(|| x[..n].to_vec())
    }

    /// Row i's side conditions and |r_i| <= t, with g_i = Σ gw z + gq and v = z_i − g_i.
    fn row(&self, i: usize, side: Side, t: usize, rows: &mut Rows) {
        let d = self.d[i];
        let gw: Vec<(usize, f64)> =
            self.w.outer_view(i).expect("a row of W").iter().map(|(j, v)| (j, v / d)).collect();
        let gq = self.q[i] / d;
        let mut vw: Vec<(usize, f64)> = gw.iter().map(|&(j, v)| (j, -v)).chain([(i, 1.0)]).collect();
        let t = Some(t);
        let Some(c) = self.bounded[i] else {
            if side == Side::Closed {
                rows.push(&vw, -1.0, None, -gq); // v >= 0, r = g
                rows.push(&gw, 1.0, t, -gq);
                rows.push(&gw, -1.0, t, gq);
            } else {
                rows.push(&vw, 1.0, None, gq); // v <= 0, r = z
                rows.push(&[(i, 1.0)], 1.0, t, 0.0);
                rows.push(&[(i, 1.0)], -1.0, t, 0.0);
            }
            return;
        };
        // B = a + b z_n; up: v >= B, r = z − B; down: v <= −B, r = z + B
        let s = match side {
            Side::Up => -1.0,
            Side::Down => 1.0,
            _ => {
                vw.push((c.normal, -c.b));
                rows.push(&vw, 1.0, None, gq + c.a); // v − B <= 0
                let last = vw.len() - 1;
                vw[..last].iter_mut().for_each(|e| e.1 = -e.1);
                rows.push(&vw, 1.0, None, c.a - gq); // −v − B <= 0
                rows.push(&gw, 1.0, t, -gq); // r = g
                rows.push(&gw, -1.0, t, gq);
                return;
            }
        };
        vw.push((c.normal, s * c.b));
        rows.push(&vw, s, None, s * gq - c.a); // up: B − v <= 0; down: v + B <= 0
        let r = [(i, 1.0), (c.normal, s * c.b)]; // r = Σ r z + s a
        rows.push(&r, 1.0, t, -s * c.a);
        rows.push(&r, -1.0, t, s * c.a);
    }
}

#[cfg(test)]
mod tests {
    //! One frictional contact, W = I, q = (−1/2, 1/5), μ = 1/2: the QVI's solution is
    //! z = (1/2, −1/5) (G = q + z = 0 and |z_t| = 0.2 <= μ z_n = 0.25: closed and sticking).
    //! The interior-point method stops at gaps of 1e-8 (relative), so 1e-6 on the answer is
    //! ample. Residuals are the solver's measure (math note §4.3; D = I, max(1, |z|) = 1 here).
    use super::super::chain::Best;
    use super::super::tests::csr;
    use super::super::{BlockLaw, BoundRule, Options, Problem, measure};

    struct Coulomb;
    impl BoundRule for Coulomb {
        fn block_bounds(&self, _k: usize, z: &[f64], lo: &mut [f64], hi: &mut [f64]) {
            (lo[0], hi[0]) = (0.0, f64::INFINITY);
            let b = 0.5 * z[0].max(0.0);
            (lo[1], hi[1]) = (-b, b);
        }
        fn block_law(&self, _k: usize, _z: &[f64]) -> Option<BlockLaw> {
            Some(BlockLaw { b: [0.5, 0.0], ..BlockLaw::default() })
        }
    }

    /// The cell program's answer from `start` and its residual.
    fn run(start: &[f64]) -> (Vec<f64>, f64) {
        let w = csr(2, &[1.0, 0.0, 0.0, 1.0]);
        let q = [-0.5, 0.2];
        let p = Problem { w: &w, q: &q, blocks: &[0, 2] };
        let z = super::answer(w.view(), &p, &Coulomb, start, 1_000, &mut 0).expect("a finite answer");
        let opts = Options { tolerance: 1e-6, ..Options::default() };
        let residual = measure::Check::default().residual(&p, &Coulomb, &z, &opts);
        (z, residual)
    }

    /// The start (0.45, 0) lies in the solution's cell (z_n − g_n = 1/2 >= 0 and
    /// |z_t − g_t| = 0.2 < μ z_n = 0.225), where the solution is the one point of zero residual.
    #[test]
    fn the_start_cell_holds_the_solution_and_the_program_finds_it() {
        let (z, residual) = run(&[0.45, 0.0]);
        assert!((z[0] - 0.5).abs() <= 1e-6 && (z[1] + 0.2).abs() <= 1e-6, "{z:?}");
        assert!(residual <= 1e-6, "{residual}");
    }

    /// The start (0.3, 0.3) is closed (z_n − g_n = 1/2) and sliding down (z_t − g_t = −0.2 <=
    /// −μ z_n = −0.15). In that cell r_n = z_n − 1/2 and r_t = z_t + z_n/2, and sliding down
    /// needs z_t − g_t + μ z_n = −1/5 + z_n/2 <= 0, i.e. z_n <= 0.4 (the cap, max(1, |z|) = 1,
    /// allows more): the smallest max |r| is 0.1, at z_n = 0.4 with |z_t + 0.2| <= 0.1. The
    /// program stays in its cell and does not reach the solution.
    #[test]
    fn a_start_in_another_cell_ends_at_that_cells_best() {
        let (z, residual) = run(&[0.3, 0.3]);
        assert!((z[0] - 0.4).abs() <= 1e-6 && (z[1] + 0.2).abs() <= 0.1 + 1e-6, "{z:?}");
        assert!((residual - 0.1).abs() <= 1e-6, "{residual}");
    }

    /// The same start through `solve`: its own cell misses (0.1), so the second start, NSGS
    /// from zero, runs; on one contact NSGS's block solve is exact, so that start lies at the
    /// solution, whose cell's program returns it.
    #[test]
    fn a_start_in_another_cell_is_taken_over_by_the_second_start() {
        let w = csr(2, &[1.0, 0.0, 0.0, 1.0]);
        let q = [-0.5, 0.2];
        let p = Problem { w: &w, q: &q, blocks: &[0, 2] };
        let opts = Options { tolerance: 1e-6, ..Options::default() };
        let mut check = measure::Check::default();
        let mut measure = |x: &[f64]| check.residual(&p, &Coulomb, x, &opts);
        let mut z = vec![0.3, 0.3];
        let (_, r) =
            super::solve(w.view(), &p, &Coulomb, &mut z, &opts, 20_000, &mut measure, &mut Best::default());
        assert!(r.is_some_and(|r| r <= 1e-6), "{r:?}");
        assert!((z[0] - 0.5).abs() <= 1e-6 && (z[1] + 0.2).abs() <= 1e-6, "{z:?}");
    }
}
