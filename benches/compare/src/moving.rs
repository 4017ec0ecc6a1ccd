//! The moving scenes of issue 55 (`scenes.rs`) in pbdda and in rapier2d-f64 (same bodies,
//! masses, friction, restitution, dt; rapier at its defaults): whole-run wall time, pbdda's
//! iterations per step (median, max), repeated steps (adaptive splits), unconverged steps, and
//! the accuracy measure (run-out of the collapse and the rockfall, travel of the sliding mass
//! against the closed form g (sin a − cos a tan φ) t² / 2).
//!
//! `cargo run --release -- moving [quick]`: the table (quick: only the 200-disk collapse at
//! aspect 2 and the 60-block slide). `cargo run --release -- trade`: run-out and travel against
//! the tolerance (1e-4 … 1e-10) and dt.

use crate::scenes::{self, Measure, Scene, Shape2};
use pbdda::geometry::Vec2;
use pbdda::world::{Event, Warning, World};
use rapier2d_f64::prelude::*;
use std::time::Instant;

/// One pbdda run's figures.
pub struct Run {
    pub seconds: f64,
    pub iterations: Vec<usize>,
    pub repeated: usize,
    pub unconverged: usize,
    pub dropped: usize,
    pub measure: f64,
}

/// pbdda on `scene` at tolerance `tol`; `stops`: the friction-stop rule of math note §10.15.
pub fn pbdda(scene: &Scene, tol: f64, stops: bool) -> Run {
    let mut w = World::new(scene.model(tol));
    w.settings.friction_stops = stops;
    w.settings.contact_records = false;
    let free: Vec<usize> = (0..scene.bodies.len()).filter(|&i| !scene.bodies[i].fixed).collect();
    let start: Vec<Vec2> = free.iter().map(|&i| w.bodies[i].centroid).collect();
    let mut run =
        Run { seconds: 0.0, iterations: Vec::new(), repeated: 0, unconverged: 0, dropped: 0, measure: 0.0 };
    let t = Instant::now();
    for _ in 0..scene.steps {
        let rec = w.step().expect("pbdda step");
        run.iterations.push(rec.inner_iterations);
        run.unconverged += usize::from(!rec.converged);
        run.repeated += rec.events.iter().filter(|e| matches!(e, Event::StepSplit { .. })).count();
        run.dropped += rec.warnings.iter().filter(|w| matches!(w, Warning::StopsDropped { .. })).count();
    }
    run.seconds = t.elapsed().as_secs_f64();
    let end: Vec<Vec2> = free.iter().map(|&i| w.bodies[i].centroid).collect();
    run.measure = scene.measure.of(&start, &end);
    run
}

/// rapier2d-f64 at its defaults on `scene`: (wall time [s], measure).
pub fn rapier(scene: &Scene) -> (f64, f64) {
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
    let t = Instant::now();
    for _ in 0..scene.steps {
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
    }
    let seconds = t.elapsed().as_secs_f64();
    let start: Vec<Vec2> = free.iter().map(|(_, c)| *c).collect();
    let end: Vec<Vec2> =
        free.iter().map(|(h, _)| bodies[*h].translation()).map(|p| Vec2::new(p.x, p.y)).collect();
    (seconds, scene.measure.of(&start, &end))
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

/// The scenes of the table (`quick`: the 200-disk collapse at aspect 2 and the 60-block slide).
fn table_scenes(quick: bool) -> Vec<Scene> {
    let mut v = vec![scenes::collapse(200, 2.0, 1e-3, 400), scenes::slide(20, 3, 1e-3, 300)];
    if !quick {
        v.insert(1, scenes::collapse(200, 5.0, 1e-3, 400));
        v.insert(2, scenes::collapse(2000, 2.0, 1e-3, 100));
        v.push(scenes::slide(60, 10, 1e-3, 100));
        v.push(scenes::rockfall(1e-3, 1500));
    }
    v
}

/// The accuracy reference of a scene: the closed form for the slide, pbdda at 1e-10 otherwise.
fn reference(scene: &Scene) -> (f64, &'static str) {
    match scene.measure {
        Measure::Travel(_) => (scenes::slide_travel(scene.dt * scene.steps as f64), "closed form"),
        Measure::RunOut(_) => (pbdda(scene, 1e-10, true).measure, "pbdda 1e-10"),
    }
}

/// `moving [quick]`: the table of the moving scenes.
pub fn table(quick: bool) {
    println!(
        "| scene | engine | simulated [s] | wall [s] | iterations/step median, max | repeated steps | unconverged steps | stops dropped | run-out or travel [m] | vs reference | reference |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for scene in table_scenes(quick) {
        let (reference, what) = reference(&scene);
        let simulated = scene.dt * scene.steps as f64;
        for (label, stops) in [("pbdda 1e-8", true), ("pbdda 1e-8, no friction stops", false)] {
            let r = pbdda(&scene, 1e-8, stops);
            let (median, max) = spread(&r.iterations);
            println!(
                "| {} | {label} | {simulated} | {:.2} | {median}, {max} | {} | {} | {} | {:.6e} | {:.2e} | {what} |",
                scene.name,
                r.seconds,
                r.repeated,
                r.unconverged,
                r.dropped,
                r.measure,
                r.measure - reference
            );
        }
        let (seconds, measure) = rapier(&scene);
        println!(
            "| {} | rapier default | {simulated} | {seconds:.2} | 4 | | | | {measure:.6e} | {:.2e} | {what} |",
            scene.name,
            measure - reference
        );
    }
}

/// `trade`: the measures of the 200-disk collapse and the 60-block slide against the tolerance
/// and dt (math note §4.3), against the tolerance-1e-10 run at the same dt (and, for the slide,
/// the closed form).
pub fn trade() {
    println!(
        "| scene | dt [s] | tolerance | wall [s] | iterations/step median, max | unconverged steps | run-out or travel [m] | vs 1e-10 at this dt | vs closed form |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    let simulated = 0.3;
    for dt in [2e-3, 1e-3, 5e-4] {
        let steps = (simulated / dt).round() as usize;
        for scene in [scenes::collapse(200, 2.0, dt, steps), scenes::slide(20, 3, dt, steps)] {
            let tight = pbdda(&scene, 1e-10, true).measure;
            let closed = match scene.measure {
                Measure::Travel(_) => format!("{:.2e}", tight - scenes::slide_travel(simulated)),
                Measure::RunOut(_) => String::new(),
            };
            println!("| {} | {dt} | 1e-10 | | | | {tight:.6e} | 0 | {closed} |", scene.name);
            for tol in [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9] {
                let r = pbdda(&scene, tol, true);
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
