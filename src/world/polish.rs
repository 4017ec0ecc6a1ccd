//! Solution polishing (math note §10.10): a converged VI solution is corrected on its active set
//! with gaps evaluated body by body in compensated arithmetic, so that the forces are as exact
//! as the statics of the bodies allow, whatever their mass ratio.
//!
//! W = B K̃⁻¹ Bᵀ sums the compliance of both bodies of a contact. When one body is 1e12 times
//! lighter than the other, the heavy one's part of every row it shares with the light one is
//! rounded away, and a solver working with W resolves the forces only to about eps · ratio
//! (1e-4 at 1e12). The statics themselves are well conditioned: B holds geometry, each body's
//! K̃ is well scaled on its own. So the correction never forms W:
//! 1. gaps `G = q + B K̃⁻¹ Bᵀ z` from the generalized forces `Bᵀ z` of each body, summed in
//!    double-double (the net force on a light body squeezed between heavy ones is the small
//!    difference of large ones), then `K̃⁻¹` per body and `B d` summed the same way;
//! 2. on the rows strictly inside their bounds (closed, sticking: their gaps must vanish) the
//!    body motion `δd` that cancels those gaps in least squares, `B_F δd = −G_F`;
//! 3. the forces that produce it, `δF = K̃ δd`, carried by the least-norm `δz` with
//!    `B_Fᵀ δz = δF`, so that `W_FF δz = B_F δd`.
//!
//! It applies only where this is exact and cheap: every row at a bound is at zero (no sliding
//! row, whose bound moves with the normal force), the bodies are single-body clusters with a
//! closed-form K̃ (no sparse cluster), B_F has full column rank (every DOF of those bodies is
//! held by the free rows; otherwise W_FF is not B_F K̃⁻¹ B_Fᵀ of an invertible map), and the
//! problem is small (dense algebra). A polish that would leave a bound or open a penetration is
//! dropped.

use super::World;
use super::rows::Rows;
use crate::body::BodyMatrix;
use crate::vi::BoundRule;
use nalgebra::{DMatrix, DVector};
use std::ops::Range;

/// Largest problem polished: rows and body DOFs (dense SVD of a rows × DOFs matrix).
const MAX_ROWS: usize = 96;
const MAX_DOFS: usize = 96;
/// Correction passes; each gains about 1/(eps · cond) of the remaining error.
const PASSES: usize = 3;

/// `a + b` as a rounded sum and its exact error (Knuth's TwoSum).
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// A double-double accumulator: adds exact products and sums, rounds once at the end.
#[derive(Clone, Copy, Default)]
struct Exact {
    hi: f64,
    lo: f64,
}

impl Exact {
    fn add_product(&mut self, a: f64, b: f64) {
        let p = a * b;
        let e = a.mul_add(b, -p); // exact error of the product
        let (s, err) = two_sum(self.hi, p);
        self.hi = s;
        self.lo += err + e;
    }

    fn value(self) -> f64 {
        self.hi + self.lo
    }
}

/// The bodies a polish moves: per cluster, its global DOF range, its place in the local
/// numbering and K̃⁻¹.
struct Bodies<'a> {
    clusters: Vec<usize>,
    ranges: Vec<Range<usize>>,
    offsets: Vec<usize>,
    kinv: Vec<&'a BodyMatrix>,
    dofs: usize,
}

impl Bodies<'_> {
    /// Local index of global DOF `g` of cluster `c`.
    fn local(&self, c: usize, g: usize) -> usize {
        let k = self.clusters.binary_search(&c).unwrap_or_else(|_| unreachable!("a touched cluster"));
        self.offsets[k] + g - self.ranges[k].start
    }
}

impl World {
    /// Polishes the converged forces `z` of the rows `rows` with gaps `q` (module docs); whether
    /// `z` was changed.
    pub(super) fn polish(&self, rows: &Rows, q: &[f64], rule: &dyn BoundRule, z: &mut [f64]) -> bool {
        let n = q.len();
        if n == 0 || n > MAX_ROWS {
            return false;
        }
        let Some(bodies) = self.polish_bodies(rows).filter(|b| b.dofs <= MAX_DOFS) else { return false };
        let (mut lo, mut hi) = (vec![0.0; n], vec![0.0; n]);
        rule.all_bounds(&rows.blocks, z, &mut lo, &mut hi);
        let free: Vec<usize> = (0..n).filter(|&r| lo[r] < z[r] && z[r] < hi[r]).collect();
        if free.is_empty() || (0..n).any(|r| z[r] != 0.0 && !(lo[r] < z[r] && z[r] < hi[r])) {
            return false;
        }
        let mut b = DMatrix::<f64>::zeros(free.len(), bodies.dofs);
        let jac = rows.jac();
        for s in jac.segments() {
            if let Ok(i) = free.binary_search(&s.row()) {
                for (dof, v) in s.dofs().zip(jac.vals(s)) {
                    b[(i, bodies.local(s.cluster(), dof))] += v;
                }
            }
        }
        // full column rank, judged on unit columns (B's columns carry lengths and lever arms)
        let scale: Vec<f64> = (0..bodies.dofs).map(|j| b.column(j).norm()).collect();
        if scale.contains(&0.0) || free.len() < bodies.dofs {
            return false;
        }
        let unit = DMatrix::from_fn(free.len(), bodies.dofs, |i, j| b[(i, j)] / scale[j]);
        let svd = unit.svd(true, true);
        let sv = &svd.singular_values;
        if sv.min() <= 1e-10 * sv.max() {
            return false;
        }
        let (Some(u), Some(v_t)) = (&svd.u, &svd.v_t) else { return false };
        let before = z.to_vec();
        let mut g = self.exact_gaps(rows, q, z, &bodies);
        let worst = |g: &[f64]| free.iter().fold(0.0f64, |m, &r| m.max(g[r].abs()));
        let start = worst(&g);
        for _ in 0..PASSES {
            // δd (unit columns) = V Σ⁻¹ Uᵀ (−G_F); then δd = δd_unit / scale
            let gf = DVector::from_iterator(free.len(), free.iter().map(|&r| -g[r]));
            let ug: DVector<f64> = u.transpose() * gf;
            let dd_unit: DVector<f64> = v_t.transpose() * ug.component_div(sv);
            let dd = DVector::from_fn(bodies.dofs, |j, _| dd_unit[j] / scale[j]);
            let Some(df) = self.body_forces(&bodies, &dd) else {
                z.copy_from_slice(&before);
                return false;
            };
            // least-norm δz with B_Fᵀ δz = δF: B_Fᵀ = diag(scale) V Σ Uᵀ
            let df_unit = DVector::from_fn(bodies.dofs, |j, _| df[j] / scale[j]);
            let vf: DVector<f64> = v_t * df_unit;
            let dz: DVector<f64> = u * vf.component_div(sv);
            for (i, &r) in free.iter().enumerate() {
                z[r] += dz[i];
            }
            g = self.exact_gaps(rows, q, z, &bodies);
        }
        rule.all_bounds(&rows.blocks, z, &mut lo, &mut hi);
        let inside = free.iter().all(|&r| lo[r] <= z[r] && z[r] <= hi[r]);
        let open_ok = (0..n).filter(|r| free.binary_search(r).is_err()).all(|r| {
            // rows held at zero keep their gap's sign (to the penetration allowance)
            lo[r] == hi[r]
                || (lo[r] == 0.0 && g[r] >= -self.allowance)
                || (hi[r] == 0.0 && g[r] <= self.allowance)
        });
        if !(inside && open_ok && worst(&g) < start) {
            z.copy_from_slice(&before);
            return false;
        }
        true
    }

    /// The single-body clusters the rows touch, or `None` if a sparse cluster is among them.
    fn polish_bodies(&self, rows: &Rows) -> Option<Bodies<'_>> {
        let mut clusters: Vec<usize> = rows.jac().segments().iter().map(|s| s.cluster()).collect();
        clusters.sort_unstable();
        clusters.dedup();
        let kinv = clusters.iter().map(|&c| self.flex.body_inverse(c)).collect::<Option<Vec<_>>>()?;
        let ranges: Vec<Range<usize>> = clusters.iter().map(|&c| self.dof_map().cluster_range(c)).collect();
        let mut offsets = Vec::with_capacity(ranges.len());
        let mut dofs = 0;
        for r in &ranges {
            offsets.push(dofs);
            dofs += r.len();
        }
        Some(Bodies { clusters, ranges, offsets, kinv, dofs })
    }

    /// Gaps `q + B K̃⁻¹ Bᵀ z` summed body by body in double-double (module docs, step 1).
    fn exact_gaps(&self, rows: &Rows, q: &[f64], z: &[f64], bodies: &Bodies) -> Vec<f64> {
        let (mut force, jac) = (vec![Exact::default(); bodies.dofs], rows.jac());
        for s in jac.segments() {
            for (dof, &v) in s.dofs().zip(jac.vals(s)) {
                force[bodies.local(s.cluster(), dof)].add_product(v, z[s.row()]);
            }
        }
        let mut d = vec![0.0; bodies.dofs];
        for (k, kinv) in bodies.kinv.iter().enumerate() {
            let (off, len) = (bodies.offsets[k], bodies.ranges[k].len());
            for i in 0..len {
                let mut acc = Exact::default();
                for j in 0..len {
                    acc.add_product(kinv[(i, j)], force[off + j].value());
                }
                d[off + i] = acc.value();
            }
        }
        let mut gaps: Vec<Exact> = q.iter().map(|&v| Exact { hi: v, lo: 0.0 }).collect();
        for s in jac.segments() {
            for (dof, &v) in s.dofs().zip(jac.vals(s)) {
                gaps[s.row()].add_product(v, d[bodies.local(s.cluster(), dof)]);
            }
        }
        gaps.into_iter().map(Exact::value).collect()
    }

    /// `δF = K̃ δd` per body, by a Cholesky solve with its K̃⁻¹; `None` if one is not SPD.
    fn body_forces(&self, bodies: &Bodies, dd: &DVector<f64>) -> Option<DVector<f64>> {
        let mut df = DVector::zeros(bodies.dofs);
        for (k, kinv) in bodies.kinv.iter().enumerate() {
            let (off, len) = (bodies.offsets[k], bodies.ranges[k].len());
            let block = DMatrix::from_fn(len, len, |i, j| kinv[(i, j)]);
            let x = block.cholesky()?.solve(&dd.rows(off, len).into_owned());
            df.rows_mut(off, len).copy_from(&x);
        }
        Some(df)
    }
}
