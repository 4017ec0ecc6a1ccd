//! Unit tests of NSGS (math note §4.7) on closed-form cases: the exact solutions of `tests.rs`,
//! its rays, and what a run that uses up its budget returns. Expected values are derived in the
//! comment above each test, with their tolerances.

use super::tests::{Friction, INF, csr, opts, singles};
use super::*;

/// NSGS (math note §4.7) on the closed forms of `coulomb_stick_and_slide`: the same two
/// solutions (stick (38/35, −12/35), slide (8/9, 4/9)), to 1e-9 as there. The test rule has no
/// closed form, so this also exercises the fixed-box local solver.
#[test]
fn nsgs_coulomb_stick_and_slide() {
    let w = csr(2, &[2.0, 0.5, 0.5, 1.0]);
    for (q, want) in [([-2.0, -0.2], [38.0 / 35.0, -12.0 / 35.0]), ([-2.0, -2.0], [8.0 / 9.0, 4.0 / 9.0])] {
        let mut z = vec![0.0, 0.0];
        let mut ws = Solver::new().with_method(Method::Nsgs);
        let rep =
            ws.solve(&Problem { w: &w, q: &q, blocks: &[0, 2] }, &Friction(0.5), &mut z, &opts(1e-12, true));
        assert!(rep.converged && rep.residual <= 1e-12, "{q:?}: {rep:?}");
        assert!((z[0] - want[0]).abs() < 1e-9 && (z[1] - want[1]).abs() < 1e-9, "{q:?}: {z:?} vs {want:?}");
        assert_eq!(ws.stats().fallbacks, 0, "solved by NSGS itself");
    }
}

/// NSGS on the rays of `unbounded_rays_are_reported`: its growth test hands over to PC from
/// the warm start, which reports Diverged with the warm start restored.
#[test]
fn nsgs_unbounded_rays_are_reported() {
    let cases = [
        ([1.0, -1.0, -1.0, 1.0], [-1.0, -1.0], [0.0, 0.0]),
        ([1.0, 1.0, 1.0, 1.0], [1.0, -1.0], [-INF, -INF]),
    ];
    for (dense, q, lo) in cases {
        let w = csr(2, &dense);
        let mut ws = Solver::new().with_method(Method::Nsgs);
        let mut z = vec![0.0; 2];
        let rule = FixedBounds { lo: lo.to_vec(), hi: vec![INF, INF] };
        let rep =
            ws.solve(&Problem { w: &w, q: &q, blocks: &singles(2) }, &rule, &mut z, &Options::default());
        assert!(!rep.converged && ws.stats().status == Status::Diverged, "{rep:?} {:?}", ws.stats());
        assert_eq!(z, vec![0.0, 0.0]);
    }
}

/// NSGS on the diagonal W = diag(1..6), q = −1, z >= 0 with blocks [0, 2, 3, 6] (the 3-row
/// block takes the box enumeration): one sweep solves a diagonal W exactly, z_j = 1/j; the
/// reported residual is the §4.3 residual (below 1e-12).
#[test]
fn nsgs_exact_on_diagonal_w() {
    let mut dense = vec![0.0; 36];
    for j in 0..6 {
        dense[7 * j] = (j + 1) as f64;
    }
    let w = csr(6, &dense);
    let rule = FixedBounds { lo: vec![0.0; 6], hi: vec![INF; 6] };
    let mut z = vec![0.0; 6];
    let mut ws = Solver::new().with_method(Method::Nsgs);
    let rep =
        ws.solve(&Problem { w: &w, q: &[-1.0; 6], blocks: &[0, 2, 3, 6] }, &rule, &mut z, &opts(1e-12, true));
    assert!(rep.converged && rep.inner_iterations == 1 && rep.residual <= 1e-12, "{rep:?}");
    for (j, zj) in z.iter().enumerate() {
        assert!((zj - 1.0 / (j + 1) as f64).abs() < 1e-14, "{z:?}");
    }
}

/// A run that uses up its budget keeps its iterate (math note §4.7, "Stall guard"). W =
/// [[1, c], [c, 1]] with c = 0.99, q = (−1, −1), z >= 0: the solution z = (1, 1)/(1 + c) is
/// interior, so every sweep of NSGS is the Gauss-Seidel update z0 = −q0 − c z1, z1 = −q1 − c z0
/// (single rows, unit diagonal), whose error shrinks by c² = 0.98 a sweep: the residual halves
/// every 35 sweeps, so the stall guard never fires, and 10 sweeps end well short of 1e-6.
/// Expected: the iterate of 10 such updates from zero, computed here in the same order (the
/// same operations, so equal to rounding: 1e-15), its residual below the warm start's, and the
/// budget's status. Before, the iterate was dropped for the warm start (z = 0, which PC with
/// no budget left returned).
#[test]
fn nsgs_that_uses_up_its_budget_keeps_its_iterate() {
    let c = 0.99;
    let w = csr(2, &[1.0, c, c, 1.0]);
    let rule = FixedBounds { lo: vec![0.0; 2], hi: vec![INF; 2] };
    let p = Problem { w: &w, q: &[-1.0, -1.0], blocks: &singles(2) };
    let o = Options { max_iterations: 10, ..opts(1e-6, false) };
    let mut ws = Solver::new().with_method(Method::Nsgs);
    let start = ws.solve(&p, &rule, &mut [0.0; 2], &Options { max_iterations: 0, ..o }).residual;
    let mut z = [0.0; 2];
    let rep = ws.solve(&p, &rule, &mut z, &o);
    assert!(!rep.converged && rep.inner_iterations == 10, "{rep:?}");
    assert_eq!(ws.stats().status, Status::IterationLimit);
    assert!(rep.residual < start, "{} against the warm start's {start}", rep.residual);
    let mut want = [0.0f64; 2];
    for _ in 0..10 {
        want[0] = (1.0 - c * want[1]).max(0.0);
        want[1] = (1.0 - c * want[0]).max(0.0);
    }
    assert!((z[0] - want[0]).abs() < 1e-15 && (z[1] - want[1]).abs() < 1e-15, "{z:?} vs {want:?}");
}
