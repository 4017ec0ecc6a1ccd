//! The contact law as box bounds of the VI (math note §4.1), recomputed from the current
//! forces in the outer compatibility loop (§4.3): normal [0, ∞) or [−t_share, ∞) for an intact
//! cemented joint (§4.5); tangential ±(c_share + μ p_n) (paper eq. 19, §4.6); rolling
//! ±δ p_n (§4.4). Shares of a joint's cohesion and tensile strength between its two adjoint
//! contacts follow the mobilization-equalizing rules of §4.5–4.6.

use crate::vi::{BlockLaw, BoundRule};

/// One contact's law and row layout, as the bound rule sees it.
#[derive(Debug, Clone, Copy, Default)]
pub struct Law {
    /// First VI row of the contact: normal; +1 tangential; +2 rolling if `rolling > 0`.
    pub row: usize,
    /// Coulomb coefficient μ.
    pub friction: f64,
    /// Cohesive capacity of the contact's joint [N] (stress × overlap length).
    pub cohesion: f64,
    /// Tensile capacity of the joint [N] while bonded (stress × overlap length).
    pub tensile: f64,
    /// Rolling friction length δ [m]; 0: no rolling row.
    pub rolling: f64,
    /// Intact cemented joint.
    pub bonded: bool,
    /// The other contact of the joint, if both ends exist.
    pub partner: Option<usize>,
    /// Newton's normal coefficient of restitution e (math note §10.15).
    pub restitution: f64,
}

impl Law {
    /// Number of VI rows of the contact.
    pub fn rows(&self) -> usize {
        if self.rolling > 0.0 { 3 } else { 2 }
    }
}

/// The QVI bounds of all contacts of a step.
pub struct ContactBounds<'a> {
    pub laws: &'a [Law],
    /// Share a joint's cohesion between its contacts (off: each gets all of it, DDA-d).
    pub share_cohesion: bool,
}

impl ContactBounds<'_> {
    #[inline(always)]
    fn forces(&self, k: usize, z: &[f64]) -> [f64; 2] {
        let r = self.laws[k].row;
        [z[r], z[r + 1]]
    }

    /// Tensile bound t_k of contact k for the iterate z (0 unless bonded).
    #[inline(always)]
    pub fn tensile_bound(&self, k: usize, z: &[f64]) -> f64 {
        let law = &self.laws[k];
        if !law.bonded {
            return 0.0;
        }
        match law.partner {
            Some(l) => tensile_share(law.tensile, self.forces(k, z)[0], self.forces(l, z)[0]),
            None => law.tensile,
        }
    }

    /// Tangential bound τ_k of contact k for the iterate z. Cohesion acts on a closed or
    /// bonded contact only.
    #[inline(always)]
    pub fn tangential_bound(&self, k: usize, z: &[f64]) -> f64 {
        let law = &self.laws[k];
        let pn = self.forces(k, z)[0];
        if pn <= 0.0 && !law.bonded {
            return 0.0;
        }
        self.cohesion(k, z) + law.friction * pn.max(0.0)
    }

    /// Cohesion c_k of contact k for the iterate z: its share of the joint's (§4.6).
    #[inline(always)]
    fn cohesion(&self, k: usize, z: &[f64]) -> f64 {
        let law = &self.laws[k];
        match (law.partner, self.share_cohesion) {
            (Some(l), true) => {
                cohesion_share(law.cohesion, law.friction, self.forces(k, z), self.forces(l, z))
            }
            _ => law.cohesion,
        }
    }
}

/// Block k is contact k: rows normal, tangential and (if rolling) rolling, starting at
/// `laws[k].row`; `z` is the whole iterate (joint partners read each other's forces).
impl BoundRule for ContactBounds<'_> {
    /// Inlined, with the helpers above, into the trait's `all_bounds` loop: as calls they cost
    /// a measurable share of a warm step (callgrind, `benches/step.rs`).
    #[inline(always)]
    fn block_bounds(&self, k: usize, z: &[f64], lo: &mut [f64], hi: &mut [f64]) {
        let law = &self.laws[k];
        lo[0] = -self.tensile_bound(k, z);
        hi[0] = f64::INFINITY;
        let tau = self.tangential_bound(k, z);
        lo[1] = -tau;
        hi[1] = tau;
        if law.rolling > 0.0 {
            let m = law.rolling * z[law.row].max(0.0);
            lo[2] = -m;
            hi[2] = m;
        }
    }

    /// In the sweeps' two halves: each block's bounds read only z and the laws.
    fn all_bounds_par(&self, blocks: &[usize], z: &[f64], lo: &mut [f64], hi: &mut [f64], par: bool) {
        crate::vi::all_bounds_in_halves(self, blocks, z, lo, hi, par);
    }

    /// The bounds as functions of p_n (math note §4.7), the partner's forces frozen at z:
    /// τ = c + μ p_n for p_n > 0 and c (bonded) or 0 for p_n <= 0; rolling δ max(p_n, 0).
    fn block_law(&self, k: usize, z: &[f64]) -> Option<BlockLaw> {
        let law = &self.laws[k];
        let c = self.cohesion(k, z);
        // Tension: the joint's capacity less the partner's current tension, t − max(−p_l, 0),
        // rather than the proportional share (§4.5). Both describe total tension <= t, but the
        // share rule also admits "winner takes all" fixed points (p_l = 0 gives contact l no
        // tensile bound, so it may open) that a Gauss-Seidel sweep runs into; every fixed point
        // of this form is one of the share rule (math note §4.7).
        let tension = match (law.bonded, law.partner) {
            (false, _) => 0.0,
            (true, None) => law.tensile,
            (true, Some(l)) => (law.tensile - (-self.forces(l, z)[0]).max(0.0)).clamp(0.0, law.tensile),
        };
        Some(BlockLaw {
            tension,
            a: [c, 0.0],
            b: [law.friction, law.rolling.max(0.0)],
            a_open: [if law.bonded { c } else { 0.0 }, 0.0],
        })
    }
}

/// Share c1 of a joint's cohesion c for contact 1 with forces `p1 = (p_n, p_t)`, partner `p2`
/// (math note §4.6): both contacts at the same mobilization |p_t|/(c_i + μ p_n); equal split
/// when neither carries shear.
pub fn cohesion_share(c: f64, mu: f64, p1: [f64; 2], p2: [f64; 2]) -> f64 {
    let (t1, t2) = (p1[1].abs(), p2[1].abs());
    if t1 + t2 <= 0.0 {
        return 0.5 * c;
    }
    let (n1, n2) = (p1[0].max(0.0), p2[0].max(0.0));
    ((t1 * (c + mu * n2) - mu * n1 * t2) / (t1 + t2)).clamp(0.0, c)
}

/// Share t1 of a joint's tensile strength t for contact 1 with normal force `p1`, partner
/// `p2` (math note §4.5, the paper's k_t): proportional to the tensions max(−p_n, 0); equal
/// split when neither is in tension.
pub fn tensile_share(t: f64, p1: f64, p2: f64) -> f64 {
    let (a, b) = ((-p1).max(0.0), (-p2).max(0.0));
    if a + b <= 0.0 { 0.5 * t } else { t * a / (a + b) }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Math note §4.6, μ = 0: c1/c2 = |p1t|/|p2t|; shares always add up to c.
    #[test]
    fn cohesion_shares_follow_shear_ratio() {
        let c1 = cohesion_share(400.0, 0.0, [4600.0, -100.0], [5400.0, -300.0]);
        assert!((c1 - 100.0).abs() < 1e-12);
        let c2 = cohesion_share(400.0, 0.0, [5400.0, -300.0], [4600.0, -100.0]);
        assert!((c1 + c2 - 400.0).abs() < 1e-12);
        assert_eq!(cohesion_share(400.0, 0.5, [1.0, 0.0], [1.0, 0.0]), 200.0);
    }

    /// With friction the shares equalize |p_t|/(c_i + μ p_n): check the mobilization ratio.
    #[test]
    fn cohesion_shares_equalize_mobilization() {
        let (c, mu, p1, p2) = (400.0, 0.3, [1000.0, 250.0], [3000.0, 900.0]);
        let c1 = cohesion_share(c, mu, p1, p2);
        let c2 = c - c1;
        let m1 = p1[1] / (c1 + mu * p1[0]);
        let m2 = p2[1] / (c2 + mu * p2[0]);
        assert!((m1 - m2).abs() < 1e-12, "{m1} vs {m2}");
    }

    /// Math note §4.5 / paper eqs. 70–73: t1 = t |p1|/(|p1| + |p2|) on the tensile parts.
    #[test]
    fn tensile_shares_follow_tensions() {
        assert_eq!(tensile_share(2000.0, -750.0, -250.0), 1500.0);
        assert_eq!(tensile_share(2000.0, -1000.0, 10.0), 2000.0);
        assert_eq!(tensile_share(2000.0, 5.0, 10.0), 1000.0);
    }

    /// Without a joint partner the closed form of NSGS (math note §4.7) is the same box as
    /// `block_bounds` for any p_n: τ = c + μ p_n (p_n > 0), c bonded / 0 open (p_n <= 0, §10.4),
    /// rolling δ max(p_n, 0), tension t bonded / 0. Checked on both sides of p_n = 0, exactly.
    #[test]
    fn block_law_matches_block_bounds_without_partner() {
        for bonded in [false, true] {
            let law = Law {
                row: 0,
                friction: 0.4,
                cohesion: 3.0,
                tensile: 5.0,
                rolling: 0.1,
                bonded,
                partner: None,
                restitution: 1.0,
            };
            let laws = [law];
            let rule = ContactBounds { laws: &laws, share_cohesion: true };
            for pn in [-2.0, 0.0, 7.0] {
                let z = [pn, 0.5, 0.1];
                let (mut lo, mut hi) = ([0.0; 3], [0.0; 3]);
                rule.block_bounds(0, &z, &mut lo, &mut hi);
                let l = rule.block_law(0, &z).expect("contact laws have a closed form");
                assert_eq!(lo[0], -l.tension);
                for i in 0..2 {
                    let tau = if pn > 0.0 { l.a[i] + l.b[i] * pn } else { l.a_open[i] };
                    assert_eq!(
                        (lo[i + 1], hi[i + 1]),
                        (-tau, tau),
                        "bonded {bonded}, p_n {pn}, row {}",
                        i + 1
                    );
                }
            }
        }
    }
}
