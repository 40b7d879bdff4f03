//! User-given text in a message: shortened and with its control characters
//! escaped, so that a message stays one line and never sends a terminal an
//! escape sequence. Used by the command line and the window alike (the
//! browser build has no command line).

/// A number as a message shows it: as written when short, else in
/// exponent form (5e-324, not its 330 digits).
pub fn short(v: f64) -> String {
    let plain = format!("{v}");
    if plain.len() <= 12 {
        plain
    } else {
        format!("{v:e}")
    }
}

/// A user's string as a message echoes it: at most 40 characters, and
/// control characters escaped (`\n`, `\u{1b}`), so that a message stays
/// one line and never sends a terminal an escape sequence.
pub fn echo(s: &str) -> String {
    let mut out = escape_controls(&s.chars().take(40).collect::<String>());
    if s.chars().nth(40).is_some() {
        out.push('…');
    }
    out
}

/// `s` with every control character escaped as Rust writes it (`\n`,
/// `\t`, `\u{1b}`): what a message prints of a value it did not choose.
pub fn escape_controls(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        if c.is_control() {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    out
}
