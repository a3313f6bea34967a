//! Files in and out: mesh generators and importers (with property tests), output files
//! (CSV, summary, PNG, VTK), and study directories.

#[path = "../common/mod.rs"]
mod common;

mod fuzz;
mod mesh_generate;
mod mesh_import;
mod outputs;
mod plots;
mod study;
mod vtk;
