//! The `pbdda` command line: `run` a scene into a results directory, `check` a scene.

use crate::model::{BodyModel, Model, Shape};
use crate::output::csv::CsvWriter;
use crate::scene;
use crate::world::World;
use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use miette::Result;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Parser, Debug)]
#[command(name = "pbdda", version, about = "Particle-block discontinuous deformation analysis (PB-DDA)")]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Run a scene and write bodies.csv, contacts.csv, monitors.csv, steps.csv and run.log.
    Run {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Output directory (created if missing).
        #[arg(long)]
        out: PathBuf,
        /// Replace the results of an earlier run in the output directory.
        #[arg(long)]
        overwrite: bool,
        /// No progress line and no summary.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Validate a scene and print a summary of it.
    Check {
        /// Scene file (TOML).
        scene: PathBuf,
    },
}

/// Runs the parsed command line.
pub fn main(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Run { scene, out, overwrite, quiet } => run(&scene, &out, overwrite, quiet),
        Command::Check { scene } => {
            let model = scene::load(&scene)?;
            print!("{}", summary(&model));
            Ok(())
        }
    }
}

fn run(scene_path: &Path, out: &Path, overwrite: bool, quiet: bool) -> Result<()> {
    // Validate everything before the first file is created.
    let model = scene::load(scene_path)?;
    let steps = model.time.steps;
    let mut writer = CsvWriter::create(out, model.output.every, steps, overwrite)?;
    let mut world = World::new(model);
    let bar = progress_bar(steps as u64, quiet);
    let started = Instant::now();
    let (mut inner, mut unconverged, mut warnings, mut max_contacts) = (0usize, 0usize, 0usize, 0usize);
    for _ in 0..steps {
        let rec = match world.step() {
            Ok(rec) => rec,
            Err(e) => {
                bar.finish_and_clear();
                writer.log(&format!("failed: {e}"))?;
                return Err(e.into());
            }
        };
        inner += rec.inner_iterations;
        unconverged += usize::from(!rec.converged);
        max_contacts = max_contacts.max(rec.contacts.len());
        for w in &rec.warnings {
            warnings += 1;
            if !quiet {
                bar.suspend(|| eprintln!("warning: {w}"));
            }
        }
        for e in &rec.events {
            if !quiet {
                bar.suspend(|| eprintln!("{e}"));
            }
        }
        writer.write_step(&world, &rec)?;
        bar.set_message(format!("t = {:.4} s, {} contacts", rec.time, rec.contacts.len()));
        bar.inc(1);
    }
    bar.finish_and_clear();
    let wall = started.elapsed().as_secs_f64();
    let done = format!(
        "completed {steps} steps to t = {} s in {wall:.2} s wall; up to {max_contacts} contacts; \
         {inner} solver iterations; {unconverged} steps not converged; {warnings} warnings",
        world.time
    );
    writer.log(&done)?;
    if !quiet {
        eprintln!("{done}\nresults in {}", out.display());
    }
    Ok(())
}

fn progress_bar(len: u64, quiet: bool) -> ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        return ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::hidden());
    }
    let bar = ProgressBar::new(len);
    if let Ok(style) = ProgressStyle::with_template("{bar:30} step {pos}/{len} {msg} (eta {eta})") {
        bar.set_style(style);
    }
    bar
}

/// The text `pbdda check` prints.
pub fn summary(model: &Model) -> String {
    let world = World::new(model.clone());
    let mut s = String::new();
    let t = &model.time;
    s += &format!("scene: {}\n", model.name);
    s += &format!("time: dt = {} s, {} steps, end = {} s\n", t.step, t.steps, t.step * t.steps as f64);
    let count = |f: &dyn Fn(&Shape) -> bool| model.bodies.iter().filter(|b| f(&b.shape)).count();
    s += &format!(
        "bodies: {} ({} disks, {} rings, {} polygons; {} fixed, {} deformable)\n",
        model.bodies.len(),
        count(&|sh| matches!(sh, Shape::Disk { .. })),
        count(&|sh| matches!(sh, Shape::Ring { .. })),
        count(&|sh| matches!(sh, Shape::Polygon { .. })),
        model.bodies.iter().filter(|b| b.fixed).count(),
        model.bodies.iter().filter(|b| b.model == BodyModel::Deformable).count(),
    );
    let mass: f64 = world.bodies.iter().filter(|b| !b.fixed).map(|b| b.mass).sum();
    s += &format!("free mass: {mass} kg/m\n");
    s += &format!(
        "materials: {}\n",
        model.materials.iter().map(|m| m.name.as_str()).collect::<Vec<_>>().join(", ")
    );
    for i in &model.interfaces {
        let pair = match i.materials {
            Some([a, b]) => format!("{} / {}", model.materials[a].name, model.materials[b].name),
            None => "default".to_string(),
        };
        s += &format!(
            "interface {pair}: friction {}, cohesion {} Pa, tensile strength {} Pa, rolling {} m\n",
            i.friction, i.cohesion, i.tensile_strength, i.rolling
        );
    }
    let how = if model.contact.threshold.is_some() { "given" } else { "estimated: 0.1 x smallest feature" };
    s += &format!("contact threshold d0: {} m ({how})\n", world.threshold);
    s += &format!("loads: {}, monitors: {}\n", model.loads.len(), model.monitors.len());
    s
}

/// Convenience for the binary: parse arguments and run.
pub fn run_from_args() -> Result<()> {
    main(Cli::parse())
}
