//! Sessions: what is on screen as a small JSON file ("Save session"), and
//! back (`oneblock gui --session FILE`). A session is the persisted
//! [`Settings`] (parameters, accuracy, layout and view, phase grid and its
//! zoom, the preset chosen, text size) plus the bifurcation diagram's zoom
//! stack, which lives in its view, and the results the window computes
//! only when asked ([`Results`]: Find bifurcations' branches, Boundaries'
//! curves), which reopen without a job.
//!
//! Reading is forgiving field by field: a field the file gets wrong (a
//! wrong type, a value out of range, a zoom too narrow to draw, a list or
//! string too long) or one this version does not know is named in one
//! message, and every other field is kept as the file has it. What cannot
//! be a session at all is refused in one line by [`Session::read`]: a
//! version this build does not understand, a FIFO, a directory, a file
//! too large or not UTF-8.

use std::io::Read as _;
use std::path::Path;

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

use super::bifurcation::Zoom;
use super::session_results::KEYS as RESULT_KEYS;
pub use super::session_results::Results;
use super::settings::{DiagramAxis, MAX_ZOOM_LEVELS, Settings, is_usable_range};
use crate::sim::continuation::ContParam;
use crate::text::echo;

/// The format's version, written as `oneblock_session`.
pub const VERSION: u32 = 1;

/// The largest session file read, in bytes. A session the window writes
/// is about 2 KB, and about 40 KB with the branches of Fig. 3b's cascade
/// to P32 (src/app/session_results.rs); the bound keeps a hostile file's
/// parse small, and a session that would exceed it is saved without its
/// results ([`Session::to_file_text`]).
pub const MAX_FILE_BYTES: u64 = 4 << 20;

/// A session: the settings, the bifurcation zoom stack (innermost last)
/// and the results kept.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Session {
    pub settings: Settings,
    pub bifurcation_zoom: Vec<Zoom>,
    pub results: Results,
}

/// One zoom level as the file holds it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
struct ZoomFile {
    theta_nu: (f64, f64),
    theta: (f64, f64),
}

impl ZoomFile {
    /// Both ranges drawable, the first (of the parameter the diagram
    /// varies: its name `theta_nu` is the paper's default) within the
    /// model's range of that parameter ([-π, π] for θν: a zoom beyond it
    /// was an empty diagram, accepted without a word).
    fn is_valid(&self, varied: ContParam) -> bool {
        let max = crate::model::MAX_ABS_THETA;
        DiagramAxis::is_valid_range(varied, self.theta_nu)
            && is_usable_range(self.theta)
            && -max <= self.theta.0
            && self.theta.1 <= max
    }
}

/// What a session file held, and what was wrong with it.
#[derive(Clone, Debug)]
pub struct Loaded {
    pub session: Session,
    /// One sentence naming every field that was replaced by its default
    /// or ignored; `None` when the file was clean.
    pub message: Option<String>,
}

impl Session {
    /// The session as pretty JSON, its results each on one line of
    /// compact JSON (a branch holds thousands of numbers).
    pub fn to_json(&self) -> String {
        let zoom: Vec<ZoomFile> = self
            .bifurcation_zoom
            .iter()
            .map(|z| ZoomFile {
                theta_nu: z.theta_nu,
                theta: z.theta,
            })
            .collect();
        let v = serde_json::json!({
            "oneblock_session": VERSION,
            "settings": self.settings,
            "bifurcation_zoom": zoom,
        });
        let mut s = serde_json::to_string_pretty(&v).unwrap_or_else(|_| "{}".into());
        // The pretty object ends in "\n}": the results go before it.
        if s.ends_with("\n}") {
            s.truncate(s.len() - 2);
            for (key, text) in self.results.to_fields() {
                s.push_str(&format!(",\n  \"{key}\": {text}"));
            }
            s.push_str("\n}");
        }
        s.push('\n');
        s
    }

    /// The text Save session writes: [`Session::to_json`], or, should its
    /// results make it larger than [`MAX_FILE_BYTES`] (which it would then
    /// refuse to read), the session without them and a sentence saying so.
    pub fn to_file_text(&self) -> (String, Option<String>) {
        let text = self.to_json();
        if text.len() as u64 <= MAX_FILE_BYTES {
            return (text, None);
        }
        let bare = Session {
            results: Results::default(),
            ..self.clone()
        };
        let why = format!(
            "the branches and boundaries would make the session over {MAX_FILE_BYTES} bytes: \
             saved without them"
        );
        (bare.to_json(), Some(why))
    }

    /// Reads the session file at `path`: refused (one line, naming the
    /// file) when it is not a regular file (a FIFO is opened without
    /// blocking and refused), larger than [`MAX_FILE_BYTES`], not UTF-8,
    /// or of a version this build does not understand; otherwise
    /// [`Session::from_json`].
    pub fn read(path: &Path) -> Result<Loaded, String> {
        let name = echo(&path.display().to_string());
        let text = read_text(path).map_err(|e| format!("cannot read {name}: {e}"))?;
        Session::from_text(&text, &name)
    }

    /// A session from the text of a file named `name` (an upload in the
    /// browser, or [`Session::read`]): refused if it is of a version this
    /// build does not understand, otherwise [`Session::from_json`].
    pub fn from_text(text: &str, name: &str) -> Result<Loaded, String> {
        if let Ok(Value::Object(m)) = serde_json::from_str::<Value>(text)
            && let Some(v) = m.get("oneblock_session")
            && v.as_u64() != Some(u64::from(VERSION))
        {
            let shown = echo(&v.to_string());
            return Err(format!(
                "{name} is a session of version {shown}, which this oneblock does not \
                 understand (it reads version {VERSION})"
            ));
        }
        Ok(Session::from_json(text, name))
    }

    /// Reads a session from `text`, `what` naming it in the message (the
    /// file name). Never fails: what cannot be read is left at its default.
    pub fn from_json(text: &str, what: &str) -> Loaded {
        let mut bad: Vec<String> = Vec::new();
        let mut unknown: Vec<String> = Vec::new();
        let mut root = match serde_json::from_str::<Value>(text) {
            Ok(Value::Object(m)) => m,
            Ok(_) => {
                return Loaded::defaults(format!(
                    "session {what}: not a JSON object: every setting is at its default"
                ));
            }
            Err(e) => {
                return Loaded::defaults(format!(
                    "session {what}: not valid JSON ({e}): every setting is at its default"
                ));
            }
        };
        for k in root.keys() {
            let known = ["oneblock_session", "settings", "bifurcation_zoom"];
            if !known.contains(&k.as_str()) && !RESULT_KEYS.contains(&k.as_str()) {
                unknown.push(echo(k));
            }
        }
        let settings = match root.get("settings") {
            Some(Value::Object(m)) => settings_from(m, &mut bad, &mut unknown),
            Some(_) => {
                bad.push("settings".into());
                Settings::default()
            }
            None => Settings::default(),
        };
        let (settings, out_of_range) = settings.sanitised();
        bad.extend(out_of_range.iter().map(|s| s.to_string()));
        let bifurcation_zoom = match root.get("bifurcation_zoom") {
            None => Vec::new(),
            Some(v) => match serde_json::from_value::<Vec<ZoomFile>>(v.clone()) {
                Ok(z)
                    if z.len() <= MAX_ZOOM_LEVELS
                        && z.iter().all(|z| z.is_valid(settings.diagram.param)) =>
                {
                    z.into_iter()
                        .map(|z| Zoom {
                            theta_nu: z.theta_nu,
                            theta: z.theta,
                        })
                        .collect()
                }
                _ => {
                    bad.push("bifurcation_zoom".into());
                    Vec::new()
                }
            },
        };
        let mut dropped = Vec::new();
        let results = Results::take_from(&mut root, settings.diagram.param, &mut dropped);
        let mut parts = Vec::new();
        if !bad.is_empty() {
            parts.push(format!("invalid {} (defaults used)", listed(&bad)));
        }
        if !dropped.is_empty() {
            parts.push(format!("dropped {}: compute them again", listed(&dropped)));
        }
        if !unknown.is_empty() {
            parts.push(format!("unknown {} (ignored)", listed(&unknown)));
        }
        Loaded {
            session: Session {
                settings,
                bifurcation_zoom,
                results,
            },
            message: (!parts.is_empty())
                .then(|| format!("session {what}: {}; the rest is as saved", parts.join("; "))),
        }
    }
}

impl Loaded {
    fn defaults(message: String) -> Loaded {
        Loaded {
            session: Session::default(),
            message: Some(message),
        }
    }
}

/// Names joined by commas, at most eight of them (a file may hold
/// thousands of unknown keys; the message stays one short line).
fn listed(names: &[String]) -> String {
    const SHOWN: usize = 8;
    let mut s = names
        .iter()
        .take(SHOWN)
        .cloned()
        .collect::<Vec<_>>()
        .join(", ");
    if names.len() > SHOWN {
        s.push_str(&format!(" and {} more", names.len() - SHOWN));
    }
    s
}

/// The text of a session file, read without ever blocking: the file is
/// opened non-blocking (a FIFO with no writer would otherwise wait
/// forever) and must then be a regular file of at most
/// [`MAX_FILE_BYTES`], holding UTF-8.
fn read_text(path: &Path) -> Result<String, String> {
    // The name first (it never blocks): a FIFO or a directory is refused
    // before anything opens it.
    let meta = std::fs::metadata(path).map_err(|e| e.to_string())?;
    if meta.is_dir() {
        return Err("it is a directory, not a session file".into());
    }
    if !meta.is_file() {
        return Err("it is not a regular file (a FIFO, socket or device)".into());
    }
    let mut opts = std::fs::OpenOptions::new();
    opts.read(true);
    // And non-blocking, in case the name now points at a FIFO.
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::fs::OpenOptionsExt as _;
        opts.custom_flags(libc::O_NONBLOCK);
    }
    let file = opts.open(path).map_err(|e| e.to_string())?;
    let meta = file.metadata().map_err(|e| e.to_string())?;
    if meta.is_dir() {
        return Err("it is a directory, not a session file".into());
    }
    if !meta.is_file() {
        return Err("it is not a regular file (a FIFO, socket or device)".into());
    }
    if meta.len() > MAX_FILE_BYTES {
        return Err(format!(
            "it holds {} bytes, more than a session's {MAX_FILE_BYTES}",
            meta.len()
        ));
    }
    let mut bytes = Vec::new();
    file.take(MAX_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| e.to_string())?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(format!(
            "it holds more than a session's {MAX_FILE_BYTES} bytes"
        ));
    }
    String::from_utf8(bytes).map_err(|e| {
        format!(
            "it is not UTF-8 text (invalid byte at offset {})",
            e.utf8_error().valid_up_to()
        )
    })
}

/// The settings from a JSON object, field by field: each field is tried on
/// its own over the defaults, so one bad field costs only itself.
fn settings_from(
    m: &Map<String, Value>,
    bad: &mut Vec<String>,
    unknown: &mut Vec<String>,
) -> Settings {
    let mut current = match serde_json::to_value(Settings::default()) {
        Ok(Value::Object(d)) => d,
        _ => return Settings::default(),
    };
    for (k, v) in m {
        if !current.contains_key(k) {
            unknown.push(format!("settings.{}", echo(k)));
            continue;
        }
        let old = current.insert(k.clone(), v.clone());
        if serde_json::from_value::<Settings>(Value::Object(current.clone())).is_err() {
            bad.push(format!("settings.{k}"));
            if let Some(old) = old {
                current.insert(k.clone(), old);
            }
        }
    }
    serde_json::from_value(Value::Object(current)).unwrap_or_default()
}

#[cfg(test)]
mod diagram_tests {
    use super::*;

    /// The diagram's varied parameter, its range and a zoom in it come
    /// back from the file; a zoom the model has no κ for is dropped.
    #[test]
    fn a_session_keeps_the_varied_parameter_its_range_and_zoom() {
        let mut s = Session::default();
        s.settings.diagram.param = ContParam::Kappa;
        s.settings.diagram.kappa = (2.0, 5.0);
        s.bifurcation_zoom = vec![Zoom {
            theta_nu: (2.5, 4.0),
            theta: (0.0, 1.0),
        }];
        let l = Session::from_json(&s.to_json(), "test");
        assert_eq!(l.session.settings.diagram, s.settings.diagram);
        assert_eq!(l.session.bifurcation_zoom, s.bifurcation_zoom);
        s.bifurcation_zoom[0].theta_nu = (2.0, 5000.0);
        let l = Session::from_json(&s.to_json(), "test");
        assert!(l.session.bifurcation_zoom.is_empty());
    }
}
