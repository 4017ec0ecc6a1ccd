//! Rows of §7.9 (a particle bouncing on a meshed block) and §7.10 (a particle chain on
//! springs dropped on a big disk): the examples that need meshes and connectors.

use super::{Row, exact, index, row, run, world_from_disk};
use miette::Result;

const UNDULATION: &str = include_str!("../../../examples/7_9_undulation.toml");
const UNDULATION_MESH: &[u8] = include_bytes!("../../../meshes/undulation.msh");
const CHAIN: &str = include_str!("../../../examples/7_10_particle_chain.toml");

/// §7.9: the particle P (x = t, centre height 0.75 + fold(v_y t, 0.25) between the meshed
/// block and the fixed block, exact reflections) for v_y = 1, 2, 3 over 1 s (1 000 steps).
pub(super) fn undulation() -> Result<Vec<Row>> {
    let e = "7.9 particle on a meshed block";
    let mut rows = Vec::new();
    for vy in [1.0f64, 2.0, 3.0] {
        let mut w = world_from_disk(
            "7_9_undulation.toml",
            UNDULATION,
            &[("meshes/undulation.msh", UNDULATION_MESH)],
            &[("body.P.velocity", format!("[1.0, {vy}]"))],
        )?;
        let p = index(&w, "P")?;
        let speed = (1.0 + vy * vy).sqrt();
        let (mut path, mut drift, mut hits, mut last_vy) = (0.0f64, 0.0f64, 0usize, vy);
        run(&mut w, 1000, |w, _| {
            let b = &w.bodies[p];
            let t = w.time;
            path = path.max((b.centroid.x - t).hypot(b.centroid.y - 0.75 - exact::fold(vy * t, 0.25)));
            let v = b.velocity;
            drift = drift.max((v[0].hypot(v[1]) - speed).abs() / speed);
            hits += usize::from(v[1] * last_vy < 0.0);
            last_vy = v[1];
        })?;
        let why = "Figure only; 1e-5 m: exact reflections on a stiff mesh (E = 1e17)";
        rows.push(
            row(e, format!("max |centre - triangle wave|, v_y = {vy} [m]"), None, 0.0, path).tol(1e-5, why),
        );
        let why = "Figure only; 1e-6: an impact leaves ~4e-8 of the energy in the mesh";
        rows.push(row(e, format!("max relative speed change, v_y = {vy}"), None, 0.0, drift).tol(1e-6, why));
        let why = "Figure only; exact count 2 v_y in 1 s";
        rows.push(
            row(e, format!("wall impacts in 1 s, v_y = {vy}"), None, 2.0 * vy, hits as f64).tol(0.0, why),
        );
    }
    Ok(rows)
}

/// §7.10: the chain's underside starts H = 3 m above the big disk (R = 8 m): its middle disk
/// p5 first presses on it in step ceil(sqrt(2H/g)/dt) = 155 (the paper's CS = 155); the
/// kinetic energy never exceeds the potential energy released (the scheme only dissipates);
/// after 15 s (3 000 steps) p5 rests on the big disk, its centre R + r = 10 m from the disk's.
pub(super) fn chain() -> Result<Vec<Row>> {
    let e = "7.10 particle chain";
    let mut w = world_from_disk("7_10_particle_chain.toml", CHAIN, &[], &[])?;
    let (base, p5, g, dt) = (index(&w, "base")?, index(&w, "p5")?, 10.0, w.dt());
    let y0: Vec<f64> = w.bodies.iter().map(|b| b.centroid.y).collect();
    let (mut first, mut excess, mut scale) = (None, 0.0f64, 0.0f64);
    run(&mut w, 3000, |w, rec| {
        let touching =
            rec.contacts.iter().any(|c| (c.body_a == base || c.body_b == base) && c.normal_force > 0.0);
        if touching && first.is_none() {
            first = Some(rec.step);
        }
        let released: f64 = w
            .bodies
            .iter()
            .zip(&y0)
            .filter(|(b, _)| !b.fixed)
            .map(|(b, y)| b.mass * g * (y - b.centroid.y))
            .sum();
        excess = excess.max(rec.kinetic_energy - released);
        scale = scale.max(released.abs());
    })?;
    let touch = ((2.0 * 3.0 / g).sqrt() / dt).ceil();
    let first = first.map_or(f64::NAN, |s| s as f64);
    let why = "§7.10 text: CS = 155; exact count ceil(sqrt(2H/g)/dt)";
    let why_e = "bound: kinetic energy <= energy released; 1e-9 of it for round-off";
    let why_p = "Figure 41 only; 1 cm: the chain still rocks slightly after 15 s";
    Ok(vec![
        row(e, "first step pressing on the big disk".into(), Some(155.0), touch, first).tol(0.0, why),
        row(e, "max (kinetic energy - energy released) [J]".into(), None, 0.0, excess.max(0.0))
            .tol(1e-9 * scale + 1e-9, why_e),
        row(e, "p5 centre to disk centre after 15 s [m]".into(), None, 10.0, w.bodies[p5].centroid.norm())
            .tol(1e-2, why_p),
    ])
}
