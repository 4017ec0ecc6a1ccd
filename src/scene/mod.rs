//! Scene files (TOML, scene-format contract version 1) -> validated [`Model`].
//!
//! Reading goes in three steps:
//! 1. `toml` parses the text into a tree with byte spans; syntax errors fail here;
//! 2. serde fills the `raw` structs: unknown keys, wrong types and missing keys fail here;
//! 3. `check` validates values, names and shapes and builds the [`Model`].
//!
//! Any failure is a `Problem` at a byte span. A `KeyIndex`, the byte span and key path
//! (`body[2].radius`, array indices 0-based) of every key and array element, turns it into a
//! [`SceneError`] naming file, line, column and key.

mod bolts;
mod check;
mod connectors;
mod expanded;
mod interfaces;
mod limits;
mod mesh;
mod overlap;
pub mod overrides;
mod raw;
mod rockmass;
mod stages;
mod traction;

use std::cmp::Reverse;
use std::ops::Range;
use std::path::Path;

use serde::Deserialize;
use toml::de::{DeTable, DeValue, Deserializer};

pub use crate::error::SceneError;
use crate::model::{Excavation, Model};
pub use expanded::{Expanded, expanded};
pub use overrides::{Override, load_with, overridden_text, parse_with};
pub use rockmass::Expansion;

/// Reads and validates the scene file at `path`. Errors name the file as `path` displays.
pub fn load(path: &Path) -> Result<Model, SceneError> {
    let file = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| SceneError::unreadable(&file, &e))?;
    parse_bytes(&bytes, &file)
}

/// Validates the scene bytes `bytes`: text that is not UTF-8 is an error at the line and
/// column of the first bad byte; `file_name` is only used in error messages.
pub fn parse_bytes(bytes: &[u8], file_name: &str) -> Result<Model, SceneError> {
    match std::str::from_utf8(bytes) {
        Ok(source) => parse(source, file_name),
        Err(e) => {
            // the valid prefix locates the error; the bad bytes are shown replaced
            let at = e.valid_up_to();
            let source = String::from_utf8_lossy(bytes);
            let shown = String::from_utf8_lossy(&bytes[..at]).len();
            let bad = bytes[at..].iter().take(e.error_len().unwrap_or(1));
            let hex: Vec<String> = bad.map(|b| format!("0x{b:02x}")).collect();
            let message =
                format!("the scene file is not valid UTF-8 (byte {} at byte offset {at})", hex.join(" "));
            Err(SceneError::at(file_name, &source, shown..shown + 1, String::new(), message))
        }
    }
}

/// Validates the scene text `source`; `file_name` is only used in error messages.
pub fn parse(source: &str, file_name: &str) -> Result<Model, SceneError> {
    parse_raw(source, file_name, true).map(|(_, model, _)| model)
}

/// [`parse`], with what the rock-mass keys and bolt patterns expanded into (`pbdda check`).
pub fn parse_expanded(source: &str, file_name: &str) -> Result<(Model, Expansion), SceneError> {
    parse_raw(source, file_name, true).map(|(_, model, expansion)| (model, expansion))
}

/// [`parse`]; without `with_stages`, the `[[stage]]` tables are read but not checked further and
/// the model has none (the settings of a stage are read so: `stages.rs`).
fn read(source: &str, file_name: &str, with_stages: bool) -> Result<Model, SceneError> {
    parse_raw(source, file_name, with_stages).map(|(_, model, _)| model)
}

/// The raw scene after the expansion of its rock mass and bolts, the model and the expansion.
fn parse_raw(
    source: &str,
    file_name: &str,
    with_stages: bool,
) -> Result<(raw::Scene, Model, Expansion), SceneError> {
    let fail = |problem: Problem| problem.into_error(source, file_name);
    let toml_fail = |e: toml::de::Error| fail(Problem::from_toml(&e, source));
    let root = DeTable::parse(source).map_err(toml_fail)?;
    let mut raw = raw::Scene::deserialize(Deserializer::from(root)).map_err(toml_fail)?;
    let mut expansion = rockmass::expand(&mut raw).map_err(fail)?;
    expansion.connectors = bolts::expand(&mut raw, &expansion.outlines).map_err(fail)?;
    let dir = Path::new(file_name).parent().unwrap_or(Path::new(""));
    let mut model = check::model(&raw, dir).map_err(fail)?;
    let index: std::collections::HashMap<&str, usize> =
        model.bodies.iter().enumerate().map(|(i, b)| (b.name.as_str(), i)).collect();
    model.excavations = expansion
        .staged
        .iter()
        .map(|(name, blocks)| Excavation {
            name: name.clone(),
            bodies: blocks.iter().filter_map(|b| index.get(b.as_str()).copied()).collect(),
        })
        .collect();
    if with_stages {
        model.stages = stages::stages(&raw, source, file_name, &model)?;
    }
    Ok((raw, model, expansion))
}

/// What is wrong, and where: a byte span of the source.
#[derive(Debug)]
struct Problem {
    span: Range<usize>,
    message: String,
    /// A required key that is absent: the span is then its table, and the key path gets
    /// this key appended.
    missing: Option<String>,
}

impl Problem {
    fn new(span: Range<usize>, message: impl Into<String>) -> Self {
        Self { span, message: message.into(), missing: None }
    }

    fn missing(table: Range<usize>, key: &str, message: impl Into<String>) -> Self {
        Self { span: table, message: message.into(), missing: Some(key.to_owned()) }
    }

    /// A syntax error, or an unknown key, wrong type or missing key found by serde, which
    /// speaks of fields, sequences and f64; a scene file has keys, arrays and numbers.
    fn from_toml(e: &toml::de::Error, source: &str) -> Self {
        let span = e.span().unwrap_or(0..0);
        let mut message = e.message().trim_end().to_owned();
        for (serde_word, scene_word) in [
            ("unknown field", "unknown key"),
            ("missing field", "missing key"),
            ("a sequence", "an array"),
            ("expected f64", "expected a number"),
            ("expected i64", "expected a whole number"),
        ] {
            message = message.replace(serde_word, scene_word);
        }
        if message == "duplicate key"
            && let Some(key) = source.get(span.clone())
        {
            message = format!("duplicate key `{key}`");
        }
        let missing =
            message.strip_prefix("missing key `").and_then(|rest| rest.split('`').next()).map(str::to_owned);
        Self { span, message, missing }
    }

    /// The error with line, column and key path. Only failures pay for the key index: the
    /// source is parsed again to build it.
    fn into_error(self, source: &str, file: &str) -> SceneError {
        let keys = KeyIndex::new(DeTable::parse_recoverable(source).0.get_ref());
        let entry = keys.innermost(&self.span);
        let mut key = entry.map_or(String::new(), |e| e.path.clone());
        if let Some(missing) = self.missing {
            key = if key.is_empty() { missing } else { format!("{key}.{missing}") };
        }
        // point at the whole `key = value` (so the column is the key's), else at the span itself
        let span = entry.map_or(self.span, |e| e.span.clone());
        SceneError::at(file, source, span, key, self.message)
    }
}

/// Byte span and key path of every key (`key = value` as a whole; a table's header) and array
/// element of a document.
struct KeyIndex {
    entries: Vec<KeyEntry>,
}

struct KeyEntry {
    span: Range<usize>,
    path: String,
    depth: usize,
}

impl KeyIndex {
    fn new(root: &DeTable) -> Self {
        let mut index = Self { entries: Vec::new() };
        index.add_table(root, "", 0);
        index
    }

    fn add_table(&mut self, table: &DeTable, prefix: &str, depth: usize) {
        for (key, value) in table.iter() {
            let path = match prefix {
                "" => key.get_ref().to_string(),
                _ => format!("{prefix}.{}", key.get_ref()),
            };
            let (k, v) = (key.span(), value.span());
            let span = k.start.min(v.start)..k.end.max(v.end);
            self.add(span, path, value.get_ref(), depth);
        }
    }

    fn add(&mut self, span: Range<usize>, path: String, value: &DeValue, depth: usize) {
        match value {
            DeValue::Table(table) => self.add_table(table, &path, depth + 1),
            DeValue::Array(items) => {
                for (i, item) in items.iter().enumerate() {
                    let item_path = format!("{path}[{i}]");
                    self.add(item.span(), item_path, item.get_ref(), depth + 1);
                }
            }
            _ => {}
        }
        self.entries.push(KeyEntry { span, path, depth });
    }

    /// The smallest entry that contains all of `span` (the deeper one on a tie, e.g. an array
    /// of tables and its first element share the first header). None for an empty span.
    fn innermost(&self, span: &Range<usize>) -> Option<&KeyEntry> {
        if span.is_empty() {
            return None;
        }
        self.entries
            .iter()
            .filter(|e| e.span.start <= span.start && span.end <= e.span.end)
            .min_by_key(|e| (e.span.len(), Reverse(e.depth)))
    }
}

#[cfg(test)]
mod tests;
