//! Validation of `[[stage]]` tables (math note §10.14): names, ends, `until_kinetic`,
//! `velocity_carry`, `remove`, the connectors' `stage` and the `set` entries. A stage's `set`
//! entries are `--set` overrides (`overrides.rs`), applied with those of every earlier stage to
//! the scene's text and read by the same reader, so each is checked as the scene's own keys are;
//! the reader's error is then reported at the entry.

use toml::Spanned;

use super::check::{Check, fail, positive, real, steps_until, unique_names};
use super::overrides::{Override, stage_settings};
use super::{Problem, SceneError, raw};
use crate::model::{Model, Stage, StageSettings};

/// The stages of `raw`, for the model `model` read from `source` without them.
pub(super) fn stages(
    raw: &raw::Scene,
    source: &str,
    file: &str,
    model: &Model,
) -> Result<Vec<Stage>, SceneError> {
    let fail_at = |p: Problem| p.into_error(source, file);
    let mut stages = ends(raw, model).map_err(fail_at)?;
    for (i, s) in raw.stage.iter().enumerate() {
        stages[i].remove = removals(s.get_ref(), model, &stages[..i]).map_err(fail_at)?;
    }
    connector_stages(raw, &mut stages).map_err(fail_at)?;
    excavation_stages(raw, model, &mut stages).map_err(fail_at)?;
    let base = StageSettings {
        physics: model.physics,
        solver: model.solver,
        interfaces: model.interfaces.clone(),
        loads: model.loads.clone(),
        gravity_history: model.gravity_history.clone(),
    };
    let mut overrides: Vec<Override> = Vec::new();
    let mut settings = base;
    for (i, s) in raw.stage.iter().enumerate() {
        let entries = s.get_ref().set.as_ref().map_or(&[][..], |v| v.get_ref().as_slice());
        for entry in entries {
            overrides.push(allowed(entry).map_err(fail_at)?);
            stages[i].set.push(entry.get_ref().clone());
        }
        if !entries.is_empty() {
            let m = stage_settings(source, file, &overrides).map_err(|e| blame(e, entries, source, file))?;
            settings = StageSettings {
                physics: m.physics,
                solver: m.solver,
                interfaces: m.interfaces,
                loads: m.loads,
                gravity_history: m.gravity_history,
            };
        }
        stages[i].settings = settings.clone();
        if let Some(k) = stage_carry(s.get_ref()).map_err(fail_at)? {
            stages[i].settings.physics.velocity_carry = k;
        }
    }
    Ok(stages)
}

/// Names, ends (each after the previous one by at least a step) and `until_kinetic`; the run's
/// `[time]` must not end after the last stage (it may end before it: the run stops there, as
/// `--set time.steps=4` does for a quick look at a staged scene).
fn ends(raw: &raw::Scene, model: &Model) -> Check<Vec<Stage>> {
    unique_names(raw.stage.iter().map(|s| &s.get_ref().name), "stage")?;
    let dt = model.time.step;
    let mut stages: Vec<Stage> = Vec::with_capacity(raw.stage.len());
    for s in raw.stage.iter().map(Spanned::get_ref) {
        let end = positive(&s.end, "end")?;
        let end_step = steps_until(end, dt, s.end.span())?;
        if let Some(prev) = stages.last()
            && end_step <= prev.end_step
        {
            let message = format!(
                "end = {end} (step {end_step}) must come at least one step of {dt} after the end of the \
                 previous stage \"{}\" (end = {}, step {})",
                prev.name, prev.end, prev.end_step
            );
            return fail(s.end.span(), message);
        }
        stages.push(Stage {
            name: s.name.get_ref().clone(),
            end,
            end_step,
            until_kinetic: s.until_kinetic.as_ref().map(|u| positive(u, "until_kinetic")).transpose()?,
            remove: Vec::new(),
            connectors: Vec::new(),
            set: Vec::new(),
            settings: placeholder(model),
        });
    }
    let time = raw.time.get_ref();
    if let (Some(last), Some(span)) =
        (stages.last(), time.end.as_ref().map(Spanned::span).or(time.steps.as_ref().map(Spanned::span)))
        && model.time.steps > last.end_step
    {
        let message = format!(
            "the run has {} steps, but its last stage \"{}\" ends at {} (step {}): with stages, leave out \
             [time] `end` and `steps`, or make them end with the last stage (or before it, to stop the run \
             early)",
            model.time.steps, last.name, last.end, last.end_step
        );
        return fail(span, message);
    }
    Ok(stages)
}

/// The scene's own settings, until `stages` sets each stage's.
fn placeholder(model: &Model) -> StageSettings {
    StageSettings {
        physics: model.physics,
        solver: model.solver,
        interfaces: Vec::new(),
        loads: Vec::new(),
        gravity_history: None,
    }
}

fn stage_carry(s: &raw::Stage) -> Check<Option<f64>> {
    let between = |k: f64| (0.0..=1.0).contains(&k);
    s.velocity_carry.as_ref().map(|v| real(v, "velocity_carry", "be between 0 and 1", between)).transpose()
}

/// The bodies `remove` names, directly or through an excavation: sorted, once each; none may
/// have been removed by an earlier stage (`earlier`).
fn removals(s: &raw::Stage, model: &Model, earlier: &[Stage]) -> Check<Vec<usize>> {
    let Some(names) = &s.remove else { return Ok(Vec::new()) };
    let mut bodies = Vec::new();
    for name in names.get_ref() {
        let n = name.get_ref().as_str();
        let found: Vec<usize> = match model.bodies.iter().position(|b| b.name == n) {
            Some(b) => vec![b],
            None => match model.excavations.iter().find(|e| e.name == n) {
                Some(e) => e.bodies.clone(),
                None => return fail(name.span(), format!("remove: no body or excavation is named \"{n}\"")),
            },
        };
        for b in found {
            if let Some(stage) = earlier.iter().find(|st| st.remove.contains(&b)) {
                let body = &model.bodies[b].name;
                let message =
                    format!("remove: body \"{body}\" is already removed by stage \"{}\"", stage.name);
                return fail(name.span(), message);
            }
            bodies.push(b);
        }
    }
    bodies.sort_unstable();
    bodies.dedup();
    Ok(bodies)
}

/// Each excavation's `stage`: its blocks are removed at that stage's start (as if the stage's
/// `remove` named it).
fn excavation_stages(raw: &raw::Scene, model: &Model, stages: &mut [Stage]) -> Check<()> {
    for x in raw.excavation.iter().map(Spanned::get_ref) {
        let Some(name) = &x.stage else { continue };
        let n = name.get_ref();
        let Some(stage) = stages.iter_mut().find(|s| s.name == *n) else {
            return fail(name.span(), format!("no [[stage]] is named \"{n}\""));
        };
        let bodies = model.excavations.iter().filter(|e| e.name == *x.name.get_ref()).flat_map(|e| &e.bodies);
        stage.remove.extend(bodies);
        stage.remove.sort_unstable();
        stage.remove.dedup();
    }
    Ok(())
}

/// Each connector's `stage`: it comes into being at that stage's start.
fn connector_stages(raw: &raw::Scene, stages: &mut [Stage]) -> Check<()> {
    for (i, c) in raw.connector.iter().enumerate() {
        let Some(name) = &c.get_ref().stage else { continue };
        let n = name.get_ref();
        match stages.iter_mut().find(|s| s.name == *n) {
            Some(stage) => stage.connectors.push(i),
            None => return fail(name.span(), format!("no [[stage]] is named \"{n}\"")),
        }
    }
    Ok(())
}

/// The tables a stage's `set` may change: the contact laws, physics, solver and loads, not the
/// geometry (bodies, the plane, anchors and load points), the materials (the bodies' mass and
/// stiffness are built from them at t = 0), time or output, and no name.
fn allowed(entry: &Spanned<String>) -> Check<Override> {
    let ov = Override::parse(entry.get_ref()).map_err(|m| Problem::new(entry.span(), format!("set: {m}")))?;
    let key = ov.key.as_str();
    let table = key.split(['.', '[']).next().unwrap_or("");
    let last = key.rsplit('.').next().unwrap_or("").split('[').next().unwrap_or("");
    let ok = match table {
        "interface" | "solver" => true,
        "physics" => last != "plane",
        "load" => !matches!(last, "body" | "point"),
        _ => false,
    };
    if !ok || last == "name" {
        let message = format!(
            "set: `{key}` cannot change at a stage: a stage may set interface, physics (not plane), solver and \
             load (not body or point) keys, never geometry, materials, time, output or names"
        );
        return fail(entry.span(), message);
    }
    Ok(ov)
}

/// The reader's error `e` for the overrides up to a stage, reported at the stage's entry that
/// caused it (the one the message names; the last one when none is named).
fn blame(e: SceneError, entries: &[Spanned<String>], source: &str, file: &str) -> SceneError {
    let named = |entry: &&Spanned<String>| {
        Override::parse(entry.get_ref()).is_ok_and(|ov| e.message.starts_with(&format!("--set {ov}:")))
    };
    let Some(entry) = entries.iter().find(named).or(entries.last()) else { return e };
    let key = if e.key.is_empty() { String::new() } else { format!("{}: ", e.key) };
    let message = format!("set: {key}{}", e.message);
    Problem::new(entry.span(), message).into_error(source, file)
}
