//! Box-constrained affine variational inequality solver (math note §4). Pure mathematics:
//! it knows nothing about bodies or contacts.
//!
//! Find z in Ω = [lo, hi] with (z' - z)ᵀ G(z) >= 0 for all z' in Ω, G(z) = q + W z,
//! W symmetric positive semidefinite (sparse CSR). The bounds may depend on z (a QVI);
//! a [`BoundRule`] recomputes them in the outer compatibility loop.

use sprs::CsMat;

/// The affine map G(z) = q + W z.
pub struct Problem<'a> {
    pub w: &'a CsMat<f64>,
    pub q: &'a [f64],
}

/// Recomputes the box from the current iterate (math note §4.3).
pub trait BoundRule {
    /// Writes the bounds valid for the iterate `z` into `lo`, `hi` (±inf allowed).
    fn bounds(&mut self, z: &[f64], lo: &mut [f64], hi: &mut [f64]);
}

/// Bounds that do not depend on z: a plain VI.
pub struct FixedBounds {
    pub lo: Vec<f64>,
    pub hi: Vec<f64>,
}

impl BoundRule for FixedBounds {
    fn bounds(&mut self, _z: &[f64], lo: &mut [f64], hi: &mut [f64]) {
        lo.copy_from_slice(&self.lo);
        hi.copy_from_slice(&self.hi);
    }
}

#[derive(Debug, Clone, Copy)]
pub struct Options {
    /// Scaled natural residual to reach (math note §4.3).
    pub tolerance: f64,
    /// Cap on inner PC iterations, all outer loops together.
    pub max_iterations: usize,
    /// Cap on outer (bound-update) iterations.
    pub max_outer: usize,
    /// Jacobi scaling z = D^{-1/2} y (math note §4.2).
    pub jacobi: bool,
}

impl Default for Options {
    fn default() -> Self {
        Self { tolerance: 1e-8, max_iterations: 200_000, max_outer: 50, jacobi: true }
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Report {
    pub outer_iterations: usize,
    pub inner_iterations: usize,
    /// Final scaled natural residual with the final bounds.
    pub residual: f64,
    pub converged: bool,
}

/// Solves the (Q)VI, starting from and overwriting `z` (warm start).
pub fn solve(_p: &Problem, _bounds: &mut dyn BoundRule, _z: &mut [f64], _opts: &Options) -> Report {
    todo!("projection-contraction solver")
}
