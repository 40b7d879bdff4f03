//! Where a CSV came from: every CSV the program writes (each command's and
//! the window's) begins with `#` lines naming the program and its version,
//! the command line or the window's view, the model's parameters and the
//! solver's accuracy, and every other setting that shaped it. A reader
//! skips them as comments (`pandas.read_csv(f, comment='#')`, the csv
//! crate's `ReaderBuilder::comment(Some(b'#'))`); the header row and the
//! rows follow unchanged.

use std::fmt::Write as _;
use std::sync::OnceLock;

use crate::integrate::SolverSettings;
use crate::model::{Params, Regime};
use crate::sim::continuation::ContParam;

/// The program and its version, as the first `#` line says them.
pub const PROGRAM: &str = concat!("oneblock ", env!("CARGO_PKG_VERSION"));

/// The command line this process was started with and every flag's value
/// as the command read it (given or default), once parsed.
static INVOCATION: OnceLock<Invocation> = OnceLock::new();

/// What the command line said, as the header's lines.
#[derive(Clone, Debug)]
pub struct Invocation {
    /// The command line, quoted so that a shell reads it back.
    pub line: String,
    /// Every flag of the subcommand with its value, `--name value`.
    pub flags: Vec<String>,
}

/// Records this process's command line (once; a second call is ignored).
pub fn record(invocation: Invocation) {
    INVOCATION.set(invocation).ok();
}

/// The recorded command line, if any.
pub fn invocation() -> Option<&'static Invocation> {
    INVOCATION.get()
}

/// `s` quoted for a POSIX shell when it holds anything but plain word
/// characters; control characters escaped, so that it stays on its line.
pub fn shell_quote(s: &str) -> String {
    let plain = !s.is_empty()
        && s.chars()
            .all(|c| c.is_alphanumeric() || "-_./=:,+@%^".contains(c));
    let s = crate::text::escape_controls(s);
    if plain {
        s
    } else {
        format!("'{}'", s.replace('\'', "'\\''"))
    }
}

pub use crate::text::short;

/// The model's parameters and the solver's accuracy on one line, θν
/// left out when it is what varies: `kappa = 10, gamma = 0.8, nu = 0.3,
/// theta-nu = 1.25, omega = 1 (stick-slip); dp54 tol 1e-8`.
pub fn model_line(params: &Params, settings: &SolverSettings, theta_nu: bool) -> String {
    let accuracy = if settings.method.is_adaptive() {
        format!("tol {:e}", settings.rtol)
    } else {
        format!("step {}", settings.step)
    };
    let theta_nu = if theta_nu {
        format!("theta-nu = {}, ", short(params.theta_nu))
    } else {
        String::new()
    };
    format!(
        "kappa = {}, gamma = {}, nu = {}, {theta_nu}omega = {} ({}); {} {}",
        short(params.kappa),
        short(params.gamma),
        short(params.nu),
        short(params.omega),
        Regime::of(params.kappa, params.gamma).name(),
        settings.method,
        accuracy
    )
}

/// [`model_line`] of a diagram over `varied`: that parameter left out and
/// named as varied (`kappa = 18.95, gamma = 6.5, nu = 0.001, omega = 50
/// (stick-slip); …` over θν, `gamma = 6.5, nu = 0.001, theta-nu = 1.25,
/// omega = 50 (kappa varied); …` over κ; the regime, which κ and γ
/// decide, is named when neither varies).
pub fn model_line_varying(params: &Params, settings: &SolverSettings, varied: ContParam) -> String {
    if varied == ContParam::ThetaNu {
        return model_line(params, settings, false);
    }
    let line = model_line(params, settings, true);
    // The line's own words for each value, the varied one's left out.
    let (values, solver) = line.split_once(" (").unwrap_or((&line, ""));
    let kept: Vec<&str> = values
        .split(", ")
        .filter(|part| !part.starts_with(&format!("{} = ", varied.name())))
        .collect();
    let solver = solver.split_once("); ").map_or("", |(_, s)| s);
    let regime = match varied {
        ContParam::Kappa | ContParam::Gamma => String::new(),
        _ => format!("{}; ", Regime::of(params.kappa, params.gamma).name()),
    };
    format!(
        "{} ({regime}{} varied); {solver}",
        kept.join(", "),
        varied.name()
    )
}

/// The `#` lines a CSV begins with: the program, then `source` (the
/// command line recorded by [`record`] if `source` is `None`, else the
/// window's view), the model (`model`, see [`model_line`]), and
/// `settings` (the command's flags, every one, when `None`).
pub fn header(source: Option<&str>, model: &str, settings: Option<&[String]>) -> String {
    let mut h = format!("# {PROGRAM}\n");
    let inv = invocation();
    match (source, inv) {
        (Some(s), _) => writeln!(h, "# {}", one_line(s)).ok(),
        (None, Some(i)) => writeln!(h, "# command: {}", one_line(&i.line)).ok(),
        (None, None) => None,
    };
    writeln!(h, "# model: {}", one_line(model)).ok();
    let flags = settings.or(inv.map(|i| i.flags.as_slice()));
    if let Some(f) = flags.filter(|f| !f.is_empty()) {
        writeln!(h, "# settings: {}", one_line(&f.join(" "))).ok();
    }
    h
}

/// `csv` with [`header`]'s lines in front.
pub fn with_header(header: &str, csv: &str) -> String {
    let mut s = String::with_capacity(header.len() + csv.len());
    s.push_str(header);
    s.push_str(csv);
    s
}

/// `s` kept to one line: newlines and other control characters escaped.
fn one_line(s: &str) -> String {
    crate::text::escape_controls(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A diagram's model line leaves the varied parameter's value out and
    /// names it; the regime only where κ and γ are both fixed.
    #[test]
    fn the_varied_parameter_is_named_not_valued() {
        let p = crate::model::preset("fig3b").expect("fig3b").params;
        let s = SolverSettings::default();
        assert_eq!(
            model_line_varying(&p, &s, ContParam::ThetaNu),
            model_line(&p, &s, false)
        );
        let k = model_line_varying(&p, &s, ContParam::Kappa);
        assert!(
            k.starts_with("gamma = 6.5, nu = 0.001, theta-nu = 1, omega = 50 (kappa varied); "),
            "{k}"
        );
        let o = model_line_varying(&p, &s, ContParam::Omega);
        assert!(
            o.contains("theta-nu = 1 (pure stick-slip; omega varied); "),
            "{o}"
        );
        assert!(!o.contains("omega ="), "{o}");
    }

    #[test]
    fn a_header_is_comment_lines_and_the_csv_reads_past_them() {
        let p = crate::model::preset("fig3b").expect("fig3b").params;
        let model = model_line(&p, &SolverSettings::default(), true);
        let h = header(Some("view: bifurcation"), &model, Some(&["--a 1".into()]));
        let text = with_header(&h, "x,y\n1,2\n");
        assert!(text.lines().take(4).all(|l| l.starts_with("# ")), "{text}");
        assert!(text.starts_with(&format!("# {PROGRAM}\n")));
        assert!(
            h.contains("kappa = 18.95,") && h.contains("theta-nu = 1,"),
            "{h}"
        );
        let mut r = csv::ReaderBuilder::new()
            .comment(Some(b'#'))
            .from_reader(text.as_bytes());
        let head: Vec<String> = r
            .headers()
            .expect("a header row")
            .iter()
            .map(str::to_string)
            .collect();
        assert_eq!(head, ["x", "y"]);
        let rows: Vec<csv::StringRecord> = r.records().map(|x| x.expect("a row")).collect();
        assert_eq!(rows.len(), 1);
        assert_eq!(&rows[0][1], "2");
    }

    #[test]
    fn a_value_with_a_newline_stays_on_its_comment_line() {
        let h = header(Some("view: x\ny"), "m", None);
        assert!(h.lines().all(|l| l.starts_with("# ")), "{h}");
        assert_eq!(shell_quote("a b"), "'a b'");
        assert_eq!(shell_quote("it's"), "'it'\\''s'");
        assert_eq!(shell_quote("--kappa=10"), "--kappa=10");
    }
}
