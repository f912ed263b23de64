//! One module per subcommand.

pub mod batch;
pub mod check;
pub mod demo;
pub mod fit;
pub mod grasp;
pub mod hands;
pub mod simulate;
pub mod view;

/// Writes `bytes` to `path`, creating its folder; the error names the path.
pub fn write_file(path: &std::path::Path, bytes: &[u8]) -> Result<(), crate::CliError> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(crate::CliError::file("create", dir))?;
    }
    std::fs::write(path, bytes).map_err(crate::CliError::file("write", path))
}
