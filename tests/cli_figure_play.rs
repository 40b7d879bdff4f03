//! `oneblock figure --play`: a GIF of θν played, through the command the
//! user runs. It has the frames asked for, 10 a second; every frame
//! differs from the one before; the return map's fixed point (its orbit
//! marker, the map's axes held over the play) moves up the diagonal as θν
//! grows; the diagram's θν cursor moves right frame by frame and nothing
//! else of the diagram changes; a played return map whose legend gains and
//! loses entries over the play (basins, the invariant density) keeps its
//! axes and its legend still in every frame; bad flags are refused in one
//! line.
#![cfg(feature = "gui")]

use std::path::{Path, PathBuf};

use crate::common::figure::{figure, gif_frames, small_session};

/// The pixels (x, y) where two pictures of width `w` differ.
fn differing(a: &[u8], b: &[u8], w: usize) -> Vec<(usize, usize)> {
    a.chunks(4)
        .zip(b.chunks(4))
        .enumerate()
        .filter(|(_, (p, q))| p.iter().zip(q.iter()).any(|(x, y)| x.abs_diff(*y) > 40))
        .map(|(i, _)| (i % w, i / w))
        .collect()
}

/// A played GIF of `view` over θν [from, to], `frames` frames of `size`.
fn played(dir: &Path, view: &str, (from, to): (&str, &str), frames: &str, size: &str) -> PathBuf {
    let session = small_session(dir);
    let out = dir.join(format!("{view}.gif"));
    let o = figure(&[
        "--view",
        view,
        "--session",
        session.to_str().expect("utf-8"),
        "--play",
        "--frames",
        frames,
        "--theta-nu-from",
        from,
        "--theta-nu-to",
        to,
        "--size",
        size,
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert!(
        o.status.success(),
        "{view}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    out
}

/// The centre of the return map's orbit marker: the dark ink pixels
/// (the orbit's iterates are drawn in the text's ink, filled circles)
/// inside the plot's interior, away from tick labels and the legend.
fn marker_centre(px: &[u8], (w, h): (usize, usize)) -> Option<(f64, f64)> {
    let (mut n, mut sx, mut sy) = (0.0, 0.0, 0.0);
    for y in h / 5..h * 17 / 20 {
        for x in w / 5..w * 19 / 20 {
            let p = &px[(y * w + x) * 4..(y * w + x) * 4 + 3];
            if p.iter().all(|&c| c < 60) {
                n += 1.0;
                sx += x as f64;
                sy += y as f64;
            }
        }
    }
    (n > 0.0).then(|| (sx / n, sy / n))
}

#[test]
fn a_played_return_map_has_its_frames_and_its_fixed_point_moves_up_the_diagonal() {
    let dir = tempfile::tempdir().expect("temp dir");
    // Fig. 3b below its first doubling: one fixed point all along.
    let out = played(dir.path(), "return-map", ("0.5", "0.9"), "6", "360x360");
    let (size, frames) = gif_frames(&out);
    assert_eq!(size, (360, 360));
    assert_eq!(frames.len(), 6, "the frames asked for");
    assert!(frames.iter().all(|(d, _)| *d == 10), "10 frames a second");
    for k in 1..frames.len() {
        let d = differing(&frames[k - 1].1, &frames[k].1, size.0);
        assert!(d.len() > 20, "frame {k} is frame {}'s picture", k - 1);
    }
    let centres: Vec<(f64, f64)> = frames
        .iter()
        .map(|(_, px)| marker_centre(px, size).expect("the orbit's marker"))
        .collect();
    // θν grows, the fixed point θ* with it: right and up (the screen's y
    // down) by the same amount, the axes' aspect being 1.
    for w in centres.windows(2) {
        let (dx, dy) = (w[1].0 - w[0].0, w[0].1 - w[1].1);
        assert!(
            dx > 1.0 && dy > 1.0,
            "the fixed point did not move up the diagonal: {centres:?}"
        );
        assert!(
            (dx - dy).abs() < 0.25 * dx.max(dy) + 1.0,
            "off the diagonal: {centres:?}"
        );
    }
}

/// Issue 57 item 5: a return map played over Fig. 3b's chaos (θν 1.15 to
/// 1.3: period 2, chaos with its invariant density, period 3) once moved
/// its axes when the density's legend entry wrapped the legend onto a
/// second row, and listed "basin: chaotic" in frames without its band.
/// The legend and the plot's bounds are now the union over the play: the
/// y axis's labels and title (the picture's left fourteenth below the
/// summary line) and the legend (the rows between the summary line and
/// the plot's top grid line) are
/// the same pixels in every frame; only the summary's numbers and the
/// plot's inside change.
#[test]
fn a_played_return_map_holds_its_axes_and_legend_over_the_play() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("chaos.gif");
    let o = figure(&[
        "--view",
        "return-map",
        "--preset",
        "chaos",
        "--play",
        "--frames",
        "8",
        "--theta-nu-from",
        "1.15",
        "--theta-nu-to",
        "1.3",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let ((w, h), frames) = gif_frames(&out);
    assert_eq!(frames.len(), 8);
    let first = &frames[0].1;
    let ink = |px: &[u8], x: usize, y: usize| {
        px[(y * w + x) * 4..(y * w + x) * 4 + 3]
            .iter()
            .any(|&c| c < 235)
    };
    // The plot's top: the first row below the summary line that a grid
    // line crosses (ink over most of the plot's width).
    let top = (h / 16..h / 2)
        .find(|&y| (w / 6..w * 9 / 10).filter(|&x| ink(first, x, y)).count() > w / 2)
        .expect("the plot's top grid line");
    let mut differ = 0;
    for (k, (_, px)) in frames.iter().enumerate().skip(1) {
        let d = differing(first, px, w);
        differ += d.len();
        let moved: Vec<&(usize, usize)> = d
            .iter()
            .filter(|&&(x, y)| y >= h / 16 && (x < w / 14 || y < top))
            .collect();
        assert!(
            moved.is_empty(),
            "frame {k}: {} pixels of the axes' labels or the legend differ from frame 0's \
             (first {:?}; the plot's top at {top})",
            moved.len(),
            moved.first()
        );
    }
    assert!(differ > 1000, "the frames are alike: nothing played");
}

#[test]
fn a_played_diagram_moves_its_cursor_and_nothing_else() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = played(dir.path(), "bifurcation", ("0.6", "1.4"), "5", "480x320");
    let (size, frames) = gif_frames(&out);
    assert_eq!(frames.len(), 5);
    let mut last_x = 0.0;
    for k in 1..frames.len() {
        let d = differing(&frames[k - 1].1, &frames[k].1, size.0);
        assert!(d.len() > 20, "frame {k}: the cursor did not move");
        // The old line and the new one: two thin columns, a fifth of the
        // plot apart; the diagram itself the same.
        let mut xs: Vec<usize> = d.iter().map(|p| p.0).collect();
        xs.sort_unstable();
        xs.dedup();
        assert!(xs.len() <= 16, "frame {k}: {} columns changed", xs.len());
        let newest = *xs.last().expect("columns") as f64;
        assert!(newest > last_x, "frame {k}: the cursor did not move right");
        last_x = newest;
    }
}

#[test]
fn a_played_plane_follows_theta_nu() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = played(dir.path(), "plane", ("0.8", "1.2"), "4", "320x240");
    let (size, frames) = gif_frames(&out);
    assert_eq!((size, frames.len()), ((320, 240), 4));
    for k in 1..frames.len() {
        let d = differing(&frames[k - 1].1, &frames[k].1, size.0);
        assert!(d.len() > 50, "frame {k}: the path did not change");
    }
}

#[test]
fn play_flags_are_checked_in_one_line() {
    let dir = tempfile::tempdir().expect("temp dir");
    let gif = dir.path().join("p.gif");
    let png = dir.path().join("p.png");
    let (gif, png) = (gif.to_str().expect("utf-8"), png.to_str().expect("utf-8"));
    for (args, flag) in [
        (
            vec!["--view", "return-map", "--play", "--out", png],
            "--play",
        ),
        (
            vec!["--view", "return-map", "--play", "--out", gif],
            "--frames",
        ),
        (
            vec!["--view", "phase", "--play", "--frames", "5", "--out", gif],
            "--play",
        ),
        (
            vec![
                "--view", "block", "--play", "--frames", "5", "--speed", "0.5", "--out", gif,
            ],
            "--speed",
        ),
        (
            vec![
                "--view",
                "return-map",
                "--play",
                "--frames",
                "601",
                "--out",
                gif,
            ],
            "[2, 600]",
        ),
        (
            vec![
                "--view",
                "return-map",
                "--play",
                "--frames",
                "5",
                "--theta-nu-from",
                "1",
                "--theta-nu-to",
                "4",
                "--out",
                gif,
            ],
            "[-pi, pi]",
        ),
    ] {
        let o = figure(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains(flag), "{args:?}: {err}");
        assert!(!Path::new(gif).exists() && !Path::new(png).exists());
    }
}
