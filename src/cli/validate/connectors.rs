//! Rows of the connectors (math note §6), each against a closed form: a bolt holding a block on
//! a frictional incline at limit equilibrium, the period of a block hanging on a spring
//! (`examples/connector_spring.toml`) and a beam cantilever (`examples/connector_beam.toml`)
//! against Timoshenko's tip deflection and rotation.

use super::{Row, exact, index, row, run, scene_world};
use miette::Result;

const SPRING: &str = include_str!("../../../examples/connector_spring.toml");
const BEAM: &str = include_str!("../../../examples/connector_beam.toml");

/// Slope angle θ, friction μ and bolt angle β below the up-slope direction of the incline.
const INCLINE: (f64, f64, f64) = (30.0, 0.3, 20.0);

/// The incline scene: a fixed slope of θ = 30°, friction μ = 0.3 (< tan θ: unbolted, the block
/// slides), a 1 m × 1 m block of density 2000 (W = 19 620 N per metre, g = 9.81) held by a bolt
/// (E A = 1e8 N) from its centre 2 m into the slope at β = 20° below the up-slope direction;
/// static analysis (`velocity_carry = 0`), dt = 0.01 s.
fn incline() -> String {
    let (t, mu, b) = (INCLINE.0.to_radians(), INCLINE.1, INCLINE.2.to_radians());
    let (s, n) = ((t.cos(), t.sin()), (-t.sin(), t.cos()));
    let at = |u: f64, v: f64| (u * s.0 + v * n.0, u * s.1 + v * n.1);
    let corners = [at(5.0, 0.0), at(6.0, 0.0), at(6.0, 1.0), at(5.0, 1.0)];
    let centre = at(5.5, 0.5);
    let l = (b.cos() * s.0 - b.sin() * n.0, b.cos() * s.1 - b.sin() * n.1);
    let anchor = (centre.0 + 2.0 * l.0, centre.1 + 2.0 * l.1);
    let top = at(20.0, 0.0);
    let points = |c: &[(f64, f64)]| {
        c.iter().map(|(x, y)| format!("[{x:.17}, {y:.17}]")).collect::<Vec<_>>().join(", ")
    };
    format!(
        "[scene]\nname = \"bolted block on an incline\"\n[time]\nstep = 0.01\nsteps = 100\n\
         [physics]\ngravity = [0.0, -9.81]\nvelocity_carry = 0.0\n\
         [[material]]\nname = \"rock\"\ndensity = 2000.0\n[[interface]]\nfriction = {mu}\n\
         [[body]]\nname = \"slope\"\nshape = \"polygon\"\nvertices = [[0.0, -5.0], [{tx:.17}, -5.0], {top}, [0.0, 0.0]]\n\
         material = \"rock\"\nfixed = true\n\
         [[body]]\nname = \"block\"\nshape = \"polygon\"\nvertices = [{block}]\nmaterial = \"rock\"\n\
         [[connector]]\nkind = \"bolt\"\npoints = [{bolt}]\nbodies = [\"block\", \"slope\"]\n\
         young = 2.0e11\narea = 5.0e-4\n",
        tx = top.0,
        top = points(&[top]),
        block = points(&corners),
        bolt = points(&[centre, anchor]),
    )
}

/// The bolted block: the block slides until the bolt holds it, so friction is fully mobilized
/// and the bolt carries the limit-equilibrium force. Static relaxation at dt = 0.01: the mass
/// term 2m/dt² = 4e7 N/m against the bolt's EA/l = 5e7 N/m shrinks the out-of-balance by 0.44
/// per step; 100 steps leave 1e-36 of it.
pub(super) fn bolted_block() -> Result<Vec<Row>> {
    let mut w = scene_world("bolted_incline.toml", &incline(), &[])?;
    run(&mut w, 100, |_, _| {})?;
    let (t, mu, b) = (INCLINE.0.to_radians(), INCLINE.1, INCLINE.2.to_radians());
    let exact = exact::bolt_limit_force(2000.0 * 9.81, t, mu, b);
    let force = w.connectors.first().map_or(f64::NAN, |c| c.axial_force());
    let why = "limit equilibrium W (sin θ - μ cos θ)/(cos β + μ sin β); 1e-5 relative: static \
               relaxation leaves 1e-36 after 100 steps, the VI's tolerance the rest";
    Ok(vec![
        row("connector: bolted block", "bolt force on a 30° incline, μ = 0.3 [N]".into(), None, exact, force)
            .tol(1e-5 * exact, why),
    ])
}

/// The hanging block of `connector_spring.toml` (m = 1000 kg/m, k = 1e5 N/m) released with the
/// spring unstretched: its lowest points come at T/2 and 3T/2, T = 2π sqrt(m/k) = 0.6283 s, and
/// the first is 2 m g / k = 0.2 m below the start. 1 000 steps of 1 ms (> 3T/2 = 0.942 s).
pub(super) fn spring() -> Result<Vec<Row>> {
    let mut w = scene_world("connector_spring.toml", SPRING, &[])?;
    let (block, dt) = (index(&w, "block")?, w.dt());
    let y0 = w.bodies[block].centroid.y;
    let (m, k) = (w.bodies[block].mass, 1.0e5);
    let period = exact::spring_period(m, k);
    // the lowest point of each half: before T and after it
    let mut lowest = [(f64::INFINITY, 0.0); 2];
    run(&mut w, 1000, |w, rec| {
        let y = w.bodies[block].centroid.y;
        let half = usize::from(rec.time > period);
        if y < lowest[half].0 {
            lowest[half] = (y, rec.time);
        }
    })?;
    let e = "connector: spring";
    let why_t = "2π sqrt(m/k); one step (1 ms): each lowest point is sampled at a step time, the \
                 scheme's period error O((ω dt)²) = 1e-4 relative is 6e-5 s";
    let why_y = "2 m g/k; 1 mm: the time scheme (Newmark γ = 1) damps the amplitude slightly";
    let g = 10.0;
    Ok(vec![
        row(e, "first lowest point, t = T/2 [s]".into(), None, period / 2.0, lowest[0].1).tol(dt, why_t),
        row(e, "period, between the lowest points [s]".into(), None, period, lowest[1].1 - lowest[0].1)
            .tol(dt, why_t),
        row(e, "first drop below the start [m]".into(), None, 2.0 * m * g / k, y0 - lowest[0].0)
            .tol(1e-3, why_y),
    ])
}

/// The beam cantilever of `connector_beam.toml`: L = 2 m, E = 200 GPa, G = 80 GPa, A = 0.01 m²,
/// I = 8e-6 m⁴, shear factor 1.2, tip load P = 1 kN, static analysis (50 steps of 0.01 s).
pub(super) fn cantilever() -> Result<Vec<Row>> {
    let mut w = scene_world("connector_beam.toml", BEAM, &[])?;
    let tip = index(&w, "tip")?;
    let start = w.bodies[tip].centroid;
    run(&mut w, 50, |_, _| {})?;
    let b = &w.bodies[tip];
    let [deflection, rotation] = exact::timoshenko_tip(2.0e11, 8.0e10, 0.01, 8.0e-6, 1.2, 1000.0, 2.0);
    let e = "connector: beam cantilever";
    let why = "Timoshenko, exact for the 2-node beam; 1e-5 relative: static relaxation and the \
               solver tolerance";
    Ok(vec![
        row(e, "tip deflection [m]".into(), None, deflection, start.y - b.centroid.y)
            .tol(1e-5 * deflection, why),
        row(e, "tip rotation, clockwise [rad]".into(), None, rotation, -b.rotation).tol(1e-5 * rotation, why),
    ])
}
