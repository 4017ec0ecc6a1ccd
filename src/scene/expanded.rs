//! The expanded scene `pbdda cut` writes: the scene's own tables kept, the rock-mass tables
//! (`[domain]`, `[[joint_set]]`, `[[joint]]`, `[[excavation]]`, `[[region]]`) and
//! `[[bolt_pattern]]`s replaced by what they expand into: `[[body]]` polygons (or mesh bodies
//! whose `.msh` files go beside the scene), bolts and bolt segments as `[[connector]]`s, and
//! each staged excavation as an `[[excavation]]` naming its `bodies`. Read back, it gives the
//! same [`Model`] (comments of the original are not kept).

use toml::{Table, Value};

use super::raw;
use super::{Expansion, SceneError};
use crate::model::Model;
use crate::rockmass::{EdgeSource, write_msh};

/// What `pbdda cut` writes and prints.
pub struct Expanded {
    /// The expanded scene file.
    pub text: String,
    /// The `.msh` files of meshed blocks: file name (relative to the scene) and contents.
    pub meshes: Vec<(String, String)>,
    pub model: Model,
    pub expansion: Expansion,
}

/// The expanded scene of `source`; meshed blocks' files are named `STEM.blk-N.msh`.
pub fn expanded(source: &str, file: &str, stem: &str) -> Result<Expanded, SceneError> {
    let (raw, model, expansion) = super::parse_raw(source, file, true)?;
    let mut doc: Table = source.parse().map_err(|e: toml::de::Error| {
        SceneError::at(file, source, e.span().unwrap_or(0..0), String::new(), e.message().to_owned())
    })?;
    for key in ["domain", "joint_set", "joint", "excavation", "region", "bolt_pattern"] {
        doc.remove(key);
    }
    let own = doc.get("body").and_then(Value::as_array).map_or(0, Vec::len);
    let mut bodies = doc.remove("body").and_then(|b| b.as_array().cloned()).unwrap_or_default();
    let mut meshes = Vec::new();
    for b in &raw.body.get_ref()[own..] {
        let b = b.get_ref();
        let mut t = Table::new();
        t.insert("name".into(), b.name.get_ref().clone().into());
        if let Some((_, mesh)) = expansion.meshes.iter().find(|(n, _)| n == b.name.get_ref()) {
            let name = format!("{stem}.{}.msh", b.name.get_ref());
            t.insert("shape".into(), "mesh".into());
            t.insert("file".into(), name.clone().into());
            meshes.push((name, write_msh(mesh, &edge_group)));
        } else {
            t.insert("shape".into(), "polygon".into());
            let vertices = b.vertices.as_ref().map_or_else(Vec::new, |v| v.get_ref().clone());
            t.insert("vertices".into(), pairs(&vertices));
        }
        t.insert("material".into(), b.material.get_ref().clone().into());
        if let Some(m) = &b.model {
            t.insert("model".into(), m.get_ref().clone().into());
        }
        if b.fixed {
            t.insert("fixed".into(), true.into());
        }
        if let Some(tags) = &b.edge_interfaces {
            t.insert("edge_interfaces".into(), strings(tags.get_ref()));
        }
        bodies.push(Value::Table(t));
    }
    doc.insert("body".into(), Value::Array(bodies));
    let connectors: Vec<Value> = raw.connector.iter().map(|c| Value::Table(connector(c.get_ref()))).collect();
    doc.remove("connector");
    if !connectors.is_empty() {
        doc.insert("connector".into(), Value::Array(connectors));
    }
    let staged: Vec<Value> = expansion
        .staged
        .iter()
        .zip(raw.excavation.iter().filter(|x| x.get_ref().stage.is_some()))
        .map(|((name, blocks), x)| {
            let mut t = Table::new();
            t.insert("name".into(), name.clone().into());
            if let Some(s) = &x.get_ref().stage {
                t.insert("stage".into(), s.get_ref().clone().into());
            }
            t.insert("bodies".into(), Value::Array(blocks.iter().map(|b| b.clone().into()).collect()));
            Value::Table(t)
        })
        .collect();
    if !staged.is_empty() {
        doc.insert("excavation".into(), Value::Array(staged));
    }
    let text = toml::to_string(&doc)
        .map_err(|e| SceneError::at(file, source, 0..0, String::new(), e.to_string()))?;
    Ok(Expanded { text, meshes, model, expansion })
}

/// The physical group name of a meshed block's boundary edge.
pub(super) fn edge_group(source: &EdgeSource) -> String {
    match source {
        EdgeSource::Outline => "outline".to_owned(),
        EdgeSource::Excavation(k) => format!("excavation-{}", k + 1),
        EdgeSource::Set(k) => format!("set-{}", k + 1),
        EdgeSource::Joint(k) => format!("joint-{}", k + 1),
        EdgeSource::Bridge(k) => format!("bridge-{}", k + 1),
        EdgeSource::Seam => "seam".to_owned(),
    }
}

fn pairs(v: &[Vec<f64>]) -> Value {
    Value::Array(v.iter().map(|p| Value::Array(p.iter().map(|x| Value::Float(*x)).collect())).collect())
}

fn strings(v: &[toml::Spanned<String>]) -> Value {
    Value::Array(v.iter().map(|s| Value::String(s.get_ref().clone())).collect())
}

/// A `[[connector]]` table of the raw connector's keys.
fn connector(c: &raw::Connector) -> Table {
    let mut t = Table::new();
    if let Some(n) = &c.name {
        t.insert("name".into(), n.get_ref().clone().into());
    }
    t.insert("kind".into(), c.kind.get_ref().clone().into());
    let points: Vec<Vec<f64>> = c.points.get_ref().iter().map(|p| p.get_ref().clone()).collect();
    t.insert("points".into(), pairs(&points));
    if let Some(b) = &c.bodies {
        t.insert("bodies".into(), strings(b.get_ref()));
    }
    let numbers = c.numbers();
    for (key, value) in numbers {
        if let Some(v) = value {
            t.insert(key.into(), Value::Float(*v.get_ref()));
        }
    }
    if let Some(g) = &c.grouted {
        t.insert("grouted".into(), Value::Boolean(*g.get_ref()));
    }
    if let Some(s) = &c.stage {
        t.insert("stage".into(), s.get_ref().clone().into());
    }
    t
}
