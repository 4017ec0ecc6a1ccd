//! The block `(K⁻¹)_SS` of a sparse SPD matrix's inverse over the DOFs contacts touch, from
//! sparse forward solves with its Cholesky factor (math note §9.3, "The code's cache", and §9.7,
//! "The contact block from the factor's paths").
//!
//! With `P K Pᵀ = L Lᵀ`, `(K⁻¹)_ab = y_a · y_b` where `y_a = L⁻¹ P e_a`. The forward solve of a
//! unit vector is nonzero only on the path from its column to the root of the elimination
//! tree, so `y_a` is a few dense pieces, one per supernode (column group) on that path, and
//! the block is `Σ_s Y_sᵀ Y_s` over the groups, `Y_s` the pieces of the DOFs whose paths pass
//! through s. No backward solve and no full-length vector is formed.

use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::sparse::linalg::cholesky::supernodal::SupernodalLltRef;
use faer::sparse::linalg::cholesky::{SymbolicCholesky, SymbolicCholeskyRaw};
use faer::{Accum, Mat, MatRef, Par};
use std::collections::HashMap;
use std::sync::Mutex;
use std::sync::mpsc::Sender;

/// No parent: a root of the elimination tree.
const ROOT: usize = usize::MAX;

/// The column groups of a Cholesky factor and their elimination tree: supernodes, or single
/// columns of a simplicial factor.
#[derive(Debug)]
pub(crate) struct Tree {
    /// Position of each original DOF in the factor's ordering.
    pos: Vec<usize>,
    /// Group of each factor column.
    group_of: Vec<usize>,
    /// First column of each group, and one past the last group's end.
    start: Vec<usize>,
    /// Parent group (the group of the smallest row below the group's diagonal block).
    parent: Vec<usize>,
}

/// One group of the numeric factor: its diagonal block and the rows below it.
struct Group<'a> {
    top: MatRef<'a, f64>,
    rows: &'a [usize],
    below: MatRef<'a, f64>,
}

impl Tree {
    pub(super) fn new(symbolic: &SymbolicCholesky<usize>) -> Tree {
        let n = symbolic.nrows();
        let pos = match symbolic.perm() {
            Some(perm) => perm.arrays().1.to_vec(),
            None => (0..n).collect(),
        };
        let (start, below): (Vec<usize>, Vec<&[usize]>) = match symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(s) => {
                let mut start = s.supernode_begin().to_vec();
                start.push(n);
                let below = (0..s.n_supernodes()).map(|g| s.supernode(g).pattern()).collect();
                (start, below)
            }
            SymbolicCholeskyRaw::Simplicial(s) => {
                let (ptr, rows) = (s.col_ptr(), s.row_idx());
                ((0..=n).collect(), (0..n).map(|j| &rows[ptr[j] + 1..ptr[j + 1]]).collect())
            }
        };
        let mut group_of = vec![0; n];
        for g in 0..below.len() {
            group_of[start[g]..start[g + 1]].fill(g);
        }
        let parent = below.iter().map(|r| r.iter().min().map_or(ROOT, |&i| group_of[i])).collect();
        Tree { pos, group_of, start, parent }
    }

    fn group<'a>(&self, symbolic: &'a SymbolicCholesky<usize>, values: &'a [f64], g: usize) -> Group<'a> {
        match symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(s) => {
                let node = SupernodalLltRef::new(s, values).supernode(g);
                let size = self.start[g + 1] - self.start[g];
                let (top, below) = node.val().split_at_row(size);
                Group { top, rows: node.pattern(), below }
            }
            SymbolicCholeskyRaw::Simplicial(s) => {
                let (p, q) = (s.col_ptr()[g], s.col_ptr()[g + 1]);
                Group {
                    top: MatRef::from_column_major_slice(&values[p..p + 1], 1, 1),
                    rows: &s.row_idx()[p + 1..q],
                    below: MatRef::from_column_major_slice(&values[p + 1..q], q - p - 1, 1),
                }
            }
        }
    }
}

/// The kept pieces of one group: the slots (in S) of the DOFs whose paths pass through it and
/// their pieces, column-major, one column of the group's size per slot.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
struct Panel {
    slots: Vec<usize>,
    values: Vec<f64>,
}

/// The symmetric block `(K⁻¹)_SS` over a growing set S of DOFs, with the pieces of every
/// member's `y` kept per group so that DOFs joining S need only their own forward solves.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub(crate) struct InverseCache {
    /// DOF → its index in S (the order in which DOFs joined).
    pub(super) slot: HashMap<usize, usize>,
    /// `lower[a][b] = (K⁻¹)_{S_a S_b}` for `b ≤ a`: every entry stored once, so the block read
    /// from it is exactly symmetric.
    pub(super) lower: Vec<Vec<f64>>,
    panels: HashMap<usize, Panel>,
}

/// The groups on the new DOFs' paths, ascending (a parent after its children), each with the
/// new DOFs (their indices in the batch, ascending) that pass through it.
fn paths(tree: &Tree, new: &[usize]) -> (Vec<usize>, Vec<Vec<usize>>) {
    let mut pairs = Vec::new();
    for (j, &d) in new.iter().enumerate() {
        let mut g = tree.group_of[tree.pos[d]];
        while g != ROOT {
            pairs.push((g, j));
            g = tree.parent[g];
        }
    }
    pairs.sort_unstable();
    let mut groups: Vec<usize> = Vec::new();
    let mut members: Vec<Vec<usize>> = Vec::new();
    for (g, j) in pairs {
        if groups.last() != Some(&g) {
            groups.push(g);
            members.push(Vec::new());
        }
        members.last_mut().expect("pushed").push(j);
    }
    (groups, members)
}

/// Subtracts the update of the `u`-th group on the paths (one row per row of the factor below
/// its diagonal block, one column per DOF through it) from the pieces of its ancestors,
/// `rest` (the groups after it): one run of rows of one ancestor at a time, column by column.
fn scatter(
    tree: &Tree,
    groups: &[usize],
    members: &[Vec<usize>],
    u: usize,
    rows: &[usize],
    update: &Mat<f64>,
    rest: &mut [Mat<f64>],
) {
    let mut i = 0;
    while i < rows.len() {
        let t = tree.group_of[rows[i]];
        let end = i + rows[i..].iter().take_while(|&&r| tree.group_of[r] == t).count();
        let v = groups.binary_search(&t).expect("an ancestor is on the paths");
        let (target, start) = (&mut rest[v - u - 1], tree.start[t]);
        for (c, j) in members[u].iter().enumerate() {
            let to = target.col_as_slice_mut(members[v].binary_search(j).expect("ancestor"));
            for (&r, &d) in rows[i..end].iter().zip(&update.col_as_slice(c)[i..end]) {
                to[r - start] -= d;
            }
        }
        i = end;
    }
}

impl InverseCache {
    /// Adds the DOFs `new` (distinct, none in S yet) to S: their forward solves along their
    /// paths, then their entries against S (old members and each other) group by group. The
    /// two run at once on the pool's two threads ([`pipeline`], math note §9.8): a group's
    /// pieces are final once the forward pass has passed it, and go to the products in the
    /// pass's order, so every entry is the same sum in the same order as one after the other.
    pub(super) fn extend(
        &mut self,
        tree: &Tree,
        symbolic: &SymbolicCholesky<usize>,
        values: &[f64],
        new: &[usize],
    ) {
        let (groups, members) = paths(tree, new);
        let known = self.lower.len();
        for (j, &d) in new.iter().enumerate() {
            self.slot.insert(d, known + j);
            self.lower.push(vec![0.0; known + j + 1]);
        }
        let (done, finished) = std::sync::mpsc::channel::<Mat<f64>>();
        let (groups, members) = (&groups, &members);
        let this = &mut *self;
        pipeline(
            move || forward(tree, symbolic, values, groups, members, new, done),
            move || {
                for (u, x) in finished.iter().enumerate() {
                    this.gram(known, groups[u], &members[u], x);
                }
            },
        );
    }

    /// The new members' rows of the block from group `g`'s pieces `x` of the new members `m`
    /// (indices in the batch after the `known` members): `Y_gᵀ [Y_g^old, Y_g^new]` added to
    /// them, then the pieces kept in the group's panel.
    fn gram(&mut self, known: usize, g: usize, m: &[usize], x: Mat<f64>) {
        let panel = self.panels.entry(g).or_default();
        let old = panel.slots.len();
        let rows = x.nrows();
        let y_old = MatRef::from_column_major_slice(&panel.values, rows, old);
        // column c: the products of the c-th new piece with the old pieces, then with the new
        let mut cross = Mat::<f64>::zeros(old + m.len(), m.len());
        let (mut with_old, mut with_new) = cross.as_mut().split_at_row_mut(old);
        matmul(with_old.as_mut(), Accum::Replace, y_old.transpose(), x.as_ref(), 1.0, Par::Seq);
        matmul(with_new.as_mut(), Accum::Replace, x.transpose(), x.as_ref(), 1.0, Par::Seq);
        for (c, &j) in m.iter().enumerate() {
            let (row, column) = (&mut self.lower[known + j], cross.col_as_slice(c));
            for (&b, &v) in panel.slots.iter().zip(column) {
                row[b] += v;
            }
            for (&j2, &v) in m[..=c].iter().zip(&column[old..]) {
                row[known + j2] += v;
            }
        }
        panel.slots.extend(m.iter().map(|j| known + j));
        for c in 0..x.ncols() {
            panel.values.extend(x.col(c).iter());
        }
    }
}

/// The forward solves of the new DOFs along their paths, group by group in ascending order
/// (a child before its parent): each group's pieces are solved with its diagonal block, their
/// product with the rows below is subtracted from the ancestors' pieces ([`scatter`]), and
/// they are sent on `done`, final, in the groups' order.
fn forward(
    tree: &Tree,
    symbolic: &SymbolicCholesky<usize>,
    values: &[f64],
    groups: &[usize],
    members: &[Vec<usize>],
    new: &[usize],
    done: Sender<Mat<f64>>,
) {
    let size = |g: usize| tree.start[g + 1] - tree.start[g];
    let mut pieces: Vec<Mat<f64>> =
        groups.iter().zip(members).map(|(&g, m)| Mat::zeros(size(g), m.len())).collect();
    for (j, &d) in new.iter().enumerate() {
        let p = tree.pos[d];
        let u = groups.binary_search(&tree.group_of[p]).expect("on its path");
        let c = members[u].binary_search(&j).expect("on its path");
        pieces[u][(p - tree.start[groups[u]], c)] = 1.0;
    }
    for u in 0..groups.len() {
        let group = tree.group(symbolic, values, groups[u]);
        let (head, rest) = pieces.split_at_mut(u + 1);
        let x = &mut head[u];
        solve_lower_triangular_in_place(group.top, x.as_mut(), Par::Seq);
        if !group.rows.is_empty() {
            let mut update = Mat::<f64>::zeros(group.rows.len(), x.ncols());
            matmul(update.as_mut(), Accum::Replace, group.below, x.as_ref(), 1.0, Par::Seq);
            scatter(tree, groups, members, u, group.rows, &update, rest);
        }
        // the receiver ends only with the pass; a send cannot fail before
        let _ = done.send(std::mem::replace(x, Mat::new()));
    }
}

/// Runs `produce` and `consume` on the pool's two threads (`micropool::join`), `consume`
/// waiting for what `produce` sends it. Whichever closure the pool starts first takes the
/// producer's part, so on one thread (or when the pool runs its two closures one after the
/// other) the producer runs to its end first and nothing waits for a closure that has not
/// started.
fn pipeline(produce: impl FnOnce() + Send, consume: impl FnOnce() + Send) {
    let roles = Mutex::new((Some(produce), Some(consume)));
    let run = || {
        let role = {
            let mut roles = roles.lock().unwrap_or_else(|e| e.into_inner());
            match roles.0.take() {
                Some(p) => Ok(p),
                None => Err(roles.1.take()),
            }
        };
        match role {
            Ok(p) => p(),
            Err(Some(c)) => c(),
            Err(None) => {}
        }
    };
    micropool::join(run, run);
}
