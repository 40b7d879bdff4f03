//! The window's layout stays within a budget at any text size and tile
//! count (issue 40). A session of the Plane, Block and Bifurcation tiles
//! at text ×3 in an 800 × 560 window aborted with "memory allocation of
//! 3221225472 bytes failed": the Block tile had no room left under its
//! controls, its stripe spacing became 0, and its stripe loop never ended
//! (16 GB in 81 s without a limit). Now a tile is given at least
//! `min_tile` of the text size, fewer tiles are shown past it with a line
//! saying so, and the Block scene in whatever room it gets draws and ends.
#![cfg(feature = "gui")]

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;

use oneblock::app::views::{min_tile, tiles_that_fit};
use oneblock::app::{Explorer, Layout, Recorder, Settings, ViewKind};
use oneblock::sim::{Phase, Sample};
use oneblock::worker::{Command, Spec, Update};

/// A `size` window showing `settings`, with a trajectory for the Block
/// scene to draw (without one it only says it is waiting).
fn window(rec: &Recorder, settings: Settings, size: [f32; 2]) -> Harness<'static, Explorer> {
    let app = Explorer::new(Box::new(rec.clone()), settings);
    let mut h = Harness::builder().with_size(size).build_ui_state(
        |ui, app: &mut Explorer| {
            app.logic_step(ui.ctx());
            app.show(ui);
        },
        app,
    );
    h.run_steps(2);
    let generation = rec
        .commands()
        .iter()
        .rev()
        .find_map(|c| match c {
            Command::Run {
                generation,
                spec: Spec::Trajectory(..),
            } => Some(*generation),
            _ => None,
        })
        .expect("a trajectory command");
    let samples: Vec<Sample> = (0..200)
        .map(|i| {
            let s = i as f64 / 199.0;
            Sample {
                t: 3.0 * s,
                x: 0.05 * (6.0 * s).cos(),
                y: 0.5 - s,
                u: 0.0,
                w: -0.3,
                phase: if s < 0.4 { Phase::Accel } else { Phase::Decel },
            }
        })
        .collect();
    rec.push(Update::TrajectoryChunk {
        generation,
        samples,
    });
    h
}

/// Every view tiled at text size `scale`.
fn all_tiles(scale: f32) -> Settings {
    Settings {
        layout: Layout::Tiles,
        tiled: ViewKind::ALL.to_vec(),
        font_scale: scale,
        ..Settings::default()
    }
}

#[test]
fn every_tile_at_every_text_size_draws_and_ends_within_the_layout_budget() {
    for size in [[800.0, 560.0], [1280.0, 800.0], [1920.0, 1200.0]] {
        for scale in [0.5, 1.0, 2.0, 3.0] {
            let rec = Recorder::new();
            let mut h = window(&rec, all_tiles(scale), size);
            // The Block scene animates: several frames with samples.
            h.run_steps(4);
            let shown: Vec<ViewKind> = ViewKind::ALL
                .into_iter()
                .filter(|v| h.state().view_rect(*v).is_some())
                .collect();
            assert!(!shown.is_empty(), "{size:?} ×{scale}: no tile shown");
            // The first tiles ticked, in order.
            assert_eq!(shown, ViewKind::ALL[..shown.len()].to_vec());
            // A row is at least the body text's size (the window uses its height).
            let row = h.ctx.global_style().text_styles[&egui::TextStyle::Body].size;
            let message = h
                .query_all_by_label_contains("tiles shown: no room")
                .count();
            if shown.len() < ViewKind::ALL.len() {
                assert_eq!(message, 1, "{size:?} ×{scale}: {} shown", shown.len());
            } else {
                assert_eq!(message, 0, "{size:?} ×{scale}");
            }
            if shown.len() > 1 {
                // Every tile shown has the least room a tile is given.
                let min = min_tile(row);
                for v in &shown {
                    let r = h.state().view_rect(*v).expect("shown");
                    assert!(
                        r.width() >= min.x && r.height() >= min.y,
                        "{size:?} ×{scale}: {v:?} in {r:?}, less than {min:?}"
                    );
                }
            }
        }
    }
}

#[test]
fn the_block_tile_at_text_3_in_the_smallest_tile_draws_and_ends() {
    // The sessions: Plane, Block and Bifurcation at text ×3 in
    // 800 × 560, and Block alone as a tab in the smallest window.
    let three = Settings {
        tiled: vec![ViewKind::Plane, ViewKind::Block, ViewKind::Bifurcation],
        ..all_tiles(3.0)
    };
    let tab = Settings {
        layout: Layout::Tabs,
        tab: ViewKind::Block,
        font_scale: 3.0,
        ..Settings::default()
    };
    for (settings, size) in [
        (three.clone(), [800.0, 560.0]),
        (three, [1280.0, 800.0]),
        (all_tiles(3.0), [1280.0, 800.0]),
        (tab.clone(), [200.0, 200.0]),
        (tab, [800.0, 560.0]),
    ] {
        let rec = Recorder::new();
        let mut h = window(&rec, settings, size);
        h.run_steps(6);
        // Whatever room Block got (none, in the smallest windows), the
        // frames ended; where it was drawn its rect lies in the window.
        if let Some(r) = h.state().view_rect(ViewKind::Block) {
            let screen = egui::Rect::from_min_size(egui::Pos2::ZERO, size.into());
            assert!(screen.expand(1.0).contains_rect(r), "{size:?}: {r:?}");
        }
    }
    // The budget itself: at text ×3 nine tiles never share 1280 × 800.
    let area = egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(900.0, 700.0));
    assert!(tiles_that_fit(area, 9, min_tile(42.0)) < 9);
}
