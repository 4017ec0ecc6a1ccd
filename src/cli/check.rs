//! `pbdda check SCENE [--set KEY=VALUE]...`: validate a scene and print a summary.

use crate::model::{BodyModel, Model, Shape};
use crate::scene::{self, Override};
use crate::world::World;
use miette::Result;
use std::path::Path;

pub(super) fn check(scene_path: &Path, overrides: &[Override]) -> Result<()> {
    let model = scene::load_with(scene_path, overrides)?;
    out!("{}", summary(&model));
    if !overrides.is_empty() {
        return Ok(());
    }
    // the rock mass's blocks and every merge and join of its cut
    let file = scene_path.display().to_string();
    if let Ok(source) = std::fs::read_to_string(scene_path)
        && let Ok((_, expansion)) = scene::parse_expanded(&source, &file)
    {
        out!("{}", super::cut::report(&expansion));
    }
    Ok(())
}

/// The text `pbdda check` prints.
pub fn summary(model: &Model) -> String {
    let world = World::new(model.clone());
    let mut s = String::new();
    let t = &model.time;
    s += &format!("scene: {}\n", model.name);
    s += &format!("time: dt = {} s, {} steps, end = {} s\n", t.step, t.steps, t.step * t.steps as f64);
    let count = |f: &dyn Fn(&Shape) -> bool| model.bodies.iter().filter(|b| f(&b.shape)).count();
    s += &format!(
        "bodies: {} ({} disks, {} rings, {} polygons; {} fixed, {} deformable)\n",
        model.bodies.len(),
        count(&|sh| matches!(sh, Shape::Disk { .. })),
        count(&|sh| matches!(sh, Shape::Ring { .. })),
        count(&|sh| matches!(sh, Shape::Polygon { .. })),
        model.bodies.iter().filter(|b| b.fixed).count(),
        model.bodies.iter().filter(|b| b.model == BodyModel::Deformable).count(),
    );
    let mass: f64 = world.bodies.iter().filter(|b| !b.fixed).map(|b| b.mass).sum();
    s += &format!("free mass: {mass} kg/m\n");
    s += &format!(
        "materials: {}\n",
        model.materials.iter().map(|m| m.name.as_str()).collect::<Vec<_>>().join(", ")
    );
    for i in &model.interfaces {
        let pair = match (&i.name, i.materials) {
            (_, Some([a, b])) => format!("{} / {}", model.materials[a].name, model.materials[b].name),
            (Some(name), None) => format!("\"{name}\" (joints)"),
            (None, None) => "default".to_string(),
        };
        s += &format!(
            "interface {pair}: friction {}, cohesion {} Pa, tensile strength {} Pa, rolling {} m, restitution {}\n",
            i.friction, i.cohesion, i.tensile_strength, i.rolling, i.restitution
        );
    }
    let how = if model.contact.threshold.is_some() { "given" } else { "estimated: 0.1 x smallest feature" };
    s += &format!("contact threshold d0: {} m ({how})\n", world.threshold);
    s += &format!("loads: {}, monitors: {}\n", model.loads.len(), model.monitors.len());
    if !model.stages.is_empty() {
        let stages: Vec<String> =
            model.stages.iter().map(|st| format!("{} (to t = {} s)", st.name, st.end)).collect();
        s += &format!("stages: {}\n", stages.join(", "));
    }
    s
}
