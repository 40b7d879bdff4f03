//! `oneblock phase --boundaries FILE`: bifurcation curves (the CSV of
//! `oneblock continue --curve`) drawn over the phase PNG.

use std::path::Path;

/// One polyline in (θν, κ).
pub type Polyline = Vec<[f64; 2]>;

/// Reads the polylines of a curve CSV: the columns `theta_nu` and `kappa`
/// (in any order); rows are grouped into polylines by the `curve`, `kind`
/// and `period` columns where present, and a repeated header (files
/// concatenated) starts new ones. Errors are one line.
pub fn read_boundaries(path: &Path) -> Result<Vec<Polyline>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read it: {e}"))?;
    let mut lines = text.lines().enumerate();
    let Some((_, header)) = lines.next() else {
        return Err("the file is empty".into());
    };
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let col = |n: &str| names.iter().position(|h| *h == n);
    let (Some(x), Some(y)) = (col("theta_nu"), col("kappa")) else {
        return Err(format!(
            "the header '{}' has no theta_nu and kappa columns (write it with oneblock continue --curve ... --params theta-nu,kappa)",
            super::values::echo(header)
        ));
    };
    let keys: Vec<usize> = ["curve", "kind", "period"]
        .iter()
        .filter_map(|n| col(n))
        .collect();
    let mut out: Vec<Polyline> = Vec::new();
    let mut last_key: Option<Vec<String>> = None;
    for (i, line) in lines {
        if line.trim().is_empty() {
            continue;
        }
        if line == header {
            last_key = None;
            continue;
        }
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        let num = |j: usize| -> Result<f64, String> {
            f.get(j)
                .and_then(|s| s.parse::<f64>().ok())
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("line {}: no finite number in column {}", i + 1, j + 1))
        };
        let p = [num(x)?, num(y)?];
        let key: Vec<String> = keys
            .iter()
            .map(|&k| f.get(k).unwrap_or(&"").to_string())
            .collect();
        match out.last_mut() {
            Some(poly) if last_key.as_ref() == Some(&key) => poly.push(p),
            _ => out.push(vec![p]),
        }
        last_key = Some(key);
    }
    if out.is_empty() {
        return Err("the file has no points".into());
    }
    Ok(out)
}

/// The pixels of the segment from (x0, y0) to (x1, y1), one per step
/// along its longer axis.
pub fn segment_pixels(a: [f64; 2], b: [f64; 2]) -> Vec<[i64; 2]> {
    let n = (b[0] - a[0])
        .abs()
        .max((b[1] - a[1]).abs())
        .ceil()
        .clamp(1.0, 1e5) as usize;
    (0..=n)
        .map(|k| {
            let t = k as f64 / n as f64;
            [
                (a[0] + t * (b[0] - a[0])).round() as i64,
                (a[1] + t * (b[1] - a[1])).round() as i64,
            ]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polylines_are_grouped_by_curve_and_the_segment_is_connected() {
        let dir = tempfile::tempdir().unwrap_or_else(|e| panic!("{e}"));
        let p = dir.path().join("c.csv");
        let head = "curve,kind,period,theta_nu,kappa,theta,multiplier";
        let text = format!(
            "{head}\n0,pd,1,1.0,16,0.4,-1\n0,pd,1,1.1,17,0.4,-1\n{head}\n0,pd,2,1.2,16,0.4,-1\n"
        );
        std::fs::write(&p, text).unwrap_or_else(|e| panic!("{e}"));
        let polys = read_boundaries(&p).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(
            polys,
            vec![vec![[1.0, 16.0], [1.1, 17.0]], vec![[1.2, 16.0]]]
        );
        let px = segment_pixels([0.0, 0.0], [10.0, 3.0]);
        assert_eq!(px.first(), Some(&[0, 0]));
        assert_eq!(px.last(), Some(&[10, 3]));
        assert!(
            px.windows(2)
                .all(|w| (w[1][0] - w[0][0]).abs() <= 1 && (w[1][1] - w[0][1]).abs() <= 1)
        );
        std::fs::write(&p, "a,b\n1,2\n").unwrap_or_else(|e| panic!("{e}"));
        assert!(read_boundaries(&p).unwrap_err().contains("theta_nu"));
    }
}
