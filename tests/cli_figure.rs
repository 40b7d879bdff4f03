//! `oneblock figure`: every view drawn headless with no display at all
//! (DISPLAY and WAYLAND_DISPLAY unset): the SVG parses, each axis has at
//! least five numeric tick labels, no control of the window is drawn, the
//! bifurcation diagram spans the θν range asked for; every view's PNG is a
//! PNG of the size asked for, not blank; an extension the command cannot write is refused;
//! a λ under the λ strip is marked as off it.
#![cfg(feature = "gui")]

use std::collections::HashMap;
use std::path::Path;

use crate::common::figure::{figure, gif_frames, session_of, small_settings};

/// Every view `figure` draws.
const VIEWS: [&str; 9] = [
    "plane",
    "block",
    "bifurcation",
    "return-map",
    "events",
    "phase",
    "numerics",
    "time-series",
    "basins",
];

/// Words of the views' controls, none of which belongs in a figure.
const CONTROLS: [&str; 14] = [
    "Compute",
    "Find bifurcations",
    "Reset zoom",
    "Back",
    "Boundaries",
    "Play",
    "Pause",
    "cycles shown",
    "also draw",
    "x axis as κx",
    "Run for current parameters",
    "Laminar length vs",
    "f(θ) − θ",
    "drag / scroll",
];

/// A session with small jobs, a 6 × 6 phase grid too, so that every view
/// is quick.
fn small_session(dir: &Path) -> std::path::PathBuf {
    let mut s = small_settings();
    s.phase.theta_nu_steps = 6;
    s.phase.kappa_steps = 6;
    session_of(dir, s)
}

/// A `<text>` of the SVG: where it starts, how wide it is, its string,
/// and whether it is turned (an axis title on its side).
struct Text {
    x: f64,
    y: f64,
    width: f64,
    text: String,
    rotated: bool,
}

/// Every `<text>` of the SVG (parsing it on the way: a malformed SVG fails).
fn texts(svg: &str) -> Vec<Text> {
    use quick_xml::events::Event;
    let mut r = quick_xml::Reader::from_str(svg);
    let mut out = Vec::new();
    let mut open: Option<HashMap<String, String>> = None;
    let mut rotated = 0usize;
    loop {
        match r.read_event().expect("the SVG parses") {
            Event::Start(e) => {
                let attrs: HashMap<String, String> = e
                    .attributes()
                    .flatten()
                    .map(|a| {
                        (
                            String::from_utf8_lossy(a.key.as_ref()).into_owned(),
                            String::from_utf8_lossy(&a.value).into_owned(),
                        )
                    })
                    .collect();
                match e.name().as_ref() {
                    b"text" => open = Some(attrs),
                    b"g" if attrs.get("transform").is_some_and(|t| t.contains("rotate")) => {
                        rotated += 1
                    }
                    _ => {}
                }
            }
            Event::Text(t) => {
                if let Some(a) = open.take() {
                    let num = |k: &str| a.get(k).and_then(|v| v.parse().ok()).unwrap_or(f64::NAN);
                    // x is the middle of the row egui laid out, data-width its width.
                    let width = num("data-width");
                    out.push(Text {
                        x: num("x") - 0.5 * width,
                        y: num("y"),
                        width,
                        text: t.decode().expect("utf-8").into_owned(),
                        rotated: rotated > 0,
                    });
                }
            }
            Event::End(e) => match e.name().as_ref() {
                b"text" => open = None,
                b"g" => rotated = rotated.saturating_sub(1),
                _ => {}
            },
            Event::Eof => break,
            _ => {}
        }
    }
    out
}

fn number(t: &Text) -> Option<f64> {
    if t.rotated {
        return None;
    }
    t.text.replace('−', "-").trim().parse::<f64>().ok()
}

/// The largest set of numeric labels on one row (an x axis's ticks) and
/// the largest set right-aligned on one column (a y axis's ticks), within
/// two points.
fn axis_ticks(texts: &[Text]) -> (Vec<f64>, Vec<f64>) {
    let labels: Vec<(&Text, f64)> = texts.iter().filter_map(|t| Some((t, number(t)?))).collect();
    let largest = |key: &dyn Fn(&Text) -> f64| -> Vec<f64> {
        labels
            .iter()
            .map(|(a, _)| {
                labels
                    .iter()
                    .filter(|(b, _)| (key(a) - key(b)).abs() <= 2.0)
                    .map(|(_, v)| *v)
                    .collect::<Vec<f64>>()
            })
            .max_by_key(Vec::len)
            .unwrap_or_default()
    };
    (largest(&|t| t.y), largest(&|t| t.x + t.width))
}

#[test]
fn every_view_is_drawn_headless_with_its_axes_and_no_controls() {
    let dir = tempfile::tempdir().expect("temp dir");
    let session = small_session(dir.path());
    let session = session.to_str().expect("utf-8 path");
    for view in VIEWS {
        let out = dir.path().join(format!("{view}.svg"));
        let o = figure(&[
            "--view",
            view,
            "--session",
            session,
            "--out",
            out.to_str().expect("utf-8"),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{view}: {err}");
        let svg = std::fs::read_to_string(&out).expect("svg written");
        let t = texts(&svg);
        for c in CONTROLS {
            assert!(
                !t.iter().any(|x| x.text.contains(c)),
                "{view}: the control '{c}' is drawn"
            );
        }
        if view == "block" {
            // A picture of the block, not a plot: its springs and forces
            // are labelled.
            assert!(t.iter().any(|x| x.text.contains("kx = κ")), "{view}");
            assert!(
                t.iter().any(|x| x.text.contains("friction force")),
                "{view}"
            );
            continue;
        }
        let (x, y) = axis_ticks(&t);
        assert!(x.len() >= 5, "{view}: x ticks {x:?}");
        assert!(y.len() >= 5, "{view}: y ticks {y:?}");
    }
}

#[test]
fn every_view_is_drawn_headless_as_a_png_too() {
    let dir = tempfile::tempdir().expect("temp dir");
    let session = small_session(dir.path());
    let session = session.to_str().expect("utf-8 path");
    for view in VIEWS {
        let out = dir.path().join(format!("{view}.png"));
        let o = figure(&[
            "--view",
            view,
            "--session",
            session,
            "--size",
            "320x240",
            "--out",
            out.to_str().expect("utf-8"),
        ]);
        assert!(
            o.status.success(),
            "{view}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let img = image::open(&out).expect("a PNG").to_rgb8();
        // Two pixels per point, and not blank: the view and its labels.
        assert_eq!(img.dimensions(), (640, 480), "{view}");
        let first = *img.get_pixel(0, 0);
        let differ = img.pixels().filter(|p| **p != first).count();
        assert!(differ > 640 * 480 / 50, "{view}: {differ} pixels drawn");
    }
}

/// The current parameters' lines (style::CURRENT, #009e73) are drawn in a
/// figure only when asked for, with the diagram's legend entry.
#[test]
fn the_current_parameters_are_marked_only_when_asked_for() {
    let dir = tempfile::tempdir().expect("temp dir");
    let session = small_session(dir.path());
    let session = session.to_str().expect("utf-8 path");
    for view in ["bifurcation", "phase"] {
        let draw = |name: &str, extra: &[&str]| {
            let out = dir.path().join(name);
            let mut args = vec!["--view", view, "--session", session];
            args.extend_from_slice(extra);
            args.extend_from_slice(&["--out", out.to_str().expect("utf-8")]);
            let o = figure(&args);
            assert!(
                o.status.success(),
                "{view}: {}",
                String::from_utf8_lossy(&o.stderr)
            );
            std::fs::read_to_string(&out).expect("svg written")
        };
        let plain = draw(&format!("{view}.svg"), &[]);
        let marked = draw(&format!("{view}-marked.svg"), &["--crosshair"]);
        let lines = |svg: &str| svg.matches("#009e73").count();
        assert_eq!(lines(&plain), 0, "{view}: a current line drawn unasked");
        assert!(
            lines(&marked) > 0,
            "{view}: no current line with --crosshair"
        );
        if view == "bifurcation" {
            let legend = |svg: &str| texts(svg).iter().any(|t| t.text == "current θν");
            assert!(
                !legend(&plain) && legend(&marked),
                "{view}: the legend entry"
            );
        }
    }
}

#[test]
fn the_diagram_spans_the_theta_nu_range_asked_for_and_a_png_is_made() {
    let dir = tempfile::tempdir().expect("temp dir");
    let session = small_session(dir.path());
    let svg = dir.path().join("fig3b.svg");
    let o = figure(&[
        "--view",
        "bifurcation",
        "--preset",
        "fig3b",
        "--session",
        session.to_str().expect("utf-8"),
        "--theta-nu-from",
        "1.0",
        "--theta-nu-to",
        "1.57",
        "--out",
        svg.to_str().expect("utf-8"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let t = texts(&std::fs::read_to_string(&svg).expect("svg"));
    let (x, _) = axis_ticks(&t);
    assert!(x.len() >= 5, "θν ticks {x:?}");
    let (lo, hi) = x
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(*v), b.max(*v)));
    // Ticks inside the range asked for, and spread over most of it.
    assert!(lo >= 1.0 - 1e-9 && hi <= 1.57 + 1e-9, "θν ticks {x:?}");
    assert!(lo <= 1.1 && hi >= 1.45, "θν ticks {x:?}");

    let png = dir.path().join("fig3b.png");
    let o = figure(&[
        "--view",
        "bifurcation",
        "--session",
        session.to_str().expect("utf-8"),
        "--size",
        "400x300",
        "--out",
        png.to_str().expect("utf-8"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(&png).expect("a PNG").to_rgb8();
    // Two pixels per point.
    assert_eq!(img.dimensions(), (800, 600));
    // Not blank: the diagram's points and the labels are drawn.
    let first = *img.get_pixel(0, 0);
    let differ = img.pixels().filter(|p| **p != first).count();
    assert!(differ > 800 * 600 / 50, "{differ} pixels drawn");
}

#[test]
fn an_extension_the_command_cannot_write_is_refused() {
    let dir = tempfile::tempdir().expect("temp dir");
    for (name, flag) in [("a.gif", "--out"), ("a.txt", "--out"), ("a", "--out")] {
        let out = dir.path().join(name);
        let o = figure(&[
            "--view",
            "plane",
            "--preset",
            "fig3b",
            "--out",
            out.to_str().expect("utf-8"),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{name}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{name}: {err}");
        assert!(err.contains(flag), "{name}: {err}");
        assert!(!out.exists(), "{name} written");
    }
}

#[test]
fn frames_and_a_gif_go_together_for_the_animated_views_only() {
    let dir = tempfile::tempdir().expect("temp dir");
    for (view, name, frames, flag) in [
        ("block", "a.png", Some("10"), "--frames"),
        ("plane", "a.svg", Some("10"), "--frames"),
        ("bifurcation", "a.gif", Some("10"), "--frames"),
        ("block", "a.gif", Some("1"), "--frames"),
        ("block", "a.gif", Some("601"), "--frames"),
        ("block", "a.gif", None, "--frames N"),
    ] {
        let out = dir.path().join(name);
        let mut args = vec!["--view", view, "--out", out.to_str().expect("utf-8")];
        if let Some(n) = frames {
            args.extend(["--frames", n]);
        }
        let o = figure(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{view} {name} {frames:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains(flag), "{err}");
        assert!(!out.exists());
    }
}

/// Pixels where two pictures differ by more than a palette's rounding
/// (each GIF learns its own palette).
fn pixels_apart(a: &[u8], b: &[u8]) -> usize {
    a.chunks(4)
        .zip(b.chunks(4))
        .filter(|(p, q)| p.iter().zip(q.iter()).any(|(x, y)| x.abs_diff(*y) > 40))
        .count()
}

/// Runs `figure` for an animation of `view` with `extra` flags into `name`.
fn animation(dir: &Path, view: &str, name: &str, extra: &[&str]) -> std::path::PathBuf {
    let session = small_session(dir);
    let out = dir.join(name);
    let mut args = vec![
        "--view",
        view,
        "--session",
        session.to_str().expect("utf-8"),
        "--size",
        "320x240",
        "--out",
        out.to_str().expect("utf-8"),
    ];
    args.extend(extra);
    let o = figure(&args);
    assert!(
        o.status.success(),
        "{view}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    out
}

#[test]
fn an_animated_gif_has_the_frames_asked_for_and_moves() {
    let dir = tempfile::tempdir().expect("temp dir");
    for view in ["block", "plane"] {
        let out = animation(
            dir.path(),
            view,
            &format!("{view}.gif"),
            &["--frames", "12"],
        );
        let (size, frames) = gif_frames(&out);
        assert_eq!(size, (320, 240), "{view}");
        assert!(frames.iter().all(|(d, _)| *d == 10), "10 frames a second");
        assert_eq!(frames.len(), 12, "{view}");
        // An animation: the first and the last frame differ.
        let differ = pixels_apart(&frames[0].1, &frames[11].1);
        assert!(differ > 50, "{view}: {differ} pixels changed");
    }
}

/// At half speed, frame 10 shows what frame 5 shows in real time (both
/// 0.5 s of playback in), and frame 5 shows less far.
#[test]
fn a_slowed_gif_shows_the_same_playback_later() {
    let dir = tempfile::tempdir().expect("temp dir");
    for view in ["block", "plane"] {
        let real = animation(
            dir.path(),
            view,
            &format!("{view}-1.gif"),
            &["--frames", "11"],
        );
        let half = animation(
            dir.path(),
            view,
            &format!("{view}-05.gif"),
            &["--frames", "11", "--speed", "0.5"],
        );
        let (_, real) = gif_frames(&real);
        let (_, half) = gif_frames(&half);
        // The same picture but for the two palettes' rounding (under 0.1 %
        // of the pixels), against a picture that moved.
        let same = pixels_apart(&real[5].1, &half[10].1);
        let ahead = pixels_apart(&real[5].1, &half[5].1);
        assert!(
            same < 320 * 240 / 1000 && ahead > 4 * same.max(8),
            "{view}: {same} pixels apart at 0.5 s of playback, {ahead} at 0.5 s and 0.25 s"
        );
    }
}

#[test]
fn the_return_map_is_drawn_as_its_distance_from_the_diagonal_on_request() {
    let dir = tempfile::tempdir().expect("temp dir");
    let session = small_session(dir.path());
    let out = dir.path().join("difference.svg");
    let o = figure(&[
        "--view",
        "return-map",
        "--map-difference",
        "--session",
        session.to_str().expect("utf-8"),
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let t = texts(&std::fs::read_to_string(&out).expect("svg"));
    assert!(
        t.iter()
            .any(|x| x.rotated && x.text.contains("f(θ) − θ, distance from the diagonal")),
        "the y axis is f(θ) − θ"
    );
    let (_, y) = axis_ticks(&t);
    // f − θ straddles 0 at the fixed point: ticks of both signs.
    assert!(
        y.len() >= 5 && y.iter().any(|v| *v < 0.0) && y.iter().any(|v| *v > 0.0),
        "{y:?}"
    );
    for (view, flags, flag) in [
        ("plane", vec!["--map-difference"], "--map-difference"),
        ("block", vec!["--frames", "10", "--speed", "2"], "--speed"),
        (
            "block",
            vec!["--frames", "10", "--speed", "0.01"],
            "--speed",
        ),
        ("block", vec!["--slip-speed", "20"], "--slip-speed"),
    ] {
        let out = dir.path().join(if flags.contains(&"--frames") {
            "x.gif"
        } else {
            "x.svg"
        });
        let mut args = vec!["--view", view, "--out", out.to_str().expect("utf-8")];
        args.extend(&flags);
        let o = figure(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{flags:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(
            err.contains(flag) && err.contains("must lie in") || flag == "--map-difference",
            "{err}"
        );
        assert!(!out.exists());
    }
}

/// κ = 10: near θν = 1.405 the fixed point's multiplier comes within 0.033
/// of 0 (Newton's cycle says so), so its λ = ln|m| dives under the λ
/// strip's floor (−3, padded): those columns are marked off the strip,
/// with a legend entry; over θν 1.30–1.36 (P2, λ > −1) nothing is.
#[test]
fn a_strongly_contracting_column_is_marked_below_the_lambda_strip() {
    use oneblock::model::Params;
    use oneblock::sim::{CycleOptions, Simulator, default_settings, solve_cycle};
    let at = |theta_nu: f64| {
        let p = Params {
            kappa: 10.0,
            gamma: 6.5,
            nu: 1e-3,
            theta_nu,
            omega: 50.0,
        };
        let sim = Simulator::new(p, default_settings(1e-10)).expect("sim");
        let opts = CycleOptions::for_settings(sim.settings());
        solve_cycle(&sim, 0.45, 1, &opts)
            .expect("fixed point")
            .multiplier
    };
    let m = at(1.405);
    assert!(m.abs().ln() < -3.3, "m = {m}");
    let dir = tempfile::tempdir().expect("temp dir");
    let below = |from: &str, to: &str| {
        let out = dir.path().join(format!("{from}-{to}.svg"));
        let range = format!("--theta-nu-from {from} --theta-nu-to {to}");
        let mut args: Vec<&str> = "--view bifurcation --kappa 10 --gamma 6.5 --nu 1e-3"
            .split(' ')
            .chain(range.split(' '))
            .collect();
        args.extend(["--out", out.to_str().expect("utf-8")]);
        let o = figure(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let svg = std::fs::read_to_string(&out).expect("svg written");
        svg.contains("λ &lt; -3.") && svg.contains(", below the strip</text>")
    };
    assert!(
        below("1.38", "1.43"),
        "no off-strip marker where the fixed point's |m| is 0.03"
    );
    assert!(
        !below("1.30", "1.36"),
        "an off-strip marker where every λ > −1"
    );
}

#[test]
fn a_diagram_in_another_parameter_spans_its_range_and_refuses_a_theta_nu_range() {
    let dir = tempfile::tempdir().expect("temp dir");
    let session = small_session(dir.path());
    let session = session.to_str().expect("utf-8");
    let run = |name: &str, extra: &[&str]| {
        let out = dir.path().join(name);
        let mut args = vec!["--session", session];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--out", out.to_str().expect("utf-8")]);
        (figure(&args), out)
    };
    let (o, svg) = run(
        "kappa.svg",
        &[
            "--view",
            "bifurcation",
            "--param",
            "kappa",
            "--from",
            "30",
            "--to",
            "10",
            "--theta-nu",
            "1.25",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let t = texts(&std::fs::read_to_string(&svg).expect("svg"));
    let (x, _) = axis_ticks(&t);
    // κ's log axis over [10, 30] (the ends in either order): its ticks lie
    // there and reach both ends' decade marks, not θν's [0, π/2].
    assert!(x.len() >= 3, "κ ticks {x:?}");
    assert!(
        x.iter().all(|v| (10.0 - 1e-9..=30.0 + 1e-9).contains(v)),
        "κ ticks {x:?}"
    );
    assert!(x.contains(&10.0) && x.contains(&20.0), "κ ticks {x:?}");
    assert!(
        t.iter().any(|t| t.rotated || t.text.contains('κ')),
        "an axis names κ"
    );

    // θν's range means nothing to a diagram in κ, nor --param to the
    // phase diagram: one line naming the flag.
    let diagram = ["--view", "bifurcation", "--param", "kappa"];
    for (name, extra) in [
        (
            "refused.svg",
            [
                &diagram[..],
                &["--theta-nu-from", "1", "--theta-nu-to", "1.5"],
            ]
            .concat(),
        ),
        (
            "zero.svg",
            [&diagram[..], &["--from", "0", "--to", "10"]].concat(),
        ),
        ("phase.svg", vec!["--view", "phase", "--param", "kappa"]),
    ] {
        let extra = &extra[..];
        let (o, out) = run(name, extra);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{extra:?}: {err}");
        let flag = extra
            .iter()
            .find(|a| a.starts_with("--") && *a != &"--view" && err.contains(*a));
        assert!(flag.is_some(), "{extra:?}: {err}");
        assert!(!out.exists(), "{extra:?} wrote {}", out.display());
    }
}
