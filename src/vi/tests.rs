//! Unit tests of the solver on closed-form cases. Every expected value below is derived by hand in the comment above
//! its test; tolerances are stated there.

use super::*;
use sprs::{CsMat, TriMat};

pub(super) const INF: f64 = f64::INFINITY;

/// One block per row.
pub(super) fn singles(n: usize) -> Vec<usize> {
    (0..=n).collect()
}

/// Dense row-major symmetric matrix -> CSR (both triangles, zeros dropped).
pub(super) fn csr(n: usize, dense: &[f64]) -> CsMat<f64> {
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

pub(super) fn opts(tolerance: f64, jacobi: bool) -> Options {
    Options { tolerance, jacobi, ..Options::default() }
}

/// Solves a plain VI from a zero warm start; returns the report, z and the stats.
fn fixed(w: &CsMat<f64>, q: &[f64], lo: &[f64], hi: &[f64], o: &Options) -> (Report, Vec<f64>, Stats) {
    let mut ws = Solver::new();
    let mut z = vec![0.0; q.len()];
    let rule = FixedBounds { lo: lo.to_vec(), hi: hi.to_vec() };
    let rep = ws.solve(&Problem { w, q, blocks: &singles(q.len()) }, &rule, &mut z, o);
    (rep, z, ws.stats())
}

/// Coulomb rule for one (normal, tangent) pair: tau = mu max(z_n, 0) (math note §4.1).
pub(super) struct Friction(pub(super) f64);
impl BoundRule for Friction {
    fn block_bounds(&self, _k: usize, z: &[f64], lo: &mut [f64], hi: &mut [f64]) {
        let tau = self.0 * z[0].max(0.0);
        (lo[0], hi[0], lo[1], hi[1]) = (0.0, INF, -tau, tau);
    }
}

/// Zero rows: nothing to do, converged, no call to the bound rule needed.
#[test]
fn empty_problem() {
    let w: CsMat<f64> = CsMat::zero((0, 0));
    let rep = solve(
        &Problem { w: &w, q: &[], blocks: &[0] },
        &FixedBounds { lo: vec![], hi: vec![] },
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
            let mut ws = Solver::new();
            ws.correction = correction;
            let mut z = vec![0.7, -3.0]; // infeasible warm start
            let rule = FixedBounds { lo: vec![0.0, 0.0], hi: vec![INF, INF] };
            let rep = ws.solve(
                &Problem { w: &w, q: &[1.0, -3.0], blocks: &singles(2) },
                &rule,
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
        let rule = FixedBounds { lo: vec![0.0; 3], hi: vec![INF; 3] };
        let rep =
            solve(&Problem { w: &w, q: &q, blocks: &singles(q.len()) }, &rule, &mut z, &opts(1e-12, jacobi));
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
        for (q, want) in [([-2.0, -0.2], [38.0 / 35.0, -12.0 / 35.0]), ([-2.0, -2.0], [8.0 / 9.0, 4.0 / 9.0])]
        {
            let mut z = vec![0.0, 0.0];
            let rep = solve(
                &Problem { w: &w, q: &q, blocks: &[0, 2] },
                &Friction(0.5),
                &mut z,
                &opts(1e-12, jacobi),
            );
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
    let rule = FixedBounds { lo: vec![0.0, 0.0], hi: vec![INF, INF] };
    let rep =
        solve(&Problem { w: &w, q: &[1.0, -3.0], blocks: &singles(2) }, &rule, &mut z, &opts(1e-12, true));
    assert_eq!((rep.outer_iterations, rep.inner_iterations, rep.converged), (1, 0, true));
    assert_eq!(z, vec![0.0, 1.5]);
}

/// A warm start that needs no iteration keeps its first box (`outer::new_box`): the bound rule
/// is a function of the iterate, and the iterate is still the warm start, so the second pass
/// does not ask the rule again. The rule below counts its calls (one per block and pass) around
/// the solution (0, 1.5) of `warm_start_at_solution`. Expected from the algorithm, for PC and
/// MPRGP alike: 2 calls (the first pass's two blocks), products = 1 (the first sweep), inner =
/// 0, outer = 1, z unchanged bit for bit. (Asking the rule again would count 4 calls, and a
/// box moved by the rounding of the unscaled warm start would cost a second measurement.)
#[test]
fn unmoved_warm_start_keeps_its_first_box() {
    struct Counting(std::cell::Cell<usize>);
    impl BoundRule for Counting {
        fn block_bounds(&self, _k: usize, _z: &[f64], lo: &mut [f64], hi: &mut [f64]) {
            self.0.set(self.0.get() + 1);
            lo.fill(0.0);
            hi.fill(10.0);
        }
    }
    let w = csr(2, &[2.0, 1.0, 1.0, 2.0]);
    for method in [Method::Pc, Method::Mprgp] {
        let mut ws = Solver::new().with_method(method);
        let mut z = vec![0.0, 1.5];
        let p = Problem { w: &w, q: &[1.0, -3.0], blocks: &singles(2) };
        let rule = Counting(Default::default());
        let rep = ws.solve(&p, &rule, &mut z, &opts(1e-12, true));
        let counts =
            (rule.0.get(), rep.outer_iterations, rep.inner_iterations, rep.converged, ws.stats().products);
        assert_eq!(counts, (2, 1, 0, true, 1), "{method:?}: {rep:?}");
        assert_eq!(z, vec![0.0, 1.5]);
    }
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
    let mut ws = Solver::new();
    let mut z = vec![0.25, 0.5];
    let rule = FixedBounds { lo: vec![0.0, 0.0], hi: vec![INF, INF] };
    let rep =
        ws.solve(&Problem { w: &w, q: &q, blocks: &singles(q.len()) }, &rule, &mut z, &Options::default());
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
    let mut ws = Solver::new();
    let mut z = vec![0.5];
    let rule = FixedBounds { lo: vec![1.0], hi: vec![0.0] };
    let rep =
        ws.solve(&Problem { w: &w, q: &[-1.0], blocks: &singles(1) }, &rule, &mut z, &Options::default());
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
    let mut ws = Solver::new();
    for _ in 0..2 {
        for (w, q) in [(&big, vec![-1.0, -1.0, -2.0]), (&small, vec![-2.0, -2.0])] {
            let n = q.len();
            let run = |ws: &mut Solver| {
                let mut z = vec![0.0; n];
                let rep = ws.solve(
                    &Problem { w, q: &q, blocks: &singles(q.len()) },
                    &FixedBounds { lo: vec![0.0; n], hi: vec![INF; n] },
                    &mut z,
                    &opts(1e-12, true),
                );
                (rep, z)
            };
            let (a, b) = (run(&mut ws), run(&mut Solver::new()));
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

/// Inconsistent input is reported, never a panic: blocks that do not partition the rows
/// (not starting at 0, not ending at n, decreasing), z or W of the wrong size, a non-square
/// explicit W. Expected: converged = false, status InvalidInput, residual +inf, z untouched.
#[test]
fn invalid_input_is_reported() {
    let w = csr(2, &[2.0, 1.0, 1.0, 2.0]);
    let w3 = csr(3, &[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]);
    let mut rect = TriMat::new((2, 3));
    rect.add_triplet(0, 0, 1.0);
    rect.add_triplet(1, 2, 1.0);
    let rect: CsMat<f64> = rect.to_csr();
    let q = [1.0, -3.0];
    let rule = FixedBounds { lo: vec![0.0; 2], hi: vec![INF; 2] };
    let cases: [(&dyn Operator, &[usize], usize); 6] = [
        (&w, &[1, 2], 2),
        (&w, &[0, 1], 2),
        (&w, &[0, 2, 1, 2], 2),
        (&w, &[0, 2], 3),
        (&w3, &[0, 2], 2),
        (&rect, &[0, 2], 2),
    ];
    for (i, (op, blocks, nz)) in cases.into_iter().enumerate() {
        let mut ws = Solver::new();
        let mut z = vec![0.5; nz];
        let rep = ws.solve(&Problem { w: op, q: &q, blocks }, &rule, &mut z, &Options::default());
        assert!(!rep.converged && rep.residual == INF, "case {i}: {rep:?}");
        assert_eq!(ws.stats().status, Status::InvalidInput, "case {i}");
        assert_eq!(z, vec![0.5; nz]);
    }
}

/// `Operator` for explicit matrices: W z and diag(W) of a non-symmetric 3×3 with small
/// integer entries (so every product and sum is exact) equal the dense values bit for bit,
/// for CSR, CSC and a view; `as_csr` of the CSC storage is Wᵀ (documented: equal to W for
/// the symmetric matrices the solver takes).
#[test]
fn operator_for_sparse_matrices() {
    let dense = [2.0, -1.0, 0.0, 3.0, 4.0, 5.0, 0.0, 6.0, -7.0];
    let m = csr(3, &dense);
    let z = [1.0, -2.0, 3.0];
    let want: Vec<f64> = (0..3).map(|i| (0..3).map(|j| dense[3 * i + j] * z[j]).sum()).collect();
    let mc = m.to_csc();
    let ops: [&dyn Operator; 3] = [&m, &mc, &m.view()];
    for op in ops {
        let (mut out, mut d) = (vec![9.0; 3], vec![9.0; 3]);
        op.apply(&z, &mut out);
        op.diagonal(&mut d);
        assert_eq!((op.dim(), out, d), (3, want.clone(), vec![2.0, 4.0, -7.0]));
    }
    let t = mc.as_csr().expect("explicit");
    assert!(t.is_csr() && t.get(0, 1) == Some(&3.0));
}

/// Records the bound rule's calls: (block, block length).
struct Recorder(std::cell::RefCell<Vec<(usize, usize)>>);
impl BoundRule for Recorder {
    fn block_bounds(&self, k: usize, _z: &[f64], lo: &mut [f64], hi: &mut [f64]) {
        self.0.borrow_mut().push((k, lo.len()));
        lo.fill(0.0);
        hi.fill(INF);
    }
}

/// The outer loop asks the rule for each block in order, with the block's own slice: blocks
/// [0, 2, 3, 6] give calls (0, 2), (1, 1), (2, 3) per pass. A plain VI takes one PC run and
/// one confirming pass (see `warm_start_at_solution`), so exactly 2 × 3 calls, and the
/// solution of the diagonal W = diag(1..6), q = −1 on z >= 0 is z_j = 1/j (to 1e-10:
/// residual 1e-12).
#[test]
fn bound_rule_sees_blocks() {
    let mut dense = vec![0.0; 36];
    for j in 0..6 {
        dense[7 * j] = (j + 1) as f64;
    }
    let w = csr(6, &dense);
    let rule = Recorder(Default::default());
    let mut z = vec![0.0; 6];
    let p = Problem { w: &w, q: &[-1.0; 6], blocks: &[0, 2, 3, 6] };
    let rep = solve(&p, &rule, &mut z, &opts(1e-12, true));
    assert!(rep.converged && rep.outer_iterations == 1, "{rep:?}");
    assert_eq!(rule.0.into_inner(), [(0, 2), (1, 1), (2, 3)].repeat(2));
    for (j, zj) in z.iter().enumerate() {
        assert!((zj - 1.0 / (j + 1) as f64).abs() < 1e-10, "{z:?}");
    }
}

/// W behind the trait without its CSR storage (the matrix-free path).
pub(super) struct MatrixFree(pub(super) CsMat<f64>);
impl Operator for MatrixFree {
    fn dim(&self) -> usize {
        self.0.dim()
    }
    fn apply(&self, z: &[f64], out: &mut [f64]) {
        self.0.apply(z, out);
    }
    fn diagonal(&self, out: &mut [f64]) {
        self.0.diagonal(out);
    }
}

/// The matrix-free path on the closed forms above: `two_by_two_active_set` (z = (0, 3/2)),
/// `coulomb_stick_and_slide` (sliding: z = (8/9, 4/9)) and the zero row of `zero_row`
/// (Diverged, detected from the zero diagonal), with Jacobi on and off; tolerances as there
/// (1e-10, 1e-9). One solver is reused across both paths and sizes.
#[test]
fn matrix_free_closed_forms() {
    let mut ws = Solver::new();
    for jacobi in [true, false] {
        let w = MatrixFree(csr(2, &[2.0, 1.0, 1.0, 2.0]));
        let mut z = vec![0.7, -3.0];
        let rule = FixedBounds { lo: vec![0.0, 0.0], hi: vec![INF, INF] };
        let p = Problem { w: &w, q: &[1.0, -3.0], blocks: &[0, 1, 2] };
        assert!(ws.solve(&p, &rule, &mut z, &opts(1e-12, jacobi)).converged);
        assert!(z[0] >= 0.0 && z[0] < 1e-10 && (z[1] - 1.5).abs() < 1e-10, "{z:?}");

        let w = MatrixFree(csr(2, &[2.0, 0.5, 0.5, 1.0]));
        let mut z = vec![0.0, 0.0];
        let p = Problem { w: &w, q: &[-2.0, -2.0], blocks: &[0, 2] };
        assert!(ws.solve(&p, &Friction(0.5), &mut z, &opts(1e-12, jacobi)).converged);
        assert!((z[0] - 8.0 / 9.0).abs() < 1e-9 && (z[1] - 4.0 / 9.0).abs() < 1e-9, "{z:?}");

        let w = MatrixFree(csr(2, &[0.0, 0.0, 0.0, 2.0]));
        let mut z = vec![0.25, 0.5];
        let p = Problem { w: &w, q: &[-1.0, -3.0], blocks: &[0, 1, 2] };
        let rep = ws.solve(&p, &rule, &mut z, &Options::default());
        assert!(!rep.converged && ws.stats().status == Status::Diverged);
        assert_eq!(z, vec![0.25, 0.5]);
    }
}

/// The gap part of the residual (math note §4.9). Two independent normal rows: a heavy
/// contact, W = 1e-19 m/N with q = −5e-4 m (solution 5e15 N), and a light one, W = 1e-7 m/N
/// with q = −5e-4 m (solution 5e3 N). From the heavy force and nothing on the light row, the
/// light row's natural residual 5e3 N is 1e-12 of ‖z‖∞: the force part alone calls it solved,
/// with the light row's gap 5e-4 m open. With a gap tolerance of 1e-9 m every method solves the
/// light row too: its force to within 1e-9 m / 1e-7 m/N = 0.01 N (checked at 0.01 N), for each
/// method.
#[test]
fn gap_part_sees_light_rows_next_to_heavy_ones() {
    let w = csr(2, &[1e-19, 0.0, 0.0, 1e-7]);
    let q = [-5e-4, -5e-4];
    let rule = FixedBounds { lo: vec![0.0; 2], hi: vec![INF; 2] };
    for method in [Method::Pc, Method::Nsgs, Method::Mprgp] {
        let mut solver = Solver::new().with_method(method);
        let forces_only = Options { tolerance: 1e-6, ..Options::default() };
        let mut z = vec![5e15, 0.0];
        let rep = solver.solve(&Problem { w: &w, q: &q, blocks: &singles(2) }, &rule, &mut z, &forces_only);
        assert!(rep.converged && z[1] == 0.0, "{method:?}: {rep:?} {z:?}");
        let with_gaps = Options { gap_tolerance: 1e-9, ..forces_only };
        let rep = solver.solve(&Problem { w: &w, q: &q, blocks: &singles(2) }, &rule, &mut z, &with_gaps);
        assert!(rep.converged && (z[1] - 5e3).abs() <= 0.01, "{method:?}: {rep:?} {z:?}");
    }
}
