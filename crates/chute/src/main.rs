//! The `chute` binary; everything lives in [`chute::cli`].
fn main() -> std::process::ExitCode {
    // A reader that stops reading (`chute check … | head -1`) ends chute as it ends other
    // command-line tools, by SIGPIPE, instead of a panic in `println!` (Rust ignores the
    // signal by default, turning it into an EPIPE error).
    // SAFETY: restoring a signal's default disposition before any thread starts.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    chute::cli::main()
}
