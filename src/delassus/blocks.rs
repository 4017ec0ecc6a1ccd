//! The body form's per-body blocks (math note §3.3): each body's DOF range, K̃⁻¹ and its square
//! root, copied once from the flexibility's factors and kept across steps, the blocks of the
//! factors that change (a deformable body's) copied again in place (`bodies.rs` applies W
//! through them).

use crate::cluster::Flexibility;
use crate::dofs::DofMap;

/// A cluster's entry in `Blocks::compact` when it is not in body form.
pub(super) const NONE: u32 = u32::MAX;

/// The body-form clusters' packed blocks: per body its DOF range and K̃_c⁻¹ and R_c, copied
/// from the factors once and kept across steps while the DOF ranges stay the same
/// ([`Blocks::same_layout`]), the blocks of a factor replaced since copied again
/// ([`Blocks::update`]; math note §3.3). On a pile of rigid disks that is the whole run.
#[derive(Debug, Default)]
pub(super) struct Blocks {
    /// The stamps of the factors copied ([`Flexibility::stamps`]).
    pub(super) stamps: Vec<u64>,
    /// Per cluster, its body (compact index), or `NONE`.
    pub(super) compact: Vec<u32>,
    /// Per cluster, where its K̃_c⁻¹ starts in `kinv` when it is a rigid body in body form (3
    /// DOFs), or `NONE`: the diagonal's common case in one load.
    pub(super) rigid: Vec<u32>,
    /// Per body: its first global DOF and DOF count, and its K̃_c⁻¹ and square root R_c
    /// (R_c R_cᵀ = K̃_c⁻¹), n_c × n_c column-major, from `kinv[square[b]..]` and
    /// `root[square[b]..]`, both laid out as the flexibility's packed K̃_c⁻¹ of the closed-form
    /// clusters ([`Flexibility::closed`]). (A copy: were it shared, the flexibility would copy
    /// all of it whenever one factor changed, since the blocks would still hold the old values.)
    pub(super) start: Vec<usize>,
    pub(super) n: Vec<usize>,
    pub(super) square: Vec<usize>,
    /// Per body, its first entry in packed n_c(n_c + 1)/2 lower triangles (`bodies + 1` offsets).
    pub(super) packed: Vec<usize>,
    pub(super) kinv: Vec<f64>,
    pub(super) root: Vec<f64>,
    /// Every body has 3 DOFs (a pile of rigid bodies) and its block follows the last one: K̃_c⁻¹
    /// of body b is `kinv[9 b..9 b + 9]`.
    pub(super) all_rigid: bool,
    /// Besides, every cluster is a body here and body b's DOFs start at 3 b: a body whose DOFs
    /// start at a has its K̃⁻¹ at `kinv[3 a..3 a + 9]`, as B's contact frames read it
    /// (`frames.rs`).
    pub(super) dense: bool,
    /// Per body, whether its cluster joins several bodies (by connectors): a row of B can then
    /// have two segments on it (a contact between two of its bodies).
    pub(super) joined: Vec<bool>,
    /// The length of the body vectors (B's columns).
    pub(super) dofs: usize,
}

impl Blocks {
    /// The blocks of the clusters with `body[c]` (each a single body with a closed-form K̃⁻¹).
    pub fn new(flex: &Flexibility, map: &DofMap, body: &[bool]) -> Blocks {
        let mut blocks = Blocks {
            stamps: flex.stamps().to_vec(),
            compact: vec![NONE; body.len()],
            rigid: vec![NONE; body.len()],
            packed: vec![0],
            dofs: map.total(),
            ..Default::default()
        };
        let count = body.iter().filter(|&&b| b).count();
        blocks.start.reserve(count);
        blocks.n.reserve(count);
        blocks.square.reserve(count);
        blocks.joined.reserve(count);
        blocks.packed.reserve(count);
        for (c, _) in body.iter().enumerate().filter(|(_, b)| **b) {
            if let ((kinv, Some(at)), Some(_)) = (flex.closed(c), flex.body_root(c)) {
                let (range, b) = (map.cluster_range(c), blocks.n.len());
                let n = range.len();
                if blocks.root.is_empty() {
                    (blocks.kinv, blocks.root) = ((**kinv).clone(), vec![0.0; kinv.len()]);
                }
                blocks.compact[c] = b as u32;
                if n == 3 {
                    blocks.rigid[c] = at as u32;
                }
                blocks.start.push(range.start);
                blocks.n.push(n);
                blocks.square.push(at);
                blocks.joined.push(map.members(c).len() > 1);
                blocks.copy_root(flex, c);
                blocks.packed.push(blocks.packed[b] + n * (n + 1) / 2);
            }
        }
        // (the blocks then lie one after the other, 9 numbers each)
        blocks.all_rigid =
            blocks.n.iter().zip(&blocks.square).enumerate().all(|(b, (&n, &s))| n == 3 && s == 9 * b);
        blocks.dense = blocks.all_rigid
            && blocks.every()
            && blocks.start.iter().enumerate().all(|(b, &start)| start == 3 * b);
        blocks
    }

    /// Whether every cluster is a body in body form.
    pub fn every(&self) -> bool {
        self.n.len() == self.compact.len()
    }

    /// Copies R_c of cluster `c` (in body form) from the flexibility: the leading n × n block,
    /// column by column (cheaper than a flat_map over the entries).
    fn copy_root(&mut self, flex: &Flexibility, c: usize) -> Option<()> {
        let (b, (r, stride)) = (self.compact[c] as usize, flex.body_root(c)?);
        let (n, at) = (self.n[b], self.square[b]);
        for (j, column) in self.root[at..at + n * n].chunks_exact_mut(n).enumerate() {
            column.copy_from_slice(&r[j * stride..j * stride + n]);
        }
        Some(())
    }

    /// Whether these blocks are laid out as [`Blocks::new`] would lay them out now: the same
    /// clusters in body form, at the same DOF ranges (their factors may have changed).
    pub fn same_layout(&self, map: &DofMap, body: &[bool]) -> bool {
        self.dofs == map.total()
            && self.compact.len() == body.len()
            && body.iter().zip(&self.compact).enumerate().all(|(c, (&on, &b))| match b {
                NONE => !on,
                b => {
                    on && map.cluster_range(c)
                        == (self.start[b as usize]..self.start[b as usize] + self.n[b as usize])
                }
            })
    }

    /// Copies K̃_c⁻¹ and R_c again for each body-form cluster c whose factor was replaced since
    /// (by stamp), in place, for blocks of the same layout ([`Self::same_layout`]): a
    /// deformable body's factor changes every step, and new blocks copied every body's. `false`
    /// (the blocks then half updated: make new ones) when a block moved in the flexibility's
    /// packing.
    pub fn update(&mut self, flex: &Flexibility) -> bool {
        if flex.stamps().len() != self.stamps.len() {
            return false;
        }
        for c in 0..self.stamps.len() {
            let stamp = flex.stamps()[c];
            if stamp == self.stamps[c] {
                continue;
            }
            self.stamps[c] = stamp;
            let b = self.compact[c];
            if b == NONE {
                continue;
            }
            let (n, at) = (self.n[b as usize], self.square[b as usize]);
            match flex.closed(c) {
                (kinv, Some(now)) if now == at && kinv.len() == self.kinv.len() => {
                    self.kinv[at..at + n * n].copy_from_slice(&kinv[at..at + n * n])
                }
                _ => return false,
            }
            if self.copy_root(flex, c).is_none() {
                return false;
            }
        }
        true
    }
}
