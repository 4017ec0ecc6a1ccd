//! Yielding and ultimate strain of bolts (math note §6.1): an elastic-perfectly-plastic axial
//! force, `N = EA (ε − ε_p)` with `|N| ≤ Y`, the plastic strain `ε_p` carried between steps, and
//! a break for good once the total strain `ε = (l − l_r)/l_r` passes the ultimate strain.
//!
//! Inside the implicit step the cap is an active set: a bolt whose elastic trial force would pass
//! `Y` is solved again as the constant axial force `±Y` with no axial stiffness, so that its force
//! at the step's end, where the scheme evaluates the equation of motion, is exactly `±Y`; a
//! yielding bolt whose elastic trial falls below `Y` (it unloads) is solved again elastically.

use super::{Connector, ConnectorForce, ConnectorKind};
use crate::body::Body;

impl Connector {
    /// Bolt: the axial (total) strain `(l − l_r)/l_r` at the anchors' current distance, from the
    /// rest length `l_r` (math note §10.7); `None` for the other kinds.
    pub fn strain(&self) -> Option<f64> {
        let rest = self.rest_length.filter(|_| matches!(self.kind, ConnectorKind::Bolt { .. }))?;
        Some((self.length() - rest) / rest)
    }

    /// Whether the bolt is at its yield force (intact, plastic).
    pub fn is_yielding(&self) -> bool {
        !self.broken && self.plastic.is_some()
    }

    /// Whether it ended the last step yielding having ended the step before elastic: the step it
    /// started to yield in.
    pub fn started_yielding(&self) -> bool {
        self.began_yielding
    }

    /// The active-set switch of math note §6.1 after a solve with DOF increments `d` (as
    /// [`Connector::update`] takes them): an elastic bolt whose elastic trial force `EA (ε − ε_p)`
    /// passes `Y` becomes the constant force `±Y`; a yielding one whose trial falls below `Y`
    /// (unloading) becomes elastic again. Returns whether it switched (the step must be solved
    /// again).
    pub fn switch_yield(&mut self, bodies_before: &[Body], d: &dyn Fn(usize, usize) -> f64) -> bool {
        let Some(y) = self.yield_force.filter(|_| !self.broken) else { return false };
        let mut trial = self.clone();
        trial.move_points(bodies_before, d);
        let Some(n) = trial.axial_from_length() else { return false };
        match self.plastic {
            None if n.abs() > y => self.plastic = Some(y.copysign(n)),
            Some(p) if n * p.signum() < y => self.plastic = None,
            _ => return false,
        }
        true
    }

    /// Whether the total strain after the increments `d` would pass the ultimate strain: the bolt
    /// breaks for good and the step is solved again without it. Returns the axial force it
    /// breaks at.
    pub fn passes_ultimate_strain(
        &self,
        bodies_before: &[Body],
        d: &dyn Fn(usize, usize) -> f64,
    ) -> Option<f64> {
        let limit = self.ultimate_strain.filter(|_| !self.broken)?;
        let mut trial = self.clone();
        trial.move_anchors(bodies_before, d);
        trial.strain().is_some_and(|e| e > limit).then(|| trial.axial_force())
    }

    /// After the step, the force from the anchors' true distance: at or beyond `Y` the plastic
    /// strain takes the excess, `ε_p += (N − ±Y)/EA`, and the force is `±Y` (exact when the active
    /// set held the bolt at `±Y`, whose trial then is at least `Y`); below it the bolt is elastic.
    pub(super) fn return_to_yield(&mut self) {
        let (Some(y), ConnectorKind::Bolt { young, area }, ConnectorForce::Axial(n)) =
            (self.yield_force, self.kind, self.force)
        else {
            return;
        };
        if n.abs() >= y {
            let cap = y.copysign(n);
            self.plastic_strain += (n - cap) / (young * area);
            self.force = ConnectorForce::Axial(cap);
            self.plastic = Some(cap);
        } else {
            self.plastic = None;
        }
        self.began_yielding = self.plastic.is_some() && !self.ended_yielding;
        self.ended_yielding = self.plastic.is_some();
    }
}
