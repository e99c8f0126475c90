//! `--arcs fit` against LinuxCNC's `rs274` (`support/rs274.rs`): the
//! output must move the tool as the input does within the tolerance
//! (sampled, in order, as `compare.py --sample`), with far fewer moves
//! where chains of lines trace arcs. Runs rs274: under
//! `flock /tmp/rs274.lock` on the shared machine.
//!
//! Without rs274 the tests pass with a note, unless it is required (CI).

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::{Path, PathBuf};

mod support;

use support::rs274;

/// `--arcs fit`'s default tolerance in a millimetre program.
const TOLERANCE_MM: f64 = 0.005;

fn oracle() -> bool {
    if rs274::available() {
        return true;
    }
    assert!(!rs274::required(), "{}", rs274::missing());
    eprintln!("skipped: {}", rs274::missing());
    false
}

/// A folder of its own for `test`, emptied of an earlier run's files.
fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ger-arcs-fit-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The moves (G0–G3 lines) of a program's text.
fn moves(path: &Path) -> usize {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| l.split(' ').any(|w| matches!(w, "G0" | "G1" | "G2" | "G3")))
        .count()
}

/// rs274 moves `a` and `b` alike within the tolerance, sampled.
fn same_within_tolerance(a: &Path, b: &Path) {
    let (ra, rb) = (
        rs274::tool_path(a, &[]).unwrap(),
        rs274::tool_path(b, &[]).unwrap(),
    );
    let options = ger::toolpath::compare::Options {
        tol: TOLERANCE_MM,
        sample: Some(0.1),
        ..Default::default()
    };
    if let Err(why) = rs274::same_path(&ra, &rb, &options) {
        panic!(
            "{} and {} move differently: {why}\n--- output ---\n{}",
            a.display(),
            b.display(),
            std::fs::read_to_string(b).unwrap()
        );
    }
}

/// [`chords_program`] fitted: every arc within the tolerance, and the
/// runs broken where they must be.
#[test]
fn chains_of_chords_become_arcs_that_move_as_rs274_moves_the_lines() {
    if !oracle() {
        return;
    }
    let text = chords_program();
    let dir = scratch("chords");
    let input = dir.join("chords.ngc");
    std::fs::write(&input, &text).unwrap();
    let out = dir.join("chords.fit.ngc");
    let note = support::compile_with(&input, &out, &["--arcs", "fit"]).unwrap();
    assert!(note.contains("lines written as"), "{note}");
    let printed = std::fs::read_to_string(&out).unwrap();
    // The comment and the new feed each begin a new arc; the helix is one.
    assert!(printed.contains("(half way)"), "{printed}");
    assert!(moves(&out) < 20, "{printed}");
    assert!(printed.contains("/N"), "{printed}");
    same_within_tolerance(&input, &out);
    let _ = std::fs::remove_dir_all(dir);
}

/// `--arcs fit-r`: the same arcs, written with R where `--arcs r` would
/// write one and the arc about the centre rs274 finds from it is proven
/// (else with I/J, and a warning); rs274 moves them as it moves the
/// lines. 4 decimals, so more R arcs need a 5th or 6th.
#[test]
fn fitted_arcs_written_with_r_move_as_rs274_moves_the_lines() {
    if !oracle() {
        return;
    }
    let dir = scratch("chords-r");
    let input = dir.join("chords.ngc");
    std::fs::write(&input, chords_program()).unwrap();
    for decimals in ["3", "4"] {
        let out = dir.join(format!("chords.fit-r.{decimals}.ngc"));
        let args = ["--arcs", "fit-r", "--decimals", decimals];
        let note = support::compile_with(&input, &out, &args).unwrap();
        assert!(note.contains("(`--arcs fit-r`"), "{note}");
        let printed = std::fs::read_to_string(&out).unwrap();
        let arcs = printed
            .lines()
            .filter(|l| l.contains(" G2 ") || l.contains(" G3 "));
        let (with_r, with_ij): (Vec<&str>, Vec<&str>) = arcs.partition(|l| l.contains(" R"));
        // The half circles' arcs may need I/J; most arcs are not near one.
        assert!(with_r.len() > with_ij.len(), "{printed}");
        assert_eq!(with_ij.is_empty(), !note.contains("not R"), "{note}");
        assert!(moves(&out) < 20, "{printed}");
        same_within_tolerance(&input, &out);
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// Chords of circles and of a helix, CAM style (3 decimals, F on every
/// line), with a feed change and a kept comment inside a circle, corners,
/// a block-delete line and a rapid.
fn chords_program() -> String {
    let mut text = String::from("G21 G90 G17\nG0 X20 Y0 Z5\nG1 Z-1 F800\n");
    for k in 1..=360 {
        let a = f64::from(k).to_radians();
        let feed = if k > 200 { 600 } else { 800 };
        text.push_str(&format!(
            "G1 X{:.3} Y{:.3} F{feed}\n",
            20.0 * a.cos(),
            20.0 * a.sin()
        ));
        if k == 100 {
            text.push_str("(half way)\n");
        }
    }
    for k in 1..=180 {
        let a = f64::from(k).to_radians() * 2.0;
        text.push_str(&format!(
            "G1 X{:.3} Y{:.3} Z{:.3}\n",
            30.0 + 10.0 * a.cos(),
            10.0 * a.sin(),
            -1.0 - 0.005 * f64::from(k)
        ));
    }
    text.push_str("G1 X40 Y10\nG1 X40 Y20\n/G1 X30 Y20\nG1 X30 Y30\nG0 Z5\nM30\n");
    text
}

/// `--arcs lines` output of the shipped examples, fitted back: the same
/// path within the tolerance, and the flange's circles arcs again.
#[test]
fn examples_written_as_lines_fit_back() {
    if !oracle() {
        return;
    }
    let dir = scratch("examples");
    let examples = support::egc_files(&support::manifest().join("examples"));
    for example in examples {
        let stem = example.file_stem().unwrap().to_string_lossy().into_owned();
        let lines = dir.join(format!("{stem}.lines.ngc"));
        support::compile_with(&example, &lines, &["--arcs", "lines"]).unwrap();
        let fit = dir.join(format!("{stem}.fit.ngc"));
        support::compile_with(&lines, &fit, &["--arcs", "fit"]).unwrap();
        same_within_tolerance(&lines, &fit);
        if stem == "bolt_flange" {
            let (before, after) = (moves(&lines), moves(&fit));
            assert!(after * 10 <= before * 3, "{before} moves as {after}");
        }
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// A flat program that never sets Z (a plotter's, a laser's): only the
/// machine knows Z, and a circle of chords is still fitted, its arcs
/// written without a Z word; rs274, starting at Z0, moves both alike.
#[test]
fn a_program_that_never_sets_z_has_its_circles_fitted_without_z() {
    if !oracle() {
        return;
    }
    let mut text = String::from("G21 G90 G17\nG0 X15 Y0\n");
    for k in 1..=360 {
        let a = f64::from(k).to_radians();
        text.push_str(&format!(
            "G1 X{:.3} Y{:.3} F500\n",
            15.0 * a.cos(),
            15.0 * a.sin()
        ));
    }
    text.push_str("G0 X0 Y0\nM30\n");
    let dir = scratch("flat");
    let input = dir.join("flat.ngc");
    std::fs::write(&input, &text).unwrap();
    let out = dir.join("flat.fit.ngc");
    let note = support::compile_with(&input, &out, &["--arcs", "fit"]).unwrap();
    assert!(note.contains("lines written as"), "{note}");
    let printed = std::fs::read_to_string(&out).unwrap();
    assert!(moves(&out) <= 6, "{printed}");
    assert!(!printed.contains('Z'), "{printed}");
    same_within_tolerance(&input, &out);
    let _ = std::fs::remove_dir_all(dir);
}
