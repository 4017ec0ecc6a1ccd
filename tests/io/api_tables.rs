//! `pbdda::api::Simulation` (src/api.rs, the Python package's core): its tables are the rows
//! the results files get, formatted by the same functions.

use pbdda::api::{Simulation, Table};

/// The bodies table after n steps is the last step's rows of the bodies.csv that
/// `Simulation::write_to` writes (the same functions format both), so the table and the
/// file agree byte for byte on a file under 4096 bytes, where no row is padded.
#[test]
fn table_is_the_files_last_rows() {
    let scene = "[scene]\nname = \"t\"\n[time]\nstep = 1e-3\nsteps = 3\n[[material]]\nname = \"m\"\ndensity = 1000.0\n\
                 [[body]]\nname = \"d\"\nshape = \"disk\"\ncenter = [0, 1]\nradius = 0.1\n\
                 material = \"m\"\n[[body]]\nname = \"floor\"\nshape = \"polygon\"\n\
                 vertices = [[-1, -1], [1, -1], [1, 0], [-1, 0]]\nmaterial = \"m\"\nfixed = true\n";
    let dir = std::env::temp_dir().join(format!("pbdda-api-{}", std::process::id()));
    let mut sim = Simulation::parse(scene, "t.toml", &[]).expect("scene");
    sim.write_to(&dir, true).expect("output");
    while sim.step().expect("step") {}
    let file = std::fs::read_to_string(dir.join("bodies.csv")).expect("bodies.csv");
    let rows: Vec<&str> = file.lines().filter(|l| l.starts_with("3,")).collect();
    let table = sim.table(Table::Bodies);
    assert_eq!(table.lines().skip(1).collect::<Vec<_>>(), rows);
    assert_eq!(table.lines().next(), file.lines().next());
    let log = std::fs::read_to_string(dir.join("run.log")).expect("run.log");
    assert!(log.lines().last().is_some_and(|l| l.starts_with("completed 3 steps")), "{log}");
    std::fs::remove_dir_all(&dir).expect("clean");
}
