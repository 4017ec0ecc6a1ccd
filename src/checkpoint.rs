//! Restart files of `pbdda run --checkpoint-every N` and `pbdda resume DIR`.
//!
//! A checkpoint names the last step whose output rows are all written, and holds what is
//! needed to continue the run from there: the scene text as it was read, the `--set`
//! overrides, and the state of the world after that step ([`World::state`]: bodies, contact
//! memory, connectors, stage, the kept factors of the step stiffness, ...). `resume` builds the
//! scene again, loads the state into it and goes on with the next step: that step and every
//! later one are bit for bit those of a run that was never stopped, so the resumed run writes
//! the same rows (tests/io/resume_examples.rs, every example). Resuming costs the steps still to
//! go, not the ones already done.
//!
//! The files are `DIR/checkpoint.toml` and the state it names, `DIR/state-NNNNNNNN.bin` (the
//! step in its name): the state is written first, then checkpoint.toml, each to a temporary
//! file renamed into place, and only then is the previous state removed; so a run killed while
//! writing leaves the previous checkpoint whole. A state file ([`encode`], [`decode`]) is
//! [`STATE_MAGIC`], [`VERSION`] (u32), an FNV-1a hash of the scene text (u64), a block that a
//! caller keeps beside the world, length first (u64; empty for `pbdda run`, a sweep case's
//! running table for `pbdda sweep --run-plan`), then [`World::state`]; integers little-endian.
//! A checkpoint of another version, or a state of another scene, is refused with an error that
//! says so. The state is binary (postcard) so that every f64 is kept bit for bit.

use serde::{Deserialize, Serialize};
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use crate::model::Model;
use crate::world::{Settings, World};

/// File name of the checkpoint in a results directory.
pub const CHECKPOINT_FILE: &str = "checkpoint.toml";

/// Format version of checkpoint.toml and of the state file.
pub const VERSION: u32 = 2;

/// The first bytes of a state file.
pub const STATE_MAGIC: &[u8; 12] = b"pbdda-state\n";

/// What `pbdda resume` needs to continue a run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Checkpoint {
    /// Format version of this file ([`VERSION`]).
    pub version: u32,
    /// The scene file's name as given to `pbdda run` (for messages and relative paths).
    pub scene_file: String,
    /// The scene text as it was read when the run started.
    pub scene: String,
    /// `--set KEY=VALUE` overrides of the run, in order.
    pub overrides: Vec<String>,
    /// `--checkpoint-every` of the run.
    pub every: usize,
    /// Last step whose rows are all written, and whose end the state is at.
    pub step: usize,
    /// The stage of that step (`[[stage]]` name; absent in a run without stages).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stage: Option<String>,
    /// The state file in the same folder (`state-NNNNNNNN.bin`).
    pub state: String,
}

#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum CheckpointError {
    #[error("{path}: {source}")]
    Io { path: PathBuf, source: io::Error },
    #[error("{path}: not a pbdda checkpoint: {message}")]
    #[diagnostic(help("resume needs the results folder of `pbdda run --checkpoint-every N`"))]
    Invalid { path: PathBuf, message: String },
}

/// FNV-1a, 64 bits (Fowler, Noll, Vo) of the scene text: ties a state file to its scene.
fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// A state file's bytes (module docs): the header, `extra` (what a caller keeps beside the
/// world, such as a sweep case's running maxima), length first, and the world's state.
pub fn encode(scene: &str, world: &World, extra: &[u8]) -> Vec<u8> {
    let mut bytes = STATE_MAGIC.to_vec();
    bytes.extend(VERSION.to_le_bytes());
    bytes.extend(fnv1a(scene.as_bytes()).to_le_bytes());
    bytes.extend((extra.len() as u64).to_le_bytes());
    bytes.extend(extra);
    bytes.extend(world.state());
    bytes
}

/// The `extra` bytes and the world of `model` (the scene whose text is `scene`) that a state
/// file's `bytes` (read from `path`, for messages) hold.
pub fn decode<'a>(
    path: &Path,
    bytes: &'a [u8],
    scene: &str,
    model: Model,
) -> Result<(&'a [u8], World), CheckpointError> {
    let invalid = |message: String| CheckpointError::Invalid { path: path.to_owned(), message };
    let word = |at: usize, n: usize| -> Option<u64> {
        let b = bytes.get(at..at + n)?;
        Some(b.iter().rev().fold(0u64, |h, &b| h << 8 | u64::from(b)))
    };
    let m = STATE_MAGIC.len();
    if bytes.get(..m) != Some(&STATE_MAGIC[..]) {
        return Err(invalid("no pbdda state header".into()));
    }
    let version = word(m, 4).unwrap_or(0);
    if version != u64::from(VERSION) {
        return Err(invalid(format!("state version {version} (this pbdda reads version {VERSION})")));
    }
    if word(m + 4, 8) != Some(fnv1a(scene.as_bytes())) {
        return Err(invalid("the state is of another scene".into()));
    }
    let n = word(m + 12, 8).and_then(|n| usize::try_from(n).ok()).unwrap_or(usize::MAX);
    let at = m + 20;
    let extra =
        at.checked_add(n).and_then(|end| bytes.get(at..end)).ok_or_else(|| invalid("cut short".into()))?;
    let world = World::from_state(model, Settings::default(), &bytes[at + n..])
        .map_err(|e| invalid(e.to_string()))?;
    Ok((extra, world))
}

/// Writes `bytes` to `path` through a temporary file renamed into place.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), CheckpointError> {
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    let io = |source| CheckpointError::Io { path: path.to_owned(), source };
    fs::write(&tmp, bytes).map_err(io)?;
    fs::rename(&tmp, path).map_err(io)
}

impl Checkpoint {
    /// A checkpoint of a run of `scene` (text as read from `scene_file`) with `overrides`, to be
    /// [`Self::save`]d every `every` steps.
    pub fn new(scene_file: &str, scene: String, overrides: Vec<String>, every: usize) -> Checkpoint {
        let scene_file = scene_file.to_owned();
        let state = String::new();
        Checkpoint { version: VERSION, scene_file, scene, overrides, every, step: 0, stage: None, state }
    }

    /// Saves `world` (between two steps) into `dir`: its state file, then checkpoint.toml, then
    /// the previous state file is removed (module docs).
    pub fn save(&mut self, dir: &Path, world: &World) -> Result<(), CheckpointError> {
        let previous = std::mem::take(&mut self.state);
        self.step = world.step_index;
        self.stage = world.stage_name().map(str::to_owned);
        self.state = format!("state-{:08}.bin", self.step);
        write_atomic(&dir.join(&self.state), &encode(&self.scene, world, &[]))?;
        self.write(dir)?;
        if !previous.is_empty() && previous != self.state {
            let path = dir.join(previous);
            match fs::remove_file(&path) {
                Err(e) if e.kind() != io::ErrorKind::NotFound => {
                    return Err(CheckpointError::Io { path, source: e });
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// Writes `dir/checkpoint.toml` atomically (temporary file, then rename).
    pub fn write(&self, dir: &Path) -> Result<(), CheckpointError> {
        let path = dir.join(CHECKPOINT_FILE);
        let text = toml::to_string(self)
            .map_err(|e| CheckpointError::Invalid { path: path.clone(), message: e.to_string() })?;
        write_atomic(&path, text.as_bytes())
    }

    /// Reads `dir/checkpoint.toml`.
    pub fn read(dir: &Path) -> Result<Checkpoint, CheckpointError> {
        let path = dir.join(CHECKPOINT_FILE);
        let text =
            fs::read_to_string(&path).map_err(|source| CheckpointError::Io { path: path.clone(), source })?;
        let invalid = |message: String| CheckpointError::Invalid { path: path.clone(), message };
        let version: Option<i64> =
            text.parse::<toml::Table>().ok().and_then(|t| t.get("version").and_then(toml::Value::as_integer));
        if let Some(v) = version.filter(|&v| v != i64::from(VERSION)) {
            return Err(invalid(format!("version {v} (this pbdda reads version {VERSION})")));
        }
        toml::from_str(&text).map_err(|e| invalid(e.message().to_owned()))
    }

    /// The world of `model` (this checkpoint's scene with its overrides) in the saved state,
    /// read from `dir`.
    pub fn load(&self, dir: &Path, model: Model) -> Result<World, CheckpointError> {
        let path = dir.join(&self.state);
        let bytes = fs::read(&path).map_err(|source| CheckpointError::Io { path: path.clone(), source })?;
        let (_, world) = decode(&path, &bytes, &self.scene, model)?;
        let invalid = |message: String| CheckpointError::Invalid { path: path.clone(), message };
        if world.step_index != self.step {
            let message =
                format!("the state is at step {}, {CHECKPOINT_FILE} names {}", world.step_index, self.step);
            return Err(invalid(message));
        }
        if world.stage_name() != self.stage.as_deref() {
            let message = format!(
                "the state is in stage {:?}, {CHECKPOINT_FILE} names {:?}",
                world.stage_name(),
                self.stage
            );
            return Err(invalid(message));
        }
        Ok(world)
    }

    /// Removes checkpoint.toml and the state file it names from `dir` (a finished run).
    pub fn remove(&self, dir: &Path) -> Result<(), CheckpointError> {
        let state = (!self.state.is_empty()).then(|| dir.join(&self.state));
        for path in std::iter::once(dir.join(CHECKPOINT_FILE)).chain(state) {
            match fs::remove_file(&path) {
                Err(e) if e.kind() != io::ErrorKind::NotFound => {
                    return Err(CheckpointError::Io { path, source: e });
                }
                _ => {}
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A checkpoint reads back equal to what was written, odd scene text included.
    #[test]
    fn round_trip() {
        let dir = std::env::temp_dir().join(format!("pbdda-ckpt-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let c = Checkpoint {
            version: VERSION,
            scene_file: "a \"b\".toml".into(),
            scene: "[scene]\nname = \"x\"\n# é ''' \"\"\" \\\n".into(),
            overrides: vec!["time.step=1e-3".into(), "scene.name=\"q\"".into()],
            every: 7,
            step: 42,
            stage: Some("excavate".into()),
            state: "state-00000042.bin".into(),
        };
        c.write(&dir).unwrap();
        assert_eq!(Checkpoint::read(&dir).unwrap(), c);
        fs::remove_dir_all(&dir).unwrap();
    }
}
