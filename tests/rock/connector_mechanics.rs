//! Connector mechanics at the matrix level (`pbdda::connector`, math note §6), without a World:
//! stiffness blocks assembled into a dense K by the test, solved with nalgebra, and compared with
//! closed forms cited in each test. Bodies: rigid disk (3 DOF), deformable disk (4 DOF),
//! deformable block (6 DOF), fixed block (0 DOF).

use nalgebra::{DMatrix, DVector};
use pbdda::body::{Body, Dofs};
use pbdda::connector::{Connector, ConnectorKind};
use pbdda::geometry::Vec2;
use pbdda::model::{BodyModel, BodySpec, ConnectorSpec, Material, Plane, Shape};

const E: f64 = 2.0e11;
const AREA: f64 = 0.01;
const INERTIA: f64 = 8.0e-6;
const G: f64 = 8.0e10;

fn v(x: f64, y: f64) -> Vec2 {
    Vec2::new(x, y)
}

fn body(shape: Shape, model: BodyModel, fixed: bool) -> Body {
    let spec = BodySpec::at_rest("b", shape, model, fixed);
    let material = Material { name: "m".into(), density: 1000.0, young: Some(1.0e9), poisson: Some(0.25) };
    Body::new(&spec, &material, Plane::Stress)
}

fn disk(c: Vec2, r: f64, model: BodyModel) -> Body {
    body(Shape::Disk { center: c, radius: r }, model, false)
}

fn block(c: Vec2, half: f64, model: BodyModel, fixed: bool) -> Body {
    let vertices = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
        .iter()
        .map(|&(x, y)| c + v(x * half, y * 0.7 * half))
        .collect();
    body(Shape::Polygon { vertices }, model, fixed)
}

fn spring(k: f64) -> ConnectorKind {
    ConnectorKind::Spring { stiffness: k }
}

fn bolt() -> ConnectorKind {
    ConnectorKind::Bolt { young: E, area: AREA }
}

fn beam(shear_factor: f64) -> ConnectorKind {
    ConnectorKind::Beam { young: E, area: AREA, inertia: INERTIA, shear_modulus: G, shear_factor }
}

fn connector(kind: ConnectorKind, bodies: [usize; 2], points: [Vec2; 2], pretension: f64) -> Connector {
    let spec = ConnectorSpec {
        name: "c".into(),
        kind,
        bodies,
        points,
        pretension,
        strength: None,
        yield_force: None,
        ultimate_strain: None,
    };
    Connector::from_spec(&spec)
}

/// Offset of each body's DOFs in the global vector (fixed bodies have none).
fn offsets(bodies: &[Body]) -> Vec<usize> {
    bodies.iter().scan(0, |o, b| Some(std::mem::replace(o, *o + b.ndof()))).collect()
}

/// Dense global K of the connectors alone, from their stiffness blocks.
fn assemble(bodies: &[Body], connectors: &[Connector]) -> DMatrix<f64> {
    let off = offsets(bodies);
    let n: usize = bodies.iter().map(Body::ndof).sum();
    let mut k = DMatrix::zeros(n, n);
    for c in connectors {
        for cp in c.stiffness(bodies) {
            assert_eq!((cp.block.nrows(), cp.block.ncols()), (cp.ra.len(), cp.rb.len()));
            for (i, &ri) in cp.ra.iter().enumerate() {
                for (j, &rj) in cp.rb.iter().enumerate() {
                    k[(off[cp.a] + ri, off[cp.b] + rj)] += cp.block[(i, j)];
                }
            }
        }
    }
    k
}

/// Body b's slice of a global DOF vector, padded.
fn dofs_of(bodies: &[Body], global: &DVector<f64>, b: usize) -> Dofs {
    let off = offsets(bodies);
    let mut d = Dofs::zeros();
    for k in 0..bodies[b].ndof() {
        d[k] = global[off[b] + k];
    }
    d
}

/// DOF i of body b in a global DOF vector, as `Connector::update` takes it.
fn dof_at<'a>(bodies: &'a [Body], global: &'a DVector<f64>) -> impl Fn(usize, usize) -> f64 + 'a {
    let off = offsets(bodies);
    move |b, i| global[off[b] + i]
}

/// The linearized rigid motion `u(x) = t + θ × (x − c)` in each body's DOFs: translation of the
/// centroid `t + θ perp(c_b − c)`, rotation θ, zero strain (paper eqs. 3, 5, 7).
fn rigid_motion(bodies: &[Body], t: Vec2, theta: f64, c: Vec2) -> DVector<f64> {
    let mut d = Vec::new();
    for b in bodies.iter().filter(|b| !b.fixed) {
        let r = b.centroid - c;
        let mut db = vec![t.x - theta * r.y, t.y + theta * r.x, theta];
        db.resize(b.ndof(), 0.0);
        d.extend(db);
    }
    DVector::from_vec(d)
}

/// Rigid-body invariance (math note §6): every connector kind between every pair of body kinds
/// has `K d_rigid = 0` for the linearized rigid motion, because e(d_rigid) = 0 exactly: the
/// elongation `lᵀ θ perp(x2 − x1)` is zero along the line, `u2 − u1 = 0` for a zero-length
/// spring, and the beam matrix annihilates `(u1, θ, u1 + θ perp(x2 − x1), θ)` with ccw rotations
/// (the printed eq. 88 fails this: typo 12). Tolerance 1e-9 |K| |d| per the issue; round-off in
/// K d is ~1e-16 |K| |d|.
#[test]
fn rigid_motion_of_any_connected_pair_carries_no_force() {
    let models = [
        (BodyModel::Rigid, false),
        (BodyModel::Deformable, false),
        (BodyModel::Deformable, true), // block
    ];
    let kinds = [spring(3.0e7), bolt(), beam(1.2), beam(0.0)];
    let mut checked = 0;
    for &(m1, block1) in &models {
        for &(m2, block2) in &models {
            let c1 = v(0.0, 0.0);
            let c2 = v(3.0, 1.0);
            let b1 = if block1 { block(c1, 1.0, m1, false) } else { disk(c1, 1.0, m1) };
            let b2 = if block2 { block(c2, 1.0, m2, false) } else { disk(c2, 1.0, m2) };
            let bodies = [b1, b2];
            let anchors = [[v(0.4, 0.3), v(2.5, 0.8)], [v(0.5, 0.5), v(0.5, 0.5)]];
            for kind in kinds {
                for points in anchors {
                    if points[0] == points[1] && !matches!(kind, ConnectorKind::Spring { .. }) {
                        continue; // zero length: springs only
                    }
                    let k = assemble(&bodies, &[connector(kind, [0, 1], points, 0.0)]);
                    let d = rigid_motion(&bodies, v(0.3, -0.2), 1.0, v(1.0, -0.5));
                    let residual = (&k * &d).norm();
                    assert!(k.norm() > 0.0);
                    assert!(
                        residual <= 1e-9 * k.norm() * d.norm(),
                        "{kind:?} {m1:?}/{m2:?}: |K d| = {residual:e}, |K| = {:e}",
                        k.norm()
                    );
                    checked += 1;
                }
            }
        }
    }
    assert_eq!(checked, 9 * 5);
}

/// Shear parameter b of eq. 89 with k_Be = shear_factor: 12 EI k_Be / (G A l²).
fn tip_deflection(p: f64, l: f64, shear_factor: f64) -> f64 {
    // Timoshenko cantilever: P L³/(3EI) + k_Be P L/(G A)
    p * l.powi(3) / (3.0 * E * INERTIA) + shear_factor * p * l / (G * AREA)
}

/// Cantilever (one beam, fixed root, light free rigid tip body, tip load P perpendicular to the
/// axis): tip deflection P L³/(3EI) + k_Be P L/(GA) and tip rotation −P L²/(2EI) (clockwise for a
/// load along the axis turned clockwise): the 2-node Timoshenko element is exact for end loads.
/// The axis is tilted 30° and the anchor is off the tip body's centroid, so T and the rotation
/// into the axis are exercised. Tolerance 1e-10 relative: a 3×3 solve of a matrix with
/// condition number ~1e6 loses ~1e-10 at worst.
#[test]
fn cantilever_beam_tip_deflection_and_rotation() {
    for shear_factor in [0.0, 1.2, 10.0 / 9.0] {
        let l = 2.0;
        let axis = v(30f64.to_radians().cos(), 30f64.to_radians().sin());
        let root = v(1.0, 0.0);
        let tip = root + axis * l;
        let bodies = [
            block(v(0.0, 0.0), 1.0, BodyModel::Rigid, true),
            disk(tip + v(0.05, 0.02), 0.1, BodyModel::Rigid),
        ];
        let c = connector(beam(shear_factor), [0, 1], [root, tip], 0.0);
        let k = assemble(&bodies, std::slice::from_ref(&c));
        let p = 1.0e4;
        let n = v(axis.y, -axis.x); // axis turned clockwise
        let f = bodies[1].shape_row(tip, n * p);
        let f = DVector::from_column_slice(&f.as_slice()[..3]);
        let d = k.clone().lu().solve(&f).expect("the cantilever is supported");
        let dt = dofs_of(&bodies, &d, 1);
        let u = bodies[1].displacement(tip, &dt);
        let expected = tip_deflection(p, l, shear_factor);
        assert!((n.dot(&u) - expected).abs() <= 1e-10 * expected, "{} vs {expected}", n.dot(&u));
        assert!(axis.dot(&u).abs() <= 1e-10 * expected, "no axial motion: {}", axis.dot(&u));
        let rotation = -p * l * l / (2.0 * E * INERTIA);
        assert!((dt[2] - rotation).abs() <= 1e-10 * rotation.abs(), "{} vs {rotation}", dt[2]);
    }
}

/// Ten beams in a row across eleven bodies (body 0 fixed), tip load P at the free end: the
/// Timoshenko elements are exact, so the tip deflection is P L³/(3EI) + k_Be P L/(GA) and the
/// tip rotation −P L²/(2EI) for the whole length L; the root beam's end moment on the fixed body
/// is −P L (clockwise for a downward load on a beam pointing +x), its shear force on end 2 is −P
/// and its axial force 0 (statics of the cantilever). The ten free bodies are rigid disks,
/// deformable disks (4 DOF) or deformable blocks (6 DOF), anchored at their centroids, where the
/// strain DOFs do not move the anchor: the bodies' own elastic stiffness is added (it keeps K
/// regular and leaves the beam solution unchanged, strain 0). Dense solve; tolerance 1e-10
/// relative (condition number ≤ ~1e9: the largest solution entries lose ≤ ~1e-12).
#[test]
fn chain_of_ten_beams_is_a_cantilever() {
    let (l, n, p) = (5.0, 10, 2.0e3);
    let h = l / n as f64;
    let makers: [(&str, &dyn Fn(Vec2) -> Body); 3] = [
        ("rigid disks", &|c| disk(c, 0.1 * h, BodyModel::Rigid)),
        ("deformable disks", &|c| disk(c, 0.1 * h, BodyModel::Deformable)),
        ("deformable blocks", &|c| block(c, 0.1 * h, BodyModel::Deformable, false)),
    ];
    for (what, make) in makers {
        let mut bodies = vec![block(v(-1.0, 0.0), 1.0, BodyModel::Rigid, true)];
        bodies.extend((1..=n).map(|k| make(v(k as f64 * h, 0.0))));
        let mut connectors: Vec<Connector> = (1..=n)
            .map(|k| {
                connector(beam(1.2), [k - 1, k], [v((k - 1) as f64 * h, 0.0), v(k as f64 * h, 0.0)], 0.0)
            })
            .collect();
        let mut k = assemble(&bodies, &connectors);
        let off = offsets(&bodies);
        for (b, body) in bodies.iter().enumerate() {
            let m = body.ndof();
            let mut view = k.view_mut((off[b], off[b]), (m, m));
            view += body.elastic_stiffness().view((0, 0), (m, m));
        }
        let mut f = DVector::zeros(k.nrows());
        f[off[n] + 1] = -p;
        let d = k.clone().lu().solve(&f).expect("the chain is supported");
        let tip = dofs_of(&bodies, &d, n);
        let expected = tip_deflection(p, l, 1.2);
        assert!((-tip[1] - expected).abs() <= 1e-10 * expected, "{what}: {} vs {expected}", -tip[1]);
        let rotation = -p * l * l / (2.0 * E * INERTIA);
        assert!((tip[2] - rotation).abs() <= 1e-10 * rotation.abs(), "{what}: {} vs {rotation}", tip[2]);
        let by_body = dof_at(&bodies, &d);
        for c in &mut connectors {
            c.update(&bodies, &by_body);
        }
        let root = &connectors[0];
        let moments = root.end_moments().expect("a beam has end moments");
        assert!((moments[0] + p * l).abs() <= 1e-10 * p * l, "{what}: root moment {}", moments[0]);
        let shear = root.shear_force().expect("a beam has a shear force");
        assert!((shear + p).abs() <= 1e-10 * p, "{what}: shear {shear}");
        assert!(root.axial_force().abs() <= 1e-10 * p, "{what}: axial {}", root.axial_force());
    }
}

/// A bolt's stiffness on the free body (anchor at its centroid, fixed far end): the 3×3 block is
/// (EA/l) [l lᵀ, 0; 0, 0] (eqs. 75-84), so the stiffness is EA/l along the bolt and 0 across it
/// and in rotation. Tolerance 1e-12 relative: a handful of products.
#[test]
fn bolt_is_stiff_along_its_line_only() {
    let l = 1.5;
    let axis = v(0.6, 0.8);
    let a1 = v(0.5, 0.3);
    let a2 = a1 + axis * l;
    let bodies = [block(v(0.0, 0.0), 1.0, BodyModel::Rigid, true), disk(a2, 0.2, BodyModel::Rigid)];
    let k = assemble(&bodies, &[connector(bolt(), [0, 1], [a1, a2], 0.0)]);
    let ea_l = E * AREA / l;
    let along = DVector::from_column_slice(&[axis.x, axis.y, 0.0]);
    let across = DVector::from_column_slice(&[-axis.y, axis.x, 0.0]);
    let spin = DVector::from_column_slice(&[0.0, 0.0, 1.0]);
    assert!(((&along.transpose() * &k * &along)[0] - ea_l).abs() <= 1e-12 * ea_l);
    assert!((&k * &across).norm() <= 1e-12 * ea_l);
    assert!((&k * &spin).norm() <= 1e-12 * ea_l);
}

/// A block hanging from a fixed ceiling by a vertical spring attached above its centroid: the
/// spring's K on the block has rank 1 (vertical), and the minimum-norm solution of K d = m g is
/// a drop of exactly m g / k, no sway or spin (Hooke). After `update` the spring carries tension
/// m g and its carried load on the block is +m g upward, balancing the weight.
/// Tolerance 1e-10 relative: SVD pseudo-inverse of a 3×3.
#[test]
fn spring_hanging_a_block_extends_by_mg_over_k() {
    let k_spring = 4.0e5;
    let hanging = block(v(0.0, -3.0), 0.5, BodyModel::Rigid, false);
    let top = v(0.0, -3.0 + 0.35);
    let bodies = [block(v(0.0, 1.0), 2.0, BodyModel::Rigid, true), hanging];
    let mut c = connector(spring(k_spring), [0, 1], [v(0.0, 0.0), top], 0.0);
    let k = assemble(&bodies, std::slice::from_ref(&c));
    let mg = bodies[1].mass * 10.0;
    let f = DVector::from_column_slice(&[0.0, -mg, 0.0]);
    let d = k.clone().pseudo_inverse(1e-12 * k.norm()).expect("svd") * f;
    let drop = mg / k_spring;
    assert!((d[1] + drop).abs() <= 1e-10 * drop, "{} vs {}", -d[1], drop);
    assert!(d[0].abs() <= 1e-10 * drop && d[2].abs() <= 1e-10 * drop);
    c.update(&bodies, &dof_at(&bodies, &d));
    assert!((c.axial_force() - mg).abs() <= 1e-10 * mg);
    let loads = c.carried_load(&bodies);
    assert_eq!(loads.len(), 1, "the fixed ceiling gets nothing");
    assert_eq!(loads[0].0, 1);
    assert!((loads[0].2[1] - mg).abs() <= 1e-10 * mg && loads[0].2[0].abs() <= 1e-10 * mg);
}

/// Carried force round trip (math note §6): starting from no force, `update` with an increment
/// d and then `carried_load` gives the force the connector exerts on the bodies, −K d, for
/// every kind on every pair of body kinds; a pretension P0 adds `T_1ᵀ l P0` and `−T_2ᵀ l P0`.
/// Tolerance 1e-12 relative: the same products in a different order.
#[test]
fn carried_force_round_trip() {
    let pairs = [
        [disk(v(0.0, 0.0), 1.0, BodyModel::Rigid), block(v(3.0, 1.0), 1.0, BodyModel::Deformable, false)],
        [disk(v(0.0, 0.0), 1.0, BodyModel::Deformable), disk(v(3.0, 1.0), 1.0, BodyModel::Rigid)],
        [
            block(v(0.0, 0.0), 1.0, BodyModel::Deformable, false),
            block(v(3.0, 1.0), 1.0, BodyModel::Rigid, true),
        ],
    ];
    let d_all = DVector::from_fn(12, |i, _| ((i * 7 + 3) % 5) as f64 * 1e-4 - 2e-4);
    for bodies in &pairs {
        for (kind, points) in [
            (spring(3.0e7), [v(0.4, 0.3), v(2.5, 0.8)]),
            (spring(3.0e7), [v(0.5, 0.5), v(0.5, 0.5)]),
            (bolt(), [v(0.4, 0.3), v(2.5, 0.8)]),
            (beam(1.2), [v(0.4, 0.3), v(2.5, 0.8)]),
        ] {
            let mut c = connector(kind, [0, 1], points, 0.0);
            let k = assemble(bodies, std::slice::from_ref(&c));
            let d = d_all.rows(0, k.nrows()).into_owned();
            let kd = &k * &d;
            c.update(bodies, &dof_at(bodies, &d));
            let mut carried = DVector::zeros(k.nrows());
            let off = offsets(bodies);
            for (b, cols, f) in c.carried_load(bodies) {
                for (k, &i) in cols.iter().enumerate() {
                    carried[off[b] + i] += f[k];
                }
            }
            let err = (&carried + &kd).norm();
            assert!(kd.norm() > 0.0 && err <= 1e-12 * kd.norm(), "{kind:?}: {err:e} of {:e}", kd.norm());
        }
    }
    // pretension: a bolt along x between two rigid disks, anchored at their centroids
    let bodies = [disk(v(0.0, 0.0), 0.5, BodyModel::Rigid), disk(v(2.0, 0.0), 0.5, BodyModel::Rigid)];
    let p0 = 5.0e4;
    let c = connector(bolt(), [0, 1], [v(0.0, 0.0), v(2.0, 0.0)], p0);
    let loads = c.carried_load(&bodies);
    assert_eq!(loads[0].2.as_slice()[..3], [p0, 0.0, 0.0]);
    assert_eq!(loads[1].2.as_slice()[..3], [-p0, 0.0, 0.0]);
}

/// Strength (math note §6): a bolt stretched beyond its strength reports it; once broken it has
/// no stiffness and carries nothing. Tension = EA/l · δ for an elongation δ of the free anchor.
#[test]
fn bolt_beyond_its_strength_breaks_for_good() {
    let bodies = [block(v(0.0, 0.0), 1.0, BodyModel::Rigid, true), disk(v(2.0, 0.0), 0.2, BodyModel::Rigid)];
    let spec = ConnectorSpec {
        name: "b".into(),
        kind: bolt(),
        bodies: [0, 1],
        points: [v(1.0, 0.0), v(2.0, 0.0)],
        pretension: 0.0,
        strength: Some(1.0e6),
        yield_force: None,
        ultimate_strain: None,
    };
    let mut c = Connector::from_spec(&spec);
    let delta = |x: f64| move |_: usize, i: usize| if i == 0 { x } else { 0.0 };
    c.update(&bodies, &delta(0.9e6 / (E * AREA)));
    assert!((c.axial_force() - 0.9e6).abs() <= 1e-9 * 0.9e6);
    assert!(!c.exceeds_strength());
    c.update(&bodies, &delta(0.2e6 / (E * AREA)));
    assert!(c.exceeds_strength());
    c.break_off();
    assert!(!c.exceeds_strength());
    assert!(c.stiffness(&bodies).is_empty() && c.carried_load(&bodies).is_empty());
}

/// Anchors are material points (math note §6): after a rigid rotation of π/2 about the body's
/// centroid (the exact map of paper eq. 16) the anchor is rotated about the centroid, and a
/// bolt's tension is unchanged by the rigid motion (first-order increment lᵀθ perp(x2 − x1) = 0).
#[test]
fn anchors_move_with_their_bodies() {
    let bodies = [disk(v(0.0, 0.0), 1.0, BodyModel::Rigid), disk(v(3.0, 0.0), 1.0, BodyModel::Rigid)];
    let mut c = connector(bolt(), [0, 1], [v(0.5, 0.0), v(2.5, 0.0)], 100.0);
    let d = rigid_motion(&bodies, Vec2::zeros(), std::f64::consts::FRAC_PI_2, v(1.5, 0.0));
    let by_body = dof_at(&bodies, &d);
    c.update(&bodies, &by_body);
    assert!((c.axial_force() - 100.0).abs() <= 1e-12 * 100.0);
    let single = |b: usize, i: usize| if i < 2 { 0.0 } else { by_body(b, i) };
    c.move_anchors(&bodies, &single);
    assert!((c.anchors[0] - v(0.0, 0.5)).norm() < 1e-15);
    assert!((c.anchors[1] - v(3.0, -0.5)).norm() < 1e-15);
}
