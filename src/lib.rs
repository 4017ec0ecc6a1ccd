//! pbdda: discontinuous deformation analysis of particle-block systems in the
//! variational-inequality form of Fan, Zhao & Zheng (2018), "PB-DDA".

pub mod contact;
pub mod geometry;
pub mod model;
pub mod vi;
pub mod body;
pub mod cluster;
pub mod world;
pub mod output;
pub mod generate;
pub mod cli;
pub mod error;
pub mod scene;
