//! The contact operator W = B K⁻¹ Bᵀ (math note §3): assembled sparse from per-body blocks, it
//! must equal the dense product B K⁻¹ Bᵀ, be symmetric, and be positive semidefinite
//! (z ᵀ W z = |K^{-1/2} Bᵀ z|² >= 0, §3.2). Random scenes of rigid disks and polygons with
//! random contacts between random pairs (including fixed bodies, which carry no DOF, and
//! deformable bodies with 4 and 6 DOF).
//! Tolerances: 1e-12 relative to the largest entry (round-off of 3-term sums); the smallest
//! eigenvalue may be negative only by round-off, 1e-10 of the largest.

use nalgebra::{DMatrix, SymmetricEigen};
use pbdda::body::Body;
use pbdda::cluster::{Flexibility, Jacobian};
use pbdda::geometry::{Vec2, cw};
use pbdda::model::{BodyModel, BodySpec, Material, Plane, Shape};
use proptest::prelude::*;

fn spec(i: usize, kind: u8, x: f64, y: f64, size: f64, fixed: bool, deformable: bool) -> BodySpec {
    let shape = match kind % 3 {
        0 => Shape::Disk { center: Vec2::new(x, y), radius: size },
        1 => Shape::Ring { center: Vec2::new(x, y), outer: size, inner: 0.4 * size },
        _ => Shape::Polygon {
            vertices: vec![
                Vec2::new(x - size, y - 0.5 * size),
                Vec2::new(x + size, y - 0.5 * size),
                Vec2::new(x + 0.3 * size, y + size),
            ],
        },
    };
    BodySpec {
        name: format!("b{i}"),
        shape,
        model: if deformable { BodyModel::Deformable } else { BodyModel::Rigid },
        material: 0,
        fixed,
        velocity: Vec2::zeros(),
        angular_velocity: 0.0,
        initial_stress: None,
    }
}

prop_compose! {
    fn scene()(bodies in prop::collection::vec((0u8..3, -5.0..5.0f64, -5.0..5.0f64, 0.2..2.0f64, prop::bool::weighted(0.2), 1.0..1e4f64, prop::bool::ANY, 1e6..1e12f64), 2..8),
               contacts in prop::collection::vec((0usize..100, 0usize..100, -6.0..6.0f64, -6.0..6.0f64, 0.0..std::f64::consts::TAU), 1..15),
               dt in 1e-4..0.1f64)
        -> (Vec<Body>, Vec<(usize, usize, Vec2, Vec2)>, f64) {
        let n = bodies.len();
        let bodies: Vec<Body> = bodies.iter().enumerate()
            .map(|(i, &(k, x, y, s, fixed, rho, deformable, young))| {
                let material = Material { name: "m".into(), density: rho, young: Some(young), poisson: Some(0.3) };
                Body::new(&spec(i, k, x, y, s, fixed, deformable), &material, Plane::Stress)
            }).collect();
        let contacts = contacts.iter().filter_map(|&(a, b, x, y, ang)| {
            let (a, b) = (a % n, b % n);
            (a != b).then(|| (a, b, Vec2::new(x, y), Vec2::new(ang.cos(), ang.sin())))
        }).collect();
        (bodies, contacts, dt)
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]
    #[test]
    fn w_is_b_kinv_bt_symmetric_psd((bodies, contacts, dt) in scene()) {
        prop_assume!(!contacts.is_empty());
        let flex = Flexibility::new(&bodies, dt);
        let rows = 2 * contacts.len();
        let mut jac = Jacobian::new(bodies.len(), rows);
        let ndof: Vec<usize> = bodies.iter().map(|b| b.ndof()).collect();
        let offset: Vec<usize> = ndof.iter().scan(0, |s, &n| { let o = *s; *s += n; Some(o) }).collect();
        let total: usize = ndof.iter().sum();
        let mut b_dense = DMatrix::zeros(rows, total);
        let mut kinv_dense = DMatrix::zeros(total, total);
        for i in 0..bodies.len() {
            for r in 0..ndof[i] { for c in 0..ndof[i] { kinv_dense[(offset[i] + r, offset[i] + c)] = flex.of(i)[(r, c)]; } }
        }
        for (k, &(a, b, x, n)) in contacts.iter().enumerate() {
            for (body, sign) in [(a, 1.0), (b, -1.0)] {
                for (row, dir) in [(2 * k, n), (2 * k + 1, cw(n))] {
                    let j = bodies[body].shape_row(x, dir) * sign;
                    if ndof[body] > 0 { jac.push(body, row, j); }
                    for c in 0..ndof[body] { b_dense[(row, offset[body] + c)] += j[c]; }
                }
            }
        }
        let w = jac.operator(&flex).to_dense();
        let reference = &b_dense * &kinv_dense * b_dense.transpose();
        let scale = reference.amax().max(1e-300);
        for r in 0..rows { for c in 0..rows {
            prop_assert!((w[[r, c]] - reference[(r, c)]).abs() <= 1e-12 * scale, "W[{r},{c}] = {} vs {}", w[[r, c]], reference[(r, c)]);
            prop_assert!((w[[r, c]] - w[[c, r]]).abs() <= 1e-12 * scale);
        }}
        let eig = SymmetricEigen::new(reference.clone());
        prop_assert!(eig.eigenvalues.min() >= -1e-10 * scale, "min eigenvalue {}", eig.eigenvalues.min());
    }
}
