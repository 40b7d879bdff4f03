//! Parsing and echoing the command line's values: counts that accept `1e3`,
//! durations with an upper bound, numbers echoed short, and the presets.

use super::CliError;
use clap::ValueEnum;
use clap::builder::PossibleValue;

use crate::integrate::Method;
use crate::model::{PRESETS, ParamError, Params, Preset, preset_keys};
use crate::sim::continuation::{ContParam, CurveKind};
use crate::sim::interpolant::MapChoice;

pub use crate::text::{echo, escape_controls, short};

/// The largest count any flag accepts before its own bound is checked;
/// above it a count is refused by the parser (a typo of a dozen digits).
pub const COUNT_PARSE_MAX: u64 = 1_000_000_000_000_000;

/// Parses a count flag: a whole number ≥ 0, written `1000`, `1e3` or
/// `1.5e3`. Each command checks its own upper bound afterwards.
pub fn parse_count(s: &str) -> Result<usize, String> {
    let t = s.trim();
    let v: f64 = if let Ok(n) = t.parse::<u64>() {
        n as f64
    } else {
        t.parse::<f64>()
            .map_err(|_| "must be a whole number >= 0, such as 1000 or 1e3".to_string())?
    };
    if v.is_nan() || v < 0.0 {
        return Err("must be a whole number >= 0, such as 1000 or 1e3".into());
    }
    if v.fract() != 0.0 {
        return Err(format!(
            "{} is not a whole number: counts are whole numbers >= 0",
            short(v)
        ));
    }
    if v > COUNT_PARSE_MAX as f64 {
        return Err(format!(
            "{} is too large: no count may exceed {COUNT_PARSE_MAX:e}",
            short(v)
        ));
    }
    usize::try_from(v as u64).map_err(|_| format!("{} does not fit this machine", short(v)))
}

/// Parses a number flag, refusing inf and NaN with the flag's own error.
pub fn parse_number(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| "must be a number, such as 0.5, -1 or 1e-3".to_string())?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("{v} is not a finite number"))
    }
}

/// The longest duration any flag accepts: about 115 days.
pub const MAX_SECONDS: f64 = 1e7;

/// Checks a duration in seconds against (0, [`MAX_SECONDS`]].
pub fn seconds(flag: &str, v: f64) -> Result<f64, CliError> {
    if v.is_finite() && v > 0.0 && v <= MAX_SECONDS {
        Ok(v)
    } else {
        Err(CliError::Usage(format!(
            "--{flag} = {} is out of range: must lie in (0, {MAX_SECONDS:e}] seconds",
            short(v)
        )))
    }
}

/// A parameter error as the command line shows it: the flag, the value
/// (short), the valid range.
pub fn param_error(e: ParamError) -> CliError {
    CliError::Usage(format!(
        "--{} = {} is out of range: {}",
        e.name,
        short(e.value),
        e.range
    ))
}

/// A solver-setting error as the command line shows it.
pub fn settings_error(e: crate::integrate::SettingsError) -> CliError {
    CliError::Usage(format!(
        "--{} = {} is out of range: {}",
        e.name,
        short(e.value),
        e.range
    ))
}

/// The parameters of `--preset NAME` (clap has checked the name).
pub fn preset_params(preset: Option<Preset>) -> Option<Params> {
    preset.map(|p| p.params)
}

// The flags that take one of a fixed set of values are parsed by clap from
// these lists, so `--help` shows them and a wrong value is refused with the
// list (cli::usage_line folds it into one line). The core types stay free of
// the command line's crate: the impls are here.

impl ValueEnum for Preset {
    fn value_variants<'a>() -> &'a [Self] {
        &PRESETS
    }
    fn to_possible_value(&self) -> Option<PossibleValue> {
        Some(PossibleValue::new(self.key).help(self.label))
    }
}

impl ValueEnum for Method {
    fn value_variants<'a>() -> &'a [Self] {
        &Method::ALL
    }
    fn to_possible_value(&self) -> Option<PossibleValue> {
        let v = PossibleValue::new(self.name());
        Some(match self {
            // The names other programs give Dormand–Prince 5(4).
            Method::Dp54 => v.aliases(["dopri5", "rk45"]),
            _ => v,
        })
    }
}

impl ValueEnum for MapChoice {
    fn value_variants<'a>() -> &'a [Self] {
        &[MapChoice::Direct, MapChoice::Interpolant, MapChoice::Auto]
    }
    fn to_possible_value(&self) -> Option<PossibleValue> {
        Some(PossibleValue::new(match self {
            MapChoice::Direct => "direct",
            MapChoice::Interpolant => "interpolant",
            MapChoice::Auto => "auto",
        }))
    }
}

impl ValueEnum for ContParam {
    fn value_variants<'a>() -> &'a [Self] {
        &ContParam::ALL
    }
    fn to_possible_value(&self) -> Option<PossibleValue> {
        Some(PossibleValue::new(self.name()))
    }
}

impl ValueEnum for CurveKind {
    fn value_variants<'a>() -> &'a [Self] {
        &[CurveKind::PeriodDoubling, CurveKind::Fold]
    }
    fn to_possible_value(&self) -> Option<PossibleValue> {
        Some(PossibleValue::new(self.name()))
    }
}

/// A parameter from its flag, else from the preset; an error names the
/// flag when neither gives it.
pub fn given_or_preset(
    flag: &str,
    given: Option<f64>,
    preset: Option<f64>,
) -> Result<f64, CliError> {
    given.or(preset).ok_or_else(|| {
        CliError::Usage(format!(
            "--{flag} is required (or give --preset, one of {})",
            preset_keys()
        ))
    })
}

/// Checks a count against [min, max], naming the flag and the range.
pub fn count_between(name: &str, v: usize, min: usize, max: usize) -> Result<usize, CliError> {
    if (min..=max).contains(&v) {
        Ok(v)
    } else {
        Err(CliError::Usage(format!(
            "--{name} = {v} is out of range: must lie in [{min}, {}]",
            short_count(max)
        )))
    }
}

/// A bound as the messages and docs write it: 1000000 as 1e6.
pub fn short_count(n: usize) -> String {
    if n >= 100_000 && n == 10usize.pow(n.ilog10()) {
        format!("1e{}", n.ilog10())
    } else {
        n.to_string()
    }
}

pub use crate::model::MAX_ABS_THETA;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_accept_exponents_and_refuse_the_rest_by_reason() {
        assert_eq!(parse_count("1000"), Ok(1000));
        assert_eq!(parse_count("1e3"), Ok(1000));
        assert_eq!(parse_count("1.5e3"), Ok(1500));
        assert_eq!(parse_count("0"), Ok(0));
        assert!(parse_count("-1").unwrap_err().contains(">= 0"));
        assert!(parse_count("1.5").unwrap_err().contains("whole"));
        assert!(parse_count("1e300").unwrap_err().contains("1e300"));
        assert!(parse_count("inf").is_err());
        assert!(parse_count("18446744073709551615").is_err());
    }

    #[test]
    fn numbers_are_echoed_short() {
        assert_eq!(short(1e308), "1e308");
        assert_eq!(short(-1e-300), "-1e-300");
        assert_eq!(short(0.5), "0.5");
        assert_eq!(short(18.95), "18.95");
        assert_eq!(short_count(1_000_000), "1e6");
        assert_eq!(short_count(10_000), "10000");
        assert_eq!(short_count(4_000_000), "4000000");
    }

    #[test]
    fn echoes_are_short_and_escape_control_characters() {
        assert_eq!(echo("a\nb\u{1b}[31m"), "a\\nb\\u{1b}[31m");
        let long = "x".repeat(5000);
        let e = echo(&long);
        assert_eq!(e.chars().count(), 41);
        assert!(e.ends_with('…'));
        assert_eq!(echo(&"y".repeat(40)), "y".repeat(40));
    }
}
