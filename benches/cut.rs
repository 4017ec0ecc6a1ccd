//! The block cutter (`pbdda::rockmass::cut`, math note §12): a 100 m x 100 m domain cut by two
//! orthogonal persistent sets at 1 m through the corner (0, 0) (100 x 100 = 10,000 blocks; issue 53
//! asks for under 1 s on one core). Measured by criterion. Printed once (a
//! plain timing, one run): the same domain at 0.3162 m (317 x 317 = 100,489 blocks, the last row and column 0.08 m wide).
//!
//! `cargo bench --bench cut`

use criterion::{Criterion, criterion_group, criterion_main};
use pbdda::rockmass::{CutSpec, JointSet, cut};
use std::time::Instant;

fn spec(spacing: f64) -> CutSpec {
    let set = |angle: f64| JointSet { angle, spacing, ..JointSet::default() };
    CutSpec {
        domain: vec![[0.0, 0.0], [100.0, 0.0], [100.0, 100.0], [0.0, 100.0]],
        joint_sets: vec![set(0.0), set(90.0)],
        block_limit: 1_000_000,
        ..CutSpec::default()
    }
}

fn bench(c: &mut Criterion) {
    let large = spec(0.3162);
    let start = Instant::now();
    let blocks = cut(&large).expect("cut").blocks.len();
    eprintln!("100,000-block cut: {blocks} blocks in {:.2} s", start.elapsed().as_secs_f64());
    let small = spec(1.0);
    let mut group = c.benchmark_group("cut");
    group.sample_size(10);
    group.bench_function("100 m x 100 m, two sets at 1 m (10,000 blocks)", |b| {
        b.iter(|| assert_eq!(cut(&small).expect("cut").blocks.len(), 10_000))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
