//! Tri3 element kernels, sparse assembly and boundary loops (math note §9.1, §9.2, §9.5) on the
//! committed gmsh meshes of `meshes/`. References: rigid-body modes of a small-strain element (zero
//! strain), the patch test (a linear field is reproduced exactly by linear elements), the mass and
//! load resultants (integrals of a constant), and the column under self-weight (closed form, §9.5).

use std::path::Path;

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use pbdda::body::constitutive;
use pbdda::geometry::Vec2;
use pbdda::mesh::Mesh;
use pbdda::mesh::loops::{BoundaryLoop, LoopError, boundary_loops};
use pbdda::mesh::tri3::{Pattern, Tri3, gather};
use pbdda::model::Plane;

fn read(name: &str) -> Mesh {
    Mesh::read(&Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes").join(name)).unwrap()
}

fn area(mesh: &Mesh) -> f64 {
    mesh.triangles.iter().map(|&t| Tri3::of(&mesh.nodes, t).area).sum()
}

/// Global K (no fixed nodes) as a dense matrix, for the small meshes of these tests.
fn dense_k(mesh: &Mesh, d: &Matrix3<f64>) -> (Pattern, DMatrix<f64>) {
    let p = Pattern::new(mesh.nodes.len(), &mesh.triangles, &[]);
    let mut v = vec![0.0; p.nnz()];
    p.assemble(&mut v, |e| Tri3::of(&mesh.nodes, mesh.triangles[e]).stiffness(d));
    let k = p.matrix(v).to_dense();
    let dense = DMatrix::from_fn(p.n_dof, p.n_dof, |i, j| k[[i, j]]);
    (p, dense)
}

/// Solves K u = f with the DOFs in `fixed` prescribed to `u[fixed]` (dense Cholesky on the rest).
fn solve_prescribed(k: &DMatrix<f64>, f: &[f64], u: &mut [f64], fixed: &[bool]) {
    let free: Vec<usize> = (0..u.len()).filter(|&i| !fixed[i]).collect();
    let kff = DMatrix::from_fn(free.len(), free.len(), |a, b| k[(free[a], free[b])]);
    let rhs = DVector::from_fn(free.len(), |a, _| {
        f[free[a]] - (0..u.len()).filter(|&j| fixed[j]).map(|j| k[(free[a], j)] * u[j]).sum::<f64>()
    });
    let x = kff.cholesky().expect("K_ff is positive definite once rigid modes are fixed").solve(&rhs);
    free.iter().enumerate().for_each(|(a, &i)| u[i] = x[a]);
}

/// Rigid-body modes (translations and the linearised rotation u = (-y, x)) have zero strain, so
/// K u = 0 to round-off: |K u| <= 1e-12 |K|_F |u| per element and for the assembled K (the bound
/// is round-off of sums of O(|K|) terms, far above 1e-16 yet far below any real strain energy).
#[test]
fn rigid_body_modes_give_zero_force() {
    for (name, plane) in [("hertz.msh", Plane::Stress), ("hole.msh", Plane::Strain)] {
        let mesh = read(name);
        let d = constitutive(2.0e10, 0.3, plane);
        let modes = |p: Vec2| [(1.0, 0.0), (0.0, 1.0), (-p.y, p.x)];
        for &t in &mesh.triangles {
            let ke = Tri3::of(&mesh.nodes, t).stiffness(&d);
            for m in 0..3 {
                let u = pbdda::mesh::tri3::Vec6::from_fn(|k, _| {
                    let v = modes(mesh.nodes[t[k / 2]])[m];
                    if k % 2 == 0 { v.0 } else { v.1 }
                });
                assert!((ke * u).norm() <= 1e-12 * ke.norm() * u.norm(), "{name}: element mode {m}");
            }
        }
        let (_, k) = dense_k(&mesh, &d);
        for m in 0..3 {
            let u = DVector::from_fn(k.nrows(), |i, _| {
                let v = modes(mesh.nodes[i / 2])[m];
                if i % 2 == 0 { v.0 } else { v.1 }
            });
            assert!((&k * &u).norm() <= 1e-12 * k.norm() * u.norm(), "{name}: global mode {m}");
        }
    }
}

/// Patch test: boundary nodes (from the boundary loops) prescribed to a linear field
/// u = (a + b x + c y, d + e x + f y); the interior solved with no load. Linear elements reproduce
/// it exactly, so every element has strain (b, f, c + e) and stress D of it, and every interior node
/// the linear field, to round-off (1e-10 relative: conditioning of a ~1000-DOF solve times 1e-16).
#[test]
fn patch_test_on_unstructured_meshes() {
    let field = |p: Vec2| (1e-3 + 2e-3 * p.x - 1e-3 * p.y, -2e-3 + 0.5e-3 * p.x - 3e-3 * p.y);
    let exact_strain = Vector3::new(2e-3, -3e-3, -1e-3 + 0.5e-3);
    for name in ["square.msh", "hole.msh"] {
        let mesh = read(name);
        let d = constitutive(3.0e9, 0.3, Plane::Strain);
        let (_, k) = dense_k(&mesh, &d);
        let loops = boundary_loops(&mesh.nodes, &mesh.triangles).unwrap();
        let mut fixed = vec![false; k.nrows()];
        let mut u = vec![0.0; k.nrows()];
        for n in loops.iter().flat_map(|l: &BoundaryLoop| l.nodes.iter().copied()) {
            let v = field(mesh.nodes[n]);
            (u[2 * n], u[2 * n + 1]) = v;
            (fixed[2 * n], fixed[2 * n + 1]) = (true, true);
        }
        let interior = fixed.iter().filter(|f| !**f).count();
        assert!(interior > 0, "{name}: the patch must have interior nodes");
        solve_prescribed(&k, &vec![0.0; k.nrows()], &mut u, &fixed);
        let exact_stress = d * exact_strain;
        for &t in &mesh.triangles {
            let s = Tri3::of(&mesh.nodes, t).stress(&d, &gather(&u, t));
            assert!((s - exact_stress).norm() <= 1e-10 * exact_stress.norm(), "{name}: {s:?}");
        }
        for (n, p) in mesh.nodes.iter().enumerate() {
            let v = field(*p);
            assert!((u[2 * n] - v.0).abs() + (u[2 * n + 1] - v.1).abs() < 1e-10 * 1e-3, "{name}: node {n}");
        }
    }
}

/// Consistent mass: for a uniform unit velocity in x (or y) the kinetic mass is the body's mass,
/// 1^T M_xx 1 = rho * area, with no x-y coupling; the body force sums to rho * area * g. The
/// square is 1.0 x 0.8 (square.geo) and the hole mesh's area is checked against its triangles.
/// Both are sums of a few hundred O(1) terms: 1e-12 relative.
#[test]
fn consistent_mass_and_body_force_resultants() {
    let rho = 2500.0;
    for (name, exact_area) in [("square.msh", Some(0.8)), ("hole.msh", None), ("hertz.msh", Some(8.0))] {
        let mesh = read(name);
        let a = area(&mesh);
        if let Some(x) = exact_area {
            assert!((a - x).abs() < 1e-12 * x, "{name}: area {a}");
        }
        let p = Pattern::new(mesh.nodes.len(), &mesh.triangles, &[]);
        let mut v = vec![0.0; p.nnz()];
        p.assemble(&mut v, |e| Tri3::of(&mesh.nodes, mesh.triangles[e]).mass(rho));
        let m = p.matrix(v);
        let (mut xx, mut yy, mut xy) = (0.0, 0.0, 0.0);
        for (val, (r, c)) in m.iter() {
            match (r % 2, c % 2) {
                (0, 0) => xx += val,
                (1, 1) => yy += val,
                _ => xy += val,
            }
        }
        assert!((xx - rho * a).abs() < 1e-12 * rho * a && (yy - rho * a).abs() < 1e-12 * rho * a, "{name}");
        assert_eq!(xy, 0.0);
        let g = Vec2::new(0.0, -9.81);
        let f = p.assemble_vector(|e| Tri3::of(&mesh.nodes, mesh.triangles[e]).body_force(rho, g));
        let fy: f64 = f.iter().skip(1).step_by(2).sum();
        let fx: f64 = f.iter().step_by(2).sum();
        assert!((fy - rho * a * g.y).abs() < 1e-12 * rho * a * 9.81 && fx == 0.0, "{name}");
    }
}

/// Initial stress (math note §9.1: f_sigma = -A B^T sigma): a uniform sigma0 in a free body is
/// self-equilibrated (resultant zero) and relaxes to the uniform strain -D^-1 sigma0 in every
/// element (rigid modes removed by fixing 3 DOFs, which carry no reaction). 1e-10 relative.
#[test]
fn initial_stress_relaxes_to_the_closed_form_strain() {
    let mesh = read("square.msh");
    let d = constitutive(1.0e9, 0.25, Plane::Stress);
    let sigma0 = Vector3::new(-2.0e6, 1.0e6, 0.5e6);
    let (p, k) = dense_k(&mesh, &d);
    let f = p.assemble_vector(|e| Tri3::of(&mesh.nodes, mesh.triangles[e]).stress_load(&sigma0));
    let scale = sigma0.norm() * 0.8;
    assert!(f.iter().step_by(2).sum::<f64>().abs() < 1e-10 * scale);
    assert!(f.iter().skip(1).step_by(2).sum::<f64>().abs() < 1e-10 * scale);
    // Node 0 is the origin (tag 1), node 1 is (1, 0) (tag 2): fix u_x, u_y at 0 and u_y at 1.
    assert_eq!((mesh.nodes[0], mesh.nodes[1]), (Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0)));
    let mut fixed = vec![false; p.n_dof];
    (fixed[0], fixed[1], fixed[3]) = (true, true, true);
    let mut u = vec![0.0; p.n_dof];
    solve_prescribed(&k, &f, &mut u, &fixed);
    let expected = -d.try_inverse().unwrap() * sigma0;
    for &t in &mesh.triangles {
        let eps = Tri3::of(&mesh.nodes, t).strain(&gather(&u, t));
        assert!((eps - expected).norm() < 1e-10 * expected.norm(), "{eps:?} vs {expected:?}");
    }
}

/// Boundary loops (math note §9.2): the hole mesh has one counter-clockwise outer loop of area 4
/// (the 2 x 2 square, exact corners) and one clockwise hole whose nodes lie on r = 0.4; on every
/// mesh the loops' signed areas sum to the triangles' area (same polygon, 1e-12 relative).
#[test]
fn boundary_loops_enclose_the_mesh() {
    for (name, n_loops) in [("square.msh", 1), ("hole.msh", 2), ("hertz.msh", 1), ("cantilever_3.msh", 1)] {
        let mesh = read(name);
        let loops = boundary_loops(&mesh.nodes, &mesh.triangles).unwrap();
        assert_eq!(loops.len(), n_loops, "{name}");
        let sum: f64 = loops.iter().map(|l| l.signed_area).sum();
        let a = area(&mesh);
        assert!((sum - a).abs() < 1e-12 * a, "{name}: loops {sum} vs triangles {a}");
        assert!(!loops[0].is_hole());
    }
    let mesh = read("hole.msh");
    let loops = boundary_loops(&mesh.nodes, &mesh.triangles).unwrap();
    assert!((loops[0].signed_area - 4.0).abs() < 1e-12);
    assert!(loops[1].is_hole());
    for &n in &loops[1].nodes {
        assert!((mesh.nodes[n].norm() - 0.4).abs() < 1e-12, "hole node {n} at {:?}", mesh.nodes[n]);
    }
}

/// Non-manifold boundaries are errors: a bow-tie (two triangles sharing only a vertex), an edge of
/// three triangles, and two triangles running a shared edge the same way (overlap).
#[test]
fn non_manifold_boundaries_are_errors() {
    let p = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0), (1.0, 1.0), (0.5, -1.0)];
    let nodes: Vec<Vec2> = p.iter().map(|&(x, y)| Vec2::new(x, y)).collect();
    // Bow-tie at node 0: (0,1,5) and (0,3,4).
    assert_eq!(boundary_loops(&nodes, &[[0, 1, 5], [0, 3, 4]]), Err(LoopError::Pinched { node: 0 }));
    assert_eq!(boundary_loops(&nodes, &[[0, 1, 2], [0, 1, 5]]), Err(LoopError::Overlap { a: 0, b: 1 }));
    assert!(matches!(
        boundary_loops(&nodes, &[[0, 1, 2], [1, 0, 4], [1, 0, 6]]),
        Err(LoopError::NonManifoldEdge { a: 0, b: 1, count: 3 })
    ));
}

/// Conjugate gradients on the free DOFs (`fixed` DOFs held at 0) of the sparse SPD matrix `k`.
fn cg(k: &sprs::CsMat<f64>, f: &[f64], fixed: &[bool]) -> Vec<f64> {
    let n = f.len();
    let mask = |v: &mut Vec<f64>| v.iter_mut().zip(fixed).filter(|(_, f)| **f).for_each(|(x, _)| *x = 0.0);
    let mul = |x: &[f64]| {
        let mut y = vec![0.0; n];
        for (val, (r, c)) in k.iter() {
            y[r] += val * x[c];
        }
        y
    };
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let mut x = vec![0.0; n];
    let mut r = f.to_vec();
    mask(&mut r);
    let mut p = r.clone();
    let mut rr = dot(&r, &r);
    let tol = 1e-30 * rr;
    for _ in 0..10 * n {
        let mut kp = mul(&p);
        mask(&mut kp);
        let alpha = rr / dot(&p, &kp);
        x.iter_mut().zip(&p).for_each(|(x, p)| *x += alpha * p);
        r.iter_mut().zip(&kp).for_each(|(r, q)| *r -= alpha * q);
        let rr_new = dot(&r, &r);
        if rr_new <= tol {
            break;
        }
        p = r.iter().zip(&p).map(|(r, p)| r + rr_new / rr * p).collect();
        rr = rr_new;
    }
    x
}

/// Column under self-weight (math note §9.5): plane stress, nu = 0, roller base (u_y = 0 on y = 0,
/// u_x = 0 at the origin), static. Closed form u_y(y) = -(rho g / E)(H y - y^2 / 2), top settlement
/// rho g H^2 / (2E) = 0.01 m here.
/// - Settlement: the mean top-node settlement is within 2e-5 relative of the closed form on each mesh
///   (discretisation error of linear elements; measured 1.0e-5, 1.4e-6, 6.6e-7 relative: a point
///   value on unstructured meshes converges fast but not monotonically, so no order is fitted to it).
/// - Order: on the three successively refined unstructured meshes column_1/2/3 (lc = 0.05, 0.025,
///   0.0125) the L2 error of u_y (edge-midpoint quadrature, exact for the quadratic u_y) falls as
///   O(h^2) for linear elements; observed orders with h = sqrt(area / triangles) must be 2 +- 0.3.
#[test]
fn column_under_self_weight_converges_at_order_two() {
    let (e, rho, g, h_col) = (1.0e6, 2000.0, 10.0, 1.0);
    let exact = rho * g * h_col * h_col / (2.0 * e);
    let uy = |y: f64| -(rho * g / e) * (h_col * y - y * y / 2.0);
    let d = constitutive(e, 0.0, Plane::Stress);
    let mut results = Vec::new();
    for name in ["column_1.msh", "column_2.msh", "column_3.msh"] {
        let mesh = read(name);
        let p = Pattern::new(mesh.nodes.len(), &mesh.triangles, &[]);
        let mut v = vec![0.0; p.nnz()];
        p.assemble(&mut v, |k| Tri3::of(&mesh.nodes, mesh.triangles[k]).stiffness(&d));
        let k = p.matrix(v);
        let weight = Vec2::new(0.0, -g);
        let f = p.assemble_vector(|k| Tri3::of(&mesh.nodes, mesh.triangles[k]).body_force(rho, weight));
        let mut fixed = vec![false; p.n_dof];
        for (n, x) in mesh.nodes.iter().enumerate() {
            if x.y == 0.0 {
                fixed[2 * n + 1] = true;
                fixed[2 * n] |= x.x == 0.0;
            }
        }
        let u = cg(&k, &f, &fixed);
        let top: Vec<usize> = (0..mesh.nodes.len()).filter(|&n| mesh.nodes[n].y == h_col).collect();
        let settlement = -top.iter().map(|&n| u[2 * n + 1]).sum::<f64>() / top.len() as f64;
        assert!((settlement - exact).abs() <= 2e-5 * exact, "{name}: settlement {settlement} vs {exact}");
        let mut l2 = 0.0;
        for &t in &mesh.triangles {
            let a = Tri3::of(&mesh.nodes, t).area;
            for (i, j) in [(0, 1), (1, 2), (2, 0)] {
                let y = 0.5 * (mesh.nodes[t[i]].y + mesh.nodes[t[j]].y);
                let uh = 0.5 * (u[2 * t[i] + 1] + u[2 * t[j] + 1]);
                l2 += a / 3.0 * (uh - uy(y)).powi(2);
            }
        }
        let h = (area(&mesh) / mesh.triangles.len() as f64).sqrt();
        eprintln!(
            "{name}: {} triangles, h {h:.4}, settlement {settlement:.10e}, L2 error {:.3e}",
            mesh.triangles.len(),
            l2.sqrt()
        );
        results.push((h, l2.sqrt()));
    }
    for w in results.windows(2) {
        let order = (w[0].1 / w[1].1).ln() / (w[0].0 / w[1].0).ln();
        eprintln!("observed order {order:.3}");
        assert!((order - 2.0).abs() <= 0.3, "observed order {order}");
    }
}

/// `"tip_uy": value` of `mesh` in meshes/reference.json (written by meshes/reference.py).
fn reference_tip(mesh: &str) -> f64 {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/reference.json");
    let text = std::fs::read_to_string(path).unwrap();
    let at = text.find(&format!("\"{mesh}\"")).unwrap();
    let rest = &text[at..];
    let v = &rest[rest.find("\"tip_uy\":").unwrap() + 9..];
    v[..v.find(['\n', ',', '}']).unwrap()].trim().parse().unwrap()
}

/// Cantilever, tip shear P (math note §9.5): plane stress, E = 1e7, nu = 0.3, L = 10, h = 1,
/// clamped by `fixed_nodes = ["clamp"]` (its nodes removed from the system), P = 1 N as a uniform
/// traction on x = L (consistent nodal loads: half an edge's share to each of its nodes).
/// - Peer code: scikit-fem (meshes/reference.py, P1 triangles, same nodes and triangles) gives the
///   same discrete tip deflection; both solve the same linear system, so they agree to solver
///   round-off (1e-9 relative; our CG stops at 1e-15 relative residual).
/// - Convergence: observed order p = log2((v2 - v1)/(v3 - v2)) (lc halved each time) near 2
///   (Tri3 displacements, O(h^2); 2 +- 0.3), and the Richardson extrapolation v3 + (v3 - v2)/(2^p - 1)
///   within 1 % of P L^3/(3 E I) + P L/(kappa G A) (kappa = 5/6; beam theory versus a clamp that also
///   holds the section's warping differ by a fraction of a percent at L/h = 10).
#[test]
fn cantilever_matches_scikit_fem_and_converges() {
    let (e, nu, p_tip, l, h) = (1.0e7, 0.3, 1.0, 10.0, 1.0);
    let d = constitutive(e, nu, Plane::Stress);
    let mut v = Vec::new();
    for name in ["cantilever_1.msh", "cantilever_2.msh", "cantilever_3.msh"] {
        let mesh = read(name).select_surface(Some("beam")).unwrap();
        let clamp = mesh.node_set(&["clamp"]).unwrap();
        let p = Pattern::new(mesh.nodes.len(), &mesh.triangles, &clamp);
        assert_eq!(p.n_dof, 2 * (mesh.nodes.len() - clamp.len()));
        let mut vals = vec![0.0; p.nnz()];
        p.assemble(&mut vals, |k| Tri3::of(&mesh.nodes, mesh.triangles[k]).stiffness(&d));
        let k = p.matrix(vals);
        let mut f = vec![0.0; p.n_dof];
        let loops = boundary_loops(&mesh.nodes, &mesh.triangles).unwrap();
        let ring = &loops[0].nodes;
        for i in 0..ring.len() {
            let (a, b) = (ring[i], ring[(i + 1) % ring.len()]);
            if mesh.nodes[a].x == l && mesh.nodes[b].x == l {
                let share = -p_tip / h * (mesh.nodes[a] - mesh.nodes[b]).norm() / 2.0;
                for n in [a, b] {
                    f[p.dof(n).unwrap() + 1] += share;
                }
            }
        }
        let u = cg(&k, &f, &vec![false; p.n_dof]);
        let tip: Vec<usize> = (0..mesh.nodes.len()).filter(|&n| mesh.nodes[n].x == l).collect();
        let uy = tip.iter().map(|&n| u[p.dof(n).unwrap() + 1]).sum::<f64>() / tip.len() as f64;
        let peer = reference_tip(name);
        eprintln!("{name}: {} triangles, tip u_y {uy:.12e}, scikit-fem {peer:.12e}", mesh.triangles.len());
        assert!((uy - peer).abs() <= 1e-9 * peer.abs(), "{name}: {uy} vs scikit-fem {peer}");
        v.push(-uy);
    }
    let (i, g) = (h * h * h / 12.0, e / (2.0 * (1.0 + nu)));
    let exact = p_tip * l.powi(3) / (3.0 * e * i) + p_tip * l / (5.0 / 6.0 * g * h);
    let order = ((v[1] - v[0]) / (v[2] - v[1])).log2();
    let extrapolated = v[2] + (v[2] - v[1]) / (2f64.powf(order) - 1.0);
    eprintln!("order {order:.3}, extrapolated {extrapolated:.6e}, exact {exact:.6e}");
    assert!((order - 2.0).abs() <= 0.3, "observed order {order}");
    assert!((extrapolated - exact).abs() <= 0.01 * exact, "{extrapolated} vs {exact}");
}
