//! The work-precision chart as SVG: log-log, max map error on x, median
//! time per iterate on y, one curve per method.

use plotters::prelude::*;

use super::work_precision::Row;

/// Draws the chart of `rows` (rows with failed points or no finite error are
/// left out) and returns the SVG text.
pub fn svg(rows: &[Row], subtitle: &str) -> Result<String, String> {
    let mut methods: Vec<&'static str> = Vec::new();
    for r in rows {
        if !methods.contains(&r.method) {
            methods.push(r.method);
        }
    }
    let usable = |r: &&Row| r.failed == 0 && r.max_error.is_finite() && r.median_us > 0.0;
    let floor = 1e-16;
    let pts: Vec<(f64, f64)> = rows
        .iter()
        .filter(usable)
        .map(|r| (r.max_error.max(floor), r.median_us))
        .collect();
    if pts.is_empty() {
        return Err("no setting succeeded on every point".into());
    }
    let ([x0, x1], [y0, y1]) = decades(&pts);
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (900, 620)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let mut chart = ChartBuilder::on(&root)
            .caption(
                format!("oneblock work-precision: map error vs cost ({subtitle})"),
                ("sans-serif", 18),
            )
            .margin(16)
            .x_label_area_size(48)
            .y_label_area_size(64)
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
            .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .x_desc("max |θ' − θ'_ref| over the sample")
            .y_desc("median time per iterate (µs)")
            .x_label_formatter(&|v| format!("{v:.0e}"))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .draw()
            .map_err(|e| e.to_string())?;
        for (i, m) in methods.iter().enumerate() {
            let color = Palette99::pick(i).to_rgba();
            let series: Vec<(f64, f64)> = rows
                .iter()
                .filter(usable)
                .filter(|r| r.method == *m)
                .map(|r| (r.max_error.max(floor), r.median_us))
                .collect();
            if series.is_empty() {
                continue;
            }
            chart
                .draw_series(LineSeries::new(series.clone(), color.stroke_width(2)))
                .map_err(|e| e.to_string())?
                .label(*m)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                });
            chart
                .draw_series(
                    series
                        .iter()
                        .map(|&(x, y)| Circle::new((x, y), 3, color.filled())),
                )
                .map_err(|e| e.to_string())?;
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(out)
}

/// The whole decades around `pts` (error, time), in each axis: the
/// chart's log ranges.
fn decades(pts: &[(f64, f64)]) -> ([f64; 2], [f64; 2]) {
    let lg = |v: f64| v.log10();
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in pts {
        x0 = x0.min(lg(x));
        x1 = x1.max(lg(x));
        y0 = y0.min(lg(y));
        y1 = y1.max(lg(y));
    }
    (
        [10f64.powf(x0.floor()), 10f64.powf(x1.ceil())],
        [10f64.powf(y0.floor()), 10f64.powf(y1.ceil())],
    )
}
