//! The contact operator W = B K̃⁻¹ Bᵀ with mesh bodies (math note §9.2, §10.6): on random scenes
//! of meshed blocks (`square.msh`, randomly scaled and placed, some with the `left` side clamped by
//! `fixed_nodes`) among rigid and deformable polygons, with random contacts whose columns on a mesh
//! have entries at the two nodes of the boundary edge holding the contact point,
//! c = s [(1 − t) e_i + t e_j] ⊗ [n, τ]. The sparse W (mesh K̄ factorized by the sparse Cholesky of
//! its cluster, columns per cluster) must equal the dense Cᵀ K̄⁻¹ C with K̄ = Σ (K_e + (2/dt²) M_e)
//! assembled densely and inverted by LU. Tolerance 1e-10 relative to the largest entry (the
//! issue's bound): K̄'s condition number here is below ~1e6 (element stiffness E ≤ 1e9 against
//! mass terms 2ρA/dt² ≥ 1e2), so LU and Cholesky agree to ~1e-16 × 1e6.

use nalgebra::DMatrix;
use pbdda::body::Body;
use pbdda::cluster::Flexibility;
use pbdda::delassus;
use pbdda::dofs::DofMap;
use pbdda::geometry::{Vec2, cw};
use pbdda::jacobian::Jacobian;
use pbdda::mesh::Mesh;
use pbdda::model::{BodyModel, BodySpec, Material, MeshShape, Plane, Shape};
use proptest::prelude::*;
use std::path::Path;
use std::sync::OnceLock;

fn square() -> &'static Mesh {
    static MESH: OnceLock<Mesh> = OnceLock::new();
    MESH.get_or_init(|| {
        Mesh::read(&Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/square.msh")).expect("square.msh")
    })
}

/// Body i: a mesh (kind 0, clamped on its left side when `clamp`), a rigid (1) or a deformable (2)
/// triangle.
fn body(i: usize, kind: u8, at: Vec2, size: f64, clamp: bool, rho: f64, young: f64) -> Body {
    let shape = match kind % 3 {
        0 => {
            let mesh = square().transformed(size, at);
            let fixed_nodes = if clamp { mesh.node_set(&["left"]).expect("left") } else { Vec::new() };
            Shape::Mesh(Box::new(MeshShape { mesh, fixed_nodes, rollers: Vec::new() }))
        }
        _ => {
            Shape::Polygon { vertices: vec![at, at + Vec2::new(size, 0.0), at + Vec2::new(0.3 * size, size)] }
        }
    };
    let spec = BodySpec {
        name: format!("b{i}"),
        shape,
        model: if kind % 3 == 2 { BodyModel::Deformable } else { BodyModel::Rigid },
        material: 0,
        fixed: false,
        velocity: Vec2::zeros(),
        angular_velocity: 0.0,
        initial_stress: None,
        edge_interfaces: Vec::new(),
    };
    let material = Material { name: "m".into(), density: rho, young: Some(young), poisson: Some(0.3) };
    Body::new(&spec, &material, Plane::Strain)
}

/// A point on body `b`'s outline: `u` in [0, 1) picks an edge and a place along it.
fn outline_point(b: &Body, u: f64) -> Vec2 {
    let pbdda::body::Outline::Polygon { vertices, .. } = &b.outline else { unreachable!() };
    let x = u * vertices.len() as f64;
    let (k, t) = (x.floor() as usize % vertices.len(), x.fract());
    vertices[k] * (1.0 - t) + vertices[(k + 1) % vertices.len()] * t
}

/// The (DOF, value) entries of one row of B on body `b` for a unit force `dir` at `x`.
fn column(b: &Body, x: Vec2, dir: Vec2, start: usize) -> Vec<(usize, f64)> {
    match &b.mesh {
        Some(fe) => fe
            .edge_weights(x)
            .iter()
            .filter_map(|&(node, w)| fe.pattern.dof(node).map(|d| (d, w)))
            .flat_map(|(d, w)| [(start + d, w * dir.x), (start + d + 1, w * dir.y)])
            .collect(),
        None => {
            let row = b.shape_row(x, dir);
            (0..b.ndof()).map(|c| (start + c, row[c])).collect()
        }
    }
}

fn check(bodies: &[Body], contacts: &[(usize, usize, f64, f64)], dt: f64) -> Result<(), TestCaseError> {
    let map = DofMap::new(bodies, &[]);
    let mut flex = Flexibility::new(false);
    flex.refresh(&map, bodies, &[], dt, 0.0).expect("K̃ is SPD");
    let (rows, total) = (2 * contacts.len(), map.total());
    let mut k_dense = DMatrix::<f64>::zeros(total, total);
    for (i, b) in bodies.iter().enumerate() {
        let s = map.range(i).start;
        match &b.mesh {
            Some(fe) => {
                for (r, c, v) in fe.step_triplets(dt) {
                    k_dense[(s + r, s + c)] = v;
                    k_dense[(s + c, s + r)] = v;
                }
            }
            None => {
                let k = b.elastic_stiffness() + b.mass_matrix() * (2.0 / (dt * dt));
                for p in 0..b.ndof() {
                    for q in 0..b.ndof() {
                        k_dense[(s + p, s + q)] = k[(p, q)];
                    }
                }
            }
        }
    }
    let mut jac = Jacobian::default();
    jac.reset(rows);
    let mut b_dense = DMatrix::<f64>::zeros(rows, total);
    for (k, &(a, b, u, angle)) in contacts.iter().enumerate() {
        let x = outline_point(&bodies[a], u);
        let n = Vec2::new(angle.cos(), angle.sin());
        for (body, sign) in [(a, 1.0), (b, -1.0)] {
            let cluster = map.cluster_of(body).expect("free body");
            for (row, dir) in [(2 * k, n), (2 * k + 1, cw(n))] {
                for (dof, v) in column(&bodies[body], x, dir * sign, map.range(body).start) {
                    let mut vals = pbdda::body::Dofs::zeros();
                    vals[0] = v;
                    jac.push(row, cluster, dof, 1, vals);
                    b_dense[(row, dof)] += v;
                }
            }
        }
    }
    let w = delassus::assemble(&jac, &flex, &map).to_dense();
    let kinv = k_dense.lu().try_inverse().expect("K̄ invertible");
    let reference = &b_dense * kinv * b_dense.transpose();
    let scale = reference.amax().max(1e-300);
    let mut err = 0.0f64;
    for r in 0..rows {
        for c in 0..rows {
            err = err.max((w[[r, c]] - reference[(r, c)]).abs() / scale);
        }
    }
    prop_assert!(err < 1e-10, "W differs from the dense product by {err:e} of its largest entry");
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    #[test]
    fn w_with_meshes_equals_dense(
        specs in prop::collection::vec((0u8..3, -3.0..3.0f64, -3.0..3.0f64, 0.5..2.0f64, prop::bool::ANY, 1e2..1e4f64, 1e6..1e9f64), 2..5),
        raw in prop::collection::vec((0usize..50, 0usize..50, 0.0..1.0f64, 0.0..std::f64::consts::TAU), 1..12),
        dt in 1e-3..0.05f64,
    ) {
        let mut bodies: Vec<Body> = specs.iter().enumerate()
            .map(|(i, &(k, x, y, s, clamp, rho, e))| body(i, k, Vec2::new(x, y), s, clamp, rho, e))
            .collect();
        // at least one mesh in every scene
        let (x, y, s) = (specs[0].1, specs[0].2, specs[0].3);
        bodies[0] = body(0, 0, Vec2::new(x, y), s, specs[0].4, specs[0].5, specs[0].6);
        let n = bodies.len();
        let contacts: Vec<_> = raw.iter().filter_map(|&(a, b, u, ang)| {
            let (a, b) = (a % n, b % n);
            (a != b).then_some((a, b, u, ang))
        }).collect();
        prop_assume!(!contacts.is_empty());
        check(&bodies, &contacts, dt)?;
    }
}
