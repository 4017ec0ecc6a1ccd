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
use pbdda::vi::{BoundRule, Correction, FixedBounds, Operator, Options, Problem, Solver};
use sprs::{CsMat, TriMat};
use std::hint::black_box;
use std::time::Duration;

/// xorshift64*: small, deterministic, good enough for test data.
struct Rng(u64);

impl Rng {
    fn new(seed: u64) -> Self {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }
}

/// 2-D contact network (the same as in `tests/vi_kkt.rs`): rigid disks on an nx×ny grid
/// (unit spacing, radius 0.5, random masses 0.5..2, J = m/8), contacts with the right and
/// upper neighbours and with the floor, (normal, tangent) rows, W = B (dt²/2) M⁻¹ Bᵀ assembled sparse (about 14
/// nonzeros per row), q = B d^f with d^f = dt v + dt²/2 g (math note §1.2), random
/// velocities v in [-vamp, vamp], gravity 10 down. Returns (W, q).
fn grid_network(nx: usize, ny: usize, seed: u64, vamp: f64) -> (CsMat<f64>, Vec<f64>) {
    let mut rng = Rng::new(seed);
    let dt = 0.01;
    let nb = nx * ny;
    let minv: Vec<f64> = (0..nb)
        .flat_map(|_| {
            let m = rng.range(0.5, 2.0);
            [1.0 / m, 1.0 / m, 8.0 / m]
        })
        .collect();
    let mut trip: Vec<(usize, usize, f64)> = Vec::new();
    let mut row = 0;
    let mut add = |a: usize, b: Option<usize>, n: [f64; 2]| {
        for dir in [n, [n[1], -n[0]]] {
            // contact point midway: arm −0.5 n from A, +0.5 n from B; r × dir
            let ca = -0.5 * n[0] * dir[1] + 0.5 * n[1] * dir[0];
            trip.extend([(row, 3 * a, dir[0]), (row, 3 * a + 1, dir[1]), (row, 3 * a + 2, ca)]);
            if let Some(b) = b {
                trip.extend([(row, 3 * b, -dir[0]), (row, 3 * b + 1, -dir[1]), (row, 3 * b + 2, ca)]);
            }
            row += 1;
        }
    };
    for iy in 0..ny {
        for ix in 0..nx {
            let k = iy * nx + ix;
            if iy == 0 {
                add(k, None, [0.0, 1.0]);
            }
            if ix + 1 < nx {
                add(k + 1, Some(k), [1.0, 0.0]);
            }
            if iy + 1 < ny {
                add(k + nx, Some(k), [0.0, 1.0]);
            }
        }
    }
    let mut bm = TriMat::new((row, 3 * nb));
    let mut bs = TriMat::new((row, 3 * nb));
    for &(i, j, v) in &trip {
        bm.add_triplet(i, j, v);
        bs.add_triplet(i, j, v * minv[j] * dt * dt / 2.0);
    }
    let b: CsMat<f64> = bm.to_csr();
    let bscaled: CsMat<f64> = bs.to_csr();
    let btr: CsMat<f64> = b.transpose_view().to_csr();
    let w: CsMat<f64> = &bscaled * &btr;
    let df: Vec<f64> = (0..3 * nb)
        .map(|j| rng.range(-vamp, vamp) * dt - if j % 3 == 1 { dt * dt / 2.0 * 10.0 } else { 0.0 })
        .collect();
    let q = b.outer_iterator().map(|r| r.iter().map(|(j, &x)| x * df[j]).sum::<f64>()).collect();
    (w, q)
}

/// Frictionless box of `grid_network`: normal rows [0, inf), tangent rows fixed at 0.
fn frictionless(m: usize) -> FixedBounds {
    FixedBounds {
        lo: vec![0.0; m],
        hi: (0..m).map(|i| if i % 2 == 0 { f64::INFINITY } else { 0.0 }).collect(),
    }
}

/// Coulomb friction without cohesion on the (normal, tangent) blocks: tau = mu max(z_n, 0)
/// (math note §4.1).
struct Coulomb(f64);

impl BoundRule for Coulomb {
    fn block_bounds(&self, k: usize, z: &[f64], lo: &mut [f64], hi: &mut [f64]) {
        let tau = self.0 * z[2 * k].max(0.0);
        (lo[0], hi[0], lo[1], hi[1]) = (0.0, f64::INFINITY, -tau, tau);
    }
}

/// W behind the trait without its CSR storage: the matrix-free path.
struct MatrixFree(CsMat<f64>);

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
    let products = solve(&mut s, &w, &q, &Coulomb(0.3), &cold, &o);
    eprintln!("coulomb_0.3_cold: {} rows, {products} W-products", q.len());
    group.bench_function("coulomb_0.3_cold", |b| b.iter(|| solve(&mut s, &w, &q, &Coulomb(0.3), &cold, &o)));
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

/// Blocks of two rows (normal, tangent).
fn pairs(m: usize) -> Vec<usize> {
    (0..=m / 2).map(|k| 2 * k).collect()
}

criterion_group!(benches, solves, products);
criterion_main!(benches);
