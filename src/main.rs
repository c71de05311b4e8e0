//! The `pushpack` command: a thin wrapper around [`pushpack::cli::main`].

fn main() {
    std::process::exit(pushpack::cli::main());
}
