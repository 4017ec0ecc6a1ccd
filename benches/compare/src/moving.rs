//! The moving scenes of issue 55 (`scenes.rs`) in pbdda and in rapier2d-f64 (same bodies,
//! masses, friction, restitution, dt; rapier at its defaults): whole-run wall time, pbdda's
//! iterations per step (median, max), repeated steps (adaptive splits), unconverged steps, and
//! the accuracy measure (run-out of the collapse and the rockfall, travel of the sliding mass
//! against the closed form g (sin a − cos a tan φ) t² / 2).
//!
//! `cargo run --release -- moving [quick] [SCENE...] [with=auto,newton] [noref]`: the table
//! (`SCENES`; quick: the 200-disk collapse at aspect 2 and the 60-block slide; `with`: pbdda's
//! methods, `+stops` for friction stops). `cargo run --release -- trade`: run-out and travel
//! against the tolerance (1e-4 … 1e-10) and dt.

use crate::scenes::{self, Measure, Scene, Shape2};
use pbdda::geometry::Vec2;
use pbdda::vi::{Chain, Method};
use pbdda::world::{Event, Warning, World};
use rapier2d_f64::prelude::*;
use std::time::Instant;

/// The solver choices of a pbdda run: the VI method and the friction-stop rule of math note
/// §10.15 (off by default, `Settings::friction_stops`).
#[derive(Clone, Copy)]
pub struct Config {
    pub method: Chain,
    pub stops: bool,
}

impl Config {
    /// The defaults a user gets: `auto`, friction stops off.
    pub fn default_config() -> Config {
        Config { method: Chain::default(), stops: false }
    }

    /// A chain by scene name (`auto`, `newton`, ...) or methods joined by `/`
    /// (`mprgp/newton/nsgs`), with `+stops` for friction stops.
    pub fn parse(c: &str) -> Config {
        let (name, stops) = c.strip_suffix("+stops").map_or((c, false), |n| (n, true));
        let method = Chain::parse(name).unwrap_or_else(|| {
            let list: Vec<Method> = name
                .split('/')
                .map(|m| Method::parse(m).unwrap_or_else(|| panic!("unknown method {m}")))
                .collect();
            Chain::new(&list).unwrap_or_else(|| panic!("bad chain {name}"))
        });
        Config { method, stops }
    }

    /// Sets this configuration's method and friction-stop rule on `w`.
    pub fn apply(&self, w: &mut World) {
        w.model.solver.method = self.method;
        w.settings.friction_stops = self.stops;
    }

    /// `scene` at tolerance `tol` with this configuration, no contact records.
    pub fn world(&self, scene: &Scene, tol: f64) -> World {
        let mut w = World::new(scene.model(tol));
        self.apply(&mut w);
        w.settings.contact_records = false;
        w
    }

    /// A label for the table: the method, and friction stops when on.
    pub fn label(&self, tol: f64) -> String {
        let stops = if self.stops { ", friction stops" } else { "" };
        format!("pbdda {} {tol:e}{stops}", self.method.name())
    }
}

/// CPU time of this process so far [s] (Linux `/proc/self/stat` utime + stime at 100 ticks a
/// second; 0 elsewhere): on a shared machine it measures the work where wall time measures the
/// load.
pub fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    // the fields after the command name's closing parenthesis; utime and stime are 14 and 15
    let rest = stat.rsplit_once(')').map_or("", |(_, r)| r);
    let ticks: f64 = rest.split_whitespace().skip(11).take(2).filter_map(|f| f.parse::<f64>().ok()).sum();
    ticks / 100.0
}

/// One pbdda run's figures.
pub struct Run {
    pub seconds: f64,
    /// CPU time of the run [s].
    pub cpu: f64,
    /// Wall time of each step [s] (its repeated trials included).
    pub step_seconds: Vec<f64>,
    pub iterations: Vec<usize>,
    pub repeated: usize,
    pub unconverged: usize,
    pub dropped: usize,
    pub measure: f64,
}

/// The table's tolerance: `PBDDA_TOL` when set, else the default 1e-8.
fn tolerance() -> f64 {
    std::env::var("PBDDA_TOL").ok().and_then(|s| s.parse().ok()).unwrap_or(1e-8)
}

/// pbdda on `scene` at tolerance `tol` with the method and friction-stop rule of `cfg`.
pub fn pbdda(scene: &Scene, tol: f64, cfg: Config) -> Run {
    let mut w = cfg.world(scene, tol);
    let free: Vec<usize> = (0..scene.bodies.len()).filter(|&i| !scene.bodies[i].fixed).collect();
    let start: Vec<Vec2> = free.iter().map(|&i| w.bodies[i].centroid).collect();
    let mut run = Run {
        seconds: 0.0,
        cpu: 0.0,
        step_seconds: Vec::new(),
        iterations: Vec::new(),
        repeated: 0,
        unconverged: 0,
        dropped: 0,
        measure: 0.0,
    };
    // PBDDA_TRACE=1: one line a step on stderr (iterations, method, hand-overs, time)
    let trace = std::env::var_os("PBDDA_TRACE").is_some();
    let (t, cpu) = (Instant::now(), cpu_seconds());
    for _ in 0..scene.steps {
        let ts = Instant::now();
        let rec = w.step().expect("pbdda step");
        run.step_seconds.push(ts.elapsed().as_secs_f64());
        run.iterations.push(rec.inner_iterations);
        run.unconverged += usize::from(!rec.converged);
        run.repeated += rec.events.iter().filter(|e| matches!(e, Event::StepSplit { .. })).count();
        run.dropped += rec.warnings.iter().filter(|w| matches!(w, Warning::StopsDropped { .. })).count();
        if trace {
            let over: Vec<String> =
                rec.handovers.iter().map(|h| format!("{}>{}:{}", h.from, h.to, h.why)).collect();
            let method = rec.method.map_or("-", |m| m.name());
            let ms = 1e3 * run.step_seconds.last().copied().unwrap_or(0.0);
            eprintln!(
                "step {} it {} outer {} {method} conv {} {ms:.1} ms {}",
                run.iterations.len(),
                rec.inner_iterations,
                rec.outer_iterations,
                rec.converged,
                over.join(" ")
            );
        }
    }
    run.seconds = t.elapsed().as_secs_f64();
    run.cpu = cpu_seconds() - cpu;
    let end: Vec<Vec2> = free.iter().map(|&i| w.bodies[i].centroid).collect();
    run.measure = scene.measure.of(&start, &end);
    run
}

/// rapier2d-f64 at its defaults on `scene`: (wall time [s], measure, median step [s], CPU [s]).
pub fn rapier(scene: &Scene) -> (f64, f64, f64, f64) {
    let mut bodies = RigidBodySet::new();
    let mut colliders = ColliderSet::new();
    let mut free = Vec::new();
    for b in &scene.bodies {
        let (centre, collider) = match &b.shape {
            Shape2::Disk { center, radius } => (*center, ColliderBuilder::ball(*radius)),
            Shape2::Polygon(v) => {
                let c = centroid(v);
                let local: Vec<Vector> = v.iter().map(|p| Vector::new(p.x - c.x, p.y - c.y)).collect();
                (c, ColliderBuilder::convex_hull(&local).expect("convex polygon"))
            }
        };
        let collider =
            collider.density(scene.density).friction(scene.friction).restitution(scene.restitution);
        let builder = if b.fixed { RigidBodyBuilder::fixed() } else { RigidBodyBuilder::dynamic() };
        let h = bodies.insert(builder.translation(Vector::new(centre.x, centre.y)));
        colliders.insert_with_parent(collider, h, &mut bodies);
        if !b.fixed {
            free.push((h, centre));
        }
    }
    let params = IntegrationParameters { dt: scene.dt, ..IntegrationParameters::default() };
    let (mut pipeline, mut islands, mut broad, mut narrow) =
        (PhysicsPipeline::new(), IslandManager::new(), DefaultBroadPhase::default(), NarrowPhase::new());
    let (mut ij, mut mj, mut ccd) = (ImpulseJointSet::new(), MultibodyJointSet::new(), CCDSolver::new());
    let mut soft = SoftBodySet::new();
    let gravity = Vector::new(0.0, -9.81);
    let (t, cpu) = (Instant::now(), cpu_seconds());
    let mut step_seconds = Vec::new();
    for _ in 0..scene.steps {
        let ts = Instant::now();
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
        step_seconds.push(ts.elapsed().as_secs_f64());
    }
    let (seconds, cpu) = (t.elapsed().as_secs_f64(), cpu_seconds() - cpu);
    let start: Vec<Vec2> = free.iter().map(|(_, c)| *c).collect();
    let end: Vec<Vec2> =
        free.iter().map(|(h, _)| bodies[*h].translation()).map(|p| Vec2::new(p.x, p.y)).collect();
    (seconds, scene.measure.of(&start, &end), median(&step_seconds), cpu)
}

/// The centroid of a polygon.
fn centroid(v: &[Vec2]) -> Vec2 {
    let (mut a, mut c) = (0.0, Vec2::zeros());
    for i in 0..v.len() {
        let (p, q) = (v[i], v[(i + 1) % v.len()]);
        let cross = p.x * q.y - q.x * p.y;
        a += cross;
        c += (p + q) * cross;
    }
    c / (3.0 * a)
}

/// Median and max of the iterations per step.
fn spread(it: &[usize]) -> (usize, usize) {
    let mut s = it.to_vec();
    s.sort_unstable();
    (s[s.len() / 2], s[s.len() - 1])
}

/// The scenes of the table by key: `c200` (200-disk collapse, aspect 2), `c200a5` (aspect 5),
/// `c2000` (2,000 disks, aspect 2), `s60` and `s600` (60 and 600 sliding blocks), `rockfall`.
pub const SCENES: [&str; 6] = ["c200", "c200a5", "c2000", "s60", "s600", "rockfall"];

/// The scene of a key of [`SCENES`]: dt and duration as issue 55 states them where it does (the
/// 200-disk collapse: dt = 5e-4 s to 1.2 s). `KEY@T` runs the scene to T seconds instead.
pub fn scene_of(key: &str) -> Option<Scene> {
    if let Some((key, t)) = key.split_once('@') {
        let mut scene = scene_of(key)?;
        scene.steps = (t.parse::<f64>().ok()? / scene.dt).round() as usize;
        return Some(scene);
    }
    Some(match key {
        "c200" => scenes::collapse(200, 2.0, 5e-4, 2400),
        "c200a5" => scenes::collapse(200, 5.0, 5e-4, 2400),
        "c2000" => scenes::collapse(2000, 2.0, 5e-4, 2400),
        "s60" => scenes::slide(20, 3, 1e-3, 300),
        "s600" => scenes::slide(60, 10, 1e-3, 300),
        "rockfall" => scenes::rockfall(1e-3, 1500),
        _ => return None,
    })
}

/// The accuracy reference of a scene: the closed form for the slide, pbdda at 1e-10 otherwise.
fn reference(scene: &Scene) -> (f64, &'static str) {
    match scene.measure {
        Measure::Travel(_) => (scenes::slide_travel(scene.dt * scene.steps as f64), "closed form"),
        Measure::RunOut(_) => (pbdda(scene, 1e-10, Config::default_config()).measure, "pbdda auto 1e-10"),
    }
}

/// Median of a list.
fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    s[s.len() / 2]
}

/// `moving [SCENE...]`: the table of the moving scenes `keys`, each in pbdda at tolerance 1e-8
/// (the default) with each of `configs`, then in rapier2d-f64 at its defaults; `reference`:
/// also the pbdda 1e-10 run of the collapses' run-out (else the column is empty).
pub fn table(keys: &[String], configs: &[Config], with_reference: bool) {
    println!(
        "| scene | engine | simulated [s] | wall [s] | wall / rapier | CPU [s] | CPU / rapier | ms/step median | iterations/step median, max | repeated steps | unconverged steps | stops dropped | run-out or travel [m] | vs reference | reference |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for key in keys {
        let Some(scene) = scene_of(key) else {
            panic!("unknown scene {key}: one of {SCENES:?}");
        };
        let (reference, what) = match (scene.measure, with_reference) {
            (Measure::RunOut(_), false) => (f64::NAN, "(not run)"),
            _ => reference(&scene),
        };
        let simulated = scene.dt * scene.steps as f64;
        let (rapier_seconds, rapier_measure, rapier_step, rapier_cpu) = rapier(&scene);
        for cfg in configs {
            let r = pbdda(&scene, tolerance(), *cfg);
            let (it_median, it_max) = spread(&r.iterations);
            println!(
                "| {} | {} | {simulated:.3} | {:.2} | {:.2} | {:.2} | {:.2} | {:.3} | {it_median}, {it_max} | {} | {} | {} | {:.6e} | {:.2e} | {what} |",
                scene.name,
                cfg.label(tolerance()),
                r.seconds,
                r.seconds / rapier_seconds,
                r.cpu,
                r.cpu / rapier_cpu,
                median(&r.step_seconds) * 1e3,
                r.repeated,
                r.unconverged,
                r.dropped,
                r.measure,
                r.measure - reference
            );
        }
        println!(
            "| {} | rapier default | {simulated:.3} | {rapier_seconds:.2} | 1 | {rapier_cpu:.2} | 1 | {:.3} | 4 | | | | {rapier_measure:.6e} | {:.2e} | {what} |",
            scene.name,
            rapier_step * 1e3,
            rapier_measure - reference
        );
    }
}

/// `trade`: the measures of the 200-disk collapse and the 60-block slide against the tolerance
/// and dt (math note §4.3), against the tolerance-1e-10 run at the same dt (and, for the slide,
/// the closed form), at each dt of `dts`.
pub fn trade(dts: &[f64]) {
    println!(
        "| scene | dt [s] | tolerance | wall [s] | iterations/step median, max | unconverged steps | run-out or travel [m] | vs 1e-10 at this dt | vs closed form |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    let simulated = 0.3;
    for &dt in dts {
        let steps = (simulated / dt).round() as usize;
        for scene in [scenes::collapse(200, 2.0, dt, steps), scenes::slide(20, 3, dt, steps)] {
            let tight = pbdda(&scene, 1e-10, Config::default_config()).measure;
            let closed = match scene.measure {
                Measure::Travel(_) => format!("{:.2e}", tight - scenes::slide_travel(simulated)),
                Measure::RunOut(_) => String::new(),
            };
            println!("| {} | {dt} | 1e-10 | | | | {tight:.6e} | 0 | {closed} |", scene.name);
            for tol in [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9] {
                let r = pbdda(&scene, tol, Config::default_config());
                let (median, max) = spread(&r.iterations);
                let closed = match scene.measure {
                    Measure::Travel(_) => format!("{:.2e}", r.measure - scenes::slide_travel(simulated)),
                    Measure::RunOut(_) => String::new(),
                };
                println!(
                    "| {} | {dt} | {tol:e} | {:.2} | {median}, {max} | {} | {:.6e} | {:.2e} | {closed} |",
                    scene.name,
                    r.seconds,
                    r.unconverged,
                    r.measure,
                    r.measure - tight
                );
            }
        }
    }
}

/// `paired SCENE CONFIG...`: the trajectory of the first configuration (`Config::parse`), and
/// from each of its steps' start states one step with each other configuration, on a copy of
/// the world: a comparison on the same problems, which a collapse's diverging trajectories do
/// not give. Per step on stderr and in total on stdout: iterations, wall time, the method that
/// answered, unconverged steps (tolerance `PBDDA_TOL`).
pub fn paired(key: &str, configs: &[Config]) {
    let scene = scene_of(key).unwrap_or_else(|| panic!("unknown scene {key}: one of {SCENES:?}"));
    let mut w = configs[0].world(&scene, tolerance());
    // (iterations, seconds, unconverged) per configuration
    let mut total = vec![(0usize, 0.0f64, 0usize); configs.len()];
    for step in 1..=scene.steps {
        let mut line = format!("step {step}");
        for (k, cfg) in configs.iter().enumerate().rev() {
            let mut copy = (k > 0).then(|| {
                let mut c = w.clone();
                cfg.apply(&mut c);
                c
            });
            let t = Instant::now();
            let rec = copy.as_mut().unwrap_or(&mut w).step().expect("pbdda step");
            let seconds = t.elapsed().as_secs_f64();
            let method = rec.method.map_or("-", |m| m.name());
            let conv = if rec.converged { "" } else { " unconverged" };
            line += &format!(" | {} it {method} {:.0} ms{conv}", rec.inner_iterations, seconds * 1e3);
            let t = &mut total[k];
            (t.0, t.1, t.2) = (t.0 + rec.inner_iterations, t.1 + seconds, t.2 + usize::from(!rec.converged));
        }
        eprintln!("{line}");
    }
    for (cfg, (it, seconds, unconverged)) in configs.iter().zip(total) {
        println!("{}: {it} iterations, {seconds:.1} s, {unconverged} unconverged", cfg.label(tolerance()));
    }
}
