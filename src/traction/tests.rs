//! The boundary part between two points and the domain resolver, on hand-written geometry whose
//! answers are read off the drawing (exact: every point is a vertex or a midpoint, so the
//! parameters are exact in binary).

use super::*;
use crate::model::{BodyModel, BodySpec, Shape};

fn v(x: f64, y: f64) -> Vec2 {
    Vec2::new(x, y)
}

fn square() -> Vec<Vec2> {
    vec![v(0.0, 0.0), v(2.0, 0.0), v(2.0, 2.0), v(0.0, 2.0)]
}

/// From the top-right corner to the top-left one, counter-clockwise: the top edge alone; the
/// other way round: the other three edges.
#[test]
fn a_boundary_part_runs_counter_clockwise_between_the_nearest_points() {
    let ring = square();
    assert_eq!(boundary_part(&ring, v(2.1, 2.1), v(-0.1, 2.1)), Some(vec![(2, [0.0, 1.0])]));
    assert_eq!(
        boundary_part(&ring, v(-0.1, 2.1), v(2.1, 2.1)),
        Some(vec![(3, [0.0, 1.0]), (0, [0.0, 1.0]), (1, [0.0, 1.0])])
    );
    // from the bottom's midpoint to the right side's midpoint: half of each
    assert_eq!(boundary_part(&ring, v(1.0, -1.0), v(3.0, 1.0)), Some(vec![(0, [0.5, 1.0]), (1, [0.0, 0.5])]));
    // within one edge
    assert_eq!(boundary_part(&ring, v(0.5, 0.0), v(1.5, 0.0)), Some(vec![(0, [0.25, 0.75])]));
    // the same boundary point twice: no part
    assert_eq!(boundary_part(&ring, v(1.0, -1.0), v(1.0, -3.0)), None);
}

/// A pressure pushes into the body along −n; a shear acts along the ccw tangent; a stress −p I
/// is the pressure p.
#[test]
fn traction_vectors_follow_the_outward_normal() {
    let tau = v(-1.0, 0.0); // the top edge of a ccw square, n = (0, 1)
    let p = TractionLaw::Pressure { pressure: 3.0, shear: 0.0 }.vector(tau);
    assert_eq!(p, v(0.0, -3.0));
    assert_eq!(TractionLaw::Pressure { pressure: 0.0, shear: 2.0 }.vector(tau), v(-2.0, 0.0));
    assert_eq!(TractionLaw::Stress([-3.0, -3.0, 0.0]).vector(tau), p);
    assert_eq!(TractionLaw::Stress([0.0, 0.0, 5.0]).vector(tau), v(5.0, 0.0));
}

fn polygon(name: &str, vertices: Vec<Vec2>) -> BodySpec {
    BodySpec::at_rest(name, Shape::Polygon { vertices }, BodyModel::Rigid, false)
}

/// Four blocks tiling the 4 × 2 rectangle (two rows of two, the top-left one a triangle pair
/// split by a diagonal): the top side from (4, 2) to (0, 2) is the top edges of the upper
/// blocks, and no interior edge; the whole bottom and right side from (0, 0) to (4, 2) are the
/// lower blocks' bottoms and the right blocks' right sides.
#[test]
fn domain_edges_are_the_blocks_edges_on_the_outline() {
    let outline = vec![v(0.0, 0.0), v(4.0, 0.0), v(4.0, 2.0), v(0.0, 2.0)];
    let bodies = vec![
        polygon("ll", vec![v(0.0, 0.0), v(2.0, 0.0), v(2.0, 1.0), v(0.0, 1.0)]),
        polygon("lr", vec![v(2.0, 0.0), v(4.0, 0.0), v(4.0, 1.0), v(2.0, 1.0)]),
        // upper left, two triangles
        polygon("ula", vec![v(0.0, 1.0), v(2.0, 1.0), v(0.0, 2.0)]),
        polygon("ulb", vec![v(2.0, 1.0), v(2.0, 2.0), v(0.0, 2.0)]),
        polygon("ur", vec![v(2.0, 1.0), v(4.0, 1.0), v(4.0, 2.0), v(2.0, 2.0)]),
    ];
    let top = domain_edges(&outline, &bodies, v(4.0, 2.0), v(0.0, 2.0));
    assert_eq!(top, vec![(3, 1), (4, 2)]);
    let bottom_right = domain_edges(&outline, &bodies, v(0.0, 0.0), v(4.0, 2.0));
    assert_eq!(bottom_right, vec![(0, 0), (1, 0), (1, 1), (4, 1)]);
    let left = domain_edges(&outline, &bodies, v(0.0, 2.0), v(0.0, 0.0));
    assert_eq!(left, vec![(0, 3), (2, 2)]);
    // half the top, from its midpoint: the upper-left blocks' top edge alone
    assert_eq!(domain_edges(&outline, &bodies, v(2.0, 2.0), v(0.0, 2.0)), vec![(3, 1)]);
    // as tractions: one per body, its edges as whole pieces
    let law = TractionLaw::Pressure { pressure: 1.0, shear: 0.0 };
    let t = domain_tractions(&outline, &bodies, v(0.0, 0.0), v(4.0, 2.0), law, None);
    let got: Vec<(usize, Vec<[usize; 2]>)> =
        t.iter().map(|t| (t.body, t.pieces.iter().map(|p| p.nodes).collect())).collect();
    assert_eq!(got, vec![(0, vec![[0, 1]]), (1, vec![[0, 1], [1, 2]]), (4, vec![[1, 2]])]);
    assert!(t.iter().flat_map(|t| &t.pieces).all(|p| p.s == [0.0, 1.0]));
}
