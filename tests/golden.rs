//! Golden tests: every `tests/cases/<area>/<name>.egc` is run through the
//! real `ger` binary; its output must equal `<name>.nc` and its diagnostics
//! `<name>.stderr` (absent file = nothing expected). `GER_BLESS=1`
//! rewrites the expectations; review the diff before committing.
//!
//! Arguments: `<name>.args` if present, else by area (`parse` prints the
//! parse stage, `syntax` and `errors` run `check`, others `compile`).

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use libtest_mimic::{Arguments, Failed, Trial};
use std::path::{Path, PathBuf};
use std::process::Command;

mod support;

fn main() {
    let args = Arguments::from_args();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/cases");
    let mut trials = Vec::new();
    let mut areas: Vec<PathBuf> = std::fs::read_dir(&root)
        .map(|d| {
            d.filter_map(|e| e.ok())
                .map(|e| e.path())
                .filter(|p| p.is_dir())
                .collect()
        })
        .unwrap_or_default();
    areas.sort();
    for area in areas {
        let cases = support::egc_files(&area);
        for case in cases {
            let name = format!(
                "{}/{}",
                area.file_name().unwrap().to_string_lossy(),
                case.file_stem().unwrap().to_string_lossy()
            );
            trials.push(Trial::test(name, move || run_case(&case)));
        }
    }
    libtest_mimic::run(&args, trials).exit();
}

fn case_args(case: &Path) -> Vec<String> {
    let args_file = case.with_extension("args");
    if let Ok(text) = std::fs::read_to_string(&args_file) {
        return text.split_whitespace().map(String::from).collect();
    }
    let area = case
        .parent()
        .and_then(|p| p.file_name())
        .unwrap()
        .to_string_lossy();
    match &*area {
        "parse" => vec!["compile".into(), "--stage".into(), "parse".into()],
        "syntax" | "errors" => vec!["check".into()],
        _ => vec!["compile".into()],
    }
}

fn run_case(case: &Path) -> Result<(), Failed> {
    let dir = case.parent().unwrap();
    let file = case.file_name().unwrap().to_string_lossy().into_owned();
    let mut args = case_args(case);
    args.push(file);
    let output = Command::new(env!("CARGO_BIN_EXE_ger"))
        .args(&args)
        .current_dir(dir)
        .output()
        .map_err(|e| format!("cannot run ger: {e}"))?;
    let code = output.status.code().unwrap_or(-1);
    if code != 0 && code != 1 {
        return Err(format!(
            "ger exited {code} (usage/I/O error or crash):\n{}",
            String::from_utf8_lossy(&output.stderr)
        )
        .into());
    }
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    let bless = std::env::var_os("GER_BLESS").is_some();
    let mut problems = Vec::new();
    for (ext, actual) in [("nc", &stdout), ("stderr", &stderr)] {
        let path = case.with_extension(ext);
        let expected = std::fs::read_to_string(&path).unwrap_or_default();
        if *actual == expected {
            continue;
        }
        if bless {
            if actual.is_empty() {
                let _ = std::fs::remove_file(&path);
            } else {
                std::fs::write(&path, actual).map_err(|e| e.to_string())?;
            }
        } else {
            problems.push(format!(
                "{} differs:\n{}",
                path.display(),
                diff(&expected, actual)
            ));
        }
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "{}\n(run with GER_BLESS=1 to accept, then review the diff)",
            problems.join("\n")
        )
        .into())
    }
}

/// A short line diff: the first lines that differ.
fn diff(expected: &str, actual: &str) -> String {
    let (e, a): (Vec<&str>, Vec<&str>) = (expected.lines().collect(), actual.lines().collect());
    let mut out = String::new();
    let mut shown = 0;
    for i in 0..e.len().max(a.len()) {
        let (x, y) = (e.get(i), a.get(i));
        if x != y {
            out.push_str(&format!(
                "  line {}:\n    expected: {}\n    actual:   {}\n",
                i + 1,
                x.unwrap_or(&"<none>"),
                y.unwrap_or(&"<none>")
            ));
            shown += 1;
            if shown == 8 {
                out.push_str("  …\n");
                break;
            }
        }
    }
    out
}
