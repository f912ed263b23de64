//! `prehensile`: grasp poses for virtual hands from the command line.
//!
//! Two layers, as ripgrep does: `args` parses and validates flags; each command resolves them
//! into a run configuration and runs it. Errors print what, where and how to fix, exit code 2.

/// `println!` that ends the command with an error instead of panicking when standard output is
/// closed (`| head`) or full (`> /dev/full`).
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        writeln!(std::io::stdout().lock(), $($arg)*).map_err($crate::CliError::output)?
    }};
}

mod args;
mod commands;
mod picture;
mod sources;

use clap::Parser;

/// An error for the user: printed as-is, exit code 2.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct CliError(pub String);

impl CliError {
    /// An error from any displayable cause.
    pub fn from_display(e: impl std::fmt::Display) -> Self {
        Self(e.to_string())
    }

    /// Standard output could not be written.
    pub fn output(e: std::io::Error) -> Self {
        Self(format!("cannot write to standard output: {e}"))
    }
}

fn main() {
    let cli = args::Cli::parse();
    let outcome = match cli.command {
        args::Command::Check(a) => commands::check::run(&a),
        args::Command::Hands(a) => commands::hands::run(&a),
        args::Command::Grasp(a) => commands::grasp::run(&a),
        args::Command::Demo(a) => commands::demo::run(&a),
        args::Command::Simulate(a) => commands::simulate::run(&a),
        args::Command::Fit(a) => commands::fit::run(&a),
        args::Command::Batch(a) => commands::batch::run(&a),
        args::Command::View(a) => commands::view::run(&a),
    };
    match outcome {
        Ok(code) => std::process::exit(code),
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(2);
        }
    }
}
