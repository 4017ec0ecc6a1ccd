//! Observed order and Richardson extrapolation from three sized runs, with Roache's grid
//! convergence index (GCI) as the estimated error, in the form of Celik et al. (2008),
//! "Procedure for estimation and reporting of uncertainty due to discretization in CFD
//! applications", J. Fluids Eng. 130(7), 078001, which allows unequal refinement ratios.
//!
//! Sizes h1 < h2 < h3 (1 the finest) with values φ1, φ2, φ3; r21 = h2/h1, r32 = h3/h2;
//! ε21 = φ2 − φ1, ε32 = φ3 − φ2, s = sign(ε32/ε21). The observed order p solves
//!
//!   p = |ln|ε32/ε21| + q(p)| / ln r21,   q(p) = ln((r21^p − s)/(r32^p − s)),
//!
//! by fixed-point iteration from q = 0 (with r21 = r32, q = 0 and this is Richardson's
//! p = ln(ε32/ε21)/ln r). The extrapolated value (Richardson 1911, the h^p term eliminated) is
//!
//!   φ_ext = (r21^p φ1 − φ2)/(r21^p − 1),
//!
//! and the estimated error of the finest value is Roache's GCI (Roache 1994, J. Fluids Eng.
//! 116(3), 405-413; safety factor Fs = 1.25 for three values)
//!
//!   GCI = Fs |φ1 − φ2|/(r21^p − 1) = 1.25 |φ_ext − φ1|,
//!
//! a band around φ1 that holds the exact value with about 95 % confidence when the three runs
//! are in the asymptotic range; φ_ext lies inside it. For φ(h) = φ* + C h^p exactly, p and
//! φ_ext = φ* are recovered to rounding (tests below). No order is reported when the values do
//! not change monotonically (s < 0: oscillating convergence), when two of them are equal, or
//! when the iteration does not settle.

/// The extrapolation of one quantity.
#[derive(Debug, Clone, PartialEq)]
pub struct Extrapolation {
    /// What is extrapolated, e.g. `monitor.tip.uy`.
    pub quantity: String,
    /// Sizes, finest first.
    pub h: [f64; 3],
    /// Values at those sizes.
    pub values: [f64; 3],
    pub order: Option<f64>,
    pub extrapolated: Option<f64>,
    /// Roache's GCI of the finest value (absolute, the quantity's unit).
    pub gci: Option<f64>,
}

/// Safety factor of the GCI for three runs (Roache).
pub const SAFETY: f64 = 1.25;

/// Order, extrapolated value and GCI from sizes `h` and values `v`, finest first.
pub fn extrapolate(quantity: &str, h: [f64; 3], v: [f64; 3]) -> Extrapolation {
    let mut out = Extrapolation {
        quantity: quantity.to_owned(),
        h,
        values: v,
        order: None,
        extrapolated: None,
        gci: None,
    };
    let (r21, r32) = (h[1] / h[0], h[2] / h[1]);
    let (e21, e32) = (v[1] - v[0], v[2] - v[1]);
    let ratio = e32 / e21;
    // NaN in any of them fails the check too
    if r21.is_nan()
        || r32.is_nan()
        || r21 <= 1.0
        || r32 <= 1.0
        || e21 == 0.0
        || e32 == 0.0
        || ratio.is_nan()
        || ratio <= 0.0
    {
        return out;
    }
    let ratio = (e32 / e21).abs().ln();
    let mut p = ratio / r21.ln();
    let mut settled = false;
    for _ in 0..200 {
        let q = ((r21.powf(p) - 1.0) / (r32.powf(p) - 1.0)).ln();
        let next = (ratio + q).abs() / r21.ln();
        if !next.is_finite() {
            return out;
        }
        let done = (next - p).abs() <= 1e-14 * next.abs().max(1.0);
        p = next;
        if done {
            settled = true;
            break;
        }
    }
    if !settled || p <= 0.0 {
        return out;
    }
    let rp = r21.powf(p);
    let ext = (rp * v[0] - v[1]) / (rp - 1.0);
    out.order = Some(p);
    out.extrapolated = Some(ext);
    out.gci = Some(SAFETY * (v[0] - v[1]).abs() / (rp - 1.0));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Manufactured sequences φ(h) = φ* + C h^p: the formulas above are exact for them, so p
    /// and φ* come back to rounding (1e-9 relative: the differences ε lose ~6 digits of 16 when
    /// C h^p is 1e-3 of φ*), for equal and unequal ratios, rising and falling sequences.
    #[test]
    fn manufactured_sequences_are_extrapolated_exactly() {
        for (h, c, p, exact) in [
            ([0.1, 0.2, 0.4], 0.7, 2.0, -4.031e-4),
            ([0.125, 0.25, 0.5], -3.0, 1.0, 12.5),
            ([0.0811, 0.157, 0.341], 2.0e-3, 2.0, 1.0),
            ([1e-3, 2.3e-3, 4.1e-3], 5.0, 1.5, -2.0),
        ] {
            let v = h.map(|h: f64| exact + c * h.powf(p));
            let e = extrapolate("q", h, v);
            let (order, ext) = (e.order.expect("an order"), e.extrapolated.expect("a value"));
            assert!((order - p).abs() < 1e-9, "p = {p}: got {order}");
            assert!((ext - exact).abs() < 1e-9 * exact.abs().max(c.abs()), "exact {exact}: got {ext}");
            let gci = e.gci.expect("a GCI");
            assert!((gci - SAFETY * (v[0] - exact).abs()).abs() < 1e-9 * gci, "GCI {gci}");
        }
    }

    /// Oscillating or stagnant values have no order (Celik et al. 2008: s < 0 is oscillatory).
    #[test]
    fn no_order_without_monotone_convergence() {
        assert_eq!(extrapolate("q", [1.0, 2.0, 4.0], [1.0, 2.0, 1.5]).order, None);
        assert_eq!(extrapolate("q", [1.0, 2.0, 4.0], [1.0, 1.0, 1.5]).order, None);
        assert_eq!(extrapolate("q", [1.0, 1.0, 4.0], [1.0, 2.0, 3.5]).order, None);
    }
}
