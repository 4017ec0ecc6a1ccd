//! The block cutter where rounding and merges decide the geometry (math note §12.7, §12.8): a
//! crossing far from the origin, and a kept excavation's corner close to the outline. Every
//! expected number is a closed form of the input coordinates, stated in each test's header.

use pbdda::rockmass::{CutSpec, Excavation, Joint, JointSet, cut};

fn shoelace(p: &[[f64; 2]]) -> f64 {
    let n = p.len();
    (0..n).map(|i| p[i][0] * p[(i + 1) % n][1] - p[(i + 1) % n][0] * p[i][1]).sum::<f64>() / 2.0
}

fn centroid(p: &[[f64; 2]]) -> [f64; 2] {
    let n = p.len() as f64;
    [p.iter().map(|q| q[0]).sum::<f64>() / n, p.iter().map(|q| q[1]).sum::<f64>() / n]
}

/// The crossing of the line y = x tan 30 deg with the line through a and b.
fn on_bedding(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    let k = 30f64.to_radians().tan();
    let s = (k * a[0] - a[1]) / ((b[1] - a[1]) - k * (b[0] - a[0]));
    [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])]
}

/// The geometry of examples/staged_slope.toml (slope outline, set J1 at 30 deg, spacing 3,
/// through the origin, the toe excavation removed), with the [[joint]] at the slab's upper end
/// starting 0.3 m below the J1 trace y = x tan 30 deg, at (8.810254, 4.740192), and running up to
/// the outline's corner C = (7.660254, 6.732051); everything shifted by `offset` (the set's
/// origin too). The traces c = -9, -6, -3, 0, 3 (c the normal offset) cross the domain and make
/// 6 strips; the excavation splits strip (0, 3) in two and the joint splits its right part, the
/// slab; the 0.3 m below the trace closes nothing: 8 blocks. Closed forms, from the input
/// coordinates: the slab is the quadrilateral (0, 0), X, C, (-1, 1.732051), X the joint's
/// crossing with the trace (20.0000015 m², 10 m x 2 m to the inputs' six decimals); the block
/// above the joint is X, (14, 14 tan 30 deg), (14, 10.392305), C; all blocks sum to the domain
/// less the excavation. A crossing placed a rounding error off the crossed joint once sent the
/// trace through the joint's lower end instead (a 21.5 m² slab at offset (1e5, -1e5), 6 blocks
/// at (1e4, 1e4)). Tolerance: each coordinate is rounded to a few ulps of its magnitude M
/// (1.4e5 at most), which moves an area by about that times the perimeter (about 25 m):
/// 1e-9 relative at M = 1e5, 1e-12 at the origin.
#[test]
fn a_joint_below_a_trace_leaves_the_closed_form_slab() {
    let domain = [
        [-8.0, -4.0],
        [14.0, -4.0],
        [14.0, 10.392305],
        [7.660254, 6.732051],
        [-1.0, 1.732051],
        [-8.0, 1.732051],
    ];
    let toe = [[-6.0, -1.5], [0.0, -1.5], [0.0, 0.0], [-1.0, 1.732051], [-6.0, 1.732051]];
    let (j0, c) = ([8.810254, 4.740192], [7.660254, 6.732051]);
    let x = on_bedding(j0, c);
    let slab = [[0.0, 0.0], x, c, [-1.0, 1.732051]];
    let above = [x, [14.0, 14.0 * 30f64.to_radians().tan()], [14.0, 10.392305], c];
    for (offset, tol) in [([0.0, 0.0], 1e-12), ([1e4, 1e4], 1e-10), ([1e5, -1e5], 1e-9)] {
        let shift = |p: &[[f64; 2]]| -> Vec<[f64; 2]> {
            p.iter().map(|q| [q[0] + offset[0], q[1] + offset[1]]).collect()
        };
        let spec = CutSpec {
            domain: shift(&domain),
            joint_sets: vec![JointSet { angle: 30.0, spacing: 3.0, origin: offset, ..JointSet::default() }],
            joints: vec![Joint { points: shift(&[j0, c]) }],
            excavations: vec![Excavation { vertices: shift(&toe), keep: false }],
            min_edge: 0.01,
            ..CutSpec::default()
        };
        let cut = cut(&spec).unwrap();
        assert_eq!(cut.blocks.len(), 8, "offset {offset:?}");
        for (shape, name) in [(&slab, "slab"), (&above, "above the joint")] {
            let m = centroid(shape);
            let m = [m[0] + offset[0], m[1] + offset[1]];
            let near = |b: &&pbdda::rockmass::Block| (b.centroid[0] - m[0]).hypot(b.centroid[1] - m[1]) < 0.5;
            let block = cut.blocks.iter().find(near).unwrap_or_else(|| panic!("{name} at {offset:?}"));
            let expected = shoelace(shape);
            assert!((block.area - expected).abs() <= tol * expected, "{name} {} vs {expected}", block.area);
        }
        let total: f64 = cut.blocks.iter().map(|b| b.area).sum();
        let expected = shoelace(&domain) - shoelace(&toe);
        assert!((total - expected).abs() <= tol * expected, "total {total} vs {expected} at {offset:?}");
    }
}

/// A kept excavation, the triangle (5, 7.996), (6, 9), (4, 9), has its corner 0.004 m inside the
/// top edge (y = 8) of a 10 x 8 rectangle; its edges cross that edge 0.0040 m either side of
/// x = 5, all three points within min_edge = 0.01 of each other, so they merge. The outline
/// vertices win (math note §12.8): the corner moves onto y = 8, the excavation's piece inside
/// the domain collapses and is dropped, and the one block left is the rectangle itself: its 4
/// corners and area 80 (1e-12 relative: every moved vertex moves along y = 8). A rule that
/// moved the outline onto the corner lost the triangle (0, 8), (5, 7.996), (10, 8): 0.02 m².
#[test]
fn a_kept_excavation_corner_yields_to_the_outline() {
    let spec = CutSpec {
        domain: vec![[0.0, 0.0], [10.0, 0.0], [10.0, 8.0], [0.0, 8.0]],
        excavations: vec![Excavation { vertices: vec![[5.0, 7.996], [6.0, 9.0], [4.0, 9.0]], keep: true }],
        min_edge: 0.01,
        ..CutSpec::default()
    };
    let cut = cut(&spec).unwrap();
    assert_eq!(cut.blocks.len(), 1, "{:?}", cut.blocks);
    let b = &cut.blocks[0];
    assert!((b.area - 80.0).abs() <= 1e-12 * 80.0, "area {}", b.area);
    assert_eq!(b.vertices, vec![[0.0, 0.0], [10.0, 0.0], [10.0, 8.0], [0.0, 8.0]]);
    assert_eq!(b.excavation, None);
}
