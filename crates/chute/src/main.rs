//! The `chute` binary; everything lives in [`chute::cli`].
fn main() -> std::process::ExitCode {
    chute::cli::main()
}
