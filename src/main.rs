//! The `mbfx` command: a thin shell over [`mbfx::cli`].

fn main() {
    std::process::exit(mbfx::cli::main());
}
