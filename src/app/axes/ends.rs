//! Labels near an axis's ends. Ticks at the multiples of a round step
//! may leave the first or last part of an axis unlabelled (a log axis over
//! 5 … 40 labelled 10 … 40, its left third bare); a reader of a figure
//! wants the range's ends read off. [`reach_ends`] adds, where the outer
//! tick is farther than [`END_REACH`] of the axis from its end, the
//! roundest value within that reach, and drops the regular tick its label
//! would run into.

use std::f64::consts::PI;

use super::Scale;
use super::ticks::{
    AngleUnit, PI_DENOMINATORS, Tick, count, format_value, labelable, pi_fraction, step_value,
};

/// The share of an axis's length within which its lowest and highest
/// labels lie.
pub const END_REACH: f64 = 0.15;

/// The roundest value in [a, b] (a < b): a multiple of the largest 1-2-5
/// step that has one there, the one nearest `toward`; with that step.
fn roundest(a: f64, b: f64, toward: f64) -> Option<(f64, f64)> {
    if !labelable(a, b) {
        return None;
    }
    let top = a.abs().max(b.abs()).max(b - a);
    // From a step above the ends' size down to one the window holds; the
    // guard keeps this within about 40 steps.
    let mut i = (top.log10().ceil() as i32 + 1) * 3;
    for _ in 0..60 {
        let s = step_value(i);
        if count(a, b, s) >= 1 {
            let first = (a / s - 1e-9).ceil();
            let last = (b / s + 1e-9).floor();
            let k = if (toward - first * s).abs() <= (toward - last * s).abs() {
                first
            } else {
                last
            };
            return Some((k * s, s));
        }
        i -= 1;
    }
    None
}

/// The roundest tick of `scale` in [a, b] (the axis's coordinates),
/// nearest `toward`; its label written to `step` at the finest (the
/// regular ticks' spacing, so one axis keeps its decimals).
fn end_tick(scale: Scale, (a, b): (f64, f64), toward: f64, step: f64) -> Option<Tick> {
    let linear = |a: f64, b: f64, toward: f64, step: f64| {
        roundest(a, b, toward).map(|(v, s)| Tick {
            value: v,
            label: format_value(v, s.min(step)),
        })
    };
    match scale {
        Scale::Linear | Scale::Angle(AngleUnit::Radians) => linear(a, b, toward, step),
        Scale::Angle(AngleUnit::Degrees) => linear(
            a.to_degrees(),
            b.to_degrees(),
            toward.to_degrees(),
            step.to_degrees(),
        )
        .map(|t| Tick {
            value: t.value.to_radians(),
            label: format!("{}°", t.label),
        }),
        Scale::Angle(AngleUnit::PiFractions) => PI_DENOMINATORS.iter().find_map(|&d| {
            let s = PI / d as f64;
            (count(a, b, s) >= 1).then(|| {
                let k = (toward / s)
                    .round()
                    .clamp((a / s - 1e-9).ceil(), (b / s + 1e-9).floor());
                Tick {
                    value: k * s,
                    label: pi_fraction(k as i64, d),
                }
            })
        }),
        Scale::Log10 => {
            let (va, vb) = (10f64.powf(a), 10f64.powf(b));
            roundest(va, vb, 10f64.powf(toward))
                .filter(|(v, _)| *v > 0.0)
                .map(|(v, s)| Tick {
                    value: v.log10(),
                    label: format_value(v, s),
                })
        }
    }
}

/// `t` (ticks of `scale` over [lo, hi], in order) with a label within
/// [`END_REACH`] of each end: where the outer tick is farther, the
/// roundest value there is added, no nearer the low end than `low_from`
/// (a corner the other axis's label takes), and the regular ticks whose
/// labels it would run into are dropped; `apart(a, b)` is how far apart
/// (in the axis's coordinates) the labels of ticks `a` and `b` must be.
pub fn reach_ends(
    scale: Scale,
    (lo, hi): (f64, f64),
    mut t: Vec<Tick>,
    low_from: f64,
    apart: impl Fn(&Tick, &Tick) -> f64,
) -> Vec<Tick> {
    let span = hi - lo;
    if t.is_empty() || !labelable(lo, hi) || span <= 0.0 {
        return t;
    }
    let reach = END_REACH * span;
    let step = t
        .windows(2)
        .map(|w| w[1].value - w[0].value)
        .fold(span, f64::min);
    let from = lo + low_from.clamp(0.0, 0.5 * reach);
    t.retain(|k| k.value >= from);
    if t.is_empty() {
        return t;
    }
    if t[0].value - lo > reach
        && let Some(e) = end_tick(scale, (from, lo + reach), lo, step)
        && e.value < t[0].value
    {
        t.insert(0, e);
        while t.len() > 2 && t[1].value - t[0].value < apart(&t[0], &t[1]) {
            t.remove(1);
        }
    }
    let n = t.len();
    if hi - t[n - 1].value > reach
        && let Some(e) = end_tick(scale, (hi - reach, hi), hi, step)
        && e.value > t[n - 1].value
    {
        t.push(e);
        while t.len() > 2 {
            let n = t.len();
            if t[n - 1].value - t[n - 2].value >= apart(&t[n - 2], &t[n - 1]) {
                break;
            }
            t.remove(n - 2);
        }
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::axes::ticks::{log10_ticks, ticks};

    fn labels(t: &[Tick]) -> Vec<&str> {
        t.iter().map(|t| t.label.as_str()).collect()
    }

    #[test]
    fn a_log_axis_over_5_to_40_is_labelled_at_both_ends() {
        let (a, b) = (5f64.log10(), 40f64.log10());
        // Three labels fit: 5, 10, 20 (the 1-2-5 mantissas) leave 20 … 40 bare.
        let t = reach_ends(Scale::Log10, (a, b), log10_ticks(a, b, 3), 0.0, |_, _| 0.1);
        assert_eq!(labels(&t), ["5", "10", "20", "40"]);
    }

    #[test]
    fn the_ends_reach_is_kept_and_crowded_ticks_give_way() {
        // 0.03 … 0.97 at 0.2 steps: 0.2 … 0.8, 18 % from each end.
        let t = ticks(0.03, 0.97, 3);
        assert_eq!(labels(&t), ["0.2", "0.4", "0.6", "0.8"]);
        let t = reach_ends(Scale::Linear, (0.03, 0.97), t, 0.0, |_, _| 0.15);
        assert_eq!(labels(&t), ["0.1", "0.4", "0.6", "0.9"]);
        // A corner kept free: no label before 0.05, the roundest after.
        let t = reach_ends(
            Scale::Linear,
            (0.0, 1.0),
            ticks(0.0, 1.0, 2),
            0.05,
            |_, _| 0.1,
        );
        assert_eq!(labels(&t)[0], "0.1");
    }
}
