//! The state a link carries: `?preset=fig3b&view=bifurcation&kappa=10`,
//! and the parameter the bifurcation diagram varies with its range
//! (`vary=kappa&vary_from=2&vary_to=5`; θν, the default, is not written).
//! The browser build opens on the page's query and its "Copy link" writes
//! the current state into one. Values are checked as a session's are
//! (each parameter by `Params::validate`, θν within [-π, π]); a bad one is
//! named in a message and the window opens on a valid value instead.
//! Plain text in, settings out: no browser needed, so tested natively.

use std::f64::consts::{FRAC_PI_2, PI};
use std::fmt::Write as _;

use super::settings::{DiagramAxis, Layout, Settings, ViewKind};
use crate::model::{Params, preset, preset_keys};
use crate::sim::continuation::ContParam;
use crate::text::echo;

/// The keys a link may carry, in the order a link writes them.
pub const KEYS: [&str; 10] = [
    "preset",
    "view",
    "kappa",
    "gamma",
    "nu",
    "theta_nu",
    "omega",
    "vary",
    "vary_from",
    "vary_to",
];

/// The most characters of a query read (a link is a few dozen).
const MAX_QUERY: usize = 2048;

/// Applies `query` (the URL's part after `?`, with or without the `?`) to
/// `settings`: the preset first, then the view, then each parameter over
/// it. Returns the message naming what was refused, if anything was.
pub fn apply_query(query: &str, settings: &mut Settings) -> Option<String> {
    let query = query.strip_prefix('?').unwrap_or(query);
    let mut bad: Vec<String> = Vec::new();
    if query.len() > MAX_QUERY {
        return Some(format!(
            "The link's query is over {MAX_QUERY} characters and was not read: \
             the explorer opens on its saved state."
        ));
    }
    let pairs: Vec<(String, String)> = query
        .split('&')
        .filter(|p| !p.is_empty())
        .map(|p| {
            let (k, v) = p.split_once('=').unwrap_or((p, ""));
            (decode(k), decode(v))
        })
        .collect();
    let get = |key: &str| pairs.iter().rev().find(|(k, _)| k == key).map(|(_, v)| v);
    // Named once, at most SHOWN of them: a link of 600 unknown keys once
    // filled a third of the window with this message.
    const SHOWN: usize = 5;
    let unknown: Vec<String> = pairs
        .iter()
        .filter(|(k, _)| !KEYS.contains(&k.as_str()))
        .map(|(k, _)| format!("'{}'", echo(k)))
        .collect();
    if !unknown.is_empty() {
        let more = unknown.len().saturating_sub(SHOWN);
        bad.push(format!(
            "unknown key{} {}{} (known: {})",
            if unknown.len() == 1 { "" } else { "s" },
            unknown[..unknown.len().min(SHOWN)].join(", "),
            if more > 0 {
                format!(" and {more} more")
            } else {
                String::new()
            },
            KEYS.join(", ")
        ));
    }
    apply_preset_and_view(get("preset"), get("view"), settings, &mut bad);
    let mut params = settings.params;
    let mut moved = false;
    for (key, field) in PARAM_FIELDS {
        let Some(text) = get(key) else { continue };
        match parse_param(key, text, &params, field) {
            Ok(p) => {
                params = p;
                moved = true;
            }
            Err(e) => bad.push(e),
        }
    }
    apply_vary(
        [get("vary"), get("vary_from"), get("vary_to")],
        settings,
        &mut bad,
    );
    if moved && params != settings.params {
        settings.params = params;
        // A parameter set by hand is no longer the preset's.
        if let Some(key) = &settings.preset
            && preset(key).is_none_or(|p| p.params != params)
        {
            settings.preset = None;
        }
        if !(0.0..=FRAC_PI_2).contains(&params.theta_nu) {
            settings.full_circle = true;
        }
    }
    (!bad.is_empty()).then(|| {
        format!(
            "The link held values that cannot be used: {}. The explorer opens on valid values instead.",
            bad.join("; ")
        )
    })
}

/// The link's preset (applied first) and view, or why not.
fn apply_preset_and_view(
    preset_key: Option<&String>,
    view_key: Option<&String>,
    settings: &mut Settings,
    bad: &mut Vec<String>,
) {
    if let Some(key) = preset_key {
        match preset(key) {
            Some(p) => settings.apply_preset(&p.params, p.key),
            None => bad.push(format!(
                "preset '{}' is not one of {}",
                echo(key),
                preset_keys()
            )),
        }
    }
    if let Some(v) = view_key {
        match ViewKind::from_key(v) {
            Some(view) => {
                settings.layout = Layout::Tabs;
                settings.tab = view;
            }
            None => bad.push(format!(
                "view '{}' is not one of {}",
                echo(v),
                ViewKind::ALL.map(ViewKind::key).join(", ")
            )),
        }
    }
}

/// The diagram's varied parameter (`vary`, a name of `oneblock
/// bifurcation --param`) and its range (`vary_from`, `vary_to`: both or
/// neither, a range the model has for it; θν's is the slider's, so it
/// takes none), or why not.
fn apply_vary(
    [vary, from, to]: [Option<&String>; 3],
    settings: &mut Settings,
    bad: &mut Vec<String>,
) {
    let param = match vary {
        None => settings.diagram.param,
        Some(name) => match ContParam::parse(name.trim()) {
            Some(p) => p,
            None => {
                bad.push(format!(
                    "vary '{}' is not one of {}",
                    echo(name),
                    ContParam::ALL.map(ContParam::name).join(", ")
                ));
                return;
            }
        },
    };
    let range = match (from, to) {
        (None, None) => None,
        (Some(a), Some(b)) => {
            let (a, b) = (a.trim().parse::<f64>(), b.trim().parse::<f64>());
            match (a, b) {
                (Ok(a), Ok(b)) if DiagramAxis::is_valid_range(param, (a, b)) => Some((a, b)),
                _ => {
                    bad.push(format!(
                        "vary_from, vary_to are not an increasing range of {} the model has",
                        param.name()
                    ));
                    return;
                }
            }
        }
        _ => {
            bad.push("vary_from and vary_to go together".into());
            return;
        }
    };
    if param == ContParam::ThetaNu && range.is_some() {
        bad.push("vary_from, vary_to: theta-nu's range is the slider's (give none)".into());
        return;
    }
    settings.diagram.param = param;
    if let Some(r) = range {
        settings.diagram.set_range(param, r);
    }
}

/// Each parameter a link may set, and where it goes.
type Field = fn(&mut Params, f64);
const PARAM_FIELDS: [(&str, Field); 5] = [
    ("kappa", |p, v| p.kappa = v),
    ("gamma", |p, v| p.gamma = v),
    ("nu", |p, v| p.nu = v),
    ("theta_nu", |p, v| p.theta_nu = v),
    ("omega", |p, v| p.omega = v),
];

/// `params` with `key` set from `text`, if that is a number the model
/// accepts there; else why not, in the words a session's check uses.
fn parse_param(key: &str, text: &str, params: &Params, field: Field) -> Result<Params, String> {
    let v: f64 = text
        .trim()
        .parse()
        .ok()
        .filter(|v: &f64| v.is_finite())
        .ok_or_else(|| format!("{key} = '{}' is not a finite number", echo(text)))?;
    let mut p = *params;
    field(&mut p, v);
    p.validate().map_err(|e| e.to_string())?;
    if key == "theta_nu" && !(-PI..=PI).contains(&v) {
        return Err(format!(
            "theta_nu = {v} is out of range: must lie in [-pi, pi]"
        ));
    }
    Ok(p)
}

/// The query that opens the current state: the view shown (when one view
/// is shown on its own), the preset (if the parameters are still its own)
/// and every parameter, in shortest round-trip form.
pub fn query_of(settings: &Settings) -> String {
    let mut q = String::new();
    let mut add = |k: &str, v: &str| {
        if !q.is_empty() {
            q.push('&');
        }
        let _ = write!(q, "{k}={}", encode(v));
    };
    let p = settings.params;
    if let Some(key) = &settings.preset
        && preset(key).is_some_and(|pr| pr.params == p)
    {
        add("preset", key);
    }
    if settings.layout == Layout::Tabs {
        add("view", settings.tab.key());
    }
    for (k, v) in [
        ("kappa", p.kappa),
        ("gamma", p.gamma),
        ("nu", p.nu),
        ("theta_nu", p.theta_nu),
        ("omega", p.omega),
    ] {
        add(k, &format!("{v}"));
    }
    let d = settings.diagram;
    if let Some((a, b)) = d.range(d.param) {
        add("vary", d.param.name());
        add("vary_from", &format!("{a}"));
        add("vary_to", &format!("{b}"));
    }
    q
}

/// Percent-decoding of a query's key or value (`+` is a space); bytes that
/// do not make UTF-8 come out as U+FFFD.
fn decode(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'+' => out.push(b' '),
            b'%' if i + 2 < b.len()
                && b[i + 1].is_ascii_hexdigit()
                && b[i + 2].is_ascii_hexdigit() =>
            {
                let hex = |c: u8| (c as char).to_digit(16).unwrap_or(0) as u8;
                out.push(hex(b[i + 1]) * 16 + hex(b[i + 2]));
                i += 3;
                continue;
            }
            c => out.push(c),
        }
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// Percent-encoding of a value for a query: what is not a letter, a digit
/// or one of `-._~` is escaped.
fn encode(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for b in s.bytes() {
        if b.is_ascii_alphanumeric() || b"-._~".contains(&b) {
            out.push(b as char);
        } else {
            let _ = write!(out, "%{b:02X}");
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_link_opens_its_preset_view_and_parameters() {
        let mut s = Settings::default();
        let msg = apply_query("?preset=fig3a&view=bifurcation", &mut s);
        assert_eq!(msg, None);
        let fig3a = preset("fig3a").unwrap();
        assert_eq!(s.params, fig3a.params);
        assert_eq!((s.layout, s.tab), (Layout::Tabs, ViewKind::Bifurcation));
        let msg = apply_query("kappa=10&gamma=6.5&nu=1e-3&theta_nu=0.87&omega=50", &mut s);
        assert_eq!(msg, None);
        assert_eq!(
            s.params,
            Params {
                kappa: 10.0,
                gamma: 6.5,
                nu: 1e-3,
                theta_nu: 0.87,
                omega: 50.0
            }
        );
        assert_eq!(s.preset, None, "hand-set parameters are no preset's");
    }

    #[test]
    fn many_unknown_keys_make_one_short_message() {
        let mut s = Settings::default();
        // 500 keys, as many as the longest query read (2048 characters)
        // holds.
        let query: Vec<String> = (0..500).map(|i| format!("{i:x}")).collect();
        let msg = apply_query(&query.join("&"), &mut s).expect("a message");
        assert!(msg.contains("'0'") && msg.contains("and 495 more"), "{msg}");
        assert!(!msg.contains("'5'"), "{msg}");
        assert!(msg.len() < 300, "{} characters: {msg}", msg.len());
        let one = apply_query("wobble=1", &mut s).expect("a message");
        assert!(one.contains("unknown key 'wobble'"), "{one}");
    }

    #[test]
    fn bad_values_are_named_and_valid_ones_kept() {
        let mut s = Settings::default();
        let before = s.params;
        let msg = apply_query(
            "kappa=-3&gamma=abc&nu=1e-3&theta_nu=9&zoom=2&view=nope",
            &mut s,
        )
        .expect("a message");
        for needle in [
            "kappa = -3",
            "gamma = 'abc'",
            "theta_nu = 9",
            "'zoom'",
            "view 'nope'",
        ] {
            assert!(msg.contains(needle), "{needle} missing from: {msg}");
        }
        assert_eq!(s.params.kappa, before.kappa);
        assert_eq!(s.params.gamma, before.gamma);
        assert_eq!(s.params.nu, 1e-3);
        assert!(s.params.validate().is_ok());
        assert!(!msg.contains('\n'));
    }

    #[test]
    fn a_copied_link_reopens_the_same_state() {
        let mut s = Settings::default();
        apply_query("preset=fig3b&view=phase", &mut s);
        s.params.theta_nu = 1.234_567_890_123_456_7;
        let q = query_of(&s);
        let mut t = Settings::default();
        assert_eq!(apply_query(&q, &mut t), None, "{q}");
        assert_eq!(t.params, s.params, "bit for bit through the text");
        assert_eq!((t.layout, t.tab), (Layout::Tabs, ViewKind::Phase));
        assert!(!q.contains("preset="), "θν moved off the preset: {q}");
    }

    /// The diagram's varied parameter and its range go into a link and
    /// come back bit for bit; θν, the default, writes no key; bad values
    /// are named and change nothing.
    #[test]
    fn the_varied_parameter_and_its_range_round_trip() {
        let mut s = Settings::default();
        assert!(!query_of(&s).contains("vary"), "{}", query_of(&s));
        s.diagram.param = ContParam::Kappa;
        s.diagram.kappa = (2.0, 5.000_000_000_000_001);
        let q = query_of(&s);
        assert!(
            q.contains("vary=kappa&vary_from=2&vary_to=5.000000000000001"),
            "{q}"
        );
        let mut t = Settings::default();
        assert_eq!(apply_query(&q, &mut t), None, "{q}");
        assert_eq!(t.diagram, s.diagram);
        assert_eq!(apply_query("vary=omega", &mut t), None);
        assert_eq!(t.diagram.param, ContParam::Omega);
        assert_eq!(t.diagram.kappa, s.diagram.kappa);
        let before = t.diagram;
        for (query, needle) in [
            ("vary=mass", "vary 'mass'"),
            ("vary=kappa&vary_from=0&vary_to=5", "vary_from, vary_to"),
            ("vary=kappa&vary_from=5&vary_to=2", "vary_from, vary_to"),
            ("vary=gamma&vary_from=1", "go together"),
            ("vary=theta-nu&vary_from=0&vary_to=1", "slider's"),
        ] {
            let msg = apply_query(query, &mut t).expect("a message");
            assert!(msg.contains(needle), "{query}: {msg}");
            assert_eq!(t.diagram, before, "{query}");
        }
    }

    #[test]
    fn percent_escapes_are_decoded_and_odd_bytes_survive() {
        assert_eq!(decode("a%20b+c"), "a b c");
        assert_eq!(decode("%zz%4"), "%zz%4");
        assert_eq!(decode("%E2%9C%93"), "✓");
        assert_eq!(encode("1e-3 π"), "1e-3%20%CF%80");
        let mut s = Settings::default();
        assert_eq!(apply_query("kappa=1%2E5e1", &mut s), None);
        assert_eq!(s.params.kappa, 15.0);
    }
}
