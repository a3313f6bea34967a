//! Physics through the library: whole runs against analytic results, failed-step recovery,
//! checkpoint and resume, metrics, and shell bending against plate theory.

#[path = "../common/mod.rs"]
mod common;

mod failure;
mod metrics;
mod recovery;
mod resume;
mod runs;
mod shell_bending;
