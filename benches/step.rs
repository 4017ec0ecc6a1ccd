//! One full time step of a settled pile of disks (radius 0.5, density 1, mu 0.6, dt 1/60) in a
//! box, built by `pbdda::generate::DiskPile`: 1 000 and 10 000 rigid disks; 1 000 deformable
//! disks (4 DOF each); 1 000 rigid disks with rolling resistance (δ = 0.05); 1 000 disks of
//! which the last (top right) is deformable, the others rigid: a mixed pile, whose rigid
//! contacts stay contact frames beside the deformable disk's segments (math note §3.3); 1 000
//! rigid disks with ten bolts, each joining two touching disks (ten clusters assembled
//! explicitly beside 980 disks in body form).
//! The pile is first stepped until a step converges (at most `SETTLE_CAP` steps), so that the
//! measured step is warm-started and converged, as in a long run; contacts, PC iterations and
//! the residual of the timed step are printed once per size.

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use pbdda::generate::DiskPile;
use pbdda::model::{BodyModel, ConnectorKind, ConnectorSpec, Model, Shape};
use pbdda::world::World;
use std::hint::black_box;

/// Most settling steps before the bench gives up waiting for a converged step.
const SETTLE_CAP: usize = 60;

fn settled(name: &str, model: Model) -> World {
    let mut world = World::new(model);
    let mut settling = 0;
    for _ in 0..SETTLE_CAP {
        settling += 1;
        if world.step().expect("pile step").converged && settling >= 5 {
            break;
        }
    }
    let rec = world.clone().step().expect("pile step");
    eprintln!(
        "{name} after {settling} settling steps: {} contacts, {} outer / {} inner iterations, \
         residual {:e} ({})",
        rec.contacts.len(),
        rec.outer_iterations,
        rec.inner_iterations,
        rec.residual,
        if rec.converged { "converged" } else { "NOT converged" }
    );
    eprintln!("  stages: {}; total {:.2} ms", rec.stages, rec.wall_seconds * 1e3);
    world
}

/// The bench pile with `count` bolts (E = 1e8 Pa, A = 0.01 m²), each joining a disk to the next
/// one when they touch, spread over the pile, their anchors at the two centres.
fn bolted(count: usize) -> Model {
    let mut model = DiskPile::benchmark(40, 25).model();
    let n = model.bodies.len();
    let center = |s: &Shape| match s {
        Shape::Disk { center, .. } => *center,
        _ => unreachable!("a pile of disks"),
    };
    let mut a = 0;
    while model.connectors.len() < count && a + 1 < n {
        let moving = !model.bodies[a].fixed && !model.bodies[a + 1].fixed;
        let (pa, pb) = match moving {
            true => (center(&model.bodies[a].shape), center(&model.bodies[a + 1].shape)),
            false => (Default::default(), Default::default()),
        };
        if !moving || (pa - pb).norm() > 1.0 + 1e-6 {
            a += 1;
            continue;
        }
        model.connectors.push(ConnectorSpec {
            name: format!("bolt{}", model.connectors.len()),
            kind: ConnectorKind::Bolt { young: 1e8, area: 0.01 },
            bodies: [a, a + 1],
            points: [pa, pb],
            pretension: 0.0,
            strength: None,
        });
        a += n / count;
    }
    assert_eq!(model.connectors.len(), count, "touching pairs for every bolt");
    model
}

fn step(c: &mut Criterion) {
    let mut group = c.benchmark_group("step");
    group.sample_size(10);
    let deformable = DiskPile { model: BodyModel::Deformable, ..DiskPile::benchmark(40, 25) };
    let rolling = DiskPile { rolling: 0.05, ..DiskPile::benchmark(40, 25) };
    let mut mixed = DiskPile::benchmark(40, 25).model();
    let last = mixed.bodies.iter().rposition(|b| !b.fixed).expect("a moving disk");
    mixed.bodies[last].model = BodyModel::Deformable;
    for (name, model) in [
        ("rigid_disks_1000", DiskPile::benchmark(40, 25).model()),
        ("deformable_disks_1000", deformable.model()),
        ("rolling_disks_1000", rolling.model()),
        ("one_deformable_in_1000", mixed),
        ("ten_bolts_in_1000", bolted(10)),
        ("rigid_disks_10000", DiskPile::benchmark(100, 100).model()),
    ] {
        let world = settled(name, model);
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
