//! Real programs (`../shared/real/`, third-party files read from there and
//! never copied here): where that folder is present, each program that
//! rs274 runs must compile with ger to the same tool path, or be refused
//! for a reason of its own line that a later issue lifts, be refused by design
//! (`REFUSED`: probing, which only the machine can run), or differ for
//! a reason written down below. Without the folder the tests are skipped
//! (they are not ger's data); without rs274 they follow `tests/oracle.rs`.
//!
//! rs274 is given a cleaned copy, fixed only in format trivia it refuses
//! and ger must accept (as `../shared/real/check.sh` does); ger always
//! gets the original bytes.

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use ger::toolpath::compare::Options;
use libtest_mimic::{Arguments, Failed, Trial};
use std::path::{Path, PathBuf};

mod support;
use support::rs274;

/// Refusals a later issue lifts: the program's first error says one of
/// these.
const NOT_YET: &[&str] = &["is not supported", "o-word call arguments"];

/// Programs ger refuses by design: the first error must say this.
const REFUSED: &[(&str, &str)] = &[
    // pcb2gcode's auto-levelling probes the board (G38.2) and corrects
    // each cut by the heights found (#5063): only the machine knows them.
    ("013_", "unsupported code G38.2"),
];

/// Tool tables (mm, LinuxCNC's format) for the programs that compensate:
/// the same table for rs274 and for ger (`--tool-table`), with the cutter
/// the program's own comments name.
const TOOL_TABLES: &[(&str, &str)] = &[("020_", "T34 P34 D3 Z0 ;3MM CRB 2FL\n")];

/// Programs whose path differs for a reason that is not ger's to fix.
const KNOWN: &[(&str, &str)] = &[(
    "040_",
    "the output passes grbl's `$H` through, which rs274 cannot read",
)];

fn clean_for_rs274(bytes: &[u8]) -> String {
    let text = String::from_utf8_lossy(bytes)
        .trim_start_matches('\u{feff}')
        .replace('\u{1a}', "")
        .replace("\r\n", "\n")
        .replace('\r', "\n");
    let mut out = String::new();
    for line in text.split('\n') {
        let s = line.trim();
        if s.starts_with('%') {
            continue;
        }
        if s.starts_with(':') && s[1..].starts_with(|c: char| c.is_ascii_digit()) {
            out.push_str(&format!("(program {})\n", &s[1..]));
            continue;
        }
        if s.starts_with('$') {
            out.push_str(&format!("({s})\n"));
            continue;
        }
        let mut depth = 0;
        for ch in line.chars() {
            match ch {
                '(' => {
                    out.push(if depth == 0 { '(' } else { '[' });
                    depth += 1;
                }
                ')' if depth > 0 => {
                    depth -= 1;
                    out.push(if depth == 0 { ')' } else { ']' });
                }
                c => out.push(c),
            }
        }
        out.push('\n');
    }
    let code: String = out
        .lines()
        .map(|l| {
            let l = l.split(';').next().unwrap_or("");
            let mut s = String::new();
            let mut depth = 0;
            for c in l.chars() {
                match c {
                    '(' => depth += 1,
                    ')' if depth > 0 => depth -= 1,
                    c if depth == 0 => s.push(c.to_ascii_uppercase()),
                    _ => {}
                }
            }
            s
        })
        .collect::<Vec<_>>()
        .join("\n");
    let ends = code.split(|c: char| !c.is_ascii_alphanumeric()).any(|w| {
        w.strip_prefix('M')
            .is_some_and(|n| n.trim_start_matches('0') == "2" || n.trim_start_matches('0') == "30")
    });
    if !ends {
        out.push_str("M2\n");
    }
    out
}

fn run(path: &Path) -> Result<(), Failed> {
    let name = path.file_name().unwrap().to_string_lossy().into_owned();
    let work = std::env::temp_dir().join(format!("ger-real-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&work).map_err(|e| e.to_string())?;
    let bytes = std::fs::read(path).map_err(|e| e.to_string())?;
    let reference = work.join("ref.ngc");
    std::fs::write(&reference, clean_for_rs274(&bytes)).map_err(|e| e.to_string())?;
    let table = TOOL_TABLES
        .iter()
        .find(|(prefix, _)| name.starts_with(prefix))
        .map(|(_, text)| *text);
    let tools = table.map(rs274::read_tool_table).unwrap_or_default();
    let a = rs274::tool_path(&reference, &tools);
    let out = work.join("out.nc");
    let compiled = match table {
        Some(text) => {
            let file = work.join("tools.tbl");
            std::fs::write(&file, text).map_err(|e| e.to_string())?;
            let file = file.to_string_lossy().into_owned();
            support::compile_with(path, &out, &["--tool-table", &file])
        }
        None => support::compile(path, &out),
    };
    let result = match (a, compiled) {
        // rs274 refuses the program: nothing to compare with.
        (Err(_), _) => Ok(()),
        (Ok(_), Err(e)) => {
            let first = e.lines().find(|l| l.starts_with("error")).unwrap_or("");
            let refused = REFUSED
                .iter()
                .any(|(prefix, says)| name.starts_with(prefix) && first.contains(says));
            if refused || NOT_YET.iter().any(|why| first.contains(why)) {
                Ok(())
            } else {
                Err(format!("ger refuses a program rs274 runs:\n{e}"))
            }
        }
        (Ok(a), Ok(_)) => {
            let known = KNOWN.iter().find(|(prefix, _)| name.starts_with(prefix));
            let b = rs274::tool_path(&out, &tools);
            let same = b
                .map_err(|e| format!("ger's output fails in rs274: {e}"))
                .and_then(|b| {
                    let options = Options {
                        ignore_tools: true,
                        ..Options::default()
                    };
                    rs274::same_path(&a, &b, &options).map(|_| ())
                });
            match (same, known) {
                (Ok(()), None) => Ok(()),
                (Ok(()), Some(_)) => Err(format!(
                    "{name} now gives rs274's path: remove it from KNOWN"
                )),
                (Err(_), Some(_)) => Ok(()),
                (Err(why), None) => Err(why),
            }
        }
    };
    let _ = std::fs::remove_dir_all(&work);
    result.map_err(Failed::from)
}

fn main() {
    let args = Arguments::from_args();
    let Some(dir) = support::shared_real() else {
        // A clone of this repository alone: the real programs are not
        // here; the one trial says so, by name, as skipped.
        let absent = Trial::test("real_programs (../shared/real absent)", || Ok(()));
        libtest_mimic::run(&args, vec![absent.with_ignored_flag(true)]).exit();
    };
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    files.retain(|p| {
        p.file_name().and_then(|n| n.to_str()).is_some_and(|n| {
            n.len() > 4 && n[..3].bytes().all(|b| b.is_ascii_digit()) && n.as_bytes()[3] == b'_'
        })
    });
    files.sort();
    let (have, required) = (rs274::available(), rs274::required());
    let trials = files
        .into_iter()
        .map(|path| {
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            Trial::test(name, move || {
                if !have {
                    return Err(rs274::missing().into());
                }
                run(&path)
            })
            .with_ignored_flag(!have && !required)
        })
        .collect();
    libtest_mimic::run(&args, trials).exit();
}
