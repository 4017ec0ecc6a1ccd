//! One full time step of a settled pile of disks (radius 0.5, density 1, mu 0.6, dt 1/60) in a
//! box, built by `pbdda::generate::DiskPile`: 1 000 and 10 000 rigid disks; 1 000 deformable
//! disks (4 DOF each); 1 000 rigid disks with rolling resistance (δ = 0.05); 1 000 disks of
//! which the last (top right) is deformable, the others rigid: a mixed pile, whose rigid
//! contacts stay contact frames beside the deformable disk's segments (math note §3.3); 1 000
//! rigid disks with ten bolts, each joining two touching disks, and with ten chains of five
//! disks bolted in a row (ten clusters of 6 and of 15 DOFs, each with a closed-form K̃⁻¹ in
//! body form beside the single disks: math note §6).
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

/// The bench pile with `chains` chains of `length` disks, each disk bolted (E = 1e8 Pa,
/// A = 0.01 m², anchors at the two centres) to the next one, which it touches: chains spread
/// over the pile, `length − 1` bolts each.
fn bolted(chains: usize, length: usize) -> Model {
    let mut model = DiskPile::benchmark(40, 25).model();
    let n = model.bodies.len();
    let center = |s: &Shape| match s {
        Shape::Disk { center, .. } => *center,
        _ => unreachable!("a pile of disks"),
    };
    // whether disks a and a + 1 both move and touch, and their centres
    let touching = |model: &Model, a: usize| {
        let (ba, bb) = (&model.bodies[a], &model.bodies[a + 1]);
        if ba.fixed || bb.fixed {
            return None; // (the box's walls are no disks)
        }
        let (pa, pb) = (center(&ba.shape), center(&bb.shape));
        ((pa - pb).norm() <= 1.0 + 1e-6).then_some([pa, pb])
    };
    let (mut a, mut made) = (0, 0);
    while made < chains && a + length <= n {
        if (a..a + length - 1).any(|k| touching(&model, k).is_none()) {
            a += 1;
            continue;
        }
        for k in a..a + length - 1 {
            let points = touching(&model, k).expect("checked above");
            model.connectors.push(ConnectorSpec {
                name: format!("bolt{}", model.connectors.len()),
                kind: ConnectorKind::Bolt { young: 1e8, area: 0.01 },
                bodies: [k, k + 1],
                points,
                pretension: 0.0,
                strength: None,
                yield_force: None,
                ultimate_strain: None,
            });
        }
        made += 1;
        a += n / chains;
    }
    assert_eq!(made, chains, "touching runs for every chain");
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
        ("ten_bolts_in_1000", bolted(10, 2)),
        ("ten_chains_of_five_in_1000", bolted(10, 5)),
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
