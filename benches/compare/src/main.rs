//! pbdda against rapier2d-f64 on the benchmark piles of issue 10 (`DiskPile::benchmark`:
//! radius 0.5, density 1, μ 0.6, dt 1/60, hexagonal packing in a box, g = 9.81): time per
//! step, solver iterations, step-1 force error and sink.
//!
//! * Force error: relative L2 of the per-pair contact normal forces at step 1 against pbdda's
//!   forces at VI tolerance 1e-10 (PC; MPRGP on the 10,000 pile), over the union of touching
//!   body pairs (a pair missing on one side counts as zero force there). rapier's force of a
//!   pair is |total impulse| / dt.
//! * Time per step: the mean over `STEPS` steps and the median of steps 2 to `STEPS` (the
//!   cold first step of the pile at rest costs pbdda far more than the warm-started ones).
//! * Sink: mean drop of the disks' centres after `STEPS` steps.
//! * rapier at its defaults (4 solver iterations, 30 Hz contacts) and at high accuracy (256
//!   iterations, contacts at 1e4 Hz).
//!
//! `cargo run --release [-- 10000] [40000]` (also the 10,000 and 40,000 piles: MPRGP only,
//! against its own forces at tolerance 1e-10; PC and NSGS take minutes per step there).
//!
//! `cargo run --release -- long DISKS STEPS [TOL]` runs one pile (1000, 10000 or 40000 disks)
//! for STEPS steps with the default method at tolerance TOL (1e-6) and reports every step
//! that did not converge, the iterations per step and the kinetic energy: the long-run check
//! of issue 10's "no unconverged step" (the table above covers 20 steps).
//!
//! `cargo run --release -- moving [quick] [SCENE...] [with=auto,newton,...] [noref]` and
//! `-- trade [DT...]`: the moving scenes of issue 55 and their speed/accuracy trade
//! (`moving.rs`). `-- methods`: the 1,000-disk pile with each VI method at tolerances 1e-6 and
//! 1e-8. `-- stops`: the cost of friction stops (math note §10.15) on slumping and settled piles.
//! `-- paired SCENE CONFIG...`: the configurations on the same problems, step by step.

mod moving;
mod scenes;

use pbdda::generate::DiskPile;
use pbdda::vi::Method;
use pbdda::world::World;
use rapier2d_f64::prelude::*;
use std::collections::HashMap;
use std::time::Instant;

const STEPS: usize = 20;

type Pairs = HashMap<(usize, usize), f64>;

fn key(a: usize, b: usize) -> (usize, usize) {
    (a.min(b), a.max(b))
}

/// Wall time per step [ms]: the mean over all steps, and the median of the steps after the
/// first (the cold first step of a pile at rest is its most expensive by far).
struct Times {
    mean: f64,
    warm_median: f64,
}

impl Times {
    fn of(ms: &[f64]) -> Times {
        let mut warm = ms[1.min(ms.len() - 1)..].to_vec();
        warm.sort_by(f64::total_cmp);
        Times { mean: ms.iter().sum::<f64>() / ms.len() as f64, warm_median: warm[warm.len() / 2] }
    }
}

/// pbdda run: (times, mean iterations, step-1 pair forces, sink).
fn pbdda_run(pile: &DiskPile, method: Method, tol: f64, steps: usize) -> (Times, f64, Pairs, f64) {
    let mut m = pile.model();
    m.solver.method = method.into();
    m.solver.tolerance = tol;
    let mut w = World::new(m);
    let y0: Vec<f64> = w.bodies.iter().map(|b| b.centroid.y).collect();
    let (mut pairs, mut iters, mut ms) = (Pairs::new(), 0.0, Vec::new());
    for s in 0..steps {
        let t = Instant::now();
        let rec = w.step().expect("pbdda step");
        ms.push(t.elapsed().as_secs_f64() * 1e3);
        iters += rec.inner_iterations as f64;
        if s == 0 {
            for c in &rec.contacts {
                *pairs.entry(key(c.body_a, c.body_b)).or_default() += c.normal_force;
            }
        }
    }
    let disks = (3..w.bodies.len()).collect::<Vec<_>>();
    let sink = disks.iter().map(|&i| y0[i] - w.bodies[i].centroid.y).sum::<f64>() / disks.len() as f64;
    (Times::of(&ms), iters / steps as f64, pairs, sink)
}

/// rapier run with `iterations` solver iterations and contact frequency `hz` (None: defaults).
fn rapier_run(
    pile: &DiskPile,
    iterations: Option<usize>,
    hz: Option<f64>,
    steps: usize,
) -> (Times, Pairs, f64) {
    let r = pile.radius;
    let width = 2.0 * r * pile.columns as f64 + r;
    let height = (pile.rows as f64 + 1.0) * 2.0 * r;
    let mut bodies = RigidBodySet::new();
    let mut colliders = ColliderSet::new();
    let mut owner: HashMap<ColliderHandle, usize> = HashMap::new();
    // walls as in DiskPile::model: floor, left, right (pbdda bodies 0, 1, 2)
    for (i, (x0, y0, x1, y1)) in
        [(-r, -r, width + r, 0.0), (-r, 0.0, 0.0, height), (width, 0.0, width + r, height)]
            .into_iter()
            .enumerate()
    {
        let c = ColliderBuilder::cuboid(0.5 * (x1 - x0), 0.5 * (y1 - y0))
            .translation(Vector::new(0.5 * (x0 + x1), 0.5 * (y0 + y1)))
            .friction(pile.friction);
        owner.insert(colliders.insert(c), i);
    }
    let dy = 3f64.sqrt() * r;
    let mut handles = Vec::new();
    for row in 0..pile.rows {
        for col in 0..pile.columns {
            let x = r + 2.0 * r * col as f64 + if row % 2 == 1 { r } else { 0.0 };
            let y = r + dy * row as f64;
            let h = bodies.insert(RigidBodyBuilder::dynamic().translation(Vector::new(x, y)));
            let c = ColliderBuilder::ball(r).density(pile.density).friction(pile.friction);
            owner.insert(colliders.insert_with_parent(c, h, &mut bodies), 3 + handles.len());
            handles.push((h, y));
        }
    }
    let mut params = IntegrationParameters { dt: pile.dt, ..IntegrationParameters::default() };
    if let Some(n) = iterations {
        params.num_solver_iterations = n;
    }
    if let Some(f) = hz {
        params.contact_softness.natural_frequency = f;
        params.static_contact_softness.natural_frequency = f;
    }
    let (mut pipeline, mut islands, mut broad, mut narrow) =
        (PhysicsPipeline::new(), IslandManager::new(), DefaultBroadPhase::default(), NarrowPhase::new());
    let (mut ij, mut mj, mut ccd) = (ImpulseJointSet::new(), MultibodyJointSet::new(), CCDSolver::new());
    let mut soft = SoftBodySet::new();
    let gravity = Vector::new(0.0, -9.81);
    let (mut pairs, mut ms) = (Pairs::new(), Vec::new());
    for s in 0..steps {
        let t = Instant::now();
        pipeline.step(
            gravity,
            &params,
            &mut islands,
            &mut broad,
            &mut narrow,
            &mut bodies,
            &mut colliders,
            &mut ij,
            &mut mj,
            &mut soft,
            &mut ccd,
            &(),
            &(),
        );
        ms.push(t.elapsed().as_secs_f64() * 1e3);
        if s == 0 {
            for p in narrow.contact_pairs() {
                let f = p.total_impulse().length() / pile.dt;
                if f > 0.0 {
                    *pairs.entry(key(owner[&p.collider1], owner[&p.collider2])).or_default() += f;
                }
            }
        }
    }
    let sink =
        handles.iter().map(|(h, y)| y - bodies[*h].translation().y).sum::<f64>() / handles.len() as f64;
    (Times::of(&ms), pairs, sink)
}

fn error(a: &Pairs, reference: &Pairs) -> f64 {
    let keys: std::collections::BTreeSet<_> = a.keys().chain(reference.keys()).collect();
    let (mut num, mut den) = (0.0, 0.0);
    for k in keys {
        let (x, y) = (a.get(k).copied().unwrap_or(0.0), reference.get(k).copied().unwrap_or(0.0));
        num += (x - y) * (x - y);
        den += y * y;
    }
    (num / den).sqrt()
}

/// The bench pile of `disks` disks (1000, 10000 or 40000), for the table and for `long`.
fn pile_of(disks: &str) -> DiskPile {
    match disks {
        "1000" => DiskPile::benchmark(40, 25),
        "10000" => DiskPile::benchmark(100, 100),
        "40000" => DiskPile::benchmark(200, 200),
        _ => panic!("DISKS is 1000, 10000 or 40000, not {disks}"),
    }
}

/// `long DISKS STEPS [TOL]`: every unconverged step of a long run, then the totals.
fn long_run(args: &[String]) {
    let arg = |i: usize| args.get(i).map(String::as_str);
    let (Some(disks), Some(steps)) =
        (arg(0), arg(1).and_then(|s| s.parse::<usize>().ok()).filter(|&n| n > 0))
    else {
        panic!("usage: long DISKS STEPS [TOL]");
    };
    let tol: f64 = arg(2).map_or(1e-6, |t| t.parse().expect("TOL is a number"));
    let mut m = pile_of(disks).model();
    m.solver.tolerance = tol;
    let mut w = World::new(m);
    let (mut iters, mut ms, mut failed) = (Vec::new(), Vec::new(), Vec::new());
    println!("{disks} disks, {steps} steps, tolerance {tol:e}, method {}", w.model.solver.method.name());
    for s in 0..steps {
        let t = Instant::now();
        let rec = w.step().expect("pbdda step");
        ms.push(t.elapsed().as_secs_f64() * 1e3);
        iters.push(rec.inner_iterations);
        if !rec.converged {
            failed.push(s);
            println!(
                "step {s}: not converged, residual {:.3e} after {} iterations, {:.0} ms, kinetic energy {:.3e}",
                rec.residual, rec.inner_iterations, ms[s], rec.kinetic_energy
            );
        }
        if (s + 1) % 50 == 0 || s + 1 == steps {
            println!("step {s}: kinetic energy {:.3e} J/m", rec.kinetic_energy);
        }
    }
    let mean = iters.iter().sum::<usize>() as f64 / steps as f64;
    iters.sort_unstable();
    println!(
        "{} of {steps} steps not converged (first: {:?}); iterations per step median {}, mean {mean:.2}, max {}; ms per step median {:.2}, mean {:.2} after step 0",
        failed.len(),
        failed.first(),
        iters[steps / 2],
        iters[steps - 1],
        Times::of(&ms).warm_median,
        ms[1..].iter().sum::<f64>() / (steps - 1).max(1) as f64
    );
}

/// `moving [quick] [SCENE...] [with=CONFIG,...] [noref]`: the moving scenes (all of
/// `moving::SCENES` by default, `quick`: c200 and s60) with pbdda's configurations (`auto`,
/// `newton`, `mprgp`, ..., each optionally `+stops`; default `auto,newton`); `noref` skips the
/// collapses' tolerance-1e-10 reference runs.
fn moving_args(args: &[String]) {
    let mut keys: Vec<String> = Vec::new();
    let mut configs = vec![moving::Config::default_config(), moving::Config::parse("newton")];
    let mut with_reference = true;
    for a in args {
        if a == "quick" {
            keys.extend(["c200", "s60"].map(String::from));
        } else if a == "noref" {
            with_reference = false;
        } else if let Some(list) = a.strip_prefix("with=") {
            configs = list.split(',').map(moving::Config::parse).collect();
        } else {
            keys.push(a.clone());
        }
    }
    if keys.is_empty() {
        keys = moving::SCENES.map(String::from).to_vec();
    }
    moving::table(&keys, &configs, with_reference);
}

/// `methods`: the settled 1,000-disk pile with each VI method at tolerances 1e-6 and 1e-8:
/// time per step, iterations, step-1 force error against PC at 1e-10, sink.
fn methods() {
    let pile = pile_of("1000");
    let (_, _, reference, _) = pbdda_run(&pile, Method::Pc, 1e-10, 1);
    println!(
        "| method | tolerance | ms/step, mean of {STEPS} | ms/step, median of steps 2-{STEPS} | iterations/step | step-1 force error vs pc 1e-10 | sink [m] after {STEPS} steps |"
    );
    println!("|---|---|---|---|---|---|---|");
    for tol in [1e-6, 1e-8] {
        for method in [Method::Newton, Method::Mprgp, Method::Nsgs] {
            let (ms, it, pairs, sink) = pbdda_run(&pile, method, tol, STEPS);
            println!(
                "| {} | {tol:e} | {:.2} | {:.2} | {it:.0} | {:.2e} | {sink:.2e} |",
                method.name(),
                ms.mean,
                ms.warm_median,
                error(&pairs, &reference)
            );
        }
    }
}

/// `stops`: the cost of friction stops (math note §10.15) on frictional disk piles, on and
/// off: the 60-disk slumping pile of tests/paper/slumping_pile.rs (the bench pile with its right wall moved
/// 0.05 m out, the scene format's iteration budget) and the settled 1,000-disk pile. Wall time,
/// iterations, unconverged steps, steps whose stops were dropped, kinetic energy at the end.
fn stops() {
    println!(
        "| pile | steps | friction stops | wall [s] | iterations/step mean, max | unconverged steps | stops dropped | kinetic energy at the end [J/m] |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for (name, cols, rows, steps, slump) in
        [("slumping, 60 disks", 10, 6, 40, true), ("settled, 1,000 disks", 40, 25, 60, false)]
    {
        for on in [false, true] {
            let mut model = DiskPile::benchmark(cols, rows).model();
            if slump {
                let pbdda::model::Shape::Polygon { vertices } = &mut model.bodies[2].shape else {
                    panic!("the right wall")
                };
                vertices.iter_mut().for_each(|v| v.x += 0.05);
                model.solver.max_iterations = pbdda::model::SolverSettings::default().max_iterations;
            }
            let mut w = World::new(model);
            w.settings.friction_stops = on;
            w.settings.contact_records = false;
            let (mut its, mut unconverged, mut dropped, mut kinetic) = (Vec::new(), 0, 0, 0.0);
            let t = Instant::now();
            for _ in 0..steps {
                let rec = w.step().expect("pbdda step");
                its.push(rec.inner_iterations);
                unconverged += usize::from(!rec.converged);
                dropped += rec
                    .warnings
                    .iter()
                    .filter(|w| matches!(w, pbdda::world::Warning::StopsDropped { .. }))
                    .count();
                kinetic = rec.kinetic_energy;
            }
            let seconds = t.elapsed().as_secs_f64();
            let mean = its.iter().sum::<usize>() as f64 / steps as f64;
            println!(
                "| {name} | {steps} | {} | {seconds:.2} | {mean:.0}, {} | {unconverged} | {dropped} | {kinetic:.3e} |",
                if on { "on" } else { "off" },
                its.iter().max().unwrap_or(&0)
            );
        }
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.get(1).is_some_and(|a| a == "stops") {
        return stops();
    }
    if args.get(1).is_some_and(|a| a == "methods") {
        return methods();
    }
    if args.get(1).is_some_and(|a| a == "long") {
        return long_run(&args[2..]);
    }
    if args.get(1).is_some_and(|a| a == "paired") {
        let configs: Vec<moving::Config> = args[3..].iter().map(|c| moving::Config::parse(c)).collect();
        return moving::paired(&args[2], &configs);
    }
    if args.get(1).is_some_and(|a| a == "moving") {
        return moving_args(&args[2..]);
    }
    if args.get(1).is_some_and(|a| a == "trade") {
        // `trade [DT...]`: the time steps (default 2e-3, 1e-3, 5e-4)
        let mut dts: Vec<f64> = args[2..].iter().map(|a| a.parse().expect("DT is a number")).collect();
        if dts.is_empty() {
            dts = vec![2e-3, 1e-3, 5e-4];
        }
        return moving::trade(&dts);
    }
    let has = |n: &str| args.iter().any(|a| a == n);
    let mut piles = vec![("1,000 disks", pile_of("1000"))];
    for (arg, name) in [("10000", "10,000 disks"), ("40000", "40,000 disks")] {
        if has(arg) {
            piles.push((name, pile_of(arg)));
        }
    }
    println!(
        "| pile | engine | ms/step, mean of {STEPS} | ms/step, median of steps 2-{STEPS} | iterations/step | step-1 force error | sink [m] after {STEPS} steps |"
    );
    println!("|---|---|---|---|---|---|---|");
    for (name, pile) in piles {
        // PC and NSGS take minutes per step on the 10,000 pile: MPRGP only there, and its own
        // tolerance-1e-10 forces as the reference
        let small = pile.columns * pile.rows <= 1000;
        let reference_method = if small { Method::Pc } else { Method::Mprgp };
        let (_, _, reference, _) = pbdda_run(&pile, reference_method, 1e-10, 1);
        println!("| {name} | (force error reference: pbdda {} 1e-10) | | | | | |", reference_method.name());
        let mut methods = vec![("pbdda mprgp 1e-6", Method::Mprgp)];
        if small {
            methods.splice(0..0, [("pbdda pc 1e-6", Method::Pc), ("pbdda nsgs 1e-6", Method::Nsgs)]);
        }
        for (label, method) in methods {
            let (ms, it, pairs, sink) = pbdda_run(&pile, method, 1e-6, STEPS);
            println!(
                "| {name} | {label} | {:.2} | {:.2} | {it:.0} | {:.2e} | {sink:.2e} |",
                ms.mean,
                ms.warm_median,
                error(&pairs, &reference)
            );
            if method != reference_method {
                // the pile is hyperstatic: frictional forces are not unique, so also against
                // the same method's own converged forces
                let (_, _, own, _) = pbdda_run(&pile, method, 1e-10, 1);
                let own_label = format!("{}, error vs {} 1e-10", label, method.name());
                println!("| {name} | {own_label} | | | | {:.2e} | |", error(&pairs, &own));
            }
        }
        for (label, it, hz) in
            [("rapier default", None, None), ("rapier 256 it., 1e4 Hz", Some(256), Some(1e4))]
        {
            let (ms, pairs, sink) = rapier_run(&pile, it, hz, STEPS);
            let iters = it.unwrap_or(4);
            println!(
                "| {name} | {label} | {:.2} | {:.2} | {iters} | {:.2e} | {sink:.2e} |",
                ms.mean,
                ms.warm_median,
                error(&pairs, &reference)
            );
        }
    }
}
