//! Progress of a run on stderr, and the summary at its end.
//!
//! On a terminal: an indicatif bar with steps/s and ETA; warnings print above it. Not on a
//! terminal (a pipe, a CI log): plain lines at every 10 % of the steps, and at least every
//! 10 s of wall time, without escape codes or carriage returns. `--quiet`: nothing.

use crate::world::{Event, StepRecord, Trouble, Warning};
use indicatif::{ProgressBar, ProgressStyle};
use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// How progress is shown.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProgressMode {
    Bar,
    Plain,
    Quiet,
}

impl ProgressMode {
    /// Bar on a terminal, plain lines otherwise, nothing when `quiet`.
    pub fn detect(quiet: bool) -> ProgressMode {
        match (quiet, std::io::stderr().is_terminal()) {
            (true, _) => ProgressMode::Quiet,
            (false, true) => ProgressMode::Bar,
            (false, false) => ProgressMode::Plain,
        }
    }
}

/// Plain mode writes a line at least this often.
const PLAIN_EVERY: Duration = Duration::from_secs(10);

/// Progress display for `total` steps.
pub struct Progress {
    mode: ProgressMode,
    bar: Option<ProgressBar>,
    total: usize,
    started: Instant,
    last_line: Instant,
    /// Next multiple of 10 % to report in plain mode.
    next_tenth: usize,
}

impl Progress {
    pub fn new(total: usize, mode: ProgressMode) -> Progress {
        let bar = (mode == ProgressMode::Bar).then(|| {
            let bar = ProgressBar::new(total as u64);
            let template = "{bar:30} step {pos}/{len} {per_sec} eta {eta} {msg}";
            if let Ok(style) = ProgressStyle::with_template(template) {
                bar.set_style(style);
            }
            bar
        });
        let now = Instant::now();
        Progress { mode, bar, total, started: now, last_line: now, next_tenth: 1 }
    }

    /// A line for the user (a warning, an event), above the bar; nothing when quiet.
    pub fn println(&self, line: &str) {
        match (&self.bar, self.mode) {
            (Some(bar), _) => bar.suspend(|| errln!("{line}")),
            (None, ProgressMode::Plain) => errln!("{line}"),
            _ => {}
        }
    }

    /// One more step done.
    pub fn step(&mut self, rec: &StepRecord) {
        if let Some(bar) = &self.bar {
            bar.set_message(format!("t = {:.4} s, {} contacts", rec.time, rec.contact_count));
            bar.inc(1);
            return;
        }
        if self.mode != ProgressMode::Plain || self.total == 0 {
            return;
        }
        let done = rec.step;
        let tenth_due = done * 10 >= self.next_tenth * self.total;
        if !tenth_due && self.last_line.elapsed() < PLAIN_EVERY {
            return;
        }
        while self.next_tenth <= 10 && done * 10 >= self.next_tenth * self.total {
            self.next_tenth += 1;
        }
        self.last_line = Instant::now();
        let wall = self.started.elapsed().as_secs_f64();
        let rate = done as f64 / wall.max(1e-9);
        let eta = (self.total - done.min(self.total)) as f64 / rate;
        errln!(
            "step {done}/{} ({} %), t = {} s, {:.0} steps/s, eta {:.0} s",
            self.total,
            done * 100 / self.total,
            rec.time,
            rate,
            eta
        );
    }

    /// Removes the bar.
    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

/// Totals of a run for its closing summary.
#[derive(Debug, Clone, Default)]
pub struct RunSummary {
    pub steps: usize,
    pub time: f64,
    pub wall_seconds: f64,
    pub worst_residual: f64,
    pub unconverged_steps: usize,
    pub inner_iterations: usize,
    pub max_contacts: usize,
    /// Warnings and events by kind (`solver not converged`, `penetration`, `joint broke`).
    pub by_kind: BTreeMap<&'static str, usize>,
}

impl RunSummary {
    pub fn record(&mut self, rec: &StepRecord) {
        self.steps = rec.step;
        self.time = rec.time;
        self.worst_residual = self.worst_residual.max(rec.residual);
        self.unconverged_steps += usize::from(!rec.converged);
        self.inner_iterations += rec.inner_iterations;
        self.max_contacts = self.max_contacts.max(rec.contact_count);
        for w in &rec.warnings {
            *self.by_kind.entry(warning_kind(w)).or_default() += 1;
        }
        for e in &rec.events {
            *self.by_kind.entry(event_kind(e)).or_default() += 1;
        }
    }

    /// The one line `run.log` ends with.
    pub fn log_line(&self) -> String {
        let warnings: usize = self
            .by_kind
            .iter()
            .filter(|(k, _)| !matches!(**k, "joint broke" | "event" | "stage started" | "stage ended"))
            .map(|(_, n)| n)
            .sum();
        format!(
            "completed {} steps to t = {} s in {:.2} s wall; up to {} contacts; {} solver iterations; \
             {} steps not converged; {warnings} warnings",
            self.steps,
            self.time,
            self.wall_seconds,
            self.max_contacts,
            self.inner_iterations,
            self.unconverged_steps
        )
    }

    /// The summary printed at the end of `pbdda run`.
    pub fn text(&self, out: &Path) -> String {
        let rate = self.steps as f64 / self.wall_seconds.max(1e-9);
        let kinds = if self.by_kind.is_empty() {
            "none".to_owned()
        } else {
            self.by_kind.iter().map(|(k, n)| format!("{n} {k}")).collect::<Vec<_>>().join(", ")
        };
        let mut s = format!(
            "completed {} steps to t = {} s in {:.2} s wall ({rate:.0} steps/s)\n\
             worst solver residual {:.3e}; {} steps not converged; up to {} contacts\n\
             warnings and events: {kinds} (details in run.log)\n\
             results in {}: bodies.csv, contacts.csv, monitors.csv, steps.csv, run.log\n",
            self.steps,
            self.time,
            self.wall_seconds,
            self.worst_residual,
            self.unconverged_steps,
            self.max_contacts,
            out.display()
        );
        let pvd: PathBuf = out.join("vtk").join("scene.pvd");
        if pvd.exists() {
            s += &format!("open in ParaView: paraview {}\n", pvd.display());
        }
        s
    }
}

/// Kind of a warning line of the world (see `world::solve`, `World::close_contacts`).
fn warning_kind(w: &Warning) -> &'static str {
    match w {
        Warning::NotConverged { .. } => "solver not converged",
        Warning::Penetration { .. } => "penetration",
        Warning::Trouble { trouble: Trouble::Penetration { .. }, .. } => "penetration",
        Warning::Trouble { trouble: Trouble::MovedTooFar { .. }, .. } => "moved beyond the contact threshold",
        Warning::Trouble { .. } => "numerical trouble",
        Warning::StopsDropped { .. } => "friction stops dropped",
    }
}

fn event_kind(e: &Event) -> &'static str {
    match e {
        Event::JointBroke { .. } => "joint broke",
        Event::ConnectorBroke { .. } => "connector broke",
        Event::StepSplit { .. } => "step split",
        Event::StageStarted { .. } => "stage started",
        Event::StageEnded { .. } => "stage ended",
    }
}
