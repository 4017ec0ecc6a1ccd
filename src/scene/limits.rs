//! Checks of a scene that has passed every value check but cannot run: the products the first
//! step forms overflow or underflow, a load acts on a fixed body, or a load or monitor point lies
//! far outside its body. Each failure points at the key that is most to blame.
//!
//! The first step (math note §1.2, §2.4) forms, per free body, the mass m = ρ S and the polar
//! inertia ρ J, the step stiffness 2M/dt² and its inverse dt²/(2m) (the flexibility of W), the
//! inertial load 2 M v0 / dt, the weight m g, the initial-stress load S σ and the kinetic energy
//! ½ vᵀ M v. All must be finite, and those that divide or are divided by must be normal
//! (not zero, not subnormal): a subnormal mass has already lost its digits.

use std::ops::Range;

use super::check::{Check, fail};
use super::raw;
use crate::body::Body;
use crate::geometry::{Aabb, Vec2};
use crate::model::{Model, Shape};

/// Finite and normal (the magnitude has all its digits), or zero when `zero_ok`.
fn sound(x: f64, zero_ok: bool) -> bool {
    x.is_normal() || (zero_ok && x == 0.0)
}

/// What went wrong with a magnitude: "overflows" (infinite or NaN) or "underflows".
fn fault(x: f64) -> &'static str {
    if x.is_finite() { "underflows" } else { "overflows" }
}

/// Every check of this module, after `check` has built the model.
pub(super) fn first_step(raw: &raw::Scene, model: &Model) -> Check<()> {
    let raw_bodies = raw.body.get_ref();
    let dt = model.time.step;
    let dt_span = raw.time.get_ref().step.span();
    let bodies: Vec<Body> = model
        .bodies
        .iter()
        .map(|s| Body::new(s, &model.materials[s.material], model.physics.plane))
        .collect();
    for ((body, spec), r) in bodies.iter().zip(&model.bodies).zip(raw_bodies) {
        let r = r.get_ref();
        geometry(body, &spec.shape, r)?;
        if !spec.fixed {
            let material = &model.materials[spec.material];
            masses(body, r, &material.name, (dt, &dt_span))?;
            loads_of(body, r, raw.physics.gravity.as_ref(), model, dt)?;
        }
    }
    for (i, (load, r)) in model.loads.iter().zip(&raw.load).enumerate() {
        let body = &bodies[load.body];
        if body.fixed {
            let message = format!("load[{i}] acts on the fixed body \"{}\", which cannot move", body.name);
            return fail(r.body.span(), message);
        }
        near_body(&model.bodies[load.body].shape, &body.name, load.point, r.point.span())?;
        let reach = load.force.norm() * dt * dt / (2.0 * body.mass);
        if !reach.is_finite() {
            let message =
                format!("the force gives a first-step displacement F dt²/(2m) that {}", fault(reach));
            return fail(r.force.span(), message);
        }
    }
    for (m, r) in model.monitors.iter().zip(&raw.monitor) {
        near_body(&model.bodies[m.body].shape, &model.bodies[m.body].name, m.point, r.point.span())?;
    }
    Ok(())
}

/// The key that holds the body's size: `radius` or `vertices`.
fn size_span(r: &raw::Body) -> Range<usize> {
    let span = r.radius.as_ref().map(|v| v.span()).or(r.vertices.as_ref().map(|v| v.span()));
    span.unwrap_or(r.shape.span())
}

/// Area S and polar moment J of every body (fixed ones too: contact detection sizes its grid
/// from them) are normal.
fn geometry(body: &Body, shape: &Shape, r: &raw::Body) -> Check<()> {
    let (area, polar) = area_and_polar(shape);
    for (what, x) in [("area", area), ("polar moment of area", polar)] {
        if !sound(x, false) {
            let message = format!("the body's {what} ({x:e}) {}: the size is out of range", fault(x));
            return fail(size_span(r), message);
        }
    }
    if !sound(body.reach, false) {
        return fail(size_span(r), format!("the body's size ({:e}) {}", body.reach, fault(body.reach)));
    }
    Ok(())
}

/// S and J = ∫ r² dA about the centroid (math note §2.1).
fn area_and_polar(shape: &Shape) -> (f64, f64) {
    use std::f64::consts::PI;
    match shape {
        Shape::Disk { radius: r, .. } => (PI * r * r, PI * r.powi(4) / 2.0),
        Shape::Ring { outer, inner, .. } => {
            (PI * (outer * outer - inner * inner), PI * (outer.powi(4) - inner.powi(4)) / 2.0)
        }
        Shape::Polygon { vertices } => {
            let m = crate::geometry::polygon_moments(vertices);
            (m.area.abs(), m.sxx + m.syy)
        }
        Shape::Mesh(mesh) => {
            // the triangles' own moments, shifted to the mesh's centroid
            let tris = mesh_triangles(mesh);
            let moments: Vec<_> = tris.iter().map(|t| crate::geometry::polygon_moments(t)).collect();
            let area: f64 = moments.iter().map(|m| m.area.abs()).sum();
            let centroid = moments.iter().map(|m| m.centroid * m.area.abs()).sum::<Vec2>() / area;
            let polar =
                moments.iter().map(|m| m.sxx + m.syy + m.area.abs() * (m.centroid - centroid).norm_squared());
            (area, polar.sum())
        }
    }
}

/// The triangles of a mesh body as vertex triples.
pub(super) fn mesh_triangles(mesh: &crate::model::MeshShape) -> Vec<Vec<Vec2>> {
    let m = &mesh.mesh;
    m.triangles.iter().map(|t| t.iter().map(|&i| m.nodes[i]).collect()).collect()
}

/// m = ρ S and the rotational inertia are normal; 2M/dt² and dt²/(2m) finite and normal.
fn masses(body: &Body, r: &raw::Body, material: &str, (dt, dt_span): (f64, &Range<usize>)) -> Check<()> {
    let m = body.mass_matrix();
    let name = &body.name;
    for (what, x) in [("mass ρ·S", m[(0, 0)]), ("rotational inertia ρ·J", m[(2, 2)])] {
        if !sound(x, false) {
            let message = format!(
                "the {what} of body \"{name}\" ({x:e}) {}: check the density of material \"{material}\"",
                fault(x)
            );
            return fail(r.material.span(), message);
        }
    }
    let k = 2.0 / (dt * dt);
    for (what, x) in [
        ("step stiffness 2m/dt²", m[(0, 0)] * k),
        ("rotational step stiffness 2I/dt²", m[(2, 2)] * k),
        ("step flexibility dt²/(2m)", 1.0 / (m[(0, 0)] * k)),
        ("rotational step flexibility dt²/(2I)", 1.0 / (m[(2, 2)] * k)),
    ] {
        if !sound(x, false) {
            let message = format!(
                "dt = {dt:e} makes the {what} of body \"{name}\" ({x:e}) {} (mass m = {:e}, material \"{material}\")",
                fault(x),
                m[(0, 0)]
            );
            return fail(dt_span.clone(), message);
        }
    }
    let stiff = body.elastic_stiffness() + m * k;
    if stiff.iter().any(|x| !x.is_finite()) {
        let message = format!("the elastic stiffness E·S of body \"{name}\" overflows");
        return fail(r.material.span(), message);
    }
    Ok(())
}

/// The first step's loads on a free body: 2 M v0 / dt, ½ vᵀ M v, m g and S σ are finite.
fn loads_of(
    body: &Body,
    r: &raw::Body,
    gravity: Option<&toml::Spanned<Vec<f64>>>,
    model: &Model,
    dt: f64,
) -> Check<()> {
    let m = body.mass_matrix();
    let name = &body.name;
    let inertial = m * body.velocity * (2.0 / dt);
    let linear_ok = inertial.fixed_rows::<2>(0).iter().all(|x| x.is_finite());
    if !linear_ok || inertial.iter().any(|x| !x.is_finite()) || !body.kinetic_energy().is_finite() {
        let blame = if linear_ok {
            r.angular_velocity.as_ref().map(|w| w.span())
        } else {
            r.velocity.as_ref().map(|v| v.span())
        };
        let span = blame.unwrap_or(r.material.span());
        let message = format!(
            "the first step's inertial load 2Mv/dt or kinetic energy ½vᵀMv of body \"{name}\" overflows"
        );
        return fail(span, message);
    }
    let weight = model.physics.gravity * body.mass;
    if let Some(g) = gravity
        && !(weight.x.is_finite() && weight.y.is_finite())
    {
        let message = format!("the weight m·g of body \"{name}\" (m = {:e}) overflows", body.mass);
        return fail(g.span(), message);
    }
    if let Some(s) = &r.initial_stress
        && body.stress_load().iter().any(|x| !x.is_finite())
    {
        return fail(s.span(), format!("the initial-stress load S·σ of body \"{name}\" overflows"));
    }
    Ok(())
}

/// A load or monitor point may sit on or near its body (a point typed on an edge, a
/// monitor just outside), but not farther from it than the body's own size (the diagonal of
/// its bounding box): that is a mistyped coordinate or body name.
fn near_body(shape: &Shape, name: &str, p: Vec2, span: Range<usize>) -> Check<()> {
    let (distance, size) = (distance_outside(shape, p), extent(shape));
    if distance > size {
        let message = format!(
            "point ({}, {}) is {distance:e} outside body \"{name}\", more than the body's size {size:e}",
            p.x, p.y
        );
        return fail(span, message);
    }
    Ok(())
}

/// Bounding box of a shape at t = 0.
pub(super) fn aabb(shape: &Shape) -> Aabb {
    match shape {
        Shape::Disk { center, radius } => Aabb::of_circle(*center, *radius),
        Shape::Ring { center, outer, .. } => Aabb::of_circle(*center, *outer),
        Shape::Polygon { vertices } => Aabb::of_points(vertices),
        Shape::Mesh(mesh) => Aabb::of_points(&mesh.mesh.nodes),
    }
}

/// Diagonal of the bounding box.
fn extent(shape: &Shape) -> f64 {
    let b = aabb(shape);
    (b.max - b.min).norm()
}

/// Distance from `p` to the shape; 0 inside.
fn distance_outside(shape: &Shape, p: Vec2) -> f64 {
    if shape.contains(p) {
        return 0.0;
    }
    match shape {
        Shape::Disk { center, radius } => (p - center).norm() - radius,
        Shape::Ring { center, outer, inner } => {
            let r = (p - center).norm();
            if r > *outer { r - outer } else { inner - r }
        }
        Shape::Polygon { vertices } => {
            let n = vertices.len();
            let to_edge = |i: usize| {
                let (a, b) = (vertices[i], vertices[(i + 1) % n]);
                let ab = b - a;
                let t = ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0);
                (a + ab * t - p).norm()
            };
            (0..n).map(to_edge).fold(f64::INFINITY, f64::min)
        }
        Shape::Mesh(mesh) => mesh_triangles(mesh)
            .iter()
            .map(|t| distance_outside(&Shape::Polygon { vertices: t.clone() }, p))
            .fold(f64::INFINITY, f64::min),
    }
}
