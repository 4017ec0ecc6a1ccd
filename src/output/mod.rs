//! Result writers and readers: the CSVs of the output contract, the ParaView time series,
//! plots and scene pictures.

pub mod connectors;
pub mod csv;
pub mod plot;
pub mod render;
pub mod results;
pub mod rows;
pub mod vtk;
