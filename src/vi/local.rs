//! Exact local solvers of one block for the nonsmooth Gauss-Seidel sweep (math note §4.7):
//! find z in the block's box K(z) with w = A z + r, (z' − z)ᵀ w >= 0 for all z' in K(z), A the
//! block's 2×2 or 3×3 diagonal block of W and r = q_k + Σ_{l≠k} W_kl z_l. The cases (open,
//! stick, slide ±, for friction and rolling) are enumerated in closed form: each case fixes
//! which rows are at a bound, the remaining equations w_R = 0 are a linear system of at most
//! 3 unknowns, and the case is accepted when its sign conditions hold. No inner iteration.

// Fixed-size 3×3 algebra indexes rows and columns together; NaN-safe `!(a > b)` tests.
#![allow(clippy::needless_range_loop, clippy::neg_cmp_op_on_partial_ord)]

use super::BlockLaw;

/// Largest block handled here (normal, tangential, rolling).
pub(super) const MAX: usize = 3;

/// Relative tolerance of the case checks (round-off only).
const EPS: f64 = 1e-12;

/// One block's data: m rows, A row-major m×m (stride MAX), r.
pub(super) struct Local {
    pub m: usize,
    pub a: [[f64; MAX]; MAX],
    pub r: [f64; MAX],
}

impl Local {
    /// w = A z + r.
    fn w(&self, z: &[f64; MAX]) -> [f64; MAX] {
        let mut w = [0.0; MAX];
        for i in 0..self.m {
            w[i] = self.r[i] + (0..self.m).map(|j| self.a[i][j] * z[j]).sum::<f64>();
        }
        w
    }

    /// Scales for the tolerances: |z| and |w| magnitudes of the candidate.
    fn scales(&self, z: &[f64; MAX]) -> (f64, f64) {
        let zs = z[..self.m].iter().fold(1e-300f64, |s, x| s.max(x.abs()));
        let mut ws = self.r[..self.m].iter().fold(1e-300f64, |s, x| s.max(x.abs()));
        for i in 0..self.m {
            ws = ws.max(self.a[i][i] * zs);
        }
        (zs, ws)
    }

    /// Exact solution for a contact law (math note §4.7): row 0 normal with p >= −tension,
    /// rows 1.. with |z_i| <= tau_i(p). Writes z; returns false if no case fits (round-off
    /// in a degenerate block), in which case z holds the least violating candidate.
    pub fn solve_law(&self, law: &BlockLaw, z: &mut [f64; MAX]) -> bool {
        let nt = self.m - 1;
        let mut best = (f64::INFINITY, *z);
        let states = 3usize.pow(nt as u32);
        // Normal modes: closed with p > 0 (tau = a + b p), open at p = −tension
        // (tau = a_open), closed in tension −tension < p <= 0 (tau = a_open).
        let lo = -law.tension;
        for mode in 0..3 {
            if mode == 2 && lo >= 0.0 {
                break;
            }
            for s in 0..states {
                let sign = signs(s, nt);
                let (alpha, beta) = if mode == 0 { (law.a, law.b) } else { (law.a_open, [0.0; 2]) };
                let Some(c) = self.case(mode != 1, lo, &sign, alpha, beta) else { continue };
                let v = self.violation(mode, lo, &sign, alpha, beta, &c);
                if v <= EPS {
                    *z = c;
                    return true;
                }
                if v < best.0 {
                    best = (v, c);
                }
            }
        }
        *z = best.1;
        false
    }

    /// Candidate of one case: normal closed (w_0 = 0, p unknown) or open (p = lo); row i >= 1
    /// free (w_i = 0) when `sign[i-1] == 0`, else z_i = sign (alpha_i + beta_i p).
    fn case(
        &self,
        closed: bool,
        lo: f64,
        sign: &[f64; 2],
        alpha: [f64; 2],
        beta: [f64; 2],
    ) -> Option<[f64; MAX]> {
        // z = u + p v + Σ_free x_i e_i
        let (mut u, mut v) = ([0.0; MAX], [0.0; MAX]);
        v[0] = 1.0;
        for i in 1..self.m {
            u[i] = sign[i - 1] * alpha[i - 1];
            v[i] = sign[i - 1] * beta[i - 1];
        }
        if !closed {
            for i in 0..self.m {
                u[i] += lo * v[i];
            }
        }
        // unknown columns: v (if closed), e_i for free i; equation rows: 0 (if closed), free i
        let mut cols: [[f64; MAX]; MAX] = [[0.0; MAX]; MAX];
        let mut eqs = [0usize; MAX];
        let mut k = 0;
        if closed {
            cols[0] = v;
            eqs[0] = 0;
            k = 1;
        }
        for i in 1..self.m {
            if sign[i - 1] == 0.0 {
                let mut e = [0.0; MAX];
                e[i] = 1.0;
                cols[k] = e;
                eqs[k] = i;
                k += 1;
            }
        }
        let wu = self.w(&u);
        let mut mat = [[0.0; MAX]; MAX];
        let mut rhs = [0.0; MAX];
        for (a, &row) in eqs[..k].iter().enumerate() {
            for b in 0..k {
                mat[a][b] = (0..self.m).map(|j| self.a[row][j] * cols[b][j]).sum();
            }
            rhs[a] = -wu[row];
        }
        let x = solve_small(k, mat, rhs)?;
        let mut z = u;
        for b in 0..k {
            for j in 0..self.m {
                z[j] += x[b] * cols[b][j];
            }
        }
        z[..self.m].iter().all(|x| x.is_finite()).then_some(z)
    }

    /// Largest relative violation of the case's conditions by the candidate z.
    fn violation(
        &self,
        mode: usize,
        lo: f64,
        sign: &[f64; 2],
        alpha: [f64; 2],
        beta: [f64; 2],
        z: &[f64; MAX],
    ) -> f64 {
        let w = self.w(z);
        let (zs, ws) = self.scales(z);
        let p = z[0];
        let mut v: f64 = match mode {
            0 => (-p).max(lo - p) / zs,
            1 => -w[0] / ws,
            _ => (lo - p).max(p) / zs,
        };
        for i in 1..self.m {
            let tau = alpha[i - 1] + beta[i - 1] * p;
            v = v.max(-tau / zs);
            let s = sign[i - 1];
            v = v.max(if s == 0.0 { (z[i].abs() - tau) / zs } else { s * w[i] / ws });
        }
        v
    }

    /// Exact solution of the block's box VI with fixed bounds (rules without a closed-form
    /// law): every row free, at lo or at hi; 3^m cases. Same return convention as
    /// [`Self::solve_law`].
    pub fn solve_box(&self, lo: &[f64], hi: &[f64], z: &mut [f64; MAX]) -> bool {
        let mut best = (f64::INFINITY, *z);
        for s in 0..3usize.pow(self.m as u32) {
            // state per row: 0 free, 1 lo, 2 hi
            let mut st = [0usize; MAX];
            let mut c = s;
            for x in st.iter_mut().take(self.m) {
                *x = c % 3;
                c /= 3;
            }
            if (0..self.m).any(|i| (st[i] == 1 && !lo[i].is_finite()) || (st[i] == 2 && !hi[i].is_finite())) {
                continue;
            }
            let mut u = [0.0; MAX];
            let mut free = [0usize; MAX];
            let mut k = 0;
            for i in 0..self.m {
                match st[i] {
                    1 => u[i] = lo[i],
                    2 => u[i] = hi[i],
                    _ => {
                        free[k] = i;
                        k += 1;
                    }
                }
            }
            let wu = self.w(&u);
            let mut mat = [[0.0; MAX]; MAX];
            let mut rhs = [0.0; MAX];
            for a in 0..k {
                for b in 0..k {
                    mat[a][b] = self.a[free[a]][free[b]];
                }
                rhs[a] = -wu[free[a]];
            }
            let Some(x) = solve_small(k, mat, rhs) else { continue };
            for a in 0..k {
                u[free[a]] += x[a];
            }
            let w = self.w(&u);
            let (zs, ws) = self.scales(&u);
            let mut v: f64 = 0.0;
            for i in 0..self.m {
                v = v.max(match st[i] {
                    0 => (lo[i] - u[i]).max(u[i] - hi[i]) / zs,
                    1 => -w[i] / ws,
                    _ => w[i] / ws,
                });
            }
            if v <= EPS {
                *z = u;
                return true;
            }
            if v < best.0 && u.iter().all(|x| x.is_finite()) {
                best = (v, u);
            }
        }
        *z = best.1;
        false
    }
}

/// Signs of the tangential rows for case index s: 0 free, +1, −1 (free first: stick is the
/// common state of a resting pile).
fn signs(s: usize, nt: usize) -> [f64; 2] {
    let mut out = [0.0; 2];
    let mut c = s;
    for o in out.iter_mut().take(nt) {
        *o = [0.0, 1.0, -1.0][c % 3];
        c /= 3;
    }
    out
}

/// Solves the k×k system by Gaussian elimination with partial pivoting; `None` when it is
/// singular to round-off.
fn solve_small(k: usize, mut a: [[f64; MAX]; MAX], mut b: [f64; MAX]) -> Option<[f64; MAX]> {
    let scale =
        (0..k).flat_map(|i| (0..k).map(move |j| (i, j))).fold(0.0f64, |s, (i, j)| s.max(a[i][j].abs()));
    for c in 0..k {
        let p = (c..k).max_by(|&x, &y| a[x][c].abs().total_cmp(&a[y][c].abs()))?;
        if !(a[p][c].abs() > 1e-14 * scale) {
            return None;
        }
        a.swap(c, p);
        b.swap(c, p);
        for r in c + 1..k {
            let f = a[r][c] / a[c][c];
            for j in c..k {
                a[r][j] -= f * a[c][j];
            }
            b[r] -= f * b[c];
        }
    }
    let mut x = [0.0; MAX];
    for c in (0..k).rev() {
        let s: f64 = (c + 1..k).map(|j| a[c][j] * x[j]).sum();
        x[c] = (b[c] - s) / a[c][c];
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A disk on the floor pushed sideways: A = [[2, 0.5], [0.5, 1]], r = (−1, −1), μ = 0.3.
    /// Stick would need |z_t| > μ z_n, so it slides: z_t = μ z_n and w_n = 0 give
    /// 2 z_n + 0.5·0.3 z_n = 1, z_n = 1/2.15 (closed form), and w_t = 0.5 z_n + 0.3 z_n − 1 < 0.
    #[test]
    fn sliding_contact_in_closed_form() {
        let l = Local { m: 2, a: [[2.0, 0.5, 0.0], [0.5, 1.0, 0.0], [0.0; 3]], r: [-1.0, -1.0, 0.0] };
        let law = BlockLaw { tension: 0.0, a: [0.0; 2], b: [0.3, 0.0], a_open: [0.0; 2] };
        let mut z = [0.0; MAX];
        assert!(l.solve_law(&law, &mut z));
        let zn = 1.0 / 2.15;
        assert!((z[0] - zn).abs() < 1e-14 && (z[1] - 0.3 * zn).abs() < 1e-14, "{z:?}");
    }

    /// Separating contact (r_n > 0): open, no force; with tension t = 0.5 and a pull
    /// r_n = 2 the bond holds at p = −t... only if w_n >= 0 there: A_nn (−0.5) + 2 = 1 > 0.
    #[test]
    fn open_and_bonded_contacts() {
        let l = Local { m: 2, a: [[2.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0; 3]], r: [2.0, 0.0, 0.0] };
        let mut z = [0.0; MAX];
        let free = BlockLaw { tension: 0.0, a: [0.0; 2], b: [0.3, 0.0], a_open: [0.0; 2] };
        assert!(l.solve_law(&free, &mut z));
        assert_eq!(&z[..2], &[0.0, 0.0]);
        // tension 2 > 1 = r_n / A_nn: the bond carries p = −1 with w_n = 0
        let bonded = BlockLaw { tension: 2.0, a: [0.1, 0.0], b: [0.3, 0.0], a_open: [0.1, 0.0] };
        assert!(l.solve_law(&bonded, &mut z));
        assert!((z[0] + 1.0).abs() < 1e-14 && z[1] == 0.0, "{z:?}");
    }

    /// Box VI with fixed bounds equals the projection of the unconstrained solution when A is
    /// diagonal: z_i = clip(−r_i / A_ii, lo_i, hi_i).
    #[test]
    fn box_case_diagonal() {
        let l = Local { m: 3, a: [[2.0, 0.0, 0.0], [0.0, 4.0, 0.0], [0.0, 0.0, 1.0]], r: [-4.0, 8.0, -0.5] };
        let mut z = [0.0; MAX];
        assert!(l.solve_box(&[0.0, -1.0, -1.0], &[1.0, 1.0, 1.0], &mut z));
        assert_eq!(z, [1.0, -1.0, 0.5]);
    }
}
