//! Where a solve that has to iterate stops (math note §4.11, `Options::aim`): at aim × tol, or
//! within tol one iteration after it first met tol. The expected stops are derived from the
//! solver's own residual sequence on the 1-D Laplacian chain of `tests_mprgp.rs` (every row
//! free, so each method's iterates do not depend on the tolerance): r_k, the residual after k
//! iterations, is read from runs capped at k with tolerance 0. Matrix-free W, so that MPRGP
//! makes no face solve, whose schedule depends on the tolerance. The iterates are the same
//! floating-point sequence in every run, so the stops compare exactly; the residuals compare
//! to 1e-12 relative, because a capped run, unconverged, reports its answer's residual measured
//! on its own from an unscaled product (math note §4.3), where a run that stops measured it in
//! its scaled sweep: the same number to rounding.

use super::tests::{MatrixFree, opts, singles};
use super::tests_mprgp::laplacian;
use super::*;

const N: usize = 60;

fn chain() -> (MatrixFree, Vec<f64>, FixedBounds) {
    (MatrixFree(laplacian(N)), vec![-1.0; N], FixedBounds { lo: vec![-1e7; N], hi: vec![1e7; N] })
}

/// (report, z) of one solve of the chain from z = 0.
fn run(method: Method, o: &Options) -> (Report, Vec<f64>) {
    let (w, q, rule) = chain();
    let p = Problem { w: &w, q: &q, blocks: &singles(N) };
    let mut z = vec![0.0; N];
    let rep = Solver::new().with_method(method).solve(&p, &rule, &mut z, o);
    (rep, z)
}

/// r_0 … r_K of `method` on the chain.
fn residuals(method: Method, k_max: usize) -> Vec<f64> {
    (0..=k_max).map(|k| run(method, &Options { max_iterations: k, ..opts(0.0, true) }).0.residual).collect()
}

/// The stop the rule asks for at tolerance `tol`: the first k with r_k <= tol, unless r_k is
/// above aim × tol; then the first k after it with r_k <= tol.
fn expected_stop(r: &[f64], tol: f64, aim: f64) -> usize {
    let first = r.iter().position(|&x| x <= tol).expect("the sequence meets the tolerance");
    if r[first] <= aim * tol {
        first
    } else {
        first + 1 + r[first + 1..].iter().position(|&x| x <= tol).unwrap()
    }
}

/// For PC and MPRGP, tolerances placed on the sequence so that its first iterate within the
/// tolerance lies above the aim (one more iteration) and, for MPRGP, below it (none): the solve stops
/// where `expected_stop` says, with that iterate's residual (to rounding); with aim 1 it stops
/// at the first iterate within the tolerance. A budget that ends between the aim and the
/// tolerance still converges.
#[test]
fn a_solve_that_iterates_stops_at_the_aim_or_one_iteration_past_the_tolerance() {
    for method in [Method::Pc, Method::Mprgp] {
        let r = residuals(method, if method == Method::Pc { 2_000 } else { 80 });
        // tol = r_j / f for an iterate j below every earlier residual by more than 1/f
        let place = |f: f64| {
            (1..r.len() - 1)
                .find(|&j| r[..j].iter().all(|&x| x > r[j] / f) && r[j + 1..].iter().any(|&x| x <= r[j] / f))
                .map(|j| (j, r[j] / f))
                .unwrap_or_else(|| panic!("{method:?}: no iterate for f = {f}"))
        };
        // PC's residual falls by less than half an iteration here: only MPRGP's CG steps give
        // an iterate within the aim of a tolerance that the iterate before it missed
        let cases: &[(f64, bool)] =
            if method == Method::Pc { &[(0.75, true)] } else { &[(0.75, true), (0.4, false)] };
        for &(f, extra) in cases {
            let (j, tol) = place(f);
            for aim in [1.0, AIM] {
                let stop = if aim == 1.0 { j } else { expected_stop(&r, tol, aim) };
                assert_eq!(stop > j, extra && aim < 1.0, "{method:?} f {f}: the case is the one meant");
                let (rep, _) = run(method, &Options { aim, ..opts(tol, true) });
                assert!(rep.converged, "{method:?} f {f} aim {aim}: {rep:?}");
                assert_eq!(rep.inner_iterations, stop, "{method:?} f {f} aim {aim}");
                let same = (rep.residual - r[stop]).abs() <= 1e-12 * r[stop];
                assert!(same, "{method:?} f {f} aim {aim}: {} against {}", rep.residual, r[stop]);
            }
            // the budget ends at the first iterate within the tolerance, above the aim
            let capped = Options { max_iterations: j, ..opts(tol, true) };
            let (rep, _) = run(method, &capped);
            assert!(rep.converged && rep.inner_iterations == j, "{method:?} f {f} capped: {rep:?}");
        }
    }
}

/// NSGS checks its residual after sweeps 0–4 and then every `nsgs::CHECK_EVERY`: with the aim
/// it goes on from the first check within the tolerance to the next check, and stops there
/// within the tolerance even though that is above the aim. The chain of 40 rows: Gauss-Seidel
/// shrinks its error by about cos²(π/41) = 0.994 a sweep, so eight sweeps take the residual
/// from just within the tolerance 1e-6 to about 0.95 of it, above the aim, and the residual
/// halves within 120 sweeps, so the stall guard (400) stays out.
#[test]
fn nsgs_goes_on_to_the_next_check() {
    let n = 40;
    let w = laplacian(n);
    let (q, rule) = (vec![-1.0; n], FixedBounds { lo: vec![-1e7; n], hi: vec![1e7; n] });
    let p = Problem { w: &w, q: &q, blocks: &singles(n) };
    let solve = |aim: f64| {
        let mut ws = Solver::new().with_method(Method::Nsgs);
        let rep = ws.solve(&p, &rule, &mut vec![0.0; n], &Options { aim, ..opts(1e-6, true) });
        assert!(rep.converged && ws.stats().fallbacks == 0, "aim {aim}: {rep:?}");
        rep
    };
    let (plain, aimed) = (solve(1.0), solve(AIM));
    assert!(plain.inner_iterations > 4 && plain.residual > AIM * 1e-6, "the case meant: {plain:?}");
    assert_eq!(aimed.inner_iterations, plain.inner_iterations + nsgs::CHECK_EVERY, "{plain:?} {aimed:?}");
    assert!(aimed.residual > AIM * 1e-6 && aimed.residual <= 1e-6, "{aimed:?}");
}
