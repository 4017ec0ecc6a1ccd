//! One full time step of a settled pile of rigid disks (radius 0.5, density 1, mu 0.6,
//! dt 1/60) in a box, 1 000 and 10 000 disks, built by `pbdda::generate::DiskPile`.
//! The pile is first stepped a few times so that the measured step is warm-started, as in a
//! long run. Contacts and PC iterations per step are printed once per size.

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use pbdda::generate::DiskPile;
use pbdda::world::World;
use std::hint::black_box;

fn settled(columns: usize, rows: usize) -> World {
    let mut world = World::new(DiskPile::benchmark(columns, rows).model());
    for _ in 0..5 {
        world.step().expect("pile step");
    }
    let rec = world.clone().step().expect("pile step");
    eprintln!(
        "pile {}x{}: {} contacts, {} outer / {} PC iterations per step, residual {:e}",
        columns, rows, rec.contacts.len(), rec.outer_iterations, rec.inner_iterations, rec.residual
    );
    world
}

fn step(c: &mut Criterion) {
    let mut group = c.benchmark_group("step");
    group.sample_size(10);
    for (name, columns, rows) in [("rigid_disks_1000", 40, 25), ("rigid_disks_10000", 100, 100)] {
        let world = settled(columns, rows);
        group.bench_function(name, |b| {
            b.iter_batched(|| world.clone(), |mut w| black_box(w.step().expect("step")), BatchSize::LargeInput)
        });
    }
    group.finish();
}

criterion_group!(benches, step);
criterion_main!(benches);
