//! The `pushpack` command: a thin wrapper around [`cli::main`]. The command line lives in the
//! binary, not the library, so library users compile no argument parser.

mod cli;

fn main() {
    restore_sigpipe();
    std::process::exit(cli::main());
}

/// Rust ignores SIGPIPE, so `println!` panics when the reader has gone
/// (`pushpack push-check FILE | head -1`). A command-line filter should end quietly instead, as
/// every Unix tool does: restore the default action.
#[cfg(unix)]
fn restore_sigpipe() {
    // SAFETY: called once at start-up, before any thread exists; SIG_DFL is a valid action
    // for SIGPIPE.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

#[cfg(not(unix))]
fn restore_sigpipe() {}
