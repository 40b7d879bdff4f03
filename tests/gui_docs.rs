//! docs/gui.md's table of Auto's settings is the code's: each job's row
//! names the accuracy its view needs (`JobKind::accuracy`) and the setting,
//! max map error, evaluations and µs per iterate that the side panel shows
//! (the budget's choice read off the committed chart). On a mismatch the
//! test prints the table as it should read.
#![cfg(feature = "gui")]

use oneblock::app::Settings;
use oneblock::app::accuracy::job_estimates;

/// The rows of the markdown table whose header starts with `header`, as
/// trimmed cells.
fn table(md: &str, header: &str) -> Vec<Vec<String>> {
    md.lines()
        .skip_while(|l| !l.starts_with(header))
        .skip(2)
        .take_while(|l| l.starts_with('|'))
        .map(|l| {
            l.trim_matches('|')
                .split('|')
                .map(|c| c.trim().to_string())
                .collect()
        })
        .collect()
}

#[test]
fn the_auto_table_in_docs_gui_md_is_what_the_code_runs() {
    let md = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/gui.md"))
        .expect("docs/gui.md");
    let rows = table(&md, "| job | feeds | needs | runs |");
    let want: Vec<[String; 6]> = job_estimates(&Settings::default())
        .iter()
        .map(|e| {
            // "dop853 tol 1e-10 · err ≤ 2.8e-11 · 1442 evals · 73 µs"
            let text = e.text();
            let parts: Vec<&str> = text.split(" · ").collect();
            assert_eq!(parts.len(), 4, "{text}");
            [
                e.job.label().to_string(),
                format!("{:e}", e.target),
                parts[0].to_string(),
                parts[1].trim_start_matches("err ≤ ").to_string(),
                parts[2].trim_end_matches(" evals").to_string(),
                parts[3].trim_end_matches(" µs").to_string(),
            ]
        })
        .collect();
    let expected: String = want
        .iter()
        .map(|w| {
            format!(
                "| {} | … | {} | {} | {} | {} | {} |\n",
                w[0], w[1], w[2], w[3], w[4], w[5]
            )
        })
        .collect();
    assert_eq!(rows.len(), want.len(), "the table should read:\n{expected}");
    for (row, w) in rows.iter().zip(&want) {
        assert_eq!(row.len(), 7, "{row:?}");
        let got = [
            row[0].clone(),
            // "1e-4 (a pixel)": the number first.
            row[2].split_whitespace().next().unwrap_or("").to_string(),
            row[3].clone(),
            row[4].clone(),
            row[5].clone(),
            row[6].clone(),
        ];
        assert_eq!(&got, w, "the table should read:\n{expected}");
    }
}

/// The "?" texts as docs/gui.md carries them between its markers: one
/// paragraph per view, "**Title.** text".
fn help_section() -> String {
    use oneblock::app::ViewKind;
    use oneblock::app::help::view_help;
    ViewKind::ALL
        .iter()
        .map(|v| format!("**{}.** {}\n", v.title(), view_help(*v)))
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn the_views_help_in_docs_gui_md_is_the_windows() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/docs/gui.md");
    let md = std::fs::read_to_string(path).expect("docs/gui.md");
    let (begin, end) = ("<!-- help:begin -->\n", "<!-- help:end -->");
    let want = help_section();
    let (Some(a), Some(b)) = (md.find(begin), md.find(end)) else {
        panic!("docs/gui.md has no {begin:?} … {end:?} section; it should hold:\n{want}");
    };
    let got = &md[a + begin.len()..b];
    if got.trim() != want.trim() && std::env::var_os("UPDATE_DOCS").is_some() {
        let new = format!("{}{begin}\n{want}\n{}", &md[..a], &md[b..]);
        std::fs::write(path, new).expect("write docs/gui.md");
        return;
    }
    assert_eq!(
        got.trim(),
        want.trim(),
        "UPDATE_DOCS=1 rewrites the section"
    );
}
