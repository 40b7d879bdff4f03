//! The figure targets of issue 29 (docs/performance.md#figures): the
//! Fig. 3b diagram (400 columns) as SVG in under 2 s, and an animated GIF
//! of the block and of the plane, 120 frames at 640x480, in under 5 s and
//! 10 MB each, all as `oneblock figure` makes them (the data computed on
//! the single-threaded host, the frames drawn by the window's code). The
//! GIFs' sizes are checked here: over 10 MB fails the run. The same
//! diagram as a PDF (issue 42) costs at most 1.5 times its SVG: the SVG's
//! cost plus svg2pdf's, which `fig3b_diagram_svg_to_pdf` times alone.
//!
//! Run on an idle machine:
//! `cargo bench --features bench --bench figures -- --warm-up-time 1 --measurement-time 10`.

#![allow(clippy::unwrap_used)]

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use eframe::egui;
use oneblock::app::animation::gif;
use oneblock::app::figure::{Figure, pdf_of_svg, svg};
use oneblock::app::{Settings, ViewKind};

/// `view` at the fig3b preset over `w`×`h` points, as `figure` draws it.
fn figure(view: ViewKind, w: f32, h: f32) -> Figure {
    let mut settings = Settings::default();
    let p = oneblock::model::preset("fig3b").unwrap();
    settings.apply_preset(&p.params, p.key);
    Figure {
        view,
        settings,
        zoom: Vec::new(),
        theta_nu: None,
        theta: None,
        size: egui::vec2(w, h),
        crosshair: false,
        look: Default::default(),
        overlays: Default::default(),
        session: None,
    }
}

fn figures(c: &mut Criterion) {
    let mut g = c.benchmark_group("figure");
    g.sample_size(10).warm_up_time(Duration::from_secs(1));
    let diagram = figure(ViewKind::Bifurcation, 900.0, 600.0);
    assert_eq!(diagram.settings.columns, 400);
    g.bench_function("fig3b_diagram_svg", |b| {
        b.iter(|| black_box(svg(&diagram).unwrap()))
    });
    let text = svg(&diagram).unwrap();
    g.bench_function("fig3b_diagram_svg_to_pdf", |b| {
        b.iter(|| black_box(pdf_of_svg(&text).unwrap()))
    });
    for (name, view) in [("block", ViewKind::Block), ("plane", ViewKind::Plane)] {
        let fig = figure(view, 640.0, 480.0);
        let bytes = gif(&fig, 120, 1.0).unwrap();
        eprintln!("{name} GIF, 120 frames at 640x480: {} bytes", bytes.len());
        assert!(bytes.len() < 10 << 20, "{name}: {} bytes", bytes.len());
        g.bench_function(format!("{name}_gif_120_frames_640x480"), |b| {
            b.iter(|| black_box(gif(&fig, 120, 1.0).unwrap()))
        });
    }
    g.finish();
}

criterion_group!(benches, figures);
criterion_main!(benches);
