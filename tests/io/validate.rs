//! `pbdda validate`: every row it prints is within its stated tolerance (the paper's §7 rows,
//! the connector rows and the mesh-convergence rows, counted per part), and --markdown writes
//! the report with one table row per printed row. The closed forms it uses (pbdda::cli::validate::exact)
//! are checked here against the numbers printed in the design note §7 (docs/math.md), to the
//! digits printed there.

use pbdda::cli::validate::exact;
use std::process::Command;

#[test]
fn closed_forms_match_the_design_note() {
    let [f1, f2, f3] = exact::heap_forces();
    assert!((f1 - 7853981.63397).abs() < 1e-5);
    assert!((f2 - 15707963.26795).abs() < 1e-5);
    assert!((f3 - 23561944.90192).abs() < 1e-5);
    assert!((exact::pendulum_peak_force() - 150_796.447).abs() < 1e-3);
    assert!((exact::pendulum_period() - 18.1661).abs() < 1e-4);
    assert_eq!(exact::sliding_block_forces(), [4600.0, 5400.0, -400.0]);
    assert!((exact::trajectory_x(false) - 2.6526).abs() < 1e-4);
    assert!((exact::trajectory_x(true) - 3.3539).abs() < 1e-4);
    assert_eq!(exact::cemented_tensions(0.5), [-750.0, -250.0]);
    assert_eq!(exact::fold(20.0, 17.0), 14.0); // 3 a - (s + a) = 51 - 37
    // W = 2000 g = 19 620 N, θ = 30°, μ = 0.3, β = 20°, by hand with 7-digit sines:
    // 19 620 × (0.5 − 0.3 × 0.8660254)/(0.9396926 + 0.3 × 0.3420201) = 4 521.33 N
    let f = exact::bolt_limit_force(2000.0 * 9.81, 30f64.to_radians(), 0.3, 20f64.to_radians());
    assert!((f - 4521.33).abs() < 0.005, "{f}");
    // examples/connector_spring.toml's header: T = 0.6283 s; connector_beam.toml's: 1.6697e-3 m
    // and 1.25e-3 rad; mesh_cantilever.toml's: 4.031e-4 m
    assert!((exact::spring_period(1000.0, 1e5) - 0.6283).abs() < 5e-5);
    let [v, r] = exact::timoshenko_tip(2e11, 8e10, 0.01, 8e-6, 1.2, 1000.0, 2.0);
    assert!((v - 1.6697e-3).abs() < 5e-8 && (r - 1.25e-3).abs() < 1e-15, "{v} {r}");
    assert!((exact::mesh_cantilever_tip() + 4.031e-4).abs() < 5e-8);
}

#[test]
fn every_row_within_tolerance_and_markdown_written() {
    let file = std::env::temp_dir().join(format!("pbdda-validate-{}.md", std::process::id()));
    let o = Command::new(env!("CARGO_BIN_EXE_pbdda"))
        .args(["validate", "--markdown", file.to_str().unwrap()])
        .output()
        .expect("the binary runs");
    let text = String::from_utf8_lossy(&o.stdout);
    eprintln!("{text}");
    assert!(o.status.success(), "{text}\n{}", String::from_utf8_lossy(&o.stderr));
    let rows: Vec<&str> = text.lines().filter(|l| l.contains(" (tol ")).collect();
    let count = |prefix: &str| rows.iter().filter(|r| r.starts_with(prefix)).count();
    // 7.1: 3, 7.2: 4, 7.3/7.4: 4, 7.5: 4, 7.6: 3, 7.7: 5 x 3 + 2, 7.8: 6, 7.9: 3 x 3, 7.10: 3
    assert_eq!(count("7."), 53, "{text}");
    // bolted block 1, spring 3, beam cantilever 2; mesh convergence: 3 meshes, order, 2 extrapolations
    assert_eq!(count("connector: "), 6, "{text}");
    assert_eq!(count("mesh: cantilever convergence"), 6, "{text}");
    assert_eq!(rows.len(), 65, "{text}");
    assert!(rows.iter().all(|r| r.contains(" ok (tol")), "{text}");
    assert!(text.contains("all 65 rows within their tolerance"));
    let md = std::fs::read_to_string(&file).expect("markdown report written");
    assert_eq!(md.lines().filter(|l| l.contains(" (tol ")).count(), 65, "{md}");
    assert!(md.contains("65 rows, 0 outside their tolerance."), "{md}");
    let _ = std::fs::remove_file(&file);
}
