//! Validation of the raw scene into a [`Model`]: ranges, references by name, shapes. Each
//! failure is a [`Problem`] at the span of the offending value; `super` turns it into a
//! [`crate::error::SceneError`] with line, column and key path.

use std::collections::HashMap;
use std::ops::Range;

use toml::Spanned;

use super::Problem;
use super::raw;
use crate::geometry::{PolygonDefect, Vec2, check_simple_polygon, signed_area2};
use crate::model::{
    BodyModel, BodySpec, ContactSettings, Load, Material, Model, Monitor, OutputSettings, Physics, Plane,
    Shape, SolverSettings, TimeSettings,
};

pub(super) type Check<T> = Result<T, Problem>;

/// Name -> index into the list it names (materials, bodies).
pub(super) type Names<'a> = HashMap<&'a str, usize>;

/// Validates the whole scene, in the contract's table order.
pub(super) fn model(raw: &raw::Scene, dir: &std::path::Path) -> Check<Model> {
    let time = time(&raw.time, raw.stage.last().map(|s| &s.get_ref().end))?;
    let physics = physics(&raw.physics)?;
    let gravity_history = optional(&raw.physics.gravity_history, "gravity_history", history)?;
    let contact = contact(&raw.contact)?;
    let solver = solver(&raw.solver)?;
    let (materials, material_names) = materials(&raw.material)?;
    let interfaces = super::interfaces::interfaces(&raw.interface, &material_names)?;
    let interface_names = super::interfaces::interface_names(&raw.interface)?;
    let (bodies, body_names) = bodies(&raw.body, &material_names, &materials, &interface_names, dir)?;
    let loads = raw.load.iter().map(|l| load(l, &body_names)).collect::<Check<_>>()?;
    let connectors = super::connectors::connectors(&raw.connector, &body_names, &bodies)?;
    let outline = raw.domain.as_ref().map(|d| d.get_ref().vertices.get_ref().as_slice());
    let tractions = super::traction::tractions(&raw.traction, &body_names, &bodies, outline)?;
    let monitors = monitors(&raw.monitor, &body_names)?;
    let output = output(&raw.output)?;
    let model = Model {
        name: raw.scene.name.clone(),
        time,
        physics,
        contact,
        solver,
        materials,
        interfaces,
        bodies,
        loads,
        tractions,
        connectors,
        monitors,
        output,
        stages: Vec::new(),
        excavations: Vec::new(),
        gravity_history,
    };
    super::limits::first_step(raw, &model)?;
    super::overlap::no_body_inside_another(&model.bodies, raw.body.get_ref())?;
    Ok(model)
}

// ---------------------------------------------------------------- numbers

pub(super) fn fail<T>(span: Range<usize>, message: impl Into<String>) -> Check<T> {
    Err(Problem::new(span, message))
}

/// The value of `v` if it is finite and passes `test`; else "`key` must `requirement`".
pub(super) fn real(v: &Spanned<f64>, key: &str, requirement: &str, test: impl Fn(f64) -> bool) -> Check<f64> {
    let x = *v.get_ref();
    if !x.is_finite() {
        return fail(v.span(), format!("{key} must be a finite number (got {x})"));
    }
    if !test(x) {
        return fail(v.span(), format!("{key} must {requirement} (got {x})"));
    }
    Ok(x)
}

pub(super) fn finite(v: &Spanned<f64>, key: &str) -> Check<f64> {
    real(v, key, "", |_| true)
}

pub(super) fn positive(v: &Spanned<f64>, key: &str) -> Check<f64> {
    real(v, key, "be positive", |x| x > 0.0)
}

pub(super) fn non_negative(v: &Spanned<f64>, key: &str) -> Check<f64> {
    real(v, key, "not be negative", |x| x >= 0.0)
}

/// A fraction in [0, 1] (`restitution`).
pub(super) fn unit_interval(v: &Spanned<f64>, key: &str) -> Check<f64> {
    real(v, key, "be between 0 and 1", |x| (0.0..=1.0).contains(&x))
}

/// `rule` applied to an optional value.
pub(super) fn optional<T, O>(
    v: &Option<Spanned<T>>,
    key: &str,
    rule: impl Fn(&Spanned<T>, &str) -> Check<O>,
) -> Check<Option<O>> {
    v.as_ref().map(|v| rule(v, key)).transpose()
}

/// `rule` applied to an optional value; `default` when it is absent.
pub(super) fn or_default<T, O>(
    v: &Option<Spanned<T>>,
    key: &str,
    rule: impl Fn(&Spanned<T>, &str) -> Check<O>,
    default: O,
) -> Check<O> {
    Ok(optional(v, key, rule)?.unwrap_or(default))
}

/// A whole number ≥ 1 (`steps`, `max_iterations`, `every`).
fn count(v: &Spanned<i64>, key: &str) -> Check<usize> {
    let n = *v.get_ref();
    match usize::try_from(n) {
        Ok(n) if n >= 1 => Ok(n),
        _ => fail(v.span(), format!("{key} must be at least 1 (got {n})")),
    }
}

/// Exactly `N` finite numbers; `what` names them in the message (`point`, `vertices[3]`).
pub(super) fn numbers<const N: usize>(values: &[f64], span: Range<usize>, what: &str) -> Check<[f64; N]> {
    let Ok(array) = <[f64; N]>::try_from(values) else {
        let n = values.len();
        return fail(span, format!("{what} must have {N} numbers (got {n})"));
    };
    match array.iter().find(|x| !x.is_finite()) {
        Some(x) => fail(span, format!("{what} must be finite numbers (got {x})")),
        None => Ok(array),
    }
}

pub(super) fn vec2(v: &Spanned<Vec<f64>>, key: &str) -> Check<Vec2> {
    let [x, y] = numbers(v.get_ref(), v.span(), key)?;
    Ok(Vec2::new(x, y))
}

/// A list of `[a, b]` pairs (`vertices`, `history`).
fn pairs(v: &Spanned<Vec<Vec<f64>>>, key: &str) -> Check<Vec<Vec2>> {
    let each = |(i, p): (usize, &Vec<f64>)| numbers(p, v.span(), &format!("{key}[{i}]"));
    v.get_ref().iter().enumerate().map(|p| each(p).map(|[a, b]| Vec2::new(a, b))).collect()
}

/// One of the listed strings.
pub(super) fn choice<T: Copy>(v: &Spanned<String>, key: &str, options: &[(&str, T)]) -> Check<T> {
    let given = v.get_ref().as_str();
    if let Some(&(_, t)) = options.iter().find(|(s, _)| *s == given) {
        return Ok(t);
    }
    let names: Vec<String> = options.iter().map(|(s, _)| format!("\"{s}\"")).collect();
    let names = names.join(", ");
    fail(v.span(), format!("{key} must be one of {names} (got \"{given}\")"))
}

// ---------------------------------------------------------------- names

/// Index of each name; a repeated name is an error at its second occurrence.
pub(super) fn unique_names<'a>(
    names: impl Iterator<Item = &'a Spanned<String>>,
    what: &str,
) -> Check<Names<'a>> {
    let mut map = Names::new();
    for (i, name) in names.enumerate() {
        // names are written unquoted into the CSV outputs
        let n = name.get_ref();
        if n.is_empty() || n.contains([',', '"', '\n', '\r']) {
            return fail(
                name.span(),
                format!("{what} name \"{n}\" must be non-empty, without commas, quotes or line breaks"),
            );
        }
        if let Some(first) = map.insert(name.get_ref().as_str(), i) {
            let n = name.get_ref();
            let message = format!("duplicate {what} name \"{n}\" (already used by {what}[{first}])");
            return fail(name.span(), message);
        }
    }
    Ok(map)
}

pub(super) fn resolve(names: &Names, name: &Spanned<String>, what: &str) -> Check<usize> {
    let n = name.get_ref();
    let message = || format!("unknown {what} \"{n}\"");
    names.get(n.as_str()).copied().ok_or_else(|| Problem::new(name.span(), message()))
}

// ---------------------------------------------------------------- settings

/// `[time]`; with stages, `steps` and `end` may both be left out: the run then ends at the last
/// stage's `end` (`stage_end`).
fn time(t: &Spanned<raw::Time>, stage_end: Option<&Spanned<f64>>) -> Check<TimeSettings> {
    let (header, t) = (t.span(), t.get_ref());
    let step = positive(&t.step, "step")?;
    let steps = match (&t.steps, &t.end) {
        (Some(n), None) => {
            let steps = count(n, "steps")?;
            if steps > MAX_STEPS {
                return fail(n.span(), format!("steps = {steps} is more than {MAX_STEPS:e}"));
            }
            steps
        }
        (None, Some(end)) => steps_until(positive(end, "end")?, step, end.span())?,
        (Some(_), Some(end)) => fail(end.span(), "give either `steps` or `end`, not both")?,
        (None, None) => match stage_end {
            Some(end) => steps_until(positive(end, "end")?, step, end.span())?,
            None => {
                let message = "[time] needs `steps` or `end`";
                return Err(Problem::missing(header, "steps", message));
            }
        },
    };
    let halvings = |v: &Spanned<i64>, key: &str| match u32::try_from(*v.get_ref()) {
        Ok(n) if n <= 30 => Ok(n),
        _ => fail(v.span(), format!("{key} must be a whole number from 0 to 30 (got {})", v.get_ref())),
    };
    let default = TimeSettings::new(step, steps);
    Ok(TimeSettings {
        adaptive: t.adaptive.unwrap_or(default.adaptive),
        max_halvings: or_default(&t.max_halvings, "max_halvings", halvings, default.max_halvings)?,
        ..default
    })
}

/// The most steps a run may have: 1e9 steps of even the smallest scene take days; a larger
/// count is a mistyped `end`, `step` or `steps`.
pub const MAX_STEPS: usize = 1_000_000_000;

/// steps = ceil(end / step - 1e-9): the 1e-9 keeps round-off such as 0.07 / 0.01 =
/// 7.000000000000001 from adding a step. `end` must be at least one step (to 1e-9).
pub(super) fn steps_until(end: f64, step: f64, span: Range<usize>) -> Check<usize> {
    let ratio = end / step;
    if ratio < 1.0 - 1e-9 {
        return fail(span, format!("end = {end} is less than one step of {step}"));
    }
    let n = (ratio - 1e-9).ceil();
    if n.is_nan() || n > MAX_STEPS as f64 {
        let message = format!("end / step = {end:e} / {step:e} is {n:e} steps, more than {MAX_STEPS:e}");
        return fail(span, message);
    }
    Ok(n as usize)
}

fn physics(p: &raw::Physics) -> Check<Physics> {
    let plane_options = [("stress", Plane::Stress), ("strain", Plane::Strain)];
    let plane = |v: &Spanned<String>, key: &str| choice(v, key, &plane_options);
    let carry =
        |v: &Spanned<f64>, key: &str| real(v, key, "be between 0 and 1", |k| (0.0..=1.0).contains(&k));
    Ok(Physics {
        gravity: or_default(&p.gravity, "gravity", vec2, Vec2::zeros())?,
        plane: or_default(&p.plane, "plane", plane, Plane::Stress)?,
        velocity_carry: or_default(&p.velocity_carry, "velocity_carry", carry, 1.0)?,
    })
}

fn contact(c: &raw::Contact) -> Check<ContactSettings> {
    Ok(ContactSettings { threshold: optional(&c.threshold, "threshold", positive)? })
}

fn solver(s: &raw::Solver) -> Check<SolverSettings> {
    let default = SolverSettings::default();
    Ok(SolverSettings {
        tolerance: or_default(&s.tolerance, "tolerance", positive, default.tolerance)?,
        max_iterations: or_default(&s.max_iterations, "max_iterations", count, default.max_iterations)?,
        method: or_default(&s.method, "method", chain, default.method)?,
        allow_unconverged: s.allow_unconverged.unwrap_or(default.allow_unconverged),
        factor_drift: or_default(&s.factor_drift, "factor_drift", non_negative, default.factor_drift)?,
        friction_stops: s.friction_stops.unwrap_or(default.friction_stops),
    })
}

/// `method`: the scene name of a whole chain (`"mprgp"`) or a list of methods (`["newton",
/// "pc"]`), math note §4.17.
fn chain(v: &Spanned<toml::Value>, key: &str) -> Check<crate::vi::Chain> {
    use crate::vi::Chain;
    let chain = match v.get_ref() {
        toml::Value::String(s) => Chain::parse(s)
            .ok_or_else(|| format!("must be one of {}, or a list of methods (got \"{s}\")", Chain::names())),
        toml::Value::Array(items) => Chain::from_list(items.iter().map(|i| i.as_str().ok_or(i))),
        other => Err(format!("must be a string or a list of methods (got a {})", other.type_str())),
    };
    chain.or_else(|e| fail(v.span(), format!("{key} {e}")))
}

fn output(o: &raw::Output) -> Check<OutputSettings> {
    let every = or_default(&o.every, "every", count, 1)?;
    let steps_every = or_default(&o.steps_every, "steps_every", count, every)?;
    Ok(OutputSettings { every, steps_every, vtk: o.vtk.unwrap_or(true) })
}

// ---------------------------------------------------------------- materials and interfaces

fn materials(raw: &[raw::Material]) -> Check<(Vec<Material>, Names<'_>)> {
    let names = unique_names(raw.iter().map(|m| &m.name), "material")?;
    Ok((raw.iter().map(material).collect::<Check<_>>()?, names))
}

fn material(m: &raw::Material) -> Check<Material> {
    // ν = 0.5 is incompressible: the plane-strain elasticity matrix is singular
    let poisson = |v: &Spanned<f64>, key: &str| {
        real(v, key, "be at least 0 and below 0.5", |nu| (0.0..0.5).contains(&nu))
    };
    Ok(Material {
        name: m.name.get_ref().clone(),
        density: positive(&m.density, "density")?,
        young: optional(&m.young, "young", positive)?,
        poisson: optional(&m.poisson, "poisson", poisson)?,
    })
}

// ---------------------------------------------------------------- bodies

/// The shapes of the contract.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum ShapeKind {
    Disk,
    Ring,
    Polygon,
    Mesh,
}

const SHAPES: [(&str, ShapeKind); 4] = [
    ("disk", ShapeKind::Disk),
    ("ring", ShapeKind::Ring),
    ("polygon", ShapeKind::Polygon),
    ("mesh", ShapeKind::Mesh),
];

fn bodies<'a>(
    raw: &'a Spanned<Vec<Spanned<raw::Body>>>,
    materials: &Names,
    material_list: &[Material],
    interfaces: &Names,
    dir: &std::path::Path,
) -> Check<(Vec<BodySpec>, Names<'a>)> {
    if raw.get_ref().is_empty() && raw.span().is_empty() {
        let message = "missing key `body`: a scene needs at least one [[body]] or a [domain]";
        return Err(Problem::missing(0..0, "body", message));
    }
    if raw.get_ref().is_empty() {
        return fail(raw.span(), "a scene needs at least one [[body]]");
    }
    let names = unique_names(raw.get_ref().iter().map(|b| &b.get_ref().name), "body")?;
    let list = raw
        .get_ref()
        .iter()
        .map(|b| body(b, materials, material_list, interfaces, dir))
        .collect::<Check<_>>()?;
    Ok((list, names))
}

fn body(
    b: &Spanned<raw::Body>,
    materials: &Names,
    material_list: &[Material],
    interfaces: &Names,
    dir: &std::path::Path,
) -> Check<BodySpec> {
    let (header, b) = (b.span(), b.get_ref());
    let kind = choice(&b.shape, "shape", &SHAPES)?;
    let material = resolve(materials, &b.material, "material")?;
    let (shape, model) = if kind == ShapeKind::Mesh {
        reject_foreign_keys(b, kind)?;
        let shape = super::mesh::shape(b, &header, dir)?;
        (shape, super::mesh::model(b, &material_list[material])?)
    } else {
        (shape(b, header, kind)?, body_model(b, &material_list[material])?)
    };
    let initial_stress = match &b.initial_stress {
        Some(s) if model == BodyModel::Rigid => {
            return fail(s.span(), "initial_stress is only for deformable bodies");
        }
        Some(s) => Some(numbers(s.get_ref(), s.span(), "initial_stress")?),
        None => None,
    };
    let edge_interfaces = edge_interfaces(b, &shape, interfaces)?;
    Ok(BodySpec {
        name: b.name.get_ref().clone(),
        shape,
        model,
        material,
        fixed: b.fixed,
        velocity: or_default(&b.velocity, "velocity", vec2, Vec2::zeros())?,
        angular_velocity: or_default(&b.angular_velocity, "angular_velocity", finite, 0.0)?,
        initial_stress,
        edge_interfaces,
    })
}

/// `edge_interfaces`: one interface name ("" for none) per polygon edge, in the order of the
/// vertices as given (re-ordered with them when they are stored counter-clockwise); on a mesh,
/// per edge of its contact loops (a meshed block of a rock mass, as `cut` writes it).
fn edge_interfaces(b: &raw::Body, shape: &Shape, interfaces: &Names) -> Check<Vec<Option<usize>>> {
    let Some(tags) = &b.edge_interfaces else { return Ok(Vec::new()) };
    let (n, vertices) = match shape {
        Shape::Polygon { vertices } => (vertices.len(), Some(vertices)),
        // one per edge of the mesh's contact loops, outer then holes (math note §4.14, §9.2)
        Shape::Mesh(m) => {
            let (outer, holes) = crate::mesh::loops::contact_loops(&m.mesh.nodes, &m.mesh.triangles);
            (outer.len() + holes.iter().map(Vec::len).sum::<usize>(), None)
        }
        _ => return fail(tags.span(), "edge_interfaces is only for polygon and mesh bodies"),
    };
    if tags.get_ref().len() != n {
        let message =
            format!("edge_interfaces must name {n} interfaces, one per edge (got {})", tags.get_ref().len());
        return fail(tags.span(), message);
    }
    let mut list: Vec<Option<usize>> = tags
        .get_ref()
        .iter()
        .map(
            |t| if t.get_ref().is_empty() { Ok(None) } else { resolve(interfaces, t, "interface").map(Some) },
        )
        .collect::<Check<_>>()?;
    let Some(vertices) = vertices else { return Ok(list) };
    let given = pairs(need(b, &(0..0), &b.vertices, "vertices")?, "vertices")?;
    if given.first() != vertices.first() || given.get(1) != vertices.get(1) {
        // reversed: stored edge i runs from given vertex n-1-i to n-2-i, given edge n-2-i
        list = (0..n).map(|i| list[(2 * n - 2 - i) % n]).collect();
    }
    Ok(list)
}

/// `model`: "rigid" (default) or "deformable", which needs the material's `young` and
/// `poisson`.
fn body_model(b: &raw::Body, material: &Material) -> Check<BodyModel> {
    let options = [("rigid", BodyModel::Rigid), ("deformable", BodyModel::Deformable)];
    let Some(m) = &b.model else { return Ok(BodyModel::Rigid) };
    let model = choice(m, "model", &options)?;
    if model == BodyModel::Deformable && (material.young.is_none() || material.poisson.is_none()) {
        let name = &material.name;
        return fail(
            m.span(),
            format!("a deformable body needs `young` and `poisson` in material \"{name}\""),
        );
    }
    Ok(model)
}

/// `header` is the span of the body's `[[body]]` line, where a missing key is reported.
fn shape(b: &raw::Body, header: Range<usize>, kind: ShapeKind) -> Check<Shape> {
    reject_mesh_keys(b)?;
    reject_foreign_keys(b, kind)?;
    match kind {
        ShapeKind::Disk => Ok(Shape::Disk {
            center: vec2(need(b, &header, &b.center, "center")?, "center")?,
            radius: positive(need(b, &header, &b.radius, "radius")?, "radius")?,
        }),
        ShapeKind::Ring => ring(b, &header),
        ShapeKind::Polygon => polygon(need(b, &header, &b.vertices, "vertices")?),
        ShapeKind::Mesh => unreachable!("mesh shapes are read by scene::mesh"),
    }
}

fn reject_mesh_keys(b: &raw::Body) -> Check<()> {
    let given = [
        ("file", b.file.as_ref().map(Spanned::span)),
        ("physical", b.physical.as_ref().map(Spanned::span)),
        ("fixed_nodes", b.fixed_nodes.as_ref().map(Spanned::span)),
        ("fixed_x_nodes", b.fixed_x_nodes.as_ref().map(Spanned::span)),
        ("fixed_y_nodes", b.fixed_y_nodes.as_ref().map(Spanned::span)),
        ("scale", b.scale.as_ref().map(Spanned::span)),
        ("offset", b.offset.as_ref().map(Spanned::span)),
    ];
    for (key, span) in given {
        if let Some(span) = span {
            let shape = b.shape.get_ref();
            return fail(span, format!("`{key}` is a key of mesh bodies, not used by a {shape} body"));
        }
    }
    Ok(())
}

/// Geometry keys that the body's shape does not use are errors, not silently ignored.
fn reject_foreign_keys(b: &raw::Body, kind: ShapeKind) -> Check<()> {
    let used: &[&str] = match kind {
        ShapeKind::Disk => &["center", "radius"],
        ShapeKind::Ring => &["center", "radius", "inner_radius"],
        ShapeKind::Polygon => &["vertices"],
        ShapeKind::Mesh => &[],
    };
    let given = [
        ("center", b.center.as_ref().map(Spanned::span)),
        ("radius", b.radius.as_ref().map(Spanned::span)),
        ("inner_radius", b.inner_radius.as_ref().map(Spanned::span)),
        ("vertices", b.vertices.as_ref().map(Spanned::span)),
    ];
    for (key, span) in given {
        if let Some(span) = span
            && !used.contains(&key)
        {
            let shape = b.shape.get_ref();
            return fail(span, format!("`{key}` is not used by a {shape} body"));
        }
    }
    Ok(())
}

/// A key the shape requires; missing, the error points at the body's `[[body]]` header.
pub(super) fn need<'a, T>(
    b: &raw::Body,
    header: &Range<usize>,
    value: &'a Option<Spanned<T>>,
    key: &str,
) -> Check<&'a Spanned<T>> {
    value.as_ref().ok_or_else(|| {
        let message = format!("a {} body needs `{key}`", b.shape.get_ref());
        Problem::missing(header.clone(), key, message)
    })
}

fn ring(b: &raw::Body, header: &Range<usize>) -> Check<Shape> {
    let center = vec2(need(b, header, &b.center, "center")?, "center")?;
    let outer = positive(need(b, header, &b.radius, "radius")?, "radius")?;
    let inner_value = need(b, header, &b.inner_radius, "inner_radius")?;
    let inner = positive(inner_value, "inner_radius")?;
    if inner >= outer {
        let message = format!("inner_radius must be less than radius (got {inner} >= {outer})");
        return fail(inner_value.span(), message);
    }
    Ok(Shape::Ring { center, outer, inner })
}

/// A simple polygon of either orientation, stored counter-clockwise.
fn polygon(v: &Spanned<Vec<Vec<f64>>>) -> Check<Shape> {
    let mut vertices = pairs(v, "vertices")?;
    if let Err(defect) = check_simple_polygon(&vertices) {
        return fail(v.span(), defect_message(&defect, vertices.len()));
    }
    if signed_area2(&vertices) < 0.0 {
        vertices.reverse();
    }
    Ok(Shape::Polygon { vertices })
}

pub(super) fn defect_message(defect: &PolygonDefect, n: usize) -> String {
    let edge = |i: usize| format!("vertices[{i}]-vertices[{}]", (i + 1) % n);
    match defect {
        PolygonDefect::TooFewVertices => format!("a polygon needs at least 3 vertices (got {n})"),
        PolygonDefect::ZeroLengthEdge(i) => format!("zero-length edge {}", edge(*i)),
        PolygonDefect::SelfIntersection(i, j) => {
            format!("the polygon intersects itself: edge {} meets edge {}", edge(*i), edge(*j))
        }
        PolygonDefect::ZeroArea => "the polygon has zero area".to_owned(),
    }
}

// ---------------------------------------------------------------- loads and monitors

fn load(l: &raw::Load, bodies: &Names) -> Check<Load> {
    Ok(Load {
        body: resolve(bodies, &l.body, "body")?,
        point: vec2(&l.point, "point")?,
        force: vec2(&l.force, "force")?,
        history: optional(&l.history, "history", history)?,
    })
}

/// (time, factor) pairs, at least one, times strictly increasing.
pub(super) fn history(h: &Spanned<Vec<Vec<f64>>>, key: &str) -> Check<Vec<(f64, f64)>> {
    let points = pairs(h, key)?;
    if points.is_empty() {
        return fail(h.span(), "history needs at least one [time, factor] pair");
    }
    if let Some(i) = points.windows(2).position(|w| w[1].x <= w[0].x) {
        let (t0, t1) = (points[i].x, points[i + 1].x);
        let message =
            format!("history times must increase strictly (history[{}] has time {t1} after {t0})", i + 1);
        return fail(h.span(), message);
    }
    Ok(points.iter().map(|p| (p.x, p.y)).collect())
}

fn monitors(raw: &[raw::Monitor], bodies: &Names) -> Check<Vec<Monitor>> {
    unique_names(raw.iter().map(|m| &m.name), "monitor")?;
    let monitor = |m: &raw::Monitor| {
        Ok(Monitor {
            name: m.name.get_ref().clone(),
            body: resolve(bodies, &m.body, "body")?,
            point: vec2(&m.point, "point")?,
        })
    };
    raw.iter().map(monitor).collect()
}
