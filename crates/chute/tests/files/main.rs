//! Files in and out: mesh generators and importers (with property tests), output files
//! (CSV, summary, PNG, VTK, the viewer page in a real browser, the console summary), and study
//! directories.

#[path = "../common/mod.rs"]
mod common;

mod circle_sites;
mod console;
mod fuzz;
mod mesh_generate;
mod mesh_import;
mod mesh_patterns;
mod outputs;
mod permissions;
mod plots;
mod plots_3d;
mod run_files;
mod study;
mod study_inputs;
mod viewer;
mod viewer_browser;
mod vtk;
