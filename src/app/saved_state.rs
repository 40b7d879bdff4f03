//! The window's saved state (eframe's `app.ron`), checked before eframe
//! reads it. A state that cannot be used (too large, not a regular file,
//! not UTF-8, not the RON eframe writes, settings that do not parse) is
//! set aside: renamed beside itself, named in a message, and the window
//! opens on defaults. It never bricks the next launch. Settings that parse
//! but hold spoiled values are brought back into range field by field
//! (`Settings::sanitised`, when the window opens).

use std::collections::HashMap;
use std::io::Read as _;
use std::path::{Path, PathBuf};

use super::settings::Settings;
use crate::text::echo;

/// The largest saved state read, in bytes. The window's own state is a
/// few KB of settings and some tens of KB of egui's memory; a 10 MB save
/// folder string once made every launch abort.
pub const MAX_BYTES: u64 = 4 << 20;

/// Where eframe keeps the window's state for this app (None where the
/// platform has no such folder).
#[cfg(not(target_arch = "wasm32"))]
pub fn default_path() -> Option<PathBuf> {
    eframe::storage_dir("oneblock").map(|d| d.join("app.ron"))
}

/// In a browser the state is in the page's local storage, read by eframe
/// (and its settings sanitised when the window opens): no file to check.
#[cfg(target_arch = "wasm32")]
pub fn default_path() -> Option<PathBuf> {
    None
}

/// Checks the saved state at `path`. `None` when it is absent or usable
/// (eframe then reads it); else the message for the window, after the
/// file was renamed aside (or, if even that failed, saying so).
pub fn check(path: &Path) -> Option<String> {
    let reason = match unusable(path) {
        Ok(()) => return None,
        Err(r) => r,
    };
    let shown = echo(&path.display().to_string());
    Some(match set_aside(path) {
        Ok(to) => format!(
            "The saved state {shown} could not be used ({reason}): it was set aside as {} \
             and the window opens on defaults.",
            echo(&to.file_name().unwrap_or_default().to_string_lossy())
        ),
        Err(e) => format!(
            "The saved state {shown} could not be used ({reason}) nor set aside ({}): \
             the window opens on defaults; delete the file.",
            echo(&e.to_string())
        ),
    })
}

/// Why the state at `path` cannot be used, or `Ok` (also when absent).
fn unusable(path: &Path) -> Result<(), String> {
    let meta = match std::fs::symlink_metadata(path) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(e.to_string()),
    };
    // A link (a state kept with one's dotfiles) is read through: its
    // target is what must be a regular file. A dangling one is set aside.
    let meta = if meta.file_type().is_symlink() {
        std::fs::metadata(path).map_err(|e| format!("a link to nothing readable: {e}"))?
    } else {
        meta
    };
    if !meta.is_file() {
        return Err("not a regular file".into());
    }
    if meta.len() > MAX_BYTES {
        return Err(format!("{} bytes, more than {MAX_BYTES}", meta.len()));
    }
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(MAX_BYTES + 1).read_to_end(&mut bytes))
        .map_err(|e| e.to_string())?;
    if bytes.len() as u64 > MAX_BYTES {
        return Err(format!("more than {MAX_BYTES} bytes"));
    }
    let text = String::from_utf8(bytes).map_err(|_| "not UTF-8 text".to_string())?;
    let kv: HashMap<String, String> =
        ron::from_str(&text).map_err(|_| "not the RON the window writes".to_string())?;
    if let Some(app) = kv.get(eframe::APP_KEY) {
        ron::from_str::<Settings>(app).map_err(|_| "its settings do not parse".to_string())?;
    }
    Ok(())
}

/// Renames `path` to `NAME.unusable-N` beside it, N the first free number.
fn set_aside(path: &Path) -> std::io::Result<PathBuf> {
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    for n in 1..1000 {
        let to = path.with_file_name(format!("{name}.unusable-{n}"));
        if std::fs::symlink_metadata(&to).is_err() {
            std::fs::rename(path, &to)?;
            return Ok(to);
        }
    }
    Err(std::io::Error::other("999 set-aside copies already exist"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn state(settings: &str) -> String {
        let kv: HashMap<String, String> =
            [(eframe::APP_KEY.to_string(), settings.to_string())].into();
        ron::to_string(&kv).expect("ron")
    }

    #[test]
    fn a_sound_state_is_kept_and_absent_is_fine() {
        let dir = tempfile::tempdir().expect("dir");
        let p = dir.path().join("app.ron");
        assert_eq!(check(&p), None);
        let good = ron::to_string(&Settings::default()).expect("ron");
        std::fs::write(&p, state(&good)).expect("write");
        assert_eq!(check(&p), None);
        assert!(p.exists());
    }

    #[test]
    fn an_unusable_state_is_set_aside_with_a_message() {
        let dir = tempfile::tempdir().expect("dir");
        let p = dir.path().join("app.ron");
        let huge = vec![b'x'; MAX_BYTES as usize + 1];
        let cases: Vec<(Vec<u8>, &str)> = vec![
            (b"(\"app\": ".to_vec(), "RON"),
            (vec![0xff, 0xfe, b'(', b')'], "UTF-8"),
            (state("(tiled: 7)").into_bytes(), "settings"),
            (huge, "bytes"),
        ];
        for (i, (bytes, why)) in cases.into_iter().enumerate() {
            std::fs::write(&p, &bytes).expect("write");
            let m = check(&p).expect("a message");
            assert!(m.contains(why) && m.contains("set aside"), "{m}");
            assert_eq!(m.lines().count(), 1);
            assert!(!p.exists());
            let aside = dir.path().join(format!("app.ron.unusable-{}", i + 1));
            assert_eq!(std::fs::read(&aside).expect("kept").len(), bytes.len());
        }
        std::fs::create_dir(&p).expect("dir");
        assert!(check(&p).expect("a message").contains("not a regular file"));
    }

    #[cfg(unix)]
    #[test]
    fn a_linked_state_is_read_through_its_link() {
        let dir = tempfile::tempdir().expect("dir");
        let (p, real) = (dir.path().join("app.ron"), dir.path().join("real.ron"));
        let good = ron::to_string(&Settings::default()).expect("ron");
        std::fs::write(&real, state(&good)).expect("write");
        std::os::unix::fs::symlink(&real, &p).expect("link");
        assert_eq!(check(&p), None);
        assert!(p.exists() && real.exists());
        // A link to a state that cannot be used is set aside (the link).
        std::fs::write(&real, "(\"app\": ").expect("write");
        assert!(check(&p).expect("a message").contains("set aside"));
        assert!(real.exists());
        // A dangling link too.
        std::fs::remove_file(&real).expect("rm");
        std::os::unix::fs::symlink(dir.path().join("gone"), &p).expect("link");
        assert!(check(&p).expect("a message").contains("link"));
    }
}
