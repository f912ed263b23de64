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

/// An error for the user: printed as-is, exit code 2. The libraries' typed errors are carried
/// whole (their messages already name the file, the place and the fix).
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// A flag or an input the command itself checks is unusable.
    #[error("{0}")]
    Usage(String),
    /// A file could not be read or understood.
    #[error(transparent)]
    Format(#[from] prehensile_formats::FormatError),
    /// An object could not be made from a mesh, or hooked.
    #[error(transparent)]
    Object(#[from] prehensile_core::ObjectError),
    /// A search could not start.
    #[error(transparent)]
    Search(#[from] prehensile_core::search::SearchError),
    /// A simulation could not run.
    #[error(transparent)]
    Sim(#[from] prehensile_sim::SimError),
    /// A batch could not run.
    #[error(transparent)]
    Batch(#[from] prehensile_batch::BatchError),
    /// A motion could not be fitted.
    #[error("fitting: {0}")]
    Fit(#[from] prehensile_control::DynamicsError),
    /// An option's value is out of range.
    #[error(transparent)]
    Parameter(#[from] prehensile_core::parameter::ParameterError),
    /// An output file could not be written, or would overwrite an input.
    #[error(transparent)]
    Output(#[from] prehensile_formats::OutputError),
    /// A file or folder could not be written, created or read.
    #[error("cannot {action} {}: {source}", path.display())]
    File {
        /// "write", "create", "read".
        action: &'static str,
        /// The file.
        path: std::path::PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
    /// Standard output could not be written (closed by `| head`, or a full disk).
    #[error("cannot write to standard output: {0}")]
    Stdout(std::io::Error),
    /// A result could not be encoded as JSON.
    #[error("cannot encode JSON: {0}")]
    Json(#[from] serde_json::Error),
}

impl CliError {
    /// Standard output could not be written.
    pub fn output(e: std::io::Error) -> Self {
        Self::Stdout(e)
    }

    /// A file operation `action` ("write", "create", "read") on `path` failed.
    pub fn file(
        action: &'static str,
        path: &std::path::Path,
    ) -> impl FnOnce(std::io::Error) -> Self {
        let path = path.to_path_buf();
        move |source| Self::File {
            action,
            path,
            source,
        }
    }
}

/// glibc's allocator set for a run that builds tens of megabytes of object and then searches:
/// big blocks from the heap instead of fresh mappings each, kept when freed, and one arena for
/// every thread. A fresh 16k-triangle grasp then takes about 2,630 page faults instead of 3,660
/// (each costs microseconds in a virtual machine) and about 2 ms less wall time
/// (docs/PERFORMANCE.md). Set through glibc's own `mallopt`, which only the C
/// library offers.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn tune_allocator() {
    // Large enough for a million-triangle object's biggest arrays.
    const MMAP_THRESHOLD: i32 = 64 << 20;
    const TRIM_THRESHOLD: i32 = 256 << 20;
    // SAFETY: `mallopt` only sets the allocator's parameters (it takes the allocator's own lock),
    // and no other thread has started yet.
    unsafe {
        libc::mallopt(libc::M_ARENA_MAX, 1);
        libc::mallopt(libc::M_MMAP_THRESHOLD, MMAP_THRESHOLD);
        libc::mallopt(libc::M_TRIM_THRESHOLD, TRIM_THRESHOLD);
    }
}

/// Other C libraries' allocators keep their defaults.
#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn tune_allocator() {}

fn main() {
    tune_allocator();
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
