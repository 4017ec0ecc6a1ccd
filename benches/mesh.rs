//! The 100k-DOF meshed block of issue 8 (`pbdda::generate::PressedBlock`): a 4 m × 2 m block of
//! 3-node triangles resting on a rigid floor, a rigid disk pressed into its top, static
//! relaxation, dt 0.01. Printed once per size (plain timings, one run each): the symbolic
//! analysis and the numeric factorization of the block's step matrix K̄ (math note §9.1, §9.3),
//! the block of K̄⁻¹ over the contact DOFs by full solves of their unit vectors and by forward
//! solves along the factor's elimination tree (what a step uses), the first step (which factors and fills the node-column cache), and the process's peak
//! resident memory. Then the static relaxation's first steps, timed one by one until the VI needs
//! at most [`SETTLED_ITERATIONS`] iterations (the pressed block settling: their cost is the
//! VI's). Measured by criterion: one step of the settled block, with the factor kept
//! (`factor_drift = 1e-3`: the block barely turns or strains, so the factor and its cached node
//! columns of step 1 serve every step) and with a refactorization every step
//! (`factor_drift = 0`, the exact default).
//!
//! `PBDDA_MESH_NX=316 cargo bench --bench mesh` picks the grid (default 316 × 158 cells:
//! 50,403 nodes, 100,806 DOF).

use criterion::{Criterion, criterion_group, criterion_main};
use pbdda::cluster::SparseFactor;
use pbdda::generate::PressedBlock;
use pbdda::mesh::body::MeshBody;
use pbdda::world::World;
use std::time::Instant;

/// Peak resident memory of this process so far [MiB] (Linux `VmHWM`; 0 elsewhere).
fn peak_mib() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let kib = status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok());
    kib.unwrap_or(0.0) / 1024.0
}

/// Times the symbolic analysis and the numeric factorization of the block's K̄ on its own.
fn factor_times(block: &PressedBlock) {
    let model = block.model();
    let pbdda::model::Shape::Mesh(shape) = &model.bodies[1].shape else { unreachable!("the block") };
    let elastic = pbdda::body::constitutive(1e10, 0.25, model.physics.plane);
    let fe = MeshBody::new(shape, 2500.0, elastic, [0.0; 3], Default::default(), 0.0);
    let triplets = fe.step_triplets(block.dt);
    let mut factor = SparseFactor::new(fe.ndof());
    let t = Instant::now();
    factor.factorize(&triplets).expect("K̄ is SPD");
    let first = t.elapsed().as_secs_f64();
    let t = Instant::now();
    factor.factorize(&triplets).expect("K̄ is SPD");
    let numeric = t.elapsed().as_secs_f64();
    eprintln!(
        "{} DOF, {} triangles: symbolic analysis {:.3} s, numeric factorization {:.3} s",
        fe.ndof(),
        fe.triangles.len(),
        first - numeric,
        numeric
    );
    // the contact DOFs: the bottom row (the floor) and the top nodes under the disk
    let nodes = &shape.mesh.nodes;
    let set: Vec<usize> = (0..nodes.len())
        .filter(|&i| {
            nodes[i].y == 0.0 || (nodes[i].y == block.height && (nodes[i].x - 0.5 * block.width).abs() < 0.1)
        })
        .flat_map(|i| [2 * i, 2 * i + 1])
        .collect();
    let t = Instant::now();
    let reference = factor.inverse_block_by_solves(&set);
    let solves = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let block = factor.inverse_block(&set);
    let paths = t.elapsed().as_secs_f64();
    let scale = reference.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let diff = block.iter().zip(&reference).fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
    eprintln!(
        "block of K̄⁻¹ over {} contact DOFs: full solves {solves:.3} s, forward solves along the \
         elimination tree {paths:.3} s; difference {:.1e} of the largest entry",
        set.len(),
        diff / scale
    );
}

/// The VI iterations of a step of the settled block (at most).
const SETTLED_ITERATIONS: usize = 10;

/// Steps after the first while the block settles (at most).
const MAX_SETTLING: usize = 40;

/// The world after its first step and the steps in which the block settles (the VI needs more
/// than [`SETTLED_ITERATIONS`] iterations), with the time of each.
fn after_first_step(block: PressedBlock) -> World {
    let mut world = World::new(block.model());
    let t = Instant::now();
    let rec = world.step().expect("first step");
    eprintln!(
        "factor_drift {}: first step {:.3} s ({} contacts, residual {:e}; {}); peak memory {:.0} MiB",
        block.factor_drift,
        t.elapsed().as_secs_f64(),
        rec.contacts.len(),
        rec.residual,
        rec.stages,
        peak_mib()
    );
    for _ in 0..MAX_SETTLING {
        let t = Instant::now();
        let rec = world.step().expect("settling step");
        eprintln!(
            "  settling step {}: {:.3} s, {} VI iterations ({})",
            rec.step,
            t.elapsed().as_secs_f64(),
            rec.inner_iterations,
            rec.stages
        );
        if rec.inner_iterations <= SETTLED_ITERATIONS {
            break;
        }
    }
    world
}

fn bench(c: &mut Criterion) {
    let nx = std::env::var("PBDDA_MESH_NX").ok().and_then(|v| v.parse().ok()).unwrap_or(316);
    let block = PressedBlock::benchmark(nx);
    factor_times(&block);
    let mut group = c.benchmark_group("meshed block");
    group.sample_size(10);
    for drift in [1e-3, 0.0] {
        // the same world steps on (a clone would drop the factor's node-column cache); static
        // relaxation under a constant load, so every step of the settled block is alike
        let mut world = after_first_step(PressedBlock { factor_drift: drift, ..block });
        let name = format!("{} DOF step, factor_drift {drift}", 2 * (nx + 1) * (nx / 2 + 1));
        group.bench_function(name, |b| b.iter(|| world.step().expect("step")));
        eprintln!(
            "  numeric factorizations after {} steps: {}",
            world.step_index,
            world.sparse_factorizations()
        );
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
