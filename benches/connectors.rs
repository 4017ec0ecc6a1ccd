//! Connector clusters (issue 7 benchmarks):
//! - a bonded-particle plate of 100 × 100 disks (radius 0.5, centres 1.1 apart, so neighbours do not
//!   touch) joined to their four neighbours by beams, resting on a fixed floor under gravity: one
//!   cluster of 30 000 DOFs with 100 floor contacts;
//! - a chain of 10 000 disks joined by springs lying on the floor (one cluster, 10 000 floor
//!   contacts: its part of W is in operator form), against the 10 000-disk unconnected pile in the
//!   same run.
//!
//! Each world is stepped twice before timing (the first step does the symbolic analysis); the stage
//! times of one step and the peak memory are printed once.

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use pbdda::generate::DiskPile;
use pbdda::world::World;
use std::fmt::Write;
use std::hint::black_box;

fn header(text: &mut String, steps: usize) {
    text.push_str(&format!(
        "[scene]\nname = \"bench\"\n[time]\nstep = 0.01\nsteps = {steps}\n[physics]\ngravity = [0.0, -9.81]\n\
         [[material]]\nname = \"m\"\ndensity = 1000.0\n[[interface]]\nfriction = 0.5\n\
         [[body]]\nname = \"floor\"\nshape = \"polygon\"\nvertices = [[-10.0, -1.0], [12000.0, -1.0], [12000.0, 0.0], [-10.0, 0.0]]\n\
         material = \"m\"\nfixed = true\n"
    ));
}

fn disk(text: &mut String, name: &str, x: f64, y: f64) {
    let _ = write!(
        text,
        "[[body]]\nname = \"{name}\"\nshape = \"disk\"\ncenter = [{x}, {y}]\nradius = 0.5\nmaterial = \"m\"\n"
    );
}

fn link(text: &mut String, kind: &str, a: &str, b: &str, pa: (f64, f64), pb: (f64, f64)) {
    let props =
        if kind == "beam" { "young = 1e9\narea = 0.1\ninertia = 1e-4\n" } else { "stiffness = 1e7\n" };
    let _ = write!(
        text,
        "[[connector]]\nkind = \"{kind}\"\npoints = [[{}, {}], [{}, {}]]\nbodies = [\"{a}\", \"{b}\"]\n{props}",
        pa.0, pa.1, pb.0, pb.1
    );
}

/// 100 × 100 disks, beams to the right and upper neighbours.
fn plate(n: usize) -> World {
    let mut t = String::new();
    header(&mut t, 10);
    let at = |i: usize, j: usize| (1.1 * i as f64, 0.5 + 1.1 * j as f64);
    for j in 0..n {
        for i in 0..n {
            let (x, y) = at(i, j);
            disk(&mut t, &format!("d{i}_{j}"), x, y);
        }
    }
    for j in 0..n {
        for i in 0..n {
            if i + 1 < n {
                link(
                    &mut t,
                    "beam",
                    &format!("d{i}_{j}"),
                    &format!("d{}_{j}", i + 1),
                    at(i, j),
                    at(i + 1, j),
                );
            }
            if j + 1 < n {
                link(
                    &mut t,
                    "beam",
                    &format!("d{i}_{j}"),
                    &format!("d{i}_{}", j + 1),
                    at(i, j),
                    at(i, j + 1),
                );
            }
        }
    }
    World::new(pbdda::scene::parse(&t, "plate.toml").expect("plate scene"))
}

/// `n` disks in a row on the floor, springs between neighbours.
fn chain(n: usize) -> World {
    let mut t = String::new();
    header(&mut t, 10);
    let at = |i: usize| (1.1 * i as f64, 0.5);
    for i in 0..n {
        disk(&mut t, &format!("c{i}"), at(i).0, at(i).1);
    }
    for i in 0..n - 1 {
        link(&mut t, "spring", &format!("c{i}"), &format!("c{}", i + 1), at(i), at(i + 1));
    }
    World::new(pbdda::scene::parse(&t, "chain.toml").expect("chain scene"))
}

fn warmed(name: &str, mut world: World) -> World {
    let first = world.step().expect("step 1");
    let rec = world.clone().step().expect("step");
    eprintln!(
        "{name}: step 1 {:.1} ms (symbolic analysis included; {}); step 2 {:.1} ms ({}); {} contacts, \
         {} iterations, residual {:.1e}",
        first.wall_seconds * 1e3,
        first.stages,
        rec.wall_seconds * 1e3,
        rec.stages,
        rec.contacts.len(),
        rec.inner_iterations,
        rec.residual
    );
    if let Ok(status) = std::fs::read_to_string("/proc/self/status")
        && let Some(line) = status.lines().find(|l| l.starts_with("VmHWM"))
    {
        eprintln!("  peak memory so far: {}", line.trim_start_matches("VmHWM:").trim());
    }
    world
}

fn connectors(c: &mut Criterion) {
    let mut group = c.benchmark_group("connectors");
    group.sample_size(10);
    let worlds = [
        ("bonded_plate_100x100", warmed("bonded plate 100x100", plate(100))),
        ("spring_chain_10000", warmed("spring chain 10000", chain(10_000))),
        ("pile_10000", warmed("pile 10000", World::new(DiskPile::benchmark(100, 100).model()))),
    ];
    for (name, world) in worlds {
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

criterion_group!(benches, connectors);
criterion_main!(benches);
