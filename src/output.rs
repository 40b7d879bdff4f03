//! Files written for the user: atomically (a temporary file beside the
//! target, then a rename), never silently over an existing file, and
//! directly when the target is not a regular file (stdout, a pipe).

use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard, PoisonError};

/// Why an output could not be written; the message names the path.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    #[error("{} already exists (use --force to overwrite)", shown(path))]
    Exists { path: PathBuf },
    #[error("cannot write {}: {source}", shown(path))]
    Io { path: PathBuf, source: io::Error },
}

/// A path as a message shows it: control characters escaped, and one
/// longer than 120 characters cut to its first 80 and "…" (a 325-byte
/// name made a message of several hundred).
fn shown(path: &Path) -> String {
    let s = path.display().to_string();
    if s.chars().nth(120).is_some() {
        let head: String = s.chars().take(80).collect();
        format!("{}…", crate::text::escape_controls(&head))
    } else {
        crate::text::escape_controls(&s)
    }
}

/// The most symbolic links followed from an output path.
const MAX_LINKS: usize = 40;

/// Where a write to `path` really goes: the end of its chain of symbolic
/// links, so that a file is replaced at the link's target and the link
/// itself is kept. A link into `/proc` (as `/dev/stdout` is) is left as
/// it is: the kernel resolves it to an open file, not to a path.
pub fn resolve_links(path: &Path) -> Result<PathBuf, OutputError> {
    let mut p = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        if p.starts_with("/proc") {
            return Ok(p);
        }
        match fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => {
                let target = fs::read_link(&p).map_err(|source| OutputError::Io {
                    path: path.to_path_buf(),
                    source,
                })?;
                p = if target.is_absolute() {
                    target
                } else {
                    parent_dir(&p).join(target)
                };
            }
            _ => return Ok(p),
        }
    }
    Err(OutputError::Io {
        path: path.to_path_buf(),
        source: io::Error::other(format!("more than {MAX_LINKS} symbolic links")),
    })
}

/// Whether two output paths name the same file (after following links),
/// so that one would silently overwrite the other. A device (such as
/// `/dev/null`) given twice is not: each output is written to it in turn,
/// and nothing is lost that was not meant to be.
pub fn same_output(a: &Path, b: &Path) -> bool {
    if a.as_os_str() == "-" || b.as_os_str() == "-" {
        return a.as_os_str() == b.as_os_str();
    }
    let is_device = |p: &Path| {
        resolve_links(p)
            .ok()
            .and_then(|r| fs::metadata(r).ok())
            .is_some_and(|m| !m.is_file() && !m.is_dir())
    };
    if is_device(a) && is_device(b) {
        return false;
    }
    let key = |p: &Path| -> Option<PathBuf> {
        let r = resolve_links(p).ok()?;
        let dir = fs::canonicalize(parent_dir(&r)).ok()?;
        Some(dir.join(r.file_name()?))
    };
    match (key(a), key(b)) {
        (Some(x), Some(y)) => x == y,
        _ => a == b,
    }
}

/// Checks, before any work, that `path` can be written: "-" always can; an
/// existing regular file needs `force`; in the parent folder a file must
/// really be creatable (tried, then removed: permission bits alone miss a
/// read-only mount, found otherwise only after the computation). A
/// symbolic link is checked at its target.
pub fn check_writable(path: &Path, force: bool) -> Result<(), OutputError> {
    if path.as_os_str() == "-" {
        return Ok(());
    }
    let target = resolve_links(path)?;
    let io_err = |source| OutputError::Io {
        path: path.to_path_buf(),
        source,
    };
    check_length(&target).map_err(io_err)?;
    match fs::metadata(&target) {
        // The file behind an open descriptor (`/dev/stdout > file`): the
        // shell has already opened it for us.
        Ok(m) if m.is_file() && target.starts_with("/proc") => return Ok(()),
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
        Ok(m) if !m.is_file() => return Ok(()),
        _ => {}
    }
    let parent = parent_dir(&target);
    match fs::metadata(&parent) {
        Ok(m) if m.is_dir() => {
            // The same kind of file the write will create, dropped (and so
            // removed) at once.
            tempfile::Builder::new()
                .prefix(".oneblock-")
                .suffix(".tmp")
                .tempfile_in(&parent)
                .map(drop)
                .map_err(io_err)
        }
        Ok(_) => Err(io_err(io::Error::new(
            io::ErrorKind::NotADirectory,
            "parent is not a folder",
        ))),
        Err(e) => Err(io_err(e)),
    }
}

/// The longest file name a folder holds (ext4, XFS, Btrfs, tmpfs), in bytes.
const NAME_MAX: usize = 255;
/// The longest path the system opens, in bytes.
const PATH_MAX: usize = 4095;

/// A name or path too long to create, found before any work: creating a
/// temporary file beside it cannot tell (its own name is short), and the
/// write then failed only after the computation.
fn check_length(target: &Path) -> Result<(), io::Error> {
    let name = target.file_name().map_or(0, |n| n.len());
    if name > NAME_MAX {
        return Err(io::Error::other(format!(
            "its file name is {name} bytes long, more than the {NAME_MAX} a folder allows"
        )));
    }
    let whole = target.as_os_str().len();
    if whole > PATH_MAX {
        return Err(io::Error::other(format!(
            "the path is {whole} bytes long, more than the {PATH_MAX} the system allows"
        )));
    }
    Ok(())
}

fn parent_dir(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// The files written so far by this process, behind a lock held through
/// each write: whoever ends the process early (the command line's
/// watchdog, Ctrl+C in the window) takes it first, so that no write is cut
/// half way (a temporary file left behind), and says that nothing was
/// written only when that is so.
static WRITTEN: Mutex<usize> = Mutex::new(0);

/// The count of files written, locked: no write starts or ends while it is
/// held.
pub fn writes_lock() -> MutexGuard<'static, usize> {
    WRITTEN.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Writes `bytes` to `path`: "-" is stdout; a regular (or new) file is written
/// to a temporary file in the same folder and renamed into place, refusing to
/// replace an existing file unless `force`; anything else (a pipe,
/// /dev/stdout) is written directly. A symbolic link is followed: the file
/// at its target is replaced, the link is kept.
pub fn write_output(path: &Path, bytes: &[u8], force: bool) -> Result<(), OutputError> {
    let mut written = writes_lock();
    write_unlocked(path, bytes, force)?;
    *written += 1;
    Ok(())
}

/// [`write_output`] without the lock.
fn write_unlocked(path: &Path, bytes: &[u8], force: bool) -> Result<(), OutputError> {
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
    let target = resolve_links(path)?;
    match fs::metadata(&target) {
        Ok(m) if (!m.is_file() && !m.is_dir()) || (m.is_file() && target.starts_with("/proc")) => {
            // A device, a pipe, or the file behind an open descriptor:
            // never rename over it.
            let mut f = fs::OpenOptions::new()
                .write(true)
                .open(&target)
                .map_err(io_err)?;
            return f.write_all(bytes).and_then(|_| f.flush()).map_err(io_err);
        }
        Ok(m) if m.is_file() && !force => {
            return Err(OutputError::Exists {
                path: path.to_path_buf(),
            });
        }
        _ => {}
    }
    let dir = parent_dir(&target);
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
        let mode = fs::metadata(&target)
            .map(|m| m.permissions().mode() & 0o777)
            .unwrap_or(0o644);
        tmp.as_file()
            .set_permissions(fs::Permissions::from_mode(mode))
            .map_err(io_err)?;
    }
    tmp.write_all(bytes).map_err(io_err)?;
    tmp.as_file().sync_all().map_err(io_err)?;
    if force {
        tmp.persist(&target).map_err(|e| io_err(e.error))?;
    } else {
        // Fails if the file appeared meanwhile: never overwrite silently.
        tmp.persist_noclobber(&target).map_err(|e| {
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
        // The probe leaves nothing behind.
        check_writable(&dir.path().join("b.csv"), false).unwrap();
        assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[cfg(unix)]
    #[test]
    fn two_device_outputs_are_not_the_same_file() {
        let null = Path::new("/dev/null");
        assert!(!same_output(null, null));
        let dir = tempfile::tempdir().unwrap();
        let f = dir.path().join("f.csv");
        assert!(same_output(&f, &f));
    }

    #[cfg(unix)]
    #[test]
    fn force_through_a_link_replaces_the_target_and_keeps_the_link() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("real.csv");
        let link = dir.path().join("link.csv");
        fs::write(&target, b"old").unwrap();
        std::os::unix::fs::symlink("real.csv", &link).unwrap();
        assert!(matches!(
            write_output(&link, b"new", false),
            Err(OutputError::Exists { .. })
        ));
        write_output(&link, b"new", true).unwrap();
        assert!(
            fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(fs::read(&target).unwrap(), b"new");
        assert!(same_output(&link, &target));
        assert!(same_output(&target, &dir.path().join(".").join("real.csv")));
        assert!(!same_output(&target, &dir.path().join("other.csv")));
        // A dangling link is written through: the file appears at its target.
        let dangling = dir.path().join("dangling.csv");
        std::os::unix::fs::symlink("new.csv", &dangling).unwrap();
        write_output(&dangling, b"x", false).unwrap();
        assert_eq!(fs::read(dir.path().join("new.csv")).unwrap(), b"x");
        assert!(
            fs::symlink_metadata(&dangling)
                .unwrap()
                .file_type()
                .is_symlink()
        );
    }
}
