//! `pbdda import-ntdda GEOMETRY [ANALYSIS] --out SCENE.toml`: ntdda's input as a pbdda scene
//! ([`crate::ntdda`]). The ignored fields and the mapping notes go to stderr, one line each, and
//! head the written scene as comments.

use miette::{IntoDiagnostic, Result, WrapErr, miette};
use std::path::Path;

pub(super) fn command(geometry: &Path, analysis: Option<&Path>, out: &Path) -> Result<()> {
    let import = crate::ntdda::import(geometry, analysis).map_err(|e| miette!("{e}"))?;
    std::fs::write(out, &import.toml)
        .into_diagnostic()
        .wrap_err_with(|| format!("writing {}", out.display()))?;
    for line in &import.ignored {
        errln!("ignored: {line}");
    }
    for line in &import.notes {
        errln!("note: {line}");
    }
    outln!("{}", out.display());
    Ok(())
}
