//! The global DOF map and the clusters (math note §10.6).
//!
//! Every free body owns a contiguous range of the global DOF vector (3 rigid, 4 deformable
//! particle, 6 deformable polygon; a fixed body owns none). A *cluster* is a connected
//! component of the graph whose edges are whatever couples bodies through the stiffness
//! (connectors; a mesh is one body with many DOFs). The map numbers the bodies cluster by
//! cluster, so each cluster also owns one contiguous range: its stiffness K̃ is one square
//! block of the global system, and K̃⁻¹ never couples two clusters.

use crate::body::{Body, Dofs};
use std::ops::Range;

/// Body → DOF range, and body → cluster.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct DofMap {
    start: Vec<usize>,
    count: Vec<usize>,
    total: usize,
    /// Cluster of each body (`None`: fixed body, no DOFs).
    cluster_of: Vec<Option<usize>>,
    /// Bodies of each cluster, in DOF order.
    members: Vec<Vec<usize>>,
    /// DOF range of each cluster.
    cluster_range: Vec<Range<usize>>,
}

impl DofMap {
    /// Numbers the free bodies cluster by cluster. `couplings` are pairs of bodies joined by
    /// stiffness (a pair with a fixed body couples nothing: the fixed body has no DOFs).
    pub fn new(bodies: &[Body], couplings: &[(usize, usize)]) -> DofMap {
        let n = bodies.len();
        let mut parent: Vec<usize> = (0..n).collect();
        for &(a, b) in couplings {
            if !bodies[a].fixed && !bodies[b].fixed {
                let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                parent[ra.max(rb)] = ra.min(rb);
            }
        }
        let mut map =
            DofMap { start: vec![0; n], count: vec![0; n], cluster_of: vec![None; n], ..Default::default() };
        // clusters in order of their first body, members in body order: deterministic
        let mut cluster_of_root = vec![usize::MAX; n];
        for b in (0..n).filter(|&b| !bodies[b].fixed) {
            let r = root(&mut parent, b);
            if cluster_of_root[r] == usize::MAX {
                cluster_of_root[r] = map.members.len();
                map.members.push(Vec::new());
            }
            map.members[cluster_of_root[r]].push(b);
            map.cluster_of[b] = Some(cluster_of_root[r]);
        }
        for members in &map.members {
            let first = map.total;
            for &b in members {
                map.start[b] = map.total;
                map.count[b] = bodies[b].ndof();
                map.total += map.count[b];
            }
            map.cluster_range.push(first..map.total);
        }
        map
    }

    /// Length of the global DOF vector.
    pub fn total(&self) -> usize {
        self.total
    }

    /// DOF range of body `b` (empty for a fixed body).
    pub fn range(&self, b: usize) -> Range<usize> {
        self.start[b]..self.start[b] + self.count[b]
    }

    pub fn cluster_of(&self, b: usize) -> Option<usize> {
        self.cluster_of[b]
    }

    pub fn clusters(&self) -> usize {
        self.members.len()
    }

    /// Bodies of cluster `c`, in DOF order.
    pub fn members(&self, c: usize) -> &[usize] {
        &self.members[c]
    }

    /// DOF range of cluster `c`.
    pub fn cluster_range(&self, c: usize) -> Range<usize> {
        self.cluster_range[c].clone()
    }

    /// Body `b`'s part of a global vector, padded to [`Dofs`] (zero for a fixed body).
    pub fn gather(&self, v: &[f64], b: usize) -> Dofs {
        let mut d = Dofs::zeros();
        for (i, x) in v[self.range(b)].iter().enumerate() {
            d[i] = *x;
        }
        d
    }

    /// Adds body `b`'s padded vector into a global vector.
    pub fn scatter_add(&self, v: &mut [f64], b: usize, d: &Dofs) {
        for (i, x) in v[self.range(b)].iter_mut().enumerate() {
            *x += d[i];
        }
    }
}

fn root(parent: &mut [usize], mut x: usize) -> usize {
    while parent[x] != x {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    x
}
