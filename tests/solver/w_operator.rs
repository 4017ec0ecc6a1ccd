//! The contact operator W = B K̃⁻¹ Bᵀ (math note §3.1, §10.6): assembled sparse from per-cluster
//! columns, it must equal the dense product B K̃⁻¹ Bᵀ, be symmetric, and be positive
//! semidefinite (zᵀ W z = |K̃^{-1/2} Bᵀ z|² >= 0, §3.2). Random scenes of rigid disks, rings and
//! polygons with random contacts between random pairs (including fixed bodies, which carry no
//! DOF, and deformable bodies with 4 and 6 DOF), and random couplings of random pairs into
//! clusters (sparse Cholesky path; a cluster of at most 6 DOFs, such as two rigid bodies, by
//! its closed form, math note §6): a zero-length translational spring plus a bolt, spring or
//! beam of the engine (math note §6); the same scenes with every cluster, single bodies
//! included, forced through the sparse path; and the operator form (W z = B K̃⁻¹ Bᵀ z by
//! solves, with its diagonal) against the same dense product.
//! Tolerances: 1e-10 relative to the largest entry: the dense reference inverts K̃ by LU, the
//! code by Cholesky; K̃'s condition number here is at most ~1e8 (mass terms 2m/dt² against
//! springs up to 1e6), so both agree to ~1e-16 × 1e8 = 1e-8 of the largest entry of K̃⁻¹ in the
//! worst case and far better in practice; symmetry to 1e-12 (round-off of 3-term sums); the
//! smallest eigenvalue may be negative only by round-off, 1e-10 of the largest.

use nalgebra::{DMatrix, DVector, SymmetricEigen};
use pbdda::body::Body;
use pbdda::cluster::{CouplingBlock, Flexibility};
use pbdda::connector::Connector;
use pbdda::delassus;
use pbdda::dofs::DofMap;
use pbdda::geometry::{Vec2, cw};
use pbdda::jacobian::Jacobian;
use pbdda::model::{BodyModel, BodySpec, ConnectorKind, ConnectorSpec, Material, Plane, Shape};
use pbdda::vi::Operator;
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
        edge_interfaces: Vec::new(),
    }
}

prop_compose! {
    fn scene()(bodies in prop::collection::vec((0u8..3, -5.0..5.0f64, -5.0..5.0f64, 0.2..2.0f64, prop::bool::weighted(0.2), 1.0..1e4f64, prop::bool::ANY, 1e6..1e12f64), 2..8),
               contacts in prop::collection::vec((0usize..100, 0usize..100, -6.0..6.0f64, -6.0..6.0f64, 0.0..std::f64::consts::TAU), 1..15),
               springs in prop::collection::vec((0usize..100, 0usize..100, 1e2..1e6f64), 0..5),
               dt in 1e-4..0.1f64)
        -> (Vec<Body>, Vec<(usize, usize, Vec2, Vec2)>, Vec<(usize, usize, f64)>, f64) {
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
        let springs = springs.iter().filter_map(|&(a, b, k)| {
            let (a, b) = (a % n, b % n);
            (a != b).then_some((a, b, k))
        }).collect();
        (bodies, contacts, springs, dt)
    }
}

/// Stiffness blocks of a zero-length translational spring k between bodies a and b: k [I −I; −I I]
/// on the translations (u0, v0), positive semidefinite.
fn spring_blocks(bodies: &[Body], a: usize, b: usize, k: f64) -> Vec<CouplingBlock> {
    let block = |i: usize, j: usize, s: f64| {
        let mut m = DMatrix::zeros(bodies[i].ndof(), bodies[j].ndof());
        for d in 0..2.min(bodies[i].ndof()).min(bodies[j].ndof()) {
            m[(d, d)] = s * k;
        }
        CouplingBlock {
            a: i,
            b: j,
            ra: (0..bodies[i].ndof()).collect(),
            rb: (0..bodies[j].ndof()).collect(),
            block: m,
        }
    };
    vec![block(a, a, 1.0), block(b, b, 1.0), block(a, b, -1.0), block(b, a, -1.0)]
}

/// The stiffness blocks of a bolt, spring or beam (by `k`'s decade, math note §6) between bodies a
/// and b, anchored off their centroids: the connector kinds of the engine in the same clusters.
fn connector_blocks(bodies: &[Body], a: usize, b: usize, k: f64) -> Vec<CouplingBlock> {
    let kind = match (k.log10() as i64) % 3 {
        0 => ConnectorKind::Spring { stiffness: k },
        1 => ConnectorKind::Bolt { young: k, area: 1.0 },
        _ => ConnectorKind::Beam {
            young: k,
            area: 1e-2,
            inertia: 1e-5,
            shear_modulus: k / 2.6,
            shear_factor: 1.2,
        },
    };
    let points = [bodies[a].centroid + Vec2::new(0.1, 0.05), bodies[b].centroid + Vec2::new(-0.07, 0.2)];
    let spec = ConnectorSpec {
        name: "c".into(),
        kind,
        bodies: [a, b],
        points,
        pretension: 0.0,
        strength: None,
        yield_force: None,
        ultimate_strain: None,
    };
    Connector::from_spec(&spec).stiffness(bodies)
}

fn check_scene(
    bodies: &[Body],
    contacts: &[(usize, usize, Vec2, Vec2)],
    springs: &[(usize, usize, f64)],
    dt: f64,
    sparse_only: bool,
) -> Result<(), TestCaseError> {
    let pairs: Vec<(usize, usize)> = springs.iter().map(|&(a, b, _)| (a, b)).collect();
    let map = DofMap::new(bodies, &pairs);
    let couplings: Vec<CouplingBlock> = springs
        .iter()
        .filter(|&&(a, b, _)| !bodies[a].fixed && !bodies[b].fixed)
        .flat_map(|&(a, b, k)| {
            let mut blocks = spring_blocks(bodies, a, b, k);
            blocks.extend(connector_blocks(bodies, a, b, k));
            blocks
        })
        .collect();
    let mut flex = Flexibility::new(sparse_only);
    flex.refresh(&map, bodies, &couplings, dt, 0.0).expect("K̃ is SPD");
    let rows = 2 * contacts.len();
    let total = map.total();
    let mut jac = Jacobian::default();
    jac.reset(rows);
    let mut b_dense: DMatrix<f64> = DMatrix::zeros(rows, total);
    let mut k_dense: DMatrix<f64> = DMatrix::zeros(total, total);
    for (i, body) in bodies.iter().enumerate() {
        let k = body.elastic_stiffness() + body.mass_matrix() * (2.0 / (dt * dt));
        let r = map.range(i);
        for p in 0..r.len() {
            for q in 0..r.len() {
                k_dense[(r.start + p, r.start + q)] += k[(p, q)];
            }
        }
    }
    for cp in &couplings {
        let (a0, b0) = (map.range(cp.a).start, map.range(cp.b).start);
        for (p, &rp) in cp.ra.iter().enumerate() {
            for (q, &rq) in cp.rb.iter().enumerate() {
                k_dense[(a0 + rp, b0 + rq)] += cp.block[(p, q)];
            }
        }
    }
    for (k, &(a, b, x, n)) in contacts.iter().enumerate() {
        for (body, sign) in [(a, 1.0), (b, -1.0)] {
            let Some(cluster) = map.cluster_of(body) else { continue };
            let r = map.range(body);
            for (row, dir) in [(2 * k, n), (2 * k + 1, cw(n))] {
                let j = bodies[body].shape_row(x, dir) * sign;
                jac.push(row, cluster, r.start, r.len(), j);
                for c in 0..r.len() {
                    b_dense[(row, r.start + c)] += j[c];
                }
            }
        }
    }
    let w = delassus::assemble(&jac, &flex, &map).to_dense();
    // the operator form (every cluster factor-backed) applied to the unit vectors, and its diagonal
    let op = delassus::ContactOperator::new(jac.clone(), &flex, &map, 0);
    matches_w(&op, rows, |r, c| w[[r, c]], "operator")?;
    check_body_form(&jac, &flex, &map, |r, c| w[[r, c]])?;
    let kinv = k_dense.clone().lu().try_inverse().expect("K̃ invertible");
    let reference: DMatrix<f64> = &b_dense * &kinv * b_dense.transpose();
    let scale = reference.amax().max(1e-300);
    for r in 0..rows {
        for c in 0..rows {
            prop_assert!(
                (w[[r, c]] - reference[(r, c)]).abs() <= 1e-10 * scale,
                "W[{r},{c}] = {} vs {}",
                w[[r, c]],
                reference[(r, c)]
            );
            prop_assert!((w[[r, c]] - w[[c, r]]).abs() <= 1e-12 * scale);
        }
    }
    let eig = SymmetricEigen::new(reference.clone());
    prop_assert!(eig.eigenvalues.min() >= -1e-10 * scale, "min eigenvalue {}", eig.eigenvalues.min());
    Ok(())
}

/// `op` applied to the unit vectors, and its diagonal, against W within 1e-10 of W's largest entry.
fn matches_w(
    op: &delassus::ContactOperator,
    rows: usize,
    w: impl Fn(usize, usize) -> f64,
    form: &str,
) -> Result<(), TestCaseError> {
    let scale = (0..rows)
        .flat_map(|r| (0..rows).map(move |c| (r, c)))
        .fold(1e-300f64, |m, (r, c)| m.max(w(r, c).abs()));
    let mut diag = vec![0.0; rows];
    op.diagonal(&mut diag);
    for c in 0..rows {
        let mut e = vec![0.0; rows];
        e[c] = 1.0;
        let mut col = vec![0.0; rows];
        op.apply(&e, &mut col);
        for (r, x) in col.iter().enumerate() {
            prop_assert!((x - w(r, c)).abs() <= 1e-10 * scale, "{form} W[{r},{c}] = {x} vs {}", w(r, c));
        }
        prop_assert!((diag[c] - w(c, c)).abs() <= 1e-10 * scale, "{form} diagonal {c}");
    }
    Ok(())
}

/// W of `jac` with every single body in body form, as the world's rows build it.
fn body_form(jac: &Jacobian, flex: &Flexibility, map: &DofMap) -> delassus::ContactOperator {
    delassus::ContactOperator::with_scratch(jac.clone(), flex, map, usize::MAX, true, &mut Default::default())
}

/// The body form (math note §3.3: single bodies applied through K̃_c⁻¹, the rest explicit)
/// against the assembled W: products with the unit vectors and the diagonal within 1e-10 of W's
/// largest entry (the same sums in another order, ~1e-16 each); its row bounds of Ŵ = S W S
/// (S = diag(W)^{-1/2}, the solver's scaling): xᵀ Ŵ x <= Σ_r out_r x_r² for random x, and so
/// ‖Ŵ‖ <= max_r out_r, less round-off (1e-10 of Ŵ's unit diagonal scale); its entries over a
/// subset of the rows.
fn check_body_form(
    jac: &Jacobian,
    flex: &Flexibility,
    map: &DofMap,
    w: impl Fn(usize, usize) -> f64,
) -> Result<(), TestCaseError> {
    let rows = jac.rows;
    let op = body_form(jac, flex, map);
    matches_w(&op, rows, &w, "body form")?;
    let sc: Vec<f64> = (0..rows).map(|r| if w(r, r) > 0.0 { 1.0 / w(r, r).sqrt() } else { 1.0 }).collect();
    let hat = DMatrix::from_fn(rows, rows, |r, c| sc[r] * w(r, c) * sc[c]);
    let mut bound = vec![0.0; rows];
    prop_assert!(op.row_bounds(&sc, &mut bound));
    let tol = 1e-10 * hat.amax().max(1.0);
    for k in 0..5 {
        let x = DVector::from_fn(rows, |r, _| ((r * 7 + k * 13) % 11) as f64 - 5.0);
        let quad = x.dot(&(&hat * &x));
        let weighted: f64 = (0..rows).map(|r| bound[r] * x[r] * x[r]).sum();
        prop_assert!(quad <= weighted + tol * x.norm_squared(), "xᵀŴx {quad} > Σ out x² {weighted}");
    }
    let largest = SymmetricEigen::new(hat).eigenvalues.max();
    prop_assert!(
        largest <= bound.iter().fold(0.0f64, |a, b| a.max(*b)) + tol,
        "‖Ŵ‖ {largest} above the bound"
    );
    // its entries in the rows and columns kept (every third row left out), summed: W's there,
    // to the same 1e-10 (math note §4.10: MPRGP's face solves factorize them)
    let keep: Vec<bool> = (0..rows).map(|r| r % 3 != 1).collect();
    let mut entries = Vec::new();
    prop_assert!(op.entries(&keep, &mut entries));
    let mut dense = vec![0.0; rows * rows];
    for (r, c, v) in entries {
        prop_assert!(keep[r] && keep[c], "entry ({r}, {c}) of a row left out");
        dense[r * rows + c] += v;
    }
    let scale = (0..rows * rows).fold(1e-300f64, |m, k| m.max(w(k / rows, k % rows).abs()));
    for (k, x) in dense.iter().enumerate() {
        let (r, c) = (k / rows, k % rows);
        let want = if keep[r] && keep[c] { w(r, c) } else { 0.0 };
        prop_assert!((x - want).abs() <= 1e-10 * scale, "entry ({r}, {c}) = {x} vs {want}");
    }
    Ok(())
}

/// Seven rigid disks in a hexagonal cluster, every touching pair a contact (6 spokes, 6 rims).
fn hexagon(fixed_rim: bool) -> (Vec<Body>, DofMap, Flexibility, Jacobian) {
    let material = Material { name: "m".into(), density: 2.0, young: Some(1e8), poisson: Some(0.3) };
    let mut centres = vec![Vec2::zeros()];
    centres.extend((0..6).map(|k| {
        let a = std::f64::consts::FRAC_PI_3 * k as f64;
        Vec2::new(a.cos(), a.sin())
    }));
    let bodies: Vec<Body> = (centres.iter().enumerate())
        .map(|(i, c)| {
            Body::new(&spec(i, 0, c.x, c.y, 0.5, fixed_rim && i > 0, false), &material, Plane::Stress)
        })
        .collect();
    let map = DofMap::new(&bodies, &[]);
    let mut flex = Flexibility::new(false);
    flex.refresh(&map, &bodies, &[], 0.01, 0.0).expect("K̃ is SPD");
    let mut jac = Jacobian::default();
    let mut pairs = vec![];
    for a in 0..7 {
        for b in a + 1..7 {
            if ((centres[a] - centres[b]).norm() - 1.0).abs() < 1e-9 {
                pairs.push((a, b));
            }
        }
    }
    assert_eq!(pairs.len(), 12, "6 spokes and 6 rim contacts");
    jac.reset(2 * pairs.len());
    for (k, &(a, b)) in pairs.iter().enumerate() {
        let n = (centres[a] - centres[b]).normalize();
        let x = centres[b] + 0.5 * n;
        for (body, sign) in [(a, 1.0), (b, -1.0)] {
            let Some(cluster) = map.cluster_of(body) else { continue };
            let r = map.range(body);
            for (row, dir) in [(2 * k, n), (2 * k + 1, cw(n))] {
                jac.push(row, cluster, r.start, r.len(), bodies[body].shape_row(x, dir) * sign);
            }
        }
    }
    (bodies, map, flex, jac)
}

/// The largest eigenvalue of Ŵ = S W S (S = diag(W)^{-1/2} where W_rr > 0), the body form's row
/// bounds of it, and Gershgorin's bound of Ŵ.
fn scaled_norm_and_bounds(map: &DofMap, flex: &Flexibility, jac: &Jacobian) -> (f64, Vec<f64>, f64) {
    let w = delassus::assemble(jac, flex, map).to_dense();
    let rows = jac.rows;
    let sc: Vec<f64> =
        (0..rows).map(|r| if w[[r, r]] > 0.0 { 1.0 / w[[r, r]].sqrt() } else { 1.0 }).collect();
    let hat = DMatrix::from_fn(rows, rows, |r, c| sc[r] * w[[r, c]] * sc[c]);
    let gershgorin = hat.row_iter().map(|r| r.iter().map(|x| x.abs()).sum::<f64>()).fold(0.0, f64::max);
    let op = body_form(jac, flex, map);
    let mut bound = vec![0.0; rows];
    assert!(op.row_bounds(&sc, &mut bound));
    (SymmetricEigen::new(hat).eigenvalues.max(), bound, gershgorin)
}

/// MPRGP's step length comes from the body form's row bounds (math note §3.3, §4.8). For one free
/// body the bound is exact: every row touches the central disk only (its six neighbours fixed),
/// so Ŵ is that body's block and the bound is its largest eigenvalue, computed in closed form
/// for 3 DOFs: equal to the dense eigenvalue of the assembled Ŵ to 1e-12 (round-off of the two
/// eigen-solvers on a matrix with unit diagonal).
#[test]
fn body_form_bound_is_the_norm_of_one_body() {
    let (_, map, flex, jac) = hexagon(true);
    let (norm, bound, _) = scaled_norm_and_bounds(&map, &flex, &jac);
    let (spokes, rims) = (&bound[..12], &bound[12..]);
    assert!(spokes.iter().all(|b| (b - norm).abs() <= 1e-12 * norm), "bounds {spokes:?} vs ‖Ŵ‖ {norm}");
    assert!(rims.iter().all(|&b| b == 0.0), "rows between fixed disks carry no bound: {rims:?}");
}

/// All seven disks free: each row's bound is the sum of its two bodies' block eigenvalues, at
/// least ‖Ŵ‖ (the rows of the busiest bodies reach it) and below Gershgorin's bound of the same
/// Ŵ, which the body form used before (its per-pair absolute values add up sign-cancelling terms).
#[test]
fn body_form_bound_lies_between_the_norm_and_gershgorin() {
    let (_, map, flex, jac) = hexagon(false);
    let (norm, bound, gershgorin) = scaled_norm_and_bounds(&map, &flex, &jac);
    let top = bound.iter().fold(0.0f64, |a, b| a.max(*b));
    assert!(norm <= top * (1.0 + 1e-12), "‖Ŵ‖ {norm} above the bound {top}");
    assert!(top < gershgorin, "bound {top} not below Gershgorin's {gershgorin}");
}

/// W's columns (products with the unit vectors) and diagonal, as computed: for bit-for-bit checks.
fn columns(op: &delassus::ContactOperator, rows: usize) -> Vec<f64> {
    let mut out = vec![0.0; rows * (rows + 1)];
    for (c, col) in out.chunks_mut(rows).take(rows).enumerate() {
        let mut e = vec![0.0; rows];
        e[c] = 1.0;
        op.apply(&e, col);
    }
    op.diagonal(&mut out[rows * rows..]);
    out
}

/// The body form keeps its packed blocks (K̃_c⁻¹ and R_c per body) in the scratch across steps
/// while the factors stay the same (math note §3.3). An operator built on kept blocks must give
/// exactly, bit for bit, what one built on fresh blocks gives: with the same factors (kept), and
/// after every factor changed with a new step length (K̃ = K + 2M/dt², rebuilt), where a
/// kept stale block would give dt = 0.01's W, a factor 4 off.
#[test]
fn body_form_keeps_its_blocks_only_while_the_factors_stay() {
    let (bodies, map, mut flex, jac) = hexagon(false);
    let rows = jac.rows;
    let mut scratch = delassus::Scratch::default();
    let mut kept = |flex: &Flexibility| {
        let op =
            delassus::ContactOperator::with_scratch(jac.clone(), flex, &map, usize::MAX, true, &mut scratch);
        columns(&op, rows)
    };
    let first = kept(&flex);
    assert_eq!(kept(&flex), first, "same factors, kept blocks");
    flex.refresh(&map, &bodies, &[], 0.02, 0.0).expect("K̃ is SPD");
    let fresh = columns(&body_form(&jac, &flex, &map), rows);
    assert_ne!(fresh, first, "a new step length changes W");
    assert_eq!(kept(&flex), fresh, "new factors, new blocks");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, rng_seed: proptest::test_runner::RngSeed::Fixed(20261123), ..ProptestConfig::default() })]
    #[test]
    fn w_is_b_kinv_bt_symmetric_psd((bodies, contacts, springs, dt) in scene()) {
        prop_assume!(!contacts.is_empty());
        check_scene(&bodies, &contacts, &springs, dt, false)?;
    }

    #[test]
    fn sparse_path_gives_the_same_w((bodies, contacts, springs, dt) in scene()) {
        prop_assume!(!contacts.is_empty());
        check_scene(&bodies, &contacts, &springs, dt, true)?;
    }
}
