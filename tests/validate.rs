//! `pbdda validate`: every row it prints is within its stated tolerance, and --markdown writes
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
    let rows: Vec<&str> = text.lines().skip(1).filter(|l| l.starts_with("7.")).collect();
    // 7.1: 3, 7.2: 4, 7.3/7.4: 4, 7.5: 4, 7.6: 3, 7.7: 5 x 3 + 2, 7.8: 6, 7.9: 3 x 3, 7.10: 3
    assert_eq!(rows.len(), 53, "{text}");
    assert!(rows.iter().all(|r| r.contains(" ok (tol")), "{text}");
    assert!(text.contains("all 53 rows within their tolerance"));
    let md = std::fs::read_to_string(&file).expect("markdown report written");
    assert_eq!(md.lines().filter(|l| l.starts_with("| 7.")).count(), 53, "{md}");
    assert!(md.contains("53 rows, 0 outside their tolerance."), "{md}");
    let _ = std::fs::remove_file(&file);
}
