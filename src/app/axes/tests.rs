//! The ticks' unit tests.

use super::*;
use std::f64::consts::PI;

fn labels(t: &[Tick]) -> Vec<&str> {
    t.iter().map(|t| t.label.as_str()).collect()
}

#[test]
fn at_least_five_round_ticks_over_any_range() {
    for &(lo, hi) in &[
        (0.0, std::f64::consts::FRAC_PI_2),
        (1.15, 1.35),
        (-1.0, 1.0),
        (0.0, 1.0),
        (1e-6, 3e-6),
        (-123456.0, 987654.0),
        (0.999, 1.001),
        (-0.3, 0.0),
    ] {
        let t = ticks(lo, hi, 5);
        assert!(t.len() >= 5, "{lo}..{hi}: {:?}", labels(&t));
        // No more than the next coarser 1-2-5 step would have given
        // beyond five (coarser is at most 2.5× the step).
        assert!(t.len() <= 13, "{lo}..{hi}: {}", t.len());
        let step = t[1].value - t[0].value;
        let m = step / 10f64.powf(step.log10().floor());
        assert!(
            [1.0, 2.0, 5.0, 10.0].iter().any(|r| (m - r).abs() < 1e-6),
            "step {step} is not 1-2-5"
        );
        for tk in &t {
            assert!(tk.value >= lo - 1e-9 * step && tk.value <= hi + 1e-9 * step);
            // The label reads back as the value.
            let back: f64 = tk.label.parse().expect("numeric label");
            assert!(
                (back - tk.value).abs() <= 1e-6 * step,
                "{} vs {}",
                tk.label,
                tk.value
            );
        }
    }
}

#[test]
fn the_issue_ranges_get_dense_labels() {
    assert_eq!(
        labels(&ticks(0.0, std::f64::consts::FRAC_PI_2, 5)),
        ["0.0", "0.2", "0.4", "0.6", "0.8", "1.0", "1.2", "1.4"]
    );
    assert_eq!(
        labels(&ticks(1.15, 1.35, 5)),
        ["1.15", "1.20", "1.25", "1.30", "1.35"]
    );
    assert_eq!(
        labels(&ticks(-1.0, 1.0, 5)),
        ["-1.0", "-0.5", "0.0", "0.5", "1.0"]
    );
    assert_eq!(
        labels(&ticks(-0.01, 0.01, 5)),
        ["-0.010", "-0.005", "0.000", "0.005", "0.010"]
    );
}

#[test]
fn angles_in_degrees_and_fractions_of_pi() {
    let deg = angle_ticks(0.0, std::f64::consts::FRAC_PI_2, 5, AngleUnit::Degrees);
    assert_eq!(labels(&deg), ["0°", "20°", "40°", "60°", "80°"]);
    assert!((deg[1].value - 20f64.to_radians()).abs() < 1e-12);
    let pi = angle_ticks(0.0, std::f64::consts::FRAC_PI_2, 5, AngleUnit::PiFractions);
    assert_eq!(labels(&pi), ["0", "π/8", "π/4", "3π/8", "π/2"]);
    assert!((pi[3].value - 3.0 * PI / 8.0).abs() < 1e-12);
    let full = angle_ticks(-PI, PI, 5, AngleUnit::PiFractions);
    assert_eq!(labels(&full), ["-π", "-π/2", "0", "π/2", "π"]);
    // Too narrow for π/24: decimal multiples of π, still at least five.
    let narrow = angle_ticks(1.15, 1.35, 5, AngleUnit::PiFractions);
    assert!(narrow.len() >= 5);
    for t in &narrow {
        let k: f64 = t
            .label
            .trim_end_matches('π')
            .parse()
            .expect("multiple of π");
        assert!((k * PI - t.value).abs() < 1e-9);
    }
}

#[test]
fn log_axes_label_decades_or_mantissas() {
    let t = log10_ticks(-9.0, -3.0, 5);
    assert_eq!(
        labels(&t),
        ["1e-9", "1e-8", "1e-7", "1e-6", "1e-5", "1e-4", "1e-3"]
    );
    let t = log10_ticks(-6.0, -4.0, 5);
    assert_eq!(labels(&t), ["1e-6", "3e-6", "1e-5", "3e-5", "1e-4"]);
    assert!((t[1].value - 3e-6f64.log10()).abs() < 1e-12);
    let t = log10_ticks(-6.0, -5.0, 5);
    assert_eq!(labels(&t), ["2e-6", "4e-6", "6e-6", "8e-6", "1.0e-5"]);
    // Within a decade: round values of the value itself.
    let t = log10_ticks(2f64.log10(), 8f64.log10(), 5);
    assert_eq!(labels(&t), ["2", "3", "4", "5", "6", "7", "8"]);
    assert!((t[1].value - 3f64.log10()).abs() < 1e-12);
    // Counts over decades: plain integers, not "3e0".
    let t = log10_ticks(0.0, 3.0, 5);
    assert_eq!(labels(&t), ["1", "3", "10", "30", "100", "300", "1000"]);
    assert!((t[3].value - 30f64.log10()).abs() < 1e-12);
}

#[test]
fn nice_bounds_reach_round_values_with_five_ticks() {
    let (a, b) = nice_bounds(0.125, 0.575, 5);
    assert!(
        (a - 0.1).abs() < 1e-12 && (b - 0.6).abs() < 1e-12,
        "{a} {b}"
    );
    assert!(ticks(a, b, 5).len() >= 5);
    let (a, b) = nice_bounds(-0.93, 2.41, 5);
    assert!(
        (a + 1.0).abs() < 1e-12 && (b - 3.0).abs() < 1e-12,
        "{a} {b}"
    );
    assert_eq!(nice_bounds(1.0, 1.0, 5), (1.0, 1.0));
}

#[test]
fn degenerate_ranges_give_no_ticks_and_never_minus_zero() {
    assert!(ticks(1.0, 1.0, 5).is_empty());
    assert!(ticks(f64::NAN, 1.0, 5).is_empty());
    assert!(ticks(0.0, f64::INFINITY, 5).is_empty());
    assert_eq!(format_value(-1e-17, 0.1), "0.0");
    assert_eq!(format_value(2e-5, 1e-5), "2e-5");
    assert_eq!(format_value(2.5e-5, 5e-6), "2.5e-5");
    assert_eq!(format_value(0.9995, 5e-4), "0.9995");
    // Reversed ends give the same ticks.
    assert_eq!(ticks(1.0, 0.0, 5), ticks(0.0, 1.0, 5));
}

#[test]
fn a_short_axis_gets_fewer_ticks_rather_than_no_labels() {
    let room = 22.0;
    LABEL_FONT.with(|c| {
        c.set(LabelFont {
            row: room,
            widths: [10.0; 16],
            other: 20.0,
        })
    });
    // 160 points over 0 … 1.75: five ticks (0.2 apart, 18 points) would
    // overlap, so egui would label none; fewer, farther apart, fit.
    let t = legible_ticks(Scale::Linear, egui_plot::Axis::Y, (0.0, 1.75), 160.0 / 1.75);
    assert!(t.len() >= 2 && t.len() < MIN_TICKS, "{:?}", labels(&t));
    for w in t.windows(2) {
        assert!((w[1].value - w[0].value) * 160.0 / 1.75 >= room);
    }
    // With room, the five or more of `ticks`.
    let t = legible_ticks(Scale::Linear, egui_plot::Axis::Y, (0.0, 1.75), 400.0 / 1.75);
    assert_eq!(t, ticks(0.0, 1.75, MIN_TICKS));
}

/// A degenerate range (subnormal, zero-width, relatively negligible,
/// overflowing, non-finite) gives no ticks and unchanged bounds at once,
/// whoever asks: a zoom of width 5e-324 once froze the window in the step
/// search.
#[test]
fn degenerate_ranges_give_no_ticks_and_return() {
    let t0 = std::time::Instant::now();
    for &(lo, hi) in &[
        (0.0, 5e-324),
        (0.0, 1e-310),
        (1.0, 1.0),
        (1.0, 1.0 + 1e-15),
        (-1e308, 1e308),
        (0.0, f64::INFINITY),
        (f64::NAN, 1.0),
        (f64::NEG_INFINITY, f64::INFINITY),
    ] {
        assert!(!labelable(lo, hi), "{lo}..{hi}");
        assert!(ticks(lo, hi, 5).is_empty(), "{lo}..{hi}");
        assert!(nice_step(lo, hi, usize::MAX).is_none(), "{lo}..{hi}");
        for unit in [
            AngleUnit::Radians,
            AngleUnit::Degrees,
            AngleUnit::PiFractions,
        ] {
            assert!(angle_ticks(lo, hi, 5, unit).is_empty(), "{lo}..{hi}");
        }
        assert!(log10_ticks(lo, hi, 5).is_empty(), "{lo}..{hi}");
        let (a, b) = nice_bounds(lo, hi, 5);
        assert!(a.to_bits() == lo.to_bits() && b.to_bits() == hi.to_bits());
    }
    // The narrowest ranges still labelled get their five ticks.
    for &(lo, hi) in &[(0.0, 1e-199), (1.0, 1.0 + 1e-11), (-1e199, 1e199)] {
        assert!(labelable(lo, hi));
        assert!(ticks(lo, hi, 5).len() >= 5, "{lo}..{hi}");
        // A huge tick count is bounded, not allocated.
        assert!(ticks(lo, hi, usize::MAX).len() <= 3000, "{lo}..{hi}");
    }
    assert!(t0.elapsed() < std::time::Duration::from_secs(1));
}

#[test]
fn hover_labels_name_the_axes() {
    let x = AxisSpec::linear("θν, pull direction (rad)");
    let y = AxisSpec::log10("count + 1 (log scale)");
    assert_eq!(short_name(&x.title), "θν");
    assert_eq!(short_name(&y.title), "count + 1");
    let pos = egui_plot::HoverPosition::NearDataPoint {
        plot_name: "cobweb",
        position: egui_plot::PlotPoint::new(1.095, 2.0),
        index: 0,
    };
    assert_eq!(
        hover_label(&x, &y, &pos).as_deref(),
        Some("cobweb\nθν = 1.0950\ncount + 1 = 1.000e2")
    );
}

#[test]
fn a_y_title_shortens_to_its_symbol_and_unit_then_its_symbol() {
    let ctx = egui::Context::default();
    let mut got = Vec::new();
    let _ = ctx.run_ui(egui::RawInput::default(), |ui| {
        for h in [600.0, 110.0, 40.0] {
            let spec = AxisSpec::angle("θ, slip onset", AngleUnit::Radians).fitted_along(ui, h);
            got.push(spec.title);
        }
    });
    assert_eq!(got, ["θ, slip onset (rad)", "θ (rad)", "θ"]);
}
