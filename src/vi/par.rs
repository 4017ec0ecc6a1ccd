//! Blocked sweeps over the rows, serial or on rayon, with deterministic reductions: every
//! block stores its partial results and [`reduce`] combines them in block order, so serial
//! and parallel runs give bit-identical results.

use rayon::prelude::*;

/// Rows per block of every sweep.
pub(super) const BLOCK: usize = 2048;

/// Per-block results of a sweep: three sums and three maxima.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Partial {
    pub s0: f64,
    pub s1: f64,
    pub s2: f64,
    pub m0: f64,
    pub m1: f64,
    pub m2: f64,
}

/// Combines the blocks' partials in block order.
pub(super) fn reduce(parts: &[Partial]) -> Partial {
    parts.iter().fold(Partial::default(), |acc, p| Partial {
        s0: acc.s0 + p.s0,
        s1: acc.s1 + p.s1,
        s2: acc.s2 + p.s2,
        m0: acc.m0.max(p.m0),
        m1: acc.m1.max(p.m1),
        m2: acc.m2.max(p.m2),
    })
}

/// Runs `f(first_row, out_block)` over the blocks of `out`, storing each block's partial.
pub(super) fn run1<F>(par: bool, out: &mut [f64], parts: &mut [Partial], f: F) -> Partial
where
    F: Fn(usize, &mut [f64]) -> Partial + Sync,
{
    if par {
        out.par_chunks_mut(BLOCK)
            .zip(parts.par_iter_mut())
            .enumerate()
            .for_each(|(b, (o, p))| *p = f(b * BLOCK, o));
    } else {
        for (b, (o, p)) in out.chunks_mut(BLOCK).zip(parts.iter_mut()).enumerate() {
            *p = f(b * BLOCK, o);
        }
    }
    reduce(parts)
}

/// As [`run1`], with two output vectors.
pub(super) fn run2<F>(par: bool, o1: &mut [f64], o2: &mut [f64], parts: &mut [Partial], f: F) -> Partial
where
    F: Fn(usize, &mut [f64], &mut [f64]) -> Partial + Sync,
{
    if par {
        o1.par_chunks_mut(BLOCK)
            .zip(o2.par_chunks_mut(BLOCK))
            .zip(parts.par_iter_mut())
            .enumerate()
            .for_each(|(b, ((a, c), p))| *p = f(b * BLOCK, a, c));
    } else {
        for (b, ((a, c), p)) in
            o1.chunks_mut(BLOCK).zip(o2.chunks_mut(BLOCK)).zip(parts.iter_mut()).enumerate()
        {
            *p = f(b * BLOCK, a, c);
        }
    }
    reduce(parts)
}

/// Elementwise map over the blocks of `out` (no reduction).
pub(super) fn map<F>(par: bool, out: &mut [f64], parts: &mut [Partial], f: F)
where
    F: Fn(usize, &mut f64) + Sync,
{
    run1(par, out, parts, |r0, o| {
        for (k, x) in o.iter_mut().enumerate() {
            f(r0 + k, x);
        }
        Partial::default()
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Serial and parallel blocked sums are bit-identical (fixed block order), for a length
    /// that is not a multiple of the block size; the sum of 1..=n is n(n+1)/2 exactly (all
    /// partial sums are integers below 2^53).
    #[test]
    fn serial_equals_parallel() {
        let n = 3 * BLOCK + 17;
        let mut sums = Vec::new();
        for par in [false, true] {
            let mut out = vec![0.0; n];
            let mut parts = vec![Partial::default(); n.div_ceil(BLOCK)];
            let p = run1(par, &mut out, &mut parts, |r0, o| {
                let mut s = 0.0;
                for (k, x) in o.iter_mut().enumerate() {
                    *x = (r0 + k + 1) as f64;
                    s += *x;
                }
                Partial { s0: s, m0: s, ..Partial::default() }
            });
            sums.push((p.s0.to_bits(), p.m0.to_bits(), out));
        }
        assert_eq!(sums[0], sums[1]);
        assert_eq!(f64::from_bits(sums[0].0), (n * (n + 1) / 2) as f64);
    }
}
