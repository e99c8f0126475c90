//! LinuxCNC's own sample programs (every `.ngc` that Debian's
//! `linuxcnc-uspace` installs, listed by `dpkg -L`) as a measurement of how
//! much of LinuxCNC's language ger reads: each sample that rs274 runs
//! alone is compiled by ger, and ger's output is run through rs274 again;
//! the two tool paths must agree as in `tests/oracle.rs`. Left out: what
//! rs274 itself refuses, and programs that probe (G38.x: their moves
//! depend on what only the machine measures). A program with cutter
//! compensation gets a tool table of the tools it names.
//!
//! The samples are LinuxCNC's files, read where they are installed, never
//! copied here. Without rs274 or the package the one trial is ignored by
//! name. The trial prints every sample that differs with its first
//! difference, and fails when fewer pass than the floors below: raise them
//! as features land, never lower them.

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use libtest_mimic::{Arguments, Failed, Trial};
use std::path::{Path, PathBuf};
use std::process::Command;

mod support;
use support::rs274;

/// Samples without `#` parameters or o-words that must give rs274's path.
const FLOOR_PLAIN: usize = 24;
/// Samples with `#` parameters or o-words that must give rs274's path.
const FLOOR_MACRO: usize = 114;

/// The diameter (mm) of every tool a compensating sample names: LinuxCNC's
/// sim table has 1/8 in and 1/16 in end mills; one size keeps every
/// sample's entry move longer than the radius.
const COMP_DIAMETER_MM: f64 = 1.5875;

fn main() {
    let args = Arguments::from_args();
    let samples = installed_samples();
    let have = rs274::available();
    let trial = if samples.is_empty() || !have {
        Trial::test(
            "linuxcnc_samples (rs274 or linuxcnc-uspace's samples absent)",
            || Ok(()),
        )
        .with_ignored_flag(true)
    } else {
        Trial::test("linuxcnc_samples", move || measure(&samples))
    };
    libtest_mimic::run(&args, vec![trial]).exit();
}

/// Every `.ngc` file the package lists, sorted.
fn installed_samples() -> Vec<PathBuf> {
    let Ok(out) = Command::new("dpkg")
        .args(["-L", "linuxcnc-uspace"])
        .output()
    else {
        return Vec::new();
    };
    let mut files: Vec<PathBuf> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter(|l| l.ends_with(".ngc"))
        .map(PathBuf::from)
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    files
}

/// What became of one sample.
enum Verdict {
    /// rs274 refuses it, or it probes: not counted.
    Out,
    Same,
    Differs(String),
}

/// Each sample's fate; the counts against the floors.
fn measure(samples: &[PathBuf]) -> Result<(), Failed> {
    let work = std::env::temp_dir().join(format!("ger-samples-{}", std::process::id()));
    std::fs::create_dir_all(&work).map_err(|e| e.to_string())?;
    let mut counts = [(0, 0), (0, 0)]; // plain, macro: (same, total)
    let mut differing = Vec::new();
    for (i, sample) in samples.iter().enumerate() {
        let Ok(text) = std::fs::read(sample) else {
            continue;
        };
        let text = String::from_utf8_lossy(&text).into_owned();
        let kind = usize::from(uses_macros(&text));
        match run(sample, &text, &work.join(format!("s{i}")))? {
            Verdict::Out => {}
            Verdict::Same => {
                counts[kind].0 += 1;
                counts[kind].1 += 1;
            }
            Verdict::Differs(why) => {
                counts[kind].1 += 1;
                differing.push(format!(
                    "{} {}: {why}",
                    ["plain", "macro"][kind],
                    sample.display()
                ));
            }
        }
    }
    let _ = std::fs::remove_dir_all(&work);
    for line in &differing {
        eprintln!("DIFF {line}");
    }
    let [(plain, plain_total), (macros, macro_total)] = counts;
    eprintln!(
        "linuxcnc samples: {plain}/{plain_total} plain and {macros}/{macro_total} with #/o-words give rs274's tool path"
    );
    if plain < FLOOR_PLAIN || macros < FLOOR_MACRO {
        return Err(format!(
            "fewer samples give rs274's path than before: {plain} plain (floor {FLOOR_PLAIN}), {macros} with #/o-words (floor {FLOOR_MACRO})"
        )
        .into());
    }
    Ok(())
}

/// Does the program use `#` parameters or o-words (outside comments)?
fn uses_macros(text: &str) -> bool {
    text.lines().map(code_of).any(|code| {
        let code = code.trim_start_matches(|c: char| c.is_whitespace() || c == '/');
        code.contains('#')
            || code
                .strip_prefix(['o', 'O'])
                .is_some_and(|r| r.starts_with(|c: char| c.is_ascii_digit() || "<#[ ".contains(c)))
    })
}

/// A line without its comments, upper case.
fn code_of(line: &str) -> String {
    let line = line.split(';').next().unwrap_or("");
    let mut code = String::new();
    let mut depth = 0;
    for c in line.chars() {
        match c {
            '(' => depth += 1,
            ')' if depth > 0 => depth -= 1,
            c if depth == 0 => code.push(c.to_ascii_uppercase()),
            _ => {}
        }
    }
    code
}

/// The G codes of the program's lines, spaces removed.
fn has_code(text: &str, codes: &[&str]) -> bool {
    text.lines().any(|l| {
        let code: String = code_of(l).chars().filter(|c| !c.is_whitespace()).collect();
        codes.iter().any(|g| {
            code.match_indices(g).any(|(at, _)| {
                !code[at + g.len()..].starts_with(|c: char| c.is_ascii_digit())
                    && !code[..at].ends_with(|c: char| c.is_ascii_digit() || c == '.')
            })
        })
    })
}

/// The tool numbers `T<n>` the program names.
fn tools_named(text: &str) -> Vec<u32> {
    let mut tools: Vec<u32> = Vec::new();
    for line in text.lines() {
        let code: String = code_of(line)
            .chars()
            .filter(|c| !c.is_whitespace())
            .collect();
        for (at, _) in code.match_indices('T') {
            let digits: String = code[at + 1..]
                .chars()
                .take_while(char::is_ascii_digit)
                .collect();
            if let Ok(t) = digits.parse() {
                if !tools.contains(&t) && t < 1000 {
                    tools.push(t);
                }
            }
        }
    }
    tools.sort();
    tools
}

/// Does the program probe, itself or in a subroutine file it calls
/// (`o<name> call`, `name.ngc` beside it, as rs274 finds it)?
fn probes(sample: &Path, text: &str) -> bool {
    let folder = sample.parent().unwrap_or(Path::new("."));
    let mut seen: Vec<String> = Vec::new();
    let mut texts = vec![text.to_string()];
    while let Some(text) = texts.pop() {
        if has_code(&text, &["G38"]) {
            return true;
        }
        for line in text.lines() {
            let code = code_of(line);
            let Some(name) = code
                .trim_start()
                .strip_prefix("O<")
                .and_then(|r| r.split_once('>'))
                .filter(|(_, rest)| rest.trim_start().starts_with("CALL"))
                .map(|(name, _)| name.trim().to_ascii_lowercase())
            else {
                continue;
            };
            if !seen.contains(&name) {
                if let Ok(t) = std::fs::read(folder.join(format!("{name}.ngc"))) {
                    texts.push(String::from_utf8_lossy(&t).into_owned());
                }
                seen.push(name);
            }
        }
    }
    false
}

fn run(sample: &Path, text: &str, work: &Path) -> Result<Verdict, Failed> {
    if probes(sample, text) {
        return Ok(Verdict::Out);
    }
    std::fs::create_dir_all(work).map_err(|e| e.to_string())?;
    let comp = has_code(text, &["G41", "G42"]);
    let tools: Vec<rs274::Tool> = if comp {
        let mut numbers = tools_named(text);
        if numbers.is_empty() {
            numbers.push(1);
        }
        numbers
            .into_iter()
            .map(|number| rs274::Tool {
                number,
                diameter: COMP_DIAMETER_MM,
                length: 0.0,
            })
            .collect()
    } else {
        Vec::new()
    };
    let Ok(a) = rs274::tool_path(sample, &tools) else {
        return Ok(Verdict::Out);
    };
    let out = work.join("out.ngc");
    let mut args: Vec<String> = Vec::new();
    if !tools.is_empty() {
        // ger reads a table in the program's units.
        let k = if a.inch { 25.4 } else { 1.0 };
        let table: String = tools
            .iter()
            .map(|t| format!("T{0} P{0} D{1} Z0\n", t.number, t.diameter / k))
            .collect();
        let file = work.join("tools.tbl");
        std::fs::write(&file, table).map_err(|e| e.to_string())?;
        args.extend(["--tool-table".into(), file.to_string_lossy().into_owned()]);
    }
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    if let Err(e) = support::compile_with(sample, &out, &args) {
        let first = e
            .lines()
            .skip_while(|l| !l.starts_with("error"))
            .take(2)
            .collect::<Vec<_>>()
            .join(" ");
        return Ok(Verdict::Differs(format!("ger refuses it: {first}")));
    }
    let b = match rs274::tool_path(&out, &tools) {
        Ok(b) => b,
        Err(e) => return Ok(Verdict::Differs(format!("ger's output fails: {e}"))),
    };
    Ok(match rs274::same_path(&a, &b, &Default::default()) {
        Ok(_) => Verdict::Same,
        Err(why) => Verdict::Differs(why.lines().next().unwrap_or("").to_string()),
    })
}
