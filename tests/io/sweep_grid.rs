//! `pbdda sweep` grids and wildcards (src/cli/sweep/, src/scene/overrides.rs).

use crate::common::one_line;
use pbdda::cli::{Axis, SweepOptions, sweep};
use pbdda::scene::{Override, parse_with};
use std::path::Path;

fn scene(name: &str) -> (String, String) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples").join(name);
    (std::fs::read_to_string(&path).expect("example"), path.display().to_string())
}

fn axis(key: &str, values: &[&str]) -> Axis {
    Axis { key: key.into(), values: values.iter().map(|v| v.to_string()).collect() }
}

fn quiet() -> SweepOptions {
    SweepOptions { quiet: true, ..Default::default() }
}

/// A grid of two keys, 2 x 3 values, is their 6 combinations, the first key slowest (the
/// grid's definition). Each case runs its own `time.steps` (the value it was given), and a
/// grid of two keys has no size, so no reference, errors or orders.
#[test]
fn grid_of_two_keys_runs_every_combination() {
    let (text, file) = scene("7_1_disk_heap.toml");
    let axes = [axis("solver.method", &["pc", "mprgp"]), axis("time.steps", &["1", "2", "3"])];
    let report = sweep(&text, &file, &[], &axes, &quiet()).unwrap_or_else(|e| panic!("{e:?}"));
    eprintln!("{}", report.table());
    assert_eq!(report.rows.len(), 6);
    let mut expected = Vec::new();
    for method in ["pc", "mprgp"] {
        for steps in [1, 2, 3] {
            expected.push((format!("solver.method={method} time.steps={steps}"), steps));
        }
    }
    let got: Vec<(String, usize)> =
        report.rows.iter().map(|r| (r.case.label(), r.run().expect("the case runs").steps)).collect();
    assert_eq!(got, expected);
    assert!(report.reference.is_none());
    assert!(report.rows.iter().all(|r| r.monitor_error.is_none() && r.orders.iter().all(Option::is_none)));
    let csv = report.csv();
    assert_eq!(csv.lines().count(), 7, "{csv}");
    assert!(csv.starts_with("case,solver.method,time.steps,h,status,message,steps,"), "{csv}");
}

/// `connector[*].strength` sets every bolt of examples/bolted_slope.toml (five bolts). The
/// example's header gives the limit-equilibrium demand of each bolt, 164 kN: with every
/// strength at 100 kN all five break (the header: the 100 kN bolts break at step 53), with
/// every strength at 500 kN none does in 60 steps (no block slides, so there is no impact).
#[test]
fn wildcard_sets_every_bolt() {
    let (text, file) = scene("bolted_slope.toml");
    let base = [Override { key: "time.steps".into(), value: "60".into() }];
    let axes = [axis("connector[*].strength", &["1e5", "5e5"])];
    let report = sweep(&text, &file, &base, &axes, &quiet()).unwrap_or_else(|e| panic!("{e:?}"));
    eprintln!("{}", report.table());
    assert_eq!(report.rows.len(), 2);
    for (row, strength, broken) in [(&report.rows[0], 1e5, true), (&report.rows[1], 5e5, false)] {
        let mut overrides = base.to_vec();
        overrides.extend(row.case.set.iter().cloned());
        let model = parse_with(&text, &file, &overrides).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(model.connectors.len(), 5);
        for c in &model.connectors {
            assert_eq!(c.strength, Some(strength), "{} in case {}", c.name, row.case.label());
        }
        let run = row.run().expect("the case runs");
        assert_eq!(run.connectors.len(), 5);
        for (name, end) in &run.connectors {
            assert_eq!(end.broken, broken, "{name} at strength {strength}: {end:?}");
            if broken {
                assert_eq!(end.force, 0.0, "{name}: a broken bolt carries nothing");
            }
        }
    }
    let csv = report.csv();
    let head = csv.lines().next().expect("a header");
    assert!(head.contains("bolt-1_force,bolt-1_broken") && head.contains("bolt-5_broken"), "{head}");
    assert_eq!(csv.lines().nth(1).expect("row").matches(",true").count(), 5, "{csv}");
}

/// A wildcard over an array the scene does not have is an error naming it (the disk heap has
/// no connectors); so is a swept value of the wrong type, naming the case.
#[test]
fn wildcard_matching_nothing_and_wrong_type_are_errors() {
    let (text, file) = scene("7_1_disk_heap.toml");
    let e = sweep(&text, &file, &[], &[axis("connector[*].strength", &["1", "2"])], &quiet()).unwrap_err();
    let e = one_line(&format!("{e:?}"));
    assert!(e.contains("`connector[*]` matches nothing: the scene has no `connector` entries"), "{e}");
    let e = sweep(&text, &file, &[], &[axis("solver.tolerance", &["1e-6", "abc"])], &quiet()).unwrap_err();
    let e = one_line(&format!("{e:?}"));
    assert!(e.contains("case 1 (solver.tolerance=abc)") && e.contains("solver.tolerance"), "{e}");
}

/// A case whose run fails is a row with its error, and the sweep goes on: with one inner
/// iteration per step, no adaptive halving and unconverged steps not allowed (the scene
/// format's defaults for the latter), PC cannot solve the heap's first step (its cold start
/// needs tens of iterations), so the first case fails at step 1; the second runs its 3 steps.
#[test]
fn a_failed_case_is_a_row_with_its_error() {
    let (text, file) = scene("7_1_disk_heap.toml");
    let base: Vec<Override> = [("time.adaptive", "false"), ("solver.method", "pc"), ("time.steps", "3")]
        .iter()
        .map(|(k, v)| Override { key: (*k).into(), value: (*v).into() })
        .collect();
    let axes = [axis("solver.max_iterations", &["1", "200000"])];
    let report = sweep(&text, &file, &base, &axes, &quiet()).unwrap_or_else(|e| panic!("{e:?}"));
    let error = report.rows[0].result.error.as_deref().expect("case 0 fails");
    assert!(error.contains("step 1") && error.contains("did not converge"), "{error}");
    assert_eq!(report.rows[1].run().expect("case 1 runs").steps, 3);
    let csv = report.csv();
    let rows: Vec<&str> = csv.lines().collect();
    assert!(rows[1].starts_with("0,1,,failed,step 1 failed"), "{csv}");
    assert!(rows[2].starts_with("1,200000,,ok,,3,"), "{csv}");
    let columns = rows[0].split(',').count();
    assert_eq!(rows[1].split(',').count(), columns, "a failed row has every column");
}
