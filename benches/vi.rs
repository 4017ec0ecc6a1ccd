//! The contact solver alone (`pbdda::vi`) on 2-D contact networks (rigid disks on a grid,
//! `grid_network`, about 14 nonzeros per row of W): whole solves with both correction steps
//! (math note §4.2), cold and warm started, and the cost per W-product, serial and on rayon,
//! for the explicit CSR path and the matrix-free operator path.
//!
//! Conclusions drawn from these runs are stated in words in the rustdoc of `pbdda::vi`
//! (the extragradient step needed fewer products on every set measured; rayon gave no
//! measurable gain on a shared 2-core machine). The W-product counts of each solve are
//! printed once per configuration.
//!
//! Run: `cargo bench --bench vi` (sample size 10; about two minutes on an idle machine).

use criterion::{Criterion, criterion_group, criterion_main};
use pbdda::vi::{BoundRule, Correction, Operator, Options, Problem, Solver};

// the problem generators of the integration tests: the bench times the same problems
#[path = "../tests/vi_support/mod.rs"]
mod vi_support;
use std::hint::black_box;
use std::time::Duration;
use vi_support::{Coulomb, MatrixFree, Rng, frictionless, grid_network, pairs};

/// One solve from `z0`; returns the W-products used.
fn solve(
    s: &mut Solver,
    w: &dyn Operator,
    q: &[f64],
    rule: &dyn BoundRule,
    z0: &[f64],
    o: &Options,
) -> usize {
    let blocks: Vec<usize> = (0..=q.len() / 2).map(|k| 2 * k).collect();
    let mut z = z0.to_vec();
    black_box(s.solve(&Problem { w, q, blocks: &blocks }, rule, &mut z, o));
    s.stats().products
}

/// Whole solves on the 20×20 grid (1 560 rows) at tolerance 1e-8: frictionless from a cold
/// start, then warm started from that solution with q perturbed by 1 % (the next step of a
/// slowly moving scene), for both correction steps; Coulomb (mu = 0.3) from a cold start on
/// the 10×10 grid (380 rows).
fn solves(c: &mut Criterion) {
    let mut group = c.benchmark_group("vi_solve");
    group.sample_size(10).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(5));
    let (w, q) = grid_network(20, 20, 7, 0.1);
    let m = q.len();
    let mut rng = Rng::new(99);
    let q2: Vec<f64> = q.iter().map(|v| v * (1.0 + 0.01 * rng.range(-1.0, 1.0))).collect();
    let o = Options { tolerance: 1e-8, ..Options::default() };
    let cold = vec![0.0; m];
    for correction in [Correction::Extragradient, Correction::Contraction] {
        let mut s = Solver::new().with_correction(correction);
        let mut warm = vec![0.0; m];
        s.solve(&Problem { w: &w, q: &q, blocks: &pairs(m) }, &frictionless(m), &mut warm, &o);
        let runs: [(&str, &[f64], &[f64]); 2] =
            [("frictionless_cold", &q, &cold), ("frictionless_warm", &q2, &warm)];
        for (label, qq, z0) in runs {
            let products = solve(&mut s, &w, qq, &frictionless(m), z0, &o);
            eprintln!("{label} {correction:?}: {m} rows, {products} W-products");
            group.bench_function(format!("{label}_{correction:?}"), |b| {
                b.iter(|| solve(&mut s, &w, qq, &frictionless(m), z0, &o))
            });
        }
    }
    // Coulomb on a 10×10 grid (380 rows): the frictional QVI takes far more products.
    let (w, q) = grid_network(10, 10, 7, 0.1);
    let cold = vec![0.0; q.len()];
    let mut s = Solver::new();
    let products = solve(&mut s, &w, &q, &Coulomb { mu: 0.3, c: 0.0 }, &cold, &o);
    eprintln!("coulomb_0.3_cold: {} rows, {products} W-products", q.len());
    group.bench_function("coulomb_0.3_cold", |b| {
        b.iter(|| solve(&mut s, &w, &q, &Coulomb { mu: 0.3, c: 0.0 }, &cold, &o))
    });
    group.finish();
}

/// Cost of 100 PC iterations (about 200 W-products) on the frictionless grids of 9 900 and
/// 39 800 rows: CSR serial, CSR on rayon, and the matrix-free path (serial).
fn products(c: &mut Criterion) {
    let mut group = c.benchmark_group("vi_products");
    group.sample_size(10).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(5));
    let o = Options { tolerance: 1e-14, max_iterations: 100, ..Options::default() };
    for (nx, ny) in [(50, 50), (100, 100)] {
        let (w, q) = grid_network(nx, ny, 7, 0.1);
        let m = q.len();
        let cold = vec![0.0; m];
        eprintln!("grid {nx}x{ny}: {m} rows, {} nnz", w.nnz());
        for (label, par) in [("csr_serial", usize::MAX), ("csr_rayon", 0)] {
            let mut s = Solver::new().with_parallel_min_rows(par);
            group.bench_function(format!("{m}_rows_{label}"), |b| {
                b.iter(|| solve(&mut s, &w, &q, &frictionless(m), &cold, &o))
            });
        }
        if m < 20_000 {
            let (free, mut s) = (MatrixFree(w.clone()), Solver::new());
            group.bench_function(format!("{m}_rows_matrix_free"), |b| {
                b.iter(|| solve(&mut s, &free, &q, &frictionless(m), &cold, &o))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, solves, products);
criterion_main!(benches);
