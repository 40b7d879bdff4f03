//! Small things a user hit on the command line (issue "views a lecture
//! hall and a paper can use", item 9): `phase --png` alone writes only the
//! picture, and counts accept exponent notation.

use crate::cli_support;

use cli_support::*;

#[test]
fn phase_png_without_out_writes_the_picture_and_nothing_on_stdout() {
    let dir = tempfile::tempdir().expect("temp dir");
    let png = dir.path().join("p.png");
    let png_s = png.display().to_string();
    let o = oneblock(&[
        "phase",
        "--gamma",
        "6.5",
        "--nu",
        "1e-3",
        "--kappa-from",
        "14",
        "--kappa-to",
        "20",
        "--kappa-steps",
        "2",
        "--theta-nu-from",
        "1.2",
        "--theta-nu-to",
        "1.5",
        "--theta-nu-steps",
        "2",
        "--transient",
        "100",
        "--keep",
        "32",
        "--png",
        &png_s,
    ]);
    assert_ok(&o);
    assert!(o.stdout.is_empty(), "no CSV on stdout: {}", stdout(&o));
    let bytes = std::fs::read(&png).expect("the png");
    assert_eq!(&bytes[1..4], b"PNG");
    // Only the picture is in the folder.
    assert_eq!(std::fs::read_dir(dir.path()).expect("dir").count(), 1);
}

#[test]
fn counts_accept_exponent_notation() {
    let o = run(&cmd_args(
        "orbit",
        &["--transient", "1e1", "--keep", "2e1", "--no-lyapunov"],
    ));
    assert_ok(&o);
    let (_, rows) = parse_csv(&stdout(&o));
    assert_eq!(rows.len(), 20);
}
