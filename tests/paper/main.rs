//! Integration tests: the paper's examples and the time scheme's closed forms (impacts, friction stops, mass ratios, the adaptive step).
//! One test binary (link time); each module is one test file, with its own header.

#[path = "../common/mod.rs"]
mod common;

mod adaptive_step;
mod cold_step;
mod friction_stop;
mod mass_ratio;
mod paper_7_10_particle_chain;
mod paper_7_1_disk_heap;
mod paper_7_2_block_staircase;
mod paper_7_2_deformable_staircase;
mod paper_7_3_ring_in_frame;
mod paper_7_4_block_in_frame;
mod paper_7_5_disk_in_ring;
mod paper_7_6_sliding_block_cohesion;
mod paper_7_7_rolling_disk;
mod paper_7_7_rolling_resistance;
mod paper_7_8_cemented_interface;
mod penetration_allowance;
mod restitution;
mod slumping_pile;
