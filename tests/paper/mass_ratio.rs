//! Extreme mass ratios (math note §4.9, §10.10): two rigid 1 m × 1 m blocks stacked on a fixed
//! floor (μ = 0.5, g = 10, dt = 0.01, 20 steps), one of density 1e3, the other 1e3·ratio.
//! Statics of two rigid blocks each on two corners is symmetric: every corner under the top block
//! carries half its weight, every floor corner half the weight of both.
//!
//! * Light on heavy, ratio 1e12: the light block's contacts carry 5e3 N next to the floor's
//!   5e15 N. The force part of the residual, relative to ||z||∞, cannot see them (before §4.9
//!   the light block fell through its support in a "converged" step); the gap part must.
//! * Heavy on light: the load path of the heavy block runs through the light one, along which W
//!   has an eigenvalue ratio⁻¹ times its diagonal: a solver working with W resolves the forces
//!   only to about eps·ratio (1e-4 at 1e12; §4.9). The polish of §10.10 corrects the converged
//!   forces with gaps summed body by body in double-double, through B and each body's K̃,
//!   never W.
//!
//! Both orders, every ratio: every corner force of every step within 1e-6 of statics (the
//! issue's acceptance), every step converged and taken whole. What is left at 1e12 (measured
//! 3.3e-7 at worst, 5e-8 at the median) is the resolution of the forces themselves: 5e15 N is
//! held to 1 N, and 1 N more on the light block moves it by dt²/m_l = 1e-7 m, so the gaps, and
//! through the heavy block's compliance its forces, are resolved to about that.

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

/// Light (1e3) on heavy (1e15): measured 1e-15 at worst.
#[test]
fn light_on_heavy_1e12_holds_the_statics() {
    let (top, floor, split) = corner_errors(1e15, 1e3);
    assert!(max(&top) <= 1e-6, "light block corners: worst error {:e}", max(&top));
    assert!(max(&floor) <= 1e-6, "floor corners: worst error {:e}", max(&floor));
    assert_eq!(split, 0, "steps taken as shorter trials");
}

/// Heavy on light at ratios 1e6 … 1e12 (worst errors measured: 0, 1.2e-16, 5.7e-9, 3.3e-7).
#[test]
fn heavy_on_light_holds_the_statics() {
    for ratio in [1e6, 1e8, 1e10, 1e12] {
        let (top, floor, split) = corner_errors(1e3, 1e3 * ratio);
        let all: Vec<f64> = top.iter().chain(&floor).copied().collect();
        assert!(max(&all) <= 1e-6, "ratio {ratio:e}: worst error {:e}", max(&all));
        assert_eq!(split, 0, "ratio {ratio:e}: steps taken as shorter trials");
    }
}
