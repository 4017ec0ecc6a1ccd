//! Mesh bodies of a scene (`shape = "mesh"`, math note §9): the gmsh file relative to the scene
//! file, the physical surface, `fixed_nodes`, `fixed_x_nodes`, `fixed_y_nodes` (rollers), `scale`
//! and `offset`. A mesh error is a scene error at
//! the key that led to it, and its message names the mesh file and the mesh file's own line.

use std::ops::Range;
use std::path::Path;

use toml::Spanned;

use super::check::{Check, fail, need, real, vec2};
use super::raw;
use crate::geometry::Vec2;
use crate::mesh::Mesh;
use crate::mesh::loops::boundary_loops;
use crate::model::{BodyModel, Material, MeshShape, Shape};

/// The shape of a mesh body: reads the file, selects the surface, applies scale and offset and
/// resolves the `fixed_nodes` groups.
pub(super) fn shape(b: &raw::Body, header: &Range<usize>, dir: &Path) -> Check<Shape> {
    if let Some(mesh) = &b.generated_mesh {
        let shape =
            crate::model::MeshShape { mesh: mesh.clone(), fixed_nodes: Vec::new(), rollers: Vec::new() };
        return Ok(Shape::Mesh(Box::new(shape)));
    }
    let file = need(b, header, &b.file, "file")?;
    let path = dir.join(file.get_ref());
    let mesh = Mesh::read(&path).map_err(|e| problem(file.span(), &e))?;
    let mesh = match &b.physical {
        Some(p) => mesh.select_surface(Some(p.get_ref())).map_err(|e| problem(p.span(), &e))?,
        None => mesh,
    };
    let scale = match &b.scale {
        Some(s) => real(s, "scale", "be a non-zero number", |x| x != 0.0)?,
        None => 1.0,
    };
    let offset = match &b.offset {
        Some(o) => vec2(o, "offset")?,
        None => Vec2::zeros(),
    };
    let mesh = mesh.transformed(scale, offset);
    let fixed_nodes = node_groups(&mesh, &b.fixed_nodes)?;
    let mut rollers: Vec<(usize, usize)> = [&b.fixed_x_nodes, &b.fixed_y_nodes]
        .into_iter()
        .enumerate()
        .map(|(c, groups)| Ok(node_groups(&mesh, groups)?.into_iter().map(move |n| (n, c))))
        .collect::<Check<Vec<_>>>()?
        .into_iter()
        .flatten()
        .filter(|(n, _)| fixed_nodes.binary_search(n).is_err())
        .collect();
    rollers.sort_unstable();
    if let Err(e) = boundary_loops(&mesh.nodes, &mesh.triangles) {
        return fail(file.span(), format!("{}: the mesh boundary is unusable: {e}", mesh.file));
    }
    if fixed_nodes.len() == mesh.nodes.len() {
        let span = b.fixed_nodes.as_ref().map_or(file.span(), Spanned::span);
        return fail(span, "fixed_nodes fixes every node of the mesh: use `fixed = true` instead");
    }
    if 2 * (mesh.nodes.len() - fixed_nodes.len()) == rollers.len() {
        let span = b.fixed_y_nodes.as_ref().or(b.fixed_x_nodes.as_ref()).map_or(file.span(), Spanned::span);
        return fail(
            span,
            "fixed_x_nodes and fixed_y_nodes fix every node of the mesh: use `fixed = true` instead",
        );
    }
    Ok(Shape::Mesh(Box::new(MeshShape { mesh, fixed_nodes, rollers })))
}

/// The sorted nodes of the named physical groups (`fixed_nodes`, `fixed_x_nodes`,
/// `fixed_y_nodes`); an unknown or empty group is an error at its name.
fn node_groups(mesh: &Mesh, groups: &Option<Spanned<Vec<Spanned<String>>>>) -> Check<Vec<usize>> {
    let Some(groups) = groups else { return Ok(Vec::new()) };
    // each group on its own, so that an error points at the group it names
    for g in groups.get_ref() {
        mesh.node_set(&[g.get_ref().as_str()]).map_err(|e| problem(g.span(), &e))?;
    }
    let keys: Vec<&str> = groups.get_ref().iter().map(|g| g.get_ref().as_str()).collect();
    mesh.node_set(&keys).map_err(|e| problem(groups.span(), &e))
}

/// A mesh body is always finite elements: `model`, if given, must be "deformable", and the
/// material needs `young` and `poisson`.
pub(super) fn model(b: &raw::Body, material: &Material) -> Check<BodyModel> {
    if let Some(m) = &b.model
        && m.get_ref() != "deformable"
    {
        return fail(
            m.span(),
            "a mesh body is always finite elements: model must be \"deformable\" or absent",
        );
    }
    if material.young.is_none() || material.poisson.is_none() {
        let name = &material.name;
        return fail(
            b.material.span(),
            format!("a mesh body needs `young` and `poisson` in material \"{name}\""),
        );
    }
    Ok(BodyModel::Deformable)
}

fn problem(span: Range<usize>, e: &crate::mesh::MeshError) -> super::Problem {
    super::Problem::new(span, e.to_string())
}
