//! Integration tests: the VI solvers and the Delassus operator (KKT conditions, networks, Newton, the chain, deformable disks and blocks).
//! One test binary (link time); each module is one test file, with its own header.

#[path = "../common/mod.rs"]
mod common;
#[path = "../vi_support/mod.rs"]
mod vi_support;

mod deformable_block_statics;
mod deformable_bouncing;
mod deformable_disk_squeeze;
mod deformable_initial_stress;
mod deformable_pile;
mod inverse_block;
mod solver_chain;
mod solver_methods;
mod stiff_deformable;
mod vi_kkt;
mod vi_networks;
mod vi_newton;
mod w_operator;
