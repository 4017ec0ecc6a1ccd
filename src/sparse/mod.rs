//! Sparse linear algebra, a leaf module (it uses no other module of the crate): faer's sparse
//! Cholesky with its kept symbolic analysis and the block of the inverse over the DOFs that
//! contacts touch ([`SparseFactor`], math note §9.3), used by the clusters' flexibilities
//! (`crate::cluster`) and by MPRGP's face solves (`crate::vi`).

mod factor;
pub(crate) mod inverse;

pub use factor::{SparseError, SparseFactor};

/// W's one matrix type (the Delassus operator W = B K̃⁻¹ Bᵀ when it is stored explicitly,
/// `crate::delassus`): compressed sparse rows of `f64` with `usize` indices, both triangles,
/// sprs's `CsMat`. The VI solvers read W through [`CsrView`]; factorizations are faer's
/// ([`SparseFactor`] here, the LU factors of `crate::vi`'s Newton and Lemke methods).
pub type Csr = sprs::CsMat<f64>;
/// A borrowed [`Csr`].
pub type CsrView<'a> = sprs::CsMatView<'a, f64>;
