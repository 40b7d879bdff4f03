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
    // No header row for the reader: a repeated header (files concatenated)
    // must be seen as a row to start new polylines.
    let mut records = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes())
        .into_records();
    let Some(header) = records.next() else {
        return Err("the file is empty".into());
    };
    let header = header.map_err(|e| format!("not CSV: {e}"))?;
    let col = |n: &str| header.iter().position(|h| h == n);
    let (Some(x), Some(y)) = (col("theta_nu"), col("kappa")) else {
        let shown = header.iter().collect::<Vec<_>>().join(",");
        return Err(format!(
            "the header '{}' has no theta_nu and kappa columns (write it with oneblock continue --curve ... --params theta-nu,kappa)",
            super::values::echo(&shown)
        ));
    };
    let keys: Vec<usize> = ["curve", "kind", "period"]
        .iter()
        .filter_map(|n| col(n))
        .collect();
    let mut out: Vec<Polyline> = Vec::new();
    let mut last_key: Option<Vec<String>> = None;
    for record in records {
        let f = record.map_err(|e| format!("not CSV: {e}"))?;
        let line = f.position().map_or(0, |p| p.line());
        if f.iter().all(str::is_empty) {
            continue;
        }
        if f == header {
            last_key = None;
            continue;
        }
        let num = |j: usize| -> Result<f64, String> {
            f.get(j)
                .and_then(|s| s.parse::<f64>().ok())
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("line {line}: no finite number in column {}", j + 1))
        };
        let p = [num(x)?, num(y)?];
        let key: Vec<String> = keys
            .iter()
            .map(|&k| f.get(k).unwrap_or("").to_string())
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
