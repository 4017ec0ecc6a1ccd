//! Result writers and readers: the CSVs of the output contract, the ParaView time series,
//! plots and scene pictures.

pub mod connectors;
pub mod csv;
pub mod plot;
pub mod render;
pub mod results;
pub mod rows;
pub mod vtk;

/// Whether a writer that writes every `every`-th step writes step `step` of a run whose last
/// step is `last` (the last is always written: docs/scene-format.md, `[output]`).
pub(crate) fn written(step: usize, every: usize, last: usize) -> bool {
    step.is_multiple_of(every) || step == last
}
