//! The staged examples do what a user reads in their header comments.
//!
//! `examples/staged_slope.toml`: a 2 m x 10 m slab (area 20 m², from the domain's vertices) on a
//! bedding joint dipping a = 30° with phi = 20°, held by the toe rock, then the toe excavated, then
//! four bolts. Where each expected number comes from:
//! - stage "equilibrium" ends by `until_kinetic` (u = 1e-8 J/kg) before its end: its kinetic
//!   energy per unit mass on d/dt (math note §10.14) stayed below u, so each free body's mean
//!   velocity satisfies ½ m_i v_i² <= u M (M the free mass): the slab moves at most
//!   n dt sqrt(2 u M / m_i) over the stage's n steps (the bound asserted, about 3e-5 m);
//! - stage "excavate" (dynamic): the scheme is exact for constant forces (math note §1.1), so the
//!   slab slides down the dip s = a_s t²/2 from rest, a_s = g (sin a − cos a tan phi), t from the
//!   stage's start; 1e-6 m is the default VI tolerance (1e-8 relative on the contact forces) over
//!   20 steps (as tests/rock_mass_examples.rs);
//! - before stage "support" the bolts do not exist: force exactly 0;
//! - stage "support" (static): the slab creeps until friction is at its limit, and the bolts hold
//!   the rest: along and across the bedding, F cos θ + tan phi (W cos a + F sin θ) = W sin a, so
//!   ΣF = W (sin a − cos a tan phi) / (cos θ + sin θ tan phi), θ the bolts' angle to the bedding
//!   from their anchors at the end (all four are parallel and the slab translates, so each carries a
//!   quarter). Static relaxation approaches it by 2m/(2m + k dt²) a step (about 0.8 here): after 200
//!   steps the limit is reached far below the 1e-6 relative asserted; the slab no longer moves
//!   (below 1e-9 m in its last step).
//!
//! `examples/tunnel_insitu.toml`: a roof wedge, apex up, between traces of J1 (70°) and J2 (110°),
//! its neighbours fixed, the rest of the outline under the in-situ stress:
//! - stage "equilibrium": as above, the run stays within the bound its `until_kinetic` implies;
//! - bolted (the example): the pattern's four segments all hold the wedge; at the end of the
//!   static stage "excavate" the wedge has settled onto them with its flanks open (it widens
//!   downward, so it leaves both flanks as it moves down), so the bolts alone balance its weight:
//!   Σ F_i e_i = (0, W) to 1e-6 W (the static relaxation's geometric convergence, as above); in
//!   the dynamic stage "observe" it starts at rest in that equilibrium and stays, within 1e-6 m;
//! - unbolted (the same text without its [[bolt_pattern]]): nothing touches the wedge once the
//!   tunnel's blocks are removed, so in the static stage it moves g dt²/2 down every step (from
//!   rest, the scheme's exact step under a constant force, math note §1.1), and in the dynamic
//!   stage it falls freely from rest, g t²/2, each to 1e-9 m (round-off of the sums).

use crate::common;
use common::*;
use pbdda::geometry::Vec2;
use pbdda::world::World;

const G: f64 = 9.81;

fn polygon_area(v: &[Vec2]) -> f64 {
    (0..v.len()).map(|i| v[i].x * v[(i + 1) % v.len()].y - v[(i + 1) % v.len()].x * v[i].y).sum::<f64>() / 2.0
}

#[test]
fn staged_slope_rests_slides_once_its_toe_is_dug_and_is_held_by_bolts_in_limit_equilibrium() {
    let model = example("staged_slope.toml");
    let toe: Vec<usize> = model.excavations.iter().flat_map(|e| e.bodies.clone()).collect();
    let free: Vec<usize> =
        (0..model.bodies.len()).filter(|&b| !model.bodies[b].fixed && !toe.contains(&b)).collect();
    assert_eq!(free.len(), 1, "one slab above the bedding, outside the toe");
    assert_eq!(model.stages.len(), 3);
    let mut w = World::new(model);
    let slab = free[0];
    let area = match &w.bodies[slab].outline {
        pbdda::body::Outline::Polygon { vertices, .. } => polygon_area(vertices).abs(),
        _ => panic!("the slab is a polygon"),
    };
    assert!((area - 20.0).abs() < 1e-5, "slab area {area}");
    let (a, phi) = (30f64.to_radians(), 20f64.to_radians());
    let down_dip = Vec2::new(-a.cos(), -a.sin());
    let accel = G * (a.sin() - a.cos() * phi.tan());
    let dt = w.model.time.step;
    let free_mass: f64 = w.bodies.iter().filter(|b| !b.fixed).map(|b| b.mass).sum();
    let start = w.bodies[slab].centroid;
    // steps of stage 1, and (time, slab centroid) at its end: where the slide starts
    let (mut rest_steps, mut rest_end) = (0usize, (0.0, start));
    let mut last = start;
    let mut step_change = f64::INFINITY;
    while !w.finished() {
        let rec = w.step().unwrap_or_else(|e| panic!("{e}"));
        let x = w.bodies[slab].centroid;
        step_change = (x - last).norm();
        last = x;
        let stage = w.stage_name().unwrap_or("").to_owned();
        if stage != "support" {
            assert!(
                w.connectors.iter().all(|c| c.axial_force() == 0.0),
                "step {}: a bolt before its stage",
                rec.step
            );
        }
        match stage.as_str() {
            "equilibrium" => {
                rest_steps += 1;
                rest_end = (rec.time, x);
            }
            "excavate" => {
                let (t0, x0) = rest_end;
                let t = rec.time - t0;
                let expected = x0 + down_dip * (accel * t * t / 2.0);
                assert!((x - expected).norm() < 1e-6, "t = {t}: slab at {x:?}, closed form {expected:?}");
                assert!(toe.iter().all(|&b| w.is_removed(b)));
            }
            _ => {}
        }
    }
    // stage 1 ended early on its kinetic energy, and the slab stayed within the bound it implies
    let stage1 = &w.model.stages[0];
    assert!(rest_steps < stage1.end_step, "equilibrium ran {rest_steps} of {} steps", stage1.end_step);
    let u = stage1.until_kinetic.expect("until_kinetic");
    let bound = rest_steps as f64 * dt * (2.0 * u * free_mass / w.bodies[slab].mass).sqrt();
    let (t0, x0) = rest_end;
    assert!((t0 - rest_steps as f64 * dt).abs() < 1e-12);
    assert!((x0 - start).norm() <= bound, "moved {} m at rest (bound {bound})", (x0 - start).norm());
    // stage 3: limit equilibrium of the slab against its four bolts
    let weight = w.bodies[slab].mass * G;
    for c in &w.connectors {
        assert!(c.bodies.contains(&slab) && !c.broken);
        let on_slab = if c.bodies[0] == slab { 0 } else { 1 };
        let b = (c.anchors[1 - on_slab] - c.anchors[on_slab]).normalize();
        // angle to the bedding: b = cos θ (up-dip) − sin θ (outward normal)
        let theta = (-b.dot(&Vec2::new(-a.sin(), a.cos()))).atan2(b.dot(&-down_dip));
        let limit = weight * (a.sin() - a.cos() * phi.tan()) / (theta.cos() + theta.sin() * phi.tan());
        assert!(
            (c.axial_force() / (limit / 4.0) - 1.0).abs() < 1e-6,
            "{}: {} N, limit {}",
            c.name,
            c.axial_force(),
            limit / 4.0
        );
    }
    assert_eq!(w.connectors.len(), 4);
    assert!(step_change < 1e-9, "the slab still creeps {step_change} m a step");
}

/// The stage-by-stage path of the tunnel's roof wedge: (stage, time, centroid) after each step.
fn wedge_path(w: &mut World, wedge: usize) -> Vec<(String, f64, Vec2)> {
    let mut path = Vec::new();
    while !w.finished() {
        let rec = w.step().unwrap_or_else(|e| panic!("{e}"));
        if w.stage_name() == Some("equilibrium") {
            assert!(
                w.connectors.iter().all(|c| c.axial_force() == 0.0),
                "step {}: a bolt before its stage",
                rec.step
            );
        }
        path.push((w.stage_name().unwrap_or("").to_owned(), rec.time, w.bodies[wedge].centroid));
    }
    path
}

/// The roof wedge: the free body above the crown outside the tunnel's blocks (its centroid in the
/// wedge's triangle, between the crown at y = 13 and the apex at y = 15.5, on the axis x = 10).
fn roof_wedge(w: &World) -> usize {
    let tunnel: Vec<usize> = w.model.excavations.iter().flat_map(|e| e.bodies.clone()).collect();
    let found: Vec<usize> = (0..w.bodies.len())
        .filter(|&b| !w.bodies[b].fixed && !tunnel.contains(&b))
        .filter(|&b| {
            let c = w.bodies[b].centroid;
            (c.x - 10.0).abs() < 0.5 && c.y > 13.0 && c.y < 15.5
        })
        .collect();
    assert_eq!(found.len(), 1, "one roof wedge");
    found[0]
}

/// Stage 1 of a staged run ended on its `until_kinetic`, within the motion bound of the header.
fn assert_rested(w: &World, path: &[(String, f64, Vec2)], body: usize, start: Vec2) {
    let rest = path.iter().filter(|p| p.0 == "equilibrium").count();
    let stage1 = &w.model.stages[0];
    assert!(rest < stage1.end_step, "equilibrium ran {rest} of {} steps", stage1.end_step);
    let u = stage1.until_kinetic.expect("until_kinetic");
    let free_mass: f64 = (0..w.bodies.len())
        .filter(|&b| !w.bodies[b].fixed || w.is_removed(b))
        .map(|b| w.bodies[b].mass)
        .sum();
    let bound = rest as f64 * w.model.time.step * (2.0 * u * free_mass / w.bodies[body].mass).sqrt();
    let moved = (path[rest - 1].2 - start).norm();
    assert!(moved <= bound, "moved {moved} m at rest (bound {bound})");
}

#[test]
fn tunnel_insitu_roof_wedge_hangs_on_its_bolts() {
    let mut w = World::new(example("tunnel_insitu.toml"));
    let wedge = roof_wedge(&w);
    let start = w.bodies[wedge].centroid;
    let path = wedge_path(&mut w, wedge);
    assert_rested(&w, &path, wedge, start);
    assert_eq!(w.connectors.len(), 4);
    let weight = w.bodies[wedge].mass * G;
    let mut sum = Vec2::zeros();
    for c in &w.connectors {
        assert!(c.bodies.contains(&wedge) && !c.broken, "{} holds the wedge", c.name);
        let on = if c.bodies[0] == wedge { 0 } else { 1 };
        sum += (c.anchors[1 - on] - c.anchors[on]).normalize() * c.axial_force();
    }
    assert!(
        (sum - Vec2::new(0.0, weight)).norm() <= 1e-6 * weight,
        "bolts {sum:?} against the weight {weight}"
    );
    let settled = path.iter().rfind(|p| p.0 == "excavate").expect("excavate").2;
    let end = path.last().expect("steps").2;
    assert!(
        (end - settled).norm() < 1e-6,
        "the bolted wedge moved {} m while observed",
        (end - settled).norm()
    );
}

#[test]
fn tunnel_insitu_roof_wedge_falls_without_bolts() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/tunnel_insitu.toml");
    let text = std::fs::read_to_string(path).expect("example");
    let from = text.find("\n[[bolt_pattern]]\n").expect("a bolt pattern");
    let to = from + 1 + text[from + 1..].find("\n\n").expect("end of the table");
    let unbolted = format!("{}{}", &text[..from], &text[to..]);
    let mut w = World::new(pbdda::scene::parse(&unbolted, "unbolted.toml").unwrap_or_else(|e| panic!("{e}")));
    assert!(w.connectors.is_empty());
    let wedge = roof_wedge(&w);
    let start = w.bodies[wedge].centroid;
    let path = wedge_path(&mut w, wedge);
    assert_rested(&w, &path, wedge, start);
    let dt = w.model.time.step;
    let rest = path.iter().filter(|p| p.0 == "equilibrium").count();
    let y_rest = path[rest - 1].2.y;
    let mut creep = 0;
    for (stage, time, x) in &path[rest..] {
        match stage.as_str() {
            "excavate" => {
                creep += 1;
                let expected = y_rest - creep as f64 * G * dt * dt / 2.0;
                assert!(
                    (x.y - expected).abs() < 1e-9,
                    "step {creep} of excavate: y = {}, expected {expected}",
                    x.y
                );
            }
            _ => {
                let (t0, y0) = (path[rest + creep - 1].1, y_rest - creep as f64 * G * dt * dt / 2.0);
                let t = time - t0;
                assert!((x.y - (y0 - G * t * t / 2.0)).abs() < 1e-9, "t = {t}: y = {}", x.y);
            }
        }
        assert!((x.x - start.x).abs() < 1e-9, "the wedge falls straight down");
    }
    assert_eq!(path.last().map(|p| p.0.as_str()), Some("observe"));
}
