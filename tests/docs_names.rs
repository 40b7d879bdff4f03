//! docs/jobs.md and docs/worker.md against the code they describe: every
//! Rust block that shows a definition (`pub enum …`, `pub trait …`) is the
//! source's, doc comments left out; every `Type::name` they quote is
//! declared in a file that defines or implements `Type`; every
//! `module::path::name` is declared under that module; every
//! `Name { field, … }` has those fields; every file named exists. These
//! pages once showed a `trait Job { fn lane(&self) … }` and
//! `Command::Sweep`, `Command::Phase` and `Command::InjectPanic` long
//! after the code had none of them.

use std::path::{Path, PathBuf};

const PAGES: [&str; 2] = ["docs/jobs.md", "docs/worker.md"];

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Every source file under `dir`, with its text.
fn sources(dir: &Path) -> Vec<(PathBuf, String)> {
    let mut out = Vec::new();
    let mut dirs = vec![dir.to_path_buf()];
    while let Some(d) = dirs.pop() {
        for e in std::fs::read_dir(&d).expect("readable").flatten() {
            let p = e.path();
            if p.is_dir() {
                dirs.push(p);
            } else if p.extension().is_some_and(|x| x == "rs") {
                let text = std::fs::read_to_string(&p).expect("utf-8");
                out.push((p, text));
            }
        }
    }
    out
}

fn is_ident(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// Whether `text` declares `name`: a function, type, constant, module or
/// re-export of it, an enum variant or a struct field.
fn declares(text: &str, name: &str) -> bool {
    let mut from = 0;
    while let Some(i) = text[from..].find(name) {
        let at = from + i;
        from = at + name.len();
        let before = text[..at].chars().next_back();
        let after = text[at + name.len()..].chars().next();
        if before.is_some_and(is_ident) || after.is_some_and(is_ident) {
            continue;
        }
        let line_start = text[..at].rfind('\n').map_or(0, |n| n + 1);
        let head = text[line_start..at].trim_start();
        let declared_by_keyword = [
            "fn ", "struct ", "enum ", "trait ", "type ", "const ", "mod ",
        ]
        .iter()
        .any(|k| head.ends_with(k) || head.ends_with(&format!("pub {k}")))
            || head.starts_with("pub use")
            || head.starts_with("pub(crate) use");
        // A variant, a field or a table entry: the name opens its line.
        let opens_line = head.is_empty()
            && after.is_some_and(|c| matches!(c, ' ' | '(' | '{' | ',' | ':' | '='));
        if declared_by_keyword || opens_line {
            return true;
        }
    }
    false
}

/// The files that define or implement the type `ty`.
fn files_of<'a>(src: &'a [(PathBuf, String)], ty: &str) -> Vec<&'a str> {
    src.iter()
        .filter(|(_, t)| {
            ["enum ", "struct ", "trait ", "type ", "impl ", "for "]
                .iter()
                .any(|k| declares_after(t, k, ty))
        })
        .map(|(_, t)| t.as_str())
        .collect()
}

/// Whether `text` has `keyword` (e.g. "impl ") followed by `ty` as a word
/// (generics allowed between: `impl<F> Collect<F>`).
fn declares_after(text: &str, keyword: &str, ty: &str) -> bool {
    text.match_indices(keyword).any(|(i, _)| {
        let rest = &text[i + keyword.len()..];
        let rest = if keyword == "impl " || rest.starts_with('<') {
            rest.trim_start_matches(|c: char| c != ' ' && c != '\n' && !c.is_uppercase())
        } else {
            rest
        };
        rest.strip_prefix(ty)
            .is_some_and(|r| !r.starts_with(is_ident))
            && text[..i].chars().next_back().is_none_or(|c| !is_ident(c))
    })
}

/// The backticked spans of a page, its code blocks left out.
fn spans(page: &str) -> Vec<String> {
    let mut prose = String::new();
    let mut in_block = false;
    for line in page.lines() {
        if line.starts_with("```") {
            in_block = !in_block;
        } else if !in_block {
            prose.push_str(line);
            prose.push('\n');
        }
    }
    prose
        .split('`')
        .skip(1)
        .step_by(2)
        .map(|s| s.split_whitespace().collect::<Vec<_>>().join(" "))
        .collect()
}

/// The `A::B::c` paths in a span (generics and arguments cut off).
fn paths(span: &str) -> Vec<Vec<String>> {
    span.split(|c: char| !(is_ident(c) || c == ':'))
        .filter(|w| w.contains("::"))
        .map(|w| {
            w.split("::")
                .filter(|s| !s.is_empty())
                .map(str::to_string)
                .collect()
        })
        .filter(|p: &Vec<String>| p.len() >= 2)
        .collect()
}

/// The definition of `head` (`pub enum Command`) in `text`, from that line
/// to its closing brace, without doc comments and attributes, each line
/// trimmed.
fn definition(text: &str, head: &str) -> Option<Vec<String>> {
    let lines: Vec<&str> = text.lines().collect();
    let start = lines.iter().position(|l| {
        l.trim_start()
            .strip_prefix(head)
            .is_some_and(|r| r.starts_with([' ', ':', '<', '{']))
    })?;
    let indent = lines[start].len() - lines[start].trim_start().len();
    let mut out = Vec::new();
    for l in &lines[start..] {
        let t = l.trim();
        if !(t.starts_with("///") || t.starts_with("//") || t.starts_with("#[") || t.is_empty()) {
            out.push(t.to_string());
        }
        if l.len() - l.trim_start().len() == indent && t == "}" {
            return Some(out);
        }
    }
    None
}

#[test]
fn the_pages_show_the_definitions_as_the_source_has_them() {
    let src = sources(&root().join("src"));
    let mut checked = 0;
    for page in PAGES {
        let text = std::fs::read_to_string(root().join(page)).expect("utf-8");
        let mut block: Option<Vec<String>> = None;
        for line in text.lines() {
            if line.starts_with("```rust") {
                block = Some(Vec::new());
            } else if line.starts_with("```") {
                let Some(b) = block.take() else { continue };
                // Each definition in the block: from its `pub enum`/`pub
                // trait` line to the closing brace at column 0.
                let mut i = 0;
                while i < b.len() {
                    let l = &b[i];
                    let is_def = l.starts_with("pub enum ") || l.starts_with("pub trait ");
                    if !is_def {
                        i += 1;
                        continue;
                    }
                    let end = (i..b.len()).find(|&j| b[j] == "}").expect("a closed block");
                    let head: String = l.split_whitespace().take(3).collect::<Vec<_>>().join(" ");
                    let head = head
                        .trim_end_matches(':')
                        .trim_end_matches(" {")
                        .to_string();
                    let shown: Vec<String> = b[i..=end]
                        .iter()
                        .map(|l| l.trim().to_string())
                        .filter(|l| !l.is_empty())
                        .collect();
                    // Several files may define a type of that name (the
                    // worker's `Command` and the command line's): one must
                    // be what is shown.
                    let found: Vec<Vec<String>> = src
                        .iter()
                        .filter_map(|(_, t)| definition(t, &head))
                        .collect();
                    assert!(!found.is_empty(), "{page}: `{head}` is in no source file");
                    assert!(
                        found.contains(&shown),
                        "{page}: `{head}` is not the source's:\n{shown:#?}\nthe source has:\n{found:#?}"
                    );
                    checked += 1;
                    i = end + 1;
                }
            } else if let Some(b) = block.as_mut() {
                b.push(line.to_string());
            }
        }
    }
    assert!(
        checked >= 3,
        "the Job and Sink traits and the Command enum are shown"
    );
}

#[test]
fn every_name_the_pages_quote_is_the_codes() {
    let src = sources(&root().join("src"));
    let mut missing = Vec::new();
    for page in PAGES {
        let text = std::fs::read_to_string(root().join(page)).expect("utf-8");
        for span in spans(&text) {
            for path in paths(&span) {
                let (last, front) = path.split_last().expect("two parts");
                let owner = front.last().expect("an owner");
                let std = [
                    "usize", "u64", "f64", "std", "core", "Duration", "Vec", "Option",
                ];
                let ok = if std.contains(&front[0].as_str()) {
                    true
                } else if owner.starts_with(char::is_uppercase) {
                    files_of(&src, owner).iter().any(|t| declares(t, last))
                } else {
                    // A module path from the crate's root.
                    let front: Vec<&str> = front
                        .iter()
                        .map(String::as_str)
                        .skip_while(|&m| m == "oneblock" || m == "crate")
                        .collect();
                    let dir = root().join("src").join(front.join("/"));
                    let file = dir.with_extension("rs");
                    src.iter()
                        .filter(|(p, _)| p.starts_with(&dir) || *p == file)
                        .any(|(_, t)| declares(t, last))
                };
                if !ok {
                    missing.push(format!("{page}: `{}`", path.join("::")));
                }
            }
            // `Name { field, field: value, … }`: each field is Name's.
            if let Some((name, fields)) = span.split_once(" {")
                && let Some(fields) = fields.trim().strip_suffix('}')
                && let Some(name) = name.rsplit("::").next()
                && name.starts_with(char::is_uppercase)
                && name.chars().all(is_ident)
            {
                // A struct's definition where there is one, else an enum
                // variant's (a line that opens with `Name {`).
                let of = |head: &str| -> Vec<Vec<String>> {
                    src.iter()
                        .filter_map(|(_, t)| definition(t, head))
                        .collect()
                };
                // A variant is indented one level (a struct literal in a
                // function body, deeper, does not count).
                let mut defs = of(&format!("pub struct {name}"));
                defs.extend(src.iter().filter_map(|(_, t)| {
                    let at = t.find(&format!("\n    {name} {{"))?;
                    definition(&t[at..], name)
                }));
                for field in fields
                    .split(',')
                    .map(|f| f.split(':').next().unwrap_or("").trim())
                {
                    if field.is_empty() || field == "…" || field == ".." {
                        continue;
                    }
                    let has = defs.iter().any(|d| {
                        d.iter().any(|l| {
                            l.starts_with(&format!("pub {field}:"))
                                || l.starts_with(&format!("{field}:"))
                        })
                    });
                    if !has {
                        missing.push(format!("{page}: `{span}`: no field `{field}`"));
                    }
                }
            }
        }
    }
    assert!(
        missing.is_empty(),
        "quoted but not in the code:\n{}",
        missing.join("\n")
    );
}

#[test]
fn every_file_the_pages_name_exists() {
    let src = sources(&root().join("src"));
    let mut missing = Vec::new();
    for page in PAGES {
        let text = std::fs::read_to_string(root().join(page)).expect("utf-8");
        for span in spans(&text) {
            let rooted = span.starts_with("src/") || span.starts_with("tests/");
            if !(rooted || span.ends_with(".rs")) || span.contains(' ') {
                continue;
            }
            let found = if rooted {
                root().join(&span).exists()
            } else {
                // Relative to a folder the page names nearby (`jobs/kinds.rs`).
                src.iter()
                    .any(|(p, _)| p.to_string_lossy().ends_with(&format!("/{span}")))
            };
            if !found {
                missing.push(format!("{page}: `{span}`"));
            }
        }
    }
    assert!(
        missing.is_empty(),
        "named but not in the repository:\n{}",
        missing.join("\n")
    );
}
