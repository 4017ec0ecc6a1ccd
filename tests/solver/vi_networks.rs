//! Integration tests of the VI solver `pbdda::vi` on larger problems (math note §4.2-§4.3):
//! the two correction steps, serial vs parallel sweeps, and the matrix-free operator path
//! against the explicit CSR path. Helpers and their sources are in `vi_support`.

use crate::vi_support;

use pbdda::vi::{BoundRule, Correction, FixedBounds, Method, Options, Problem, Solver};
use sprs::CsMat;
use vi_support::*;

/// Extragradient vs contraction correction (math note §4.2) on two sets: 200 random box
/// VIs (`constructed_vi`, face condition <= 1e4) and 60 Coulomb QVIs (`disk_row`,
/// mu = 0.3); the contact-grid comparison is in `benches/vi.rs`. Both must converge
/// everywhere; the summed W-product counts are printed (the conclusion is stated on
/// `pbdda::vi::Correction`). A measurement: the only expected value is convergence.
#[test]
fn correction_comparison() {
    let eps = 1e-10;
    for correction in [Correction::Extragradient, Correction::Contraction] {
        let mut ws = Solver::new().with_correction(correction);
        let mut count = |w: &CsMat<f64>, q: &[f64], rule: &dyn BoundRule, blocks: &[usize]| {
            let mut z = vec![0.0; q.len()];
            let o = Options { max_outer: 1000, ..opts(eps, true) };
            let rep = ws.solve(&Problem { w, q, blocks }, rule, &mut z, &o);
            assert!(rep.converged, "{correction:?}: {rep:?}");
            ws.stats().products
        };
        let (mut p_box, mut p_qvi, mut cases) = (0, 0, 0);
        for seed in 0..400u64 {
            let mut rng = Rng::new(1000 + seed);
            let (m, n) = (1 + rng.below(30), 1 + rng.below(12));
            let w = random_w(&mut rng, m, n, 1.0);
            let c = constructed_vi(&mut rng, &w, 1.0);
            if cases == 200 || face_condition(&w, &c) > MAX_FACE_CONDITION {
                continue;
            }
            cases += 1;
            p_box += count(&to_csr(&w), &c.q, &FixedBounds { lo: c.lo, hi: c.hi }, &singles(m));
        }
        for seed in 0..60u64 {
            let (w, q) = disk_row(&mut Rng::new(seed));
            p_qvi += count(&to_csr(&w), &q, &Coulomb { mu: 0.3, c: 0.0 }, &pairs(q.len()));
        }
        println!("{correction:?}: {cases} box VIs {p_box} products; 60 disk-row QVIs {p_qvi} products");
    }
}

/// Serial and parallel sweeps give bit-identical results (reductions are summed per fixed
/// block in a fixed order), with PC and with MPRGP (whose every pass runs in halves).
/// Expected: identical z, reports and counters, for a converged frictionless solve (tolerance
/// 1e-6) and for a Coulomb QVI stopped by a 2 000-iteration budget. 3 540 rows: two blocks of
/// 2 048, one per half of `micropool::join`.
#[test]
fn slow_parallel_equals_serial() {
    let (w, q) = grid_network(30, 30, 11, 0.1);
    for (qvi, method) in [false, true].into_iter().flat_map(|q| [(q, Method::Pc), (q, Method::Mprgp)]) {
        let mut res = Vec::new();
        for par in [usize::MAX, 0] {
            let mut ws = Solver::new().with_parallel_min_rows(par).with_method(method);
            let mut z = vec![0.0; q.len()];
            let mut o = opts(1e-6, true);
            let blocks = pairs(q.len());
            let p = Problem { w: &w, q: &q, blocks: &blocks };
            let rep = if qvi {
                o.max_iterations = 2000;
                ws.solve(&p, &Coulomb { mu: 0.3, c: 0.0 }, &mut z, &o)
            } else {
                ws.solve(&p, &frictionless(q.len()), &mut z, &o)
            };
            assert_eq!(rep.converged, !qvi, "{method:?} {rep:?}");
            res.push((rep, z, ws.stats()));
        }
        assert_eq!(res[0].0, res[1].0);
        assert_eq!(res[0].2, res[1].2);
        assert!(res[0].1.iter().zip(&res[1].1).all(|(a, b)| a.to_bits() == b.to_bits()));
    }
}

/// The matrix-free path (`MatrixFree`: `apply` + `diagonal`, Jacobi scaling by vectors) must
/// solve the same problems as the CSR path, on the families of this file: 100 random box
/// VIs (`constructed_vi`, face condition <= 1e4, Jacobi on and off), 60 three-disk Coulomb
/// QVIs (`disk_row`, mu in [0.05, 0.7]), the badly scaled `heavy_base` chain and a 552-row
/// frictionless contact grid (`grid_network` 12×12).
/// Expected: converged with residual <= eps (1e-10; 1e-8 for the grid), and the KKT
/// conditions (`check_kkt`, `check_coulomb`, dense and independent of the solver) at eps.
/// For the box VIs also W z_free = W z_csr within 2 (1 + κ) eps ||W||_inf Z, κ the face
/// condition: both z pass the residual test at eps, and the error bound of an affine VI puts
/// each within (1 + κ) eps Z of the solution set in the scaled variables, on which W z is
/// unique (math note §3.2).
#[test]
fn operator_path_matches_csr() {
    let eps = 1e-10;
    let both = |w: &CsMat<f64>, q: &[f64], rule: &dyn BoundRule, fixed: bool, o: &Options| {
        let (ra, za, _) = run(w, q, rule, o, fixed);
        let (rb, zb, sb) = run(&MatrixFree(w.clone()), q, rule, o, fixed);
        assert!(ra.converged && rb.converged && rb.residual <= o.tolerance, "{ra:?} {rb:?} {:?}", sb.stats());
        (za, zb)
    };
    let mut cases = 0;
    for seed in 0..400u64 {
        let mut rng = Rng::new(7000 + seed);
        let (m, n) = (1 + rng.below(30), 1 + rng.below(12));
        let w = random_w(&mut rng, m, n, 1.0);
        let c = constructed_vi(&mut rng, &w, 1.0);
        let kappa = face_condition(&w, &c);
        if cases == 100 || kappa > MAX_FACE_CONDITION {
            continue;
        }
        cases += 1;
        for jacobi in [true, false] {
            let rule = FixedBounds { lo: c.lo.clone(), hi: c.hi.clone() };
            let (za, zb) = both(&to_csr(&w), &c.q, &rule, true, &opts(eps, jacobi));
            check_kkt(&w, &c.q, &c.lo, &c.hi, &zb, eps).unwrap();
            let wd = gap(&w, &vec![0.0; m], &za.iter().zip(&zb).map(|(a, b)| a - b).collect::<Vec<_>>());
            let zn = inf_norm(&za).max(inf_norm(&zb)).max(1.0);
            let tol = 2.0 * (1.0 + kappa) * eps * w_norm(&w) * zn;
            assert!(inf_norm(&wd) <= tol, "seed {seed}: |W(z_csr - z_free)| = {} > {tol}", inf_norm(&wd));
        }
    }
    for seed in 0..60u64 {
        let mut rng = Rng::new(seed);
        let (w, q) = disk_row(&mut rng);
        let rule = Coulomb { mu: rng.range(0.05, 0.7), c: 0.0 };
        let (_, zb) = both(&to_csr(&w), &q, &rule, false, &Options { max_outer: 1000, ..opts(eps, true) });
        check_coulomb(&w, &q, &rule, &zb, eps).unwrap();
    }
    let (w, q) = heavy_base();
    let (lo, hi) = (vec![0.0; q.len()], vec![f64::INFINITY; q.len()]);
    let rule = FixedBounds { lo: lo.clone(), hi: hi.clone() };
    let (_, zb) = both(&to_csr(&w), &q, &rule, true, &opts(eps, true));
    check_kkt(&w, &q, &lo, &hi, &zb, eps).unwrap();
    let (w, q) = grid_network(12, 12, 3, 0.1);
    let rule = frictionless(q.len());
    let (_, zb) = both(&w, &q, &rule, true, &opts(1e-8, true));
    check_kkt(&dense(&w), &q, &rule.lo, &rule.hi, &zb, 1e-8).unwrap();
}
