//! Files written for the user: atomically (a temporary file beside the
//! target, then a rename), never silently over an existing file, and
//! directly when the target is not a regular file (stdout, a pipe).

use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// Why an output could not be written; the message names the path.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    #[error("{path} already exists (use --force to overwrite)")]
    Exists { path: PathBuf },
    #[error("cannot write {path}: {source}")]
    Io { path: PathBuf, source: io::Error },
}

/// Checks, before any work, that `path` can be written: "-" always can; an
/// existing regular file needs `force`; the parent folder must exist.
pub fn check_writable(path: &Path, force: bool) -> Result<(), OutputError> {
    if path.as_os_str() == "-" {
        return Ok(());
    }
    let io_err = |source| OutputError::Io {
        path: path.to_path_buf(),
        source,
    };
    match fs::metadata(path) {
        Ok(m) if m.is_file() && !force => {
            return Err(OutputError::Exists {
                path: path.to_path_buf(),
            });
        }
        Ok(m) if m.is_dir() => {
            return Err(io_err(io::Error::new(
                io::ErrorKind::IsADirectory,
                "it is a directory",
            )));
        }
        _ => {}
    }
    let parent = parent_dir(path);
    match fs::metadata(&parent) {
        Ok(m) if m.is_dir() => {
            if m.permissions().readonly() {
                return Err(io_err(io::Error::new(
                    io::ErrorKind::PermissionDenied,
                    "folder is read-only",
                )));
            }
            Ok(())
        }
        Ok(_) => Err(io_err(io::Error::new(
            io::ErrorKind::NotADirectory,
            "parent is not a folder",
        ))),
        Err(e) => Err(io_err(e)),
    }
}

fn parent_dir(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Writes `bytes` to `path`: "-" is stdout; a regular (or new) file is written
/// to a temporary file in the same folder and renamed into place, refusing to
/// replace an existing file unless `force`; anything else (a pipe,
/// /dev/stdout) is written directly.
pub fn write_output(path: &Path, bytes: &[u8], force: bool) -> Result<(), OutputError> {
    let io_err = |source| OutputError::Io {
        path: path.to_path_buf(),
        source,
    };
    if path.as_os_str() == "-" {
        let mut out = io::stdout().lock();
        return out
            .write_all(bytes)
            .and_then(|_| out.flush())
            .map_err(io_err);
    }
    match fs::metadata(path) {
        Ok(m) if !m.is_file() && !m.is_dir() => {
            // A device or a pipe: never rename over it.
            let mut f = fs::OpenOptions::new()
                .write(true)
                .open(path)
                .map_err(io_err)?;
            return f.write_all(bytes).map_err(io_err);
        }
        Ok(m) if m.is_file() && !force => {
            return Err(OutputError::Exists {
                path: path.to_path_buf(),
            });
        }
        _ => {}
    }
    let dir = parent_dir(path);
    let mut tmp = tempfile::Builder::new()
        .prefix(".oneblock-")
        .suffix(".tmp")
        .tempfile_in(&dir)
        .map_err(io_err)?;
    // tempfile creates its files private (0600); a figure or a CSV for the
    // user gets the usual mode, or the mode of the file it replaces.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = fs::metadata(path)
            .map(|m| m.permissions().mode() & 0o777)
            .unwrap_or(0o644);
        tmp.as_file()
            .set_permissions(fs::Permissions::from_mode(mode))
            .map_err(io_err)?;
    }
    tmp.write_all(bytes).map_err(io_err)?;
    tmp.as_file().sync_all().map_err(io_err)?;
    if force {
        tmp.persist(path).map_err(|e| io_err(e.error))?;
    } else {
        // Fails if the file appeared meanwhile: never overwrite silently.
        tmp.persist_noclobber(path).map_err(|e| {
            if e.error.kind() == io::ErrorKind::AlreadyExists {
                OutputError::Exists {
                    path: path.to_path_buf(),
                }
            } else {
                io_err(e.error)
            }
        })?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_atomically_and_refuses_to_clobber() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.csv");
        write_output(&p, b"one", false).unwrap();
        assert_eq!(fs::read(&p).unwrap(), b"one");
        assert!(matches!(
            write_output(&p, b"two", false),
            Err(OutputError::Exists { .. })
        ));
        assert!(matches!(
            check_writable(&p, false),
            Err(OutputError::Exists { .. })
        ));
        write_output(&p, b"two", true).unwrap();
        assert_eq!(fs::read(&p).unwrap(), b"two");
        // No temporary files left behind, and the usual mode, not 0600.
        assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 1);
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            assert_eq!(
                fs::metadata(&p).unwrap().permissions().mode() & 0o777,
                0o644
            );
        }
        assert!(check_writable(&dir.path().join("missing/x.csv"), false).is_err());
    }
}
