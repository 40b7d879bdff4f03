//! Small 3-vector helpers for the curve continuation.

/// a·b.
pub(super) fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// a − b.
pub(super) fn sub(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// |a|.
pub(super) fn norm(a: &[f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// a × b.
pub(super) fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// a/|a|, or `None` for a zero or non-finite a.
pub(super) fn normalize(a: [f64; 3]) -> Option<[f64; 3]> {
    let n = norm(&a);
    (n > 0.0 && n.is_finite()).then(|| a.map(|v| v / n))
}

/// a, turned to point the way `prev` does.
pub(super) fn orient(a: [f64; 3], prev: &[f64; 3]) -> [f64; 3] {
    if dot(&a, prev) < 0.0 {
        a.map(|v| -v)
    } else {
        a
    }
}

/// Solves the 3×3 system a·x = b by Cramer's rule (`None` when singular).
pub(super) fn solve3(a: &[[f64; 3]; 3], b: &[f64; 3]) -> Option<[f64; 3]> {
    let det = |m: &[[f64; 3]; 3]| dot(&m[0], &cross(&m[1], &m[2]));
    let d = det(a);
    if !(d.is_finite() && d != 0.0) {
        return None;
    }
    let mut x = [0.0; 3];
    for (j, xj) in x.iter_mut().enumerate() {
        let mut m = *a;
        for i in 0..3 {
            m[i][j] = b[i];
        }
        *xj = det(&m) / d;
    }
    Some(x)
}
