//! Integration tests: rock masses, stages and connectors (joint crossings, cemented bridges, ntdda import, bolts).
//! One test binary (link time); each module is one test file, with its own header.

#[path = "../common/mod.rs"]
mod common;

mod bolt_yield;
mod cemented_bridges;
mod connector_errors;
mod connector_mechanics;
mod connectors_world;
mod cut_threads;
mod joint_crossings;
mod joint_provenance;
mod ntdda_import;
mod rock_mass_scene;
mod staged_bolts;
mod staged_examples;
mod stages;
