//! What a sweep runs: the swept keys and their values, the grid (or zip) of cases, the study
//! file `sweep.toml`, the `--exact` quantity and the size of a case.

use crate::model::{Model, Shape};
use crate::scene::Override;
use miette::{Result, miette};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// One swept key and its values (TOML literals or bare strings, as `--set` takes them).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Axis {
    pub key: String,
    pub values: Vec<String>,
}

impl Axis {
    /// `KEY=V1,V2,...` as one axis.
    pub fn from_override(ov: &Override) -> Axis {
        Axis { key: ov.key.clone(), values: split_values(&ov.value) }
    }
}

/// One case: its index in the grid and the swept keys' values.
#[derive(Debug, Clone, PartialEq)]
pub struct Case {
    pub index: usize,
    pub set: Vec<Override>,
}

impl Case {
    /// `k1=v1 k2=v2`, as the table and error messages name the case.
    pub fn label(&self) -> String {
        self.set.iter().map(|o| o.to_string()).collect::<Vec<_>>().join(" ")
    }
}

/// Splits `V1,V2,...` at the commas outside brackets, braces and quotes.
pub fn split_values(text: &str) -> Vec<String> {
    let (mut out, mut cur, mut depth, mut quote) = (Vec::new(), String::new(), 0i32, None);
    for c in text.chars() {
        match (c, quote) {
            ('"' | '\'', None) => quote = Some(c),
            (q, Some(open)) if q == open => quote = None,
            ('[' | '{', None) => depth += 1,
            (']' | '}', None) => depth -= 1,
            (',', None) if depth == 0 => {
                out.push(cur.trim().to_owned());
                cur.clear();
                continue;
            }
            _ => {}
        }
        cur.push(c);
    }
    out.push(cur.trim().to_owned());
    out.retain(|v| !v.is_empty());
    out
}

/// The cases of `axes`: every combination (the first key slowest), or with `zip` the i-th
/// value of every key together. An empty grid and a zip of unequal lengths are errors.
pub fn grid(axes: &[Axis], zip: bool) -> Result<Vec<Case>> {
    if axes.is_empty() {
        return Err(miette!("empty grid: no key to sweep (give --set KEY=V1,V2,... with several values)"));
    }
    if let Some(a) = axes.iter().find(|a| a.values.is_empty()) {
        return Err(miette!("empty grid: the swept key `{}` has no values", a.key));
    }
    let mut cases: Vec<Vec<Override>> = vec![Vec::new()];
    if zip {
        let n = axes[0].values.len();
        if let Some(a) = axes.iter().find(|a| a.values.len() != n) {
            return Err(miette!(
                "--zip pairs the values element-wise, but `{}` has {} values and `{}` has {}",
                axes[0].key,
                n,
                a.key,
                a.values.len()
            ));
        }
        cases = (0..n)
            .map(|i| {
                axes.iter().map(|a| Override { key: a.key.clone(), value: a.values[i].clone() }).collect()
            })
            .collect();
    } else {
        for a in axes {
            cases = cases
                .into_iter()
                .flat_map(|c| {
                    a.values.iter().map(move |v| {
                        let mut c = c.clone();
                        c.push(Override { key: a.key.clone(), value: v.clone() });
                        c
                    })
                })
                .collect();
        }
    }
    Ok(cases.into_iter().enumerate().map(|(index, set)| Case { index, set }).collect())
}

/// How a case's size h is found: the value itself (`time.step`, `solver.tolerance`,
/// `domain.mesh_size`), or the mean edge length of the model's meshes (a key ending in `.file`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SizeKind {
    Value,
    MeshEdge,
}

/// The size kind of a key, if it has one.
pub fn size_kind(key: &str) -> Option<SizeKind> {
    match key {
        "time.step" | "solver.tolerance" | "domain.mesh_size" => Some(SizeKind::Value),
        k if k.ends_with(".file") => Some(SizeKind::MeshEdge),
        _ => None,
    }
}

/// Mean edge length over every triangle's three edges, over every mesh body of `model`
/// (an edge inside a mesh counts once for each of its two triangles); None without meshes.
pub fn mean_edge(model: &Model) -> Option<f64> {
    let (mut sum, mut n) = (0.0, 0usize);
    for body in &model.bodies {
        if let Shape::Mesh(m) = &body.shape {
            for t in &m.mesh.triangles {
                for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                    sum += (m.mesh.nodes[a] - m.mesh.nodes[b]).norm();
                    n += 1;
                }
            }
        }
    }
    (n > 0).then(|| sum / n as f64)
}

/// A known answer: `monitor.NAME.COMPONENT=VALUE`, COMPONENT one of x, y (final position) or
/// ux, uy (displacement).
#[derive(Debug, Clone, PartialEq)]
pub struct Exact {
    pub monitor: String,
    pub component: String,
    pub value: f64,
}

impl Exact {
    pub fn parse(text: &str) -> Result<Exact> {
        let bad = |why: &str| {
            miette!(
                "--exact {text}: {why}; expected monitor.NAME.COMPONENT=VALUE, e.g. monitor.tip.uy=-4.031e-4"
            )
        };
        let (quantity, value) = text.split_once('=').ok_or_else(|| bad("no `=`"))?;
        let value: f64 = value.trim().parse().map_err(|_| bad("the value is not a number"))?;
        let rest = quantity
            .trim()
            .strip_prefix("monitor.")
            .ok_or_else(|| bad("the quantity must start with `monitor.`"))?;
        let (monitor, component) = rest.rsplit_once('.').ok_or_else(|| bad("no component"))?;
        if !["x", "y", "ux", "uy"].contains(&component) {
            return Err(bad(&format!("unknown component `{component}` (x, y, ux or uy)")));
        }
        Ok(Exact { monitor: monitor.to_owned(), component: component.to_owned(), value })
    }

    /// `monitor.NAME.COMPONENT`.
    pub fn quantity(&self) -> String {
        format!("monitor.{}.{}", self.monitor, self.component)
    }
}

impl std::fmt::Display for Exact {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}={}", self.quantity(), self.value)
    }
}

/// A sweep as a study file `sweep.toml` gives it (and as a plan stores it).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Study {
    /// Scene file; in a study file relative to the study file's folder.
    pub scene: String,
    /// Results folder for sweep.csv and sweep.png; in a study file relative to its folder.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub out: Option<String>,
    /// `KEY=VALUE` overrides applied to every case.
    #[serde(default)]
    pub set: Vec<String>,
    #[serde(default)]
    pub zip: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub exact: Option<String>,
    /// Sizes h of the values of the (single or first zipped) swept key, instead of measured ones.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sizes: Option<Vec<f64>>,
    pub sweep: Vec<Axis>,
}

/// The study file's form: values as TOML values.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct StudyFile {
    scene: String,
    out: Option<String>,
    #[serde(default)]
    set: Vec<String>,
    #[serde(default)]
    zip: bool,
    reference: Option<toml::Value>,
    exact: Option<String>,
    sizes: Option<Vec<f64>>,
    #[serde(default)]
    sweep: Vec<AxisFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct AxisFile {
    key: String,
    values: Vec<toml::Value>,
}

/// A TOML value as `--set` would take it: strings bare unless they would read as another type.
fn literal(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) if Override { key: String::new(), value: s.clone() }.literal() != *s => {
            s.clone()
        }
        other => other.to_string(),
    }
}

impl Study {
    /// Reads a study file; `scene` and `out` become paths usable from the current directory.
    pub fn read(path: &Path) -> Result<Study> {
        let shown = path.display();
        let text =
            std::fs::read_to_string(path).map_err(|e| miette!("{shown}: cannot read the study file: {e}"))?;
        let raw: StudyFile = toml::from_str(&text).map_err(|e| miette!("{shown}: {e}"))?;
        let dir = path.parent().unwrap_or(Path::new(""));
        let rel = |p: &str| dir.join(p).display().to_string();
        let sweep = raw
            .sweep
            .iter()
            .map(|a| Axis { key: a.key.clone(), values: a.values.iter().map(literal).collect() })
            .collect();
        Ok(Study {
            scene: rel(&raw.scene),
            out: raw.out.as_deref().map(rel),
            set: raw.set,
            zip: raw.zip,
            reference: raw.reference.as_ref().map(literal),
            exact: raw.exact,
            sizes: raw.sizes,
            sweep,
        })
    }

    /// The fixed overrides, parsed.
    pub fn base(&self) -> Result<Vec<Override>> {
        self.set.iter().map(|s| Override::parse(s).map_err(|e| miette!("set: {e}"))).collect()
    }
}

/// `I/N` of `--shard`: 0 <= I < N.
pub fn parse_shard(text: &str) -> Result<(usize, usize)> {
    let bad = |why: String| miette!("--shard {text}: {why}; expected I/N with 0 <= I < N, e.g. 0/4");
    let (i, n) = text.split_once('/').ok_or_else(|| bad("no `/`".into()))?;
    let i: usize = i.trim().parse().map_err(|_| bad(format!("`{i}` is not a shard index")))?;
    let n: usize = n.trim().parse().map_err(|_| bad(format!("`{n}` is not a shard count")))?;
    if n == 0 {
        return Err(bad("the shard count must be at least 1".into()));
    }
    if i >= n {
        return Err(bad(format!("shard index {i} is out of range for {n} shards (0 to {})", n - 1)));
    }
    Ok((i, n))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn axis(key: &str, values: &[&str]) -> Axis {
        Axis { key: key.into(), values: values.iter().map(|v| v.to_string()).collect() }
    }

    /// A grid of 2 keys x 3 values is their 3 x 3 = 9 combinations, the first key slowest; a zip pairs.
    #[test]
    fn grid_and_zip() {
        let axes = [axis("a", &["1", "2", "3"]), axis("b", &["x", "y", "z"])];
        let cases = grid(&axes, false).expect("grid");
        let labels: Vec<String> = cases.iter().map(Case::label).collect();
        assert_eq!(labels.len(), 9);
        assert_eq!(labels[..4], ["a=1 b=x", "a=1 b=y", "a=1 b=z", "a=2 b=x"]);
        assert_eq!(labels[8], "a=3 b=z");
        let zipped: Vec<String> = grid(&axes, true).expect("zip").iter().map(Case::label).collect();
        assert_eq!(zipped, vec!["a=1 b=x", "a=2 b=y", "a=3 b=z"]);
        let err = grid(&[axis("a", &["1"]), axis("b", &["1", "2"])], true).unwrap_err().to_string();
        assert!(err.contains("`a` has 1 values and `b` has 2"), "{err}");
        assert!(grid(&[], false).unwrap_err().to_string().starts_with("empty grid"));
        assert!(grid(&[axis("a", &[])], false).unwrap_err().to_string().contains("`a` has no values"));
    }

    #[test]
    fn exact_and_shard() {
        let e = Exact::parse("monitor.tip.uy=-4.031e-4").expect("exact");
        assert_eq!((e.monitor.as_str(), e.component.as_str(), e.value), ("tip", "uy", -4.031e-4));
        assert!(Exact::parse("tip.y=1").unwrap_err().to_string().contains("must start with `monitor.`"));
        assert!(Exact::parse("monitor.tip.z=1").unwrap_err().to_string().contains("unknown component `z`"));
        assert_eq!(parse_shard("1/2").expect("shard"), (1, 2));
        let e = parse_shard("2/2").unwrap_err().to_string();
        assert!(e.contains("shard index 2 is out of range for 2 shards"), "{e}");
    }
}
