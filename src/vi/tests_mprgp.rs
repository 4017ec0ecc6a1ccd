//! MPRGP (math note §4.8) on closed-form cases, through both W paths (explicit CSR with
//! Gershgorin's step length, matrix-free with power iteration). Expected values are derived
//! in the comments of `tests.rs` where the same cases test PC, or below.

use super::tests::{Friction, INF, MatrixFree, csr, opts, singles};
use super::*;

fn mprgp() -> Solver {
    Solver::new().with_method(Method::Mprgp)
}

/// `two_by_two_active_set` (z = (0, 3/2) from an infeasible warm start) and
/// `coulomb_stick_and_slide` (stick (38/35, −12/35), slide (8/9, 4/9)), to the 1e-10 and
/// 1e-9 of those tests, with and without Jacobi scaling and on both W paths; solved by MPRGP
/// itself (no hand-over to PC).
#[test]
fn mprgp_closed_forms() {
    for jacobi in [true, false] {
        for free in [false, true] {
            let m = csr(2, &[2.0, 1.0, 1.0, 2.0]);
            let (explicit, wrapped) = (m.clone(), MatrixFree(m));
            let w: &dyn Operator = if free { &wrapped } else { &explicit };
            let mut ws = mprgp();
            let mut z = vec![0.7, -3.0];
            let rule = FixedBounds { lo: vec![0.0, 0.0], hi: vec![INF, INF] };
            let p = Problem { w, q: &[1.0, -3.0], blocks: &singles(2) };
            assert!(ws.solve(&p, &rule, &mut z, &opts(1e-12, jacobi)).converged);
            assert!(z[0] >= 0.0 && z[0] < 1e-10 && (z[1] - 1.5).abs() < 1e-10, "{z:?}");
            assert_eq!(ws.stats().fallbacks, 0);

            let m = csr(2, &[2.0, 0.5, 0.5, 1.0]);
            let (explicit, wrapped) = (m.clone(), MatrixFree(m));
            let w: &dyn Operator = if free { &wrapped } else { &explicit };
            for (q, want) in
                [([-2.0, -0.2], [38.0 / 35.0, -12.0 / 35.0]), ([-2.0, -2.0], [8.0 / 9.0, 4.0 / 9.0])]
            {
                let mut z = vec![0.0, 0.0];
                let rep = ws.solve(
                    &Problem { w, q: &q, blocks: &[0, 2] },
                    &Friction(0.5),
                    &mut z,
                    &opts(1e-12, jacobi),
                );
                assert!(rep.converged && ws.stats().fallbacks == 0, "{q:?}: {rep:?}");
                assert!(
                    (z[0] - want[0]).abs() < 1e-9 && (z[1] - want[1]).abs() < 1e-9,
                    "{q:?}: {z:?} vs {want:?}"
                );
            }
        }
    }
}

/// The 1-D Laplacian W = tridiag(−1, 2, −1) of order 20 with q = −1 and wide bounds
/// [−1e3, 1e3]: W z = 1 with z_0 = z_21 = 0 gives z_i = i (21 − i) / 2 (at most 110, inside
/// the box). Every row stays free, so MPRGP is conjugate gradients, which ends in as many
/// steps as the right-hand side excites distinct eigenvalues: q is symmetric under
/// i -> 21 − i, which excites only the 10 symmetric eigenvectors, so 10 steps in exact
/// arithmetic; the assertion allows one more for rounding (the residual is asked to 1e-12).
/// PC on the same problem needs over a thousand iterations (cond W = 178), asserted to show
/// what the conjugate directions buy. z to 1e-8 relative (residual 1e-12 times cond W).
#[test]
fn mprgp_is_conjugate_gradients_on_free_rows() {
    let n = 20;
    let w = laplacian(n);
    let rule = FixedBounds { lo: vec![-1e3; n], hi: vec![1e3; n] };
    let p = Problem { w: &w, q: &vec![-1.0; n], blocks: &singles(n) };
    let mut z = vec![0.0; n];
    let rep = mprgp().solve(&p, &rule, &mut z, &opts(1e-12, true));
    assert!(rep.converged && rep.inner_iterations <= 11, "{rep:?}");
    for (i, zi) in z.iter().enumerate() {
        let want = ((i + 1) * (n - i)) as f64 / 2.0;
        assert!((zi - want).abs() < 1e-8 * want, "z[{i}] = {zi} vs {want}");
    }
    let mut z = vec![0.0; n];
    let pc = Solver::new().solve(&p, &rule, &mut z, &opts(1e-12, true));
    assert!(pc.converged && pc.inner_iterations > 1000, "{pc:?}");
}

/// Unbounded rays and NaN are reported as by PC (`unbounded_rays_are_reported`,
/// `nan_input_is_reported`): Diverged or NonFinite, warm start restored, and no hand-over to
/// PC (which would report the same).
#[test]
fn mprgp_reports_rays_and_nan() {
    let cases = [
        ([1.0, -1.0, -1.0, 1.0], [-1.0, -1.0], [0.0, 0.0], Status::Diverged),
        ([1.0, 1.0, 1.0, 1.0], [1.0, -1.0], [-INF, -INF], Status::Diverged),
        ([2.0, 1.0, 1.0, 2.0], [f64::NAN, 1.0], [0.0, 0.0], Status::NonFinite),
    ];
    for (dense, q, lo, status) in cases {
        let w = csr(2, &dense);
        let mut ws = mprgp();
        let mut z = vec![0.0; 2];
        let rule = FixedBounds { lo: lo.to_vec(), hi: vec![INF, INF] };
        let rep =
            ws.solve(&Problem { w: &w, q: &q, blocks: &singles(2) }, &rule, &mut z, &Options::default());
        assert!(!rep.converged && ws.stats().status == status, "{rep:?} {:?}", ws.stats());
        assert_eq!((z, ws.stats().fallbacks), (vec![0.0, 0.0], 0));
    }
}

/// The guard (math note §4.8). (a) Budget: on the free 2×2 of `iteration_limit_is_reported`
/// (W = [[1, 0.999], [0.999, 1]]) with q = (1, 0), no eigenvector of W, so CG needs its 2
/// steps, and the box ±1e4 around −W⁻¹q = (−1, 0.999) / (1 − 0.999²) ≈ (−500.25, 499.75):
/// with max_iterations = 1 MPRGP uses the whole budget, so there is nothing left for PC:
/// IterationLimit after exactly 1 iteration, no hand-over; with the full budget exactly CG's 2
/// steps solve it (z to 5e-6: residual 1e-12 times cond W = 1999 times |z| = 500).
/// (b) Pass limit: the sliding case of `coulomb_stick_and_slide` (W = [[2, 0.5], [0.5, 1]],
/// q = (−2, −2), μ = 0.5: sliding at z = (8/9, 4/9), the normal row 2 z_n + 0.5 · z_n / 2 = 2)
/// needs at least 3 passes; with max_outer = 1 MPRGP stops after its one pass with budget left,
/// and NSGS, which takes the friction bound at the current iterate and needs no passes, solves
/// it from the warm start: converged (to 1e-9, the residual 1e-12 times cond W ≈ 2.5 times
/// |z| ≈ 1, with margin), one hand-over, 2 passes in all; from the warm start (0.5, 0.1) the
/// hand-over's answer is, bit for bit, that of NSGS alone from the same warm start, not from
/// MPRGP's iterate. (c) The same problem behind a matrix-free W (`MatrixFree`, no entries for
/// NSGS to sweep): PC takes over from the warm start and stops after its one pass too:
/// OuterLimit, one hand-over, 2 passes; from (0.5, 0.1) PC alone's answer, (15/16, 1/4), to
/// rounding (1e-12), and no worse by the residual: the chain returns the better of MPRGP's
/// pass and PC's answer (math note §4.7, "The best answer of a failed chain"), here MPRGP's,
/// which is exact where PC's is 1.3e-13 off.
#[test]
fn mprgp_guard() {
    let w = csr(2, &[1.0, 0.999, 0.999, 1.0]);
    let mut ws = mprgp();
    let rule = FixedBounds { lo: vec![-1e4; 2], hi: vec![1e4; 2] };
    let p = Problem { w: &w, q: &[1.0, 0.0], blocks: &singles(2) };
    let mut z = vec![0.0; 2];
    let rep = ws.solve(&p, &rule, &mut z, &Options { max_iterations: 1, ..opts(1e-12, true) });
    let st = ws.stats();
    assert!(!rep.converged && st.status == Status::IterationLimit && st.fallbacks == 0, "{rep:?} {st:?}");
    assert_eq!(rep.inner_iterations, 1);
    let mut z = vec![0.0; 2];
    let rep = ws.solve(&p, &rule, &mut z, &opts(1e-12, true));
    assert!(rep.converged && rep.inner_iterations == 2 && ws.stats().fallbacks == 0, "{rep:?}");
    let det = 1.0 - 0.999 * 0.999;
    assert!((z[0] + 1.0 / det).abs() < 5e-6 && (z[1] - 0.999 / det).abs() < 5e-6, "{z:?}");

    let w = csr(2, &[2.0, 0.5, 0.5, 1.0]);
    let o = Options { max_outer: 1, ..opts(1e-12, true) };
    let p = Problem { w: &w, q: &[-2.0, -2.0], blocks: &[0, 2] };
    let mut z = vec![0.0; 2];
    let rep = ws.solve(&p, &Friction(0.5), &mut z, &o);
    let st = ws.stats();
    assert!(rep.converged && rep.outer_iterations == 2 && st.fallbacks == 1, "{rep:?} {st:?}");
    assert!((z[0] - 8.0 / 9.0).abs() < 1e-9 && (z[1] - 4.0 / 9.0).abs() < 1e-9, "{z:?}");
    let (mut z, mut z_nsgs) = (vec![0.5, 0.1], vec![0.5, 0.1]);
    assert!(ws.solve(&p, &Friction(0.5), &mut z, &o).converged);
    let nsgs = Solver::new().with_method(Method::Nsgs).solve(&p, &Friction(0.5), &mut z_nsgs, &o);
    assert!(nsgs.converged && z == z_nsgs, "{z:?} {z_nsgs:?}");

    let free = MatrixFree(w.clone());
    let p = Problem { w: &free, q: &[-2.0, -2.0], blocks: &[0, 2] };
    let mut z = vec![0.0; 2];
    let rep = ws.solve(&p, &Friction(0.5), &mut z, &o);
    let st = ws.stats();
    assert!(!rep.converged && st.status == Status::OuterLimit && st.fallbacks == 1, "{rep:?} {st:?}");
    assert_eq!(rep.outer_iterations, 2);
    let (mut z, mut z_pc) = (vec![0.5, 0.1], vec![0.5, 0.1]);
    let chain = ws.solve(&p, &Friction(0.5), &mut z, &o);
    assert_eq!(chain.outer_iterations, 2);
    let pc = Solver::new().with_method(Method::Pc).solve(&p, &Friction(0.5), &mut z_pc, &o);
    assert_eq!(pc.outer_iterations, 1);
    assert!(chain.residual <= pc.residual, "{chain:?} {pc:?}");
    assert!(z.iter().zip(&z_pc).all(|(a, b)| (a - b).abs() <= 1e-12), "{z:?} {z_pc:?}");
}

/// Face solves (math note §4.10) on the 1-D Laplacian W = tridiag(−1, 2, −1) of order 400 with
/// q = −1 and the wide box [−1e7, 1e7]: z_i = (i + 1)(400 − i) / 2 (up to 40,100), so every row
/// stays free and MPRGP is CG, which would need about 200 steps (q excites the 200 symmetric
/// eigenvectors). With the explicit W, the first face solve (at iteration `face::FIRST`)
/// factorizes the whole block (positive definite: no regularization) and lands on the
/// minimizer with its full step, which meets the tolerance: the run ends there, after exactly
/// `FIRST` iterations and one face solve. z to 1e-8 relative: the factorization's error is
/// about eps · cond W = 1e-16 · 6.5e4. The matrix-free path has no entries: no face solve,
/// and more than `FIRST` iterations to the same answer, to 1e-5 (its residual 1e-10 times
/// cond W).
#[test]
fn face_solve_lands_on_the_minimizer_of_a_long_chain() {
    let n = 400;
    let (explicit, wrapped) = (laplacian(n), MatrixFree(laplacian(n)));
    let rule = FixedBounds { lo: vec![-1e7; n], hi: vec![1e7; n] };
    for free in [false, true] {
        let w: &dyn Operator = if free { &wrapped } else { &explicit };
        let p = Problem { w, q: &vec![-1.0; n], blocks: &singles(n) };
        let (mut ws, mut z) = (mprgp(), vec![0.0; n]);
        let rep = ws.solve(&p, &rule, &mut z, &opts(1e-10, true));
        assert!(rep.converged && ws.stats().fallbacks == 0, "{rep:?}");
        if free {
            assert_eq!(ws.stats().face_solves, 0);
            assert!(rep.inner_iterations > face::FIRST, "{rep:?}");
        } else {
            assert_eq!((ws.stats().face_solves, rep.inner_iterations), (1, face::FIRST), "{rep:?}");
        }
        let rel = if free { 1e-5 } else { 1e-8 };
        for (i, zi) in z.iter().enumerate() {
            let want = ((i + 1) * (n - i)) as f64 / 2.0;
            assert!((zi - want).abs() < rel * want, "free {free}: z[{i}] = {zi} vs {want}");
        }
    }
}

/// A warm run's first face solve waits one iteration per `face::ROWS_PER_ITERATION` rows (math
/// note §4.10). The chain of `face_solve_lands_on_the_minimizer_of_a_long_chain` with 30,000
/// rows: z_i = (i + 1)(30,000 − i)/2, every row free; tolerance 1e-10, a budget of 58, of which
/// MPRGP has 58 − 58 / `HANDOVER_SHARE` = 29 = 30,000 / ROWS_PER_ITERATION − 1 iterations.
/// Starts:
/// * z = 0 (cold): the face solve comes at iteration `FIRST` = 20 and lands on the minimizer,
///   converged after exactly 20 iterations with one face solve;
/// * the minimizer plus `amp` times the 60 smoothest eigenvectors, each weighted 1/λ_k so that
///   each adds alike to the gradient: CG needs about one iteration per eigenvalue, more than
///   the budget. With amp = 0.1 the start's residual (measured by a call with no iterations)
///   is above `WARM` times the tolerance, so the run is cold: face solve at 20, converged. With
///   amp = 1e-3 it is within it: no face solve in MPRGP's 29 iterations, so MPRGP hands over
///   (a face solve here lands on the minimizer and converges, so a hand-over means there was
///   none), and NSGS cannot converge in the 29 left (a Gauss-Seidel sweep shrinks the k-th
///   smoothest mode by about 1 − (kπ/30,001)², 1 − 1.1e-8 to 1 − 4e-5 for these 60): 58
///   iterations in all, unconverged.
#[test]
fn warm_runs_wait_longer_for_their_first_face_solve() {
    let n = 30_000;
    assert_eq!(n / face::ROWS_PER_ITERATION - 1, 29);
    let w = laplacian(n);
    let rule = FixedBounds { lo: vec![-1e12; n], hi: vec![1e12; n] };
    let q = vec![-1.0; n];
    let p = Problem { w: &w, q: &q, blocks: &singles(n) };
    let o = Options { max_iterations: 58, ..opts(1e-10, true) };
    assert_eq!(58 - 58 / HANDOVER_SHARE, 29);
    let mut ws = mprgp();
    let rep = ws.solve(&p, &rule, &mut vec![0.0; n], &o);
    assert!(rep.converged, "cold: {rep:?}");
    assert_eq!((ws.stats().face_solves, rep.inner_iterations), (1, face::FIRST), "cold: {rep:?}");
    let h = std::f64::consts::PI / (n + 1) as f64;
    let smooth = |i: usize| -> f64 {
        (1..=60).map(|k| ((k * (i + 1)) as f64 * h).sin() / (2.0 - 2.0 * (k as f64 * h).cos())).sum()
    };
    for (amp, warm) in [(0.1, false), (1e-3, true)] {
        let z: Vec<f64> = (0..n).map(|i| ((i + 1) * (n - i)) as f64 / 2.0 + amp * smooth(i)).collect();
        let start = ws.solve(&p, &rule, &mut z.clone(), &Options { max_iterations: 0, ..o }).residual;
        assert_eq!(start <= face::WARM * o.tolerance, warm, "amp {amp}: start residual {start:e}");
        let rep = ws.solve(&p, &rule, &mut z.clone(), &o);
        let st = ws.stats();
        let got = (st.fallbacks, st.face_solves, rep.converged, rep.inner_iterations);
        let want = if warm { (1, 0, false, 58) } else { (0, 1, true, face::FIRST) };
        assert_eq!(got, want, "amp {amp}: {rep:?}");
    }
}

/// The 1-D Laplacian tridiag(−1, 2, −1) of order n.
pub(super) fn laplacian(n: usize) -> sprs::CsMat<f64> {
    let mut t = sprs::TriMat::new((n, n));
    for i in 0..n {
        t.add_triplet(i, i, 2.0);
        if i + 1 < n {
            t.add_triplet(i, i + 1, -1.0);
            t.add_triplet(i + 1, i, -1.0);
        }
    }
    t.to_csr()
}

/// `Solver::gaps` gives G = q + W z at the answer from the solver's last product: on the
/// stick and slide cases of `mprgp_closed_forms` (explicit and matrix-free W, with and without
/// Jacobi scaling) it equals q + W z computed here to 1e-13 (the two sums differ by rounding
/// only; the answers are O(1)); after a solve that did not converge it is `None`.
#[test]
fn gaps_come_from_the_last_product() {
    on_both_paths(|jacobi, w| {
        let mut ws = mprgp();
        for q in [[-2.0, -0.2], [-2.0, -2.0]] {
            let mut z = vec![0.0, 0.0];
            let p = Problem { w, q: &q, blocks: &[0, 2] };
            assert!(ws.solve(&p, &Friction(0.5), &mut z, &opts(1e-12, jacobi)).converged);
            let mut wz = [0.0; 2];
            w.apply(&z, &mut wz);
            let gaps = ws.gaps(&q).expect("a converged MPRGP solve ends with a sweep");
            for i in 0..2 {
                assert!((gaps[i] - (q[i] + wz[i])).abs() < 1e-13, "{q:?}: {gaps:?} vs {wz:?}");
            }
        }
        let mut z = vec![0.0, 0.0];
        let p = Problem { w, q: &[-2.0, -2.0], blocks: &[0, 2] };
        let capped = Options { max_iterations: 1, ..opts(1e-12, jacobi) };
        assert!(!ws.solve(&p, &Friction(0.5), &mut z, &capped).converged);
        assert!(ws.gaps(&[-2.0, -2.0]).is_none());
    });
}

/// `test(jacobi, w)` for the stick-and-slide W = [[2, ½], [½, 1]] of `mprgp_closed_forms`, explicit
/// and matrix-free, with and without Jacobi scaling.
fn on_both_paths(test: impl Fn(bool, &dyn Operator)) {
    let m = csr(2, &[2.0, 0.5, 0.5, 1.0]);
    let (explicit, wrapped) = (m.clone(), MatrixFree(m));
    for jacobi in [true, false] {
        for w in [&explicit as &dyn Operator, &wrapped] {
            test(jacobi, w);
        }
    }
}

/// `Solver::residual_again` is the residual a solve of a changed q measures at the last answer
/// before it iterates: on the stick case of `gaps_come_from_the_last_product` (explicit and
/// matrix-free W, with and without Jacobi scaling), solved to 1e-12, then q's tangential entry
/// moved by δ. The fresh solve from that answer with no iteration allowed reports the same
/// residual to 1e-14 relative (its product is made anew from D^{1/2} z, so the two differ by
/// rounding only). δ = 1e-9 keeps the answer within a tolerance of 1e-6 and δ = 1e-3 does not;
/// both sides agree on which. After a solve that did not converge there is no product: `None`.
#[test]
fn residual_again_is_the_next_solves_first_measure() {
    on_both_paths(|jacobi, w| {
        for delta in [1e-9, 1e-3] {
            let mut ws = mprgp();
            let (q1, q2) = ([-2.0, -0.2], [-2.0, -0.2 + delta]);
            let mut z = vec![0.0, 0.0];
            let p1 = Problem { w, q: &q1, blocks: &[0, 2] };
            assert!(ws.solve(&p1, &Friction(0.5), &mut z, &opts(1e-12, jacobi)).converged);
            let o = opts(1e-6, jacobi);
            let again = ws.residual_again(&q2, &z, &o).expect("a converged MPRGP solve ends with a sweep");
            let p2 = Problem { w, q: &q2, blocks: &[0, 2] };
            let first = ws.solve(&p2, &Friction(0.5), &mut z.clone(), &Options { max_iterations: 0, ..o });
            let l = format!("jacobi {jacobi} delta {delta}: {again:e} vs {first:?}");
            assert!((again - first.residual).abs() <= 1e-14 * first.residual.max(1e-300), "{l}");
            assert_eq!(again <= o.tolerance, first.converged, "{l}");
            assert_eq!(again <= o.tolerance, delta < 1e-6, "{l}");
        }
        let mut ws = mprgp();
        let p = Problem { w, q: &[-2.0, -2.0], blocks: &[0, 2] };
        let capped = Options { max_iterations: 1, ..opts(1e-12, jacobi) };
        let mut z = vec![0.0, 0.0];
        assert!(!ws.solve(&p, &Friction(0.5), &mut z, &capped).converged);
        assert!(ws.residual_again(&[-2.0, -2.0], &z, &capped).is_none());
    });
}

/// MPRGP's step length is never computed by a solve that does not iterate
/// (`mprgp::StepLength`). A matrix-free W without row bounds gets it by 10 power iterations,
/// each one product. From the solution (0, 3/2) of `two_by_two_active_set` a solve needs one
/// sweep (one product) and no iteration, so exactly 1 product; computing ᾱ up front would
/// count 11.
#[test]
fn step_length_only_when_a_pass_iterates() {
    let w = MatrixFree(csr(2, &[2.0, 1.0, 1.0, 2.0]));
    let rule = FixedBounds { lo: vec![0.0, 0.0], hi: vec![INF, INF] };
    let p = Problem { w: &w, q: &[1.0, -3.0], blocks: &singles(2) };
    let mut ws = mprgp();
    let mut z = vec![0.0, 1.5];
    let rep = ws.solve(&p, &rule, &mut z, &opts(1e-12, true));
    assert_eq!((rep.inner_iterations, rep.converged, ws.stats().products), (0, true, 1), "{rep:?}");
    assert_eq!(z, vec![0.0, 1.5]);
}

/// The bound of ‖Ŵ‖ is computed when a run first expands; until then the proportioning test
/// takes the last step length the solver computed (`mprgp::StepLength`). `two_by_two_active_set`
/// from z = (0, 0), Jacobi scaled (Ŵ = [[1, ½], [½, 1]], q̂ = (1, −3)/√2): row 0 sits at its
/// bound with a positive gradient, row 1 at its bound with g = −3/√2, so the free gradient is
/// zero and the first iteration is a proportioning step along β = (0, −3/√2). Its exact line
/// search (α = 1, no upper bound to stop it) lands on y = (0, 3/√2), z = (0, 3/2): solved,
/// without an expansion. Products: the first sweep, the step's, and for the first solve of a
/// fresh solver the 10 power iterations of the matrix-free W's step length (it has no guess
/// yet): 12. The second solve of the same problem takes the first one's ᾱ as its guess: 2.
#[test]
fn step_length_only_when_a_run_expands() {
    let w = MatrixFree(csr(2, &[2.0, 1.0, 1.0, 2.0]));
    let rule = FixedBounds { lo: vec![0.0, 0.0], hi: vec![INF, INF] };
    let p = Problem { w: &w, q: &[1.0, -3.0], blocks: &singles(2) };
    let mut ws = mprgp();
    for want in [12, 2] {
        let mut z = vec![0.0, 0.0];
        let rep = ws.solve(&p, &rule, &mut z, &opts(1e-12, true));
        assert_eq!((rep.inner_iterations, rep.converged, ws.stats().products), (1, true, want), "{rep:?}");
        assert!(z[0] == 0.0 && (z[1] - 1.5).abs() < 1e-12, "{z:?}");
    }
}

/// A warm start that already meets the tolerance comes back bit for bit (`outer::new_box`,
/// `pc::State::kept`), with PC and with MPRGP. W = (3), q = −0.3, z >= 0: z = 0.1 solves it to
/// rounding (G = 3 · 0.1 − 0.3 = 5.6e-17). Scaled and unscaled, 0.1 would come back as
/// 0.1 · √3 · (1/√3) = 0.10000000000000002; the warm start itself is returned, after one
/// product (the first sweep) and no iteration.
#[test]
fn a_warm_start_that_meets_the_tolerance_comes_back_unchanged() {
    let w = csr(1, &[3.0]);
    let rule = FixedBounds { lo: vec![0.0], hi: vec![INF] };
    let p = Problem { w: &w, q: &[-0.3], blocks: &singles(1) };
    for mut ws in [Solver::new(), mprgp()] {
        let mut z = vec![0.1];
        let rep = ws.solve(&p, &rule, &mut z, &opts(1e-12, true));
        assert_eq!((rep.inner_iterations, rep.converged, ws.stats().products), (0, true, 1), "{rep:?}");
        assert_eq!(z[0].to_bits(), 0.1f64.to_bits(), "{z:?}");
    }
}

/// A box that moves after a run ended on one MPRGP step is measured again without a product
/// (`pc::State::exact`: Ŵy updated by one step is exact to rounding). `two_by_two_active_set`
/// from z = (0, 0) with bounds [0, 10 + z₁] (a function of z): as derived in
/// `step_length_only_when_a_run_expands`, one proportioning step of length 1 lands on
/// z = (0, 3/2), inside the first box (scaled, y₁ = 3/√2 against 10√2). The next pass's box
/// has hi = 11.5: it moved, the iterate did not, and Ŵy is one step from the first sweep's
/// product, so it is remeasured; the pass after finds the box settled. Products: the first
/// sweep and the step's, 2 (a new sweep for the moved box would make 3); outer passes 2.
#[test]
fn moved_box_after_one_step_costs_no_product() {
    struct Sliding;
    impl BoundRule for Sliding {
        fn block_bounds(&self, _k: usize, z: &[f64], lo: &mut [f64], hi: &mut [f64]) {
            lo.fill(0.0);
            hi.fill(10.0 + z[1]);
        }
    }
    let w = csr(2, &[2.0, 1.0, 1.0, 2.0]);
    let p = Problem { w: &w, q: &[1.0, -3.0], blocks: &singles(2) };
    let mut ws = mprgp();
    let mut z = vec![0.0, 0.0];
    let rep = ws.solve(&p, &Sliding, &mut z, &opts(1e-12, true));
    let counts = (rep.outer_iterations, rep.inner_iterations, rep.converged, ws.stats().products);
    assert_eq!(counts, (2, 1, true, 2), "{rep:?}");
    assert!(z[0] == 0.0 && (z[1] - 1.5).abs() < 1e-12, "{z:?}");
}

/// An expansion takes the step length a solve of the same solver computed before it, and keeps
/// the step when the step decreased the cost; else the exact ᾱ is computed and the step done
/// again (`mprgp::expand_step`, math note §4.8). The Laplacian chain of
/// `mprgp_is_conjugate_gradients_on_free_rows` with q alternating −2 and 1 in the box [0, 3]:
/// CG steps leave the box, so runs expand. A first solve computes ᾱ = 1.9/2 (Gershgorin's bound
/// of Ŵ = W/2 with Jacobi scaling, rows (−½, 1, −½); ‖Ŵ‖ = 1 + cos(π/21) < 2). A guess of 0.9 ᾱ
/// (below 2/‖Ŵ‖) decreases f at every expansion, as a projected gradient step with ᾱ <= 2/‖Ŵ‖
/// always does, so the solver still holds that guess afterwards, bit for bit. A guess of 100 ᾱ
/// (about 190/‖Ŵ‖) raises f on an expansion here, and the solver ends with the exact ᾱ again
/// (a longer guess need not raise f: on the box [0, 5] with q = −1 the projection keeps even
/// 100 ᾱ's steps descending). Every run converges to the first run's answer, within the 1e-12
/// residual times cond W = 178, so 1e-9.
#[test]
fn expansion_keeps_a_guessed_step_length_that_decreases_the_cost() {
    let n = 20;
    let w = laplacian(n);
    let rule = FixedBounds { lo: vec![0.0; n], hi: vec![3.0; n] };
    let q: Vec<f64> = (0..n).map(|i| if i % 2 == 0 { -2.0 } else { 1.0 }).collect();
    let p = Problem { w: &w, q: &q, blocks: &singles(n) };
    let mut ws = mprgp();
    let mut first = vec![0.0; n];
    assert!(ws.solve(&p, &rule, &mut first, &opts(1e-12, true)).converged);
    let exact = ws.step_length.expect("the first solve expands");
    assert!((exact - 1.9 / 2.0).abs() < 1e-12, "ᾱ {exact}");
    for (guess, after) in [(0.9 * exact, 0.9 * exact), (100.0 * exact, exact)] {
        ws.step_length = Some(guess);
        let mut z = vec![0.0; n];
        let rep = ws.solve(&p, &rule, &mut z, &opts(1e-12, true));
        assert!(rep.converged, "guess {guess}: {rep:?}");
        assert_eq!(ws.step_length, Some(after), "guess {guess}");
        for (a, b) in z.iter().zip(&first) {
            assert!((a - b).abs() < 1e-9, "guess {guess}: {z:?} vs {first:?}");
        }
    }
}
