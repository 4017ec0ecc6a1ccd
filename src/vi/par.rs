//! Blocked sweeps over the rows, serial or on both cores, with deterministic reductions: every
//! block stores its partial results and [`reduce`] combines them in block order, so serial
//! and parallel runs give bit-identical results.
//!
//! In parallel the blocks are cut into two halves at a block boundary, one per core, through
//! `micropool::join`, whose calling thread runs one half itself (math note §3.3, "Both cores
//! at a join's true cost"): rayon's `join` called from outside its pool parks the caller, and
//! a join must cost far less than a sweep's half for the second core to pay.

use super::BoundRule;

/// Rows per block of every sweep.
pub(super) const BLOCK: usize = 2048;

/// Per-block results of a sweep: four sums, three maxima and a minimum (+inf in a block that
/// takes none).
#[derive(Debug, Clone, Copy)]
pub(super) struct Partial {
    pub s0: f64,
    pub s1: f64,
    pub s2: f64,
    pub s3: f64,
    pub m0: f64,
    pub m1: f64,
    pub m2: f64,
    pub lo: f64,
}

impl Default for Partial {
    fn default() -> Self {
        Partial { s0: 0.0, s1: 0.0, s2: 0.0, s3: 0.0, m0: 0.0, m1: 0.0, m2: 0.0, lo: f64::INFINITY }
    }
}

/// Combines the blocks' partials in block order.
pub(super) fn reduce(parts: &[Partial]) -> Partial {
    parts.iter().fold(Partial::default(), |acc, p| Partial {
        s0: acc.s0 + p.s0,
        s1: acc.s1 + p.s1,
        s2: acc.s2 + p.s2,
        s3: acc.s3 + p.s3,
        m0: acc.m0.max(p.m0),
        m1: acc.m1.max(p.m1),
        m2: acc.m2.max(p.m2),
        lo: acc.lo.min(p.lo),
    })
}

/// Runs `f(first_row, rows)` over the blocks of `n` rows, storing each block's partial: a
/// sweep that writes no vector.
pub(super) fn fold<F>(par: bool, n: usize, parts: &mut [Partial], f: F) -> Partial
where
    F: Fn(usize, usize) -> Partial + Sync,
{
    let blocks = |first: usize, parts: &mut [Partial]| {
        for (b, p) in parts.iter_mut().enumerate() {
            let r0 = (first + b) * BLOCK;
            *p = f(r0, BLOCK.min(n - r0));
        }
    };
    let parts = &mut parts[..n.div_ceil(BLOCK)];
    let half = split(n) / BLOCK;
    let (p1, p2) = parts.split_at_mut(half);
    join(par, || blocks(0, p1), || blocks(half, p2));
    reduce(parts)
}

/// Where the sweeps cut `n` rows into their two halves: at a block boundary.
pub(super) fn split(n: usize) -> usize {
    n.div_ceil(BLOCK) / 2 * BLOCK
}

/// `(a(), b())`: on both cores when `par`, else `a` then `b`. Every pass over the rows runs its
/// two halves of [`split`] through it, so each core keeps to the rows it has in its cache from
/// the other passes; a pass whose halves reduce (sums) combines them in block order after it.
pub(super) fn join<A: Send, B: Send>(
    par: bool,
    a: impl FnOnce() -> A + Send,
    b: impl FnOnce() -> B + Send,
) -> (A, B) {
    if par { micropool::join(a, b) } else { (a(), b()) }
}

/// `f(first_row, rows)` over the sweeps' two halves of `out` ([`split`]), through [`join`]: a
/// pass that needs no per-block partials.
pub(super) fn halves<T: Send>(
    par: bool,
    out: &mut [f64],
    f: impl Fn(usize, &mut [f64]) -> T + Sync,
) -> (T, T) {
    let at = split(out.len());
    let (o1, o2) = out.split_at_mut(at);
    join(par, || f(0, o1), || f(at, o2))
}

/// [`BoundRule::all_bounds`] of a `Sync` rule over the blocks of the sweeps' two halves (the
/// block that holds their cut row starts the second), one per core when `par`: the bounds of
/// each block are those of `block_bounds`, in any order.
pub fn all_bounds_in_halves<R: BoundRule + Sync + ?Sized>(
    rule: &R,
    blocks: &[usize],
    z: &[f64],
    lo: &mut [f64],
    hi: &mut [f64],
    par: bool,
) {
    if !par || blocks.is_empty() {
        // the same bounds (a test checks it), by the rule's own loop over its blocks
        return rule.all_bounds(blocks, z, lo, hi);
    }
    let k = blocks.partition_point(|&b| b < split(lo.len())).min(blocks.len() - 1);
    let (lo1, lo2) = lo.split_at_mut(blocks[k]);
    let (hi1, hi2) = hi.split_at_mut(blocks[k]);
    let half = |k0: usize, blocks: &[usize], base: usize, lo: &mut [f64], hi: &mut [f64]| {
        for (j, b) in blocks.windows(2).enumerate() {
            let (a, e) = (b[0] - base, b[1] - base);
            rule.block_bounds(k0 + j, z, &mut lo[a..e], &mut hi[a..e]);
        }
    };
    join(par, || half(0, &blocks[..=k], 0, lo1, hi1), || half(k, &blocks[k..], blocks[k], lo2, hi2));
}

/// Runs `f(first_row, out_block)` over the blocks of `out`, storing each block's partial.
pub(super) fn run1<F>(par: bool, out: &mut [f64], parts: &mut [Partial], f: F) -> Partial
where
    F: Fn(usize, &mut [f64]) -> Partial + Sync,
{
    let blocks = |r0: usize, out: &mut [f64], parts: &mut [Partial]| {
        for (b, (o, p)) in out.chunks_mut(BLOCK).zip(parts.iter_mut()).enumerate() {
            *p = f(r0 + b * BLOCK, o);
        }
    };
    let parts = &mut parts[..out.len().div_ceil(BLOCK)];
    let at = split(out.len());
    let (o1, o2) = out.split_at_mut(at);
    let (p1, p2) = parts.split_at_mut(at / BLOCK);
    join(par, || blocks(0, o1, p1), || blocks(at, o2, p2));
    reduce(parts)
}

/// As [`run1`], with two output vectors.
pub(super) fn run2<F>(par: bool, o1: &mut [f64], o2: &mut [f64], parts: &mut [Partial], f: F) -> Partial
where
    F: Fn(usize, &mut [f64], &mut [f64]) -> Partial + Sync,
{
    let blocks = |r0: usize, o1: &mut [f64], o2: &mut [f64], parts: &mut [Partial]| {
        for (b, ((a, c), p)) in
            o1.chunks_mut(BLOCK).zip(o2.chunks_mut(BLOCK)).zip(parts.iter_mut()).enumerate()
        {
            *p = f(r0 + b * BLOCK, a, c);
        }
    };
    let parts = &mut parts[..o1.len().div_ceil(BLOCK)];
    let at = split(o1.len());
    let ((a1, a2), (c1, c2)) = (o1.split_at_mut(at), o2.split_at_mut(at));
    let (p1, p2) = parts.split_at_mut(at / BLOCK);
    join(par, || blocks(0, a1, c1, p1), || blocks(at, a2, c2, p2));
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

    /// `fold` visits every row once, in blocks, serial or in halves alike: the sum of 1..=n is
    /// n(n+1)/2 and the smallest of n + 1 − i over the rows is 1 (exact in doubles); a block
    /// that takes no minimum leaves +inf, which the reduction ignores.
    #[test]
    fn fold_sums_and_takes_the_least() {
        let n = 5 * BLOCK + 3;
        let mut parts = vec![Partial::default(); n.div_ceil(BLOCK)];
        let got: Vec<(u64, u64)> = [false, true]
            .into_iter()
            .map(|par| {
                let p = fold(par, n, &mut parts, |r0, m| {
                    let s = (r0..r0 + m).map(|i| (i + 1) as f64).sum();
                    let lo = if r0 == 0 {
                        f64::INFINITY
                    } else {
                        (r0..r0 + m).map(|i| (n - i) as f64).fold(f64::INFINITY, f64::min)
                    };
                    Partial { s0: s, lo, ..Partial::default() }
                });
                (p.s0.to_bits(), p.lo.to_bits())
            })
            .collect();
        assert_eq!(got[0], got[1]);
        assert_eq!(f64::from_bits(got[0].0), (n * (n + 1) / 2) as f64);
        assert_eq!(f64::from_bits(got[0].1), 1.0);
    }

    /// `all_bounds_in_halves` on both cores gives every block the bounds `all_bounds` gives it
    /// (serially it is `all_bounds` itself): blocks of 1–3 rows (5,001 rows: the halves are cut at
    /// the block that holds row 2,048), bounds that depend on the block's index, its
    /// rows and z. Expected: bit-identical lo and hi, every row set.
    #[test]
    fn bounds_in_halves_are_the_serial_bounds() {
        struct Indexed;
        impl BoundRule for Indexed {
            fn block_bounds(&self, k: usize, z: &[f64], lo: &mut [f64], hi: &mut [f64]) {
                for (i, (l, h)) in lo.iter_mut().zip(hi.iter_mut()).enumerate() {
                    *l = -(k as f64) - 0.25 * i as f64 - z[k % z.len()];
                    *h = k as f64 + 0.5 * i as f64 + z[k % z.len()];
                }
            }
        }
        let mut blocks = vec![0];
        while *blocks.last().unwrap() < 5001 {
            let next = blocks.last().unwrap() + 1 + blocks.len() % 3;
            blocks.push(next.min(5001));
        }
        let z: Vec<f64> = (0..5001).map(|i| (i as f64).sin()).collect();
        let (mut lo, mut hi) = (vec![f64::NAN; 5001], vec![f64::NAN; 5001]);
        Indexed.all_bounds(&blocks, &z, &mut lo, &mut hi);
        let (mut l2, mut h2) = (vec![f64::NAN; 5001], vec![f64::NAN; 5001]);
        all_bounds_in_halves(&Indexed, &blocks, &z, &mut l2, &mut h2, true);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!((bits(&lo), bits(&hi)), (bits(&l2), bits(&h2)));
        assert!(lo.iter().chain(&hi).all(|x| x.is_finite()));
    }
}
