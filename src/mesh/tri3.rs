//! Constant-strain 3-node triangle (math note §9.1) and sparse assembly over the nodal DOFs.
//!
//! DOF order: `(u_x, u_y)` per node; nodes of `fixed_nodes` have no DOFs, and a fixed component of
//! a roller node (`fixed_x_nodes`, `fixed_y_nodes`) none for that component ([`Pattern::with_rollers`]).
//! Thickness 1 (plane problems per unit thickness). Stress and strain are `(xx, yy, xy)` with the
//! engineering shear strain `gamma_xy`, as `D` of [`crate::body::constitutive`].

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

use crate::geometry::Vec2;

/// 6x6 element matrix over `(u_xa, u_ya, u_xb, u_yb, u_xc, u_yc)`.
pub type Mat6 = SMatrix<f64, 6, 6>;
/// Element vector over the same 6 DOFs.
pub type Vec6 = SVector<f64, 6>;
/// Strain-displacement matrix `B_e`.
pub type Mat36 = SMatrix<f64, 3, 6>;

/// Geometry of one counter-clockwise triangle: area and the shape-function derivative coefficients
/// `beta_a = y_b - y_c`, `gamma_a = x_c - x_b` (cyclic), math note §9.1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tri3 {
    pub area: f64,
    pub beta: [f64; 3],
    pub gamma: [f64; 3],
}

impl Tri3 {
    /// From the three corners, counter-clockwise (a clockwise triangle gives a negative area).
    pub fn new(p: [Vec2; 3]) -> Tri3 {
        let beta = [p[1].y - p[2].y, p[2].y - p[0].y, p[0].y - p[1].y];
        let gamma = [p[2].x - p[1].x, p[0].x - p[2].x, p[1].x - p[0].x];
        let area = 0.5 * (beta[1] * gamma[2] - beta[2] * gamma[1]);
        Tri3 { area, beta, gamma }
    }

    /// Triangle `t` of a mesh given as node coordinates and node-index triples.
    pub fn of(nodes: &[Vec2], tri: [usize; 3]) -> Tri3 {
        Tri3::new(tri.map(|i| nodes[i]))
    }

    /// `B_e = 1/(2A) [beta 0; 0 gamma; gamma beta]` per node (math note §9.1).
    pub fn b(&self) -> Mat36 {
        let s = 0.5 / self.area;
        let mut b = Mat36::zeros();
        for i in 0..3 {
            b[(0, 2 * i)] = s * self.beta[i];
            b[(1, 2 * i + 1)] = s * self.gamma[i];
            b[(2, 2 * i)] = s * self.gamma[i];
            b[(2, 2 * i + 1)] = s * self.beta[i];
        }
        b
    }

    /// `K_e = A B^T D B` (math note §9.1; `D` from [`crate::body::constitutive`]).
    pub fn stiffness(&self, d: &Matrix3<f64>) -> Mat6 {
        let b = self.b();
        b.transpose() * d * b * self.area
    }

    /// Consistent mass `M_e = rho A / 12 [2 1 1; 1 2 1; 1 1 2] (x) I_2` (math note §9.1).
    pub fn mass(&self, rho: f64) -> Mat6 {
        let mut m = Mat6::zeros();
        let c = rho * self.area / 12.0;
        for i in 0..3 {
            for j in 0..3 {
                let v = if i == j { 2.0 * c } else { c };
                m[(2 * i, 2 * j)] = v;
                m[(2 * i + 1, 2 * j + 1)] = v;
            }
        }
        m
    }

    /// Body force `rho A g / 3` at each node (math note §9.1).
    pub fn body_force(&self, rho: f64, g: Vec2) -> Vec6 {
        let f = g * (rho * self.area / 3.0);
        Vec6::new(f.x, f.y, f.x, f.y, f.x, f.y)
    }

    /// Constant strain `(eps_xx, eps_yy, gamma_xy) = B u`.
    pub fn strain(&self, u: &Vec6) -> Vector3<f64> {
        self.b() * u
    }

    /// Stress `D B u`.
    pub fn stress(&self, d: &Matrix3<f64>, u: &Vec6) -> Vector3<f64> {
        d * self.strain(u)
    }

    /// Nodal load of an element stress, `f_sigma = -A B^T sigma` (math note §9.1, sign of §2.4).
    pub fn stress_load(&self, sigma: &Vector3<f64>) -> Vec6 {
        -(self.b().transpose() * sigma) * self.area
    }
}

/// The 6 nodal values of triangle `tri` from a full nodal vector `(u_x, u_y)` per node.
pub fn gather(u: &[f64], tri: [usize; 3]) -> Vec6 {
    Vec6::from_fn(|k, _| u[2 * tri[k / 2] + k % 2])
}

/// Sparse pattern of a mesh's global matrices (CSC, symmetric, both triangles stored), built once;
/// values are refilled per step by [`Pattern::assemble`]. Fixed nodes have no DOFs.
#[derive(Debug, Clone, Default)]
pub struct Pattern {
    /// Number of DOFs: twice the number of free nodes.
    pub n_dof: usize,
    /// CSC column pointers (`n_dof + 1`).
    pub indptr: Vec<usize>,
    /// CSC row indices, sorted within each column.
    pub indices: Vec<usize>,
    /// DOF of each node's `u_x` and `u_y`; `None` for a fixed component.
    dof: Vec<[Option<usize>; 2]>,
    /// Per element: the value slot of each (row, col) of the 6x6 element matrix, `usize::MAX` where
    /// a fixed DOF drops the entry.
    slots: Vec<[usize; 36]>,
    /// Per element: the global DOF of each of its 6 DOFs, `usize::MAX` if fixed.
    edofs: Vec<[usize; 6]>,
}

impl Pattern {
    /// Pattern of the mesh `triangles` over `n_nodes` nodes, with the nodes in `fixed` removed.
    /// Every triangle index must be below `n_nodes` (true of a [`crate::mesh::Mesh`]).
    pub fn new(n_nodes: usize, triangles: &[[usize; 3]], fixed: &[usize]) -> Pattern {
        Pattern::with_rollers(n_nodes, triangles, fixed, &[])
    }

    /// As [`Pattern::new`], and each `(node, component)` of `rollers` (0 = x, 1 = y) without its
    /// DOF: the node slides along the other axis (a roller).
    pub fn with_rollers(
        n_nodes: usize,
        triangles: &[[usize; 3]],
        fixed: &[usize],
        rollers: &[(usize, usize)],
    ) -> Pattern {
        let mut is_fixed = vec![[false; 2]; n_nodes];
        fixed.iter().filter(|&&n| n < n_nodes).for_each(|&n| is_fixed[n] = [true; 2]);
        rollers.iter().filter(|&&(n, c)| n < n_nodes && c < 2).for_each(|&(n, c)| is_fixed[n][c] = true);
        let mut next = 0;
        let dof: Vec<[Option<usize>; 2]> = (0..n_nodes)
            .map(|n| {
                is_fixed[n].map(|fixed| {
                    (!fixed).then(|| {
                        next += 1;
                        next - 1
                    })
                })
            })
            .collect();
        let n_dof = next;
        // Node adjacency (through shared triangles), then rows of each column.
        let mut adj: Vec<Vec<usize>> = vec![Vec::new(); n_nodes];
        for t in triangles {
            for &a in t {
                adj[a].extend_from_slice(t);
            }
        }
        let mut indptr = vec![0; n_dof + 1];
        let mut indices = Vec::new();
        for (n, nbrs) in adj.iter_mut().enumerate() {
            if dof[n] == [None; 2] {
                continue;
            }
            nbrs.sort_unstable();
            nbrs.dedup();
            let rows: Vec<usize> = nbrs.iter().flat_map(|&m| dof[m]).flatten().collect();
            for col in dof[n].into_iter().flatten() {
                indices.extend_from_slice(&rows);
                indptr[col + 1] = indices.len();
            }
        }
        let edofs: Vec<[usize; 6]> = triangles
            .iter()
            .map(|t| std::array::from_fn(|k| dof[t[k / 2]][k % 2].unwrap_or(usize::MAX)))
            .collect();
        let slots = edofs
            .iter()
            .map(|ed| {
                std::array::from_fn(|k| {
                    let (r, c) = (ed[k / 6], ed[k % 6]);
                    if r == usize::MAX || c == usize::MAX {
                        return usize::MAX;
                    }
                    let col = &indices[indptr[c]..indptr[c + 1]];
                    indptr[c] + col.binary_search(&r).expect("row in its column by construction")
                })
            })
            .collect();
        Pattern { n_dof, indptr, indices, dof, slots, edofs }
    }

    /// DOF of node `n`'s `u_x` (`u_y` is the next) when both are free; `None` if the node is
    /// fixed or a roller ([`Pattern::dofs`] gives each component).
    pub fn dof(&self, n: usize) -> Option<usize> {
        match self.dofs(n) {
            [Some(x), Some(_)] => Some(x),
            _ => None,
        }
    }

    /// DOFs of node `n`'s `u_x` and `u_y`, `None` for a fixed component.
    pub fn dofs(&self, n: usize) -> [Option<usize>; 2] {
        self.dof.get(n).copied().unwrap_or([None; 2])
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.indices.len()
    }

    /// Sums the element matrices `element(e)` into `values` (length [`Pattern::nnz`]), overwriting it.
    pub fn assemble(&self, values: &mut [f64], mut element: impl FnMut(usize) -> Mat6) {
        values.iter_mut().for_each(|v| *v = 0.0);
        for (e, slots) in self.slots.iter().enumerate() {
            let m = element(e);
            for (k, &s) in slots.iter().enumerate() {
                if s != usize::MAX {
                    values[s] += m[(k / 6, k % 6)];
                }
            }
        }
    }

    /// Sums element vectors into a global vector of length `n_dof` (fixed DOFs dropped).
    pub fn assemble_vector(&self, mut element: impl FnMut(usize) -> Vec6) -> Vec<f64> {
        let mut f = vec![0.0; self.n_dof];
        for (e, ed) in self.edofs.iter().enumerate() {
            let v = element(e);
            for (k, &d) in ed.iter().enumerate() {
                if d != usize::MAX {
                    f[d] += v[k];
                }
            }
        }
        f
    }

    /// The element's 6 values from a global DOF vector (fixed DOFs read as 0).
    pub fn gather(&self, u: &[f64], e: usize) -> Vec6 {
        Vec6::from_fn(|k, _| match self.edofs[e][k] {
            usize::MAX => 0.0,
            d => u[d],
        })
    }

    /// The assembled matrix as a `sprs` CSC matrix.
    pub fn matrix(&self, values: Vec<f64>) -> sprs::CsMat<f64> {
        sprs::CsMat::new_csc((self.n_dof, self.n_dof), self.indptr.clone(), self.indices.clone(), values)
    }
}
