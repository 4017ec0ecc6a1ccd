//! Semismooth Newton on the natural map (math note §4.16): the residual of §4.3,
//! r(z) = z − P_[lo(z), hi(z)][z − D⁻¹ G(z)], is piecewise affine in z, bounds included (a
//! friction bound a + b p moves with its own normal force p). Each step picks the piece of the
//! current iterate (row by row: free, at its lower or at its upper bound), solves that piece's
//! linear system by a sparse LU, and takes the step with a backtracking line search on ½‖r‖².
//! Where the pattern of free, stick and slide rows is right, one step lands on the solution;
//! sliding contacts cost no outer passes, since a slide row's equation z_t = ±(a + b p) holds
//! the bound's dependence on p.

use super::measure::{Goal, Measure, Tally};
use super::{BoundRule, Options};
use crate::sparse::CsrView;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::lu::{LuRef, NumericLu, factorize_symbolic_lu};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, MatMut, Par};

/// Newton steps a run may take before it hands over (each is one sparse LU).
pub(super) const MAX_STEPS: usize = 30;
/// Added to the unit diagonal of a free row's D⁻¹-scaled equation, so that a hyperstatic set of
/// sticking rows (W_FF singular, §3.2) still gives a step: range components converge at rate
/// reg / (reg + λ) a step, null-space ones (self-stress, which changes no gap) stay. A step the
/// line search rejects is tried again from the same iterate with reg × [`REG_GROWTH`] (shorter
/// and closer to a Jacobi step), up to [`MAX_REG`]; an accepted step resets it.
const REG: f64 = 1e-9;
const REG_GROWTH: f64 = 1e3;
const MAX_REG: f64 = 1e-2;
/// Armijo's constant and the shortest step of the line search.
const SIGMA: f64 = 1e-4;
const MIN_STEP: f64 = 1.0 / 1024.0;

/// Work storage, reused across calls.
#[derive(Default)]
pub(super) struct Work {
    g: Vec<f64>,
    d: Vec<f64>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    rhs: Vec<f64>,
    zt: Vec<f64>,
    trip: Vec<Triplet<usize, usize, f64>>,
    numeric: NumericLu<usize, f64>,
}

/// A clone starts with empty storage (the factor is scratch, remade every step).
impl Clone for Work {
    fn clone(&self) -> Self {
        Work::default()
    }
}

impl std::fmt::Debug for Work {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("newton::Work").field("rows", &self.g.len()).finish()
    }
}

/// How a run ended: converged (z the answer, of this residual), or not (z the warm start again).
pub(super) enum End {
    Done { steps: usize, residual: f64 },
    Failed { steps: usize },
}

/// The measure of one iterate: reported residual (§4.3) and ½‖r‖².
#[derive(Clone, Copy)]
struct Value {
    res: f64,
    merit: f64,
}

impl Work {
    /// Runs Newton from z (overwritten): `Done` once the residual meets the goal of §4.11 (a
    /// start within the tolerance is kept), `Failed` (z restored) when the line search finds no
    /// decrease, a step is not finite, or [`MAX_STEPS`] (or `opts.max_iterations`) are spent.
    /// `products` counts products with W.
    #[allow(clippy::too_many_arguments)]
    pub fn run(
        &mut self,
        w: CsrView<'_>,
        q: &[f64],
        blocks: &[usize],
        rule: &dyn BoundRule,
        z: &mut [f64],
        opts: &Options,
        products: &mut usize,
    ) -> End {
        let n = q.len();
        if !self.setup(w, n) {
            return End::Failed { steps: 0 };
        }
        let z0 = z.to_vec();
        let measure = Measure::new(opts);
        let mut goal = Goal::new(opts.tolerance, opts.aim * opts.tolerance);
        let cap = MAX_STEPS.min(opts.max_iterations);
        *products += 1;
        let mut v = self.value(w, q, blocks, rule, z, measure);
        let (mut steps, mut reg) = (0, REG);
        let fail = |z: &mut [f64], steps| {
            z.copy_from_slice(&z0);
            End::Failed { steps }
        };
        loop {
            if !v.res.is_finite() {
                return fail(z, steps);
            }
            if goal.reached(v.res, steps) {
                return End::Done { steps, residual: v.res };
            }
            if steps >= cap || reg > MAX_REG {
                return fail(z, steps);
            }
            steps += 1;
            let accepted = match self.direction(w, blocks, rule, z, reg) {
                true => self.search(w, q, blocks, rule, z, v, measure, products),
                false => None,
            };
            match accepted {
                Some(vt) => {
                    z.copy_from_slice(&self.zt);
                    (v, reg) = (vt, REG);
                }
                // a shorter, more gradient-like step from the same z
                None => reg *= REG_GROWTH,
            }
        }
    }

    /// Backtracking on ½‖r‖² along the direction in `rhs`: the measure of the accepted point,
    /// which is left in `zt`; `None` below [`MIN_STEP`].
    #[allow(clippy::too_many_arguments)]
    fn search(
        &mut self,
        w: CsrView<'_>,
        q: &[f64],
        blocks: &[usize],
        rule: &dyn BoundRule,
        z: &[f64],
        v: Value,
        measure: Measure,
        products: &mut usize,
    ) -> Option<Value> {
        let mut t = 1.0;
        while t >= MIN_STEP {
            for (i, zt) in self.zt.iter_mut().enumerate() {
                *zt = z[i] + t * self.rhs[i];
            }
            let zt = std::mem::take(&mut self.zt);
            *products += 1;
            let vt = self.value(w, q, blocks, rule, &zt, measure);
            self.zt = zt;
            if vt.merit <= (1.0 - 2.0 * SIGMA * t) * v.merit {
                return Some(vt);
            }
            t *= 0.5;
        }
        None
    }

    /// Sizes the vectors and reads D = diag(W); false when a diagonal is not positive and finite.
    fn setup(&mut self, w: CsrView<'_>, n: usize) -> bool {
        for v in [&mut self.g, &mut self.d, &mut self.lo, &mut self.hi, &mut self.rhs, &mut self.zt] {
            v.clear();
            v.resize(n, 0.0);
        }
        if w.rows() != n || w.cols() != n || !w.is_csr() {
            return false;
        }
        for (i, row) in w.outer_iterator().enumerate() {
            self.d[i] = row.iter().filter(|&(j, _)| j == i).map(|(_, v)| *v).sum();
        }
        self.d.iter().all(|&d| d > 0.0 && d.is_finite())
    }

    /// G = q + W z, the rule's bounds at z, and the measure of z (reported and merit).
    fn value(
        &mut self,
        w: CsrView<'_>,
        q: &[f64],
        blocks: &[usize],
        rule: &dyn BoundRule,
        z: &[f64],
        measure: Measure,
    ) -> Value {
        rule.all_bounds(blocks, z, &mut self.lo, &mut self.hi);
        let (mut tally, mut merit) = (Tally::default(), 0.0);
        for (i, row) in w.outer_iterator().enumerate() {
            let g = q[i] + row.iter().map(|(j, v)| v * z[j]).sum::<f64>();
            self.g[i] = g;
            let (l, h) = (self.lo[i], self.hi[i]);
            if l.is_nan() || h.is_nan() || l > h {
                return Value { res: f64::INFINITY, merit: f64::INFINITY };
            }
            let d = self.d[i];
            tally.add(&measure, z[i], g / d, l, h, d);
            let r = z[i] - super::pc::clip(z[i] - g / d, l, h);
            merit += 0.5 * r * r;
        }
        let res = tally.value().unwrap_or(f64::INFINITY);
        Value { res, merit: if res.is_finite() { merit } else { f64::INFINITY } }
    }

    /// The Newton direction of the piece of z (G, bounds from the last [`Self::value`] at z)
    /// into `rhs`; false when the system is singular or the step not finite.
    fn direction(
        &mut self,
        w: CsrView<'_>,
        blocks: &[usize],
        rule: &dyn BoundRule,
        z: &[f64],
        reg: f64,
    ) -> bool {
        let n = z.len();
        self.trip.clear();
        for (k, b) in blocks.windows(2).enumerate() {
            let (r0, m) = (b[0], b[1] - b[0]);
            // d bound / d p of the block's friction and rolling rows (law of math note §4.7)
            let slope = match rule.block_law(k, z).filter(|_| m >= 2) {
                Some(law) if z[r0] > 0.0 => law.b,
                _ => [0.0; 2],
            };
            for i in r0..r0 + m {
                let (l, h, d) = (self.lo[i], self.hi[i], self.d[i]);
                let u = z[i] - self.g[i] / d;
                let at = if u >= h {
                    Some((h, 1.0))
                } else if u <= l {
                    Some((l, -1.0))
                } else {
                    None
                };
                match at {
                    Some((bound, side)) => {
                        // z_i − bound(p) = 0, bound = ±(a + b p) on a friction row
                        self.trip.push(Triplet::new(i, i, 1.0));
                        if i > r0 && slope[i - r0 - 1] != 0.0 {
                            self.trip.push(Triplet::new(i, r0, -side * slope[i - r0 - 1]));
                        }
                        self.rhs[i] = bound - z[i];
                    }
                    None => {
                        // D⁻¹ (q + W z)_i = 0
                        let Some(row) = w.outer_view(i) else { return false };
                        for (j, v) in row.iter() {
                            self.trip.push(Triplet::new(i, j, v / d + if j == i { reg } else { 0.0 }));
                        }
                        self.rhs[i] = -self.g[i] / d;
                    }
                }
            }
        }
        self.solve(n) && self.rhs.iter().all(|x| x.is_finite())
    }

    /// rhs ← J⁻¹ rhs, J from `trip` (faer's sparse LU, COLAMD ordering, one core).
    fn solve(&mut self, n: usize) -> bool {
        let Ok(j) = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &self.trip) else { return false };
        let Ok(symbolic) = factorize_symbolic_lu(j.symbolic(), Default::default()) else { return false };
        let req = symbolic
            .factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default())
            .or(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        let mut buffer = MemBuffer::new(req);
        let stack = MemStack::new(&mut buffer);
        // a fresh numeric factor: faer's keeps the sizes of the last system it held
        self.numeric = NumericLu::new();
        let ok =
            symbolic.factorize_numeric_lu(&mut self.numeric, j.as_ref(), Par::Seq, stack, Default::default());
        if ok.is_err() {
            return false;
        }
        let lu = LuRef::new_unchecked(&symbolic, &self.numeric);
        let rhs = MatMut::from_column_major_slice_mut(&mut self.rhs, n, 1);
        lu.solve_in_place_with_conj(Conj::No, rhs, Par::Seq, MemStack::new(&mut buffer));
        true
    }
}
