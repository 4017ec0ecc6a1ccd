//! Connectors in the step (math note §6): their stiffness joins the clusters' K̃, the force
//! they carried into the step is a load, a connector whose tension would exceed its strength
//! breaks and the step is solved again without it, and after the step their forces and anchors
//! follow the bodies' increments. Within a trial they are the trial's connectors
//! (`adaptive::Next`), which replace the World's when the trial is committed.

use super::{Event, World};
use crate::cluster::{CouplingBlock, Flexibility};
use crate::connector::Connector;
use crate::dofs::DofMap;

/// Pairs of bodies joined by an intact connector of `connectors`.
fn coupled_pairs(connectors: &[Connector]) -> Vec<(usize, usize)> {
    connectors.iter().filter(|c| !c.broken).map(|c| (c.bodies[0], c.bodies[1])).collect()
}

impl World {
    /// The DOF map and clusters for the World's connector graph; the factors start afresh.
    pub(super) fn renumber(&mut self) {
        self.dofs = DofMap::new(&self.bodies, &coupled_pairs(&self.connectors));
        self.fresh_factors();
    }

    /// The running trial's DOF map and clusters for its connector graph, after a connector
    /// broke in it; the factors start afresh.
    pub(super) fn renumber_trial(&mut self) {
        self.next.dofs = Some(DofMap::new(&self.bodies, &coupled_pairs(&self.next.connectors)));
        self.fresh_factors();
    }

    fn fresh_factors(&mut self) {
        self.flex =
            Flexibility::new(self.settings.sparse_only).with_factor_drift(self.model.solver.factor_drift);
    }

    /// Stiffness blocks of the trial's intact connectors, step-start geometry (math note §6).
    pub(super) fn couplings(&self) -> Vec<CouplingBlock> {
        self.next.connectors.iter().flat_map(|c| c.stiffness(&self.bodies)).collect()
    }

    /// Adds the forces the connectors carried into the step to the global load vector (§6).
    pub(super) fn add_connector_loads(&self, f: &mut [f64]) {
        for c in &self.next.connectors {
            for (b, cols, load) in c.carried_load(&self.bodies) {
                let at = self.dof_map().range(b).start;
                for (&i, v) in cols.iter().zip(load.iter()) {
                    f[at + i] += v;
                }
            }
        }
    }

    /// Connectors whose tension after the increment `dbar` (a global DOF vector) would exceed
    /// their strength: they break for good (math note §6), and the caller solves the step again
    /// without them.
    pub(super) fn break_connectors(&mut self, dbar: &[f64], step: usize) -> Vec<Event> {
        let mut events = Vec::new();
        for k in 0..self.next.connectors.len() {
            let force = {
                let d = body_dof(self.dof_map(), dbar);
                let mut trial = self.next.connectors[k].clone();
                trial.update(&self.bodies, &d);
                if trial.exceeds_strength() {
                    Some(trial.axial_force())
                } else {
                    self.next.connectors[k].passes_ultimate_strain(&self.bodies, &d)
                }
            };
            if let Some(force) = force {
                let c = &mut self.next.connectors[k];
                c.break_off();
                c.broken_at = Some(step);
                c.broke_with = Some(force);
                events.push(Event::ConnectorBroke { step, connector: c.name.clone(), force });
            }
        }
        events
    }

    /// The yield active set (math note §6.1): bolts whose elastic trial after the increment
    /// `dbar` passes their yield force become the constant force ±Y, yielding ones that unload
    /// become elastic. Returns whether any switched (the caller solves the step again).
    pub(super) fn switch_yields(&mut self, dbar: &[f64]) -> bool {
        let mut switched = false;
        for k in 0..self.next.connectors.len() {
            let mut c = self.next.connectors[k].clone();
            if c.switch_yield(&self.bodies, &body_dof(self.dof_map(), dbar)) {
                self.next.connectors[k] = c;
                switched = true;
            }
        }
        switched
    }

    /// The trial's connectors after it, before the bodies move: forces from the increments,
    /// anchors moved with their bodies (the bodies are still in the step-start state the
    /// stiffness was built on). Called by the commit, with the trial's DOF map in place.
    pub(super) fn update_connectors(&mut self, dbar: &[f64], step: usize) {
        let (bodies, d) = (&self.bodies, body_dof(&self.dofs, dbar));
        for c in &mut self.next.connectors {
            c.update(bodies, &d);
            c.move_anchors(bodies, &d);
            if c.started_yielding() {
                c.yielded_at = Some(step);
            }
        }
    }
}

/// DOF i of body b in the global vector `v`, as `Connector::update` and `move_anchors` take it.
fn body_dof<'a>(dofs: &'a DofMap, v: &'a [f64]) -> impl Fn(usize, usize) -> f64 + 'a {
    move |b, i| v[dofs.range(b).start + i]
}
