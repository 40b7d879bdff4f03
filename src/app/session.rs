//! Sessions: what is on screen as a small JSON file ("Save session"), and
//! back (`oneblock gui --session FILE`). A session is the persisted
//! [`Settings`] (parameters, accuracy, layout and view, phase grid and its
//! zoom, the preset chosen, text size) plus the bifurcation diagram's zoom
//! stack, which lives in its view.
//!
//! Reading is forgiving field by field: a field the file gets wrong (a
//! wrong type, a value out of range) or one this version does not know is
//! named in one message, and every other field is kept as the file has it.

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

use super::bifurcation::Zoom;
use super::settings::Settings;

/// The format's version, written as `oneblock_session`.
pub const VERSION: u32 = 1;

/// A session: the settings and the bifurcation zoom stack (innermost last).
#[derive(Clone, Debug, PartialEq)]
pub struct Session {
    pub settings: Settings,
    pub bifurcation_zoom: Vec<Zoom>,
}

/// One zoom level as the file holds it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
struct ZoomFile {
    theta_nu: (f64, f64),
    theta: (f64, f64),
}

impl ZoomFile {
    fn is_valid(&self) -> bool {
        let ok = |(a, b): (f64, f64)| a.is_finite() && b.is_finite() && a < b;
        ok(self.theta_nu) && ok(self.theta)
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
    /// The session as pretty JSON.
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
        s.push('\n');
        s
    }

    /// Reads a session from `text`, `what` naming it in the message (the
    /// file name). Never fails: what cannot be read is left at its default.
    pub fn from_json(text: &str, what: &str) -> Loaded {
        let mut bad: Vec<String> = Vec::new();
        let mut unknown: Vec<String> = Vec::new();
        let root = match serde_json::from_str::<Value>(text) {
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
            if !["oneblock_session", "settings", "bifurcation_zoom"].contains(&k.as_str()) {
                unknown.push(k.clone());
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
                Ok(z) if z.iter().all(ZoomFile::is_valid) => z
                    .into_iter()
                    .map(|z| Zoom {
                        theta_nu: z.theta_nu,
                        theta: z.theta,
                    })
                    .collect(),
                _ => {
                    bad.push("bifurcation_zoom".into());
                    Vec::new()
                }
            },
        };
        let mut parts = Vec::new();
        if !bad.is_empty() {
            parts.push(format!("invalid {} (defaults used)", bad.join(", ")));
        }
        if !unknown.is_empty() {
            parts.push(format!("unknown {} (ignored)", unknown.join(", ")));
        }
        Loaded {
            session: Session {
                settings,
                bifurcation_zoom,
            },
            message: (!parts.is_empty())
                .then(|| format!("session {what}: {}; the rest is as saved", parts.join("; "))),
        }
    }
}

impl Loaded {
    fn defaults(message: String) -> Loaded {
        Loaded {
            session: Session {
                settings: Settings::default(),
                bifurcation_zoom: Vec::new(),
            },
            message: Some(message),
        }
    }
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
            unknown.push(format!("settings.{k}"));
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
