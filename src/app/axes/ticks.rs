//! The tick computation, pure arithmetic (no egui): ticks at round
//! values, at least five per axis, for linear, angle and log10 axes, with
//! the guards every caller relies on ([`labelable`]).

use std::f64::consts::PI;

pub use super::super::settings::AngleUnit;

/// The fewest labelled ticks an axis shows.
pub const MIN_TICKS: usize = 5;

/// One labelled tick: where it is (in the plot's coordinates) and what it
/// says.
#[derive(Clone, Debug, PartialEq)]
pub struct Tick {
    /// The position on the axis, in the data's own coordinates (radians
    /// for angles, log10 of the value on a log axis).
    pub value: f64,
    /// The text written at it.
    pub label: String,
}

/// The narrowest span an axis labels, relative to the size of its ends:
/// below it the ticks' round values are no longer distinct doubles.
pub const MIN_RELATIVE_SPAN: f64 = 1e-12;
/// The narrowest and widest spans an axis labels at all: outside them a
/// 1-2-5 step (10^e) under- or overflows.
pub const MIN_SPAN: f64 = 1e-200;
pub const MAX_SPAN: f64 = 1e200;

/// Whether [lo, hi] (either order) is a range the tick code can label:
/// finite ends, a span within [`MIN_SPAN`, `MAX_SPAN`] and at least
/// [`MIN_RELATIVE_SPAN`] of the ends' size. Every public entry checks it,
/// whoever calls (a saved zoom of width 5e-324 once froze the window in
/// the step search, which started from log10(0) = −∞).
pub fn labelable(lo: f64, hi: f64) -> bool {
    let (a, b) = (lo.min(hi), lo.max(hi));
    let span = b - a;
    a.is_finite()
        && b.is_finite()
        && span.is_finite()
        && (MIN_SPAN..=MAX_SPAN).contains(&span)
        && span >= MIN_RELATIVE_SPAN * a.abs().max(b.abs())
}

/// The 1-2-5 steps (m · 10^e, m ∈ {1, 2, 5}) in increasing order, as
/// (mantissa index, exponent).
pub(super) fn step_value(i: i32) -> f64 {
    let e = i.div_euclid(3);
    let m = [1.0, 2.0, 5.0][i.rem_euclid(3) as usize];
    m * 10f64.powi(e)
}

/// How many multiples of `step` lie in [lo, hi] (with a little slack, so
/// that an end on a tick counts).
pub(super) fn count(lo: f64, hi: f64, step: f64) -> usize {
    let eps = 1e-9;
    let first = (lo / step - eps).ceil();
    let last = (hi / step + eps).floor();
    if last < first {
        0
    } else {
        (last - first) as usize + 1
    }
}

/// The largest 1-2-5 step that puts at least `min_count` multiples of
/// itself in [lo, hi]; `None` for a range that is not [`labelable`].
pub fn nice_step(lo: f64, hi: f64, min_count: usize) -> Option<f64> {
    if !labelable(lo, hi) {
        return None;
    }
    let (lo, hi) = (lo.min(hi), lo.max(hi));
    let span = hi - lo;
    // More ticks than this are never legible; the bound also keeps the
    // searches below short.
    let n = min_count.clamp(2, 1000);
    let raw = span / (n - 1) as f64;
    // Index of the largest 1-2-5 value at or below `raw`.
    // Each search is bounded: the guard above keeps `raw` within about
    // 1e-203 … 1e200, a few steps from this start.
    let mut i = (raw.log10().floor() as i32) * 3;
    for _ in 0..8 {
        if step_value(i + 1) > raw {
            break;
        }
        i += 1;
    }
    for _ in 0..8 {
        if step_value(i) <= raw {
            break;
        }
        i -= 1;
    }
    // A step of span/(n−1) may lose one tick to the ends' rounding.
    for _ in 0..6 {
        if count(lo, hi, step_value(i)) >= n {
            break;
        }
        i -= 1;
    }
    for _ in 0..8 {
        if count(lo, hi, step_value(i + 1)) < n {
            break;
        }
        i += 1;
    }
    Some(step_value(i))
}

/// [lo, hi] widened to the multiples of the largest 1-2-5 step that then
/// holds at least `min_count` ticks, ends included: bounds for a plot
/// that frames its data itself, so that a short axis still gets five
/// labels at round values. Unchanged for a range that is not
/// [`labelable`].
pub fn nice_bounds(lo: f64, hi: f64, min_count: usize) -> (f64, f64) {
    if !labelable(lo, hi) {
        return (lo, hi);
    }
    let (a, b) = (lo.min(hi), lo.max(hi));
    let span = b - a;
    let n = min_count.clamp(2, 1000);
    let expanded = |s: f64| ((a / s + 1e-9).floor() * s, (b / s - 1e-9).ceil() * s);
    let ticks_in = |s: f64| {
        let (x, y) = expanded(s);
        ((y - x) / s).round() as usize + 1
    };
    let mut i = (span.log10().floor() as i32) * 3 + 2;
    for _ in 0..12 {
        if ticks_in(step_value(i)) >= n {
            break;
        }
        i -= 1;
    }
    expanded(step_value(i))
}

/// `v` written with as many decimals as `step` needs, in plain notation
/// unless the numbers are very large or very small; never "-0".
pub fn format_value(v: f64, step: f64) -> String {
    let step = step.abs();
    let v = if (v / step).abs() < 1e-6 { 0.0 } else { v };
    // The style is chosen by the step alone, so one axis never mixes them.
    if !(1e-4..1e5).contains(&step) {
        // Scientific, with the mantissa to the step's precision.
        if v == 0.0 {
            return "0".into();
        }
        let e = v.abs().log10().floor() as i32;
        let digits = (e - step.log10().floor() as i32).clamp(0, 6) as usize;
        let m = v / 10f64.powi(e);
        let m = format!("{m:.digits$}");
        return format!("{m}e{e}");
    }
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    let s = format!("{v:.decimals$}");
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
        s[1..].to_string()
    } else {
        s
    }
}

/// At least `min_count` ticks over [lo, hi] at the multiples of the
/// largest 1-2-5 step that gives them, each labelled with as many decimals
/// as the step needs. Empty for an empty or non-finite range.
pub fn ticks(lo: f64, hi: f64, min_count: usize) -> Vec<Tick> {
    let Some(step) = nice_step(lo, hi, min_count) else {
        return Vec::new();
    };
    multiples(lo, hi, step)
        .map(|v| Tick {
            value: v,
            label: format_value(v, step),
        })
        .collect()
}

/// The multiples of `step` in [lo, hi].
fn multiples(lo: f64, hi: f64, step: f64) -> impl Iterator<Item = f64> {
    let (lo, hi) = (lo.min(hi), lo.max(hi));
    let first = (lo / step - 1e-9).ceil() as i64;
    let n = count(lo, hi, step) as i64;
    (first..first + n).map(move |k| k as f64 * step)
}

/// The fractions of π offered as steps, coarsest first.
pub(super) const PI_DENOMINATORS: [u32; 9] = [1, 2, 3, 4, 6, 8, 12, 16, 24];

fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 { a } else { gcd(b, a % b) }
}

/// k·π/d written as a reduced fraction: "0", "π", "-π/2", "3π/4".
pub(super) fn pi_fraction(k: i64, d: u32) -> String {
    if k == 0 {
        return "0".into();
    }
    let g = gcd(k.unsigned_abs(), d as u64) as i64;
    let (num, den) = (k / g, d as i64 / g);
    let sign = if num < 0 { "-" } else { "" };
    let num = num.abs();
    let top = if num == 1 {
        "π".to_string()
    } else {
        format!("{num}π")
    };
    if den == 1 {
        format!("{sign}{top}")
    } else {
        format!("{sign}{top}/{den}")
    }
}

/// At least `min_count` ticks over the angles [lo, hi] (radians), at round
/// values of `unit`: 1-2-5 steps of radians or of degrees, or fractions
/// π/d (d up to 24; narrower ranges fall back to 1-2-5 multiples of π,
/// "0.38π"). Each tick's `value` is in radians.
pub fn angle_ticks(lo: f64, hi: f64, min_count: usize, unit: AngleUnit) -> Vec<Tick> {
    match unit {
        AngleUnit::Radians => ticks(lo, hi, min_count),
        AngleUnit::Degrees => ticks(lo.to_degrees(), hi.to_degrees(), min_count)
            .into_iter()
            .map(|t| Tick {
                value: t.value.to_radians(),
                label: format!("{}°", t.label),
            })
            .collect(),
        AngleUnit::PiFractions => {
            let (a, b) = (lo.min(hi), lo.max(hi));
            if !labelable(a, b) {
                return Vec::new();
            }
            let n = min_count.max(2);
            if let Some(&d) = PI_DENOMINATORS
                .iter()
                .find(|&&d| count(a, b, PI / d as f64) >= n)
            {
                let step = PI / d as f64;
                let first = (a / step - 1e-9).ceil() as i64;
                return (first..first + count(a, b, step) as i64)
                    .map(|k| Tick {
                        value: k as f64 * step,
                        label: pi_fraction(k, d),
                    })
                    .collect();
            }
            ticks(a / PI, b / PI, min_count)
                .into_iter()
                .map(|t| Tick {
                    value: t.value * PI,
                    label: if t.label == "0" {
                        t.label
                    } else {
                        format!("{}π", t.label)
                    },
                })
                .collect()
        }
    }
}

/// Ticks on a log axis whose coordinate is log10 of the value: the
/// decades, then 1-3 and then 1-2-5 mantissas when the decades alone are
/// fewer than `min_count`, labelled with the value ("1e-6", "3e-6");
/// less than about a decade wide, 1-2-5 steps of the value itself.
pub fn log10_ticks(lo: f64, hi: f64, min_count: usize) -> Vec<Tick> {
    let (a, b) = (lo.min(hi), lo.max(hi));
    if !labelable(a, b) || b - a > 600.0 {
        return Vec::new();
    }
    let n = min_count.max(2);
    let mantissas: [&[u32]; 3] = [&[1], &[1, 3], &[1, 2, 5]];
    let eps = 1e-9;
    // Over many decades, every k-th one: the largest 1-2-5 stride that
    // still gives n, as on a linear axis.
    let decades = (b.floor() - a.ceil()) as usize + 1;
    let stride = [1, 2, 5, 10, 20, 50, 100]
        .into_iter()
        .rev()
        .find(|k| decades / k >= n)
        .unwrap_or(1) as i32;
    let mut best = Vec::new();
    for ms in mantissas {
        best.clear();
        let stride = if ms.len() == 1 { stride } else { 1 };
        for e in (a.floor() as i32)..=(b.ceil() as i32) {
            if e.rem_euclid(stride) != 0 {
                continue;
            }
            for &m in ms {
                let v = e as f64 + (m as f64).log10();
                if v >= a - eps && v <= b + eps {
                    best.push(Tick {
                        value: v,
                        // Counts and other values from 1 to 50,000 as
                        // plain integers ("2", not "2e0").
                        label: if (0..=4).contains(&e) {
                            (u64::from(m) * 10u64.pow(e as u32)).to_string()
                        } else if m == 1 {
                            format!("1e{e}")
                        } else {
                            format!("{m}e{e}")
                        },
                    });
                }
            }
        }
        if best.len() >= n {
            return best;
        }
    }
    // Less than about a decade wide: round values, placed at their log10.
    let (va, vb) = (10f64.powf(a), 10f64.powf(b));
    let Some(step) = nice_step(va, vb, n) else {
        return Vec::new();
    };
    multiples(va, vb, step)
        .filter(|v| *v > 0.0)
        .map(|v| Tick {
            value: v.log10(),
            label: format_value(v, step),
        })
        .collect()
}
