//! Integration tests: Tri3 meshes (reader, element, node-based contact, tractions, in-situ stress).
//! One test binary (link time); each module is one test file, with its own header.

#[path = "../common/mod.rs"]
mod common;

mod in_situ_stress;
mod mesh_7_9_undulation;
mod mesh_connectors;
mod mesh_convergence;
mod mesh_examples;
mod mesh_holes;
mod mesh_joint_strength;
mod mesh_on_disks;
mod mesh_rigid_motion;
mod mesh_scene;
mod mesh_w_operator;
mod msh_reader;
mod tractions;
mod tri3_element;
