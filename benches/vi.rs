//! The contact solver alone (`pbdda::vi`) on 2-D contact networks (rigid disks on a grid,
//! `grid_network`, about 14 nonzeros per row of W): whole solves with both correction steps
//! (math note §4.2), cold and warm started, and the cost per W-product, serial and on both
//! cores, for the explicit CSR path and the matrix-free operator path.
//!
//! Conclusions drawn from these runs are stated in words in the rustdoc of `pbdda::vi`
//! (the extragradient step needed fewer products on every set measured). The W-product counts
//! of each solve are printed once per configuration.
//!
//! Group `body_form_product`: the body form's W z (math note §3.3) on a triangular lattice of
//! 100 × 100 rigid disks (10,000 bodies, 59,202 rows, 118,404 segments, like the 10,000-disk
//! pile, pushed as contact frames as the world pushes a pile's contacts), on one thread and on
//! two (the calling thread and one micropool worker): above `HALVES_FROM` (`delassus/bodies.rs`)
//! segments the product runs in two halves (`BodyPart::apply`), the same bits either way.
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
/// 39 800 rows: CSR serial, CSR on both cores, and the matrix-free path (serial).
fn products(c: &mut Criterion) {
    let mut group = c.benchmark_group("vi_products");
    group.sample_size(10).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(5));
    let o = Options { tolerance: 1e-14, max_iterations: 100, ..Options::default() };
    for (nx, ny) in [(50, 50), (100, 100)] {
        let (w, q) = grid_network(nx, ny, 7, 0.1);
        let m = q.len();
        let cold = vec![0.0; m];
        eprintln!("grid {nx}x{ny}: {m} rows, {} nnz", w.nnz());
        for (label, par) in [("csr_serial", usize::MAX), ("csr_two_cores", 0)] {
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

/// The body form's operator on a triangular lattice of `side` × `side` rigid disks, each touching
/// its right, upper and upper-right neighbours (two rows per contact), with a z to apply it to.
fn lattice(side: usize) -> (pbdda::delassus::ContactOperator, Vec<f64>) {
    use pbdda::body::Body;
    use pbdda::geometry::{Vec2, cw};
    use pbdda::jacobian::Frame;
    use pbdda::model::{BodyModel, BodySpec, Material, Plane, Shape};
    let n = side * side;
    let material = Material { name: "m".into(), density: 2.0, young: Some(1e8), poisson: Some(0.3) };
    let centre = |i: usize| Vec2::new((i % side) as f64 + 0.5 * (i / side) as f64, (i / side) as f64 * 0.866);
    let bodies: Vec<Body> = (0..n)
        .map(|i| {
            let spec = BodySpec::at_rest(
                format!("b{i}"),
                Shape::Disk { center: centre(i), radius: 0.5 },
                BodyModel::Rigid,
                false,
            );
            Body::new(&spec, &material, Plane::Stress)
        })
        .collect();
    let map = pbdda::dofs::DofMap::new(&bodies, &[]);
    let mut flex = pbdda::cluster::Flexibility::new(false);
    flex.refresh(&map, &bodies, &[], 1e-3, 0.0).expect("K̃ is SPD");
    let mut pairs = Vec::new();
    for i in 0..n {
        let (x, y) = (i % side, i / side);
        if x + 1 < side {
            pairs.push((i, i + 1));
        }
        if y + 1 < side {
            pairs.push((i, i + side));
            if x > 0 {
                pairs.push((i, i + side - 1));
            }
        }
    }
    let mut jac = pbdda::jacobian::Jacobian::default();
    jac.reset(2 * pairs.len());
    // each contact as one frame, as the world's rows push a rigid contact (B v is not needed)
    let (v, mut bv) = (vec![0.0; map.total()], vec![0.0; jac.rows]);
    for (k, &(a, b)) in pairs.iter().enumerate() {
        let normal = (bodies[a].centroid - bodies[b].centroid).normalize();
        let x = 0.5 * (bodies[a].centroid + bodies[b].centroid);
        let rows = |body: usize, sign| [normal, cw(normal)].map(|dir| bodies[body].rigid_row(x, dir, sign));
        let ([na, ta], [nb, tb]) = (rows(a, 1.0), rows(b, -1.0));
        let frame = Frame::new(2 * k, map.range(a).start, na, ta).with_second(map.range(b).start, nb, tb);
        let clusters = [a, b].map(|body| map.cluster_of(body).expect("free"));
        jac.push_frame(frame, clusters, &v, &mut bv);
    }
    let z = (0..jac.rows).map(|r| ((r * 37) % 101) as f64 / 101.0).collect();
    let op = pbdda::delassus::ContactOperator::with_scratch(
        jac,
        &flex,
        &map,
        usize::MAX,
        true,
        &mut Default::default(),
    );
    (op, z)
}

fn body_form(c: &mut Criterion) {
    let mut group = c.benchmark_group("body_form_product");
    group.sample_size(20).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(3));
    let (op, z) = lattice(100);
    let mut out = vec![0.0; z.len()];
    for threads in [1, 2] {
        let pool = micropool::ThreadPoolBuilder::default().num_threads(threads - 1).build();
        group.bench_function(format!("10000_disks_{threads}_threads"), |b| {
            b.iter(|| pool.install(|| op.apply(black_box(&z), &mut out)))
        });
    }
    group.finish();
}

criterion_group!(benches, solves, products, body_form);
criterion_main!(benches);
