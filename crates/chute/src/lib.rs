#![warn(missing_docs)]
//! chute: parachute scenarios, builders, metrics, outputs and the command line. How the
//! layers fit together (scenario → builders → engine → observers → outputs, and how a
//! scenario key flows) is described in docs/architecture.md §Application.
//!
//! The interface is [`api`]: the command line ([`cli`]) and the Python bindings use nothing
//! else. The other modules are internal, public only so that the integration tests can reach
//! them; they may change without notice.

pub mod api;
pub mod app;
pub mod bench;
pub mod build;
pub mod checkpoint;
pub mod cli;
pub mod control;
pub mod converge;
pub mod mesh;
pub mod metrics;
pub mod output;
pub mod resolve;
pub mod runner;
pub mod scenario;
pub mod steady;
pub mod study;
pub mod verify;

/// `eprintln!` that never panics: a message that cannot be written (stderr closed, or a full
/// disk behind it) is dropped rather than turning into a crash of the command that wanted to
/// say it.
#[macro_export]
macro_rules! err_line {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr(), $($arg)*);
    }};
}

/// `print!` of a command's results on stdout that never panics: a write that fails (a full
/// disk behind stdout) is remembered ([`output::console::stdout_failed`]) and makes the command
/// exit with status 1 after its work is done, saying so.
#[macro_export]
macro_rules! out_text {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if let Err(e) = write!(std::io::stdout(), $($arg)*) {
            $crate::output::console::stdout_failed(e);
        }
    }};
}

/// [`out_text!`] with a newline (`println!`).
#[macro_export]
macro_rules! out_line {
    () => { $crate::out_text!("\n") };
    ($($arg:tt)*) => {{
        $crate::out_text!($($arg)*);
        $crate::out_text!("\n");
    }};
}
