//! `oneblock bench-worker --pieces`: every kind of job once on the
//! single-threaded host in the page's slices, counted in pieces. Timings
//! are this machine's, so only their form is checked here; that the
//! continuation and the boundaries come in many pieces (they pause
//! between map evaluations) is not a timing.

use crate::cli_support;

use cli_support::*;
use oneblock::jobs::Kind;

#[test]
fn pieces_json_lists_every_kind_with_its_pieces_and_longest_piece() {
    let o = oneblock(&["bench-worker", "--pieces", "--json", "--quick"]);
    assert_ok(&o);
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("JSON");
    let obj = v.as_object().expect("an object");
    assert_eq!(obj.keys().collect::<Vec<_>>(), ["kinds"], "{v}");
    let kinds = v["kinds"].as_array().expect("a list");
    let names: Vec<String> = Kind::ALL.iter().map(|k| format!("{k:?}")).collect();
    let listed: Vec<&str> = kinds.iter().filter_map(|k| k["kind"].as_str()).collect();
    assert_eq!(listed, names, "{v}");
    for k in kinds {
        let keys: Vec<&String> = k.as_object().expect("an object").keys().collect();
        assert_eq!(keys, ["kind", "longest_ms", "pieces"], "{k}");
        let pieces = k["pieces"].as_u64().expect("a count");
        let longest = k["longest_ms"].as_f64().expect("a number");
        assert!(pieces >= 1, "{k}");
        assert!(longest.is_finite() && longest >= 0.0, "{k}");
        // (How many pieces a kind takes depends on the machine's speed;
        // that the continuation pauses between map evaluations is
        // tests/jobs_hosts.rs's, deterministically.)
    }
}

#[test]
fn pieces_prints_a_table_and_refuses_json_alone() {
    let o = oneblock(&["bench-worker", "--pieces", "--quick"]);
    assert_ok(&o);
    let text = stdout(&o);
    for k in Kind::ALL {
        let name = format!("{k:?}");
        assert!(
            text.lines()
                .any(|l| l.split_whitespace().next() == Some(&name)),
            "{name}: {text}"
        );
    }
    let o = oneblock(&["bench-worker", "--json"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--pieces"), "{}", stderr(&o));
}
