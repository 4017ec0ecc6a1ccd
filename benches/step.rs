//! One full time step of a settled pile of disks (radius 0.5, density 1, mu 0.6, dt 1/60) in a
//! box, built by `pbdda::generate::DiskPile`: 1 000 and 10 000 rigid disks; 1 000 deformable
//! disks (4 DOF each); 1 000 rigid disks with rolling resistance (δ = 0.05).
//! The pile is first stepped until a step converges (at most `SETTLE_CAP` steps), so that the
//! measured step is warm-started and converged, as in a long run; contacts, PC iterations and
//! the residual of the timed step are printed once per size.

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use pbdda::generate::DiskPile;
use pbdda::model::BodyModel;
use pbdda::world::World;
use std::hint::black_box;

/// Most settling steps before the bench gives up waiting for a converged step.
const SETTLE_CAP: usize = 60;

fn settled(pile: DiskPile) -> World {
    let (columns, rows) = (pile.columns, pile.rows);
    let mut world = World::new(pile.model());
    let mut settling = 0;
    for _ in 0..SETTLE_CAP {
        settling += 1;
        if world.step().expect("pile step").converged && settling >= 5 {
            break;
        }
    }
    let rec = world.clone().step().expect("pile step");
    eprintln!(
        "pile {}x{} after {settling} settling steps: {} contacts, {} outer / {} PC iterations, \
         residual {:e} ({})",
        columns,
        rows,
        rec.contacts.len(),
        rec.outer_iterations,
        rec.inner_iterations,
        rec.residual,
        if rec.converged { "converged" } else { "NOT converged" }
    );
    eprintln!("  stages: {}; total {:.2} ms", rec.stages, rec.wall_seconds * 1e3);
    world
}

fn step(c: &mut Criterion) {
    let mut group = c.benchmark_group("step");
    group.sample_size(10);
    let deformable = DiskPile { model: BodyModel::Deformable, ..DiskPile::benchmark(40, 25) };
    let rolling = DiskPile { rolling: 0.05, ..DiskPile::benchmark(40, 25) };
    for (name, pile) in [
        ("rigid_disks_1000", DiskPile::benchmark(40, 25)),
        ("deformable_disks_1000", deformable),
        ("rolling_disks_1000", rolling),
        ("rigid_disks_10000", DiskPile::benchmark(100, 100)),
    ] {
        let world = settled(pile);
        group.bench_function(name, |b| {
            b.iter_batched(
                || world.clone(),
                |mut w| black_box(w.step().expect("step")),
                BatchSize::LargeInput,
            )
        });
    }
    group.finish();
}

criterion_group!(benches, step);
criterion_main!(benches);
