//! `--set KEY=VALUE` overrides, applied to the scene's TOML text before it is read, so that
//! every check of the scene reader (types, ranges, names) and its error spans apply to an
//! overridden value exactly as to one written in the file.
//!
//! Keys are dotted paths as in the error messages of the scene reader:
//! - `time.step`, `solver.tolerance`, `output.every`, `physics.gravity` (tables);
//! - `body.d1.radius`, `material.rock.density`, `monitor.O.point`: an entry of an array of
//!   tables by its `name`; `body[3].radius`, `interface[0].friction`: by its 0-based index (as
//!   error messages name it); `physics.gravity[1]`: one element of an array value;
//! - `connector[*].strength`, `body[*].material`: the wildcard `[*]` stands for every entry of
//!   the array (the override is applied to each, in order); a wildcard over an array the scene
//!   does not have, or has empty, is an error.
//!
//! A value is a TOML literal (`1e-3`, `10`, `true`, `"text"`, `[0.0, -9.81]`); anything that
//! is not a TOML literal is taken as a string (`body.d1.model=deformable`). A key that is
//! absent from the file is added to its table, so an unknown key is rejected by the reader's
//! own check. `time.end` and `time.steps` are alternatives: setting one removes the other.
//!
//! An error caused by an override names it: `scene.toml:5:1: time.step: --set time.step=-1:
//! step must be positive (got -1)`. The line is that of the overridden key, or where an absent
//! key was added.

use std::ops::Range;
use std::path::Path;

use toml::de::{DeTable, DeValue};

use super::SceneError;
use crate::model::Model;

/// One `--set KEY=VALUE`.
#[derive(Debug, Clone, PartialEq)]
pub struct Override {
    /// Dotted key path, e.g. `time.step`, `body.d1.radius` or `body[3].radius`.
    pub key: String,
    /// The value as given (a TOML literal, or a bare string).
    pub value: String,
}

impl Override {
    /// Parses `KEY=VALUE` (the first `=` separates them).
    pub fn parse(text: &str) -> Result<Override, String> {
        let Some((key, value)) = text.split_once('=') else {
            return Err(format!("`{text}`: expected KEY=VALUE, e.g. time.step=1e-3"));
        };
        let (key, value) = (key.trim(), value.trim());
        if key.is_empty() || value.is_empty() {
            return Err(format!("`{text}`: expected KEY=VALUE with a non-empty key and value"));
        }
        Ok(Override { key: key.to_owned(), value: value.to_owned() })
    }

    /// The value as TOML text: the literal itself if it is one, else a quoted string.
    pub fn literal(&self) -> String {
        let probe = format!("v = {}", self.value);
        if !self.value.contains('\n') && probe.parse::<toml::Table>().is_ok() {
            return self.value.clone();
        }
        let escaped: String = self
            .value
            .chars()
            .flat_map(|c| match c {
                '"' => vec!['\\', '"'],
                '\\' => vec!['\\', '\\'],
                '\n' => vec!['\\', 'n'],
                c => vec![c],
            })
            .collect();
        format!("\"{escaped}\"")
    }
}

impl std::fmt::Display for Override {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}={}", self.key, self.value)
    }
}

impl std::str::FromStr for Override {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Override::parse(s)
    }
}

/// Reads the scene at `path` with `overrides` applied (in order; a later one wins).
pub fn load_with(path: &Path, overrides: &[Override]) -> Result<Model, SceneError> {
    let file = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| SceneError::unreadable(&file, &e))?;
    match String::from_utf8(bytes) {
        Ok(source) => parse_with(&source, &file, overrides),
        // not UTF-8: the reader's error names the line of the first bad byte
        Err(e) => super::parse_bytes(e.as_bytes(), &file),
    }
}

/// Validates the scene text `source` with `overrides` applied.
pub fn parse_with(source: &str, file: &str, overrides: &[Override]) -> Result<Model, SceneError> {
    read_with(source, file, overrides, true)
}

/// [`parse_with`] for a stage's `set` entries: the stages themselves are not read (`stages.rs`).
pub(super) fn stage_settings(source: &str, file: &str, overrides: &[Override]) -> Result<Model, SceneError> {
    read_with(source, file, overrides, false)
}

fn read_with(source: &str, file: &str, overrides: &[Override], stages: bool) -> Result<Model, SceneError> {
    if overrides.is_empty() || DeTable::parse(source).is_err() {
        // nothing to apply, or a syntax error of the file itself: the reader reports it
        return super::read(source, file, stages);
    }
    let mut text = source.to_owned();
    let mut edits: Vec<Edit> = Vec::new();
    let mut expanded = Vec::new();
    for ov in overrides {
        expanded.extend(expand(&text, ov).map_err(|(span, key, message)| {
            SceneError::at(file, &text, span, key, format!("--set {ov}: {message}"))
        })?);
    }
    for ov in &expanded {
        let edit = apply(&text, ov).map_err(|(span, key, message)| {
            SceneError::at(file, &text, span, key, format!("--set {ov}: {message}"))
        })?;
        text = edit.text.clone();
        edits.push(edit);
    }
    super::read(&text, file, stages).map_err(|e| blame(e, &text, file, &edits))
}

/// The scene text `source` with `overrides` applied (a wildcard expanded), as the reader of
/// [`parse_with`] sees it; an override that cannot be placed is an error naming it.
pub fn overridden_text(source: &str, file: &str, overrides: &[Override]) -> Result<String, SceneError> {
    let mut text = source.to_owned();
    for ov in overrides {
        let fail = |t: &str, (span, key, message): Misplaced| {
            SceneError::at(file, t, span, key, format!("--set {ov}: {message}"))
        };
        for one in expand(&text, ov).map_err(|m| fail(&text, m))? {
            text = apply(&text, &one).map_err(|m| fail(&text, m))?.text;
        }
    }
    Ok(text)
}

/// The overrides that `ov` stands for: itself, or, when its key holds the wildcard `[*]`, one
/// per entry of the array before the first `[*]` (recursively for later wildcards).
fn expand(text: &str, ov: &Override) -> Result<Vec<Override>, Misplaced> {
    let Some((prefix, rest)) = ov.key.split_once("[*]") else {
        return Ok(vec![ov.clone()]);
    };
    let root = DeTable::parse(text).map_err(|e| {
        (e.span().unwrap_or(0..0), String::new(), format!("the scene is not valid TOML: {}", e.message()))
    })?;
    let path = steps(prefix).map_err(|m| (0..0, ov.key.clone(), m))?;
    let nothing = || {
        (0..0, ov.key.clone(), format!("`{prefix}[*]` matches nothing: the scene has no `{prefix}` entries"))
    };
    let mut value: Option<&toml::Spanned<DeValue>> = None;
    for step in &path {
        let next = match (value.map(|v| v.get_ref()), step) {
            (None, Step::Key(k)) => root.get_ref().get(*k),
            (Some(DeValue::Table(t)), Step::Key(k)) => t.get(*k),
            (Some(DeValue::Array(items)), Step::Index(i)) => items.get(*i),
            (Some(DeValue::Array(items)), Step::Key(name)) => items
                .iter()
                .find(|v| v.get_ref().get("name").and_then(|n| n.get_ref().as_str()) == Some(*name)),
            _ => None,
        };
        value = Some(next.ok_or_else(nothing)?);
    }
    let n = match value.map(|v| v.get_ref()) {
        Some(DeValue::Array(items)) if !items.is_empty() => items.len(),
        Some(DeValue::Array(_)) | None => return Err(nothing()),
        Some(other) => {
            return Err((
                0..0,
                ov.key.clone(),
                format!("`{prefix}` is a {}, not an array", other.type_str()),
            ));
        }
    };
    let mut out = Vec::new();
    for i in 0..n {
        let one = Override { key: format!("{prefix}[{i}]{rest}"), value: ov.value.clone() };
        out.extend(expand(text, &one)?);
    }
    Ok(out)
}

/// The text after one override, and where it went.
struct Edit {
    text: String,
    ov: Override,
    /// Key path as the reader's errors name it (`body[0].radius`).
    path: String,
    /// Byte range of the new value (or of the added `key = value`) in `text`.
    span: Range<usize>,
    /// The key was absent and has been added with this many new lines (before `span`).
    added_lines: Option<usize>,
}

/// A failure to place an override: span in the text, key path, message.
type Misplaced = (Range<usize>, String, String);

/// One path step: a key, or a 0-based index.
enum Step<'a> {
    Key(&'a str),
    Index(usize),
}

fn steps(key: &str) -> Result<Vec<Step<'_>>, String> {
    let mut out = Vec::new();
    for part in key.split('.') {
        let (name, mut rest) = part.split_at(part.find('[').unwrap_or(part.len()));
        if name.is_empty() && out.is_empty() {
            return Err("the key must start with a name".into());
        }
        if !name.is_empty() {
            out.push(Step::Key(name));
        }
        while let Some(r) = rest.strip_prefix('[') {
            let (index, after) = r.split_once(']').ok_or("unclosed `[` in the key")?;
            out.push(Step::Index(index.parse().map_err(|_| format!("`[{index}]` is not an index"))?));
            rest = after;
        }
        if !rest.is_empty() {
            return Err(format!("unexpected `{rest}` in the key"));
        }
    }
    Ok(out)
}

/// Applies one override to `text`.
fn apply(text: &str, ov: &Override) -> Result<Edit, Misplaced> {
    let root = DeTable::parse(text).map_err(|e| {
        (e.span().unwrap_or(0..0), String::new(), format!("the scene is not valid TOML: {}", e.message()))
    })?;
    let steps = steps(&ov.key).map_err(|m| (0..0, ov.key.clone(), m))?;
    let literal = ov.literal();
    let target = locate(root.get_ref(), &(0..0), text, &steps, "", true, Vec::new())?;
    let (mut out, span, added_lines, path) = match target {
        Target::Value { span, path } => {
            let mut out = text.to_owned();
            out.replace_range(span.clone(), &literal);
            (out, span.start..span.start + literal.len(), None, path)
        }
        Target::Absent { at, before, key, after, path } => {
            let added = format!("{before}{key} = {literal}{after}");
            let mut out = text.to_owned();
            out.insert_str(at, &added);
            let start = at + before.len();
            (out, start..start + key.len() + 3 + literal.len(), Some(added.matches('\n').count()), path)
        }
    };
    // `end` and `steps` are alternatives (scene format): setting one removes the other.
    let other = match ov.key.as_str() {
        "time.end" => Some("steps"),
        "time.steps" => Some("end"),
        _ => None,
    };
    let mut span = span;
    if let Some(other) = other
        && let Ok(root) = DeTable::parse(&out)
        && let Some(time) = root.get_ref().get("time").and_then(|t| t.get_ref().as_table())
        && let Some((k, v)) = time.get_key_value(other)
    {
        let cut = k.span().start..v.span().end;
        if cut.end <= span.start {
            span = span.start - cut.len()..span.end - cut.len();
        }
        out.replace_range(cut, "");
    }
    Ok(Edit { text: out, ov: ov.clone(), path, span, added_lines })
}

enum Target {
    /// An existing scalar or array value at `span`.
    Value { span: Range<usize>, path: String },
    /// An absent key: insert `before key = value after` at byte `at`.
    Absent { at: usize, before: String, key: String, after: String, path: String },
}

/// Finds where the override's value goes: `steps` start in `table` (at `span`, key path
/// `path`); `header` is the path of plain keys from the root while there is one.
fn locate<'a>(
    table: &DeTable,
    span: &Range<usize>,
    text: &str,
    steps: &[Step<'a>],
    path: &str,
    keys_only: bool,
    mut header: Vec<&'a str>,
) -> Result<Target, Misplaced> {
    let Some(Step::Key(key)) = steps.first() else {
        return Err((span.clone(), path.to_owned(), "an index must follow an array".into()));
    };
    let Some(mut value) = table.get(*key) else {
        return absent(table, span, text, steps, path, keys_only, &header);
    };
    let mut here = join(path, key);
    let mut rest = &steps[1..];
    let mut keys_only = keys_only;
    // array steps: `[i]`, or `.name` in an array of tables
    while let DeValue::Array(items) = value.get_ref() {
        let (n, item) = match rest.first() {
            None => break,
            Some(Step::Index(n)) => items.get(*n).map(|v| (*n, v)).ok_or_else(|| {
                let m = format!("index {n} is out of range ({} entries)", items.len());
                (value.span(), here.clone(), m)
            })?,
            Some(Step::Key(name)) if items.iter().all(|v| v.get_ref().is_table()) => {
                let named = |v: &&toml::Spanned<DeValue>| {
                    v.get_ref().get("name").and_then(|n| n.get_ref().as_str()) == Some(*name)
                };
                let m = format!("no entry of `{here}` is named `{name}`");
                items.iter().enumerate().find(|(_, v)| named(v)).ok_or((value.span(), here.clone(), m))?
            }
            Some(Step::Key(k)) => {
                return Err((value.span(), here, format!("`{k}`: expected an index `[i]`")));
            }
        };
        here = format!("{here}[{n}]");
        value = item;
        rest = &rest[1..];
        keys_only = false;
    }
    if rest.is_empty() {
        if value.get_ref().is_table() {
            return Err((value.span(), here, "is a table: give a key inside it".into()));
        }
        return Ok(Target::Value { span: value.span(), path: here });
    }
    let DeValue::Table(inner) = value.get_ref() else {
        return Err((value.span(), here, format!("is a {}, not a table", value.get_ref().type_str())));
    };
    if keys_only {
        header.push(key);
    }
    locate(inner, &value.span(), text, rest, &here, keys_only, header)
}

fn join(path: &str, key: &str) -> String {
    if path.is_empty() { key.to_owned() } else { format!("{path}.{key}") }
}

/// Where an absent key goes: into its table if that exists, else into a new `[a.b]` table
/// at the end of the document (only along plain keys from the root).
fn absent(
    table: &DeTable,
    span: &Range<usize>,
    text: &str,
    rest: &[Step],
    path: &str,
    keys_only: bool,
    header: &[&str],
) -> Result<Target, Misplaced> {
    let names: Option<Vec<&str>> =
        rest.iter().map(|s| if let Step::Key(k) = s { Some(*k) } else { None }).collect();
    let Some(names) = names else {
        return Err((span.clone(), path.to_owned(), "an index must follow an array".into()));
    };
    let full = join(path, &names.join("."));
    let key = names[names.len() - 1].to_owned();
    if names.len() == 1 {
        let (at, before, after) = match insertion_point(table, span, text) {
            Some(Insert::Line(at)) => (at, "\n", ""),
            Some(Insert::Inline(at, true)) => (at, " ", " "),
            Some(Insert::Inline(at, false)) => (at, ", ", ""),
            Some(Insert::Top) => (0, "", "\n"),
            None => return Err((span.clone(), full, "cannot add a key to a dotted-key table".into())),
        };
        return Ok(Target::Absent { at, before: before.into(), key, after: after.into(), path: full });
    }
    if !keys_only {
        return Err((span.clone(), full, format!("no table `{}` here", names[0])));
    }
    let mut tables: Vec<&str> = header.to_vec();
    tables.extend(&names[..names.len() - 1]);
    let newline = if text.ends_with('\n') { "" } else { "\n" };
    let before = format!("{newline}[{}]\n", tables.join("."));
    Ok(Target::Absent { at: text.len(), before, key, after: "\n".into(), path: full })
}

enum Insert {
    /// On a new line after byte `at` (a `[header]` table).
    Line(usize),
    /// Inside an inline table before byte `at`; `true` if the table is empty.
    Inline(usize, bool),
    /// The root table: at the top of the document.
    Top,
}

/// Where a new key of `table` goes: after its last key (or header), inside an inline table's
/// braces; None for a table made by dotted keys.
fn insertion_point(table: &DeTable, span: &Range<usize>, text: &str) -> Option<Insert> {
    if span.is_empty() && span.start == 0 {
        return Some(Insert::Top);
    }
    let own = &text[span.clone()];
    let last_end = table
        .iter()
        // a sub-table's `[header]` (or dotted key) span holds its key: not a key of this table's text
        .filter(|(k, v)| !(v.span().start <= k.span().start && k.span().end <= v.span().end))
        .map(|(k, v)| k.span().end.max(v.span().end))
        .max();
    if own.starts_with('{') {
        return Some(match last_end {
            Some(end) => Insert::Inline(end, false),
            None => Insert::Inline(span.start + 1, true),
        });
    }
    if own.starts_with('[') {
        return Some(Insert::Line(last_end.unwrap_or(span.end).max(span.end)));
    }
    None
}

/// Turns an error of the overridden scene into one that names the override that caused it;
/// an error of the scene itself keeps its own line (corrected for added lines).
fn blame(mut e: SceneError, text: &str, file: &str, edits: &[Edit]) -> SceneError {
    let caused = edits.iter().rev().find(|ed| {
        let under =
            |a: &str, b: &str| a == b || a.starts_with(&format!("{b}.")) || a.starts_with(&format!("{b}["));
        under(&e.key, &ed.path) || (ed.added_lines.is_some() && under(&ed.path, &e.key) && !e.key.is_empty())
    });
    if let Some(ed) = caused {
        let span = ed.span.clone();
        return SceneError::at(file, text, span, e.key.clone(), format!("--set {}: {}", ed.ov, e.message));
    }
    for ed in edits.iter().rev() {
        if let Some(n) = ed.added_lines {
            let line = text[..ed.span.start].matches('\n').count() + 1;
            if e.line > line {
                e.line -= n;
            }
        }
    }
    e
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set(text: &str, key: &str, value: &str) -> String {
        apply(text, &Override { key: key.into(), value: value.into() })
            .map(|e| e.text)
            .unwrap_or_else(|e| e.2)
    }

    #[test]
    fn replaces_adds_and_quotes() {
        let s = "[time]\nstep = 0.5 # dt\nsteps = 3\n[[body]]\nname = \"a\"\n[[body]]\nname = \"b\"\nr = 1\n";
        assert_eq!(set(s, "time.step", "1e-3"), s.replace("0.5", "1e-3"));
        assert_eq!(set(s, "body.b.r", "2"), s.replace("r = 1", "r = 2"));
        assert_eq!(set(s, "body[0].r", "2"), s.replace("name = \"a\"", "name = \"a\"\nr = 2"));
        assert_eq!(set(s, "body.a.model", "deformable"), s.replace("\"a\"", "\"a\"\nmodel = \"deformable\""));
        assert_eq!(set(s, "solver.tolerance", "1e-9"), format!("{s}[solver]\ntolerance = 1e-9\n"));
        assert_eq!(set(s, "time.end", "2"), s.replace("steps = 3", "\nend = 2"));
        assert_eq!(set(s, "physics.gravity[1]", "-9.81"), "an index must follow an array");
        let g = "[physics]\ngravity = [0.0, -10.0]\n";
        assert_eq!(set(g, "physics.gravity[1]", "-9.81"), g.replace("-10.0", "-9.81"));
        assert_eq!(set(g, "physics.plane", "strain"), g.replace("0]", "0]\nplane = \"strain\""));
        assert_eq!(set(s, "body.c.r", "1"), "no entry of `body` is named `c`");
        let inline = "time = { step = 1 }\n";
        let star = |key: &str| {
            let ov = Override { key: key.into(), value: "5".into() };
            expand(s, &ov).map(|v| v.into_iter().map(|o| o.key).collect::<Vec<_>>()).map_err(|e| e.2)
        };
        assert_eq!(star("body[*].r"), Ok(vec!["body[0].r".to_owned(), "body[1].r".to_owned()]));
        assert_eq!(
            star("connector[*].strength"),
            Err("`connector[*]` matches nothing: the scene has no `connector` entries".to_owned())
        );
        assert_eq!(star("time[*].step"), Err("`time` is a table, not an array".to_owned()));
        assert_eq!(set(inline, "time.steps", "4"), "time = { step = 1, steps = 4 }\n");
    }
}
