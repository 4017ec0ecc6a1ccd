//! Lemke's complementary pivoting on the LCP of a small Coulomb QVI (math note §4.12): the
//! last resort of the methods' hand-overs (`guard.rs`) when NSGS has stalled. It ends in a
//! finite number of pivots at an exact solution, where the iterative methods can circle a
//! near-solution of the wrong contact pattern for ever (the slumping pile of §4.12).
//!
//! Each block (normal row n, rows i = 1.. with |z_i| <= a_i + b_i max(n, 0)) gives the LCP
//! variables of Anitescu and Potra: n, and per row i its parts z_i = t⁺ − t⁻ and a sliding
//! multiplier λ:
//!
//! ```text
//!   w_n  =  G_n                  >= 0  ⟂  n  >= 0
//!   w_t+ =  G_i + λ              >= 0  ⟂  t⁺ >= 0
//!   w_t- = −G_i + λ              >= 0  ⟂  t⁻ >= 0
//!   w_λ  =  a_i + b_i n − t⁺ − t⁻ >= 0  ⟂  λ  >= 0,     G = q + W z,
//! ```
//!
//! in Jacobi-scaled variables. Only laws without tension or cohesion that an open contact
//! loses (`tension = 0`, `a = a_open`) have this form; other problems are not taken. The
//! basis inverse is dense (m² values for m LCP variables) and a pivot costs about 2 m² flops,
//! hence [`MAX_VARS`].

// Dense index loops over rows and columns of the same matrices.
#![allow(clippy::needless_range_loop)]

use super::{BoundRule, Problem};
use sprs::CsMatView;

/// Largest LCP taken (variables; four per frictional contact of two rows, so 250 contacts):
/// 8 MB of basis inverse and about 2 Mflop a pivot. A solve that fails costs at most
/// `COVERINGS` × (`PIVOTS_PER_VAR` m + 100) pivots: about 10 s at m = 660 here (the slumping
/// pile of §4.12), where a success took 382–4,503 pivots (0.2–2 s). The 10 × 10 deformable pile
/// (1,124 variables, some 39,000 pivots for Lemke, §4.8) is left out.
pub(super) const MAX_VARS: usize = 1_000;

/// Covering vectors tried, each with a pivot cap of `PIVOTS_PER_VAR` m + 100.
const COVERINGS: usize = 4;
const PIVOTS_PER_VAR: usize = 8;

/// A row counts as tied in the ratio test when stepping by its ratio leaves no basic variable
/// below −TIE max(1, max x_B) (math note §4.12: the tie rule that keeps the path feasible).
const TIE: f64 = 1e-9;

/// The LCP w = M x + q ⟂ x >= 0 of a problem, and the map back to its z.
struct Lcp {
    m: usize,
    /// M, column-major.
    mat: Vec<f64>,
    q: Vec<f64>,
    /// Per VI row: its variable(s), `(plus, minus)`; `minus = usize::MAX` for a normal row.
    vars: Vec<(usize, usize)>,
    /// Jacobi scaling: z = sc y.
    sc: Vec<f64>,
}

/// Solves the problem, W given as the CSR that NSGS swept, by Lemke's method when it has the
/// form above and at most [`MAX_VARS`] LCP variables, in at most `budget` pivots; z
/// (overwritten only on success) gets the answer. Returns the pivots and the residual
/// (`measure`: the solver's measure of an answer, `measure::Check`, math note §4.3, §4.9) when
/// that meets `tolerance`, `None` otherwise.
pub(super) fn solve(
    w: CsMatView<'_, f64>,
    p: &Problem,
    rule: &dyn BoundRule,
    z: &mut [f64],
    (tolerance, budget): (f64, usize),
    measure: &mut dyn FnMut(&[f64]) -> f64,
) -> Option<(usize, f64)> {
    let n = p.q.len();
    let w = dense(w)?;
    let lcp = Lcp::new(p, rule, &w, z)?;
    let mut pivots = 0;
    for k in 0..COVERINGS {
        let d: Vec<f64> = (0..lcp.m).map(|i| covering(i, k)).collect();
        let cap = (PIVOTS_PER_VAR * lcp.m + 100).min(budget - pivots);
        if cap == 0 {
            break;
        }
        let (x, used) = lemke(&lcp, &d, cap);
        pivots += used;
        let Some(x) = x else { continue };
        let answer = lcp.answer(&x, n);
        let residual = measure(&answer);
        if residual <= tolerance {
            z.copy_from_slice(&answer);
            return Some((pivots, residual));
        }
    }
    None
}

/// Covering vector k, entry i: k = 0 gives ones; later ones spread over [0.5, 1.5) by the
/// golden-ratio sequence (deterministic), which breaks the ties of a degenerate q.
fn covering(i: usize, k: usize) -> f64 {
    if k == 0 {
        return 1.0;
    }
    let golden = 0.618_033_988_749_894_9;
    0.5 + ((i as f64 + 1.0) * golden * k as f64).fract()
}

/// W dense (row-major n × n) from its CSR; `None` when it is too large for [`MAX_VARS`] at any
/// block size or an entry is not finite.
fn dense(w: CsMatView<'_, f64>) -> Option<Vec<f64>> {
    let n = w.rows();
    if n > MAX_VARS {
        return None;
    }
    let mut d = vec![0.0; n * n];
    for (i, row) in w.outer_iterator().enumerate() {
        for (j, &v) in row.iter() {
            d[i * n + j] += v;
        }
    }
    d.iter().all(|v| v.is_finite()).then_some(d)
}

impl Lcp {
    /// The LCP of the problem, its laws taken at z; `None` when a block has no closed-form law
    /// of the LCP's kind, a diagonal entry is not positive, or it has more than MAX_VARS
    /// variables.
    fn new(p: &Problem, rule: &dyn BoundRule, w: &[f64], z: &[f64]) -> Option<Lcp> {
        let n = p.q.len();
        let sc: Vec<f64> = (0..n).map(|i| 1.0 / w[i * n + i].sqrt()).collect();
        if !sc.iter().all(|s| s.is_finite() && *s > 0.0) {
            return None;
        }
        let (mut vars, mut m) = (vec![(0, usize::MAX); n], 0);
        // per friction row: its λ's variable, bound a (scaled) and b (scaled), normal row
        let mut lambdas = Vec::new();
        for (k, b) in p.blocks.windows(2).enumerate() {
            let law = rule.block_law(k, z)?;
            let rows = b[1] - b[0];
            let plain = law.tension == 0.0 && law.a == law.a_open;
            if !(plain && (1..=3).contains(&rows) && law.b.iter().all(|b| *b >= 0.0)) {
                return None;
            }
            vars[b[0]] = (m, usize::MAX);
            m += 1;
            for i in 1..rows {
                let r = b[0] + i;
                vars[r] = (m, m + 1);
                lambdas.push((m + 2, law.a[i - 1] / sc[r], law.b[i - 1] * sc[b[0]] / sc[r], vars[b[0]].0));
                m += 3;
            }
        }
        if m > MAX_VARS {
            return None;
        }
        let mut lcp = Lcp { m, mat: vec![0.0; m * m], q: vec![0.0; m], vars, sc };
        lcp.fill(p.q, w);
        for &(l, a, b, normal) in &lambdas {
            let (plus, minus) = (l - 2, l - 1);
            lcp.q[l] = a;
            lcp.mat[normal * m + l] = b;
            lcp.mat[plus * m + l] = -1.0;
            lcp.mat[minus * m + l] = -1.0;
            // λ enters the rows of t⁺ and t⁻
            lcp.mat[l * m + plus] = 1.0;
            lcp.mat[l * m + minus] = 1.0;
        }
        Some(lcp)
    }

    /// The rows of n, t⁺ and t⁻: ±(Ŵ y + q̂) with y = n or t⁺ − t⁻.
    fn fill(&mut self, q: &[f64], w: &[f64]) {
        let (n, m) = (q.len(), self.m);
        for r in 0..n {
            let (plus, minus) = self.vars[r];
            let rows = [(plus, 1.0), (minus, -1.0)];
            for &(row, sign) in rows.iter().filter(|(row, _)| *row != usize::MAX) {
                self.q[row] = sign * self.sc[r] * q[r];
                for c in 0..n {
                    let v = sign * self.sc[r] * w[r * n + c] * self.sc[c];
                    let (cp, cm) = self.vars[c];
                    self.mat[cp * m + row] += v;
                    if cm != usize::MAX {
                        self.mat[cm * m + row] -= v;
                    }
                }
            }
        }
    }

    /// z from the LCP's x.
    fn answer(&self, x: &[f64], n: usize) -> Vec<f64> {
        (0..n)
            .map(|r| {
                let (plus, minus) = self.vars[r];
                let y = if minus == usize::MAX { x[plus] } else { x[plus] - x[minus] };
                self.sc[r] * y
            })
            .collect()
    }
}

/// Lemke's method with covering vector d (> 0) and at most `cap` pivots: x and the pivots
/// used, x `None` on a ray, the cap or a singular final basis.
fn lemke(lcp: &Lcp, d: &[f64], cap: usize) -> (Option<Vec<f64>>, usize) {
    let m = lcp.m;
    let q = &lcp.q;
    if q.iter().all(|v| *v >= 0.0) {
        return (Some(vec![0.0; m]), 0);
    }
    // variables: w_i = i, x_j = m + j, the artificial z0 = 2m; the basis starts with all w
    let z0 = 2 * m;
    let mut basis: Vec<usize> = (0..m).collect();
    let mut binv = vec![0.0; m * m];
    (0..m).for_each(|i| binv[i * m + i] = 1.0);
    let mut xb = q.clone();
    let (mut col, mut row_r, mut cand) = (vec![0.0; m], vec![0.0; m], Vec::new());
    let first = (0..m).filter(|&i| q[i] < 0.0).max_by(|&a, &b| (-q[a] / d[a]).total_cmp(&(-q[b] / d[b])));
    let mut r = first.unwrap_or(0);
    let mut entering = z0;
    for pivot in 0..cap {
        column(lcp, d, &binv, entering, &mut col);
        if pivot > 0 {
            match ratio_test(&xb, &col, &basis, z0, &mut cand) {
                Some(row) => r = row,
                None => return (None, pivot),
            }
        }
        let p = col[r];
        let theta = xb[r] / p;
        (0..m).for_each(|i| xb[i] -= theta * col[i]);
        xb[r] = theta;
        row_r.iter_mut().zip(&binv[r * m..(r + 1) * m]).for_each(|(o, v)| *o = v / p);
        for i in (0..m).filter(|&i| i != r && col[i] != 0.0) {
            let c = col[i];
            binv[i * m..(i + 1) * m].iter_mut().zip(&row_r).for_each(|(b, v)| *b -= c * v);
        }
        binv[r * m..(r + 1) * m].copy_from_slice(&row_r);
        let leaving = std::mem::replace(&mut basis[r], entering);
        if leaving == z0 {
            return (final_x(lcp, d, &basis), pivot + 1);
        }
        entering = if leaving < m { leaving + m } else { leaving - m };
    }
    (None, cap)
}

/// col = B⁻¹ a_j, a_j the column of variable j in [I, −M, −d].
fn column(lcp: &Lcp, d: &[f64], binv: &[f64], j: usize, col: &mut [f64]) {
    let m = lcp.m;
    if j < m {
        (0..m).for_each(|i| col[i] = binv[i * m + j]);
        return;
    }
    let a = if j < 2 * m { &lcp.mat[(j - m) * m..(j - m + 1) * m] } else { d };
    for i in 0..m {
        col[i] = -binv[i * m..(i + 1) * m].iter().zip(a).map(|(b, a)| b * a).sum::<f64>();
    }
}

/// The leaving row: the least ratio x_i / col_i over col_i > 0, rows whose ratio keeps every
/// basic variable above −TIE max(1, max x_B) counting as tied; among ties z0's row, else the
/// largest pivot. `None` on a ray.
fn ratio_test(
    xb: &[f64],
    col: &[f64],
    basis: &[usize],
    z0: usize,
    cand: &mut Vec<(f64, usize)>,
) -> Option<usize> {
    let big = col.iter().fold(0.0f64, |s, c| s.max(c.abs()));
    let eps = 1e-12 * big.max(1.0);
    cand.clear();
    cand.extend((0..xb.len()).filter(|&i| col[i] > eps).map(|i| (xb[i] / col[i], i)));
    if cand.is_empty() {
        return None;
    }
    cand.sort_by(|a, b| a.0.total_cmp(&b.0));
    let floor = -TIE * xb.iter().fold(1.0f64, |s, v| s.max(v.abs()));
    let mut best = cand[0].1;
    for (k, &(theta, i)) in cand.iter().enumerate() {
        let feasible = k == 0 || cand.iter().all(|&(_, j)| xb[j] - theta * col[j] >= floor);
        if !feasible {
            break;
        }
        if basis[i] == z0 {
            return Some(i);
        }
        if col[i] > col[best] {
            best = i;
        }
    }
    Some(best)
}

/// x from the final basis, solved afresh (LU of B) rather than read from the updated x_B.
fn final_x(lcp: &Lcp, d: &[f64], basis: &[usize]) -> Option<Vec<f64>> {
    let m = lcp.m;
    let b = nalgebra::DMatrix::from_fn(m, m, |i, k| {
        let j = basis[k];
        if j < m {
            f64::from(u8::from(i == j))
        } else if j < 2 * m {
            -lcp.mat[(j - m) * m + i]
        } else {
            -d[i]
        }
    });
    let xb = b.lu().solve(&nalgebra::DVector::from_column_slice(&lcp.q))?;
    let mut x = vec![0.0; m];
    for (k, &j) in basis.iter().enumerate() {
        if (m..2 * m).contains(&j) {
            x[j - m] = xb[k].max(0.0);
        }
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    //! Lemke on closed forms. The 2 × 2 Coulomb problems are those of `vi::tests::
    //! coulomb_stick_and_slide` (W = [[2, 0.5], [0.5, 1]], μ = 0.5), solved by hand there:
    //! sticking, q = (−2, −0.2): z = (38/35, −12/35), |z_t| = 0.343 < μ z_n = 0.543; sliding,
    //! q = (−2, −2): z = (8/9, 4/9) = (z_n, μ z_n). Pivoting is exact up to rounding on a
    //! 4-variable LCP, so 1e-12.
    use super::super::tests::csr;
    use super::super::{BlockLaw, BoundRule, Options, Problem, measure};
    use sprs::CsMat;

    /// Lemke on the problem with the solver's measure of an answer (as the hand-overs run it),
    /// tolerance `tol`.
    fn solve(
        w: &CsMat<f64>,
        p: &Problem,
        rule: &dyn BoundRule,
        z: &mut [f64],
        tol: f64,
    ) -> Option<(usize, f64)> {
        let opts = Options { tolerance: tol, ..Options::default() };
        let mut check = measure::Check::default();
        let mut measure = |x: &[f64]| check.residual(p, rule, x, &opts);
        super::solve(w.view(), p, rule, z, (tol, 100), &mut measure)
    }

    struct Coulomb(f64, f64);
    impl BoundRule for Coulomb {
        fn block_bounds(&self, _k: usize, z: &[f64], lo: &mut [f64], hi: &mut [f64]) {
            let tau = if z[0] > 0.0 { self.1 + self.0 * z[0] } else { 0.0 };
            (lo[0], hi[0], lo[1], hi[1]) = (0.0, f64::INFINITY, -tau, tau);
        }
        fn block_law(&self, _k: usize, _z: &[f64]) -> Option<BlockLaw> {
            Some(BlockLaw { a: [self.1, 0.0], b: [self.0, 0.0], ..BlockLaw::default() })
        }
    }

    #[test]
    fn lemke_stick_and_slide() {
        let w = csr(2, &[2.0, 0.5, 0.5, 1.0]);
        for (q, want) in [([-2.0, -0.2], [38.0 / 35.0, -12.0 / 35.0]), ([-2.0, -2.0], [8.0 / 9.0, 4.0 / 9.0])]
        {
            let mut z = vec![0.0; 2];
            let p = Problem { w: &w, q: &q, blocks: &[0, 2] };
            let (pivots, residual) = solve(&w, &p, &Coulomb(0.5, 0.0), &mut z, 1e-12).expect("solved");
            assert!(residual <= 1e-12 && pivots > 0, "{q:?}: {residual} after {pivots}");
            assert!((z[0] - want[0]).abs() < 1e-12 && (z[1] - want[1]).abs() < 1e-12, "{z:?} vs {want:?}");
        }
    }

    /// Cohesion that an open contact loses (a ≠ a_open) has no LCP of this form: refused, z kept.
    #[test]
    fn lemke_refuses_cohesion() {
        let w = csr(2, &[2.0, 0.5, 0.5, 1.0]);
        let mut z = vec![0.25, 0.0];
        let p = Problem { w: &w, q: &[-2.0, -0.2], blocks: &[0, 2] };
        assert!(solve(&w, &p, &Coulomb(0.5, 0.1), &mut z, Options::default().tolerance).is_none());
        assert_eq!(z, [0.25, 0.0]);
    }
}
