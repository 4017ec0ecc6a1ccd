use super::*;
use crate::geometry::tests::l_shape;

fn spec(shape: Shape, model: BodyModel) -> BodySpec {
    BodySpec {
        name: "b".into(),
        shape,
        model,
        material: 0,
        fixed: false,
        velocity: Vec2::zeros(),
        angular_velocity: 0.0,
        initial_stress: None,
        edge_interfaces: Vec::new(),
    }
}

fn material() -> Material {
    Material { name: "m".into(), density: 2.5, young: Some(3.0e9), poisson: Some(0.3) }
}

/// ρ ∫ Tᵀ T dA over a triangle fan, with the 3-point (edge-midpoint) rule, exact for the
/// quadratic integrand: the reference for the closed-form mass matrices of math note §2.2.
fn quadrature_mass(body: &Body, vertices: &[Vec2]) -> BodyMatrix {
    let rho = 2.5;
    let mut m = BodyMatrix::zeros();
    let o = vertices[0];
    for i in 1..vertices.len() - 1 {
        let (a, b) = (vertices[i], vertices[i + 1]);
        let area = 0.5 * cross(a - o, b - o);
        for x in [(o + a) / 2.0, (a + b) / 2.0, (b + o) / 2.0] {
            let tx = body.shape_row(x, Vec2::x());
            let ty = body.shape_row(x, Vec2::y());
            m += (tx * tx.transpose() + ty * ty.transpose()) * (rho * area / 3.0);
        }
    }
    m
}

/// Closed-form mass matrices (rigid 3×3, deformable 6×6) against exact quadrature of
/// ρ ∫ Tᵀ T dA on a concave L-shape; tolerance: round-off of O(10) terms.
#[test]
fn polygon_mass_matrices_match_quadrature() {
    for model in [BodyModel::Rigid, BodyModel::Deformable] {
        let body =
            Body::new(&spec(Shape::Polygon { vertices: l_shape() }, model), &material(), Plane::Stress);
        let exact = quadrature_mass(&body, &l_shape());
        assert!((body.mass_matrix() - exact).amax() < 1e-12, "{model:?}: {}", body.mass_matrix() - exact);
    }
}

/// `mass_times` (a rigid body's M v from its diagonal) against the product with `mass_matrix`,
/// for rigid and deformable disks and polygons with a velocity in every DOF. Exact equality:
/// the rigid case computes the product's nonzero terms, and the other bodies take the product.
#[test]
fn mass_times_is_the_mass_matrix_product() {
    let disk = Shape::Disk { center: Vec2::new(1.0, -2.0), radius: 0.7 };
    let polygon = Shape::Polygon { vertices: l_shape() };
    for (shape, model) in [
        (disk.clone(), BodyModel::Rigid),
        (disk, BodyModel::Deformable),
        (polygon.clone(), BodyModel::Rigid),
        (polygon, BodyModel::Deformable),
    ] {
        let body = Body::new(&spec(shape, model), &material(), Plane::Stress);
        let n = body.ndof();
        let mut v = Dofs::zeros();
        for i in 0..n {
            v[i] = [0.3, -1.7, 2.9, -0.4, 0.8, -2.2][i];
        }
        let (fast, full) = (body.mass_times(&v), body.mass_matrix() * v);
        assert_eq!(fast, full, "{model:?}, {n} DOFs");
    }
}

/// Disk and ring: M = ρ diag(A, A, J(, J)), J = ρπ(RE⁴ − RI⁴)/2 (math note §2.2, eq. A.9).
#[test]
fn particle_mass_matrices() {
    use std::f64::consts::PI;
    let ring = Shape::Ring { center: Vec2::new(1.0, 2.0), outer: 3.0, inner: 1.0 };
    let body = Body::new(&spec(ring, BodyModel::Deformable), &material(), Plane::Stress);
    let (a, j) = (PI * 8.0, PI * 80.0 / 2.0);
    let m = body.mass_matrix();
    for (i, v) in [a, a, j, j].iter().enumerate() {
        assert!((m[(i, i)] - 2.5 * v).abs() < 1e-12 * 2.5 * v);
    }
    assert_eq!(m.iter().filter(|x| **x != 0.0).count(), 4);
}

/// Math note §2.3: K_44 = 2πE(RE² − RI²)/(1 − ν) in plane stress and
/// 2πE(RE² − RI²)/((1 + ν)(1 − 2ν)) in plane strain (the paper's A.4 is half of it).
#[test]
fn particle_stiffness_is_the_corrected_one() {
    use std::f64::consts::PI;
    let (e, nu) = (3.0e9, 0.3);
    let ring = Shape::Ring { center: Vec2::zeros(), outer: 3.0, inner: 1.0 };
    let stress = Body::new(&spec(ring.clone(), BodyModel::Deformable), &material(), Plane::Stress);
    let strain = Body::new(&spec(ring, BodyModel::Deformable), &material(), Plane::Strain);
    let k_stress = 2.0 * PI * e * 8.0 / (1.0 - nu);
    let k_strain = 2.0 * PI * e * 8.0 / ((1.0 + nu) * (1.0 - 2.0 * nu));
    assert!((stress.elastic_stiffness()[(3, 3)] - k_stress).abs() < 1e-12 * k_stress);
    assert!((strain.elastic_stiffness()[(3, 3)] - k_strain).abs() < 1e-12 * k_strain);
}

/// Post-adjusted update (paper eq. 16): a rigid rotation by θ = π/2 of a square is exact,
/// so the vertices keep their distances from the centroid to round-off.
#[test]
fn rigid_rotation_is_exact() {
    let sq = vec![Vec2::new(-1.0, -1.0), Vec2::new(1.0, -1.0), Vec2::new(1.0, 1.0), Vec2::new(-1.0, 1.0)];
    let mut body =
        Body::new(&spec(Shape::Polygon { vertices: sq }, BodyModel::Rigid), &material(), Plane::Stress);
    let mut d = Dofs::zeros();
    d[2] = std::f64::consts::FRAC_PI_2;
    body.apply_increment(&d);
    let Outline::Polygon { vertices, .. } = &body.outline else { unreachable!() };
    assert!((vertices[0] - Vec2::new(1.0, -1.0)).norm() < 1e-15);
    assert!((body.rotation - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
}

/// The strain map of math note §2.3, written out: a particle's ε (DOF 3) acts on εx and εy; a
/// deformable block's (εx, εy, γxy) are DOFs 3, 4, 5; a rigid body has none. `strain_map` is
/// built from `strain_of`, so this checks both against the note. For finite d, `strain_of(d)`
/// is the product `strain_map() d` bit for bit (its other terms are exact zeros), and
/// `scaled_shape_row(x, dir, s)` is `shape_row(x, dir) s` bit for bit (each entry computed as
/// there, then multiplied by s), with the entries past ndof untouched. Bit-exact by
/// construction: any tolerance would hide a changed operation order.
#[test]
fn strain_and_scaled_rows_match_their_definitions() {
    let polygon = Shape::Polygon { vertices: l_shape() };
    let disk = Shape::Disk { center: Vec2::new(0.3, -0.2), radius: 0.7 };
    let mut map = [SMatrix::<f64, 3, MAX_DOF>::zeros(); 3];
    (map[1][(0, 3)], map[1][(1, 3)]) = (1.0, 1.0);
    (map[2][(0, 3)], map[2][(1, 4)], map[2][(2, 5)]) = (1.0, 1.0, 1.0);
    let cases = [
        (disk.clone(), BodyModel::Rigid, 3),
        (disk, BodyModel::Deformable, 4),
        (polygon, BodyModel::Deformable, 6),
    ];
    let d = Dofs::from_column_slice(&[0.1, -0.25, 0.03, 1.5e-4, -2.5e-4, 3.5e-4]);
    let (x, dir) = (Vec2::new(0.9, 0.4), Vec2::new(0.6, -0.8));
    for ((shape, model, n), want) in cases.into_iter().zip(map) {
        let body = Body::new(&spec(shape, model), &material(), Plane::Stress);
        assert_eq!(body.ndof(), n);
        assert_eq!(body.strain_map(), want, "ndof {n}");
        assert_eq!(
            body.strain_of(&d).map(f64::to_bits),
            (body.strain_map() * d).map(f64::to_bits),
            "ndof {n}"
        );
        for s in [1.0, -1.0, 0.37] {
            let mut out = [f64::NAN; MAX_DOF];
            body.scaled_shape_row(x, dir, s, &mut out);
            let want = body.shape_row(x, dir) * s;
            assert!((0..n).all(|i| out[i].to_bits() == want[i].to_bits()), "ndof {n}, s {s}: {out:?}");
            assert!(out[n..].iter().all(|v| v.is_nan()), "ndof {n}: wrote past ndof");
        }
    }
}

/// `max_motion` bounds |T(x) d| over the body (the refinement and the step's motion checks rely
/// on it): for rigid and deformable disks and the L-shape, with every DOF of d nonzero, no
/// outline point (the L's vertices, where the linear map T(x) d peaks, and 64 points of the
/// circle) moves farther. It is exact, to round-off, where the triangle inequality it uses is
/// an equality: a pure translation (every point) and a pure rotation (the farthest point, at
/// the body's reach). A fixed body has no DOFs and does not move.
#[test]
fn max_motion_bounds_every_point() {
    let disk = Shape::Disk { center: Vec2::new(1.0, -2.0), radius: 0.7 };
    let circle: Vec<Vec2> = (0..64)
        .map(|k| {
            let a = k as f64 * std::f64::consts::TAU / 64.0;
            Vec2::new(1.0, -2.0) + 0.7 * Vec2::new(a.cos(), a.sin())
        })
        .collect();
    for (shape, points) in [(disk, circle), (Shape::Polygon { vertices: l_shape() }, l_shape())] {
        for model in [BodyModel::Rigid, BodyModel::Deformable] {
            let body = Body::new(&spec(shape.clone(), model), &material(), Plane::Stress);
            let n = body.ndof();
            let farthest =
                |d: &Dofs| points.iter().map(|&x| body.displacement(x, d).norm()).fold(0.0, f64::max);
            let d = Dofs::from_fn(|i, _| if i < n { [3e-3, -2e-3, 1e-3, 4e-4, -5e-4, 2e-4][i] } else { 0.0 });
            let bound = body.max_motion(&d.as_slice()[..n]);
            assert!(farthest(&d) <= bound * (1.0 + 1e-12), "{model:?} {n}: {} > {bound}", farthest(&d));
            let translation = Dofs::from_fn(|i, _| [3e-3, -4e-3, 0.0, 0.0, 0.0, 0.0][i]);
            let bound = body.max_motion(&translation.as_slice()[..n]);
            assert!((bound - 5e-3).abs() < 1e-15 && (farthest(&translation) - bound).abs() < 1e-15);
            let rotation = Dofs::from_fn(|i, _| if i == 2 { 2e-3 } else { 0.0 });
            let bound = body.max_motion(&rotation.as_slice()[..n]);
            assert!((farthest(&rotation) - bound).abs() < 1e-15 * bound.max(1.0), "{model:?} {n}");
        }
    }
    let fixed = Body::new(
        &BodySpec { fixed: true, ..spec(Shape::Polygon { vertices: l_shape() }, BodyModel::Rigid) },
        &material(),
        Plane::Stress,
    );
    assert_eq!(fixed.max_motion(&[]), 0.0);
}
