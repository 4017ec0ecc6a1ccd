//! The VI methods side by side (`[solver] method`, math note §4.2 and §4.7) on the issue's
//! benchmark piles (`DiskPile::benchmark`: radius 0.5, density 1, μ 0.6, dt 1/60): 1 000 and
//! 10 000 rigid disks, 1 000 deformable disks, and a hyperstatic stack of bricks (two contacts
//! per edge, a running bond 8 wide and 12 high).
//!
//! Printed once (stderr), at tolerance 1e-6:
//! * per pile and method: time per step (median and mean), VI iterations per step (median,
//!   mean, max; PC counts iterations, NSGS sweeps), the worst residual and unconverged steps,
//!   over `STEPS` steps from the start;
//! * the cold first step of the 10 000 pile (time, iterations, converged);
//! * accuracy against cost: step-1 normal-force error (relative L2 against PC at tolerance
//!   1e-10) and step time for tolerances 1e-2 … 1e-10, per method, on the 1 000 pile (and on
//!   the 10 000 pile with `PBDDA_BENCH_ACCURACY_10K=1`: minutes).
//!
//! Then criterion times one warm step per method on the 1 000 pile and on the brick stack.
//! `PBDDA_BENCH_QUICK=1` skips the 10 000 pile in the tables. The deformable and 10 000 piles
//! run 5 steps, the others 20.

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use pbdda::generate::DiskPile;
use pbdda::model::{BodyModel, Model};
use pbdda::scene::parse;
use pbdda::vi::Method;
use pbdda::world::{StepRecord, World};
use std::hint::black_box;
use std::time::Instant;

const STEPS: usize = 20;
const METHODS: [Method; 3] = [Method::Pc, Method::Nsgs, Method::Mprgp];

fn with(mut m: Model, method: Method, tolerance: f64) -> Model {
    m.solver.method = method.into();
    m.solver.tolerance = tolerance;
    m
}

/// A running-bond wall of 2×1 bricks (density 2000, μ 0.5) on a fixed floor: every brick
/// rests on two below along edges, two contacts per edge: hyperstatic.
fn brick_stack() -> Model {
    let mut s = String::from(
        "[scene]\nname = \"brick stack\"\n[time]\nstep = 0.001\nsteps = 10\n[physics]\n\
         gravity = [0.0, -10.0]\n[solver]\ntolerance = 1e-6\n[[material]]\nname = \"rock\"\n\
         density = 2000.0\n[[interface]]\nfriction = 0.5\n[[body]]\nname = \"floor\"\n\
         shape = \"polygon\"\nvertices = [[-2.0, -1.0], [20.0, -1.0], [20.0, 0.0], [-2.0, 0.0]]\n\
         material = \"rock\"\nfixed = true\n",
    );
    for row in 0..12 {
        let shift = if row % 2 == 0 { 0.0 } else { 1.0 };
        let y = row as f64;
        for col in 0..8 {
            let x = shift + 2.0 * col as f64;
            s += &format!(
                "[[body]]\nname = \"b{row}_{col}\"\nshape = \"polygon\"\nvertices = [[{x}, {y}], [{}, {y}], \
                 [{}, {}], [{x}, {}]]\nmaterial = \"rock\"\n",
                x + 2.0,
                x + 2.0,
                y + 1.0,
                y + 1.0
            );
        }
    }
    parse(&s, "brick_stack.toml").expect("valid brick stack")
}

fn piles() -> Vec<(&'static str, Model)> {
    let mut v = vec![
        ("rigid_disks_1000", DiskPile::benchmark(40, 25).model()),
        (
            "deformable_disks_1000",
            DiskPile { model: BodyModel::Deformable, ..DiskPile::benchmark(40, 25) }.model(),
        ),
        ("brick_stack_96", brick_stack()),
    ];
    if std::env::var_os("PBDDA_BENCH_QUICK").is_none() {
        v.push(("rigid_disks_10000", DiskPile::benchmark(100, 100).model()));
    }
    v
}

fn stats(mut x: Vec<f64>) -> (f64, f64, f64) {
    x.sort_by(f64::total_cmp);
    let mean = x.iter().sum::<f64>() / x.len().max(1) as f64;
    (x.get(x.len() / 2).copied().unwrap_or(f64::NAN), mean, x.last().copied().unwrap_or(f64::NAN))
}

/// Runs `steps` steps; returns the records.
fn run(model: Model, steps: usize) -> Vec<StepRecord> {
    let mut w = World::new(model);
    (0..steps).map(|_| w.step().expect("step")).collect()
}

fn summary() {
    eprintln!(
        "pile method | ms/step median mean | iterations median mean max | worst residual | unconverged"
    );
    for (name, model) in piles() {
        // the 10 000 pile and the deformable pile cost seconds per step: fewer steps
        let steps = if name.contains("10000") || name.contains("deformable") { 5 } else { STEPS };
        for m in METHODS {
            let recs = run(with(model.clone(), m, 1e-6), steps);
            let (tm, ta, _) = stats(recs.iter().map(|r| r.wall_seconds * 1e3).collect());
            let (im, ia, ix) = stats(recs.iter().map(|r| r.inner_iterations as f64).collect());
            let worst = recs.iter().map(|r| r.residual).fold(0.0, f64::max);
            let bad = recs.iter().filter(|r| !r.converged).count();
            eprintln!(
                "{name} {:5} | {tm:9.2} {ta:9.2} | {im:8.0} {ia:9.1} {ix:8.0} | {worst:9.2e} | {bad}/{steps}",
                m.name()
            );
            if name.contains("10000") {
                let r = &recs[0];
                eprintln!(
                    "  cold first step: {:.2} s, {} iterations, converged {}",
                    r.wall_seconds, r.inner_iterations, r.converged
                );
            }
        }
    }
}

/// Relative L2 difference of the normal forces of two step records with the same contacts.
fn force_error(a: &StepRecord, reference: &StepRecord) -> f64 {
    if a.contacts.len() != reference.contacts.len() {
        return f64::NAN;
    }
    let (mut num, mut den) = (0.0, 0.0);
    for (x, y) in a.contacts.iter().zip(&reference.contacts) {
        if (x.body_a, x.body_b) != (y.body_a, y.body_b) {
            return f64::NAN;
        }
        num += (x.normal_force - y.normal_force).powi(2);
        den += y.normal_force.powi(2);
    }
    (num / den.max(1e-300)).sqrt()
}

fn accuracy() {
    eprintln!("accuracy vs cost, step 1 (normal-force error vs PC at 1e-10; time per step [ms])");
    let full = std::env::var_os("PBDDA_BENCH_ACCURACY_10K").is_some();
    for (name, model) in
        piles().into_iter().filter(|(n, _)| n == &"rigid_disks_1000" || (full && n.starts_with("rigid")))
    {
        let reference = run(with(model.clone(), Method::Pc, 1e-10), 1).remove(0);
        for m in METHODS {
            let mut line = format!("{name} {:5}", m.name());
            for e in 2..=10 {
                let tol = 10f64.powi(-e);
                let started = Instant::now();
                let r = run(with(model.clone(), m, tol), 1).remove(0);
                let t = started.elapsed().as_secs_f64() * 1e3;
                line += &format!(" | 1e-{e}: {:.1e} {t:.1}ms", force_error(&r, &reference));
            }
            eprintln!("{line}");
        }
    }
}

fn bench(c: &mut Criterion) {
    summary();
    accuracy();
    let mut group = c.benchmark_group("solvers");
    group.sample_size(10);
    for (name, model) in
        [("rigid_disks_1000", DiskPile::benchmark(40, 25).model()), ("brick_stack_96", brick_stack())]
    {
        for m in METHODS {
            // warm: five steps in, as in a running simulation
            let mut world = World::new(with(model.clone(), m, 1e-6));
            for _ in 0..5 {
                world.step().expect("step");
            }
            group.bench_function(format!("{name}/{}", m.name()), |b| {
                b.iter_batched(
                    || world.clone(),
                    |mut w| black_box(w.step().expect("step")),
                    BatchSize::LargeInput,
                )
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
