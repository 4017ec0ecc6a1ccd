//! Integration tests: the command line, scene overrides, outputs, sweeps, resume, validate, and the module graph.
//! One test binary (link time); each module is one test file, with its own header.

#[path = "../common/mod.rs"]
mod common;

mod api_tables;
mod cli;
mod module_graph;
mod overrides;
mod plots;
mod resume_examples;
mod run_interrupts;
mod sweep;
mod sweep_grid;
mod sweep_mesh;
mod sweep_plan;
mod validate;
mod vtk_output;
