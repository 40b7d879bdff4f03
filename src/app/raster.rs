//! Texel images the views draw as textures: the bifurcation diagram's
//! density spread to a thick line's width.

/// The largest count within `spread` texels (a square), rows of `w`:
/// two passes, along rows then along columns.
pub fn dilate(counts: &[u32], w: usize, spread: usize) -> Vec<u32> {
    if spread == 0 || w == 0 {
        return counts.to_vec();
    }
    let rows = counts.len() / w;
    let mut across = vec![0u32; counts.len()];
    for r in 0..rows {
        for c in 0..w {
            let (a, b) = (c.saturating_sub(spread), (c + spread).min(w - 1));
            across[r * w + c] = (a..=b).map(|k| counts[r * w + k]).max().unwrap_or(0);
        }
    }
    let mut out = vec![0u32; counts.len()];
    for r in 0..rows {
        let (a, b) = (r.saturating_sub(spread), (r + spread).min(rows - 1));
        for c in 0..w {
            out[r * w + c] = (a..=b).map(|k| across[k * w + c]).max().unwrap_or(0);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::dilate;

    #[test]
    fn a_point_spreads_to_a_square_and_nothing_else_moves() {
        // 5 × 4 texels, one hit of 3 at row 1, column 2.
        let mut c = vec![0u32; 20];
        c[5 + 2] = 3;
        let d = dilate(&c, 5, 1);
        for r in 0..4 {
            for k in 0..5 {
                let near = r <= 2 && (1..=3).contains(&k);
                assert_eq!(d[r * 5 + k], if near { 3 } else { 0 }, "row {r} col {k}");
            }
        }
        assert_eq!(dilate(&c, 5, 0), c);
    }
}
