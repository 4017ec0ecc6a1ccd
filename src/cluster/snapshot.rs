//! The factorized step stiffness as a checkpoint keeps it ([`FlexState`]): every factor with
//! its numbers, not the configuration it was formed on. A factor is kept across steps (a rigid
//! body's from the last full refresh, a sparse cluster's while `factor_drift` allows, math note
//! §9.3), so it is a function of the run's history, not of the state at the checkpoint: a
//! factor formed again on loading would differ in the last bits. A sparse factor is saved as
//! its pattern, its numeric values and its cache of K⁻¹ entries (whose values depend on the
//! order in which DOFs joined it); the symbolic analysis, a function of the pattern, is done
//! again on loading.

use super::{Factor, Flexibility, Formed, STAMPS};
use crate::body::BodyMatrix;
use crate::sparse::inverse::InverseCache;
use crate::sparse::{SparseError, SparseFactor};
use serde::{Deserialize, Serialize};
use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex};

/// Everything of a [`Flexibility`] that the next refresh and solves read.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct FlexState {
    factors: Vec<FactorState>,
    sparse_only: bool,
    dt: f64,
    factor_drift: f64,
    formed: Vec<Option<Vec<Formed>>>,
    sparse_factorizations: usize,
    deforming: Vec<usize>,
    closed_at: Vec<u32>,
    closed: Vec<f64>,
}

/// One cluster's factor.
#[derive(Debug, Clone, Serialize, Deserialize)]
enum FactorState {
    // boxed: the variant is far larger than the others (postcard writes a box as its contents)
    Body { inverse: Box<BodyMatrix>, root: Box<BodyMatrix> },
    Dense { n: usize, inverse: Vec<f64>, root: Vec<f64> },
    Sparse(SparseState),
}

/// A sparse factor's pattern, numeric values and cached block of K⁻¹.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub(super) struct SparseState {
    pub n: usize,
    pub pattern: Vec<(usize, usize)>,
    pub numeric: Option<Vec<f64>>,
    pub inverse: InverseCache,
}

impl Flexibility {
    /// What a checkpoint keeps of this flexibility.
    pub fn state(&self) -> FlexState {
        let factors = self
            .factors
            .iter()
            .map(|f| match f.as_ref() {
                Factor::Body { inverse, root } => {
                    FactorState::Body { inverse: Box::new(*inverse), root: Box::new(*root) }
                }
                Factor::Dense(d) => {
                    FactorState::Dense { n: d.n, inverse: d.inverse.clone(), root: d.root.clone() }
                }
                Factor::Sparse(s) => FactorState::Sparse(s.state()),
            })
            .collect();
        FlexState {
            factors,
            sparse_only: self.sparse_only,
            dt: self.dt,
            factor_drift: self.factor_drift,
            formed: self.formed.clone(),
            sparse_factorizations: self.sparse_factorizations,
            deforming: self.deforming.clone(),
            closed_at: self.closed_at.clone(),
            closed: self.closed.as_ref().clone(),
        }
    }

    /// The flexibility `state` was taken of, with new stamps (what was derived from the old
    /// factors is derived again).
    pub fn from_state(state: FlexState) -> Result<Flexibility, SparseError> {
        let mut factors = Vec::with_capacity(state.factors.len());
        for f in state.factors {
            factors.push(Arc::new(match f {
                FactorState::Body { inverse, root } => Factor::Body { inverse: *inverse, root: *root },
                FactorState::Dense { n, inverse, root } => Factor::Dense(super::Dense { n, inverse, root }),
                FactorState::Sparse(s) => Factor::Sparse(SparseFactor::from_state(s)?),
            }));
        }
        let stamps = factors.iter().map(|_| STAMPS.fetch_add(1, Ordering::Relaxed)).collect();
        Ok(Flexibility {
            factors,
            stamps,
            sparse_only: state.sparse_only,
            dt: state.dt,
            factor_drift: state.factor_drift,
            formed: state.formed,
            sparse_factorizations: state.sparse_factorizations,
            deforming: state.deforming,
            closed_at: state.closed_at,
            closed: Arc::new(state.closed),
        })
    }
}

impl SparseFactor {
    fn state(&self) -> SparseState {
        let (n, pattern, numeric) = self.parts();
        let inverse = self.inverse_cache();
        SparseState { n, pattern: pattern.to_vec(), numeric: numeric.cloned(), inverse }
    }

    /// The factor of `state`: the symbolic analysis of its pattern done again (the same
    /// ordering: faer's AMD is a function of the pattern), its values and cache as saved.
    fn from_state(state: SparseState) -> Result<SparseFactor, SparseError> {
        let symbolic = match state.pattern.is_empty() && state.numeric.is_none() {
            true => None,
            false => Some(SparseFactor::analyse(state.n, &state.pattern)?),
        };
        Ok(SparseFactor::from_parts(
            state.n,
            state.pattern,
            symbolic,
            state.numeric,
            Mutex::new(state.inverse),
        ))
    }
}
