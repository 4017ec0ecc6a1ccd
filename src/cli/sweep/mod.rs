//! `pbdda sweep`: runs a scene once per case of a grid of `--set` values and tabulates what
//! each case costs (wall time, solver iterations) and what it gives (every monitor, the peak
//! and final normal force between every pair of bodies, every connector's final axial force
//! and whether it broke), with the change against a reference case and, for keys with a size,
//! the observed order and a Richardson extrapolation.
//!
//! - Cases: one `--set KEY=V1,V2,...` per swept key; several make a grid of all combinations
//!   (the first key slowest), or with `--zip` the i-th values together. Other `--set` apply to
//!   every case. `connector[*].strength=...` sets the key in every entry (scene overrides).
//! - Size h of a case: the value of `time.step`, `solver.tolerance` and `domain.mesh_size`;
//!   for a key ending in `.file` (a mesh), the mean edge length over every triangle's three
//!   edges of the scene's mesh bodies; or the `--sizes` given (e.g. gmsh's `lc`). Only a single
//!   swept key (or the first sized key of a zip) has sizes; a strength has none, and gets no
//!   order.
//! - Reference: `--reference V`, else the case of the smallest h; none for unsized grids.
//!   Errors are distances to it (largest over monitors [m], over body pairs [N]).
//! - `--exact monitor.NAME.C=V`: the known value of one monitor component (x, y, ux, uy); its
//!   error |φ − V| gets a column and orders of its own.
//! - Observed order between successive rows with sizes h_i, h_{i+1} and errors e_i, e_{i+1}:
//!   p = ln(e_i / e_{i+1}) / ln(h_i / h_{i+1}); against a reference it is the scheme's order
//!   when the reference is much finer than the values compared.
//! - Richardson extrapolation of every monitor displacement (and the `--exact` quantity) from
//!   the three finest sizes, with Roache's GCI as its estimated error ([`richardson`]).
//! - A time-step sweep keeps the simulated time: when `time.step` is swept every case ends at
//!   the base scene's end time (`time.end` is set, which replaces `time.steps`).
//! - A case whose run fails is a row with its error message; the sweep goes on. A case the
//!   scene reader rejects (a value of the wrong type) stops the sweep before any run.
//! - `--plan DIR`, `--run-plan DIR --shard I/N`, `--collect DIR` split the cases over
//!   processes or machines ([`plan`]); the collected sweep.csv equals the sequential one.

mod cases;
mod measure;
pub mod plan;
mod plot;
mod report;
pub mod richardson;

pub use cases::{Axis, Case, Exact, Study, split_values};
pub use measure::{CaseResult, ConnectorEnd, MonitorEnd, SweepRun};
pub use report::{SweepReport, SweepRow};

use crate::model::Model;
use crate::scene::{Override, parse_with};
use cases::{SizeKind, grid, mean_edge, size_kind};
use miette::{IntoDiagnostic, Result, miette};
use std::path::{Path, PathBuf};

/// Options of a sweep besides the scene and the swept keys.
#[derive(Debug, Clone, Default)]
pub struct SweepOptions {
    /// Value of the swept key for the reference case (run in addition if not among the values).
    pub reference: Option<String>,
    /// A known value of one monitor component.
    pub exact: Option<Exact>,
    /// Sizes h of the swept key's values, instead of the measured or nominal ones.
    pub sizes: Option<Vec<f64>>,
    /// Pair the keys' values element-wise instead of a grid.
    pub zip: bool,
    pub quiet: bool,
}

/// The cases of a sweep, checked: every case's model reads, sizes, the reference.
#[derive(Debug, Clone)]
pub struct Plan {
    pub axes: Vec<Axis>,
    /// Overrides of every case (the given ones, and `time.end` for a time-step sweep).
    pub base: Vec<Override>,
    /// The grid's cases, then the reference case if it is not among them.
    pub cases: Vec<Case>,
    /// Number of grid cases (rows of the table).
    pub rows: usize,
    /// Size of every case, if the sweep has sizes.
    pub h: Vec<Option<f64>>,
    pub reference: Option<usize>,
    pub exact: Option<Exact>,
}

impl Plan {
    /// Builds and checks the cases of `axes` on the scene text `source` (read from `file`).
    pub fn new(
        source: &str,
        file: &str,
        base: &[Override],
        axes: &[Axis],
        options: &SweepOptions,
    ) -> Result<Plan> {
        let mut cases = grid(axes, options.zip)?;
        let rows = cases.len();
        let mut base = base.to_vec();
        if axes.iter().any(|a| a.key == "time.step") {
            // keep the simulated time: every case ends where the base scene ends
            let model = parse_with(source, file, &base)?;
            let end = model.time.step * model.time.steps as f64;
            base.push(Override { key: "time.end".into(), value: format!("{end:e}") });
        }
        let single = axes.len() == 1 || options.zip;
        let sized = if single { axes.iter().position(|a| size_kind(&a.key).is_some()) } else { None };
        let sized = sized.or((single && options.sizes.is_some()).then_some(0));
        if let Some(sizes) = &options.sizes {
            if !single {
                return Err(miette!(
                    "--sizes needs a single swept key (or --zip): a grid of several keys has no size"
                ));
            }
            if sizes.len() != axes[0].values.len() {
                let n = axes[0].values.len();
                return Err(miette!(
                    "--sizes gives {} sizes for the {n} values of `{}`",
                    sizes.len(),
                    axes[0].key
                ));
            }
        }
        let mut reference = None;
        if let Some(r) = &options.reference {
            if !single {
                return Err(miette!(
                    "--reference needs a single swept key (or --zip): which case of the grid is it?"
                ));
            }
            let at = cases.iter().position(|c| c.set[0].value == *r);
            reference = Some(at.unwrap_or(rows));
            if at.is_none() {
                let mut set = cases[0].set.clone();
                set[0].value = r.clone();
                cases.push(Case { index: rows, set });
            }
        }
        let models = check(source, file, &base, &cases)?;
        let h: Vec<Option<f64>> = cases
            .iter()
            .zip(&models)
            .map(|(c, m)| sized.and_then(|a| size_of(c, a, m, options.sizes.as_deref(), &axes[a])))
            .collect();
        if reference.is_none() && sized.is_some() {
            let finest = (0..rows).filter_map(|i| h[i].map(|h| (h, i))).min_by(|a, b| a.0.total_cmp(&b.0));
            reference = finest.map(|(_, i)| i);
        }
        if let Some(e) = &options.exact
            && !models[0].monitors.iter().any(|m| m.name == e.monitor)
        {
            return Err(miette!("--exact {e}: the scene has no monitor named `{}`", e.monitor));
        }
        Ok(Plan { axes: axes.to_vec(), base, cases, rows, h, reference, exact: options.exact.clone() })
    }

    /// The model of case `i`, from the scene text.
    pub fn model(&self, source: &str, file: &str, i: usize) -> Result<Model> {
        Ok(parse_with(source, file, &self.overrides(i))?)
    }

    /// Every override of case `i`: the base, then its swept values.
    pub fn overrides(&self, i: usize) -> Vec<Override> {
        let mut all = self.base.clone();
        all.extend(self.cases[i].set.iter().cloned());
        all
    }
}

/// Reads every case's model; the first that the scene reader rejects is an error naming it.
fn check(source: &str, file: &str, base: &[Override], cases: &[Case]) -> Result<Vec<Model>> {
    let mut models = Vec::new();
    for c in cases {
        let mut all = base.to_vec();
        all.extend(c.set.iter().cloned());
        let model = parse_with(source, file, &all)
            .map_err(|e| miette::Report::new(e).wrap_err(format!("case {} ({})", c.index, c.label())))?;
        models.push(model);
    }
    Ok(models)
}

/// The size of case `c` along axis `a`.
fn size_of(c: &Case, a: usize, model: &Model, sizes: Option<&[f64]>, axis: &Axis) -> Option<f64> {
    if let Some(sizes) = sizes {
        return axis.values.iter().position(|v| *v == c.set[a].value).map(|i| sizes[i]);
    }
    match size_kind(&axis.key)? {
        SizeKind::Value => c.set[a].value.parse().ok(),
        SizeKind::MeshEdge => mean_edge(model),
    }
}

/// Runs every case of the sweep on the scene text `source` (read from `file`) in this process.
pub fn sweep(
    source: &str,
    file: &str,
    base: &[Override],
    axes: &[Axis],
    options: &SweepOptions,
) -> Result<SweepReport> {
    let plan = Plan::new(source, file, base, axes, options)?;
    let mut results = Vec::new();
    for (i, case) in plan.cases.iter().enumerate() {
        let model = plan.model(source, file, i)?;
        results.push(measure::run_case(model, i, &case.label(), options.quiet, None));
    }
    Ok(SweepReport::new(&plan, results))
}

/// The command line of `pbdda sweep`.
#[derive(clap::Args, Debug)]
pub struct SweepArgs {
    /// Scene file (TOML); not with --study, --run-plan or --collect.
    pub scene: Option<PathBuf>,
    /// KEY=V1,V2,... for a swept key (several make a grid); KEY=VALUE for every case
    /// (repeatable). `connector[*].strength=1e5,2e5` sets every connector's strength.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<Override>,
    /// Pair the swept keys' values element-wise (equal lengths) instead of a grid.
    #[arg(long)]
    pub zip: bool,
    /// Value of the swept key for the reference case (default: the smallest size).
    #[arg(long)]
    pub reference: Option<String>,
    /// Known value of a monitor component, e.g. monitor.tip.uy=-4.031e-4 (x, y, ux, uy).
    #[arg(long, value_name = "monitor.NAME.C=VALUE")]
    pub exact: Option<String>,
    /// Sizes h of the swept values, e.g. a mesh's gmsh lc (default: measured).
    #[arg(long, value_name = "H1,H2,...")]
    pub sizes: Option<String>,
    /// A study file (sweep.toml) with the scene, keys, values and options.
    #[arg(long, value_name = "FILE")]
    pub study: Option<PathBuf>,
    /// Write the cases into DIR (plan.toml, one scene file per case) instead of running them.
    #[arg(long, value_name = "DIR")]
    pub plan: Option<PathBuf>,
    /// Run the cases of a plan (those of --shard I/N), skipping finished ones.
    #[arg(long, value_name = "DIR")]
    pub run_plan: Option<PathBuf>,
    /// With --run-plan: run the cases whose index % N == I (0 <= I < N).
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// With --run-plan: a running case saves its state every N steps (default 1000); a shard
    /// run again goes on with an interrupted case from it.
    #[arg(long, value_name = "N")]
    pub checkpoint_every: Option<usize>,
    /// Merge the results of a plan's cases into DIR/sweep.csv (or --out).
    #[arg(long, value_name = "DIR")]
    pub collect: Option<PathBuf>,
    /// Directory for sweep.csv and sweep.png (default: the study's `out`, else `.`).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// No progress lines.
    #[arg(long, short)]
    pub quiet: bool,
}

impl SweepArgs {
    /// The study the command line (or its study file) describes.
    fn study(&self) -> Result<Study> {
        if let Some(path) = &self.study {
            let extra = !self.set.is_empty()
                || self.zip
                || self.reference.is_some()
                || self.exact.is_some()
                || self.sizes.is_some();
            if self.scene.is_some() || extra {
                return Err(miette!(
                    "--study {}: the study file gives the scene, --set, --zip, --reference, --exact and --sizes",
                    path.display()
                ));
            }
            return Study::read(path);
        }
        let scene = self.scene.as_ref().ok_or_else(|| miette!("sweep needs a scene file or --study FILE"))?;
        let swept = |o: &&Override| split_values(&o.value).len() > 1;
        let sizes = match &self.sizes {
            Some(s) => Some(
                split_values(s)
                    .iter()
                    .map(|v| v.parse::<f64>().map_err(|_| miette!("--sizes {s}: `{v}` is not a number")))
                    .collect::<Result<Vec<f64>>>()?,
            ),
            None => None,
        };
        Ok(Study {
            scene: scene.display().to_string(),
            out: None,
            set: self.set.iter().filter(|o| !swept(o)).map(|o| o.to_string()).collect(),
            zip: self.zip,
            reference: self.reference.clone(),
            exact: self.exact.clone(),
            sizes,
            sweep: self.set.iter().filter(swept).map(Axis::from_override).collect(),
        })
    }
}

impl Study {
    pub fn options(&self, quiet: bool) -> Result<SweepOptions> {
        Ok(SweepOptions {
            reference: self.reference.clone(),
            exact: self.exact.as_deref().map(Exact::parse).transpose()?,
            sizes: self.sizes.clone(),
            zip: self.zip,
            quiet,
        })
    }
}

/// Runs `pbdda sweep`.
pub fn command(args: &SweepArgs) -> Result<()> {
    let modes = [args.plan.is_some(), args.run_plan.is_some(), args.collect.is_some()];
    if modes.iter().filter(|m| **m).count() > 1 {
        return Err(miette!("give one of --plan, --run-plan and --collect"));
    }
    if args.shard.is_some() && args.run_plan.is_none() {
        return Err(miette!("--shard I/N goes with --run-plan DIR"));
    }
    if args.checkpoint_every.is_some() && args.run_plan.is_none() {
        return Err(miette!("--checkpoint-every N goes with --run-plan DIR"));
    }
    if let Some(dir) = &args.run_plan {
        let shard = cases::parse_shard(args.shard.as_deref().unwrap_or("0/1"))?;
        let every = args.checkpoint_every.unwrap_or(plan::CHECKPOINT_EVERY);
        return plan::run_plan_every(dir, shard, args.quiet, every);
    }
    if let Some(dir) = &args.collect {
        let report = plan::collect(dir)?;
        return write(&report, args.out.as_deref().unwrap_or(dir));
    }
    let study = args.study()?;
    if let Some(dir) = &args.plan {
        return plan::write_plan(dir, &study);
    }
    let file = study.scene.clone();
    let source =
        std::fs::read_to_string(&file).map_err(|e| crate::scene::SceneError::unreadable(&file, &e))?;
    let report = sweep(&source, &file, &study.base()?, &study.sweep, &study.options(args.quiet)?)?;
    let out =
        args.out.clone().or(study.out.as_ref().map(PathBuf::from)).unwrap_or_else(|| PathBuf::from("."));
    write(&report, &out)
}

/// Prints the table and writes sweep.csv (and sweep.png when there are errors to plot).
fn write(report: &SweepReport, out: &Path) -> Result<()> {
    out!("{}", report.table());
    for path in write_files(report, out)? {
        outln!("wrote {}", path.display());
    }
    Ok(())
}

/// Writes `out`/sweep.csv (and sweep.png when there are errors to plot); returns their paths.
pub fn write_files(report: &SweepReport, out: &Path) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(out).into_diagnostic()?;
    let csv = out.join("sweep.csv");
    std::fs::write(&csv, report.csv()).into_diagnostic()?;
    let mut written = vec![csv];
    let png = out.join("sweep.png");
    if plot::error_against_cost(report, &png)? {
        written.push(png);
    }
    Ok(written)
}
