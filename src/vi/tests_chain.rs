//! Unit tests of what an unconverged solve returns and reports (math note §4.7, "The best
//! answer of a failed chain"): the residual is that of the returned z with its own bounds,
//! and a chain of methods returns the best answer it reached. Expected values are derived in
//! the comment above each test, with their tolerances.

use super::chain::Best;
use super::tests::{Friction, csr, opts};
use super::*;

/// The sliding case of `coulomb_stick_and_slide` (W = [[2, 0.5], [0.5, 1]], q = (−2, −2),
/// μ = 0.5) from z = 0, cut by budgets of 1 to 12 iterations: the passes' boxes move with z
/// (the first pass has the friction bound 0 of z = 0), so a run cut inside a pass holds an
/// iterate whose own box is not the pass's. Every one of these 24 runs is cut (at 1e-12 both
/// methods need more than 12 iterations here; asserted, so that the test keeps testing cut
/// runs). Whatever the budget, the reported residual must be that of the returned z measured
/// on its own, as NSGS measures its start (a run from z with no budget, which neither clips
/// nor moves z), to 1e-12 relative: the two measure the same point, one from PC's scaled
/// y, the other from z, which differ by rounding. Before the rule, PC cut at 1 iteration reported its pass's box's 0.192
/// where z's own gives 0.404 (checked).
#[test]
fn a_cut_run_reports_the_residual_of_its_answer() {
    let w = csr(2, &[2.0, 0.5, 0.5, 1.0]);
    let p = Problem { w: &w, q: &[-2.0, -2.0], blocks: &[0, 2] };
    for method in [Method::Pc, Method::Mprgp] {
        for budget in 1..=12 {
            let o = Options { max_iterations: budget, ..opts(1e-12, true) };
            let mut z = vec![0.0; 2];
            let mut ws = Solver::new().with_method(method);
            let rep = ws.solve(&p, &Friction(0.5), &mut z, &o);
            assert!(!rep.converged, "{method:?}, budget {budget}: {rep:?}");
            let again = Solver::new().with_method(Method::Nsgs).solve(
                &p,
                &Friction(0.5),
                &mut z.clone(),
                &Options { max_iterations: 0, ..o },
            );
            let l = format!("{method:?}, budget {budget}: {rep:?} against {again:?} at {z:?}");
            assert!((rep.residual - again.residual).abs() <= 1e-12 * again.residual, "{l}");
        }
    }
}

/// `Best` keeps the smallest residual offered (NaN never), and an unconverged answer that is
/// an iterate (IterationLimit, OuterLimit, Stalled) gives way to it when it is strictly
/// smaller; a converged answer, a better final answer, and answers whose z the status
/// describes otherwise (the warm start of Diverged and NonFinite, invalid bounds) stay.
#[test]
fn a_failed_chain_returns_its_best_answer() {
    let mut best = Best::default();
    best.start();
    for (residual, z) in [(2e-3, [1.0, 2.0]), (5e-4, [3.0, 4.0]), (1e-3, [5.0, 6.0]), (f64::NAN, [7.0, 8.0])]
    {
        best.offer(residual, &z);
    }
    let report =
        |residual, converged| Report { outer_iterations: 1, inner_iterations: 9, residual, converged };
    for status in [Status::IterationLimit, Status::OuterLimit, Status::Stalled] {
        let (mut r, mut z) = (report(4e-3, false), vec![9.0, 9.0]);
        best.keep(&mut r, status, &mut z);
        assert_eq!((r.residual, z), (5e-4, vec![3.0, 4.0]), "{status:?}");
    }
    let stays = [
        (report(4e-3, false), Status::Diverged),
        (report(4e-3, false), Status::NonFinite),
        (report(4e-3, false), Status::InvalidBounds),
        (report(5e-4, false), Status::IterationLimit),
        (report(1e-9, true), Status::Converged),
    ];
    for (r0, status) in stays {
        let (mut r, mut z) = (r0, vec![9.0, 9.0]);
        best.keep(&mut r, status, &mut z);
        assert_eq!((r, z), (r0, vec![9.0, 9.0]), "{status:?}");
    }
    // a new chain forgets the last one's answer
    best.start();
    let (mut r, mut z) = (report(4e-3, false), vec![9.0, 9.0]);
    best.keep(&mut r, Status::IterationLimit, &mut z);
    assert_eq!((r.residual, z), (4e-3, vec![9.0, 9.0]));
}
