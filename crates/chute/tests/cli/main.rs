//! The `chute` binary: exit codes and messages, reliability (partial outputs, signals,
//! resume), adaptive runs, `bench`, `validate` and `converge`.

#[path = "../common/mod.rs"]
mod common;

mod adaptive;
mod bench;
mod collect;
mod converge;
mod dispersion;
mod errors;
mod full_disk;
mod inputs;
mod integrity;
mod recovery;
mod reliability;
mod reports;
mod resume;
mod shell_laws;
mod steady;
mod study_dirs;
mod study_inputs;
mod validate;
