//! Issue 57 item 6: every file `figure` writes is well-formed for every
//! value the help allows. Each case either is refused (exit 2, one line
//! naming the flag) or writes an SVG with no `inf` or `NaN` that an XML
//! parser reads to its end: a θ axis of ±1e50 (flags or a session's
//! zoom), a θν range to 1e308 or of one value, a session's kept special
//! point at ±1e308, titles with characters XML 1.0 does not allow, and
//! quotes and `<&>` in a title.
#![allow(clippy::unwrap_used)]

#[cfg(feature = "gui")]
use std::path::Path;

#[cfg(feature = "gui")]
use crate::cli_support::{oneblock, stderr};

/// Whether XML 1.0 allows `c` (tab, newline, CR, and from U+0020 on but
/// U+FFFE and U+FFFF; Rust strings hold no surrogates).
#[cfg(feature = "gui")]
fn xml_char(c: char) -> bool {
    matches!(c, '\t' | '\n' | '\r') || (c >= ' ' && c != '\u{FFFE}' && c != '\u{FFFF}')
}

/// Reads `svg` to its end with quick-xml (tags balanced, attributes and
/// references well-formed), every character one XML allows; the text of
/// its `<text>` elements, unescaped.
#[cfg(feature = "gui")]
fn parse(svg: &str) -> Vec<String> {
    use quick_xml::events::Event;
    if let Some(c) = svg.chars().find(|&c| !xml_char(c)) {
        panic!("U+{:04X} in the SVG", c as u32);
    }
    let mut reader = quick_xml::Reader::from_str(svg);
    let mut texts = Vec::new();
    let mut in_text = false;
    let mut depth = 0i64;
    loop {
        match reader.read_event() {
            Err(e) => panic!("not well-formed at {}: {e}", reader.buffer_position()),
            Ok(Event::Eof) => break,
            Ok(Event::Start(e)) => {
                depth += 1;
                for a in e.attributes() {
                    a.unwrap()
                        .normalized_value(quick_xml::XmlVersion::Implicit1_0)
                        .unwrap();
                }
                if e.name().as_ref() == b"text" {
                    in_text = true;
                    texts.push(String::new());
                }
            }
            Ok(Event::Empty(e)) => {
                for a in e.attributes() {
                    a.unwrap()
                        .normalized_value(quick_xml::XmlVersion::Implicit1_0)
                        .unwrap();
                }
            }
            Ok(Event::End(e)) => {
                depth -= 1;
                assert!(depth >= 0, "unbalanced");
                if e.name().as_ref() == b"text" {
                    in_text = false;
                }
            }
            Ok(Event::Text(t)) => {
                let s = t.decode().unwrap();
                if in_text {
                    texts.last_mut().unwrap().push_str(&s);
                }
            }
            Ok(Event::GeneralRef(r)) => {
                let name = r.decode().unwrap();
                let c = match name.as_ref() {
                    "amp" => "&",
                    "lt" => "<",
                    "gt" => ">",
                    "quot" => "\"",
                    "apos" => "'",
                    n => panic!("unknown reference &{n};"),
                };
                if in_text {
                    texts.last_mut().unwrap().push_str(c);
                }
            }
            Ok(_) => {}
        }
    }
    assert_eq!(depth, 0, "unclosed elements");
    texts
}

/// Runs `figure` with `args` and `--out dir/name`: refused with exit 2
/// and one line naming `flag`, or exit 0 with a file that, for an SVG, is
/// well-formed and holds no `inf` or `NaN` (its texts returned).
#[cfg(feature = "gui")]
fn refused_or_wellformed(dir: &Path, name: &str, args: &[&str], flag: &str) -> Option<Vec<String>> {
    let out = dir.join(name);
    let mut all = vec!["figure"];
    all.extend_from_slice(args);
    let out_s = out.to_str().unwrap().to_string();
    all.extend(["--out", &out_s]);
    let o = oneblock(&all);
    let err = stderr(&o);
    assert!(!err.contains("panicked"), "{all:?}: {err}");
    if o.status.code() == Some(2) {
        assert_eq!(err.trim_end().lines().count(), 1, "{all:?}: {err}");
        assert!(err.contains(flag), "{all:?} should name {flag}: {err}");
        assert!(!out.exists(), "{all:?}: refused, yet wrote a file");
        return None;
    }
    assert_eq!(o.status.code(), Some(0), "{all:?}: {err}");
    let bytes = std::fs::read(&out).unwrap();
    assert!(!bytes.is_empty(), "{all:?}: an empty file");
    if !name.ends_with(".svg") {
        return Some(Vec::new());
    }
    let svg = String::from_utf8(bytes).unwrap();
    assert!(
        !svg.contains("inf") && !svg.contains("NaN"),
        "{all:?}: inf or NaN in the SVG"
    );
    Some(parse(&svg))
}

#[cfg(feature = "gui")]
#[test]
fn a_theta_axis_of_1e50_is_refused_or_drawn() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "--view",
        "bifurcation",
        "--theta-from",
        "-1e50",
        "--theta-to",
        "1.3",
    ];
    for name in ["t.svg", "t.png", "t.pdf"] {
        refused_or_wellformed(dir.path(), name, &args, "--theta-from");
    }
    // The bound itself draws.
    let ok = [
        "--view",
        "bifurcation",
        "--theta-from",
        "-1000",
        "--theta-to",
        "1000",
    ];
    assert!(refused_or_wellformed(dir.path(), "ok.svg", &ok, "--theta-from").is_some());
}

#[cfg(feature = "gui")]
#[test]
fn a_session_zoom_of_1e50_draws_a_wellformed_file() {
    let dir = tempfile::tempdir().unwrap();
    let session = r#"{"oneblock_session": 1, "settings": {},
        "bifurcation_zoom": [{"theta_nu": [0.0, 1.5], "theta": [-1e50, 1.3]}]}"#;
    let path = dir.path().join("zoom.json");
    std::fs::write(&path, session).unwrap();
    let s = path.to_str().unwrap();
    for name in ["z.svg", "z.png"] {
        let args = ["--view", "bifurcation", "--session", s];
        refused_or_wellformed(dir.path(), name, &args, "--session");
    }
}

#[cfg(feature = "gui")]
#[test]
fn a_theta_nu_range_is_checked_as_its_own_flags() {
    let dir = tempfile::tempdir().unwrap();
    let base = ["--view", "bifurcation", "--param", "theta-nu"];
    for (from, to, flag) in [
        ("1", "1e308", "--to"),
        ("1", "1", "--from"),
        ("-4", "1", "--from"),
    ] {
        let mut args = base.to_vec();
        args.extend(["--from", from, "--to", to]);
        let got = refused_or_wellformed(dir.path(), &format!("r{from}_{to}.svg"), &args, flag);
        assert!(got.is_none(), "{from}..{to} should be refused");
    }
    // The same for another parameter: two equal ends are no range.
    let args = [
        "--view",
        "bifurcation",
        "--param",
        "kappa",
        "--from",
        "2",
        "--to",
        "2",
    ];
    assert!(refused_or_wellformed(dir.path(), "k.svg", &args, "--from").is_none());
}

/// A session keeping one θν branch whose special point sits at
/// (`lambda`, `theta`), its branch points ordinary.
#[cfg(feature = "gui")]
fn session_with_special(lambda: f64, theta: f64) -> String {
    let point = |l: f64, t: f64, m: f64| {
        format!(
            r#"{{"lambda": {l:e}, "points": [{t:e}], "multiplier": {m:e}, "stable": {}, "minimal_period": 1}}"#,
            m.abs() < 1.0
        )
    };
    let points = [
        point(1.0, 0.3, -0.5),
        point(1.1, 0.4, -1.0),
        point(1.2, 0.5, -1.4),
    ]
    .join(",");
    format!(
        r#"{{"oneblock_session": 1, "settings": {{}},
        "branches": {{"param": "ThetaNu", "range": [0.5, 1.5], "branches": [{{
            "param": "ThetaNu", "period": 1, "points": [{points}],
            "special": [{{"kind": "PeriodDoubling", "period": 1, "lambda": {lambda:e},
                "theta": {theta:e}, "multiplier": -1.0, "note": "", "flip": null}}],
            "stop": "Reached", "map_evals": 40}}]}}}}"#
    )
}

#[cfg(feature = "gui")]
#[test]
fn kept_points_at_1e308_are_left_out() {
    let dir = tempfile::tempdir().unwrap();
    for (i, (l, t)) in [(1e308, 0.4), (1.1, -1e308), (-1e308, 1e308)]
        .into_iter()
        .enumerate()
    {
        let path = dir.path().join(format!("kept{i}.json"));
        std::fs::write(&path, session_with_special(l, t)).unwrap();
        let s = path.to_str().unwrap();
        let args = ["--view", "bifurcation", "--session", s, "--branches"];
        let out = dir.path().join(format!("kept{i}.svg"));
        let o = oneblock(&[
            "figure",
            args[0],
            args[1],
            args[2],
            args[3],
            args[4],
            "--out",
            out.to_str().unwrap(),
        ]);
        let err = stderr(&o);
        // The branch was read, not set aside (else the case proves nothing).
        assert!(!err.contains("branches ("), "{err}");
        assert_eq!(o.status.code(), Some(0), "{err}");
        let svg = std::fs::read_to_string(&out).unwrap();
        assert!(
            !svg.contains("inf") && !svg.contains("NaN"),
            "kept point {l}, {t}: inf or NaN"
        );
        parse(&svg);
    }
}

#[cfg(feature = "gui")]
#[test]
fn titles_xml_does_not_allow_are_refused_and_quotes_escaped() {
    let dir = tempfile::tempdir().unwrap();
    for (i, t) in ["\u{FFFF}", "\u{FFFE}", "a\u{1}b", "x\u{1F}", "\u{B}z"]
        .into_iter()
        .enumerate()
    {
        let args = ["--view", "bifurcation", "--title", t];
        refused_or_wellformed(dir.path(), &format!("bad{i}.svg"), &args, "--title");
    }
    let title = r#"a "quoted" <b> & 'c'"#;
    let args = ["--view", "bifurcation", "--title", title];
    let texts = refused_or_wellformed(dir.path(), "q.svg", &args, "--title").unwrap();
    assert!(
        texts.iter().any(|t| t == title),
        "the title whole in one text: {texts:?}"
    );
}
