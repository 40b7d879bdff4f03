//! A bracketing root finder for event location on dense output.

/// Finds t in [a, b] with g(t) = 0, given g(a) and g(b) of opposite signs
/// (or g(b) = 0), by the Illinois variant of regula falsi with a bisection
/// guard, to an absolute tolerance `tol` in t. Returns the end of the final
/// bracket on the far side (g ≤ 0 side is `b`'s side), so that the event is
/// never reported before it happened.
pub fn find_root<G: FnMut(f64) -> f64>(
    mut g: G,
    mut a: f64,
    mut ga: f64,
    mut b: f64,
    mut gb: f64,
    tol: f64,
) -> f64 {
    if gb == 0.0 {
        return b;
    }
    let mut side = 0i8;
    for _ in 0..200 {
        if (b - a).abs() <= tol {
            break;
        }
        let mut c = (a * gb - b * ga) / (gb - ga);
        // Keep the secant point strictly inside and away from stagnation.
        let w = b - a;
        if !(c > a.min(b) && c < a.max(b) && c.is_finite()) {
            c = a + 0.5 * w;
        }
        let gc = g(c);
        if gc == 0.0 {
            return c;
        }
        if (gc > 0.0) == (ga > 0.0) {
            a = c;
            ga = gc;
            if side == -1 {
                gb *= 0.5;
            }
            side = -1;
        } else {
            b = c;
            gb = gc;
            if side == 1 {
                ga *= 0.5;
            }
            side = 1;
        }
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_roots_to_tolerance() {
        let r = find_root(|t| t.cos(), 0.0, 1.0, 3.0, 3f64.cos(), 1e-14);
        assert!((r - std::f64::consts::FRAC_PI_2).abs() < 1e-13);
        let r = find_root(|t| (t - 0.3).powi(3), 0.0, -0.027, 1.0, 0.343, 1e-13);
        assert!((r - 0.3).abs() < 1e-12);
    }
}
