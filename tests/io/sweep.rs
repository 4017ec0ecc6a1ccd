//! `pbdda sweep` (src/cli/sweep/) on two paper examples, shortened with --set.
//!
//! §7.5 pendulum, time steps h = 0.16, 0.08, 0.04, 0.02 s to t = 4.8 s (past the first peak
//! at T/4 = 4.54 s), reference h_ref = 0.005 s. Expected order of the peak-force error: with
//! beta = 1/2 (math note §1.1) the positions advance by the trapezoidal rule
//! d = dt (v0 + v1)/2, and the swing's positions converge at second order (the sweep's monitor
//! column shows 2.00 to 2.07, but is not asserted here). A step's contact force is the mean
//! over the step (the impulse of the step over dt, math note §1.2) reported at the step's end:
//! against N(t) at a fixed time that is a first-order shift N'(t) dt/2 (the final-force
//! column shows order ~1), but at the peak N' = 0, so the peak value N = m g + m v²/L keeps
//! the second order of the motion: e(h) = C |h² - h_ref²|, and the observed order between h
//! and h/2 is ln((h² - h_ref²)/(h²/4 - h_ref²)) / ln 2 (2.00 to 2.07 here).
//! The sweep refines each peak by the parabola through the largest step value and its two
//! neighbours, which removes the sampling error at step times. Tolerance 0.25 on each order: besides
//! discretization, the reference carries an error of ~0.2 N from the solver tolerance (it
//! grows like 1/dt², and dominates below dt = 0.005 s), up to 15 % of the smallest error
//! compared (1.5 N), i.e. up to 0.2 in the order.
//!
//! §7.1 heap, solver tolerances 1e-4 ... 1e-10, 5 steps, reference 1e-13 (the scene's own):
//! the contact forces' change must fall as the tolerance tightens, while the iterations grow
//! (the scaled natural residual of math note §4.3 bounds the distance to the VI's solution,
//! so a tighter tolerance leaves a smaller force error, at the price of more PC iterations).
//! That trade is PC's (`solver.method = "pc"` is set): MPRGP, the default's method, solves
//! the heap's three-contact problem exactly (conjugate gradients end in at most as many steps
//! as there are free rows, math note §4.8), so at every tolerance its forces equal the
//! reference's to rounding: the second test asserts below 1e-9 N (forces are ~10 N, and
//! rounding of a 6-iteration solve is ~1e-15 relative).

use pbdda::cli::{Axis, SweepOptions, sweep};
use pbdda::scene::Override;
use std::path::Path;

fn scene(name: &str) -> (String, String) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples").join(name);
    (std::fs::read_to_string(&path).expect("example"), path.display().to_string())
}

fn set(pairs: &[(&str, &str)]) -> Vec<Override> {
    pairs.iter().map(|(k, v)| Override { key: (*k).into(), value: (*v).into() }).collect()
}

fn axis(key: &str, values: &[&str]) -> Vec<Axis> {
    vec![Axis { key: key.into(), values: values.iter().map(|v| v.to_string()).collect() }]
}

#[test]
fn pendulum_peak_force_converges_at_second_order() {
    let (text, file) = scene("7_5_disk_in_ring.toml");
    let h_ref = 0.005;
    let options = SweepOptions { reference: Some(h_ref.to_string()), quiet: true, ..Default::default() };
    let values = axis("time.step", &["0.16", "0.08", "0.04", "0.02"]);
    let report = sweep(&text, &file, &set(&[("time.end", "4.8")]), &values, &options)
        .unwrap_or_else(|e| panic!("{e:?}"));
    eprintln!("{}", report.table());
    assert_eq!(report.rows.len(), 4);
    // 4.8 / h steps for every step size (4.8 s is a multiple of every h)
    let steps: Vec<usize> = report.rows.iter().map(|r| r.run().expect("a run").steps).collect();
    assert_eq!(steps, vec![30, 60, 120, 240]);
    let reference = report.reference.as_ref().and_then(|r| r.1.run.as_ref()).expect("the reference run");
    assert_eq!(reference.steps, 960);
    assert!(report.rows[0].orders.iter().all(Option::is_none), "no order for the first value");
    for pair in report.rows.windows(2) {
        let (h0, h1) = (pair[0].h.unwrap(), pair[1].h.unwrap());
        let expected = ((h0 * h0 - h_ref * h_ref) / (h1 * h1 - h_ref * h_ref)).ln() / (h0 / h1).ln();
        let observed = pair[1].orders[1].expect("order of the peak-force error");
        assert!(
            (observed - expected).abs() < 0.25,
            "h = {h0} -> {h1}: observed order {observed}, second order predicts {expected}"
        );
    }
}

#[test]
fn heap_force_error_falls_with_tolerance_as_iterations_grow() {
    let (text, file) = scene("7_1_disk_heap.toml");
    let options = SweepOptions { reference: Some("1e-13".into()), quiet: true, ..Default::default() };
    let values = axis("solver.tolerance", &["1e-4", "1e-6", "1e-8", "1e-10"]);
    let overrides = set(&[("time.steps", "5"), ("solver.method", "pc")]);
    let report = sweep(&text, &file, &overrides, &values, &options).unwrap_or_else(|e| panic!("{e:?}"));
    eprintln!("{}", report.table());
    for pair in report.rows.windows(2) {
        let (e0, e1) = (pair[0].final_force_error.expect("error"), pair[1].final_force_error.expect("error"));
        let (c0, c1) = (pair[0].case.label(), pair[1].case.label());
        assert!(e1 < e0, "error must fall: {e0} at {c0} then {e1} at {c1}");
        let (r0, r1) = (pair[0].run().expect("run"), pair[1].run().expect("run"));
        assert!(r1.iterations >= r0.iterations, "a tighter tolerance costs iterations");
    }
}

#[test]
fn heap_forces_are_exact_at_every_tolerance_with_mprgp() {
    let (text, file) = scene("7_1_disk_heap.toml");
    let options = SweepOptions { reference: Some("1e-13".into()), quiet: true, ..Default::default() };
    let values = axis("solver.tolerance", &["1e-4", "1e-6", "1e-8"]);
    let overrides = set(&[("time.steps", "5"), ("solver.method", "mprgp")]);
    let report = sweep(&text, &file, &overrides, &values, &options).unwrap_or_else(|e| panic!("{e:?}"));
    eprintln!("{}", report.table());
    for row in &report.rows {
        let e = row.final_force_error.expect("an error against the reference");
        assert!(e < 1e-9, "{e} at {}", row.case.label());
    }
}

#[test]
fn binary_writes_csv_and_png() {
    let out = std::env::temp_dir().join(format!("pbdda-sweep-{}", std::process::id()));
    let (_, file) = scene("7_1_disk_heap.toml");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_pbdda"))
        .args(["sweep", &file, "--set", "solver.tolerance=1e-4,1e-8", "--set", "time.steps=3", "-q"])
        .args(["--reference", "1e-13", "--out", out.to_str().unwrap()])
        .output()
        .expect("the binary runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = std::fs::read_to_string(out.join("sweep.csv")).expect("sweep.csv");
    // header + one line per value
    assert_eq!(csv.lines().count(), 3, "{csv}");
    assert!(csv.lines().next().unwrap().contains("d1/d2_peak_error"), "{csv}");
    let png = std::fs::read(out.join("sweep.png")).expect("sweep.png");
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    // IHDR: width and height, big-endian, at bytes 16..24
    let (w, h) = (
        u32::from_be_bytes(png[16..20].try_into().unwrap()),
        u32::from_be_bytes(png[20..24].try_into().unwrap()),
    );
    assert_eq!((w, h), (900, 600));
    let _ = std::fs::remove_dir_all(&out);
}
