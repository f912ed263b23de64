//! Writing a command's output files without ever losing a user's file: an output may not be one
//! of the command's inputs (nor named twice), and every file is written whole — to a temporary
//! file beside it, flushed, then renamed over the old one — so an interrupted run leaves the
//! old file or the new one, never half of either.

use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Why an output file cannot be written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OutputError {
    /// The output is one of the command's own inputs.
    #[error("{}: is an input of this command; writing the output there would destroy it, so give another output path", path.display())]
    IsInput {
        /// The output path.
        path: PathBuf,
    },
    /// Two outputs of one command name the same file.
    #[error("{}: is named as two different outputs; give each output its own path", path.display())]
    Twice {
        /// The output path.
        path: PathBuf,
    },
    /// The file system refused.
    #[error("cannot {action} {}: {source}", path.display())]
    Io {
        /// `create` (a folder), `write` or `rename`.
        action: &'static str,
        /// The file or folder.
        path: PathBuf,
        /// What the system said.
        #[source]
        source: std::io::Error,
    },
}

/// The outputs of one command, checked against its inputs before any long work starts.
#[derive(Debug, Default, Clone)]
pub struct Outputs {
    /// The inputs that exist, each as the file it names (links followed).
    inputs: Vec<PathBuf>,
    /// The outputs claimed so far, as [`Outputs::claim`] resolved them.
    claimed: Vec<PathBuf>,
}

impl Outputs {
    /// The outputs of a command that reads `inputs` (paths or other arguments: only those
    /// naming an existing file count).
    pub fn reading<P: AsRef<Path>>(inputs: impl IntoIterator<Item = P>) -> Self {
        Self {
            inputs: inputs
                .into_iter()
                .filter_map(|p| std::fs::canonicalize(p.as_ref()).ok())
                .collect(),
            claimed: Vec::new(),
        }
    }

    /// Claims `path` as an output: refused when it is an input or already claimed. Call it for
    /// every output before the work that makes them.
    pub fn claim(&mut self, path: &Path) -> Result<(), OutputError> {
        let resolved = resolve(path);
        if self.inputs.contains(&resolved) {
            return Err(OutputError::IsInput {
                path: path.to_path_buf(),
            });
        }
        if self.claimed.contains(&resolved) {
            return Err(OutputError::Twice {
                path: path.to_path_buf(),
            });
        }
        self.claimed.push(resolved);
        Ok(())
    }

    /// Writes `bytes` to `path` whole ([`write_file`]), after checking it is not an input.
    pub fn write(&self, path: &Path, bytes: &[u8]) -> Result<(), OutputError> {
        if self.inputs.contains(&resolve(path)) {
            return Err(OutputError::IsInput {
                path: path.to_path_buf(),
            });
        }
        write_file(path, bytes)
    }
}

/// Where `path` points: the file itself when it exists (links followed), else its folder's
/// resolved path with its name.
fn resolve(path: &Path) -> PathBuf {
    if let Ok(p) = std::fs::canonicalize(path) {
        return p;
    }
    let parent = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    match (std::fs::canonicalize(parent), path.file_name()) {
        (Ok(dir), Some(name)) => dir.join(name),
        _ => path.to_path_buf(),
    }
}

/// [`write_atomically`], creating the file's folder first if needed.
pub fn write_file(path: &Path, bytes: &[u8]) -> Result<(), OutputError> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|source| OutputError::Io {
            action: "create",
            path: dir.to_path_buf(),
            source,
        })?;
    }
    write_atomically(path, bytes)
}

/// Writes `bytes` to `path` through a temporary file in the same folder, flushed to disk and
/// renamed over `path`: whoever reads `path` sees the old file or the new one, whole. The
/// folder must exist (a folder that vanished is an error, not made again).
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), OutputError> {
    write_atomically_with(path, |file| file.write_all(bytes))
}

/// [`write_atomically`] of what `write` writes to the temporary file.
pub fn write_atomically_with(
    path: &Path,
    write: impl FnOnce(&mut File) -> std::io::Result<()>,
) -> Result<(), OutputError> {
    let io = |action, path: &Path| {
        let path = path.to_path_buf();
        move |source| OutputError::Io {
            action,
            path,
            source,
        }
    };
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty());
    let name = path
        .file_name()
        .map_or_else(Default::default, |n| n.to_string_lossy());
    let partial = path.with_file_name(format!(".{name}.{}.partial", std::process::id()));
    let written = File::create(&partial)
        .and_then(|mut file| {
            write(&mut file)?;
            file.sync_all()
        })
        .map_err(io("write", &partial))
        .and_then(|()| std::fs::rename(&partial, path).map_err(io("rename", path)));
    if written.is_err() {
        let _ = std::fs::remove_file(&partial);
    }
    written?;
    if let Some(dir) = dir {
        // Make the rename itself durable; not every file system lets a folder be synced.
        let _ = File::open(dir).and_then(|d| d.sync_all());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("prehensile-output-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn an_input_is_never_an_output() {
        let dir = scratch("input");
        let mesh = dir.join("part.obj");
        std::fs::write(&mesh, "v 0 0 0\n").unwrap();
        let mut outputs = Outputs::reading([mesh.as_path(), Path::new("sphere")]);
        // The same file named another way is still the input.
        let other_name = dir.join(".").join("part.obj");
        assert!(matches!(
            outputs.claim(&other_name),
            Err(OutputError::IsInput { .. })
        ));
        assert!(outputs.write(&mesh, b"{}").is_err());
        assert_eq!(std::fs::read_to_string(&mesh).unwrap(), "v 0 0 0\n");
        outputs.claim(&dir.join("grasp.json")).unwrap();
        assert!(matches!(
            outputs.claim(&dir.join("grasp.json")),
            Err(OutputError::Twice { .. })
        ));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_failed_write_keeps_the_old_file_whole_and_leaves_no_scrap() {
        let dir = scratch("whole");
        let path = dir.join("run.json");
        std::fs::write(&path, "old").unwrap();
        let failed = write_atomically_with(&path, |f| {
            f.write_all(b"half")?;
            Err(std::io::Error::other("interrupted"))
        });
        assert!(failed.is_err());
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
        assert_eq!(
            std::fs::read_dir(&dir).unwrap().count(),
            1,
            "a scrap was left"
        );
        write_atomically(&path, b"new").unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
        assert!(write_atomically(&dir.join("sub/deeper/x.txt"), b"x").is_err());
        write_file(&dir.join("sub/deeper/x.txt"), b"x").unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
