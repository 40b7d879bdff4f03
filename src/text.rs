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

/// A value with its error, to the digits the error allows (two
/// significant digits of the error, at most 6 decimals): `0.069 +- 0.020`.
/// An infinite or unknown error prints the value to 2 decimals and says
/// so.
pub fn with_error(v: f64, e: f64) -> String {
    if !(e.is_finite() && e > 0.0) {
        return format!("{v:.2} (error unknown)");
    }
    let decimals = (1 - e.log10().floor() as i32).clamp(0, 6) as usize;
    format!("{v:.decimals$} +- {e:.decimals$}")
}

/// λ as the window and the figures show it: a solved cycle's exact λ
/// (`stderr` `None`) to four decimals, `λ = -0.7300`; a mean to the digits
/// its standard error allows, `λ = 0.365 ± 0.012`; a mean too short for an
/// error to two decimals with "≈".
pub fn lyapunov(l: f64, stderr: Option<f64>, exact: bool) -> String {
    match (stderr, exact) {
        (Some(e), _) => format!("λ = {}", with_error(l, e).replace("+-", "±")),
        (None, true) => format!("λ = {l:.4}"),
        (None, false) => format!("λ ≈ {l:.2}"),
    }
}

#[cfg(test)]
mod with_error_tests {
    use super::{lyapunov, with_error};

    #[test]
    fn lambda_carries_its_error_or_says_it_is_exact() {
        assert_eq!(lyapunov(-0.729_993, None, true), "λ = -0.7300");
        assert_eq!(lyapunov(0.3656, Some(0.0121), false), "λ = 0.366 ± 0.012");
        assert_eq!(lyapunov(0.3655, None, false), "λ ≈ 0.37");
    }

    #[test]
    fn digits_follow_the_error() {
        assert_eq!(with_error(0.068_68, 0.0201), "0.069 +- 0.020");
        assert_eq!(with_error(0.350_93, 0.000_23), "0.35093 +- 0.00023");
        assert_eq!(with_error(12.3456, 1.5), "12.3 +- 1.5");
    }
}
