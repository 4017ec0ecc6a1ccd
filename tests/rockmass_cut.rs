//! The block cutter (src/rockmass, math note §12). Every expected number is a closed form of the
//! geometry stated in each test's header; tolerances are justified there.

use pbdda::rockmass::{
    Bridges, CutError, CutSpec, EdgeSource, Excavation, Joint, JointSet, Report, circle, cut,
};

fn rect(a: f64, b: f64) -> Vec<[f64; 2]> {
    vec![[0.0, 0.0], [a, 0.0], [a, b], [0.0, b]]
}

fn set(angle: f64, spacing: f64, origin: [f64; 2]) -> JointSet {
    JointSet { angle, spacing, origin, ..JointSet::default() }
}

fn total_area(c: &pbdda::rockmass::Cut) -> f64 {
    c.blocks.iter().map(|b| b.area).sum()
}

/// Two persistent orthogonal sets across a 6 x 4 rectangle, spacings 1.5 (traces at 90 deg) and
/// 0.5 (traces at 0 deg) through the corner: traces at x = 0, 1.5, ..., 6 and y = 0, 0.5, ..., 4,
/// those at x = 0, 6, y = 0, 4 running on the outline (a collinear overlap). Closed form
/// (design note §1): (6 / 1.5)(4 / 0.5) = 32 blocks, each 1.5 x 0.5. The coordinates are sums of
/// multiples of 0.5, exact in binary, so 1e-12 only allows for the intersection formula's
/// rounding.
#[test]
fn orthogonal_sets_on_the_outline_give_the_closed_form() {
    let spec = CutSpec {
        domain: rect(6.0, 4.0),
        joint_sets: vec![set(90.0, 1.5, [0.0, 0.0]), set(0.0, 0.5, [0.0, 0.0])],
        ..CutSpec::default()
    };
    let c = cut(&spec).unwrap();
    assert_eq!(c.blocks.len(), 32);
    for b in &c.blocks {
        assert_eq!(b.vertices.len(), 4, "{b:?}");
        let xs: Vec<f64> = b.vertices.iter().map(|p| p[0]).collect();
        let ys: Vec<f64> = b.vertices.iter().map(|p| p[1]).collect();
        let w = xs.iter().cloned().fold(f64::MIN, f64::max) - xs.iter().cloned().fold(f64::MAX, f64::min);
        let h = ys.iter().cloned().fold(f64::MIN, f64::max) - ys.iter().cloned().fold(f64::MAX, f64::min);
        assert!((w - 1.5).abs() < 1e-12 && (h - 0.5).abs() < 1e-12, "{w} x {h}");
        assert!((b.area - 0.75).abs() < 1e-12);
    }
    assert!((total_area(&c) - 24.0).abs() < 1e-12 * 24.0);
    assert!(c.reports.is_empty(), "{:?}", c.reports);
    // the outline wins over a set along it (EdgeSource order)
    let first = &c.blocks[0];
    assert!(first.edges.contains(&EdgeSource::Outline));
    // blocks ordered by centroid y, then x
    assert_eq!(first.centroid, [0.75, 0.25]);
}

/// The same sets with origin (0.75, 0.25), half a spacing off the outline: traces at
/// x = 0.75 + 1.5 k and y = 0.25 + 0.5 k; no trace on the outline. 4 vertical traces make 5 columns
/// (widths 0.75, 1.5, 1.5, 1.5, 0.75), 8 horizontal ones 9 rows (0.25, 0.5 x 7, 0.25): 45 blocks,
/// the 3 x 7 = 21 inner ones 1.5 x 0.5; areas sum to 24 (1e-12 as above).
#[test]
fn orthogonal_sets_off_the_outline_give_the_closed_form() {
    let spec = CutSpec {
        domain: rect(6.0, 4.0),
        joint_sets: vec![set(90.0, 1.5, [0.75, 0.25]), set(0.0, 0.5, [0.75, 0.25])],
        ..CutSpec::default()
    };
    let c = cut(&spec).unwrap();
    assert_eq!(c.blocks.len(), 45);
    let full = c.blocks.iter().filter(|b| (b.area - 0.75).abs() < 1e-12).count();
    assert_eq!(full, 21);
    assert!(c.blocks.iter().all(|b| b.vertices.len() == 4));
    assert!((total_area(&c) - 24.0).abs() < 1e-12 * 24.0);
    assert!(c.reports.is_empty(), "{:?}", c.reports);
}

/// Area of the regular n-gon inscribed in a circle of radius r: (n / 2) r^2 sin(2 pi / n).
fn ngon_area(n: usize, r: f64) -> f64 {
    0.5 * n as f64 * r * r * (std::f64::consts::TAU / n as f64).sin()
}

/// A 24-gon of radius 2 removed from a 10 x 8 rectangle cut by two sets at 1 m: the blocks sum to
/// 80 - A, A = 12 * 4 * sin(15 deg) (closed form of the polygon's area); 1e-12 relative allows
/// for the rounding of the cut points (each ~1e-16 relative). Kept instead (`keep = true`), the
/// blocks sum to 80 and those tagged with the excavation to A.
#[test]
fn an_excavation_removes_its_area() {
    let hole = circle([5.0, 4.0], 2.0, 24);
    let a = ngon_area(24, 2.0);
    let mut spec = CutSpec {
        domain: rect(10.0, 8.0),
        joint_sets: vec![set(30.0, 1.0, [0.1, 0.2]), set(120.0, 1.0, [0.1, 0.2])],
        excavations: vec![Excavation { vertices: hole, keep: false }],
        ..CutSpec::default()
    };
    let c = cut(&spec).unwrap();
    assert!((total_area(&c) - (80.0 - a)).abs() < 1e-12 * 80.0, "{}", total_area(&c) - (80.0 - a));
    assert!(c.blocks.iter().all(|b| b.excavation.is_none()));
    spec.excavations[0].keep = true;
    let c = cut(&spec).unwrap();
    assert!((total_area(&c) - 80.0).abs() < 1e-12 * 80.0);
    let inside: f64 = c.blocks.iter().filter(|b| b.excavation == Some(0)).map(|b| b.area).sum();
    assert!((inside - a).abs() < 1e-12 * 80.0, "{inside} against {a}");
}

/// The same 24-gon in an uncut 10 x 8 rectangle would leave one block with a hole: the cutter
/// adds two seams (from the hole's rightmost vertex (7, 4) to (10, 4) and from its leftmost
/// (3, 4) to (0, 4)), giving exactly 2 blocks of (80 - A) / 2 each (the figure is symmetric about
/// y = 4), and reports both seams.
#[test]
fn a_hole_in_one_block_is_cut_by_two_seams() {
    let spec = CutSpec {
        domain: rect(10.0, 8.0),
        excavations: vec![Excavation { vertices: circle([5.0, 4.0], 2.0, 24), keep: false }],
        ..CutSpec::default()
    };
    let c = cut(&spec).unwrap();
    let half = (80.0 - ngon_area(24, 2.0)) / 2.0;
    assert_eq!(c.blocks.len(), 2);
    for b in &c.blocks {
        assert!((b.area - half).abs() < 1e-12 * 80.0);
        assert!(b.edges.contains(&EdgeSource::Seam));
    }
    let seams: Vec<_> = c.reports.iter().filter(|r| matches!(r, Report::Seam { .. })).collect();
    assert_eq!(seams.len(), 2, "{:?}", c.reports);
}

/// A persistent set at 0 deg, spacing 1, origin (0, 0), cuts a 10 x 4 rectangle into 4 strips
/// (its lines y = 0 and 4 run on the outline). A second set at 90 deg with pieces 0.3 +- 0.1 long
/// (gap 0.7 +- 0.2) is never long enough to cross a 1 m strip, so with bridges = "remove" it
/// closes no block: still 4. With "cemented" its lines are cut through: lines at x = 0.5, 1.5,
/// ..., 9.5 make 11 columns, 4 x 11 = 44 blocks, and the gap pieces are Bridge(1) edges.
#[test]
fn a_set_that_closes_no_block_changes_nothing() {
    let mut spec = CutSpec {
        domain: rect(10.0, 4.0),
        joint_sets: vec![
            set(0.0, 1.0, [0.0, 0.0]),
            JointSet { trace: 0.3, gap: 0.7, trace_dev: 0.1, gap_dev: 0.2, ..set(90.0, 1.0, [0.5, 0.0]) },
        ],
        seed: 7,
        ..CutSpec::default()
    };
    let c = cut(&spec).unwrap();
    assert_eq!(c.blocks.len(), 4);
    assert!((total_area(&c) - 40.0).abs() < 1e-12 * 40.0);
    spec.joint_sets[1].bridges = Bridges::Cemented;
    let c = cut(&spec).unwrap();
    assert_eq!(c.blocks.len(), 44);
    assert!(c.blocks.iter().any(|b| b.edges.contains(&EdgeSource::Bridge(1))));
    assert!((total_area(&c) - 40.0).abs() < 1e-12 * 40.0);
}

fn joint(points: &[[f64; 2]]) -> Joint {
    Joint { points: points.to_vec() }
}

/// Degenerate: a joint through two domain vertices (the diagonal of a 4 x 4 square) makes 2
/// triangles of area 8; a set at 45 deg with spacing 2 sqrt(2) through the corner (0, 0) has
/// lines y = x + 4k: y = x and the lines through the corners (0, 4) and (4, 0), which touch the
/// square at one point and close nothing, so 2 blocks again. Areas to 1e-12 relative.
#[test]
fn traces_through_vertices() {
    let spec = CutSpec {
        domain: rect(4.0, 4.0),
        joints: vec![joint(&[[0.0, 0.0], [4.0, 4.0]])],
        ..CutSpec::default()
    };
    let c = cut(&spec).unwrap();
    assert_eq!(c.blocks.len(), 2);
    assert!(c.blocks.iter().all(|b| (b.area - 8.0).abs() < 1e-12 * 16.0 && b.vertices.len() == 3));
    let spec = CutSpec {
        domain: rect(4.0, 4.0),
        joint_sets: vec![set(45.0, 2.0 * 2f64.sqrt(), [0.0, 0.0])],
        ..CutSpec::default()
    };
    let c = cut(&spec).unwrap();
    assert_eq!(c.blocks.len(), 2, "{:?}", c.blocks);
    assert!(c.blocks.iter().all(|b| (b.area - 8.0).abs() < 1e-12 * 16.0 && b.vertices.len() == 3));
}

/// Degenerate: two joints overlapping on y = 2 ((0, 2)-(3, 2) and (1, 2)-(4, 2)) cut a 4 x 4
/// square into 2 blocks of 8. Along y = 2 the edge from x = 0 to 3 takes joint 0 (the first in
/// EdgeSource order where both lie) and from 3 to 4 joint 1, so (3, 2) stays a vertex (the source
/// changes there; joint 0's end is pushed on by the reach of math note §12.1, 1e-9 D = 5.7e-9 m,
/// hence the 1e-8 below) and (1, 2) does not: 5 vertices each. A joint on the outline ((0, 0)-(4, 0))
/// cuts nothing and names no edge (the outline comes first).
#[test]
fn collinear_overlaps() {
    let spec = CutSpec {
        domain: rect(4.0, 4.0),
        joints: vec![
            joint(&[[0.0, 2.0], [3.0, 2.0]]),
            joint(&[[1.0, 2.0], [4.0, 2.0]]),
            joint(&[[0.0, 0.0], [4.0, 0.0]]),
        ],
        ..CutSpec::default()
    };
    let c = cut(&spec).unwrap();
    assert_eq!(c.blocks.len(), 2);
    for b in &c.blocks {
        assert!((b.area - 8.0).abs() < 1e-12 * 16.0);
        assert_eq!(b.vertices.len(), 5, "{b:?}");
        assert!(!b.edges.contains(&EdgeSource::Joint(2)));
        for (i, v) in b.vertices.iter().enumerate() {
            let w = b.vertices[(i + 1) % 5];
            if v[1] == 2.0 && w[1] == 2.0 {
                let expected =
                    if v[0].max(w[0]) <= 3.0 + 1e-8 { EdgeSource::Joint(0) } else { EdgeSource::Joint(1) };
                assert_eq!(b.edges[i], expected, "{b:?}");
            }
        }
    }
}

/// Degenerate: two persistent sets a small angle d apart through (0, 0.5), spacing 1, across a
/// 10 x 4 rectangle. Set 0's lines y = 0.5, ..., 3.5 make 5 strips; each line of set 1 leaves its
/// twin at x = 0 and is 10 tan d away at x = 10, bounding a wedge of area 5 (10 tan d) and
/// thickness (area / longest edge, the 10 m side) 0.5 (10 tan d).
/// d = 0.01 deg: 10 tan d = 1.745e-3 m > min_edge = 1e-3, so no vertices merge, and the wedges,
/// 8.7e-4 m thick, are joined to a neighbour: 4 joins, 5 blocks.
/// d = 0.001 deg: the wedges' far corners are 1.745e-4 m apart, below min_edge: they merge (4
/// merges at x = 10, 10 tan d apart to 1e-9), the wedges collapse to zero area and are dropped (4
/// reports): 5 blocks. Total area 40 to 1e-12 either way (every move is along the outline).
#[test]
fn near_parallel_sets_are_joined_or_merged_and_reported() {
    for (d, joins, merges) in [(0.01f64, 4, 0), (0.001, 0, 4)] {
        let spec = CutSpec {
            domain: rect(10.0, 4.0),
            joint_sets: vec![set(0.0, 1.0, [0.0, 0.5]), set(d, 1.0, [0.0, 0.5])],
            ..CutSpec::default()
        };
        let c = cut(&spec).unwrap();
        assert_eq!(c.blocks.len(), 5, "{:?}", c.reports);
        let count = |f: &dyn Fn(&Report) -> bool| c.reports.iter().filter(|r| f(r)).count();
        assert_eq!(count(&|r| matches!(r, Report::JoinedBlock { .. })), joins, "{:?}", c.reports);
        let far = 10.0 * d.to_radians().tan();
        let at_far_end = |r: &Report| match r {
            Report::MergedVertices { count: 2, distance, at } => {
                at[0] == 10.0 && (distance - far).abs() < 1e-9
            }
            _ => false,
        };
        assert_eq!(count(&at_far_end), merges, "{:?}", c.reports);
        let dropped = count(&|r| matches!(r, Report::DroppedSliver { area, .. } if *area == 0.0));
        assert_eq!(dropped, merges, "{:?}", c.reports);
        assert!((total_area(&c) - 40.0).abs() < 1e-12 * 40.0);
        for r in &c.reports {
            assert!(!r.to_string().is_empty());
        }
    }
}

/// Degenerate: a joint (2, 2)-(2, 4) ending exactly on the joint (0, 2)-(4, 2) closes two blocks
/// (2 x 2 each) above it: 3 blocks. A joint (1, 0)-(1, 1) ending inside a block closes nothing.
#[test]
fn traces_ending_on_other_traces() {
    let spec = CutSpec {
        domain: rect(4.0, 4.0),
        joints: vec![
            joint(&[[0.0, 2.0], [4.0, 2.0]]),
            joint(&[[2.0, 2.0], [2.0, 4.0]]),
            joint(&[[1.0, 0.0], [1.0, 1.0]]),
        ],
        ..CutSpec::default()
    };
    let c = cut(&spec).unwrap();
    assert_eq!(c.blocks.len(), 3);
    let areas: Vec<f64> = c.blocks.iter().map(|b| b.area).collect();
    for (a, e) in areas.iter().zip([8.0, 4.0, 4.0]) {
        assert!((a - e).abs() < 1e-12 * 16.0, "{areas:?}");
    }
    assert_eq!(c.blocks[0].vertices.len(), 4, "the dangling joint leaves no vertex");
}

/// Bad input: each error kind names the item.
#[test]
fn errors_name_what_is_wrong() {
    let base = CutSpec { domain: rect(100.0, 100.0), ..CutSpec::default() };
    let with_sets = |sets: Vec<JointSet>| CutSpec { joint_sets: sets, ..base.clone() };
    let e = cut(&with_sets(vec![set(0.0, 0.0, [0.0, 0.0])])).unwrap_err();
    assert!(matches!(e, CutError::Set { set: 0, .. }) && e.to_string().contains("spacing"), "{e}");
    let e = cut(&with_sets(vec![set(0.0, f64::NAN, [0.0, 0.0])])).unwrap_err();
    assert!(matches!(e, CutError::Set { set: 0, .. }), "{e}");
    // two sets at 0.1 m across 100 m: floor(100 / 0.1) + 1 = 1001 lines each (math note §12.1),
    // 1 + 2002 + 1001^2 = 1,004,004 blocks estimated, above 100,000
    let e = cut(&with_sets(vec![set(0.0, 0.1, [0.0, 0.0]), set(90.0, 0.1, [0.0, 0.0])])).unwrap_err();
    match e {
        CutError::TooManyBlocks { set, estimate, limit, .. } => {
            assert_eq!((set, estimate, limit), (1, 1_004_004.0, 100_000));
        }
        e => panic!("{e}"),
    }
    let e = cut(&CutSpec { domain: vec![[0.0, 0.0], [1.0, 0.0]], ..CutSpec::default() }).unwrap_err();
    assert!(matches!(e, CutError::Domain(_)) && e.to_string().contains("3 vertices"), "{e}");
    let bowtie = vec![[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]];
    let e = cut(&CutSpec { domain: bowtie.clone(), ..CutSpec::default() }).unwrap_err();
    assert!(matches!(e, CutError::Domain(_)) && e.to_string().contains("intersects itself"), "{e}");
    let e = cut(&CutSpec { domain: vec![[0.0, 0.0], [f64::NAN, 0.0], [1.0, 1.0]], ..CutSpec::default() })
        .unwrap_err();
    assert!(matches!(e, CutError::Domain(_)), "{e}");
    let e = cut(&CutSpec { excavations: vec![Excavation { vertices: bowtie, keep: false }], ..base.clone() })
        .unwrap_err();
    assert!(matches!(e, CutError::Excavation { excavation: 0, .. }), "{e}");
    let far = circle([500.0, 500.0], 1.0, 8);
    let e = cut(&CutSpec { excavations: vec![Excavation { vertices: far, keep: false }], ..base.clone() })
        .unwrap_err();
    assert!(
        matches!(e, CutError::Excavation { excavation: 0, .. }) && e.to_string().contains("outside"),
        "{e}"
    );
    let e = cut(&CutSpec { joints: vec![joint(&[[200.0, 0.0], [300.0, 5.0]])], ..base.clone() }).unwrap_err();
    assert!(matches!(e, CutError::Joint { joint: 0, .. }) && e.to_string().contains("outside"), "{e}");
    let e = cut(&CutSpec { joints: vec![joint(&[[2.0, 0.0]])], ..base.clone() }).unwrap_err();
    assert!(matches!(e, CutError::Joint { joint: 0, .. }), "{e}");
    let e = cut(&CutSpec { min_edge: -1.0, ..base.clone() }).unwrap_err();
    assert!(matches!(e, CutError::MinEdge(_)), "{e}");
    // spacing 300 m from (0, 500): the lines y = 500 - 300 k nearest the domain are y = 200 and -100
    let e = cut(&with_sets(vec![set(0.0, 300.0, [0.0, 500.0])])).unwrap_err();
    assert!(matches!(e, CutError::Set { set: 0, .. }) && e.to_string().contains("no trace"), "{e}");
}

/// A meshed block (an irregular pentagon cut from a rectangle by two joints): the mesh read back
/// through the gmsh reader's checks has counter-clockwise triangles whose areas sum to the block's
/// area (1e-12 relative: the nodes are the block's vertices and points on its edges and inside,
/// written in round-trip form), one boundary loop whose polygon has the block's area, that loop
/// passing through every block vertex, and one physical curve per edge source.
#[test]
fn a_meshed_block_passes_the_mesh_checks() {
    use pbdda::geometry::{Vec2, signed_area2};
    use pbdda::mesh::loops::boundary_loops;
    use pbdda::rockmass::{mesh_block, to_mesh};
    let spec = CutSpec {
        domain: rect(6.0, 4.0),
        joints: vec![joint(&[[0.0, 1.3], [6.0, 2.9]]), joint(&[[2.2, 0.0], [3.9, 4.0]])],
        ..CutSpec::default()
    };
    let c = cut(&spec).unwrap();
    assert_eq!(c.blocks.len(), 4);
    let block = c.blocks.iter().max_by_key(|b| b.vertices.len()).unwrap();
    let tri = mesh_block(block, 0.4).unwrap();
    let names = |s: &EdgeSource| match s {
        EdgeSource::Outline => "outline".to_string(),
        other => format!("{other:?}"),
    };
    let mesh = to_mesh(&tri, &names, "block.msh").unwrap();
    assert_eq!(mesh.triangles.len(), tri.triangles.len());
    let area: f64 = (0..mesh.triangles.len()).map(|t| mesh.area2(t) / 2.0).sum();
    assert!((0..mesh.triangles.len()).all(|t| mesh.area2(t) > 0.0));
    assert!((area - block.area).abs() < 1e-12 * block.area, "{area} against {}", block.area);
    let loops = boundary_loops(&mesh.nodes, &mesh.triangles).unwrap();
    assert_eq!(loops.len(), 1);
    let outline: Vec<Vec2> = loops[0].nodes.iter().map(|&i| mesh.nodes[i]).collect();
    assert!((signed_area2(&outline) / 2.0 - block.area).abs() < 1e-12 * block.area);
    for v in &block.vertices {
        assert!(outline.iter().any(|p| p.x == v[0] && p.y == v[1]), "vertex {v:?} not on the mesh outline");
    }
    let mut sources: Vec<String> = block.edges.iter().map(names).collect();
    sources.sort();
    sources.dedup();
    for s in &sources {
        assert_eq!(mesh.group(s).unwrap().dim, 1);
    }
    assert!(mesh.group("block").is_ok());
    // triangles no larger than the equilateral triangle of side 0.4 (the refinement's bound)
    let max = (0..mesh.triangles.len()).map(|t| mesh.area2(t) / 2.0).fold(0.0, f64::max);
    assert!(max <= 3f64.sqrt() / 4.0 * 0.16 * (1.0 + 1e-12), "{max}");
}

mod random {
    use super::*;
    use pbdda::geometry::{Vec2, check_simple_polygon};
    use proptest::prelude::*;

    /// A star-shaped domain around (0, 0): n = 5..8 vertices at increasing angles (gaps at most
    /// 1.5 x 72 = 108 deg), radii in [6, 10], so that the disk of radius 6 cos 54 deg = 3.5 about
    /// (0, 0) lies inside it.
    fn domain() -> impl Strategy<Value = Vec<[f64; 2]>> {
        (5usize..9, proptest::collection::vec((0.0..1.0f64, 6.0..10.0f64), 8)).prop_map(|(n, r)| {
            (0..n)
                .map(|k| {
                    let a = std::f64::consts::TAU * (k as f64 + 0.5 * r[k].0) / n as f64;
                    [r[k].1 * a.cos(), r[k].1 * a.sin()]
                })
                .collect()
        })
    }

    fn joint_set() -> impl Strategy<Value = JointSet> {
        (0.0..180.0f64, 0.7..3.0f64, 0.0..1.0f64, 0.0..4.0f64, 0.0..1.0f64, any::<bool>()).prop_map(
            |(angle, spacing, dev, trace, gap, cemented)| JointSet {
                angle,
                spacing,
                origin: [0.3, -0.2],
                trace: if trace < 1.0 { 0.0 } else { trace },
                gap,
                angle_dev: 10.0 * dev,
                spacing_dev: 0.5 * dev * spacing,
                trace_dev: 0.5 * dev * trace,
                gap_dev: dev * gap,
                bridges: if cemented { Bridges::Cemented } else { Bridges::Remove },
            },
        )
    }

    fn dist_to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
        let d = [b[0] - a[0], b[1] - a[1]];
        let t = (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / (d[0] * d[0] + d[1] * d[1])).clamp(0.0, 1.0);
        (p[0] - a[0] - t * d[0]).hypot(p[1] - a[1] - t * d[1])
    }

    /// Whether `p` lies inside `poly` farther than `eps` from its outline.
    fn strictly_inside(p: [f64; 2], poly: &[[f64; 2]], eps: f64) -> bool {
        let n = poly.len();
        let mut c = false;
        for i in 0..n {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            if dist_to_segment(p, a, b) <= eps {
                return false;
            }
            if (a[1] > p[1]) != (b[1] > p[1]) && p[0] < a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]) {
                c = !c;
            }
        }
        c
    }

    /// Whether the interiors of two simple polygons overlap (1e-9 tolerance on a 20 m domain):
    /// two edges cross at interior points of both, a vertex of one lies strictly inside the
    /// other, or a point just inside one (1e-6 of its longest edge inwards of that edge's middle)
    /// lies strictly inside the other.
    fn overlap(a: &[[f64; 2]], b: &[[f64; 2]]) -> bool {
        let eps = 1e-9;
        let o = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| {
            let l = (q[0] - p[0]).hypot(q[1] - p[1]);
            ((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])) / l
        };
        for i in 0..a.len() {
            let (p, q) = (a[i], a[(i + 1) % a.len()]);
            for j in 0..b.len() {
                let (r, s) = (b[j], b[(j + 1) % b.len()]);
                let (d1, d2, d3, d4) = (o(p, q, r), o(p, q, s), o(r, s, p), o(r, s, q));
                if d1 * d2 < 0.0 && d3 * d4 < 0.0 && d1.abs().min(d2.abs()).min(d3.abs()).min(d4.abs()) > eps
                {
                    return true;
                }
            }
        }
        let probe = |p: &[[f64; 2]]| {
            let n = p.len();
            let k = (0..n)
                .max_by(|&i, &j| {
                    let l = |i: usize| (p[(i + 1) % n][0] - p[i][0]).hypot(p[(i + 1) % n][1] - p[i][1]);
                    l(i).total_cmp(&l(j))
                })
                .unwrap();
            let (u, w) = (p[k], p[(k + 1) % n]);
            let d = [w[0] - u[0], w[1] - u[1]];
            [0.5 * (u[0] + w[0]) - 1e-6 * d[1], 0.5 * (u[1] + w[1]) + 1e-6 * d[0]]
        };
        a.iter().any(|p| strictly_inside(*p, b, eps))
            || b.iter().any(|p| strictly_inside(*p, a, eps))
            || strictly_inside(probe(a), b, eps)
            || strictly_inside(probe(b), a, eps)
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]
        /// Any cut tiles the domain minus the removed excavation: block areas sum to the domain's
        /// shoelace area minus the excavation's (1e-12 relative; the cut points are rounded at
        /// ~1e-16 relative, merges move vertices by at most 1e-9 D here since min_edge = 0 and
        /// thin-block joins conserve area), no two blocks overlap (joints start within 2.1 of
        /// (0, 0) and the excavation's radius is at most 2.5, both inside the domain), every block is simple and
        /// counter-clockwise; the same seed gives identical output twice (the cutter is
        /// sequential).
        #[test]
        fn cuts_tile_the_domain(
            domain in domain(),
            sets in proptest::collection::vec(joint_set(), 0..3),
            joints in proptest::collection::vec((-1.5..1.5f64, -1.5..1.5f64, -8.0..8.0f64, -8.0..8.0f64), 0..3),
            hole in (0.5..2.5f64, any::<bool>(), any::<bool>()),
            seed in any::<u64>(),
        ) {
            let excavations = if hole.1 {
                vec![Excavation { vertices: circle([0.0, 0.0], hole.0, 16), keep: hole.2 }]
            } else {
                Vec::new()
            };
            let spec = CutSpec {
                domain: domain.clone(),
                joint_sets: sets,
                joints: joints.iter().map(|j| Joint { points: vec![[j.0, j.1], [j.2, j.3]] }).collect(),
                excavations: excavations.clone(),
                min_edge: 0.0,
                seed,
                ..CutSpec::default()
            };
            let c = cut(&spec).unwrap_or_else(|e| panic!("{e}"));
            let shoelace = |p: &[[f64; 2]]| {
                (0..p.len()).map(|i| p[i][0] * p[(i + 1) % p.len()][1] - p[i][1] * p[(i + 1) % p.len()][0]).sum::<f64>() / 2.0
            };
            let removed: f64 = excavations.iter().filter(|e| !e.keep).map(|e| shoelace(&e.vertices)).sum();
            let expected = shoelace(&domain) - removed;
            prop_assert!((total_area(&c) - expected).abs() < 1e-12 * expected, "{} against {}", total_area(&c), expected);
            for b in &c.blocks {
                let pts: Vec<Vec2> = b.vertices.iter().map(|p| Vec2::new(p[0], p[1])).collect();
                prop_assert!(check_simple_polygon(&pts).is_ok());
                prop_assert!(shoelace(&b.vertices) > 0.0);
                prop_assert_eq!(b.edges.len(), b.vertices.len());
            }
            let bbox = |p: &[[f64; 2]]| p.iter().fold([f64::MAX, f64::MAX, f64::MIN, f64::MIN], |b, q| {
                [b[0].min(q[0]), b[1].min(q[1]), b[2].max(q[0]), b[3].max(q[1])]
            });
            let boxes: Vec<[f64; 4]> = c.blocks.iter().map(|b| bbox(&b.vertices)).collect();
            for i in 0..c.blocks.len() {
                for j in i + 1..c.blocks.len() {
                    let (p, q) = (boxes[i], boxes[j]);
                    if p[0] > q[2] || q[0] > p[2] || p[1] > q[3] || q[1] > p[3] {
                        continue;
                    }
                    prop_assert!(!overlap(&c.blocks[i].vertices, &c.blocks[j].vertices), "blocks {} and {} overlap", i, j);
                }
            }
            prop_assert_eq!(&cut(&spec).unwrap(), &c);
        }
    }
}

/// Merges do not chain (math note §12.3): three vertical joints x = 1, 1.0006, 1.0012 across the
/// rectangle 2 x 1, min_edge 1e-3. Their crossings with each long side are 6e-4 apart (x = 1 and
/// 1.0012 are 1.2e-3 apart). The crossing at x = 1 (first inserted, so of lowest index among
/// these rank-1 vertices) takes the one at 1.0006; the one at 1.0012 is 1.2e-3 from it and stays.
/// So 2 merges (one per side) of 2 vertices 6e-4 apart, the strip 1 < x < 1.0006 collapses
/// (dropped, zero area) and the strip 1 < x < 1.0012 remains (1.2e-3 thick, above min_edge):
/// 3 blocks of 1, 1.2e-3 and 0.9988 m2. (A union of all close pairs would merge all three
/// crossings, moving the last by 1.2e-3, and leave 2 blocks.) 1e-12 on areas: the coordinates
/// are not binary fractions, each area carries the rounding of 1.0006 and 1.0012.
#[test]
fn merges_do_not_chain() {
    let spec = CutSpec {
        domain: rect(2.0, 1.0),
        joints: [1.0, 1.0006, 1.0012].iter().map(|&x| joint(&[[x, -1.0], [x, 2.0]])).collect(),
        ..CutSpec::default()
    };
    let c = cut(&spec).unwrap();
    let mut areas: Vec<f64> = c.blocks.iter().map(|b| b.area).collect();
    areas.sort_by(f64::total_cmp);
    assert_eq!(areas.len(), 3, "{:?}", c.reports);
    for (a, e) in areas.iter().zip([1.2e-3, 0.9988, 1.0]) {
        assert!((a - e).abs() < 1e-12, "{areas:?}");
    }
    let merges: Vec<&Report> =
        c.reports.iter().filter(|r| matches!(r, Report::MergedVertices { .. })).collect();
    assert_eq!(merges.len(), 2, "{:?}", c.reports);
    for r in merges {
        let Report::MergedVertices { count, distance, at } = r else { unreachable!() };
        assert_eq!(*count, 2);
        assert!((distance - 6e-4).abs() < 1e-12 && at[0] == 1.0, "{r}");
    }
}

/// Inputs on which `cargo fuzz run cut` found the cutter failing, decoded exactly as
/// fuzz/fuzz_targets/cut.rs decodes its bytes (the decoder is copied here, since the fuzz crate is
/// not part of the workspace). Each must cut without error (spade's constraint splitting once
/// asserted on their nearly coincident crossings; the glue now splits constraints itself, math
/// note §12.7), or be refused by a named error where merges would lose area (math note §12.8).
/// The fuzz target's area identity (blocks
/// sum to the domain less the removed excavation, 1e-9 relative plus 4 merge distances squared per
/// report: a merge moves the outline by at most the merge distance near a corner) is checked
/// where the target checks it.
#[path = "../fuzz/fuzz_targets/cut_input.rs"]
mod cut_input;

#[path = "rockmass_cut/fuzz_crashes.rs"]
mod fuzz_crashes;
