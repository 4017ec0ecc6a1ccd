//! The `cut` fuzz target's input decoding and area check, shared by the target
//! (fuzz_targets/cut.rs) and the regression tests of tests/rockmass_cut.rs (included there with
//! `#[path]`), so that a crash input means the same scene in both. The identity: the blocks'
//! areas sum to the domain's less the removed excavation's (1e-9 relative) for a star-shaped
//! domain and at most one removed excavation inside it; each reported merge or dropped sliver may
//! move the outline by up to max(min_edge, 1e-9 D) near a corner, so each allows that squared.
//! A removed excavation whose outline comes closer than the merge distance to the domain's has
//! no identity: by the cutter's rule (math note §12.8) its vertex there merges into the
//! outline's and moves by up to the merge distance, which changes its area by up to the merge
//! distance times half its two edges there.

use pbdda::rockmass::{Bridges, CutSpec, Excavation, Joint, JointSet, circle, cut};

struct Bytes<'a>(&'a [u8]);

impl Bytes<'_> {
    fn byte(&mut self) -> u8 {
        let (b, rest) = self.0.split_first().map(|(b, r)| (*b, r)).unwrap_or((0, &[]));
        self.0 = rest;
        b
    }
    fn num(&mut self, lo: f64, hi: f64) -> f64 {
        let v = u16::from_le_bytes([self.byte(), self.byte()]) as f64 / 65535.0;
        lo + v * (hi - lo)
    }
}

fn shoelace(p: &[[f64; 2]]) -> f64 {
    (0..p.len()).map(|i| p[i][0] * p[(i + 1) % p.len()][1] - p[i][1] * p[(i + 1) % p.len()][0]).sum::<f64>()
        / 2.0
}

fn distance_to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let d = [b[0] - a[0], b[1] - a[1]];
    let dd = d[0] * d[0] + d[1] * d[1];
    let t = if dd > 0.0 { (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / dd).clamp(0.0, 1.0) } else { 0.0 };
    (p[0] - a[0] - t * d[0]).hypot(p[1] - a[1] - t * d[1])
}

/// The least distance between the outlines of two polygons (0 where two edges cross).
fn outline_gap(p: &[[f64; 2]], q: &[[f64; 2]]) -> f64 {
    let side =
        |a: [f64; 2], b: [f64; 2], c: [f64; 2]| (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    let mut best = f64::INFINITY;
    for i in 0..p.len() {
        let (a, b) = (p[i], p[(i + 1) % p.len()]);
        for j in 0..q.len() {
            let (c, d) = (q[j], q[(j + 1) % q.len()]);
            if side(a, b, c) * side(a, b, d) < 0.0 && side(c, d, a) * side(c, d, b) < 0.0 {
                return 0.0;
            }
            let ends = [distance_to_segment(a, c, d), distance_to_segment(b, c, d)];
            let others = [distance_to_segment(c, a, b), distance_to_segment(d, a, b)];
            best = ends.into_iter().chain(others).fold(best, f64::min);
        }
    }
    best
}

fn inside(p: [f64; 2], poly: &[[f64; 2]]) -> bool {
    let mut c = false;
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        if (a[1] > p[1]) != (b[1] > p[1]) && p[0] < a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]) {
            c = !c;
        }
    }
    c
}

/// The fuzz target's spec, whether its area identity applies, and its expected area.
pub fn decode(data: &[u8]) -> (CutSpec, Option<f64>) {
    let mut b = Bytes(data);
    let n = 3 + (b.byte() % 10) as usize;
    let free = b.byte() & 1 == 1;
    let domain: Vec<[f64; 2]> = (0..n)
        .map(|k| {
            if free {
                [b.num(-10.0, 10.0), b.num(-10.0, 10.0)]
            } else {
                let a = std::f64::consts::TAU * (k as f64 + b.num(0.0, 0.95)) / n as f64;
                let r = b.num(5.0, 10.0);
                [r * a.cos(), r * a.sin()]
            }
        })
        .collect();
    let sets = (0..b.byte() % 4)
        .map(|_| JointSet {
            angle: b.num(-360.0, 360.0),
            spacing: b.num(0.0, 5.0),
            origin: [b.num(-20.0, 20.0), b.num(-20.0, 20.0)],
            trace: b.num(-0.5, 6.0).max(0.0),
            gap: b.num(0.0, 3.0),
            angle_dev: b.num(0.0, 45.0),
            spacing_dev: b.num(0.0, 2.0),
            trace_dev: b.num(0.0, 2.0),
            gap_dev: b.num(0.0, 2.0),
            bridges: if b.byte() & 1 == 1 { Bridges::Cemented } else { Bridges::Remove },
        })
        .collect();
    let joints = (0..b.byte() % 4)
        .map(|_| Joint {
            points: (0..2 + b.byte() % 3).map(|_| [b.num(-12.0, 12.0), b.num(-12.0, 12.0)]).collect(),
        })
        .collect();
    let excavations: Vec<Excavation> = (0..b.byte() % 3)
        .map(|_| {
            let r = b.num(0.1, 2.0);
            let c = [b.num(-2.5, 2.5), b.num(-2.5, 2.5)];
            Excavation { vertices: circle(c, r, 3 + (b.byte() % 30) as usize), keep: b.byte() & 1 == 1 }
        })
        .collect();
    let spec = CutSpec {
        domain: domain.clone(),
        joint_sets: sets,
        joints,
        excavations: excavations.clone(),
        min_edge: b.num(0.0, 0.05),
        seed: u64::from(b.byte()),
        block_limit: 2_000,
    };
    let removed: Vec<&Excavation> = excavations.iter().filter(|e| !e.keep).collect();
    let merge = merge_distance(spec.min_edge);
    let within = removed.iter().all(|e| {
        e.vertices.iter().all(|p| inside(*p, &domain)) && outline_gap(&e.vertices, &domain) >= merge
    });
    let expected = (!free && removed.len() <= 1 && within)
        .then(|| shoelace(&domain).abs() - removed.iter().map(|e| shoelace(&e.vertices)).sum::<f64>());
    (spec, expected)
}

#[allow(dead_code)]
pub fn check(data: &[u8]) {
    let (spec, expected) = decode(data);
    let c = cut(&spec).unwrap_or_else(|e| panic!("{e}"));
    check_area(&spec, &c, expected);
}

/// The cutter's merge distance, max(min_edge, 1e-9 D), with D = 30 bounding the diagonal of the
/// decoder's domains (inside [-10, 10]^2).
fn merge_distance(min_edge: f64) -> f64 {
    min_edge.max(1e-9 * 30.0)
}

pub fn check_area(spec: &CutSpec, c: &pbdda::rockmass::Cut, expected: Option<f64>) {
    if let Some(expected) = expected {
        let total: f64 = c.blocks.iter().map(|b| b.area).sum();
        let merge = merge_distance(spec.min_edge);
        let tol = 1e-9 * expected + c.reports.len() as f64 * 4.0 * merge * merge;
        assert!((total - expected).abs() <= tol, "area {total} against {expected}");
    }
}
