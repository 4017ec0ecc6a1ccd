//! Paper §7.6, Table 3: rigid unit block (G = 10 000 N) on a fixed base, pulled by F = 1000 N at
//! 0.7 m height, mu = 0, joint cohesion c = 400 N. Closed form (math note §7.6): it slides
//! with a = (F - c)/m = 0.6 m/s², Fn1 = 4600 (rear), Fn2 = 5400 (front), Fs1 + Fs2 = -400.
//! Without cohesion sharing (DDA-d) each contact gets all of c and the forces become
//! 4400 / 5600 / -800 (the paper's DDA-d column). Tolerance 1e-5 N (2e-9 relative): the
//! forces follow from statics and Newton's law, which the scheme meets exactly under constant
//! forces (math note §1.1), so the only error is the solver's, tol |z| = 1e-12 · 5400 N ~ 5e-9 N.

use crate::common;
use common::*;
use pbdda::world::{Settings, World};

fn forces(settings: Settings) -> Vec<(f64, f64, f64, f64)> {
    let mut world = World::with_settings(example("7_6_sliding_block_cohesion.toml"), settings);
    let block = body(&world, "block");
    let x0 = world.bodies[block].centroid.x;
    let mut out = Vec::new();
    run(&mut world, 20, |w, rec| {
        let mut cs = between(w, rec, "base", "block");
        assert_eq!(cs.len(), 2, "step {}: two adjoint contacts", rec.step);
        cs.sort_by(|a, b| a.point.x.total_cmp(&b.point.x));
        let shift = w.bodies[block].centroid.x - x0;
        out.push((cs[0].normal_force, cs[1].normal_force, cs[0].shear_force + cs[1].shear_force, shift));
    });
    out
}

#[test]
fn shared_cohesion_gives_table_3() {
    let dt = 0.01;
    for (i, (fn1, fn2, fs, shift)) in forces(Settings::default()).into_iter().enumerate() {
        let t = (i + 1) as f64 * dt;
        assert!((fn1 - 4600.0).abs() < 1e-5, "step {}: Fn1 = {fn1}", i + 1);
        assert!((fn2 - 5400.0).abs() < 1e-5, "step {}: Fn2 = {fn2}", i + 1);
        assert!((fs + 400.0).abs() < 1e-5, "step {}: Fs1 + Fs2 = {fs}", i + 1);
        // constant acceleration 0.6 m/s²: exact parabola of the Newmark scheme (math note §1.1)
        assert!((shift - 0.3 * t * t).abs() < 1e-9, "step {}: x = {shift}", i + 1);
    }
}

#[test]
fn unshared_cohesion_reproduces_dda_d_over_resistance() {
    let settings = Settings { share_cohesion: false, ..Settings::default() };
    for (i, (fn1, fn2, fs, _)) in forces(settings).into_iter().enumerate() {
        assert!((fn1 - 4400.0).abs() < 1e-5, "step {}: Fn1 = {fn1}", i + 1);
        assert!((fn2 - 5600.0).abs() < 1e-5, "step {}: Fn2 = {fn2}", i + 1);
        assert!((fs + 800.0).abs() < 1e-5, "step {}: Fs1 + Fs2 = {fs}", i + 1);
    }
}
