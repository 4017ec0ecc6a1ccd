//! The rock-mass keys (`[domain]`, `[[joint_set]]`, `[[joint]]`, `[[excavation]]`,
//! `[[region]]`; scene-format "Rock masses") expanded into ordinary `[[body]]` tables before
//! anything else is checked: the domain is cut into blocks by [`crate::rockmass::cut`], each
//! block becomes a polygon (or, `model = "mesh"`, a meshed) body `blk-N`, N from 1 in the
//! cutter's order (centroid y, x, area). The generated tables carry the spans of the keys they
//! come from, so that a later error about them names the domain's keys. Bolts are expanded by
//! [`super::bolts`].

use std::ops::Range;

use toml::Spanned;

use super::check::{Check, fail, non_negative, numbers, positive, real};
use super::raw;
use crate::geometry::{Vec2, check_simple_polygon, signed_area2};
use crate::model::Shape;
use crate::rockmass::{self as rm, EdgeSource};

/// What the expansion made, for `pbdda cut` and `pbdda check`.
#[derive(Debug, Clone, Default)]
pub struct Expansion {
    /// Names of the generated blocks, in body order (after the scene's own bodies).
    pub blocks: Vec<String>,
    /// The generated blocks' areas [m²], as `blocks`.
    pub areas: Vec<f64>,
    /// Every merge and join the cutter made, one line each.
    pub reports: Vec<String>,
    /// Staged excavations: name and the names of the blocks inside, which stay until a stage
    /// removes them.
    pub staged: Vec<(String, Vec<String>)>,
    /// The meshed blocks (`model = "mesh"`): body name and its triangulation, for `.msh` files.
    pub meshes: Vec<(String, rm::TriMesh)>,
    /// Traces of the cut (for pictures): every block edge and where it came from.
    pub edges: Vec<([[f64; 2]; 2], EdgeSource)>,
    /// Names of the generated connectors (bolt segments and patterns).
    pub connectors: Vec<String>,
    /// The excavations' outlines (counter-clockwise), for bolt patterns.
    pub outlines: Vec<(String, Vec<Vec2>)>,
}

impl Expansion {
    /// The smallest generated block: name and area.
    pub fn smallest(&self) -> Option<(&str, f64)> {
        let i = (0..self.areas.len()).min_by(|&a, &b| self.areas[a].total_cmp(&self.areas[b]))?;
        Some((self.blocks[i].as_str(), self.areas[i]))
    }
}

fn at<T>(span: &Range<usize>, value: T) -> Spanned<T> {
    Spanned::new(span.clone(), value)
}

/// An excavation stays in the model, its blocks tagged, when a stage removes it: its own `stage`
/// key, or a `[[stage]] remove` that names it; else it is removed before t = 0.
fn staged(raw: &raw::Scene, x: &raw::Excavation) -> bool {
    let name = x.name.get_ref();
    let removes = |s: &Spanned<raw::Stage>| {
        s.get_ref().remove.as_ref().is_some_and(|r| r.get_ref().iter().any(|n| n.get_ref() == name))
    };
    x.stage.is_some() || raw.stage.iter().any(removes)
}

/// Expands `[domain]` (if any) into `raw.body`; errors name the rock-mass keys.
pub(super) fn expand(raw: &mut raw::Scene) -> Check<Expansion> {
    let Some(domain) = &raw.domain else {
        return without_domain(raw);
    };
    let (header, d) = (domain.span(), domain.get_ref());
    let outline = simple_polygon(&d.vertices, "vertices")?;
    let keys = domain_keys(d, &header)?;
    let domain_shape = Shape::Polygon { vertices: outline.clone() };
    let inside = |p: Vec2| domain_shape.contains(p);
    let joint_sets = joint_sets(raw, &outline)?;
    let joints = joints(raw, &inside)?;
    let excavations = excavations(raw, &inside)?;
    let mut out = Expansion::default();
    let names = raw.excavation.iter().map(|x| x.get_ref().name.get_ref().clone());
    let outline_of = |x: &rm::Excavation| x.vertices.iter().map(|v| Vec2::new(v[0], v[1])).collect();
    out.outlines = names.zip(excavations.iter().map(outline_of)).collect();
    let spec = rm::CutSpec {
        domain: outline.iter().map(|v| [v.x, v.y]).collect(),
        joint_sets,
        joints,
        excavations,
        min_edge: keys.min_edge,
        seed: keys.seed,
        block_limit: keys.block_limit,
    };
    let cut = rm::cut(&spec).or_else(|e| fail(cut_error_span(raw, &header, &e), e.to_string()))?;
    out.reports = cut.reports.iter().map(ToString::to_string).collect();
    let mut generated = block_bodies(raw, d, &header, &keys, &cut.blocks, &mut out)?;
    fix_points(d, &cut.blocks, &mut generated)?;
    for (e, x) in raw.excavation.iter().enumerate() {
        if staged(raw, x.get_ref()) {
            let inside = cut.blocks.iter().enumerate().filter(|(_, b)| b.excavation == Some(e));
            let names = inside.map(|(k, _)| out.blocks[k].clone()).collect();
            out.staged.push((x.get_ref().name.get_ref().clone(), names));
        }
    }
    raw.body.get_mut().extend(generated);
    Ok(out)
}

/// A scene without `[domain]`: joints and regions are errors; an excavation is one only when
/// a stage removes its `bodies`.
fn without_domain(raw: &raw::Scene) -> Check<Expansion> {
    if let Some(t) = raw.joint_set.first().map(Spanned::span).or(raw.joint.first().map(Spanned::span)) {
        return fail(t, "joints need a [domain] to cut");
    }
    let mut out = Expansion::default();
    for x in &raw.excavation {
        let (header, x) = (x.span(), x.get_ref());
        match (&x.bodies, staged(raw, x)) {
            (Some(b), true) => {
                let names = b.get_ref().iter().map(|n| n.get_ref().clone()).collect();
                out.staged.push((x.name.get_ref().clone(), names));
            }
            _ => return fail(header, "an [[excavation]] needs a [domain] (or, staged, its `bodies`)"),
        }
    }
    if let Some(r) = raw.region.first() {
        return fail(r.span(), "a [[region]] needs a [domain]");
    }
    Ok(out)
}

/// The `[domain]` keys that shape the cut and its bodies, checked (defaults of scene-format
/// "Rock masses").
struct DomainKeys {
    /// "rigid", "deformable" or "mesh".
    model: &'static str,
    mesh_size: Option<f64>,
    seed: u64,
    min_edge: f64,
    block_limit: usize,
}

fn domain_keys(d: &raw::Domain, header: &Range<usize>) -> Check<DomainKeys> {
    let model = match &d.model {
        None => "rigid",
        Some(m) => match m.get_ref().as_str() {
            "rigid" => "rigid",
            "deformable" => "deformable",
            "mesh" => "mesh",
            other => {
                let message =
                    format!("model must be \"rigid\", \"deformable\" or \"mesh\" (got \"{other}\")");
                return fail(m.span(), message);
            }
        },
    };
    let mesh_size = match (&d.mesh_size, model) {
        (Some(s), "mesh") => Some(positive(s, "mesh_size")?),
        (None, "mesh") => return fail(header.clone(), "a [domain] with model = \"mesh\" needs `mesh_size`"),
        (Some(s), _) => return fail(s.span(), "mesh_size is only for model = \"mesh\""),
        (None, _) => None,
    };
    let seed = match &d.seed {
        Some(s) => u64::try_from(*s.get_ref()).or_else(|_| fail(s.span(), "seed must not be negative"))?,
        None => 1,
    };
    let min_edge = match &d.min_edge {
        Some(m) => non_negative(m, "min_edge")?,
        None => 1e-3,
    };
    let block_limit = match &d.block_limit {
        Some(n) => match usize::try_from(*n.get_ref()) {
            Ok(n) if n >= 1 => n,
            _ => return fail(n.span(), format!("block_limit must be at least 1 (got {})", n.get_ref())),
        },
        None => 100_000,
    };
    Ok(DomainKeys { model, mesh_size, seed, min_edge, block_limit })
}

/// The `[[body]]` tables of the cut's blocks (`blk-N`), recorded in `out` (names, areas,
/// meshes, edges).
fn block_bodies(
    raw: &raw::Scene,
    d: &raw::Domain,
    header: &Range<usize>,
    keys: &DomainKeys,
    blocks: &[rm::Block],
    out: &mut Expansion,
) -> Check<Vec<Spanned<raw::Body>>> {
    let tags = edge_tags(raw);
    let model = keys.model;
    let mut generated = Vec::with_capacity(blocks.len());
    for (k, block) in blocks.iter().enumerate() {
        let name = format!("blk-{}", k + 1);
        let (material, fixed) = region_of(raw, d, block)?;
        let mut body = block_body(&name, block, material, fixed, header);
        body.model = (model != "mesh" && model != "rigid").then(|| at(header, model.to_owned()));
        body.edge_interfaces = tagged(&block.edges, &tags, header);
        if let Some(size) = keys.mesh_size {
            let mesh = rm::mesh_block(block, size).or_else(|e| fail(header.clone(), e.to_string()))?;
            let fe = rm::to_mesh(&mesh, &super::expanded::edge_group, &name)
                .or_else(|e| fail(header.clone(), e.to_string()))?;
            body.shape = at(header, "mesh".to_owned());
            body.vertices = None;
            body.edge_interfaces = tagged(&mesh.loop_sources(), &tags, header);
            body.generated_mesh = Some(fe);
            out.meshes.push((name.clone(), mesh));
        }
        for (i, source) in block.edges.iter().enumerate() {
            let (a, b) = (block.vertices[i], block.vertices[(i + 1) % block.vertices.len()]);
            out.edges.push(([a, b], *source));
        }
        out.blocks.push(name);
        out.areas.push(block.area);
        generated.push(at(header, body));
    }
    Ok(generated)
}

/// A simple polygon's vertices (either orientation), counter-clockwise.
fn simple_polygon(v: &Spanned<Vec<Vec<f64>>>, key: &str) -> Check<Vec<Vec2>> {
    let mut points = Vec::with_capacity(v.get_ref().len());
    for (i, p) in v.get_ref().iter().enumerate() {
        let [x, y] = numbers(p, v.span(), &format!("{key}[{i}]"))?;
        points.push(Vec2::new(x, y));
    }
    if let Err(defect) = check_simple_polygon(&points) {
        return fail(v.span(), super::check::defect_message(&defect, points.len()));
    }
    if signed_area2(&points) < 0.0 {
        points.reverse();
    }
    Ok(points)
}

fn pair(v: &Spanned<Vec<f64>>, key: &str) -> Check<[f64; 2]> {
    numbers(v.get_ref(), v.span(), key)
}

fn optional_non_negative(v: &Option<Spanned<f64>>, key: &str) -> Check<f64> {
    v.as_ref().map_or(Ok(0.0), |v| non_negative(v, key))
}

/// An interface name that a `[[interface]] name` defines.
fn known_interface(raw: &raw::Scene, name: &Option<Spanned<String>>) -> Check<()> {
    let Some(name) = name else { return Ok(()) };
    let defines = |i: &Spanned<raw::Interface>| {
        i.get_ref().name.as_ref().is_some_and(|n| n.get_ref() == name.get_ref())
    };
    if raw.interface.iter().any(defines) {
        return Ok(());
    }
    fail(name.span(), format!("unknown interface \"{}\" (no [[interface]] has this name)", name.get_ref()))
}

fn joint_sets(raw: &raw::Scene, outline: &[Vec2]) -> Check<Vec<rm::JointSet>> {
    let mut sets = Vec::with_capacity(raw.joint_set.len());
    for s in &raw.joint_set {
        let s = s.get_ref();
        known_interface(raw, &s.interface)?;
        known_interface(raw, &s.bridge_interface)?;
        let bridges = match &s.bridges {
            None => rm::Bridges::Remove,
            Some(b) => match b.get_ref().as_str() {
                "remove" => rm::Bridges::Remove,
                "cemented" => rm::Bridges::Cemented,
                other => {
                    let message = format!("bridges must be \"remove\" or \"cemented\" (got \"{other}\")");
                    return fail(b.span(), message);
                }
            },
        };
        if let (Some(b), rm::Bridges::Remove) = (&s.bridge_interface, &bridges) {
            return fail(b.span(), "bridge_interface is only for bridges = \"cemented\"");
        }
        let origin = match &s.origin {
            Some(o) => pair(o, "origin")?,
            None => [outline[0].x, outline[0].y],
        };
        sets.push(rm::JointSet {
            angle: real(&s.angle, "angle", "be finite", |_| true)?,
            spacing: positive(&s.spacing, "spacing")?,
            origin,
            trace: optional_non_negative(&s.trace, "trace")?,
            gap: optional_non_negative(&s.gap, "gap")?,
            angle_dev: optional_non_negative(&s.angle_dev, "angle_dev")?,
            spacing_dev: optional_non_negative(&s.spacing_dev, "spacing_dev")?,
            trace_dev: optional_non_negative(&s.trace_dev, "trace_dev")?,
            gap_dev: optional_non_negative(&s.gap_dev, "gap_dev")?,
            bridges,
        });
    }
    Ok(sets)
}

fn joints(raw: &raw::Scene, inside: &dyn Fn(Vec2) -> bool) -> Check<Vec<rm::Joint>> {
    let mut list = Vec::with_capacity(raw.joint.len());
    for j in &raw.joint {
        known_interface(raw, &j.get_ref().interface)?;
        let points = &j.get_ref().points;
        let mut trace = Vec::with_capacity(points.get_ref().len());
        for (i, p) in points.get_ref().iter().enumerate() {
            let [x, y] = numbers(p, points.span(), &format!("points[{i}]"))?;
            if !inside(Vec2::new(x, y)) {
                return fail(points.span(), format!("points[{i}] = ({x}, {y}) lies outside the [domain]"));
            }
            trace.push([x, y]);
        }
        if trace.len() < 2 {
            return fail(points.span(), format!("a joint needs at least 2 points (got {})", trace.len()));
        }
        list.push(rm::Joint { points: trace });
    }
    Ok(list)
}

fn excavations(raw: &raw::Scene, inside: &dyn Fn(Vec2) -> bool) -> Check<Vec<rm::Excavation>> {
    let mut list = Vec::with_capacity(raw.excavation.len());
    let mut seen = std::collections::HashMap::new();
    for (i, x) in raw.excavation.iter().enumerate() {
        let (header, x) = (x.span(), x.get_ref());
        if let Some(b) = &x.bodies {
            return fail(b.span(), "an excavation of a [domain] is given by its geometry, not `bodies`");
        }
        if let Some(first) = seen.insert(x.name.get_ref().as_str(), i) {
            let message = format!(
                "duplicate excavation name \"{}\" (already used by excavation[{first}])",
                x.name.get_ref()
            );
            return fail(x.name.span(), message);
        }
        let (vertices, span) = match (&x.vertices, &x.center, &x.radius) {
            (Some(v), None, None) => (simple_polygon(v, "vertices")?, v.span()),
            (None, Some(c), Some(r)) => {
                let center = pair(c, "center")?;
                let radius = positive(r, "radius")?;
                let segments = match &x.segments {
                    Some(s) if (3..=100_000).contains(s.get_ref()) => *s.get_ref() as usize,
                    Some(s) => {
                        return fail(
                            s.span(),
                            format!("segments must be from 3 to 100000 (got {})", s.get_ref()),
                        );
                    }
                    None => 24,
                };
                let circle = rm::circle(center, radius, segments);
                (circle.iter().map(|p| Vec2::new(p[0], p[1])).collect(), c.span())
            }
            (Some(v), _, _) => {
                return fail(v.span(), "give either `vertices` or `center` and `radius`, not both");
            }
            _ => return fail(header, "an excavation needs `vertices`, or `center` and `radius`"),
        };
        if let Some(p) = vertices.iter().find(|p| !inside(**p)) {
            return fail(
                span,
                format!(
                    "excavation \"{}\" reaches outside the [domain] at ({}, {})",
                    x.name.get_ref(),
                    p.x,
                    p.y
                ),
            );
        }
        list.push(rm::Excavation {
            vertices: vertices.iter().map(|v| [v.x, v.y]).collect(),
            keep: staged(raw, x),
        });
    }
    Ok(list)
}

/// Where a cut error points: the item it names (the spacing of a set that makes too many
/// blocks), else the domain.
fn cut_error_span(raw: &raw::Scene, header: &Range<usize>, e: &rm::CutError) -> Range<usize> {
    let span = match e {
        rm::CutError::TooManyBlocks { set, .. } => {
            raw.joint_set.get(*set).map(|s| s.get_ref().spacing.span())
        }
        rm::CutError::Set { set, .. } => raw.joint_set.get(*set).map(Spanned::span),
        rm::CutError::Joint { joint, .. } => raw.joint.get(*joint).map(Spanned::span),
        rm::CutError::Excavation { excavation, .. } => raw.excavation.get(*excavation).map(Spanned::span),
        rm::CutError::MinEdge(_) => {
            raw.domain.as_ref().and_then(|d| d.get_ref().min_edge.as_ref().map(Spanned::span))
        }
        _ => None,
    };
    span.unwrap_or_else(|| header.clone())
}

/// The interface name each edge source carries ("" for none).
struct Tags {
    sets: Vec<String>,
    bridges: Vec<String>,
    joints: Vec<String>,
}

fn edge_tags(raw: &raw::Scene) -> Tags {
    let name = |n: &Option<Spanned<String>>| n.as_ref().map_or(String::new(), |n| n.get_ref().clone());
    Tags {
        sets: raw.joint_set.iter().map(|s| name(&s.get_ref().interface)).collect(),
        bridges: raw.joint_set.iter().map(|s| name(&s.get_ref().bridge_interface)).collect(),
        joints: raw.joint.iter().map(|j| name(&j.get_ref().interface)).collect(),
    }
}

/// The block's `edge_interfaces`; `None` when no edge carries one.
fn tagged(edges: &[EdgeSource], tags: &Tags, span: &Range<usize>) -> Option<Spanned<Vec<Spanned<String>>>> {
    let tag = |e: &EdgeSource| match e {
        EdgeSource::Set(k) => tags.sets[*k].clone(),
        EdgeSource::Bridge(k) => tags.bridges[*k].clone(),
        EdgeSource::Joint(k) => tags.joints[*k].clone(),
        EdgeSource::Outline | EdgeSource::Excavation(_) | EdgeSource::Seam => String::new(),
    };
    let list: Vec<String> = edges.iter().map(tag).collect();
    list.iter().any(|t| !t.is_empty()).then(|| at(span, list.into_iter().map(|t| at(span, t)).collect()))
}

/// The material name (with the span it comes from) and `fixed` of a block: the domain's,
/// unless the centroid lies in `[[region]]`s (the last one wins).
fn region_of(raw: &raw::Scene, d: &raw::Domain, block: &rm::Block) -> Check<(Spanned<String>, bool)> {
    let mut material = d.material.clone();
    let mut fixed = false;
    let c = Vec2::new(block.centroid[0], block.centroid[1]);
    for r in &raw.region {
        let r = r.get_ref();
        let vertices = simple_polygon(&r.vertices, "vertices")?;
        if (Shape::Polygon { vertices }).contains(c) {
            if let Some(m) = &r.material {
                material = m.clone();
            }
            if let Some(f) = &r.fixed {
                fixed = *f.get_ref();
            }
        }
    }
    Ok((material, fixed))
}

fn block_body(
    name: &str,
    block: &rm::Block,
    material: Spanned<String>,
    fixed: bool,
    span: &Range<usize>,
) -> raw::Body {
    let vertices = block.vertices.iter().map(|v| v.to_vec()).collect();
    raw::Body {
        name: at(span, name.to_owned()),
        shape: at(span, "polygon".to_owned()),
        center: None,
        radius: None,
        inner_radius: None,
        vertices: Some(at(span, vertices)),
        file: None,
        physical: None,
        fixed_nodes: None,
        fixed_x_nodes: None,
        fixed_y_nodes: None,
        scale: None,
        offset: None,
        model: None,
        material,
        fixed,
        velocity: None,
        angular_velocity: None,
        initial_stress: None,
        edge_interfaces: None,
        generated_mesh: None,
    }
}

/// `fixed_points`: the block holding each point is fixed.
fn fix_points(d: &raw::Domain, blocks: &[rm::Block], bodies: &mut [Spanned<raw::Body>]) -> Check<()> {
    let Some(points) = &d.fixed_points else { return Ok(()) };
    for (i, p) in points.get_ref().iter().enumerate() {
        let [x, y] = numbers(p, points.span(), &format!("fixed_points[{i}]"))?;
        let holds = |b: &rm::Block| {
            let vertices = b.vertices.iter().map(|v| Vec2::new(v[0], v[1])).collect();
            (Shape::Polygon { vertices }).contains(Vec2::new(x, y))
        };
        match blocks.iter().position(holds) {
            Some(k) => bodies[k].get_mut().fixed = true,
            None => return fail(points.span(), format!("fixed_points[{i}] = ({x}, {y}) lies in no block")),
        }
    }
    Ok(())
}
