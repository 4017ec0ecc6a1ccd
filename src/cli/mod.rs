//! The `pbdda` command line: `run` a scene into a results directory, `check` a scene,
//! `validate` against the paper's examples, `sweep` one key of a scene.
//!
//! `--set KEY=VALUE` (see [`crate::scene::overrides`]) changes any key of the scene file for
//! one invocation; every check of the scene reader applies to the new value.

/// `print!` / `println!` / `eprint!` / `eprintln!` that ignore a failed write: when the reader
/// of the terminal output goes away (`pbdda run … | head`), the run still finishes and writes its
/// files; the std macros would panic on the closed pipe mid-run.
macro_rules! say {
    ($stream:expr, $write:ident, $($t:tt)*) => {{
        use std::io::Write as _;
        let _ = $write!($stream, $($t)*);
    }};
}
macro_rules! out {
    ($($t:tt)*) => { say!(std::io::stdout(), write, $($t)*) };
}
macro_rules! outln {
    ($($t:tt)*) => { say!(std::io::stdout(), writeln, $($t)*) };
}
macro_rules! err {
    ($($t:tt)*) => { say!(std::io::stderr(), write, $($t)*) };
}
macro_rules! errln {
    ($($t:tt)*) => { say!(std::io::stderr(), writeln, $($t)*) };
}

mod check;
mod cut;
mod import;
mod progress;
pub(crate) mod run;
pub mod sweep;
pub mod validate;

pub use check::summary;
pub use progress::{Progress, ProgressMode, RunSummary};
pub use sweep::{Axis, SweepOptions, SweepReport, sweep};

use crate::scene::Override;
use clap::{Parser, Subcommand};
use miette::Result;
use std::path::PathBuf;

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
        /// No progress, no warnings on the terminal and no summary (run.log still has them).
        #[arg(long, short)]
        quiet: bool,
        /// Override a scene key, e.g. --set time.step=1e-3 --set body.d1.radius=2 (repeatable).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<Override>,
        /// Write a restart file (DIR/checkpoint.toml) every N steps, for `pbdda resume DIR`.
        #[arg(long, value_name = "N")]
        checkpoint_every: Option<usize>,
    },
    /// Continue an interrupted `pbdda run --checkpoint-every N` from its last checkpoint; the
    /// results are the same, byte for byte (wall-time column aside), as those of an
    /// uninterrupted run.
    Resume {
        /// Results folder of the interrupted run.
        dir: PathBuf,
        /// No progress, no warnings on the terminal and no summary.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Validate a scene and print a summary of it.
    Check {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Override a scene key, e.g. --set time.step=1e-3 (repeatable).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<Override>,
    },
    /// Cut a scene's rock mass into blocks and write the scene with them as explicit bodies.
    Cut {
        /// Scene file (TOML) with a `[domain]` to cut.
        scene: PathBuf,
        /// The expanded scene file to write (meshed blocks' `.msh` files go beside it).
        #[arg(long)]
        out: PathBuf,
        /// Also draw the blocks, the joints by set and the bolts into this PNG file.
        #[arg(long)]
        png: Option<PathBuf>,
    },
    /// Run the paper's examples (§7.1-7.10, built in) and print paper, exact and pbdda values.
    Validate {
        /// Also write the table as a Markdown report to this file.
        #[arg(long, value_name = "FILE")]
        markdown: Option<PathBuf>,
    },
    /// Run a scene for a grid of values of one or more keys; tabulate cost, results, change
    /// against a reference, observed orders and Richardson extrapolation (sweep.csv, sweep.png).
    Sweep(sweep::SweepArgs),
    /// Write PNG and SVG figures from a results folder (finished or still running): monitor
    /// paths and displacements, contact and connector forces, kinetic energy, solver effort.
    Plot {
        /// Results folder of `pbdda run`.
        dir: PathBuf,
        /// Where to write the figures (default: DIR/plots).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Bodies whose contact forces to plot (repeatable; default: the first four in contact).
        #[arg(long = "body")]
        bodies: Vec<String>,
    },
    /// Draw the scene at a step as a PNG: bodies, force chains (width ∝ force), connectors.
    Render {
        /// Results folder of `pbdda run`.
        dir: PathBuf,
        /// Step to draw (default: the last written step).
        #[arg(long)]
        step: Option<usize>,
        /// Output PNG (default: DIR/render_STEP.png).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Picture width and height in pixels.
        #[arg(long, default_value_t = 1200)]
        width: u32,
        #[arg(long, default_value_t = 900)]
        height: u32,
    },
    /// Write a pbdda rock-mass scene from ntdda's geometry and analysis files (text or DDAML);
    /// what has no meaning in pbdda is listed on stderr and atop the scene.
    ImportNtdda {
        /// ntdda geometry file (.geo, text or DDAML).
        geometry: PathBuf,
        /// ntdda analysis file (.ana, text or DDAML).
        analysis: Option<PathBuf>,
        /// The scene file to write.
        #[arg(long)]
        out: PathBuf,
    },
}

/// Runs the parsed command line.
pub fn main(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Run { scene, out, overwrite, quiet, set, checkpoint_every } => {
            run::run(&scene, &out, (overwrite, quiet), &set, checkpoint_every)
        }
        Command::Resume { dir, quiet } => run::resume(&dir, quiet),
        Command::Check { scene, set } => check::check(&scene, &set),
        Command::Cut { scene, out, png } => cut::cut(&scene, &out, png.as_deref()),
        Command::Validate { markdown } => validate::command(markdown.as_deref()),
        Command::Sweep(args) => sweep::command(&args),
        Command::Plot { dir, out, bodies } => {
            let out = out.unwrap_or_else(|| dir.join("plots"));
            let opts = crate::output::plot::PlotOptions { bodies, ..Default::default() };
            let written = crate::output::plot::plot_results(&dir, &out, &opts)?;
            outln!("{} figures in {}", written.len(), out.display());
            Ok(())
        }
        Command::Render { dir, step, out, width, height } => {
            let out = out.unwrap_or_else(|| {
                dir.join(format!("render_{}.png", step.map_or("last".into(), |s| s.to_string())))
            });
            let path = crate::output::render::render_step(&dir, step, &out, (width, height))?;
            outln!("{}", path.display());
            Ok(())
        }
        Command::ImportNtdda { geometry, analysis, out } => {
            import::command(&geometry, analysis.as_deref(), &out)
        }
    }
}

/// Convenience for the binary: parse arguments and run.
pub fn run_from_args() -> Result<()> {
    main(Cli::parse())
}
