//! A yielding bolt in a pull test (math note §6.1), against the closed form of the step.
//!
//! One fixed block and one free rigid block of mass m, joined by a bolt of rest length L along x
//! from the fixed block to the free block's centroid, pulled along x at its centroid by
//! F(t) = F1 t/T1 (a `[[load]]` history). No gravity, no contact (a 1 m gap that only opens),
//! static relaxation (`velocity_carry = 0`: v0 = 0 at every step). Everything acts along x
//! through the centroid, so the only moving DOF is u, and one step of the scheme (math note eq.
//! 1.2, §6, §10.7, §6.1) is, with M' = 2m/dt², l_n the bolt's length at the step start, N_n its
//! force, ε_p its plastic strain and t_{n+1} the step's end:
//! - elastic:   (M' + EA/l_n) d = F(t_{n+1}) − N_n;
//! - yielding:  M' d = F(t_{n+1}) − Y (the bolt is the constant force Y, no axial stiffness);
//! - then l_{n+1} = l_n + d, ε = (l_{n+1} − L)/L, N = EA (ε − ε_p), and at N ≥ Y: ε_p = ε − Y/EA,
//!   N = Y.
//!
//! The bolt yields in a step whose elastic trial force passes Y and stays yielding while its
//! trial stays at or above Y (the active set of §6.1); it breaks in the first step whose total
//! strain passes ε_u. The test steps this recursion beside the engine and checks, each to 1e-9
//! relative (the recursion and the engine do the same few floating-point operations per step,
//! so they agree to round-off, 1e-13 here):
//! - the displacement at every step equals the recursion's;
//! - while intact and not yielding, N = (EA/L)(l − L): the bolt's force rises at EA/L times the
//!   elongation;
//! - yielding, N = Y and ε_p = ε − Y/EA;
//! - the break step is the recursion's, the first with ε > ε_u, and the force it broke at is Y;
//! - unloaded from the plastic state the bolt is elastic, N = EA (ε − ε_p) with ε_p frozen, and
//!   at F = 0 it rests at l = L (1 + ε_p) (static relaxation converges by (M'/(M' + EA/l))^n,
//!   below 1e-40 after the steps run here).

use pbdda::scene::parse;
use pbdda::world::{Event, World};

use crate::common::scenes::pull::{AREA, DT, E, L, RHO, Y, scene};

const TOL: f64 = 1e-9;

/// The recursion of the module header: state (l, N, ε_p, yielding, broken).
#[derive(Clone, Copy, Debug)]
struct Bolt {
    l: f64,
    n: f64,
    ep: f64,
    plastic: bool,
    broken: bool,
}

impl Bolt {
    fn step(&mut self, f: f64, ultimate: Option<f64>) -> bool {
        let m2 = 2.0 * RHO / (DT * DT);
        let ea = E * AREA;
        let trial = |plastic: bool, b: &Bolt| {
            let d = if b.broken {
                f / m2
            } else if plastic {
                (f - Y) / m2
            } else {
                (f - b.n) / (m2 + ea / b.l)
            };
            (d, ea * ((b.l + d - L) / L - b.ep))
        };
        // the active set, as the engine switches it (at most 8 rounds)
        let mut plastic = self.plastic;
        for _ in 0..8 {
            let (_, n) = trial(plastic, self);
            match plastic {
                false if n > Y => plastic = true,
                true if n < Y => plastic = false,
                _ => break,
            }
        }
        let (d, _) = trial(plastic, self);
        if !self.broken && ultimate.is_some_and(|u| (self.l + d - L) / L > u) {
            self.broken = true;
            // the step is solved again without the bolt; it broke in this step either way
            self.step(f, ultimate);
            return true;
        }
        self.l += d;
        if !self.broken {
            let n = ea * ((self.l - L) / L - self.ep);
            if n >= Y {
                self.ep += (n - Y) / ea;
                (self.n, self.plastic) = (Y, true);
            } else {
                (self.n, self.plastic) = (n, false);
            }
        }
        false
    }
}

fn close(a: f64, b: f64, scale: f64, what: &str, step: usize) {
    assert!((a - b).abs() <= TOL * scale, "step {step}: {what} = {a}, expected {b} (diff {:e})", a - b);
}

/// Runs the scene beside the recursion; returns (the recursion's final state, steps yielding,
/// the break step).
fn pull(
    history: &str,
    load: impl Fn(f64) -> f64,
    ultimate: Option<f64>,
    steps: usize,
) -> (Bolt, usize, Option<usize>) {
    let mut w =
        World::new(parse(&scene(history, ultimate, steps), "pull.toml").unwrap_or_else(|e| panic!("{e:?}")));
    let mut b = Bolt { l: L, n: 0.0, ep: 0.0, plastic: false, broken: false };
    let (mut yielding, mut broke) = (0, None);
    let x0 = w.bodies[1].centroid.x;
    for s in 1..=steps {
        let rec = w.step().expect("step");
        let was_broken = b.broken;
        b.step(load(s as f64 * DT), ultimate);
        let c = &w.connectors[0];
        let x = w.bodies[1].centroid.x;
        close(x - x0, b.l - L, L, "displacement", s);
        if b.broken {
            assert!(c.broken, "step {s}: the recursion broke, the engine's bolt did not");
            if !was_broken {
                broke = Some(s);
                let force = rec.events.iter().find_map(|e| match e {
                    Event::ConnectorBroke { force, .. } => Some(*force),
                    _ => None,
                });
                close(force.expect("a break event"), Y, Y, "force at break", s);
                assert_eq!(c.broke_with, force);
            }
            continue;
        }
        assert!(!c.broken, "step {s}: broke early");
        let strain = c.strain().expect("a bolt");
        close(c.length(), b.l, L, "length", s);
        assert_eq!(c.is_yielding(), b.plastic, "step {s}: yielding");
        if c.is_yielding() {
            yielding += 1;
            close(c.axial_force(), Y, Y, "yielding force", s);
            close(c.plastic_strain, strain - Y / (E * AREA), 1e-2, "plastic strain", s);
        } else {
            close(c.axial_force(), E * AREA * (strain - c.plastic_strain), Y, "elastic force", s);
        }
        if c.plastic_strain == 0.0 {
            close(c.axial_force(), E * AREA / L * (c.length() - L), Y, "force = EA/L elongation", s);
        }
    }
    (b, yielding, broke)
}

/// F = 2e4 N t/1 s: elastic, yielding, broken at ε_u = 0.05.
#[test]
fn a_pulled_bolt_rises_at_ea_over_l_plateaus_at_its_yield_force_and_breaks_at_its_ultimate_strain() {
    let (b, yielding, broke) = pull("[[0.0, 0.0], [1.0, 2.0e4]]", |t| 2.0e4 * t, Some(0.05), 100);
    assert!(yielding > 5, "a plateau of several steps (got {yielding})");
    let broke = broke.expect("it breaks");
    assert!(b.broken && broke < 100);
}

/// F up to 1.5 Y and back to 0: the bolt yields, then unloads elastically from its plastic strain
/// and rests at l = L (1 + ε_p).
#[test]
fn an_unloaded_yielded_bolt_rests_at_its_plastic_elongation() {
    let load = |t: f64| if t <= 0.5 { 3.0e4 * t } else { (1.5e4 - 3.0e4 * (t - 0.5)).max(0.0) };
    let (b, yielding, broke) = pull("[[0.0, 0.0], [0.5, 1.5e4], [1.0, 0.0]]", load, None, 200);
    assert!(yielding > 5 && broke.is_none());
    assert!(b.ep > 0.0);
    close(b.l, L * (1.0 + b.ep), L, "rest length after unloading", 200);
}

/// connectors.csv with `[output] every` far beyond the run: the row of the step the bolt starts
/// to yield in (state `yielding`, force Y, its plastic strain) and of the step it breaks in
/// (state `broken`, the force it broke at, Y) are written all the same, and nothing else (the
/// last step's row would list intact connectors only). The steps are the recursion's.
#[test]
fn the_steps_a_bolt_yields_and_breaks_in_are_always_written() {
    let steps = 100;
    let (mut b, mut yielded, mut broke) =
        (Bolt { l: L, n: 0.0, ep: 0.0, plastic: false, broken: false }, None, None);
    for s in 1..=steps {
        let was = b;
        b.step(2.0e4 * s as f64 * DT, Some(0.05));
        if b.plastic && !was.plastic && yielded.is_none() {
            yielded = Some(s);
        }
        if b.broken && !was.broken {
            broke = Some(s);
        }
    }
    let (yielded, broke) = (yielded.expect("yields"), broke.expect("breaks"));
    let dir = std::env::temp_dir().join(format!("pbdda-bolt-yield-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    let text =
        scene("[[0.0, 0.0], [1.0, 2.0e4]]", Some(0.05), steps) + "[output]\nevery = 1000\nvtk = false\n";
    let path = dir.join("pull.toml");
    std::fs::write(&path, text).expect("scene");
    let out = dir.join("out");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_pbdda"))
        .args(["run", path.to_str().unwrap(), "--out", out.to_str().unwrap(), "-q"])
        .output()
        .expect("the binary runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = std::fs::read_to_string(out.join("connectors.csv")).expect("connectors.csv");
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some(
            "step,time,connector,kind,body_a,body_b,length,axial_force,shear_force,moment_a,moment_b,state,plastic_strain,anchor_a_x,anchor_a_y,anchor_b_x,anchor_b_y"
        )
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 2, "{csv}");
    let num = |s: &str| s.parse::<f64>().expect("a number");
    assert_eq!((num(rows[0][0]) as usize, rows[0][11]), (yielded, "yielding"));
    assert_eq!((num(rows[1][0]) as usize, rows[1][11]), (broke, "broken"));
    for r in &rows {
        close(num(r[7]), Y, Y, "axial_force", num(r[0]) as usize);
    }
    assert!(num(rows[0][12]) >= 0.0);
    let _ = std::fs::remove_dir_all(&dir);
}
