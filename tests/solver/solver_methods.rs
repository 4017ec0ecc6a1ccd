//! Every VI method (`[solver] method`, math note §4.2, §4.7, §4.8 and §4.15) reproduces the paper's examples
//! §7.1–7.10: the rows of `pbdda validate` (closed forms of design note §7, `cli::validate::exact`,
//! each row with the tolerance justified in its note) are run with the method forced on every
//! scene, and every row must lie within its tolerance. The QVIs of these scenes have unique
//! solutions where the rows compare forces (statically determinate supports, §7.2 compares
//! the reactions the paper's Table 2 gives), so forces are comparable across methods.

use pbdda::cli::validate::{Row, paper_rows_with};
use pbdda::scene::Override;

fn run(method: &str) -> Vec<Row> {
    let o = Override::parse(&format!("solver.method={method}")).expect("a valid override");
    let rows = paper_rows_with(&[o]).expect("every example runs");
    // 7.1: 3, 7.2: 4, 7.3/7.4: 4, 7.5: 4, 7.6: 3, 7.7: 5 x 3 + 2, 7.8: 6, 7.9: 9, 7.10: 3
    // (as tests/io/validate.rs)
    assert_eq!(rows.len(), 53);
    rows
}

fn check(method: &str) {
    let rows = run(method);
    let bad: Vec<String> = rows
        .iter()
        .filter(|r| !r.within())
        .map(|r| {
            format!("{} {}: {} vs exact {} (tol {:e})", r.example, r.quantity, r.pbdda, r.exact, r.tolerance)
        })
        .collect();
    assert!(bad.is_empty(), "method {method}: {} rows outside tolerance:\n{}", bad.len(), bad.join("\n"));
}

#[test]
fn paper_examples_with_pc() {
    check("pc");
}

#[test]
fn paper_examples_with_nsgs() {
    check("nsgs");
}

#[test]
fn paper_examples_with_mprgp() {
    check("mprgp");
}

#[test]
fn paper_examples_with_newton() {
    check("newton");
}

/// `auto` (the default) is MPRGP's chain (`Chain::parse`), so the MPRGP run above covers it;
/// what is left to check is that the default scene gets that chain and that `auto` names it
/// (the scene-format reference says so).
#[test]
fn auto_is_the_default_and_stands_for_mprgp() {
    use pbdda::vi::Chain;
    let scene = pbdda::scene::load_with(std::path::Path::new("examples/7_1_disk_heap.toml"), &[])
        .expect("the example loads");
    let mprgp = Chain::parse("mprgp").expect("mprgp names a chain");
    assert_eq!(scene.solver.method, mprgp);
    assert_eq!(Chain::parse("auto"), Some(mprgp));
}

/// A method name outside the list is a typed error naming the key (scene-format contract).
#[test]
fn unknown_method_is_an_error() {
    let o = Override::parse("solver.method=cg").expect("a valid override");
    let e = pbdda::scene::load_with(std::path::Path::new("examples/7_1_disk_heap.toml"), &[o]);
    let Err(e) = e else { panic!("an unknown method was accepted") };
    let msg = format!("{e:?}");
    assert!(msg.contains("method must be one of"), "{msg}");
}
