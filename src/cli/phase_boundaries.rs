//! `oneblock phase --boundaries FILE`: bifurcation curves (the CSV of
//! `oneblock continue --curve`) read back as the curves the Phase view
//! draws over the grid, each kind and period in its own style.

use std::path::Path;

use crate::sim::continuation::{ContParam, Curve, CurveKind, CurvePoint};

/// Reads the curves of a curve CSV: the columns `theta_nu`, `kappa`,
/// `kind` (pd or fold) and `period` (in any order, as `continue --curve
/// --params theta-nu,kappa` writes them, after its `#` lines); rows are grouped into curves by
/// the `curve`, `kind` and `period` columns, and a repeated header (files
/// concatenated) starts new ones. Errors are one line.
pub fn read_boundaries(path: &Path) -> Result<Vec<Curve>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read it: {e}"))?;
    // No header row for the reader: a repeated header (files concatenated)
    // must be seen as a row to start new curves.
    let mut records = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        // The `#` provenance lines `continue --out` writes first.
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes())
        .into_records();
    let Some(header) = records.next() else {
        return Err("the file is empty".into());
    };
    let header = header.map_err(|e| format!("not CSV: {e}"))?;
    let col = |n: &str| header.iter().position(|h| h == n);
    let (Some(x), Some(y), Some(k), Some(p)) =
        (col("theta_nu"), col("kappa"), col("kind"), col("period"))
    else {
        let shown = header.iter().collect::<Vec<_>>().join(",");
        return Err(format!(
            "the header '{}' lacks one of the columns theta_nu, kappa, kind and period (write it with oneblock continue --curve ... --params theta-nu,kappa)",
            super::values::echo(&shown)
        ));
    };
    let keys: Vec<usize> = ["curve", "kind", "period"]
        .iter()
        .filter_map(|n| col(n))
        .collect();
    let mut out: Vec<Curve> = Vec::new();
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
        let kind = match f.get(k) {
            Some("pd") => CurveKind::PeriodDoubling,
            Some("fold") => CurveKind::Fold,
            other => {
                return Err(format!(
                    "line {line}: the kind '{}' is neither pd nor fold",
                    super::values::echo(other.unwrap_or(""))
                ));
            }
        };
        let period = f
            .get(p)
            .and_then(|s| s.parse::<usize>().ok())
            .filter(|&n| (1..=1 << 20).contains(&n))
            .ok_or_else(|| format!("line {line}: the period is not a whole number in [1, 2^20]"))?;
        let point = CurvePoint {
            lambda: [num(x)?, num(y)?],
            theta: col("theta").map_or(Ok(f64::NAN), &num)?,
            multiplier: kind.target(),
        };
        let key: Vec<String> = keys
            .iter()
            .map(|&k| f.get(k).unwrap_or("").to_string())
            .collect();
        match out.last_mut() {
            Some(c) if last_key.as_ref() == Some(&key) => c.points.push(point),
            _ => out.push(Curve {
                kind,
                period,
                params: [ContParam::ThetaNu, ContParam::Kappa],
                points: vec![point],
                ends: [String::new(), String::new()],
                map_evals: 0,
                generalised_flips: Vec::new(),
            }),
        }
        last_key = Some(key);
    }
    if out.is_empty() {
        return Err("the file has no points".into());
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn curves_are_grouped_by_curve_kind_and_period() {
        let dir = tempfile::tempdir().unwrap_or_else(|e| panic!("{e}"));
        let p = dir.path().join("c.csv");
        let head = "curve,kind,period,theta_nu,kappa,theta,multiplier";
        let text = format!(
            "# oneblock 0.1.0\n{head}\n0,pd,1,1.0,16,0.4,-1\n0,pd,1,1.1,17,0.4,-1\n{head}\n0,pd,2,1.2,16,0.4,-1\n1,fold,1,1.3,3,0.1,1\n"
        );
        std::fs::write(&p, text).unwrap_or_else(|e| panic!("{e}"));
        let curves = read_boundaries(&p).unwrap_or_else(|e| panic!("{e}"));
        let got: Vec<(CurveKind, usize, Vec<[f64; 2]>)> = curves
            .iter()
            .map(|c| {
                (
                    c.kind,
                    c.period,
                    c.points.iter().map(|q| q.lambda).collect(),
                )
            })
            .collect();
        assert_eq!(
            got,
            vec![
                (CurveKind::PeriodDoubling, 1, vec![[1.0, 16.0], [1.1, 17.0]]),
                (CurveKind::PeriodDoubling, 2, vec![[1.2, 16.0]]),
                (CurveKind::Fold, 1, vec![[1.3, 3.0]]),
            ]
        );
        std::fs::write(&p, "a,b\n1,2\n").unwrap_or_else(|e| panic!("{e}"));
        assert!(read_boundaries(&p).unwrap_err().contains("theta_nu"));
        std::fs::write(&p, "theta_nu,kappa\n1,2\n").unwrap_or_else(|e| panic!("{e}"));
        assert!(read_boundaries(&p).unwrap_err().contains("kind"));
        std::fs::write(&p, format!("{head}\n0,hopf,1,1,2,0,1\n")).unwrap_or_else(|e| panic!("{e}"));
        assert!(read_boundaries(&p).unwrap_err().contains("hopf"));
    }
}
