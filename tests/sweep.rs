//! `pbdda sweep` (src/cli/sweep.rs) on two paper examples, shortened with --set.
//!
//! §7.5 pendulum, time steps h = 0.04, 0.02, 0.01, 0.005 s to t = 4.6 s (past the first peak
//! at T/4 = 4.54 s), reference h_ref = 0.00125 s. Expected order of the peak-force error: the
//! scheme is Newmark with gamma = 1, beta = 1/2 (math note §1.1): positions follow the
//! trapezoidal rule but the velocity is updated with the end-of-step acceleration only
//! (v1 = v0 + dt a1, a backward-Euler step), whose local error dt²/2 a' makes the velocity,
//! hence v² at the bottom and the peak force N = m g + m v²/L, first-order accurate:
//! e(h) = C (h - h_ref) + O(h²). The observed order between h and h/2 is then
//! ln((h - h_ref)/(h/2 - h_ref)) / ln 2, which the reference's own error shifts above 1
//! (1.05 to 1.22 here). Tolerance 0.25 on each order: the O(h²) terms, and the sampling of the
//! peak at step times (an error up to N''(dt/2)²/2 whose phase varies with h).
//!
//! §7.1 heap, solver tolerances 1e-4 ... 1e-10, 5 steps, reference 1e-13 (the scene's own):
//! the contact forces' change must fall as the tolerance tightens, while the iterations grow;
//! the force error must stay below tolerance × total weight (the residual is scaled by the
//! force magnitude, math note §4.3).

use pbdda::cli::{SweepOptions, sweep};
use pbdda::scene::Override;
use std::path::Path;

fn scene(name: &str) -> (String, String) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples").join(name);
    (std::fs::read_to_string(&path).expect("example"), path.display().to_string())
}

fn set(pairs: &[(&str, &str)]) -> Vec<Override> {
    pairs.iter().map(|(k, v)| Override { key: (*k).into(), value: (*v).into() }).collect()
}

fn strings(values: &[&str]) -> Vec<String> {
    values.iter().map(|v| v.to_string()).collect()
}

#[test]
fn pendulum_peak_force_converges_at_first_order() {
    let (text, file) = scene("7_5_disk_in_ring.toml");
    let options = SweepOptions { reference: Some("0.00125".into()), quiet: true };
    let values = strings(&["0.04", "0.02", "0.01", "0.005"]);
    let report = sweep(&text, &file, &set(&[("time.end", "4.6")]), "time.step", &values, &options)
        .unwrap_or_else(|e| panic!("{e:?}"));
    eprintln!("{}", report.table());
    assert_eq!(report.rows.len(), 4);
    // the same simulated time for every step size: ceil(4.6 / h) steps
    let steps: Vec<usize> = report.rows.iter().map(|r| r.run.steps).collect();
    assert_eq!(steps, vec![115, 230, 460, 920]);
    assert_eq!(report.reference.steps, 3680);
    let h_ref = 0.00125;
    for pair in report.rows.windows(2) {
        let (h0, h1) = (pair[0].run.h.unwrap(), pair[1].run.h.unwrap());
        let expected = ((h0 - h_ref) / (h1 - h_ref)).ln() / (h0 / h1).ln();
        let observed = pair[1].orders[1].expect("order of the peak-force error");
        assert!(
            (observed - expected).abs() < 0.25,
            "h = {h0} -> {h1}: observed order {observed}, first order predicts {expected}"
        );
    }
}

#[test]
fn heap_force_error_falls_with_tolerance_as_iterations_grow() {
    let (text, file) = scene("7_1_disk_heap.toml");
    let options = SweepOptions { reference: Some("1e-13".into()), quiet: true };
    let values = strings(&["1e-4", "1e-6", "1e-8", "1e-10"]);
    let report = sweep(&text, &file, &set(&[("time.steps", "5")]), "solver.tolerance", &values, &options)
        .unwrap_or_else(|e| panic!("{e:?}"));
    eprintln!("{}", report.table());
    let weight = 3.0 * 2500.0 * std::f64::consts::PI * 100.0 * 10.0;
    for r in &report.rows {
        let tol: f64 = r.run.value.parse().unwrap();
        assert!(r.final_force_error <= tol * weight, "tolerance {tol}: force error {}", r.final_force_error);
    }
    for pair in report.rows.windows(2) {
        assert!(
            pair[1].final_force_error < pair[0].final_force_error,
            "error must fall: {} at {} then {} at {}",
            pair[0].final_force_error,
            pair[0].run.value,
            pair[1].final_force_error,
            pair[1].run.value
        );
        assert!(pair[1].run.iterations >= pair[0].run.iterations, "a tighter tolerance costs iterations");
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
