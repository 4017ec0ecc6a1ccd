//! Paper §7.8, Table 6: rigid 2 x 2 block B2 (H = 1, rho = 1000, m = 4000 kg) cemented to a
//! fixed block B1 along C1C2 (x = 0, C1 at y = +H, C2 at y = -H), no gravity, dt = 0.01;
//! t = 1000 Pa x 2 m = 2000 N shared by the two joints. F = 1000 N pulls B2 away
//! perpendicular to the interface along y = h.
//! Statics (math note §7.8, force and moment balance of B2 with signed normal forces,
//! tension negative): P1 = -F (H + h)/(2H), P2 = -F (H - h)/(2H), i.e. -500/-500, -750/-250,
//! -1000/0 for h = 0, 0.5, 1; the contacts stay Bonded and B2 does not move. Tolerances at each
//! of 20 steps: 1e-5 N on P1, P2 (the paper's own errors are 1e-5 N; the solver's are
//! tol |z| ~ 1e-12 · 1000 N = 1e-9 N), 1e-9 m on B2's displacement (balanced forces move a
//! bonded block only by the solver's error times W, ~1e-16 m).
//! Break test (math note §4.5, hypothesis iv; §10.8): F = 3000 N > t at h = 0. Step 1: the
//! first solve puts both joints at their shares and they open, so the interface breaks (an
//! event) and the step is solved again without the bond: the step's contacts carry nothing
//! (P1 = P2 = 0 to 1e-9 N: an open contact's force is exactly 0, the tolerance allows the
//! solver's 1e-12 relative error on ~1000 N) and B2 moves off under F alone from t = 0,
//! v = F/m dt after step 1. From step 2 the interface carries nothing (no contact Bonded, no
//! tension): each step adds F/m dt = 0.0075 m/s to its velocity (Newmark is exact under a
//! constant force, math note §1.1; tolerance 1e-9 relative, far above rounding and far below
//! any lost share of the load).

use crate::common;
use common::*;
use pbdda::geometry::Vec2;
use pbdda::model::Model;
use pbdda::world::{ContactState, World};

const H: f64 = 1.0;
const T: f64 = 2000.0;
const MASS: f64 = 4000.0;

fn pulled(f: f64, h: f64) -> Model {
    let mut model = example("7_8_cemented_interface.toml");
    model.loads[0].point = Vec2::new(1.0, h);
    model.loads[0].force = Vec2::new(f, 0.0);
    model
}

#[test]
fn table_6_interface_tensions() {
    let f = 1000.0;
    for h in [0.0, 0.5, 1.0] {
        let (p1, p2) = (-f * (H + h) / (2.0 * H), -f * (H - h) / (2.0 * H));
        let mut world = World::new(pulled(f, h));
        let b2 = body(&world, "B2");
        let c0 = world.bodies[b2].centroid;
        let mut worst = 0.0f64;
        run(&mut world, 20, |w, rec| {
            assert!(rec.events.is_empty(), "h = {h}, step {}: {:?}", rec.step, rec.events);
            let mut cs = between(w, rec, "B1", "B2");
            assert_eq!(cs.len(), 2, "h = {h}, step {}: two joints C1, C2", rec.step);
            cs.sort_by(|a, b| b.point.y.total_cmp(&a.point.y)); // C1 (y = +H) first
            for (c, p, name) in [(cs[0], p1, "P1"), (cs[1], p2, "P2")] {
                worst = worst.max((c.normal_force - p).abs());
                assert_eq!(c.state, ContactState::Bonded, "h = {h}, step {}: {name} not bonded", rec.step);
                assert!(
                    (c.normal_force - p).abs() < 1e-5,
                    "h = {h}, step {}: {name} = {} N, expected {p} N",
                    rec.step,
                    c.normal_force
                );
            }
            let moved = (w.bodies[b2].centroid - c0).norm();
            assert!(moved < 1e-9, "h = {h}, step {}: B2 moved by {moved:e} m", rec.step);
            assert!(
                w.bodies[b2].rotation.abs() < 1e-9,
                "h = {h}, step {}: B2 turned by {}",
                rec.step,
                w.bodies[b2].rotation
            );
        });
        eprintln!("7.8 Table 6, h = {h}: worst |P - exact| = {worst:e} N");
    }
}

#[test]
fn interface_breaks_when_pull_exceeds_strength() {
    let f = 3000.0;
    assert!(f > T, "the pull exceeds the interface's strength t");
    let dt = 0.01;
    let mut world = World::new(pulled(f, 0.0));
    let b2 = body(&world, "B2");
    let mut v_prev = 0.0;
    let mut worst = 0.0f64;
    run(&mut world, 20, |w, rec| {
        let cs = between(w, rec, "B1", "B2");
        let v = w.bodies[b2].velocity[0];
        if rec.step == 1 {
            assert!(!rec.events.is_empty(), "step 1: the interface must break");
            assert_eq!(cs.len(), 2, "step 1: two joints");
            let sum: f64 = cs.iter().map(|c| c.normal_force).sum();
            eprintln!(
                "7.8 break, step 1: P1 = {}, P2 = {}, events {:?}",
                cs[0].normal_force, cs[1].normal_force, rec.events
            );
            assert!(cs.iter().all(|c| c.normal_force.abs() < 1e-9), "step 1: P1 + P2 = {sum} N, expected 0");
            let v1 = f / MASS * dt;
            assert!((v - v1).abs() <= 1e-9 * v1, "step 1: v = {v}, expected {v1}");
        } else {
            assert!(rec.events.is_empty(), "step {}: {:?}", rec.step, rec.events);
            for c in &cs {
                assert_ne!(
                    c.state,
                    ContactState::Bonded,
                    "step {}: a broken joint is bonded again",
                    rec.step
                );
                assert!(
                    c.normal_force >= 0.0,
                    "step {}: tension {} N after breaking",
                    rec.step,
                    c.normal_force
                );
            }
            let dv = f / MASS * dt;
            worst = worst.max(((v - v_prev) - dv).abs() / dv);
            assert!(
                ((v - v_prev) - dv).abs() <= 1e-9 * dv,
                "step {}: dv = {}, expected {dv}",
                rec.step,
                v - v_prev
            );
        }
        v_prev = v;
    });
    eprintln!("7.8 break: worst relative error of the velocity increments from step 2: {worst:e}");
}
