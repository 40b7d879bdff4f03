//! What a played GIF holds over all its frames (issue 57): each legend's
//! entries and each plot's bounds, the union over every frame. A first
//! run over the frames (an off-screen context in [`Mode::Collect`])
//! draws each frame as usual and gathers, per legend row and per plot in
//! the order the views draw them, the entries drawn (label and key, as
//! shapes: an entry is its exact style) and the bounds shown. The frames
//! are then drawn in [`Mode::Hold`]: every legend row lists the union of
//! its entries, each once and in the order they first came, and every
//! plot's automatic bounds take in the union of its bounds, so the axes
//! and the legend stand still while the data moves. The window draws in
//! [`Mode::Free`]: entries as the view draws them, plots as egui_plot
//! bounds them.

use eframe::egui;
use egui::epaint::Shape;
use egui::{Id, Pos2, Rect, Ui, Vec2};
use egui_plot::{Plot, PlotBounds, PlotMemory};

/// One legend entry: its key (shapes in a `size` box at the origin) and
/// its label.
#[derive(Clone, Debug, PartialEq)]
pub struct Entry {
    label: String,
    size: Vec2,
    key: Vec<Shape>,
}

/// The union over a play's frames: each legend row's entries, each plot's
/// bounds, in the order the views draw them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Held {
    pub legends: Vec<Vec<Entry>>,
    pub bounds: Vec<Option<PlotBounds>>,
}

/// How a renderer begins: gathering a play's union, or holding one.
#[derive(Clone, Debug)]
pub enum Start {
    Collect,
    Hold(Held),
}

/// How a context draws legends and bounds plots.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Mode {
    /// As the views draw them (the window, a still figure).
    #[default]
    Free,
    /// As the views draw them, gathering the union.
    Collect,
    /// The union gathered, whatever this frame draws.
    Hold,
}

#[derive(Clone, Default)]
struct State {
    mode: Mode,
    held: Held,
    /// Legend rows and plots begun this pass.
    rows: usize,
    plots: usize,
    /// The entries of the legend row being drawn.
    row: Option<Vec<Entry>>,
}

fn state_id() -> Id {
    Id::unique("oneblock-hold")
}

fn with<R>(ctx: &egui::Context, f: impl FnOnce(&mut State) -> R) -> R {
    ctx.data_mut(|d| f(d.get_temp_mut_or_default::<State>(state_id())))
}

/// `ctx` gathers the union from now on.
pub fn collect(ctx: &egui::Context) {
    with(ctx, |s| {
        *s = State {
            mode: Mode::Collect,
            ..State::default()
        }
    });
}

/// `ctx` draws `held` from now on.
pub fn hold(ctx: &egui::Context, held: Held) {
    with(ctx, |s| {
        *s = State {
            mode: Mode::Hold,
            held,
            ..State::default()
        }
    });
}

/// The union gathered so far.
pub fn gathered(ctx: &egui::Context) -> Held {
    with(ctx, |s| s.held.clone())
}

/// A new pass: its rows and plots counted from the first again.
pub fn begin_pass(ctx: &egui::Context) {
    with(ctx, |s| {
        s.rows = 0;
        s.plots = 0;
        s.row = None;
    });
}

/// The pass just drawn: in [`Mode::Collect`], each plot's bounds taken
/// into the union.
pub fn end_pass(ctx: &egui::Context) {
    let (mode, plots) = with(ctx, |s| (s.mode, s.plots));
    if mode != Mode::Collect {
        return;
    }
    let shown: Vec<Option<PlotBounds>> = (0..plots)
        .map(|i| PlotMemory::load(ctx, plot_id(i)).map(|m| *m.bounds()))
        .collect();
    with(ctx, |s| {
        let all = &mut s.held.bounds;
        all.resize(all.len().max(shown.len()), None);
        for (u, b) in all.iter_mut().zip(shown) {
            let Some(b) = b.filter(PlotBounds::is_finite) else {
                continue;
            };
            match u {
                Some(u) => u.merge(&b),
                None => *u = Some(b),
            }
        }
    });
}

fn plot_id(i: usize) -> Id {
    Id::unique("oneblock-held-plot").with(i)
}

/// `plot` as this context bounds it: outside [`Mode::Free`] under an id
/// of its place in the pass (the same plot in every frame), and in
/// [`Mode::Hold`] its automatic bounds taking in the union's (a view
/// that sets its bounds itself keeps them).
pub fn plot<'a>(ctx: &egui::Context, plot: Plot<'a>) -> Plot<'a> {
    let (mode, i, held) = with(ctx, |s| {
        let i = s.plots;
        if s.mode != Mode::Free {
            s.plots += 1;
        }
        (s.mode, i, s.held.bounds.get(i).copied().flatten())
    });
    if mode == Mode::Free {
        return plot;
    }
    let plot = plot.id(plot_id(i));
    match held {
        Some(b) if mode == Mode::Hold => plot
            .include_x(b.min()[0])
            .include_x(b.max()[0])
            .include_y(b.min()[1])
            .include_y(b.max()[1]),
        _ => plot,
    }
}

/// A legend row's entries, drawn by `add`: gathered (or, held, replaced
/// by the union's).
pub fn row<R>(ui: &mut Ui, add: impl FnOnce(&mut Ui) -> R) -> R {
    let (mode, i) = with(ui.ctx(), |s| {
        let i = s.rows;
        if s.mode != Mode::Free {
            s.rows += 1;
            s.row = Some(Vec::new());
        }
        (s.mode, i)
    });
    let r = add(ui);
    let drawn = with(ui.ctx(), |s| s.row.take()).unwrap_or_default();
    match mode {
        Mode::Free => {}
        Mode::Collect => with(ui.ctx(), |s| {
            let all = &mut s.held.legends;
            all.resize(all.len().max(i + 1), Vec::new());
            merge(&mut all[i], drawn);
        }),
        Mode::Hold => {
            let held = with(ui.ctx(), |s| s.held.legends.get(i).cloned());
            for e in held.unwrap_or(drawn) {
                draw(ui, &e);
            }
        }
    }
    r
}

/// `frame`'s entries into `union`: each new one after the one drawn
/// before it, so the union keeps every frame's order.
fn merge(union: &mut Vec<Entry>, frame: Vec<Entry>) {
    let mut at = 0;
    for e in frame {
        match union.iter().position(|u| *u == e) {
            Some(i) => at = i + 1,
            None => {
                union.insert(at, e);
                at += 1;
            }
        }
    }
}

/// A legend entry of a `size` key drawn by `key` (its shapes for a box
/// at the origin) and `label`: drawn, and in a held row gathered (drawn
/// with the row's union at its end instead).
pub fn entry(ui: &mut Ui, size: Vec2, label: &str, key: impl FnOnce(Rect) -> Vec<Shape>) {
    let e = Entry {
        label: label.to_owned(),
        size,
        key: key(Rect::from_min_size(Pos2::ZERO, size)),
    };
    let held = with(ui.ctx(), |s| match &mut s.row {
        Some(row) => {
            row.push(e.clone());
            s.mode == Mode::Hold
        }
        None => false,
    });
    if !held {
        draw(ui, &e);
    }
}

/// An entry drawn: its key, then its label, the two kept on one row.
fn draw(ui: &mut Ui, e: &Entry) {
    super::style::keep_key_with_label(ui, e.size.x, &e.label);
    let (rect, _) = ui.allocate_exact_size(e.size, egui::Sense::hover());
    let at = rect.min.to_vec2();
    ui.painter().extend(e.key.iter().cloned().map(|mut s| {
        s.translate(at);
        s
    }));
    ui.label(&e.label);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn e(label: &str) -> Entry {
        Entry {
            label: label.into(),
            size: Vec2::splat(10.0),
            key: Vec::new(),
        }
    }

    #[test]
    fn the_union_keeps_each_entry_once_in_the_order_drawn() {
        let mut u = Vec::new();
        merge(&mut u, vec![e("f"), e("orbit"), e("basin: P2")]);
        merge(
            &mut u,
            vec![e("f"), e("orbit"), e("basin: chaotic"), e("density")],
        );
        merge(&mut u, vec![e("f"), e("basin: P2")]);
        let labels: Vec<&str> = u.iter().map(|x| x.label.as_str()).collect();
        assert_eq!(
            labels,
            ["f", "orbit", "basin: chaotic", "density", "basin: P2"]
        );
    }
}
