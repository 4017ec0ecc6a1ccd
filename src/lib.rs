//! pbdda: discontinuous deformation analysis of particle-block systems in the
//! variational-inequality form of Fan, Zhao & Zheng (2018), "PB-DDA".

pub mod body;
pub mod cli;
pub mod cluster;
pub mod contact;
pub mod error;
pub mod generate;
pub mod geometry;
pub mod model;
pub mod output;
pub mod scene;
pub mod vi;
pub mod world;
