//! Lemke's complementary pivoting on the LCP of a Coulomb QVI (math note §4.12): the last
//! resort of the chain of methods (`chain.rs`) when NSGS has stalled. It ends in a finite
//! number of pivots at an exact solution, where the iterative methods can circle a
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
//! loses (`tension = 0`, `a = a_open`) have this form; other problems are not taken. M is kept
//! sparse and the basis as a sparse LU with one eta per pivot (`basis.rs`), so a pivot costs
//! about the factor's fill, not m²; [`MAX_VARS`], the pivot cap and [`Path`] (a covering
//! ends when its path comes back to a basis) bound the time a solve that fails can take.

use super::chain::Best;
use super::{BlockLaw, BoundRule, Problem};
use crate::sparse::{Csr, CsrView};
use sprs::TriMat;

mod basis;
use basis::Basis;

/// Largest LCP taken (variables; four per frictional contact of two rows, so 1,000 contacts).
/// The 240-disk slump's 2,756 are solved in about a second; at the 1,000-disk piles' 11,744 a
/// pivot costs about 1.8 ms and the paths loop without ending (math note §4.12, "A sparse
/// basis", "Cycling").
pub(super) const MAX_VARS: usize = 4_000;

/// Covering vectors tried, each with a pivot cap of `PIVOTS_PER_VAR` m + 100.
const COVERINGS: usize = 4;
const PIVOTS_PER_VAR: usize = 8;

/// A row counts as tied in the ratio test when stepping by its ratio leaves no basic variable
/// below −TIE max(1, max x_B) (math note §4.12: the tie rule that keeps the path feasible).
const TIE: f64 = 1e-9;

/// The LCP w = M x + q ⟂ x >= 0 of a problem, and the map back to its z.
struct Lcp {
    m: usize,
    /// M, by columns.
    mat: Csr,
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
/// that meets `tolerance`, else the pivots made (`Err`). Every answer measured is offered to `best` (the
/// chain's best answer, math note §4.7), so a near-solution that misses the tolerance still
/// counts when the chain fails.
pub(super) fn solve(
    w: CsrView<'_>,
    p: &Problem,
    rule: &dyn BoundRule,
    z: &mut [f64],
    (tolerance, budget): (f64, usize),
    measure: &mut dyn FnMut(&[f64]) -> f64,
    best: &mut Best,
) -> Result<(usize, f64), usize> {
    let n = p.q.len();
    let Some(lcp) = Lcp::new(w, p, rule, z) else { return Err(0) };
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
            return Ok((pivots, residual));
        }
        best.offer(residual, &answer);
    }
    Err(pivots)
}

/// Whether a block of `rows` rows with this law has the LCP's form: no tension, no cohesion
/// that an open contact loses (a = a_open), b >= 0, one normal row and up to two bounded ones.
pub(super) fn takes(law: &BlockLaw, rows: usize) -> bool {
    let plain = law.tension == 0.0 && law.a == law.a_open;
    plain && (1..=3).contains(&rows) && law.b.iter().all(|b| *b >= 0.0)
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

impl Lcp {
    /// The LCP of the problem (W its CSR), its laws taken at z; `None` when a block has no
    /// closed-form law of the LCP's kind, a diagonal entry is not positive or an entry not
    /// finite, or it has more than MAX_VARS variables.
    fn new(w: CsrView<'_>, p: &Problem, rule: &dyn BoundRule, z: &[f64]) -> Option<Lcp> {
        let n = p.q.len();
        // n, and per further row t⁺, t⁻ and λ: the size first, before any pass over W
        let size: usize = p.blocks.windows(2).map(|b| 1 + 3 * (b[1] - b[0]).saturating_sub(1)).sum();
        if size > MAX_VARS || w.rows() != n || w.data().iter().any(|v| !v.is_finite()) {
            return None;
        }
        let sc: Vec<f64> = (0..n).map(|i| 1.0 / w.get(i, i).copied().unwrap_or(0.0).sqrt()).collect();
        if !sc.iter().all(|s| s.is_finite() && *s > 0.0) {
            return None;
        }
        let (mut vars, mut m) = (vec![(0, usize::MAX); n], 0);
        // per friction row: its λ's variable, bound a (scaled) and b (scaled), normal row
        let mut lambdas = Vec::new();
        for (k, b) in p.blocks.windows(2).enumerate() {
            let law = rule.block_law(k, z)?;
            let rows = b[1] - b[0];
            if !takes(&law, rows) {
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
        debug_assert_eq!(m, size, "the size counted before the pass");
        let mut q = vec![0.0; m];
        let mut mat = TriMat::with_capacity((m, m), 4 * w.nnz() + 5 * lambdas.len());
        fill(w, p.q, &vars, &sc, &mut mat, &mut q);
        for &(l, a, b, normal) in &lambdas {
            let (plus, minus) = (l - 2, l - 1);
            q[l] = a;
            mat.add_triplet(l, normal, b);
            mat.add_triplet(l, plus, -1.0);
            mat.add_triplet(l, minus, -1.0);
            // λ enters the rows of t⁺ and t⁻
            mat.add_triplet(plus, l, 1.0);
            mat.add_triplet(minus, l, 1.0);
        }
        Some(Lcp { m, mat: mat.to_csc(), q, vars, sc })
    }

    /// Calls `f(i, v)` for the nonzeros of variable j's column in [I, −M, −d] (w_j: j < m, x_j:
    /// m + j, the artificial variable: 2 m).
    fn column_of(&self, d: &[f64], j: usize, mut f: impl FnMut(usize, f64)) {
        let m = self.m;
        if j < m {
            f(j, 1.0);
        } else if j < 2 * m {
            let col = self.mat.outer_view(j - m).expect("a column of M");
            col.iter().for_each(|(i, &v)| f(i, -v));
        } else {
            d.iter().enumerate().for_each(|(i, &v)| f(i, -v));
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

/// The rows of n, t⁺ and t⁻: ±(Ŵ y + q̂) with y = n or t⁺ − t⁻, into M's triplets and q.
fn fill(
    w: CsrView<'_>,
    qz: &[f64],
    vars: &[(usize, usize)],
    sc: &[f64],
    mat: &mut TriMat<f64>,
    q: &mut [f64],
) {
    let signed = |(plus, minus): (usize, usize)| {
        [(plus, 1.0), (minus, -1.0)].into_iter().filter(|v| v.0 != usize::MAX)
    };
    for (r, row) in w.outer_iterator().enumerate() {
        for (lrow, sign) in signed(vars[r]) {
            q[lrow] = sign * sc[r] * qz[r];
            for (c, &v) in row.iter() {
                let v = sign * sc[r] * v * sc[c];
                signed(vars[c]).for_each(|(lcol, s)| mat.add_triplet(lrow, lcol, s * v));
            }
        }
    }
}

/// Lemke's method with covering vector d (> 0) and at most `cap` pivots: x and the pivots
/// used. x is the LCP's solution when the artificial variable z0 leaves the basis; when the
/// path comes back to a basis or reaches the cap, x of the basis it stopped at, an exact
/// solution of the LCP with q + z0 d (a near-solution where z0 is small: math note §4.12,
/// "Cycling"); `None` on a ray or a singular basis.
fn lemke(lcp: &Lcp, d: &[f64], cap: usize) -> (Option<Vec<f64>>, usize) {
    let m = lcp.m;
    let q = &lcp.q;
    if q.iter().all(|v| *v >= 0.0) {
        return (Some(vec![0.0; m]), 0);
    }
    // variables: w_i = i, x_j = m + j, the artificial z0 = 2m; the basis starts with all w
    let z0 = 2 * m;
    let mut basis: Vec<usize> = (0..m).collect();
    let mut inv = Basis::identity();
    let mut xb = q.clone();
    let mut col = vec![0.0; m];
    let first = (0..m).filter(|&i| q[i] < 0.0).max_by(|&a, &b| (-q[a] / d[a]).total_cmp(&(-q[b] / d[b])));
    let mut r = first.unwrap_or(0);
    let mut entering = z0;
    let mut path = Path::new(m);
    for pivot in 0..cap {
        if inv.due() {
            // a fresh factor, and x_B solved afresh from it rather than carried by the updates
            if inv.refactor(lcp, d, &basis).is_none() {
                return (None, pivot);
            }
            xb.copy_from_slice(q);
            inv.solve(&mut xb);
        }
        col.fill(0.0);
        lcp.column_of(d, entering, |i, v| col[i] = v);
        inv.solve(&mut col);
        if !col.iter().all(|c| c.is_finite()) {
            return (None, pivot);
        }
        if pivot > 0 {
            match ratio_test(&xb, &col, &basis, z0) {
                Some(row) => r = row,
                None => return (None, pivot),
            }
        }
        let theta = xb[r] / col[r];
        xb.iter_mut().zip(&col).for_each(|(x, c)| *x -= theta * c);
        xb[r] = theta;
        inv.push(r, &col);
        let leaving = std::mem::replace(&mut basis[r], entering);
        // the end, or a loop: the basis's x either way (its z0 is 0 at the end)
        if leaving == z0 || !path.moved(leaving, entering) {
            return (final_x(lcp, d, &basis, &mut inv), pivot + 1);
        }
        entering = if leaving < m { leaving + m } else { leaving - m };
    }
    (final_x(lcp, d, &basis, &mut inv), cap)
}

/// The bases Lemke's path has passed, each as the Zobrist hash of its set of variables (the
/// XOR of a 64-bit key per variable, updated by a pivot in two XORs). In exact arithmetic the
/// path never meets a basis twice; in floating point it can close into a loop of a few to a few
/// hundred pivots at a degenerate near-solution and go round it until the cap (math note §4.12,
/// "Cycling"), so a repeat ends the covering. A collision of two hashes (a chance of about
/// k² / 2⁶⁵ over a path of k pivots) would only end it early.
struct Path {
    hash: u64,
    seen: std::collections::HashSet<u64>,
}

impl Path {
    /// The path at the starting basis, the slack variables w_i = 0..m.
    fn new(m: usize) -> Path {
        let hash = (0..m).fold(0, |h, v| h ^ key(v));
        Path { hash, seen: std::collections::HashSet::from([hash]) }
    }

    /// The pivot that swapped `leaving` for `entering`: false when its basis was met before.
    fn moved(&mut self, leaving: usize, entering: usize) -> bool {
        self.hash ^= key(leaving) ^ key(entering);
        self.seen.insert(self.hash)
    }
}

/// A variable's key in [`Path`]'s hashes (splitmix64's finalizer: distinct variables give
/// unrelated 64-bit keys).
fn key(v: usize) -> u64 {
    let mut h = (v as u64).wrapping_add(0x9E37_79B9_7F4A_7C15);
    h = (h ^ (h >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    h = (h ^ (h >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    h ^ (h >> 31)
}

/// The leaving row: the least ratio x_i / col_i over col_i > 0, rows whose ratio keeps every
/// basic variable above −TIE max(1, max x_B) counting as tied; among ties z0's row, else the
/// largest pivot (the least ratio, then the lowest row, among equal pivots). `None` on a ray.
/// Two passes over the rows: the largest step that keeps them all above that floor, `reach`,
/// is the least of (x_i − floor) / col_i, and a row is tied when its ratio is within it.
fn ratio_test(xb: &[f64], col: &[f64], basis: &[usize], z0: usize) -> Option<usize> {
    let big = col.iter().fold(0.0f64, |s, c| s.max(c.abs()));
    let eps = 1e-12 * big.max(1.0);
    let floor = -TIE * xb.iter().fold(1.0f64, |s, v| s.max(v.abs()));
    let rows = || (0..xb.len()).filter(|&i| col[i] > eps).map(|i| (xb[i] / col[i], i));
    let least = |a: &(f64, usize), b: &(f64, usize)| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1));
    let first = rows().min_by(least)?;
    let reach = rows().map(|(_, i)| (xb[i] - floor) / col[i]).fold(f64::INFINITY, f64::min);
    let mut best = first;
    for (theta, i) in rows().filter(|&(theta, i)| theta <= reach || i == first.1) {
        if basis[i] == z0 {
            return Some(i);
        }
        if col[i] > col[best.1] || (col[i] == col[best.1] && least(&(theta, i), &best).is_lt()) {
            best = (theta, i);
        }
    }
    Some(best.1)
}

/// x from the final basis, solved afresh (a new LU of B) rather than read from the updated x_B.
fn final_x(lcp: &Lcp, d: &[f64], basis: &[usize], inv: &mut Basis) -> Option<Vec<f64>> {
    let m = lcp.m;
    inv.refactor(lcp, d, basis)?;
    let mut xb = lcp.q.clone();
    inv.solve(&mut xb);
    let mut x = vec![0.0; m];
    for (k, &j) in basis.iter().enumerate() {
        if (m..2 * m).contains(&j) {
            x[j - m] = xb[k].max(0.0);
        }
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

#[cfg(test)]
mod tests {
    //! Lemke on closed forms. The 2 × 2 Coulomb problems are those of `vi::tests::
    //! coulomb_stick_and_slide` (W = [[2, 0.5], [0.5, 1]], μ = 0.5), solved by hand there:
    //! sticking, q = (−2, −0.2): z = (38/35, −12/35), |z_t| = 0.343 < μ z_n = 0.543; sliding,
    //! q = (−2, −2): z = (8/9, 4/9) = (z_n, μ z_n). Pivoting is exact up to rounding on a
    //! 4-variable LCP, so 1e-12.
    use super::super::chain::Best;
    use super::super::tests::csr;
    use super::super::{BlockLaw, BoundRule, Operator, Options, Problem, measure};
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
        super::solve(w.view(), p, rule, z, (tol, 100), &mut measure, &mut Best::default()).ok()
    }

    /// Normal contacts alone (one row a block, no friction): z >= 0, G >= 0, z G = 0.
    struct Normal;
    impl BoundRule for Normal {
        fn block_bounds(&self, _k: usize, _z: &[f64], lo: &mut [f64], hi: &mut [f64]) {
            (lo[0], hi[0]) = (0.0, f64::INFINITY);
        }
        fn block_law(&self, _k: usize, _z: &[f64]) -> Option<BlockLaw> {
            Some(BlockLaw::default())
        }
    }

    /// The chain matrix of the tests below: diagonal 3 + i mod 4, off diagonal −1.
    fn chain(n: usize) -> sprs::TriMat<f64> {
        let mut t = sprs::TriMat::new((n, n));
        for i in 0..n {
            t.add_triplet(i, i, 3.0 + (i % 4) as f64);
            if i + 1 < n {
                t.add_triplet(i, i + 1, -1.0);
                t.add_triplet(i + 1, i, -1.0);
            }
        }
        t
    }

    /// An LCP beyond 1,000 variables, where the basis is sparse (math note §4.12, "A sparse
    /// basis"): 1,500 normal contacts in a chain, W tridiagonal (diagonal 3 + i mod 4, off
    /// diagonal −1: strictly diagonally dominant, so symmetric positive definite, a P-matrix,
    /// and the LCP has exactly one solution, Cottle, Pang & Stone, Thm 3.3.7). q is made from
    /// a chosen answer: z* = 1 + i mod 5 on rows i mod 3 ≠ 0 and 0 on the others, where the gap
    /// G* = q + W z* is 0.5 + i mod 7 (and 0 where z* > 0). Lemke must end at z*; W's condition
    /// number is below 3, so rounding leaves about 1e-14 and 1e-10 is ample.
    #[test]
    fn lemke_solves_a_chain_beyond_the_dense_limit() {
        let n = 1_500;
        let w: CsMat<f64> = chain(n).to_csr();
        let want: Vec<f64> = (0..n).map(|i| if i % 3 == 0 { 0.0 } else { 1.0 + (i % 5) as f64 }).collect();
        let gap: Vec<f64> = (0..n).map(|i| if i % 3 == 0 { 0.5 + (i % 7) as f64 } else { 0.0 }).collect();
        let mut wz = vec![0.0; n];
        w.apply(&want, &mut wz);
        let q: Vec<f64> = (0..n).map(|i| gap[i] - wz[i]).collect();
        let blocks: Vec<usize> = (0..=n).collect();
        let p = Problem { w: &w, q: &q, blocks: &blocks };
        let opts = Options { tolerance: 1e-12, ..Options::default() };
        let mut check = measure::Check::default();
        let mut measure = |x: &[f64]| check.residual(&p, &Normal, x, &opts);
        let mut z = vec![0.0; n];
        let (pivots, residual) =
            super::solve(w.view(), &p, &Normal, &mut z, (1e-12, 100_000), &mut measure, &mut Best::default())
                .expect("solved");
        let err = z.iter().zip(&want).fold(0.0f64, |e, (a, b)| e.max((a - b).abs()));
        assert!(err < 1e-10 && residual <= 1e-12, "|z - z*| = {err}, residual {residual} after {pivots}");
    }

    /// A path cut by the cap hands back x of the basis it stopped at, which solves the LCP with
    /// q + z0 d (math note §4.12, "Cycling"): with d = ones, every x_i > 0 has w_i = (M x + q)_i
    /// = −z0, the same for all (z0 > 0, the artificial variable still basic), and every other
    /// row w_i >= −z0. M is a chain like that of `lemke_solves_a_chain_beyond_the_dense_limit`
    /// (60 rows; symmetric, so its columns are its rows), cut at 40 pivots; exact up to
    /// rounding of entries of order one.
    #[test]
    fn a_cut_path_hands_back_a_solution_of_the_shifted_lcp() {
        let n = 60;
        let t = chain(n);
        let q: Vec<f64> =
            (0..n).map(|i| -1.0 - (i % 5) as f64 + if i % 3 == 0 { 6.0 } else { 0.0 }).collect();
        let lcp = super::Lcp { m: n, mat: t.to_csc(), q: q.clone(), vars: Vec::new(), sc: Vec::new() };
        let (x, used) = super::lemke(&lcp, &vec![1.0; n], 40);
        let x = x.expect("a basis");
        assert_eq!(used, 40, "the cap ends the path");
        let mut w = q.clone();
        let mut mx = vec![0.0; n];
        lcp.mat.apply(&x, &mut mx);
        w.iter_mut().zip(&mx).for_each(|(w, v)| *w += v);
        let positive: Vec<usize> = (0..n).filter(|&i| x[i] > 0.0).collect();
        assert!(!positive.is_empty());
        let z0 = -w[positive[0]];
        assert!(z0 > 0.0, "z0 = {z0}");
        for i in 0..n {
            if x[i] > 0.0 {
                assert!((w[i] + z0).abs() < 1e-12, "row {i}: w = {} against -z0 = {}", w[i], -z0);
            } else {
                assert!(w[i] >= -z0 - 1e-12, "row {i}: w = {} below -z0 = {}", w[i], -z0);
            }
        }
    }

    /// The path's hashes are of sets: the bases met again after any order of swaps are
    /// recognised, and a new basis is not (the starting basis {0, 1, 2, 3}; variables 5 and 6
    /// enter and leave again).
    #[test]
    fn a_path_that_comes_back_is_seen() {
        let mut path = super::Path::new(4);
        assert!(path.moved(0, 5), "{{5, 1, 2, 3}} is new");
        assert!(path.moved(1, 6), "{{5, 6, 2, 3}} is new");
        assert!(path.moved(5, 0), "{{0, 6, 2, 3}} is new");
        assert!(!path.moved(6, 1), "{{0, 1, 2, 3}} is the start");
        assert!(!path.moved(0, 5), "{{5, 1, 2, 3}} again");
        assert!(path.moved(2, 6), "{{5, 1, 6, 3}} is new");
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
