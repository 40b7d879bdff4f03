//! `oneblock figure` as a journal takes it: by default a white picture
//! with no frame and no view name (`--title` adds one), `--font-size`
//! setting every text's size, legend keys that are the plotted markers
//! (shape, fill, colour), and `--out x.pdf` a vector PDF whose text is
//! text: glyphs of an embedded font, read back as the labels' words
//! through the font's ToUnicode map.
#![cfg(feature = "gui")]

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::common::figure::small_session;

/// Runs `oneblock figure ARGS --session small --out DIR/NAME`, which must
/// succeed; returns the file's path.
fn figure(dir: &Path, name: &str, args: &[&str]) -> PathBuf {
    let out = dir.join(name);
    let session = small_session(dir);
    let o: Output = Command::new(env!("CARGO_BIN_EXE_oneblock"))
        .arg("figure")
        .args(args)
        .args(["--session", session.to_str().expect("utf-8")])
        .args(["--out", out.to_str().expect("utf-8")])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("run oneblock figure");
    assert!(
        o.status.success(),
        "figure {args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    out
}

/// One element of the SVG, in document order: its tag, attributes and
/// (for `<text>`) its string.
#[derive(Debug, Clone)]
struct Element {
    tag: String,
    attrs: HashMap<String, String>,
    text: String,
}

impl Element {
    fn attr(&self, k: &str) -> &str {
        self.attrs.get(k).map_or("", String::as_str)
    }

    /// What a marker looks like, whatever its place and size: its tag,
    /// number of corners (a path), fill and stroke colours and opacities.
    fn look(&self) -> String {
        let corners = self.attr("d").matches(['M', 'L']).count();
        format!(
            "{} {corners} fill={} {} stroke={} {}",
            self.tag,
            self.attr("fill"),
            self.attr("fill-opacity"),
            self.attr("stroke"),
            self.attr("stroke-opacity")
        )
    }
}

/// Every element of `svg` (parsing it: a malformed SVG fails).
fn elements(svg: &str) -> Vec<Element> {
    use quick_xml::events::Event;
    let mut r = quick_xml::Reader::from_str(svg);
    let mut out: Vec<Element> = Vec::new();
    let mut open_text: Option<usize> = None;
    loop {
        let (e, start) = match r.read_event().expect("the SVG parses") {
            Event::Start(e) => (e, true),
            Event::Empty(e) => (e, false),
            Event::Text(t) => {
                if let Some(i) = open_text {
                    out[i].text.push_str(&t.decode().expect("utf-8"));
                }
                continue;
            }
            Event::End(e) => {
                if e.name().as_ref() == b"text" {
                    open_text = None;
                }
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        let attrs = e
            .attributes()
            .flatten()
            .map(|a| {
                (
                    String::from_utf8_lossy(a.key.as_ref()).into_owned(),
                    String::from_utf8_lossy(&a.value).into_owned(),
                )
            })
            .collect();
        let tag = String::from_utf8_lossy(e.name().as_ref()).into_owned();
        if start && tag == "text" {
            open_text = Some(out.len());
        }
        out.push(Element {
            tag,
            attrs,
            text: String::new(),
        });
    }
    out
}

/// The `<text>` elements' strings.
fn words(els: &[Element]) -> Vec<&str> {
    els.iter()
        .filter(|e| e.tag == "text")
        .map(|e| e.text.as_str())
        .collect()
}

#[test]
fn a_figure_is_white_without_a_frame_or_title_unless_one_is_asked_for() {
    let dir = tempfile::tempdir().expect("temp dir");
    for view in ["bifurcation", "return-map"] {
        let out = figure(dir.path(), &format!("{view}.svg"), &["--view", view]);
        let els = elements(&std::fs::read_to_string(out).expect("svg"));
        let background = els
            .iter()
            .find(|e| e.tag == "rect" && e.attr("width") == "100%")
            .expect("a background");
        assert_eq!(background.attr("fill"), "#ffffff", "{view}");
        // No frame: no outlined rectangle around (nearly) the whole picture.
        let framed = els.iter().filter(|e| e.tag == "rect").any(|e| {
            let w: f64 = e.attr("width").parse().unwrap_or(0.0);
            let stroke = e.attr("stroke");
            w > 800.0 && !stroke.is_empty() && stroke != "none"
        });
        assert!(!framed, "{view}: a frame is drawn");
        let t = words(&els);
        for title in ["Bifurcation", "Return map"] {
            assert!(!t.contains(&title), "{view}: the title '{title}' is drawn");
        }
    }
    let out = figure(
        dir.path(),
        "titled.svg",
        &["--view", "bifurcation", "--title", "Fig. 3b: kappa = 10"],
    );
    let els = elements(&std::fs::read_to_string(out).expect("svg"));
    let texts: Vec<&Element> = els.iter().filter(|e| e.tag == "text").collect();
    let title = texts
        .iter()
        .find(|e| e.text == "Fig. 3b: kappa = 10")
        .expect("the title is drawn");
    let y = |e: &Element| e.attr("y").parse::<f64>().expect("a y");
    assert!(
        texts.iter().all(|e| y(e) >= y(title)),
        "the title is above every other text"
    );
}

#[test]
fn font_size_sets_every_text_of_the_figure() {
    let dir = tempfile::tempdir().expect("temp dir");
    for view in ["bifurcation", "time-series"] {
        let out = figure(
            dir.path(),
            &format!("{view}.svg"),
            &["--view", view, "--font-size", "16", "--title", "T"],
        );
        let els = elements(&std::fs::read_to_string(out).expect("svg"));
        let sizes: Vec<&str> = els
            .iter()
            .filter(|e| e.tag == "text")
            .map(|e| e.attr("font-size"))
            .collect();
        assert!(sizes.len() > 10, "{view}: {} texts", sizes.len());
        assert!(
            sizes.iter().all(|s| *s == "16.0"),
            "{view}: sizes {sizes:?}"
        );
    }
    let o = Command::new(env!("CARGO_BIN_EXE_oneblock"))
        .args([
            "figure",
            "--view",
            "phase",
            "--out",
            "x.svg",
            "--font-size",
            "100",
        ])
        .output()
        .expect("run");
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("--font-size = 100") && err.contains("[4, 72]") && err.lines().count() == 1,
        "{err}"
    );
}

/// The legend's key of `label`: the last shape drawn before the label's
/// text, outside every plot (no series class).
fn key_of<'a>(els: &'a [Element], label: &str) -> &'a Element {
    let at = els
        .iter()
        .position(|e| e.tag == "text" && e.text == label)
        .unwrap_or_else(|| panic!("the legend entry '{label}'"));
    els[..at]
        .iter()
        .rev()
        .find(|e| matches!(e.tag.as_str(), "circle" | "path") && e.attr("class") != "series")
        .unwrap_or_else(|| panic!("a key before '{label}'"))
}

/// The looks of the markers (circles and closed paths) plotted in `plot`.
fn plotted(els: &[Element], plot: &str) -> Vec<String> {
    els.iter()
        .filter(|e| e.attr("class") == "series" && e.attr("data-series").starts_with(plot))
        .filter(|e| e.tag == "circle" || e.attr("d").ends_with('Z'))
        .map(Element::look)
        .collect()
}

#[test]
fn legend_keys_are_the_markers_plotted() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = figure(dir.path(), "b.svg", &["--view", "bifurcation"]);
    let els = elements(&std::fs::read_to_string(out).expect("svg"));
    let strip = plotted(&els, "lyapunov:");
    // A solved cycle's filled dot, an aperiodic column's ring (Fig. 3b's
    // diagram has both).
    for label in ["λ = ln|m|/p (solved cycle)", "λ = mean ln|f'| ± 1 s.e."] {
        let key = key_of(&els, label).look();
        assert!(
            strip.contains(&key),
            "'{label}': key {key}, plotted {strip:?}"
        );
    }
    let solved = key_of(&els, "λ = ln|m|/p (solved cycle)");
    let ring = key_of(&els, "λ = mean ln|f'| ± 1 s.e.");
    assert_eq!(
        (solved.tag.as_str(), ring.tag.as_str()),
        ("circle", "circle")
    );
    assert_eq!(ring.attr("fill"), "none", "the ring's key is a ring");
    assert_ne!(solved.attr("fill"), "none", "the dot's key is filled");

    let out = figure(dir.path(), "r.svg", &["--view", "return-map"]);
    let els = elements(&std::fs::read_to_string(out).expect("svg"));
    let map: Vec<String> = els
        .iter()
        .filter(|e| e.attr("class") == "series" && e.tag == "circle")
        .map(Element::look)
        .collect();
    for label in ["orbit iterates", "cycles incl. transient"] {
        let key = key_of(&els, label).look();
        assert!(map.contains(&key), "'{label}': key {key}, plotted {map:?}");
    }
}

/// A PDF's objects by number: (dictionary text, inflated stream if any).
fn pdf_objects(pdf: &[u8]) -> HashMap<u32, (String, Vec<u8>)> {
    let mut out = HashMap::new();
    let find = |hay: &[u8], needle: &[u8], from: usize| {
        hay[from..]
            .windows(needle.len())
            .position(|w| w == needle)
            .map(|p| p + from)
    };
    let mut at = 0;
    while let Some(o) = find(pdf, b" 0 obj", at) {
        let start = pdf[..o]
            .iter()
            .rposition(|b| !b.is_ascii_digit())
            .map_or(0, |p| p + 1);
        let num: u32 = std::str::from_utf8(&pdf[start..o])
            .ok()
            .and_then(|n| n.parse().ok())
            .expect("an object number");
        let end = find(pdf, b"endobj", o).expect("endobj");
        let body = &pdf[o + 6..end];
        let (dict, data) = match find(body, b"stream\n", 0) {
            Some(s) => {
                let e = find(body, b"\nendstream", s).expect("endstream");
                (&body[..s], body[s + 7..e].to_vec())
            }
            None => (body, Vec::new()),
        };
        let dict = String::from_utf8_lossy(dict).into_owned();
        let data = if dict.contains("/FlateDecode") {
            miniz_oxide::inflate::decompress_to_vec_zlib(&data).expect("a zlib stream")
        } else {
            data
        };
        out.insert(num, (dict, data));
        at = end;
    }
    out
}

/// The number `N` of the reference `KEY N 0 R` in `dict`.
fn reference(dict: &str, key: &str) -> Option<u32> {
    let rest = &dict[dict.find(key)? + key.len()..];
    rest.split_whitespace().next()?.parse().ok()
}

/// A ToUnicode CMap's glyph → text pairs (`<cid> <utf16>` lines).
fn cmap(data: &[u8]) -> HashMap<u16, String> {
    let text = String::from_utf8_lossy(data);
    let mut map = HashMap::new();
    for line in text.lines() {
        let hex: Vec<&str> = line
            .split(['<', '>'])
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .collect();
        if let [cid, uni] = hex[..]
            && let Ok(cid) = u16::from_str_radix(cid, 16)
        {
            let units: Vec<u16> = (0..uni.len() / 4)
                .filter_map(|i| u16::from_str_radix(&uni[4 * i..4 * i + 4], 16).ok())
                .collect();
            map.insert(cid, String::from_utf16_lossy(&units));
        }
    }
    map
}

/// The bytes of a PDF string token at the start of `s` (literal `(...)`
/// with its escapes, or hex `<...>`), and the rest of `s`.
fn pdf_string(s: &[u8]) -> (Vec<u8>, &[u8]) {
    let mut out = Vec::new();
    if s[0] == b'<' {
        let end = s.iter().position(|&b| b == b'>').expect("a hex string");
        let hex = String::from_utf8_lossy(&s[1..end]).replace(char::is_whitespace, "");
        for i in (0..hex.len()).step_by(2) {
            out.push(u8::from_str_radix(&hex[i..i + 2], 16).expect("hex"));
        }
        return (out, &s[end + 1..]);
    }
    let mut i = 1;
    while s[i] != b')' {
        if s[i] == b'\\' {
            i += 1;
            let digits = s[i..]
                .iter()
                .take(3)
                .take_while(|b| b.is_ascii_digit())
                .count();
            if digits > 0 {
                let oct = String::from_utf8_lossy(&s[i..i + digits]).into_owned();
                out.push(u8::from_str_radix(&oct, 8).expect("octal"));
                i += digits;
                continue;
            }
            out.push(match s[i] {
                b'n' => b'\n',
                b'r' => b'\r',
                b't' => b'\t',
                b'b' => 8,
                b'f' => 12,
                c => c,
            });
        } else {
            out.push(s[i]);
        }
        i += 1;
    }
    (out, &s[i + 1..])
}

/// The text a PDF page shows: each content stream's glyphs, through the
/// ToUnicode map of the font each was set in, and the font sizes used.
fn pdf_text(pdf: &[u8]) -> (String, Vec<f64>) {
    let objs = pdf_objects(pdf);
    // Font resource name → that font's glyph → text map.
    let mut fonts: HashMap<String, HashMap<u16, String>> = HashMap::new();
    let mut contents = Vec::new();
    let mut numbers: Vec<&u32> = objs.keys().collect();
    numbers.sort();
    for n in numbers {
        let dict = &objs[n].0;
        // The page's content, and the groups drawn as form XObjects.
        if let Some(c) = reference(dict, "/Contents") {
            contents.push(c);
        }
        if dict.contains("/Subtype /Form") {
            contents.push(*n);
        }
        let Some(i) = dict.find("/Font <<") else {
            continue;
        };
        let list = &dict[i + 8..i + 8 + dict[i + 8..].find(">>").expect(">>")];
        let toks: Vec<&str> = list.split_whitespace().collect();
        for w in toks.windows(4) {
            if let (Some(name), Ok(num), "0", "R") =
                (w[0].strip_prefix('/'), w[1].parse::<u32>(), w[2], w[3])
            {
                let map = reference(&objs[&num].0, "/ToUnicode")
                    .map(|u| cmap(&objs[&u].1))
                    .expect("every font has a ToUnicode map");
                fonts.insert(name.to_string(), map);
            }
        }
    }
    assert!(!fonts.is_empty(), "the page has fonts");
    let (mut text, mut sizes, mut font) = (String::new(), Vec::new(), String::new());
    for c in contents {
        let mut s: &[u8] = &objs[&c].1;
        let mut last: Vec<String> = Vec::new();
        while !s.is_empty() {
            if s[0] == b'(' || s[0] == b'<' && s.get(1) != Some(&b'<') {
                let (bytes, rest) = pdf_string(s);
                for cid in bytes.chunks(2).filter(|c| c.len() == 2) {
                    let cid = u16::from_be_bytes([cid[0], cid[1]]);
                    text.push_str(fonts[&font].get(&cid).map_or("\u{fffd}", String::as_str));
                }
                s = rest;
                continue;
            }
            let n = s
                .iter()
                .position(u8::is_ascii_whitespace)
                .unwrap_or(s.len());
            let tok = String::from_utf8_lossy(&s[..n]).into_owned();
            if tok == "Tf" && last.len() >= 2 {
                font = last[last.len() - 2].trim_start_matches('/').to_string();
                sizes.push(last[last.len() - 1].parse().expect("a font size"));
            }
            if tok == "ET" {
                // Each glyph is its own text object; a gap between them
                // is not known here, so words run together.
            }
            if !tok.is_empty() {
                last.push(tok);
            }
            s = &s[n.max(1).min(s.len())..];
        }
    }
    (text, sizes)
}

#[test]
fn a_pdf_figure_is_vector_with_its_text_as_text() {
    let dir = tempfile::tempdir().expect("temp dir");
    let pdf_path = figure(
        dir.path(),
        "b.pdf",
        &[
            "--view",
            "bifurcation",
            "--font-size",
            "11",
            "--size",
            "700x500",
        ],
    );
    let pdf = std::fs::read(&pdf_path).expect("pdf");
    assert!(pdf.starts_with(b"%PDF-"), "a PDF");
    let objs = pdf_objects(&pdf);
    // One page of the figure's size in points.
    assert!(
        objs.values()
            .any(|(d, _)| d.contains("/MediaBox [0 0 700 500]")),
        "a 700x500 pt page"
    );
    // The font program is in the file (no font needed on the reader's side).
    assert!(
        objs.values().any(|(d, _)| d.contains("/FontFile2")),
        "an embedded TrueType font"
    );
    let (text, sizes) = pdf_text(&pdf);
    let squeezed: String = text.chars().filter(|c| !c.is_whitespace()).collect();
    for word in [
        // "λ, Lyapunov exponent", or "Lyapunov λ" where the strip is short.
        "Lyapunov",
        "θν,pulldirection(rad)",
        "θ,sliponset(rad)",
    ] {
        assert!(
            squeezed.contains(word),
            "'{word}' in the PDF's text: {squeezed}"
        );
    }
    assert!(!text.contains('\u{fffd}'), "every glyph maps to text");
    assert!(
        !sizes.is_empty() && sizes.iter().all(|s| (*s - 11.0).abs() < 1e-6),
        "the text is set at 11 pt: {sizes:?}"
    );
    // The same drawing as the SVG: its lines (axes, ticks, grid, λ's
    // error bars) as path segments, the diagram's points as vector dots
    // (issue 57), not an image.
    let ops: usize = objs
        .values()
        .map(|(_, d)| String::from_utf8_lossy(d).matches(" l\n").count())
        .sum();
    assert!(ops > 50, "{ops} line segments");
    assert!(
        !objs.values().any(|(d, _)| d.contains("/Subtype /Image")),
        "the diagram's points as an image"
    );
}

#[test]
fn branches_are_drawn_over_the_diagram_as_find_bifurcations_draws_them() {
    let dir = tempfile::tempdir().expect("temp dir");
    let range = ["--theta-nu-from", "1.0", "--theta-nu-to", "1.3"];
    let plain = figure(
        dir.path(),
        "plain.svg",
        &[&["--view", "bifurcation"][..], &range].concat(),
    );
    let drawn = figure(
        dir.path(),
        "branches.svg",
        &[&["--view", "bifurcation", "--branches"][..], &range].concat(),
    );
    let plain = elements(&std::fs::read_to_string(plain).expect("svg"));
    let els = elements(&std::fs::read_to_string(drawn).expect("svg"));
    // The branches' blue (0, 114, 178), as a series of the diagram.
    let branch = |els: &[Element]| {
        els.iter()
            .filter(|e| e.attr("data-series") == "bifurcation:035" && e.tag == "path")
            .filter(|e| e.attr("d").matches('L').count() > 2)
            .count()
    };
    assert_eq!(branch(&plain), 0, "no branch without --branches");
    assert!(branch(&els) > 0, "branch paths are drawn");
    let t = words(&els);
    for label in ["stable branch", "unstable branch", "PD"] {
        assert!(t.contains(&label), "the legend's '{label}'");
        assert!(
            !words(&plain).contains(&label),
            "'{label}' without --branches"
        );
    }
    // Fig. 3b's P1 doubles at θν ≈ 1.09 and its P2 near 1.2: PD diamonds
    // drawn, and the legend's key is that diamond.
    let pd = key_of(&els, "PD").look();
    let marked = plotted(&els, "bifurcation:");
    assert!(marked.contains(&pd), "PD key {pd}, plotted {marked:?}");
    assert!(pd.starts_with("path 4 "), "a diamond: {pd}");
}

#[test]
fn boundaries_and_seeds_are_drawn_only_on_their_views() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = figure(
        dir.path(),
        "phase.svg",
        &[
            "--view",
            "phase",
            "--preset",
            "fig4",
            "--boundaries",
            "--kappa-from",
            "10",
            "--kappa-to",
            "22",
            "--theta-nu-from",
            "0.1",
            "--theta-nu-to",
            "1.55",
            "--theta-nu-steps",
            "8",
            "--kappa-steps",
            "6",
        ],
    );
    let els = elements(&std::fs::read_to_string(out).expect("svg"));
    // The doubling curves in white (the window's Boundaries), as series
    // of the phase plot, with their legend entry.
    let curves = els
        .iter()
        .filter(|e| e.attr("data-series") == "phase:777" && e.tag == "path")
        .count();
    assert!(curves > 0, "doubling curves are drawn");
    // Fig. 4's box holds the doublings FP to P2 and P2 to P4, each with
    // an entry of its own.
    assert!(words(&els).contains(&"FP to P2"), "{:?}", words(&els));
    assert!(words(&els).contains(&"P2 to P4"), "{:?}", words(&els));

    let seeded = figure(
        dir.path(),
        "seeded.svg",
        &[
            "--view",
            "bifurcation",
            "--kappa",
            "10",
            "--gamma",
            "6.5",
            "--nu",
            "1e-3",
            "--theta-nu",
            "1.4",
            "--theta-nu-from",
            "1.33",
            "--theta-nu-to",
            "1.45",
            "--seeds",
            "4",
        ],
    );
    let t = std::fs::read_to_string(seeded).expect("svg");
    let els = elements(&t);
    assert!(
        words(&els).contains(&"other attractors"),
        "the seeded diagram's legend"
    );
    // The diagram's points, vector dots, hold the other attractor (κ = 10's
    // small P2 beside the large one over 1.364-1.420) in its colour
    // (204, 0, 102).
    let other = els
        .iter()
        .filter(|e| e.tag == "path" && e.attr("data-series") == "bifurcation:points")
        .find(|e| e.attr("stroke") == "#cc0066")
        .expect("the other attractor's dots");
    let n: usize = other.attr("data-points").parse().expect("a count");
    assert!(n > 0, "the other attractor's points are drawn");
    for (flag, view) in [
        ("--branches", "phase"),
        ("--boundaries", "bifurcation"),
        ("--seeds", "plane"),
    ] {
        let mut args = vec!["figure", "--view", view, "--out", "never.svg", flag];
        if flag == "--seeds" {
            args.push("2");
        }
        let o = Command::new(env!("CARGO_BIN_EXE_oneblock"))
            .args(&args)
            .output()
            .expect("run");
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(flag) && err.lines().count() == 1, "{err}");
    }
}
