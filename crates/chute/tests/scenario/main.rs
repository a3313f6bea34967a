//! Scenario files through the library: bundled scenarios, defaults, every error class,
//! overrides, the generated key tables of docs/scenarios.md, and property tests.

#[path = "../common/mod.rs"]
mod common;

mod bundled;
mod control;
mod defaults;
mod docs;
mod errors;
mod fuzz;
mod imperfection;
mod limits;
mod membranes;
mod messages;
mod notes;
mod overrides;
mod shell_laws;
mod wind;
