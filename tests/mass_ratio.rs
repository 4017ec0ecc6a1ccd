//! Extreme mass ratios (math note §4.9): two rigid 1 m × 1 m blocks stacked on a fixed floor
//! (μ = 0.5, g = 10, dt = 0.01, 20 steps), one of density 1e3, the other 1e3·ratio. Statics of
//! two rigid blocks each on two corners is symmetric: every corner under the top block carries
//! half its weight, every floor corner half the weight of both.
//!
//! * Light on heavy, ratio 1e12: the light block's contacts carry 5e3 N next to the floor's
//!   5e15 N. The force part of the residual, relative to ||z||∞, cannot see them (before §4.9
//!   the light block fell through its support in a "converged" step); the gap part must.
//! * Heavy on light: the load path of the heavy block runs through the light one, along which W
//!   has an eigenvalue ratio⁻¹ times its diagonal. The forces there are only *resolvable* to
//!   about eps·ratio relative (the light block moves by the difference of two forces of size
//!   m_h g, which a double holds to eps·m_h g; §4.9 derives it), so the test asserts the
//!   statics within 1e-6 where 4·eps·ratio allows it (ratios 1e6 and 1e8) and, for every
//!   ratio, a median error within 4·eps·ratio; all steps must converge without a halving
//!   failure (before §4.9 the divergence test, scaled by D⁻¹q ~ m_l g, stopped the solver on the
//!   first step for any ratio above ~2e4).

use pbdda::world::{StepRecord, World};

fn stack(lower: f64, upper: f64) -> World {
    let text = format!(
        "[scene]\nname = \"stack\"\n[time]\nstep = 0.01\nsteps = 20\n[physics]\ngravity = [0.0, -10.0]\n\
        [[material]]\nname = \"lower\"\ndensity = {lower:e}\nyoung = 1.0e9\npoisson = 0.25\n\
        [[material]]\nname = \"upper\"\ndensity = {upper:e}\nyoung = 1.0e9\npoisson = 0.25\n\
        [[interface]]\nfriction = 0.5\n\
        [[body]]\nname = \"floor\"\nshape = \"polygon\"\nvertices = [[-2.0, -1.0], [3.0, -1.0], [3.0, 0.0], [-2.0, 0.0]]\n\
        material = \"lower\"\nfixed = true\n\
        [[body]]\nname = \"lower\"\nshape = \"polygon\"\nvertices = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]\n\
        material = \"lower\"\n\
        [[body]]\nname = \"upper\"\nshape = \"polygon\"\nvertices = [[0.0, 1.0], [1.0, 1.0], [1.0, 2.0], [0.0, 2.0]]\n\
        material = \"upper\"\n"
    );
    World::new(pbdda::scene::parse(&text, "stack.toml").unwrap_or_else(|e| panic!("{e}")))
}

/// Relative errors of every corner force of 20 steps against statics (top, floor), and the
/// number of steps taken as shorter trials; panics on a failed step or one that did not converge.
fn corner_errors(lower: f64, upper: f64) -> (Vec<f64>, Vec<f64>, usize) {
    let mut world = stack(lower, upper);
    let floor = world.bodies.iter().position(|b| b.name == "floor").expect("floor");
    let (m_low, m_up) = (world.bodies[floor + 1].mass, world.bodies[floor + 2].mass);
    let (top, bottom) = (m_up * 10.0 / 2.0, (m_low + m_up) * 10.0 / 2.0);
    let (mut e_top, mut e_floor, mut split) = (Vec::new(), Vec::new(), 0);
    for _ in 0..20 {
        let rec: StepRecord = world.step().unwrap_or_else(|e| panic!("{e}"));
        split += usize::from(rec.dt < 0.01);
        assert!(rec.converged, "step {} did not converge: {rec:?}", rec.step);
        assert_eq!(rec.contacts.len(), 4, "step {}: {:?}", rec.step, rec.contacts);
        for c in &rec.contacts {
            if c.body_a == floor || c.body_b == floor {
                e_floor.push((c.normal_force - bottom).abs() / bottom);
            } else {
                e_top.push((c.normal_force - top).abs() / top);
            }
        }
    }
    (e_top, e_floor, split)
}

fn max(v: &[f64]) -> f64 {
    v.iter().copied().fold(0.0, f64::max)
}

fn median(v: &[f64]) -> f64 {
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Light (1e3) on heavy (1e15). The gap part of the residual asks each row for its gap to
/// tolerance · L = 1e-6 · 1 m (L the smallest edge); the light block's compliance is
/// dt²/m = 1e-7 m/N, so its corner forces are guaranteed to 10 N of 5 000 N (2e-3); the floor
/// corners, well conditioned, to the force part's 1e-6 of ‖z‖∞. Each of the 20 steps is taken
/// whole (no halving).
#[test]
fn light_on_heavy_1e12_holds_the_statics() {
    let (top, floor, split) = corner_errors(1e15, 1e3);
    assert!(max(&top) <= 2e-3, "light block corners: worst error {:e}", max(&top));
    assert!(max(&floor) <= 1e-6, "floor corners: worst error {:e}", max(&floor));
    assert_eq!(split, 0, "steps taken as shorter trials");
}

/// Heavy on light at ratios 1e6 … 1e12: see the module header for the resolution eps·ratio.
#[test]
fn heavy_on_light_within_the_resolution_of_doubles() {
    for ratio in [1e6, 1e8, 1e10, 1e12] {
        let (top, floor, _) = corner_errors(1e3, 1e3 * ratio);
        let all: Vec<f64> = top.iter().chain(&floor).copied().collect();
        let resolution = f64::EPSILON * ratio;
        assert!(median(&all) <= 4.0 * resolution, "ratio {ratio:e}: median error {:e}", median(&all));
        if 4.0 * resolution <= 1e-6 {
            assert!(max(&all) <= 1e-6, "ratio {ratio:e}: worst error {:e}", max(&all));
        }
    }
}
