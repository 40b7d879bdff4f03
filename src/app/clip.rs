//! Lines cut to what a plot shows. egui_plot lays a dashed or dotted line's
//! dashes along its whole length on screen, inside the frame or not: the
//! diagonal θ = θν of a diagram zoomed to a θ range 1e-5 wide is kilometres
//! of screen, and its dots once took gigabytes (an SVG of 841,753 dots, an
//! abort at 2.2 GB). A line cut to the plot's bounds has at most the
//! frame's length of dashes, whatever the zoom.

/// The parts of the polyline `points` inside the box `min`–`max` (each
/// part a polyline of two or more points), for a line drawn dashed or
/// dotted. A segment crossing the box keeps the piece inside it.
pub fn clip_polyline(points: &[[f64; 2]], min: [f64; 2], max: [f64; 2]) -> Vec<Vec<[f64; 2]>> {
    let mut parts: Vec<Vec<[f64; 2]>> = Vec::new();
    let mut open = false;
    for w in points.windows(2) {
        match clip_segment(w[0], w[1], min, max) {
            Some((a, b)) => {
                // The piece continues the last part when it starts where
                // that part ended (the segment began inside the box).
                match parts.last_mut() {
                    Some(last) if open && last.last() == Some(&a) => last.push(b),
                    _ => parts.push(vec![a, b]),
                }
                // The next segment continues only if this one ended inside.
                open = b == w[1];
            }
            None => open = false,
        }
    }
    parts
}

/// The piece of the segment a–b inside the box (Liang–Barsky), if any.
fn clip_segment(
    a: [f64; 2],
    b: [f64; 2],
    min: [f64; 2],
    max: [f64; 2],
) -> Option<([f64; 2], [f64; 2])> {
    if !(a.iter().chain(&b).all(|v| v.is_finite())) {
        return None;
    }
    let d = [b[0] - a[0], b[1] - a[1]];
    // A span that overflows (ends near ±1e308) would cut at NaN.
    if !(d[0].is_finite() && d[1].is_finite()) {
        return None;
    }
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-d[0], a[0] - min[0]),
        (d[0], max[0] - a[0]),
        (-d[1], a[1] - min[1]),
        (d[1], max[1] - a[1]),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
    }
    if t0 > t1 {
        return None;
    }
    let at = |t: f64| {
        if t == 0.0 {
            a
        } else if t == 1.0 {
            b
        } else {
            [a[0] + d[0] * t, a[1] + d[1] * t]
        }
    };
    Some((at(t0), at(t1)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn a_long_diagonal_is_cut_to_a_thin_box() {
        // θ = θν over [0, π/2] seen through θ ∈ [0.4, 0.4 + 1e-5].
        let parts = clip_polyline(
            &[[0.0, 0.0], [FRAC_PI_2, FRAC_PI_2]],
            [0.0, 0.4],
            [FRAC_PI_2, 0.40001],
        );
        assert_eq!(parts.len(), 1);
        let [a, b] = [parts[0][0], parts[0][1]];
        assert!(
            (a[0] - 0.4).abs() < 1e-12 && (a[1] - 0.4).abs() < 1e-12,
            "{a:?}"
        );
        assert!(
            (b[0] - 0.40001).abs() < 1e-12 && (b[1] - 0.40001).abs() < 1e-12,
            "{b:?}"
        );
    }

    #[test]
    fn a_polyline_leaving_and_entering_splits_and_inside_stays_whole() {
        let box_ = ([0.0, 0.0], [1.0, 1.0]);
        // In, out over the top, back in: two parts.
        let parts = clip_polyline(&[[0.2, 0.5], [0.5, 2.0], [0.8, 0.5]], box_.0, box_.1);
        assert_eq!(parts.len(), 2, "{parts:?}");
        assert_eq!(parts[0][0], [0.2, 0.5]);
        assert!((parts[0][1][1] - 1.0).abs() < 1e-12);
        assert_eq!(parts[1][1], [0.8, 0.5]);
        // Wholly inside: one part, every point kept.
        let inside = [[0.1, 0.1], [0.5, 0.9], [0.9, 0.1]];
        assert_eq!(
            clip_polyline(&inside, box_.0, box_.1),
            vec![inside.to_vec()]
        );
        // Wholly outside, or not finite: nothing.
        assert!(clip_polyline(&[[2.0, 2.0], [3.0, 3.0]], box_.0, box_.1).is_empty());
        assert!(clip_polyline(&[[f64::NAN, 0.5], [0.5, 0.5]], box_.0, box_.1).is_empty());
    }
}
