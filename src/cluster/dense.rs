//! The closed-form K̃_c⁻¹ of a cluster without meshes of at most [`DENSE_MAX`] DOFs (math note
//! §6, "Clusters", code rules): K̃ assembled dense from the cluster's entries (`StepStiffness`),
//! factorized by a dense Cholesky and inverted, with the square root R (R Rᵀ = K̃⁻¹) that the
//! body form's bound of ‖Ŵ‖ needs. A single body, or a cluster of at most `MAX_DOF` DOFs (two
//! rigid disks joined by a bolt), on the fixed 6 × 6; a larger cluster (a chain of bolted blocks,
//! a bolt into a deformable body) on its own n × n.

use super::{CouplingBlock, Factor, StepStiffness};
use crate::body::{Body, BodyMatrix, MAX_DOF};
use crate::dofs::DofMap;
use nalgebra::DMatrix;

/// The largest cluster (in DOFs) kept in closed form. Such a cluster's K̃⁻¹ is n × n dense: in
/// body form a product costs n² multiply-adds per cluster and its refresh about (5/3) n³ (a
/// coupled cluster's K̃ follows its anchors, so every step), against the m² entries of its
/// explicit part of W (m its contact rows: about 4 n for rigid bodies with six contacts each) plus
/// the sparse factor and the block of its inverse the explicit assembly reads (math note §6).
/// At 48 DOFs (16 rigid bodies, 8 deformable polygons) the refresh is about 0.2 M flops and
/// the block 18 kB; a mesh always goes through the sparse factor.
pub const DENSE_MAX: usize = 48;

/// K̃_c⁻¹ and R of a cluster of more than `MAX_DOF` DOFs, n × n column-major.
#[derive(Debug, Clone)]
pub(crate) struct Dense {
    pub n: usize,
    pub inverse: Vec<f64>,
    pub root: Vec<f64>,
}

/// Whether cluster `c` takes the closed form: at most [`DENSE_MAX`] DOFs, no meshes.
pub(super) fn is_closed(map: &DofMap, c: usize, bodies: &[Body]) -> bool {
    map.cluster_range(c).len() <= DENSE_MAX && map.members(c).iter().all(|&b| bodies[b].mesh.is_none())
}

/// The cluster's closed-form factor from its K̃ (`stiffness`'s entries summed); `None` unless K̃
/// is positive definite with finite results.
pub(super) fn closed_factor<'a>(
    stiffness: StepStiffness<'a, impl Iterator<Item = &'a CouplingBlock>>,
) -> Option<Factor> {
    let n = stiffness.dofs();
    if n <= MAX_DOF {
        let mut k = BodyMatrix::zeros();
        stiffness.entries(|r, col, v| k[(r, col)] += v);
        let (inverse, root) = closed_form(k, n)?;
        return Some(Factor::Body { inverse, root });
    }
    let mut k = DMatrix::<f64>::zeros(n, n);
    stiffness.entries(|r, col, v| k[(r, col)] += v);
    // R = L⁻ᵀ, and K̃⁻¹ = R Rᵀ by one product (symmetric bit for bit: entries (i, j) and (j, i)
    // sum the same products in the same order)
    let root = k.cholesky()?.l().solve_lower_triangular(&DMatrix::identity(n, n))?.transpose();
    let inverse = &root * root.transpose();
    let finite = inverse.iter().chain(root.iter()).all(|x| x.is_finite());
    let dense = Dense { n, inverse: inverse.as_slice().to_vec(), root: root.as_slice().to_vec() };
    finite.then_some(Factor::Dense(dense))
}

/// K̃⁻¹ and an upper triangular square root R (R Rᵀ = K̃⁻¹) of the symmetric leading n × n block
/// of `k`, padded with zeros to `MAX_DOF` × `MAX_DOF`; `None` unless that block is positive
/// definite with finite results. On the fixed size, its unused diagonal set to one: no heap
/// allocation (it runs every step for a deformable body or a bolted pair). The leading block's
/// factor, inverse and root are the n × n ones: the padding adds only exact zeros to their sums.
fn closed_form(mut k: BodyMatrix, n: usize) -> Option<(BodyMatrix, BodyMatrix)> {
    let pad = |m: &mut BodyMatrix, diagonal: f64| {
        for i in n..MAX_DOF {
            m.row_mut(i).fill(0.0);
            m.column_mut(i).fill(0.0);
            m[(i, i)] = diagonal;
        }
    };
    pad(&mut k, 1.0);
    let chol = k.cholesky()?;
    let mut inverse = chol.inverse();
    let mut root = chol.l().solve_lower_triangular(&BodyMatrix::identity())?.transpose();
    pad(&mut inverse, 0.0);
    pad(&mut root, 0.0);
    let leading = |m: &BodyMatrix| m.view((0, 0), (n, n)).iter().all(|x| x.is_finite());
    (leading(&inverse) && leading(&root)).then_some((inverse, root))
}

/// `v ← K v` over a cluster's n = `v.len()` DOFs, K its closed-form K̃⁻¹, column-major with
/// column stride `stride` (n packed, or the padded 6): column by column, as a product.
pub(super) fn body_solve(k: &[f64], stride: usize, v: &mut [f64]) {
    match v.len() {
        // a rigid body, unrolled (the same sums) and written back as three stores, not a call
        // to memcpy
        3 => crate::jacobian::copy_small(v, &block_times::<3>(k, stride, v)),
        n if n <= MAX_DOF => times::<MAX_DOF>(k, stride, v),
        _ => times::<DENSE_MAX>(k, stride, v),
    }
}

/// `v ← K v` for `v.len()` <= M, through an M-long work array.
fn times<const M: usize>(k: &[f64], stride: usize, v: &mut [f64]) {
    let (n, mut x) = (v.len(), [0.0; M]);
    for (j, &vj) in v.iter().enumerate() {
        for (i, xi) in x[..n].iter_mut().enumerate() {
            *xi += k[j * stride + i] * vj;
        }
    }
    v.copy_from_slice(&x[..n]);
}

/// K u over the leading N × N block of the column-major `k` (column stride `stride`), summed
/// column by column: the order of every body-block product (a body's factor here, the body
/// form's packed blocks in `delassus`), so that their sums agree bit for bit.
#[inline(always)]
pub(crate) fn block_times<const N: usize>(k: &[f64], stride: usize, u: &[f64]) -> [f64; N] {
    let (k, u) = (&k[..(N - 1) * stride + N], &u[..N]);
    let mut o = [0.0; N];
    for j in 0..N {
        for i in 0..N {
            o[i] += k[j * stride + i] * u[j];
        }
    }
    o
}
