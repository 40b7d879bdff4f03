//! The Auto table in `docs/numerics.md` says which setting each consumer
//! of map iterates gets and what the chart says of it. Three documents once
//! gave three different sets of Auto settings; this test reads the table
//! and checks every row against `numerics::budget_for`, so the page cannot
//! drift from the code (re-measuring the chart means updating the page).

use oneblock::Method;
use oneblock::numerics::{Accuracy, budget_for};

/// The consumers as the table names them.
const CONSUMERS: [(&str, Accuracy); 5] = [
    ("`TrajectoryView`", Accuracy::TrajectoryView),
    ("`BifurcationDiagram`", Accuracy::BifurcationDiagram),
    ("`PhaseDiagram`", Accuracy::PhaseDiagram),
    ("`ReturnMap`", Accuracy::ReturnMap),
    ("`CommandLine`", Accuracy::CommandLine),
];

/// The method as the docs spell it.
fn docs_name(m: Method) -> &'static str {
    match m {
        Method::Dop853 => "DOP853",
        Method::Dp54 => "DP5(4)",
        Method::Rk4 => "RK4",
        Method::Euler => "Euler",
    }
}

#[test]
fn the_auto_table_in_numerics_md_is_what_budget_for_chooses() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/docs/numerics.md");
    let page = std::fs::read_to_string(path).expect("docs/numerics.md is readable");
    for (name, accuracy) in CONSUMERS {
        let row = page
            .lines()
            .find(|l| l.starts_with(&format!("| {name} |")))
            .unwrap_or_else(|| panic!("no row for {name} in the Auto table"));
        let cells: Vec<&str> = row.trim_matches('|').split('|').map(str::trim).collect();
        assert_eq!(cells.len(), 7, "row for {name}: {row}");
        let target = accuracy.target();
        assert!(
            cells[2].starts_with(&format!("{target:e}")),
            "{name}: the page says it can show {}, the code {target:e}",
            cells[2]
        );
        let b = budget_for(target);
        let expected = [
            format!("{} tol {:e}", docs_name(b.settings.method), b.settings.rtol),
            format!("{:.1e}", b.est_error),
            format!("{:.0}", b.est_evals),
            format!("{:.1}", b.est_us),
        ];
        assert_eq!(
            cells[3..],
            expected.each_ref().map(String::as_str),
            "{name}: the page's setting, max error, evaluations and µs against budget_for"
        );
    }
}
