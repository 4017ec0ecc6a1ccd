//! Writes the README pictures into `docs/img/`: the force chains of a settled hexagonal pile
//! (`pbdda render`), the contact force of the §7.5 pendulum and the roof bolts' forces of the
//! staged tunnel `examples/tunnel_insitu.toml` (`pbdda plot`).
//! Run: `cargo run --release --example readme_pictures`.

use pbdda::model::Model;
use pbdda::output::connectors::ConnectorWriter;
use pbdda::output::csv::CsvWriter;
use pbdda::output::plot::{PlotOptions, plot_results};
use pbdda::output::render::render_step;
use pbdda::output::results::write_geometry;
use pbdda::world::World;
use std::path::{Path, PathBuf};

/// Runs `steps` steps of `model`, writing every step into `target/readme_pictures/NAME`.
fn run(name: &str, mut model: Model, steps: usize) -> Result<PathBuf, Box<dyn std::error::Error>> {
    model.time.steps = steps;
    model.output.every = 1;
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/readme_pictures").join(name);
    let mut world = World::new(model);
    let mut csv = CsvWriter::create(&dir, 1, steps, true)?;
    let mut connectors = ConnectorWriter::create(&dir, &world, true)?;
    write_geometry(&dir, &world)?;
    while !world.finished() {
        let rec = world.step()?;
        csv.write_step(&world, &rec)?;
        connectors.write_step(&world, &rec)?;
    }
    Ok(dir)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let img = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/img");
    std::fs::create_dir_all(&img)?;
    let pile = run("pile", pbdda::generate::DiskPile::benchmark(24, 14).model(), 5)?;
    render_step(&pile, None, &img.join("pile_force_chains.png"), (1000, 640))?;
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/7_5_disk_in_ring.toml");
    let model = pbdda::scene::load(&path)?;
    let steps = model.time.steps;
    let ring = run("ring", model, steps)?;
    let opts = PlotOptions { bodies: vec![], size: (900, 650), png: true, svg: false };
    let written = plot_results(&ring, &ring.join("plots"), &opts)?;
    let chosen =
        written.iter().find(|p| p.to_string_lossy().contains("contact_forces")).ok_or("no contact figure")?;
    std::fs::copy(chosen, img.join("contact_forces.png"))?;
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/tunnel_insitu.toml");
    let model = pbdda::scene::load(&path)?;
    let steps = model.time.steps;
    let tunnel = run("tunnel", model, steps)?;
    let written = plot_results(&tunnel, &tunnel.join("plots"), &opts)?;
    let chosen = written
        .iter()
        .find(|p| p.to_string_lossy().contains("connector_forces"))
        .ok_or("no connector figure")?;
    std::fs::copy(chosen, img.join("tunnel_bolt_forces.png"))?;
    println!("wrote {}", img.display());
    Ok(())
}
