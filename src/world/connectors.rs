//! Connectors in the step (math note §6): their stiffness joins the clusters' K̃, the force
//! they carried into the step is a load, a connector whose tension would exceed its strength
//! breaks and the step is solved again without it, and after the step their forces and anchors
//! follow the bodies' increments.

use super::adaptive::Part;
use super::{Event, World};
use crate::cluster::{CouplingBlock, Flexibility};
use crate::dofs::DofMap;

impl World {
    /// Pairs of bodies joined by an intact connector.
    pub(super) fn coupled_pairs(&self) -> Vec<(usize, usize)> {
        self.connectors.iter().filter(|c| !c.broken).map(|c| (c.bodies[0], c.bodies[1])).collect()
    }

    /// The DOF map and clusters for the current connector graph; the factors start afresh.
    pub(super) fn renumber(&mut self) {
        self.keep(Part::Dofs);
        self.dofs = DofMap::new(&self.bodies, &self.coupled_pairs());
        self.flex =
            Flexibility::new(self.settings.sparse_only).with_factor_drift(self.model.solver.factor_drift);
    }

    /// Stiffness blocks of the intact connectors, step-start geometry (math note §6).
    pub(super) fn couplings(&self) -> Vec<CouplingBlock> {
        self.connectors.iter().flat_map(|c| c.stiffness(&self.bodies)).collect()
    }

    /// Adds the forces the connectors carried into the step to the global load vector (§6).
    pub(super) fn add_connector_loads(&self, f: &mut [f64]) {
        for c in &self.connectors {
            for (b, cols, load) in c.carried_load(&self.bodies) {
                let at = self.dofs.range(b).start;
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
        for k in 0..self.connectors.len() {
            let force = {
                let d = body_dof(&self.dofs, dbar);
                let mut trial = self.connectors[k].clone();
                trial.update(&self.bodies, &d);
                if trial.exceeds_strength() {
                    Some(trial.axial_force())
                } else {
                    self.connectors[k].passes_ultimate_strain(&self.bodies, &d)
                }
            };
            if let Some(force) = force {
                self.keep(Part::Connectors);
                let c = &mut self.connectors[k];
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
        for k in 0..self.connectors.len() {
            let mut c = self.connectors[k].clone();
            if c.switch_yield(&self.bodies, &body_dof(&self.dofs, dbar)) {
                self.keep(Part::Connectors);
                self.connectors[k] = c;
                switched = true;
            }
        }
        switched
    }

    /// After the step, before the bodies move: forces from the increments, anchors moved with
    /// their bodies (the bodies are still in the step-start state the stiffness was built on).
    pub(super) fn update_connectors(&mut self, dbar: &[f64], step: usize) {
        self.keep(Part::Connectors);
        let (bodies, d) = (&self.bodies, body_dof(&self.dofs, dbar));
        for c in &mut self.connectors {
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
