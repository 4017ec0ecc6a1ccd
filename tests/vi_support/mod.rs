//! Shared helpers of the VI integration tests (`vi_kkt.rs`, `vi_networks.rs`): problem
//! generators with known structure (random W = B K⁻¹ Bᵀ, constructed box VIs, three-disk
//! rows, chains, contact grids), bound rules, and dense KKT checks independent of the
//! solver's sparse code.

#![allow(dead_code)]

use nalgebra::DMatrix;
use pbdda::vi::{BoundRule, FixedBounds, Operator, Options, Problem, Report, Solver};
use sprs::{CsMat, TriMat};

/// xorshift64*: small, deterministic, good enough for test data.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }
    pub fn below(&mut self, k: usize) -> usize {
        (self.next_u64() % k as u64) as usize
    }
}

/// Dense symmetric matrix -> CSR with both triangles stored (exact zeros dropped).
pub fn to_csr(w: &DMatrix<f64>) -> CsMat<f64> {
    let mut t = TriMat::new((w.nrows(), w.ncols()));
    for i in 0..w.nrows() {
        for j in 0..w.ncols() {
            if w[(i, j)] != 0.0 {
                t.add_triplet(i, j, w[(i, j)]);
            }
        }
    }
    t.to_csr()
}

/// W = B K⁻¹ Bᵀ (math note eq. 3.1) with B m×n uniform in [-1, 1] and K = AᵀA + I/2 SPD,
/// times `scale`; symmetrized exactly. Rank <= min(m, n), so W is singular when m > n.
pub fn random_w(rng: &mut Rng, m: usize, n: usize, scale: f64) -> DMatrix<f64> {
    let b = DMatrix::from_fn(m, n, |_, _| rng.range(-1.0, 1.0));
    let a = DMatrix::from_fn(n, n, |_, _| rng.range(-1.0, 1.0));
    let k = a.transpose() * &a + DMatrix::identity(n, n) * 0.5;
    let kinv = k.cholesky().expect("K is SPD").inverse();
    let w = &b * kinv * b.transpose() * scale;
    (&w + w.transpose()) * 0.5
}

/// A box VI with a known solution: random bounds (each side infinite with probability
/// 1/3), a random activity pattern for z*, multipliers lambda of the right sign on active
/// rows (sometimes 0: degenerate) and q = lambda − W z*, so that G(z*) = lambda satisfies
/// the KKT conditions.
pub fn constructed_vi(rng: &mut Rng, w: &DMatrix<f64>, zscale: f64) -> Constructed {
    let m = w.nrows();
    let (mut lo, mut hi, mut zs, mut lam) = (vec![0.0; m], vec![0.0; m], vec![0.0; m], vec![0.0; m]);
    let (mut free, mut degenerate) = (Vec::new(), Vec::new());
    let gscale = zscale * w.diagonal().max();
    for i in 0..m {
        let c = rng.range(-1.0, 1.0) * zscale;
        lo[i] = if rng.below(3) == 0 { f64::NEG_INFINITY } else { c - rng.unit() * zscale };
        hi[i] = if rng.below(3) == 0 { f64::INFINITY } else { c + rng.unit() * zscale };
        let mult = if rng.below(5) == 0 { 0.0 } else { rng.unit() * gscale };
        match rng.below(3) {
            0 if lo[i].is_finite() => {
                zs[i] = lo[i];
                lam[i] = mult;
            }
            1 if hi[i].is_finite() => {
                zs[i] = hi[i];
                lam[i] = -mult;
            }
            _ => {
                let (a, b) = (lo[i].max(c - zscale), hi[i].min(c + zscale));
                zs[i] = rng.range(a, b);
                free.push(i);
                continue;
            }
        }
        if mult == 0.0 {
            degenerate.push(i);
        }
    }
    let wz = w * DMatrix::from_column_slice(m, 1, &zs);
    let q = (0..m).map(|i| lam[i] - wz[i]).collect();
    Constructed { q, lo, hi, zs, free, degenerate }
}

pub struct Constructed {
    pub q: Vec<f64>,
    pub lo: Vec<f64>,
    pub hi: Vec<f64>,
    /// A solution (G(z*) = lambda).
    pub zs: Vec<f64>,
    /// Rows strictly inside the box at z*.
    pub free: Vec<usize>,
    /// Rows at a bound with a zero multiplier (degenerate complementarity).
    pub degenerate: Vec<usize>,
}

/// G = q + W z, computed densely (independently of the solver's sparse code).
pub fn gap(w: &DMatrix<f64>, q: &[f64], z: &[f64]) -> Vec<f64> {
    let wz = w * DMatrix::from_column_slice(z.len(), 1, z);
    (0..z.len()).map(|i| q[i] + wz[i]).collect()
}

/// KKT conditions of the box VI at the solver tolerance `eps`.
///
/// Why these tolerances: the solver guarantees the scaled natural residual
/// |z_j − P[z_j − G_j/D_j]| <= eps Z, Z = max(1, ||z||_inf) (math note §4.3). For G_j > 0
/// that component equals min(z_j − lo_j, G_j/D_j), for G_j < 0 it is
/// min(hi_j − z_j, −G_j/D_j). Hence: z_j within `ztol = eps Z` of lo_j counts as active
/// lower (then only G_j >= −gtol is required), within ztol of hi_j as active upper
/// (G_j <= gtol), otherwise |G_j| <= gtol, with `gtol = eps D_j Z` (D_j <= ||W||) plus the
/// round-off of forming q + W z, 1e-12 (||q||_inf + ||W||_inf Z). lo <= z <= hi must hold
/// exactly.
pub fn check_kkt(
    w: &DMatrix<f64>,
    q: &[f64],
    lo: &[f64],
    hi: &[f64],
    z: &[f64],
    eps: f64,
) -> Result<(), String> {
    check_kkt_slack(w, q, lo, hi, z, eps, 0.0)
}

/// [`check_kkt`] for a box known only up to `slack` per bound (QVI: the box of the returned
/// z may differ from the last box the solver used by the outer tolerance). lo − slack <= z
/// <= hi + slack, and "active" means within ztol + slack of a bound.
pub fn check_kkt_slack(
    w: &DMatrix<f64>,
    q: &[f64],
    lo: &[f64],
    hi: &[f64],
    z: &[f64],
    eps: f64,
    slack: f64,
) -> Result<(), String> {
    let g = gap(w, q, z);
    let zn = z.iter().fold(1.0f64, |a, v| a.max(v.abs()));
    let qn = q.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let wn = (0..w.nrows()).map(|i| w.row(i).iter().map(|v| v.abs()).sum::<f64>()).fold(0.0, f64::max);
    let round = 1e-12 * (qn + wn * zn);
    let ztol = eps * zn * (1.0 + 1e-9) + slack;
    for j in 0..z.len() {
        if !(lo[j] - slack <= z[j] && z[j] <= hi[j] + slack) {
            return Err(format!("row {j}: z = {} outside [{}, {}]", z[j], lo[j], hi[j]));
        }
        let gtol = eps * w[(j, j)].max(0.0) * zn + round;
        let at_lo = z[j] - lo[j] <= ztol;
        let at_hi = hi[j] - z[j] <= ztol;
        if !at_hi && g[j] < -gtol {
            return Err(format!("row {j}: G = {} < -{gtol} with z below hi", g[j]));
        }
        if !at_lo && g[j] > gtol {
            return Err(format!("row {j}: G = {} > {gtol} with z above lo", g[j]));
        }
    }
    Ok(())
}

pub fn inf_norm(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |a, x| a.max(x.abs()))
}

/// Conditioning of a constructed instance for first-order methods: the largest ratio
/// max eig / min nonzero eig of the Jacobi-scaled principal block W_FF over the row sets
/// F = free ∪ S, S any subset of the degenerate rows (at a bound with zero multiplier), i.e.
/// over every face of the box that touches the solution set. Eigenvalues below 1e-11 max
/// count as exact zeros (rank deficiency of W with m > n is harmless: W z stays unique).
/// The PC method converges linearly with a rate governed by this number (the error-bound
/// constant of the affine VI), so random instances where it is huge (it reaches 1e7 on about
/// 1 % of the draws) are out of reach of any first-order method in a test's time budget.
pub fn face_condition(w: &DMatrix<f64>, c: &Constructed) -> f64 {
    let deg = &c.degenerate[..c.degenerate.len().min(10)];
    let s = |j: usize| 1.0 / w[(j, j)].max(f64::MIN_POSITIVE).sqrt();
    let mut worst = 1.0f64;
    for mask in 0u32..(1 << deg.len()) {
        let rows: Vec<usize> = c
            .free
            .iter()
            .copied()
            .chain(deg.iter().enumerate().filter(|(b, _)| mask >> b & 1 == 1).map(|(_, &j)| j))
            .collect();
        if rows.is_empty() {
            continue;
        }
        let sub =
            DMatrix::from_fn(rows.len(), rows.len(), |i, j| w[(rows[i], rows[j])] * s(rows[i]) * s(rows[j]));
        let ev = sub.symmetric_eigenvalues();
        let mx = ev.max();
        if mx <= 0.0 {
            continue;
        }
        let mn = ev.iter().copied().filter(|&e| e > 1e-11 * mx).fold(f64::INFINITY, f64::min);
        worst = worst.max(mx / mn);
    }
    worst
}

pub fn opts(tol: f64, jacobi: bool) -> Options {
    Options { tolerance: tol, max_iterations: 2_000_000, max_outer: 50, jacobi, ..Options::default() }
}

/// ||W||_inf (max absolute row sum).
pub fn w_norm(w: &DMatrix<f64>) -> f64 {
    (0..w.nrows()).map(|i| w.row(i).iter().map(|v| v.abs()).sum::<f64>()).fold(0.0, f64::max)
}

/// Coulomb friction with cohesion (math note §4.1, eq. 19): rows come in (normal, tangent)
/// pairs; normal [0, inf), tangent [−tau, tau] with tau = c + mu max(z_n, 0).
pub struct Coulomb {
    pub mu: f64,
    pub c: f64,
}

impl BoundRule for Coulomb {
    /// Block k is the pair of rows 2k, 2k + 1.
    fn block_bounds(&self, k: usize, z: &[f64], lo: &mut [f64], hi: &mut [f64]) {
        let tau = self.c + self.mu * z[2 * k].max(0.0);
        lo[0] = 0.0;
        hi[0] = f64::INFINITY;
        lo[1] = -tau;
        hi[1] = tau;
    }
}

/// The Coulomb QVI at the returned z: KKT of the box VI whose box is recomputed from z
/// itself (the QVI fixed point). Tolerances as in [`check_kkt`], plus a slack of
/// eps (1 + max|bound|) on the box: the solver stops when the box moved by at most
/// eps max(1, max|finite bound|) between its last two passes (math note §4.3).
pub fn check_coulomb(w: &DMatrix<f64>, q: &[f64], rule: &Coulomb, z: &[f64], eps: f64) -> Result<(), String> {
    let m = z.len();
    let (mut lo, mut hi) = (vec![0.0; m], vec![0.0; m]);
    rule.all_bounds(&pairs(m), z, &mut lo, &mut hi);
    let bmax = hi.iter().copied().filter(|h| h.is_finite()).fold(0.0, f64::max);
    check_kkt_slack(w, q, &lo, &hi, z, eps, eps * (1.0 + bmax))
}

/// Three rigid disks side by side on a fixed floor (math note §3.1, rigid-body W):
/// radii 0.5..1.5, densities 0.5..2, random velocities (vx, vy, omega) in [-1, 1], gravity
/// 10, dt = 0.01. Contacts: each disk on the floor (n = +y into the disk, tau = cw(n) = +x,
/// arm (0, −r)) and each neighbour pair (n = +x into the right disk A, tau = (0, −1), arms
/// (−r_A, 0) and (+r_B, 0)). Rows (normal, tangent) per contact, q = B d^f with
/// d^f = dt v0 + dt²/2 g (math note §1.2, g0 = 0), W = B (dt²/2) M⁻¹ Bᵀ.
pub fn disk_row(rng: &mut Rng) -> (DMatrix<f64>, Vec<f64>) {
    let dt = 0.01;
    let radius: Vec<f64> = (0..3).map(|_| rng.range(0.5, 1.5)).collect();
    let rho: Vec<f64> = (0..3).map(|_| rng.range(0.5, 2.0)).collect();
    let cross = |a: [f64; 2], d: [f64; 2]| a[0] * d[1] - a[1] * d[0];
    // (body A, arm A, body B with arm, normal)
    type Con = (usize, [f64; 2], Option<(usize, [f64; 2])>, [f64; 2]);
    let mut cons: Vec<Con> = Vec::new();
    for (k, r) in radius.iter().enumerate() {
        cons.push((k, [0.0, -r], None, [0.0, 1.0]));
    }
    for k in 0..2 {
        cons.push((k + 1, [-radius[k + 1], 0.0], Some((k, [radius[k], 0.0])), [1.0, 0.0]));
    }
    let m = 2 * cons.len();
    let mut b = DMatrix::zeros(m, 9);
    for (c, &(a, arm_a, other, n)) in cons.iter().enumerate() {
        for (r, dir) in [n, [n[1], -n[0]]].into_iter().enumerate() {
            let row = 2 * c + r;
            b[(row, 3 * a)] = dir[0];
            b[(row, 3 * a + 1)] = dir[1];
            b[(row, 3 * a + 2)] = cross(arm_a, dir);
            if let Some((bb, arm_b)) = other {
                b[(row, 3 * bb)] = -dir[0];
                b[(row, 3 * bb + 1)] = -dir[1];
                b[(row, 3 * bb + 2)] = -cross(arm_b, dir);
            }
        }
    }
    let mut minv = DMatrix::zeros(9, 9);
    let mut df = DMatrix::zeros(9, 1);
    for k in 0..3 {
        let mass = std::f64::consts::PI * radius[k] * radius[k] * rho[k];
        let j = mass * radius[k] * radius[k] / 2.0;
        for (d, inv) in [1.0 / mass, 1.0 / mass, 1.0 / j].into_iter().enumerate() {
            minv[(3 * k + d, 3 * k + d)] = dt * dt / 2.0 * inv;
            df[3 * k + d] = rng.range(-1.0, 1.0) * dt;
        }
        df[3 * k + 1] -= dt * dt / 2.0 * 10.0;
    }
    let w = &b * minv * b.transpose();
    let q = (&b * df).iter().copied().collect();
    ((&w + w.transpose()) * 0.5, q)
}

/// One block per row (the blocks of a [`FixedBounds`] problem do not matter).
pub fn singles(m: usize) -> Vec<usize> {
    (0..=m).collect()
}

/// Blocks of two rows (normal, tangent): the contacts of a [`Coulomb`] problem.
pub fn pairs(m: usize) -> Vec<usize> {
    (0..=m / 2).map(|k| 2 * k).collect()
}

/// Solves from a zero warm start with a fresh [`Solver`]; blocks `singles` for
/// [`FixedBounds`], `pairs` otherwise.
pub fn run(
    w: &dyn Operator,
    q: &[f64],
    rule: &dyn BoundRule,
    o: &Options,
    fixed: bool,
) -> (Report, Vec<f64>, Solver) {
    let mut ws = Solver::new();
    let mut z = vec![0.0; q.len()];
    let blocks = if fixed { singles(q.len()) } else { pairs(q.len()) };
    let rep = ws.solve(&Problem { w, q, blocks: &blocks }, rule, &mut z, o);
    (rep, z, ws)
}

/// Face-condition cap of the property tests (see `face_condition`): about 3 % of the
/// random draws exceed it and are rejected; below it PC needs at most ~1e5 products.
pub const MAX_FACE_CONDITION: f64 = 1e4;

/// A 1-D chain of bodies along x with one row per contact: gap rate = relative approach,
/// W = B (dt²/2) M⁻¹ Bᵀ (math note §3.1), q = (v_right − v_left) dt, a force p >= 0 pushes
/// the right body to +x and the left one to −x (it opens its own gap, math note §0).
pub fn chain(mass: &[f64], vel: &[f64], pairs: &[(usize, usize)]) -> (DMatrix<f64>, Vec<f64>) {
    let dt = 0.01;
    let (m, nb) = (pairs.len(), mass.len());
    let mut b = DMatrix::zeros(m, nb);
    let mut q = vec![0.0; m];
    for (k, &(l, r)) in pairs.iter().enumerate() {
        b[(k, r)] = 1.0;
        b[(k, l)] = -1.0;
        q[k] = (vel[r] - vel[l]) * dt;
    }
    let minv =
        DMatrix::from_diagonal(&nalgebra::DVector::from_iterator(nb, mass.iter().map(|m| dt * dt / 2.0 / m)));
    let w = &b * minv * b.transpose();
    ((&w + w.transpose()) * 0.5, q)
}

/// Heavy "static" base: bodies A, B of mass 1e12 at rest (B drifting away from A at 1e-3)
/// and light bodies L1..L4 (masses 1, 2, 0.5, 1) driven into them: chain L3 L2 L1 | A | B L4.
/// The A–B row has W_jj = 2e-12 dt²/2 against about dt²/2 for the light rows (twelve
/// orders of magnitude); it stays open (its force is 0 at the solution).
pub fn heavy_base() -> (DMatrix<f64>, Vec<f64>) {
    // bodies: 0 A, 1 B, 2 L1, 3 L2, 4 L3, 5 L4
    let mass = [1e12, 1e12, 1.0, 2.0, 0.5, 1.0];
    let vel = [0.0, 1e-3, 1.0, 2.0, 3.0, -1.0];
    chain(&mass, &vel, &[(4, 3), (3, 2), (2, 0), (0, 1), (1, 5)])
}

/// 2-D contact network (the same as in `benches/vi.rs`): rigid disks on an nx×ny grid
/// (unit spacing, radius 0.5, random masses 0.5..2, J = m/8), contacts with the right and
/// upper neighbours and with the floor, (normal, tangent) rows, W = B (dt²/2) M⁻¹ Bᵀ assembled sparse (about 14
/// nonzeros per row), q = B d^f with d^f = dt v + dt²/2 g (math note §1.2), random
/// velocities v in [-vamp, vamp], gravity 10 down. Returns (W, q).
pub fn grid_network(nx: usize, ny: usize, seed: u64, vamp: f64) -> (CsMat<f64>, Vec<f64>) {
    let mut rng = Rng::new(seed);
    let dt = 0.01;
    let nb = nx * ny;
    let minv: Vec<f64> = (0..nb)
        .flat_map(|_| {
            let m = rng.range(0.5, 2.0);
            [1.0 / m, 1.0 / m, 8.0 / m]
        })
        .collect();
    let mut trip: Vec<(usize, usize, f64)> = Vec::new();
    let mut row = 0;
    let mut add = |a: usize, b: Option<usize>, n: [f64; 2]| {
        for dir in [n, [n[1], -n[0]]] {
            // contact point midway: arm −0.5 n from A, +0.5 n from B; r × dir
            let ca = -0.5 * n[0] * dir[1] + 0.5 * n[1] * dir[0];
            trip.extend([(row, 3 * a, dir[0]), (row, 3 * a + 1, dir[1]), (row, 3 * a + 2, ca)]);
            if let Some(b) = b {
                trip.extend([(row, 3 * b, -dir[0]), (row, 3 * b + 1, -dir[1]), (row, 3 * b + 2, ca)]);
            }
            row += 1;
        }
    };
    for iy in 0..ny {
        for ix in 0..nx {
            let k = iy * nx + ix;
            if iy == 0 {
                add(k, None, [0.0, 1.0]);
            }
            if ix + 1 < nx {
                add(k + 1, Some(k), [1.0, 0.0]);
            }
            if iy + 1 < ny {
                add(k + nx, Some(k), [0.0, 1.0]);
            }
        }
    }
    let mut bm = TriMat::new((row, 3 * nb));
    let mut bs = TriMat::new((row, 3 * nb));
    for &(i, j, v) in &trip {
        bm.add_triplet(i, j, v);
        bs.add_triplet(i, j, v * minv[j] * dt * dt / 2.0);
    }
    let b: CsMat<f64> = bm.to_csr();
    let bscaled: CsMat<f64> = bs.to_csr();
    let btr: CsMat<f64> = b.transpose_view().to_csr();
    let w: CsMat<f64> = &bscaled * &btr;
    let df: Vec<f64> = (0..3 * nb)
        .map(|j| rng.range(-vamp, vamp) * dt - if j % 3 == 1 { dt * dt / 2.0 * 10.0 } else { 0.0 })
        .collect();
    let q = b.outer_iterator().map(|r| r.iter().map(|(j, &x)| x * df[j]).sum::<f64>()).collect();
    (w, q)
}

/// Frictionless box of `grid_network`: normal rows [0, inf), tangent rows fixed at 0.
pub fn frictionless(m: usize) -> FixedBounds {
    FixedBounds {
        lo: vec![0.0; m],
        hi: (0..m).map(|i| if i % 2 == 0 { f64::INFINITY } else { 0.0 }).collect(),
    }
}

/// W behind the trait without its CSR storage: the solver takes its matrix-free path
/// (products through `apply`, Jacobi scaling by vectors).
pub struct MatrixFree(pub CsMat<f64>);

impl Operator for MatrixFree {
    fn dim(&self) -> usize {
        self.0.dim()
    }
    fn apply(&self, z: &[f64], out: &mut [f64]) {
        self.0.apply(z, out);
    }
    fn diagonal(&self, out: &mut [f64]) {
        self.0.diagonal(out);
    }
}

/// Dense copy of a sparse W (for the independent checks).
pub fn dense(w: &CsMat<f64>) -> DMatrix<f64> {
    let mut d = DMatrix::zeros(w.rows(), w.cols());
    for (v, (i, j)) in w.iter() {
        d[(i, j)] += *v;
    }
    d
}
