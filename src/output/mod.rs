//! Result writers. CSV now (the output contract of the scene format); VTK and plots later.

pub mod csv;
