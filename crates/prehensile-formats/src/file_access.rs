//! Reading input files safely: regular files only (no FIFO, device or folder, which could block or
//! never end), with a size cap checked before and while reading; and files a file refers to (glTF
//! buffers, MJCF includes) only from the referring file's own folder and below — no absolute
//! path, no `..` out of it, no symbolic link leading out of it.

use std::io::Read;
use std::path::{Component, Path, PathBuf};

use crate::FormatError;

/// Largest hand or motion file read (TOML, URDF, MJCF with its includes, BVH, JSON), bytes.
pub const MAX_TEXT_BYTES: u64 = 64 << 20;
/// Largest mesh or glTF file (or glTF buffer) read, bytes.
pub const MAX_MESH_BYTES: u64 = 2 << 30;

/// The bytes of `path`, refused unless it is a regular file of at most `max` bytes.
pub fn read_input(path: &Path, max: u64) -> Result<Vec<u8>, FormatError> {
    let name = path.display().to_string();
    let meta = std::fs::metadata(path)
        .map_err(|e| FormatError::new(&name, format!("cannot read the file: {e}")))?;
    if !meta.is_file() {
        return Err(FormatError::new(
            &name,
            "not a regular file (a folder, device or pipe); give the path of a file",
        ));
    }
    if meta.len() > max {
        return Err(FormatError::new(
            &name,
            format!(
                "{} bytes is larger than the {max}-byte limit for this kind of file",
                meta.len()
            ),
        ));
    }
    let file = std::fs::File::open(path)
        .map_err(|e| FormatError::new(&name, format!("cannot read the file: {e}")))?;
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    // The size may have changed since: never read more than the cap.
    file.take(max + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| FormatError::new(&name, format!("cannot read the file: {e}")))?;
    if bytes.len() as u64 > max {
        return Err(FormatError::new(
            &name,
            format!("the file grew past the {max}-byte limit while it was read"),
        ));
    }
    Ok(bytes)
}

/// The text of `path` (UTF-8), refused unless it is a regular file of at most `max` bytes.
pub fn read_input_text(path: &Path, max: u64) -> Result<String, FormatError> {
    let bytes = read_input(path, max)?;
    String::from_utf8(bytes).map_err(|e| {
        FormatError::new(
            &path.display().to_string(),
            format!("the file is not UTF-8 text: {e}"),
        )
    })
}

/// The file that `reference` (relative, `/`-separated, as in a glTF URI or an MJCF include) names
/// beside `referrer`, refused if it would lie outside `referrer`'s folder: absolute paths, URI
/// schemes, `..` components and symbolic links that lead out are errors naming the reference.
pub fn confined(referrer: &Path, reference: &str) -> Result<PathBuf, FormatError> {
    let name = referrer.display().to_string();
    let refuse = |why: &str| {
        Err(FormatError::new(
            &name,
            format!(
                "refers to '{reference}', {why}; files it uses must lie in its own folder or below"
            ),
        ))
    };
    let decoded = percent_decode(reference);
    if decoded.contains(':') || decoded.starts_with('/') || decoded.starts_with('\\') {
        return refuse("an absolute path or URI");
    }
    let relative = Path::new(&decoded);
    if relative
        .components()
        .any(|c| !matches!(c, Component::Normal(_) | Component::CurDir))
    {
        return refuse("which leaves the folder (..) or is absolute");
    }
    let folder = referrer.parent().unwrap_or(Path::new("."));
    let folder = if folder.as_os_str().is_empty() {
        Path::new(".")
    } else {
        folder
    };
    let target = folder.join(relative);
    // Symbolic links: the real path must stay below the real folder.
    let (real_folder, real_target) = match (folder.canonicalize(), target.canonicalize()) {
        (Ok(f), Ok(t)) => (f, t),
        (_, Err(e)) => {
            return Err(FormatError::new(
                &name,
                format!("cannot read '{reference}': {e}"),
            ))
        }
        (Err(e), _) => {
            return Err(FormatError::new(
                &name,
                format!("cannot read its folder: {e}"),
            ))
        }
    };
    if !real_target.starts_with(&real_folder) {
        return refuse("a link that leads out of its folder");
    }
    Ok(target)
}

/// `%XX` escapes decoded (glTF URIs are URI-encoded); anything malformed is kept as it is.
fn percent_decode(s: &str) -> String {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' && i + 2 < bytes.len() {
            let hex = |b: u8| (b as char).to_digit(16);
            if let (Some(h), Some(l)) = (hex(bytes[i + 1]), hex(bytes[i + 2])) {
                out.push((h * 16 + l) as u8);
                i += 3;
                continue;
            }
        }
        out.push(bytes[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn references_stay_in_the_folder() {
        let dir = std::env::temp_dir().join(format!("prehensile-confined-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        std::fs::write(dir.join("sub/b.bin"), b"x").unwrap();
        std::fs::write(dir.join("a.gltf"), b"{}").unwrap();
        let referrer = dir.join("a.gltf");
        assert!(confined(&referrer, "sub/b.bin").is_ok());
        assert!(confined(&referrer, "sub%2Fb.bin").is_ok());
        for bad in [
            "/etc/passwd",
            "../x.bin",
            "sub/../../x",
            "file:///etc/passwd",
            "%2E%2E/x",
        ] {
            let e = confined(&referrer, bad).unwrap_err();
            assert!(e.reason.contains("own folder"), "{bad}: {e}");
        }
        #[cfg(unix)]
        {
            let _ = std::fs::remove_file(dir.join("out.bin"));
            std::os::unix::fs::symlink("/etc/hostname", dir.join("out.bin")).unwrap();
            let e = confined(&referrer, "out.bin").unwrap_err();
            assert!(e.reason.contains("link"), "{e}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn only_regular_files_of_bounded_size_are_read() {
        let e = read_input(Path::new("/dev/zero"), 1024).unwrap_err();
        assert!(e.reason.contains("not a regular file"), "{e}");
        let e = read_input(Path::new("."), 1024).unwrap_err();
        assert!(e.reason.contains("not a regular file"), "{e}");
        let file = std::env::temp_dir().join(format!("prehensile-cap-{}", std::process::id()));
        std::fs::write(&file, vec![b'a'; 100]).unwrap();
        assert!(read_input(&file, 99).unwrap_err().reason.contains("limit"));
        assert_eq!(read_input(&file, 100).unwrap().len(), 100);
        std::fs::remove_file(&file).unwrap();
    }
}
