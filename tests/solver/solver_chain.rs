//! The solver chain (math note §4.17): `[solver] method` names a list of methods, each runs in
//! turn until one answers, `steps.csv`'s `method` names the one that answered and `run.log`
//! lists the hand-overs; one budget, `[solver] max_iterations`, bounds the whole step.
//!
//! The scene: a rigid 1 m × 1 m block of density 1e3 resting on a fixed floor (g = 10, μ = 0.5,
//! dt = 0.01). Its statics is symmetric: each of its two corner contacts carries half its weight,
//! 5,000 N (closed form). The solves run at tolerance 1e-6, a scaled residual relative to
//! max(1, |z|max) (§4.3), so a corner force is held to about 1e-6 of the 5,000 N; 1e-5 relative
//! leaves room for the interior-point program's own accuracy (1e-8 gaps, §4.13).

use pbdda::vi::{Chain, Method};
use pbdda::world::{StepRecord, World};
use std::path::PathBuf;
use std::process::Command;

/// Half the block's weight [N]: 1e3 kg/m³ × 1 m² × 10 m/s² / 2.
const CORNER: f64 = 5_000.0;

/// The scene with `[solver]` keys `solver` and the floor's interface keys `interface`.
fn scene(solver: &str, interface: &str) -> String {
    format!(
        "[scene]\nname = \"block\"\n[time]\nstep = 0.01\nsteps = 3\n[physics]\ngravity = [0.0, -10.0]\n\
        [solver]\ntolerance = 1e-6\n{solver}\n\
        [[material]]\nname = \"rock\"\ndensity = 1.0e3\nyoung = 1.0e9\npoisson = 0.25\n\
        [[interface]]\nfriction = 0.5\n{interface}\n\
        [[body]]\nname = \"floor\"\nshape = \"polygon\"\nvertices = [[-2.0, -1.0], [3.0, -1.0], [3.0, 0.0], [-2.0, 0.0]]\n\
        material = \"rock\"\nfixed = true\n\
        [[body]]\nname = \"block\"\nshape = \"polygon\"\nvertices = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]\n\
        material = \"rock\"\n"
    )
}

fn world(text: &str) -> World {
    World::new(pbdda::scene::parse(text, "block.toml").unwrap_or_else(|e| panic!("{e}")))
}

/// The step's two corner forces' largest error relative to [`CORNER`].
fn corner_error(rec: &StepRecord) -> f64 {
    assert_eq!(rec.contacts.len(), 2, "step {}: {:?}", rec.step, rec.contacts);
    rec.contacts.iter().map(|c| (c.normal_force - CORNER).abs() / CORNER).fold(0.0, f64::max)
}

/// Each method alone (`method = ["pc"]`, ...) answers every step of its chain: the record names
/// it, no method handed over, and the corners carry half the weight each (1e-5, header).
#[test]
fn each_method_answers_a_step_of_its_own() {
    for (name, method) in Method::ALL {
        let mut w = world(&scene(&format!("method = [\"{name}\"]"), ""));
        assert_eq!(w.model.solver.method.methods(), &[method]);
        for _ in 0..3 {
            let rec = w.step().unwrap_or_else(|e| panic!("{name}: {e}"));
            assert!(rec.converged, "{name}, step {}: {rec:?}", rec.step);
            assert_eq!(rec.method, Some(method), "{name}, step {}", rec.step);
            assert!(rec.handovers.is_empty(), "{name}: {:?}", rec.handovers);
            let err = corner_error(&rec);
            assert!(err <= 1e-5, "{name}, step {}: corner force error {err:e}", rec.step);
        }
    }
}

/// A cemented floor (`tensile_strength` > 0) gives the contacts a tension, which Lemke's method
/// and the cell program do not take (math note §4.12): in the chain ["lemke", "cell", "pc"] both
/// run, give no answer and hand over, and PC answers. Through the command line: `steps.csv`'s
/// `method` is "pc" on every step, `run.log` has the two hand-overs of step 1's first solve, and
/// the cement carries nothing in this statics (the block only presses), so the corners carry
/// half the weight each (1e-5, header).
#[test]
fn a_chain_hands_over_to_the_method_that_answers() {
    let dir = std::env::temp_dir().join(format!("pbdda-chain-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("block.toml");
    let text = scene("method = [\"lemke\", \"cell\", \"pc\"]", "tensile_strength = 1.0e5");
    std::fs::write(&path, &text).expect("write");
    let out: PathBuf = dir.join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_pbdda"))
        .args(["run", path.to_str().unwrap(), "--out", out.to_str().unwrap(), "--quiet"])
        .output()
        .expect("the binary runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let steps = std::fs::read_to_string(out.join("steps.csv")).expect("steps.csv");
    let mut lines = steps.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    let col = header.iter().position(|c| *c == "method").expect("a method column");
    let methods: Vec<String> = lines.map(|l| l.split(',').nth(col).unwrap_or("").to_string()).collect();
    assert_eq!(methods, vec!["pc"; 3]);
    let log = std::fs::read_to_string(out.join("run.log")).expect("run.log");
    for line in [
        "hand-over: step 1 (solve 1): lemke handed over to cell (no answer)",
        "hand-over: step 1 (solve 1): cell handed over to pc (no answer)",
    ] {
        assert!(log.contains(line), "missing `{line}` in:\n{log}");
    }
    let mut w = world(&text);
    let rec = w.step().unwrap_or_else(|e| panic!("{e}"));
    let first: Vec<(Method, Method, &str)> =
        rec.handovers.iter().take(2).map(|h| (h.from, h.to, h.why)).collect();
    assert_eq!(first, [(Method::Lemke, Method::Cell, "no answer"), (Method::Cell, Method::Pc, "no answer")]);
    assert_eq!(rec.method, Some(Method::Pc));
    assert!(corner_error(&rec) <= 1e-5, "corner force error {:e}", corner_error(&rec));
    std::fs::remove_dir_all(&dir).expect("cleanup");
}

/// The budget bounds the whole step (math note §4.17): with `max_iterations = 1` the default
/// chain's first method, MPRGP, gets the one unit (NSGS's half of nothing is nothing), and every
/// later solve of the step (refinements, the cold step's continuation, solve 2) gets what is
/// left, none: the step spends exactly 1, whether or not the one iteration converged.
/// `adaptive = false` keeps the step one trial.
#[test]
fn one_budget_bounds_the_step() {
    let text = scene("max_iterations = 1\nallow_unconverged = true", "")
        .replace("steps = 3\n", "steps = 3\nadaptive = false\n");
    let mut w = world(&text);
    assert_eq!(w.model.solver.method, Chain::named(Method::Mprgp));
    let rec = w.step().unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((rec.inner_iterations, rec.method), (1, Some(Method::Mprgp)), "{rec:?}");
}

/// The chains a single name stands for (docs/scene-format.md's table).
#[test]
fn names_stand_for_their_chains() {
    use Method::*;
    let m = |text: &str| world(&scene(text, "")).model.solver.method;
    assert_eq!(m("").methods(), &[Mprgp, Nsgs, Lemke, Cell, Pc]);
    assert_eq!(m("method = \"auto\"").methods(), &[Mprgp, Nsgs, Lemke, Cell, Pc]);
    assert_eq!(m("method = \"nsgs\"").methods(), &[Nsgs, Lemke, Cell, Pc]);
    assert_eq!(m("method = \"newton\"").methods(), &[Newton, Mprgp, Nsgs, Lemke, Cell, Pc]);
    assert_eq!(m("method = \"pc\"").methods(), &[Pc]);
    assert_eq!(m("method = [\"newton\", \"pc\"]").methods(), &[Newton, Pc]);
}
