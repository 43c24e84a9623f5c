//! `glint-view`: the viewer without the rest of glint (what `glint view` runs), for
//! tests and for machines that want the viewer alone.

use std::process::ExitCode;

use clap::Parser;

/// glint's interactive viewer (the same as `glint view`).
#[derive(Parser)]
#[command(name = "glint-view", version, about)]
struct Cli {
    #[command(flatten)]
    args: glint_view::ViewArgs,
}

fn main() -> ExitCode {
    match glint_view::run(&Cli::parse().args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("glint view: error: {message}");
            ExitCode::FAILURE
        }
    }
}
