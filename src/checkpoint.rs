//! Restart files of `pbdda run --checkpoint-every N` and `pbdda resume DIR`.
//!
//! A checkpoint names the last step whose output rows are all written, and holds what is
//! needed to rebuild the run: the scene text as it was read and the `--set` overrides. The
//! state at that step is recovered by replaying the steps from t = 0 without output: a step is
//! a deterministic function of the state before it (tests/determinism.rs), so the replayed
//! state is bit for bit the one the interrupted run had, and the resumed run writes the same
//! rows as a run that was never stopped. (Replay costs the time of the steps already done; a
//! state snapshot would avoid it but needs every part of `World` serializable.)
//!
//! The file is `DIR/checkpoint.toml`, written to a temporary file and renamed into place, so a
//! run killed while writing it leaves the previous checkpoint whole.

use serde::{Deserialize, Serialize};
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

/// File name of the checkpoint in a results directory.
pub const CHECKPOINT_FILE: &str = "checkpoint.toml";

/// What `pbdda resume` needs to continue a run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Checkpoint {
    /// Format version of this file (1).
    pub version: u32,
    /// The scene file's name as given to `pbdda run` (for messages only).
    pub scene_file: String,
    /// The scene text as it was read when the run started.
    pub scene: String,
    /// `--set KEY=VALUE` overrides of the run, in order.
    pub overrides: Vec<String>,
    /// `--checkpoint-every` of the run.
    pub every: usize,
    /// Last step whose rows are all written (and whose state the replay recovers).
    pub step: usize,
    /// The stage of that step (`[[stage]]` name; absent in a run without stages): `resume` checks
    /// that the replay reaches the same stage.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stage: Option<String>,
}

#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum CheckpointError {
    #[error("{path}: {source}")]
    Io { path: PathBuf, source: io::Error },
    #[error("{path}: not a pbdda checkpoint: {message}")]
    #[diagnostic(help("resume needs the results folder of `pbdda run --checkpoint-every N`"))]
    Invalid { path: PathBuf, message: String },
}

impl Checkpoint {
    /// Writes `dir/checkpoint.toml` atomically (temporary file, then rename).
    pub fn write(&self, dir: &Path) -> Result<(), CheckpointError> {
        let path = dir.join(CHECKPOINT_FILE);
        let tmp = dir.join(format!("{CHECKPOINT_FILE}.tmp"));
        let io = |source| CheckpointError::Io { path: path.clone(), source };
        let text = toml::to_string(self)
            .map_err(|e| CheckpointError::Invalid { path: path.clone(), message: e.to_string() })?;
        fs::write(&tmp, text).map_err(io)?;
        fs::rename(&tmp, &path).map_err(|source| CheckpointError::Io { path: path.clone(), source })
    }

    /// Reads `dir/checkpoint.toml`.
    pub fn read(dir: &Path) -> Result<Checkpoint, CheckpointError> {
        let path = dir.join(CHECKPOINT_FILE);
        let text =
            fs::read_to_string(&path).map_err(|source| CheckpointError::Io { path: path.clone(), source })?;
        let c: Checkpoint = toml::from_str(&text)
            .map_err(|e| CheckpointError::Invalid { path: path.clone(), message: e.message().to_owned() })?;
        if c.version != 1 {
            let message = format!("version {} (this pbdda reads version 1)", c.version);
            return Err(CheckpointError::Invalid { path, message });
        }
        Ok(c)
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
            version: 1,
            scene_file: "a \"b\".toml".into(),
            scene: "[scene]\nname = \"x\"\n# é ''' \"\"\" \\\n".into(),
            overrides: vec!["time.step=1e-3".into(), "scene.name=\"q\"".into()],
            every: 7,
            step: 42,
            stage: Some("excavate".into()),
        };
        c.write(&dir).unwrap();
        assert_eq!(Checkpoint::read(&dir).unwrap(), c);
        fs::remove_dir_all(&dir).unwrap();
    }
}
