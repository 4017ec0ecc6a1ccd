//! Closed forms of design note §7 (g = 10 m/s²), of the connector rows (math note §6) and of
//! the meshed cantilever (math note §9.5), shared with the tests.

use std::f64::consts::PI;

/// §7.1: contact forces F1 = G, F2 = 2G, F3 = 3G (top to bottom), G = rho pi R² g.
pub fn heap_forces() -> [f64; 3] {
    let g = 2500.0 * PI * 10.0 * 10.0 * 10.0;
    [g, 2.0 * g, 3.0 * g]
}

/// §7.2: floor reactions of the staircase over the block weight W: F1/W, F2/W.
pub fn staircase_reactions_over_weight() -> [f64; 2] {
    [0.5, 3.5]
}

/// §7.3 and §7.4: the triangle wave, position of a point moving at unit rate `s` in [-a, a]
/// with elastic reflections.
pub fn fold(s: f64, a: f64) -> f64 {
    let sp = (s + a).rem_euclid(4.0 * a);
    if sp < 2.0 * a { sp - a } else { 3.0 * a - sp }
}

/// §7.5: peak normal force 3 m g of the frictionless pendulum (disk R1 = 40, rho = 1).
pub fn pendulum_peak_force() -> f64 {
    3.0 * PI * 40.0 * 40.0 * 10.0
}

/// §7.5: period T = 4 sqrt(L/g) K(1/2), L = 60 (K(1/2) = 1.854 074 677 301 372).
pub fn pendulum_period() -> f64 {
    4.0 * (60.0f64 / 10.0).sqrt() * 1.854_074_677_301_372
}

/// §7.6: rear and front normal forces and total shear of the sliding block: (4600, 5400, -400).
pub fn sliding_block_forces() -> [f64; 3] {
    let (g, f, c, h, l) = (10_000.0, 1000.0, 400.0, 0.7, 1.0);
    // Fn2 - Fn1 = S + (2h/l - 1) F with S = c, Fn1 + Fn2 = G
    let diff = c + (2.0 * h / l - 1.0) * f;
    [(g - diff) / 2.0, (g + diff) / 2.0, -c]
}

/// Mass of the §7.7 disk, R = 1, rho = 1000.
pub fn rolling_disk_mass() -> f64 {
    1000.0 * PI
}

/// §7.7 Table 4, pure rolling: (Fn, Fs) = (G, F (2d - 3R)/(3R)) for the lever d, F = 1000.
pub fn pure_rolling_forces(d: f64) -> [f64; 2] {
    [rolling_disk_mass() * 10.0, 1000.0 * (2.0 * d - 3.0) / 3.0]
}

/// §7.7 Table 5: rolling couple M_r = F d holding the disk.
pub fn rolling_couple(d: f64) -> f64 {
    1000.0 * d
}

/// §7.7 trajectories at t = 5 s, d = R = 1: x_O of case I (pure rolling, a = 2F/(3m)) and
/// case III (sliding with mu = 0.005, a = (F - mu G)/m).
pub fn trajectory_x(case_iii: bool) -> f64 {
    let m = rolling_disk_mass();
    let a = if case_iii { (1000.0 - 0.005 * m * 10.0) / m } else { 2.0 * 1000.0 / (3.0 * m) };
    0.5 * a * 25.0
}

/// §7.8 Table 6: signed joint forces P1 = -F (H + h)/(2H), P2 = -F (H - h)/(2H), F = 1000,
/// H = 1.
pub fn cemented_tensions(h: f64) -> [f64; 2] {
    [-1000.0 * (1.0 + h) / 2.0, -1000.0 * (1.0 - h) / 2.0]
}

/// A bolt holding a block of weight `w` on a frictional incline θ (friction μ), at the angle β
/// between the bolt and the up-slope direction, once the block has slid onto it (friction fully
/// mobilized): F = W (sin θ − μ cos θ)/(cos β + μ sin β) (math note §6).
pub fn bolt_limit_force(w: f64, theta: f64, mu: f64, beta: f64) -> f64 {
    w * (theta.sin() - mu * theta.cos()) / (beta.cos() + mu * beta.sin())
}

/// Period 2π sqrt(m/k) of a mass `m` on a spring of stiffness `k`.
pub fn spring_period(m: f64, k: f64) -> f64 {
    2.0 * PI * (m / k).sqrt()
}

/// Tip deflection and rotation of a Timoshenko cantilever of length `l` under a tip load `p`:
/// `p l³/(3 E I) + κ p l/(G A)` and `p l²/(2 E I)` (κ the shear factor; exact for the 2-node
/// beam element, math note §6).
pub fn timoshenko_tip(e: f64, g: f64, area: f64, inertia: f64, kappa: f64, p: f64, l: f64) -> [f64; 2] {
    [p * l.powi(3) / (3.0 * e * inertia) + kappa * p * l / (g * area), p * l * l / (2.0 * e * inertia)]
}

/// The meshed cantilever of `examples/mesh_cantilever.toml` (L = 10, h = 1, E = 1e7, ν = 0.3,
/// P = 1, plane stress) by beam theory: P L³/(3EI) + P L/(κ G A), κ = 5/6, downward (math note
/// §9.5): -4.031e-4 m.
pub fn mesh_cantilever_tip() -> f64 {
    let (e, nu, l, h, p) = (1.0e7f64, 0.3, 10.0f64, 1.0f64, 1.0);
    let (i, g, kappa) = (h.powi(3) / 12.0, e / (2.0 * (1.0 + nu)), 5.0 / 6.0);
    -(p * l.powi(3) / (3.0 * e * i) + p * l / (kappa * g * h))
}
