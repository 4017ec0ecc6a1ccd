//! Stage 4: the two VI solves of math note §1.3 — solve 1 (geometry) refined on the mid-step
//! configuration (§10.1), then solve 2 (velocity) — and the classification of contacts
//! (closed, impacting; §10.5).

use super::detect::{Brief, Detected, Inputs};
use super::refine::Refined;
use super::rows::{Linearization, Rows};
use super::{HandOver, Pipeline, SolveKind, Warning, World};
use crate::contact::ContactGeom;
use crate::contact::law::Law;
use crate::vi::{self, Operator, Problem};
use std::time::Instant;

/// The most outer passes (math note §4.3) a solve of a scene step runs before its method hands
/// over. Once the box moves little a pass costs a few MPRGP iterations, while the box of a
/// frictional, hyperstatic packing settles slowly: on the first 100 steps of the 200-disk
/// collapse at tolerance 1e-6 the steps MPRGP answered took a median of 142 passes (max 508),
/// and the first 60 steps, each from the same state, took 150 s with a cap of 400 against 233 s
/// with 50 (`benches/compare`, `paired`).
const MAX_PASSES: usize = 400;

/// Refinements of solve 1 on the mid-step configuration (math note §10.1); the fixed point is
/// reached in two or three.
const MAX_REFINEMENTS: usize = 4;

/// The iteration budget of a cold step's continuation (math note §10.11) is the first solve's
/// count, and at least this: a floor chosen (not tuned) so that a first solve that needed no
/// iteration still gets a budget.
const MIN_CONTINUATION: usize = 50;

/// Contact states after a solve 1.
pub(super) struct Classified {
    /// Gaps G(z1) = q + W z1 at the end of the step.
    pub gaps: Vec<f64>,
    /// Per contact: closed (or bonded) in solve 1.
    pub closed: Vec<bool>,
    /// Per VI row: belongs to an impacting contact (math note §1.3 b).
    pub impacting_rows: Vec<bool>,
    /// Some contact is impacting.
    pub impacts: bool,
    /// Solve 2 changes the forces: some contact closed in solve 1 started the step with a gap
    /// the solver sees (|g0| beyond the allowance: math note §1.3 d, §10.2, §10.5).
    pub velocity: bool,
    /// Some contact is bonded (a cemented joint that may break).
    pub bonded: bool,
}

/// Result of stage 4.
pub(super) struct Solved {
    /// The contacts' laws and VI row layout.
    pub laws: Vec<Law>,
    /// The rows of solve 1 (the forces z1 belong to them).
    pub rows: Rows,
    /// The rows of solve 2 when they differ (impacts on deformable bodies, §10.3).
    pub rows2: Option<Rows>,
    /// Forces of solve 1 (geometry).
    pub z1: Vec<f64>,
    /// Forces of solve 2 (velocity; reported). Equal to z1 when solve 2 was skipped.
    pub z2: Vec<f64>,
    /// K̃⁻¹ Bᵀ z1 over the rows of solve 1 (the response d^p of paper eq. 22).
    pub dp1: Vec<f64>,
    /// K̃⁻¹ Bᵀ z2 over the rows of solve 2, when solve 2 ran (else it is `dp1`).
    pub dp2: Option<Vec<f64>>,
    /// The geometry increment d̄ of z1 and its bodies' motions (taken by `World::motion`).
    pub increment: Increment,
    pub state: Classified,
    pub report: vi::Report,
    pub warnings: Vec<Warning>,
    /// Largest diagonal entry of W (gap per unit force).
    pub w_diag_max: f64,
    /// Time spent building rows and in the VI.
    pub times: SolveTimes,
    /// The method whose answer the step took and the chain's hand-overs ([`super::StepRecord`]).
    pub method: Option<vi::Method>,
    pub handovers: Vec<HandOver>,
}

/// A geometry increment d̄ (math note §1.3 c) and each body's largest point motion under it.
#[derive(Default)]
pub(super) struct Increment {
    pub dbar: Vec<f64>,
    pub motions: Vec<f64>,
}

/// Wall time of the parts of stage 4 [s].
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct SolveTimes {
    pub rows: f64,
    pub vi: f64,
}

/// Runs the VI solves of one step and accumulates their report and warnings. Every solve
/// draws on the step's one budget (math note §4.17): its `max_iterations` is what the step's
/// solves before it left of `[solver] max_iterations`.
struct Runner<'a> {
    /// The scene's options (`max_iterations`: what is left of the step's budget).
    opts: vi::Options,
    /// The step's budget of work (`[solver] max_iterations`).
    budget: usize,
    /// The chain of methods (`[solver] method`).
    chain: vi::Chain,
    /// The method whose answer was taken latest in the chain's order, with its place.
    method: Option<(usize, vi::Method)>,
    handovers: Vec<HandOver>,
    /// On a cold step, the factor on the tolerances of each solve's continuation (§10.11).
    tighten: Option<f64>,
    step: usize,
    report: vi::Report,
    warnings: Vec<Warning>,
    pipeline: &'a mut Pipeline,
    times: SolveTimes,
}

impl Runner<'_> {
    /// Solves one VI into `z`; returns G = q + W z at the answer when the solver has it from its
    /// last product ([`vi::Solver::gaps`]) and the polish (§10.10) left z alone. `again`: z is
    /// the answer of the solver's last solve, on these rows' W (§10.5).
    #[allow(clippy::too_many_arguments)]
    fn run(
        &mut self,
        world: &World,
        laws: &[Law],
        rows: &Rows,
        q: &[f64],
        z: &mut [f64],
        solve: SolveKind,
        again: bool,
    ) -> Option<Vec<f64>> {
        let started = Instant::now();
        let rule = world.bounds(laws);
        let problem = Problem { w: &rows.w, q, blocks: &rows.blocks };
        self.pipeline.vi.chain = self.chain;
        self.opts.max_iterations = self.budget.saturating_sub(self.report.inner_iterations);
        let (r, last) = self.solve_vi(&problem, &rule, z, again, solve);
        let mut gaps = None;
        if r.converged {
            if !world.polish(rows, q, &rule, z) && last {
                gaps = self.pipeline.vi.gaps(q);
            }
        } else {
            let (step, residual, iterations) = (self.step, r.residual, r.inner_iterations);
            self.warnings.push(Warning::NotConverged { step, solve, residual, iterations });
        }
        self.report.outer_iterations += r.outer_iterations;
        self.report.inner_iterations += r.inner_iterations;
        self.report.residual = self.report.residual.max(r.residual);
        self.report.converged &= r.converged;
        self.times.vi += started.elapsed().as_secs_f64();
        gaps
    }

    /// One VI solve with the scene's options; on a cold step, once it has converged, continued
    /// from its answer to the tightened tolerances (math note §10.11) with at most as many
    /// iterations again. A continuation that misses is dropped: z goes back to the first
    /// answer, so the rule never changes whether a step converges. Returns the report (both
    /// solves counted) and whether z is the solver's last answer (for [`vi::Solver::gaps`]).
    ///
    /// With `again` (z is the last solve's answer on the same W, so the same bounds), a start
    /// that the solver's last product shows within the tolerance is kept without a solve: the
    /// solve would keep it bit for bit (§4.11, §10.5). Not on a cold step, which continues.
    fn solve_vi(
        &mut self,
        problem: &Problem,
        rule: &dyn vi::BoundRule,
        z: &mut [f64],
        again: bool,
        solve: SolveKind,
    ) -> (vi::Report, bool) {
        let kept = (again && self.tighten.is_none())
            .then(|| self.pipeline.vi.residual_again(problem.q, z, &self.opts))
            .flatten()
            .filter(|&r| r <= self.opts.tolerance);
        if let Some(residual) = kept {
            return (
                vi::Report { outer_iterations: 0, inner_iterations: 0, residual, converged: true },
                true,
            );
        }
        let first = self.pipeline.vi.solve(problem, rule, z, &self.opts);
        self.note(solve, true);
        let Some(factor) = self.tighten.filter(|_| first.converged) else { return (first, true) };
        let answer = z.to_vec();
        let left = self.opts.max_iterations.saturating_sub(first.inner_iterations);
        let tight = vi::Options {
            tolerance: self.opts.tolerance * factor,
            gap_tolerance: self.opts.gap_tolerance * factor,
            max_iterations: first.inner_iterations.max(MIN_CONTINUATION).min(left),
            // the continuation is itself the tightening: it stops at its tolerance
            aim: 1.0,
            ..self.opts
        };
        // its miss is dropped, so its chain leaves out the cell program (math note §4.13)
        self.pipeline.vi.chain = self.chain.without(vi::Method::Cell);
        let more = self.pipeline.vi.solve(problem, rule, z, &tight);
        self.pipeline.vi.chain = self.chain;
        self.note(solve, more.converged);
        let report = vi::Report {
            outer_iterations: first.outer_iterations + more.outer_iterations,
            inner_iterations: first.inner_iterations + more.inner_iterations,
            ..if more.converged { more } else { first }
        };
        if !more.converged {
            z.copy_from_slice(&answer);
        }
        (report, more.converged)
    }

    /// Records the last VI solve's hand-overs and, when its answer is taken (`taken`), its
    /// method if it stands later in the chain than the step's answers so far.
    fn note(&mut self, solve: SolveKind, taken: bool) {
        let step = self.step;
        let vi = &self.pipeline.vi;
        let handovers =
            vi.handovers().iter().map(|h| HandOver { step, solve, from: h.from, to: h.to, why: h.why });
        self.handovers.extend(handovers);
        let answered = vi.stats().method.filter(|_| taken);
        let placed = answered.map(|m| (self.chain.position(m).unwrap_or(0), m));
        if placed.is_some_and(|p| self.method.is_none_or(|q| p.0 >= q.0)) {
            self.method = placed;
        }
    }

    /// Builds rows with the pipeline's storage, timing it.
    fn rows<T>(&mut self, build: impl FnOnce(&mut super::rows::Scratch) -> T) -> T {
        let started = Instant::now();
        let rows = build(&mut self.pipeline.rows);
        self.times.rows += started.elapsed().as_secs_f64();
        rows
    }
}

impl World {
    /// A force the contacts may legitimately carry this step, for the solver's divergence test
    /// (math note §4.9): the weight, applied loads and momentum per step of every free body.
    /// Speeds are √(u² + v²), not libm's `hypot`, whose care against overflow (from 1e154 m/s,
    /// where a run has long failed its motion checks) costs time in every step; the scale only
    /// sets a threshold, which moves by an ulp.
    fn force_scale(&self) -> f64 {
        let g = self.gravity(self.time + self.h).norm();
        let h = self.h;
        let norm = |v: &[f64]| (v[0] * v[0] + v[1] * v[1]).sqrt();
        let bodies: f64 = (self.bodies.iter().filter(|b| !b.fixed))
            .map(|b| {
                let speed = match &b.mesh {
                    // a mesh's velocity is per node: its fastest node
                    Some(fe) => (0..fe.nodes.len())
                        .map(|n| fe.node_value(&fe.velocity, n))
                        .map(|v| norm(&[v.x, v.y]))
                        .fold(0.0, f64::max),
                    None => norm(b.velocity.as_slice()) + b.velocity[2].abs() * b.reach,
                };
                b.mass * (g + 2.0 * speed / h)
            })
            .sum();
        let t = self.time + h;
        let loads: f64 = self.model.loads.iter().map(|l| l.force.norm() * l.factor(t).abs()).sum();
        bodies + loads
    }

    /// Solve 1 with g0 in the gaps (geometry), refined on the mid-step configuration; then
    /// solve 2 with g0 dropped for the contacts closed in solve 1 (velocity), skipped when
    /// those g0 are all zero to within the allowance (math note §1.3 a, d; §10.5).
    pub(super) fn solve(
        &self,
        found: &Detected,
        inputs: Inputs,
        df: &[f64],
        pipeline: &mut Pipeline,
    ) -> Solved {
        let Inputs { warm: mut z1, laws, mut lin } = inputs;
        let mut runner = self.runner(&z1, pipeline);
        let mut refinements = 0;
        // the rows of the last solve 1, the patches of a further refinement (`None`: the rows'
        // own linearization), the response to z1 and the increment; whether the solver's last
        // product is of z1 (the gaps came from it)
        let (rows, state, last, dp1, increment, product) = loop {
            let rows = runner.rows(|a| self.rows(found, lin, df, |_| false, a));
            let kind = if refinements == 0 { SolveKind::Geometry } else { SolveKind::GeometryRefined };
            let gaps = runner.run(self, &laws, &rows, &rows.q, &mut z1, kind, false);
            let product = gaps.is_some();
            let state = self.classify(found, &rows, &z1, gaps);
            let dp = self.response(&rows, &z1, None);
            let dbar = self.geometry_increment(found, &rows, &laws, df, &z1, &dp, &state);
            let motions = self.motions(&found.reach, &dbar);
            let shapes = &mut runner.pipeline.shapes;
            let next = (refinements < MAX_REFINEMENTS)
                .then(|| self.refine(found, &rows.lin, &dbar, &motions, &state, shapes))
                .flatten();
            match next {
                Some(next) if next.changed => {
                    lin = next.apply(&rows.lin);
                    runner.pipeline.recycle(rows);
                    refinements += 1;
                }
                next => break (rows, state, next, dp, Increment { dbar, motions }, product),
            }
        };
        let rows2 = runner.rows(|a| self.impact_rows(found, &rows.lin, last.as_ref(), &state, df, a));
        // restitution and friction stops (math note §10.15): offsets of solve 2's gaps
        let targets = self.velocity_targets(found, rows2.as_ref().unwrap_or(&rows), &laws, &state);
        let (z2, dp2) = match rows2.is_some() || state.velocity || targets.is_some() {
            true => self.velocity_solve(
                &mut runner,
                found,
                &laws,
                (&rows, rows2.as_ref()),
                &state,
                &z1,
                targets,
                product,
            ),
            false => (z1.clone(), None),
        };
        let w_diag_max = rows.w.largest_diagonal();
        let (report, warnings, times) = (runner.report, runner.warnings, runner.times);
        let (method, handovers) = (runner.method.map(|(_, m)| m), runner.handovers);
        Solved {
            laws,
            rows,
            rows2,
            z1,
            z2,
            dp1,
            dp2,
            increment,
            state,
            report,
            warnings,
            w_diag_max,
            times,
            method,
            handovers,
        }
    }

    /// The step's VI options and the runner of its solves (math note §10.11: a cold step, z1 all
    /// zero, continues each solve to the tightened tolerances).
    fn runner<'a>(&self, z1: &[f64], pipeline: &'a mut Pipeline) -> Runner<'a> {
        let opts = vi::Options {
            tolerance: self.model.solver.tolerance,
            max_iterations: self.model.solver.max_iterations,
            max_outer: MAX_PASSES,
            jacobi: self.settings.jacobi,
            gap_tolerance: self.model.solver.tolerance * self.feature,
            force_scale: self.force_scale(),
            aim: self.settings.aim,
        };
        // a cold step (math note §10.11): its error becomes the motion later steps inherit
        let factor = self.settings.cold_tightening;
        let tighten = (factor < 1.0 && z1.iter().all(|&x| x == 0.0)).then_some(factor);
        Runner {
            opts,
            budget: self.model.solver.max_iterations,
            chain: self.model.solver.method,
            method: None,
            handovers: Vec::new(),
            tighten,
            step: self.step_index + 1,
            report: vi::Report { outer_iterations: 0, inner_iterations: 0, residual: 0.0, converged: true },
            warnings: Vec::new(),
            pipeline,
            times: SolveTimes::default(),
        }
    }

    /// Solve 2 (velocity, math note §1.3 d) on solve 1's rows or its own (`rows`), with the
    /// offsets of restitution and friction stops (`targets`, §10.15), from z1: z2 and, when z2
    /// is not z1 on solve 1's rows, its response. `product`: the solver's last product is of z1.
    #[allow(clippy::too_many_arguments)]
    fn velocity_solve(
        &self,
        runner: &mut Runner,
        found: &Detected,
        laws: &[Law],
        (rows, rows2): (&Rows, Option<&Rows>),
        state: &Classified,
        z1: &[f64],
        targets: Option<super::velocity::Targets>,
        product: bool,
    ) -> (Vec<f64>, Option<Vec<f64>>) {
        let solve2 = rows2.unwrap_or(rows);
        let plain = velocity_gaps(&found.brief, &solve2.q, state);
        let offset = |o: &[f64]| plain.iter().zip(o).map(|(q, o)| q + o).collect::<Vec<f64>>();
        let q2 = targets.as_ref().map_or_else(|| plain.clone(), |t| offset(&t.offsets));
        let mut z2 = z1.to_vec();
        let again = rows2.is_none() && product;
        let (warned, report) = (runner.warnings.len(), runner.report);
        runner.run(self, laws, solve2, &q2, &mut z2, SolveKind::Velocity, again);
        // a solve 2 with friction stops that misses: solved again without them (§10.15)
        let missed = runner.warnings.len() > warned;
        let fallback = targets.as_ref().filter(|t| missed && !t.stops.is_empty());
        if let Some(t) = fallback {
            let (step, spent) = (runner.step, runner.report.inner_iterations - report.inner_iterations);
            let residual = runner.report.residual;
            runner.warnings.truncate(warned);
            runner.report = vi::Report { inner_iterations: runner.report.inner_iterations, ..report };
            runner.warnings.push(Warning::StopsDropped { step, residual, iterations: spent });
            z2.copy_from_slice(z1);
            match t.without_stops() {
                Some(o) => runner.run(self, laws, solve2, &offset(&o), &mut z2, SolveKind::Velocity, false),
                // solve 2 without offsets is solve 1 when nothing else changed its gaps
                None if rows2.is_none() && !state.velocity => None,
                None => runner.run(self, laws, solve2, &plain, &mut z2, SolveKind::Velocity, false),
            };
        }
        // z1 kept bit for bit on solve 1's rows: its response is dp1
        let same = rows2.is_none() && z2.iter().zip(z1).all(|(a, b)| a.to_bits() == b.to_bits());
        let dp2 = (!same).then(|| self.response(solve2, &z2, None));
        (z2, dp2)
    }

    /// Impacts act on the rigid-body DOFs (math note §10.3): when an impacting contact
    /// touches a deformable body, solve 2 gets its own rows with zero strain columns for the
    /// impacting contacts.
    fn impact_rows(
        &self,
        found: &Detected,
        lin: &[Linearization],
        refined: Option<&Refined>,
        state: &Classified,
        df: &[f64],
        scratch: &mut super::rows::Scratch,
    ) -> Option<Rows> {
        let contacts = &found.brief;
        let impacting = |k: usize| state.impacting_rows[contacts[k].row()];
        let deformable_impact = state.impacts
            && (0..contacts.len())
                .any(|k| impacting(k) && contacts[k].bodies().iter().any(|&b| self.bodies[b].deformable));
        deformable_impact.then(|| {
            let lin = refined.map_or_else(|| lin.to_vec(), |r| r.apply(lin));
            self.rows(found, lin, df, impacting, scratch)
        })
    }

    /// Ten times the gap accuracy of a solve: tolerance × max(1, |z|max) × max W_jj (the
    /// scaled natural residual bounds |G_j| by D_jj res |z|), at least 1e-9 d0 (§10.2).
    pub(super) fn gap_accuracy(&self, s: &Solved) -> f64 {
        let zmax = s.z1.iter().fold(1.0f64, |m, z| m.max(z.abs()));
        (10.0 * self.model.solver.tolerance * zmax * s.w_diag_max).max(1e-9 * self.threshold)
    }

    /// End-of-step gaps G = q + W z (`gaps` when the solver had them from its last product, else
    /// one product here), which contacts are closed (bonded, loaded, or touching at the end of
    /// the step to within the penetration allowance), and the rows of impacting contacts (math
    /// note §10.5).
    fn classify(&self, found: &Detected, rows: &Rows, z: &[f64], gaps: Option<Vec<f64>>) -> Classified {
        let gaps = gaps.unwrap_or_else(|| {
            let mut gaps = vec![0.0; z.len()];
            rows.w.apply(z, &mut gaps);
            gaps.iter_mut().zip(&rows.q).for_each(|(g, q)| *g += q);
            gaps
        });
        let touching = self.allowance;
        // one pass over the briefs; a contact itself only for a possible impact
        let mut closed = Vec::with_capacity(found.brief.len());
        let mut impacting_rows = vec![false; rows.q.len()];
        let (mut impacts, mut velocity, mut bonded) = (false, false, false);
        for (k, c) in found.brief.iter().enumerate() {
            bonded |= c.bonded;
            let r = c.row();
            let cl = c.bonded || z[r] > 0.0 || gaps[r] <= touching;
            if cl && !c.was_closed && self.is_impacting(found.geoms.get(k)) {
                impacting_rows[c.rows()].fill(true);
                impacts = true;
            }
            velocity |= cl && c.start_gap != 0.0;
            closed.push(cl);
        }
        Classified { gaps, closed, impacting_rows, impacts, velocity, bonded }
    }

    /// Math note §1.3 (b), §10.5: not closed at the end of the last step and approaching at
    /// the step start faster than the allowance per step (the caller checks that it closed
    /// in solve 1 and was not closed at the end of the last step). A slower approach is the
    /// solver's own noise, not an impact: doubling a resting contact's share would push its
    /// bodies into their neighbours.
    fn is_impacting(&self, c: &ContactGeom) -> bool {
        let x = c.point;
        let velocity = |b: usize| {
            let body = &self.bodies[b];
            body.displacement(x, &self.v0(body))
        };
        let rate = c.normal.dot(&(velocity(c.a) - velocity(c.b)));
        rate * self.h < -self.allowance
    }

    /// d̄ = d^f + K̃⁻¹ Bᵀ z + K̃⁻¹ B_impᵀ e z_imp: the geometry increment with the impacting
    /// contacts' share taken 1 + e times (math note §1.3 c, §10.15; e the restitution) on the
    /// bodies it does not drive into others (§10.12, [`Self::hold_driven_bodies`]), as a global
    /// DOF vector, from the response `dp` = K̃⁻¹ Bᵀ z.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn geometry_increment(
        &self,
        found: &Detected,
        rows: &Rows,
        laws: &[Law],
        df: &[f64],
        z: &[f64],
        dp: &[f64],
        state: &Classified,
    ) -> Vec<f64> {
        let mut d: Vec<f64> = dp.iter().zip(df).map(|(x, f)| x + f).collect();
        if state.impacts {
            let scaled = restituted(found, laws, z, state);
            let z = scaled.as_deref().unwrap_or(z);
            let mut dimp = self.response(rows, z, Some(&state.impacting_rows));
            self.hold_driven_bodies(found, rows, z, state, &mut dimp);
            d.iter_mut().zip(&dimp).for_each(|(x, y)| *x += y);
        }
        d
    }

    /// Math note §10.12: the doubled share K̃⁻¹ B_impᵀ z_imp moves every contact's gap by
    /// W z_imp (to first order). A contact that is not impacting and would end below
    /// −allowance, G(z1) + W z_imp, has its bodies held where solve 1 put them: their part of
    /// the share is dropped. So an impact into a body its other contacts hold (a jammed pile,
    /// disks resting on a floor under a landing block) mirrors only the bodies that are free to
    /// move, and an isolated impact is mirrored in full (math note §1.3 c), bit for bit.
    fn hold_driven_bodies(
        &self,
        found: &Detected,
        rows: &Rows,
        z: &[f64],
        state: &Classified,
        dimp: &mut [f64],
    ) {
        let impacting = &state.impacting_rows;
        let zi: Vec<f64> = z.iter().zip(impacting).map(|(z, &i)| if i { *z } else { 0.0 }).collect();
        let mut dg = vec![0.0; z.len()];
        rows.w.apply(&zi, &mut dg);
        for c in &found.brief {
            let r = c.row();
            if !impacting[r] && state.gaps[r] + dg[r] < -self.allowance {
                c.bodies().iter().for_each(|&b| dimp[self.dof_map().range(b)].fill(0.0));
            }
        }
    }

    /// K̃⁻¹ Bᵀ z over the rows `keep` selects, all of them with `None` (paper eq. 22: d^p = K⁻¹
    /// C p).
    pub(super) fn response(&self, rows: &Rows, z: &[f64], keep: Option<&[bool]>) -> Vec<f64> {
        let mut out = vec![0.0; self.dof_map().total()];
        // every row kept, each on a body in body form: through W's bodies (their frames, a third
        // of B's bytes, and on a large pile both cores)
        if keep.is_none() && rows.w.response(z, &mut out) {
            return out;
        }
        rows.jac().transpose_apply(z, |r| keep.is_none_or(|k| k[r]), &mut out);
        self.flex.solve_in_place(self.dof_map(), &mut out);
        out
    }
}

/// z with the rows of each impacting contact times its restitution e (math note §10.15), or
/// `None` when every impacting contact is elastic (e = 1: z itself, bit for bit).
fn restituted(found: &Detected, laws: &[Law], z: &[f64], state: &Classified) -> Option<Vec<f64>> {
    let impacting = |c: &Brief| state.impacting_rows[c.row()];
    let elastic = found.brief.iter().zip(laws).all(|(c, l)| l.restitution == 1.0 || !impacting(c));
    if elastic {
        return None;
    }
    let mut ze = z.to_vec();
    for (c, l) in found.brief.iter().zip(laws).filter(|(c, _)| impacting(c)) {
        ze[c.rows()].iter_mut().for_each(|x| *x *= l.restitution);
    }
    Some(ze)
}

/// The gaps of solve 2, the velocity solve (math note §1.3 d): the offset of every contact
/// closed in solve 1 loses its g0 (split impulse), so that the velocity follows from the
/// constraint alone (an impacting contact reflects its approach velocity).
fn velocity_gaps(contacts: &[Brief], q: &[f64], state: &Classified) -> Vec<f64> {
    let mut q2 = q.to_vec();
    for (c, &closed) in contacts.iter().zip(&state.closed) {
        if closed {
            q2[c.row()] -= c.start_gap;
        }
    }
    q2
}
