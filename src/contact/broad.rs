//! Broad phase (math note §5): axis-aligned bounding boxes inflated by half the contact
//! threshold on every side, so that two bodies whose surfaces are closer than the threshold
//! (d0 in the paper) always have overlapping boxes: their gap along each axis is at most their
//! distance.
//!
//! Overlapping boxes are found by a sort-and-sweep inside strips: the domain is cut into
//! strips across the axis on which the bodies are more spread out, each box is listed in every
//! strip it touches, and each strip is sorted and swept along the other axis. A pair is
//! reported only in the strip holding the start of the two boxes' common interval, hence
//! exactly once. Strips are about two median box sizes wide, so a plain sweep's O(N·√N)
//! checks in a square packing drop to O(N); a few large boxes (a floor, a frame wall) only add
//! one entry per strip they cross. The number of strips is capped at 2√N, which bounds the
//! entries by N·2√N even in contrived scenes.

use super::BodyShape;
use crate::geometry::Aabb;

/// Bounding box of a body's material: a ring's is its outer circle's, which also covers
/// anything in its hole.
pub fn body_aabb(shape: &BodyShape) -> Aabb {
    match shape {
        BodyShape::Disk { center, radius } => Aabb::of_circle(*center, *radius),
        BodyShape::Ring { center, outer, .. } => Aabb::of_circle(*center, *outer),
        BodyShape::Polygon { vertices, .. } => Aabb::of_points(vertices),
    }
}

/// Pairs of bodies whose boxes inflated by `threshold / 2` (d0 in the paper) overlap
/// ([`Aabb::overlaps`]), except pairs of two fixed bodies: each pair as its contacts are keyed
/// (a particle before a block, else the lower index first: `oriented`), sorted.
pub fn candidate_pairs(shapes: &[BodyShape], fixed: &[bool], threshold: f64) -> Vec<(usize, usize)> {
    overlapping(shapes, &boxes(shapes, threshold), fixed)
}

/// The bodies' boxes inflated by `threshold / 2`.
fn boxes(shapes: &[BodyShape], threshold: f64) -> Vec<Aabb> {
    let half = 0.5 * threshold.max(0.0);
    shapes.iter().map(|s| body_aabb(s).inflated(half)).collect()
}

/// [`candidate_pairs`] kept between steps (a Verlet list of boxes; math note §5, "Pairs kept
/// between steps"). The pairs are found once for boxes grown by a margin; while every body's
/// box stays inside its grown box, the pairs of the current boxes are among them, and a
/// filter of the kept pairs by overlap gives exactly [`candidate_pairs`]'s answer (same pairs,
/// same order) for O(N) work instead of the sweep.
#[derive(Debug, Clone, Default)]
pub struct PairCache {
    /// The grown boxes the pairs were found for, and the fixed flags they assumed.
    grown: Vec<Aabb>,
    fixed: Vec<bool>,
    /// Pairs of overlapping grown boxes, sorted.
    pairs: Vec<(usize, usize)>,
}

/// The margin by which [`PairCache`] grows the boxes, as a fraction of their median extent: a
/// body moves this far before the sweep runs again. A twentieth of a disk's diameter adds no
/// pairs in a packing of equal disks (the next neighbours are 0.73 radii apart).
const MARGIN: f64 = 0.05;

impl PairCache {
    /// [`candidate_pairs`]`(shapes, fixed, threshold)`, from the kept pairs when they still
    /// cover it.
    pub fn candidate_pairs(
        &mut self,
        shapes: &[BodyShape],
        fixed: &[bool],
        threshold: f64,
    ) -> Vec<(usize, usize)> {
        let boxes = boxes(shapes, threshold);
        let covered = self.grown.len() == boxes.len()
            && self.fixed.as_slice() == fixed
            && boxes.iter().zip(&self.grown).all(|(b, g)| g.contains(b));
        if !covered {
            let margin = if boxes.is_empty() { 0.0 } else { MARGIN * median_extent(&boxes, 0) };
            self.grown = boxes.iter().map(|b| b.inflated(margin)).collect();
            self.fixed = fixed.to_vec();
            self.pairs = overlapping(shapes, &self.grown, fixed);
        }
        self.pairs.iter().copied().filter(|&(i, j)| boxes[i].overlaps(&boxes[j])).collect()
    }
}

/// Pairs of overlapping boxes, except pairs of two fixed bodies, [`oriented`] and sorted.
fn overlapping(shapes: &[BodyShape], boxes: &[Aabb], fixed: &[bool]) -> Vec<(usize, usize)> {
    if boxes.is_empty() {
        return Vec::new();
    }
    let mut strips = Strips::new(boxes);
    let entries = strips.entries(boxes, fixed);
    // a packing of disks has at most three pairs per body (six neighbours each)
    let mut pairs: Vec<u64> = Vec::with_capacity(3 * boxes.len());
    for (s, w) in strips.offsets.windows(2).enumerate() {
        sweep(&strips, s, &entries[w[0]..w[1]], &mut pairs);
    }
    for p in &mut pairs {
        let (a, b) = oriented(shapes, (*p >> 32) as usize, (*p & 0xffff_ffff) as usize);
        *p = (a as u64) << 32 | b as u64;
    }
    pairs.sort_unstable();
    pairs.into_iter().map(|p| ((p >> 32) as usize, (p & 0xffff_ffff) as usize)).collect()
}

/// The pair `(i, j)`, `i < j`, as the narrow phase keys its contacts: a particle's contacts with
/// a block have the particle as `a` (`particle::particle_block`), two particles' the lower
/// index (`particle::particle_particle`); a pair of blocks keeps the lower index first. Sorted
/// so, the pairs of a pile give its contacts in key order as they are found, which
/// `contact::detect_in_order` then checks instead of sorting them (math note §5, "Pairs kept
/// between steps").
fn oriented(shapes: &[BodyShape], i: usize, j: usize) -> (usize, usize) {
    let particle = |k: usize| !matches!(shapes[k], BodyShape::Polygon { .. });
    if particle(j) && !particle(i) { (j, i) } else { (i, j) }
}

/// One box in one strip: its interval on the sweep axis and on the strip axis.
#[derive(Debug, Clone, Copy)]
struct Entry {
    lo: f64,
    hi: f64,
    strip_lo: f64,
    strip_hi: f64,
    body: u32,
    fixed: bool,
}

/// The cut of the strip axis into `count` strips of equal width from `origin`.
struct Strips {
    /// 0 = x, 1 = y: the axis across which the strips are cut.
    axis: usize,
    origin: f64,
    /// Strips per unit length.
    density: f64,
    count: usize,
    /// Start of each strip's entries, plus the end (filled by [`Strips::entries`]).
    offsets: Vec<usize>,
}

impl Strips {
    fn new(boxes: &[Aabb]) -> Strips {
        let axis = if spread(boxes, 1) > spread(boxes, 0) { 1 } else { 0 };
        let origin = boxes.iter().map(|b| b.min[axis]).fold(f64::INFINITY, f64::min);
        let end = boxes.iter().map(|b| b.max[axis]).fold(f64::NEG_INFINITY, f64::max);
        let length = end - origin;
        let width = 2.0 * median_extent(boxes, axis);
        let cap = 2.0 * (boxes.len() as f64).sqrt();
        let count = if length > 0.0 && width > 0.0 { (length / width).ceil().clamp(1.0, cap) } else { 1.0 };
        let density = if length > 0.0 { count / length } else { 0.0 };
        Strips { axis, origin, density, count: count as usize, offsets: Vec::new() }
    }

    /// Index of the strip holding coordinate `c` of the strip axis; monotone in `c`.
    fn of(&self, c: f64) -> usize {
        (((c - self.origin) * self.density) as usize).min(self.count - 1)
    }

    /// The entries of all strips, strip by strip (see `offsets`), each strip sorted by the
    /// lower end on the sweep axis, then body index.
    fn entries(&mut self, boxes: &[Aabb], fixed: &[bool]) -> Vec<Entry> {
        let (a, o) = (self.axis, 1 - self.axis);
        let mut count = vec![0usize; self.count + 1];
        for b in boxes {
            for s in self.of(b.min[a])..=self.of(b.max[a]) {
                count[s + 1] += 1;
            }
        }
        for s in 0..self.count {
            count[s + 1] += count[s];
        }
        let mut next = count.clone();
        let blank = Entry { lo: 0.0, hi: 0.0, strip_lo: 0.0, strip_hi: 0.0, body: 0, fixed: false };
        let mut entries = vec![blank; count[self.count]];
        for (k, b) in boxes.iter().enumerate() {
            let e = Entry {
                lo: b.min[o],
                hi: b.max[o],
                strip_lo: b.min[a],
                strip_hi: b.max[a],
                body: k as u32,
                fixed: fixed.get(k).copied().unwrap_or(false),
            };
            for s in self.of(b.min[a])..=self.of(b.max[a]) {
                entries[next[s]] = e;
                next[s] += 1;
            }
        }
        for w in count.windows(2) {
            entries[w[0]..w[1]].sort_unstable_by(|x, y| x.lo.total_cmp(&y.lo).then(x.body.cmp(&y.body)));
        }
        self.offsets = count;
        entries
    }
}

/// Sort-and-sweep of the sorted entries of strip `s`; appends pairs as `i << 32 | j`, `i < j`.
/// A pair is kept only if `s` holds the start of the boxes' common interval on the strip axis
/// (both boxes are listed there, since each is listed in every strip it crosses).
fn sweep(strips: &Strips, s: usize, entries: &[Entry], pairs: &mut Vec<u64>) {
    for (k, ea) in entries.iter().enumerate() {
        for eb in &entries[k + 1..] {
            if eb.lo > ea.hi {
                break;
            }
            let overlap = (ea.strip_lo <= eb.strip_hi) & (eb.strip_lo <= ea.strip_hi);
            if overlap && !(ea.fixed && eb.fixed) && strips.of(ea.strip_lo.max(eb.strip_lo)) == s {
                let (i, j) = (ea.body.min(eb.body) as u64, ea.body.max(eb.body) as u64);
                pairs.push(i << 32 | j);
            }
        }
    }
}

/// Variance of the box centres along `axis` (0 = x, 1 = y).
fn spread(boxes: &[Aabb], axis: usize) -> f64 {
    let n = boxes.len() as f64;
    let c = |b: &Aabb| 0.5 * (b.min[axis] + b.max[axis]);
    let mean = boxes.iter().map(c).sum::<f64>() / n;
    boxes.iter().map(|b| (c(b) - mean).powi(2)).sum::<f64>() / n
}

/// Median extent of the boxes along `axis`.
fn median_extent(boxes: &[Aabb], axis: usize) -> f64 {
    let mut ext: Vec<f64> = boxes.iter().map(|b| b.max[axis] - b.min[axis]).collect();
    let mid = ext.len() / 2;
    *ext.select_nth_unstable_by(mid, f64::total_cmp).1
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Vec2;
    use proptest::prelude::*;

    /// Reference: every pair, same inflated boxes, same fixed rule.
    fn brute_force(shapes: &[BodyShape], fixed: &[bool], threshold: f64) -> Vec<(usize, usize)> {
        let boxes: Vec<Aabb> = shapes.iter().map(|s| body_aabb(s).inflated(0.5 * threshold)).collect();
        let mut pairs = Vec::new();
        for i in 0..shapes.len() {
            for j in i + 1..shapes.len() {
                if boxes[i].overlaps(&boxes[j]) && !(fixed[i] && fixed[j]) {
                    pairs.push(oriented(shapes, i, j));
                }
            }
        }
        pairs.sort_unstable();
        pairs
    }

    /// Moves a body by `d`.
    fn shift(shape: &mut BodyShape, d: Vec2) {
        match shape {
            BodyShape::Disk { center, .. } | BodyShape::Ring { center, .. } => *center += d,
            BodyShape::Polygon { vertices, .. } => vertices.iter_mut().for_each(|v| *v += d),
        }
    }

    /// A random body: a disk or a ring (radius 0.05-1) or a convex-ish polygon (3-7 vertices
    /// on a circle of radius 0.1-2), centred in [0, 20]² — or, with `column`, in [0,1]×[0,60].
    fn body(column: bool) -> impl Strategy<Value = (BodyShape, bool)> {
        let w = if column { 1.0 } else { 20.0 };
        let h = if column { 60.0 } else { 20.0 };
        (0.0..w, 0.0..h, 0.05..2.0f64, 0u8..3, 3usize..8, any::<bool>()).prop_map(
            move |(x, y, r, kind, n, fixed)| {
                let c = Vec2::new(x, y);
                let shape = match kind {
                    0 => BodyShape::Disk { center: c, radius: r / 2.0 },
                    1 => BodyShape::Ring { center: c, outer: r / 2.0, inner: r / 4.0 },
                    _ => {
                        let vertices: Vec<Vec2> = (0..n)
                            .map(|k| {
                                let a = std::f64::consts::TAU * (k as f64 + 0.3 * (k % 2) as f64) / n as f64;
                                c + r * Vec2::new(a.cos(), a.sin())
                            })
                            .collect();
                        BodyShape::Polygon {
                            vertices,
                            convex: vec![true; n],
                            nodes: false,
                            holes: Vec::new(),
                        }
                    }
                };
                (shape, fixed)
            },
        )
    }

    proptest! {
        /// The sweep finds exactly the pairs of the O(N²) check (same boxes, same rule).
        #[test]
        fn sweep_matches_brute_force(
            bodies in prop::collection::vec(body(false), 0..120),
            threshold in 0.0..0.5f64,
        ) {
            let (shapes, fixed): (Vec<_>, Vec<_>) = bodies.into_iter().unzip();
            prop_assert_eq!(candidate_pairs(&shapes, &fixed, threshold), brute_force(&shapes, &fixed, threshold));
        }

        /// Same, in a tall narrow column (the sweep switches to the y axis).
        #[test]
        fn sweep_matches_brute_force_in_a_column(
            bodies in prop::collection::vec(body(true), 0..120),
            threshold in 0.0..0.5f64,
        ) {
            let (shapes, fixed): (Vec<_>, Vec<_>) = bodies.into_iter().unzip();
            prop_assert_eq!(candidate_pairs(&shapes, &fixed, threshold), brute_force(&shapes, &fixed, threshold));
        }

        /// The kept pairs give the sweep's answer at every step of a random walk: small moves
        /// (kept pairs reused), large ones (swept again), a changing threshold and a body
        /// changing between fixed and free.
        #[test]
        fn kept_pairs_match_the_sweep(
            bodies in prop::collection::vec(body(false), 1..60),
            walk in prop::collection::vec((0.0..0.5f64, 0.0..0.5f64, 0u8..8, 0.0..1.0f64), 1..12),
        ) {
            let (mut shapes, mut fixed): (Vec<_>, Vec<_>) = bodies.into_iter().unzip();
            let mut cache = PairCache::default();
            for (k, &(threshold, size, big, frac)) in walk.iter().enumerate() {
                // a small step most of the time, a large one for big == 0
                let step = if big == 0 { 2.0 * size } else { 1e-3 * size };
                for (i, s) in shapes.iter_mut().enumerate() {
                    let angle = 2.4 * (i + 7 * k) as f64 + frac;
                    shift(s, step * Vec2::new(angle.cos(), angle.sin()));
                }
                if big == 1 {
                    let i = (frac * fixed.len() as f64) as usize % fixed.len();
                    fixed[i] = !fixed[i];
                }
                prop_assert_eq!(
                    cache.candidate_pairs(&shapes, &fixed, threshold),
                    candidate_pairs(&shapes, &fixed, threshold)
                );
            }
        }

        /// Every pair of disks with surface distance below the threshold is a candidate
        /// (the inflation argument of the module doc).
        #[test]
        fn close_disks_are_found(
            disks in prop::collection::vec((0.0..10.0f64, 0.0..10.0f64, 0.05..1.0f64), 2..80),
            threshold in 0.0..0.5f64,
        ) {
            let shapes: Vec<BodyShape> = disks.iter()
                .map(|&(x, y, r)| BodyShape::Disk { center: Vec2::new(x, y), radius: r })
                .collect();
            let pairs = candidate_pairs(&shapes, &vec![false; shapes.len()], threshold);
            for i in 0..disks.len() {
                for j in i + 1..disks.len() {
                    let (a, b) = (disks[i], disks[j]);
                    let gap = ((a.0 - b.0).powi(2) + (a.1 - b.1).powi(2)).sqrt() - a.2 - b.2;
                    if gap < threshold {
                        prop_assert!(pairs.binary_search(&(i, j)).is_ok(), "{i} {j} gap {gap}");
                    }
                }
            }
        }
    }

    /// The kept pairs are reused, not swept again, while the bodies stay inside their grown
    /// boxes: two disks of radius 1 with threshold 0.1 have boxes 2.1 wide, grown by 0.05 × 2.1
    /// = 0.105. A move of 0.1 keeps the grown boxes (and the pair); a move to 0.3 leaves them,
    /// and the sweep grows new ones.
    #[test]
    fn small_moves_reuse_the_kept_pairs() {
        let d = |x: f64| BodyShape::Disk { center: Vec2::new(x, 0.0), radius: 1.0 };
        let mut cache = PairCache::default();
        assert_eq!(cache.candidate_pairs(&[d(0.0), d(2.05)], &[false, false], 0.1), vec![(0, 1)]);
        let grown = cache.grown.clone();
        assert_eq!(cache.candidate_pairs(&[d(0.1), d(2.05)], &[false, false], 0.1), vec![(0, 1)]);
        assert_eq!(cache.grown, grown, "a move of 0.1 swept again");
        assert_eq!(cache.candidate_pairs(&[d(0.3), d(2.05)], &[false, false], 0.1), vec![(0, 1)]);
        assert_ne!(cache.grown, grown, "a move of 0.3 kept boxes it left");
    }

    /// Two touching fixed bodies are no candidate pair; a free body touching both gives two.
    #[test]
    fn fixed_pairs_are_skipped() {
        let d = |x: f64| BodyShape::Disk { center: Vec2::new(x, 0.0), radius: 1.0 };
        let shapes = [d(0.0), d(2.0), d(4.0)];
        assert_eq!(candidate_pairs(&shapes, &[true, false, true], 0.1), vec![(0, 1), (1, 2)]);
        assert_eq!(candidate_pairs(&shapes, &[true, true, false], 0.1), vec![(1, 2)]);
    }

    /// A pair is oriented as its contacts are keyed: a particle (disk or ring) before a block
    /// whatever their indices, two particles and two blocks lower index first; and sorted so.
    /// Bodies 0 and 3 are squares, 1 and 2 disks, all four overlapping (the pairs listed by
    /// hand).
    #[test]
    fn pairs_come_particle_first_and_sorted() {
        use super::super::testkit::{disk, rect};
        let shapes =
            [rect(-1.0, -1.0, 1.0, 1.0), disk(0.5, 0.0, 1.0), disk(1.0, 0.0, 1.0), rect(0.0, -1.0, 2.0, 1.0)];
        let pairs = candidate_pairs(&shapes, &[false; 4], 0.1);
        assert_eq!(pairs, vec![(0, 3), (1, 0), (1, 2), (1, 3), (2, 0), (2, 3)]);
    }

    /// A disk in a ring's hole overlaps the ring's (outer circle) box.
    #[test]
    fn body_in_ring_hole_is_a_candidate() {
        let shapes = [
            BodyShape::Ring { center: Vec2::zeros(), outer: 10.0, inner: 8.0 },
            BodyShape::Disk { center: Vec2::new(1.0, 0.0), radius: 1.0 },
        ];
        assert_eq!(candidate_pairs(&shapes, &[false, false], 0.1), vec![(0, 1)]);
    }
}
