//! Differential tests against LinuxCNC's `rs274` (`support/rs274.rs`). For
//! each `tests/oracle/<area>/<name>.egc`, ger's output must move the tool as
//! the reference does: `<name>.ngc` when present, else the `.egc` itself
//! (a program both ger and rs274 read). `<name>.tbl` is a LinuxCNC tool
//! table (mm) given to rs274 and, as `SetTool` lines, to ger.
//! `machine/` holds LinuxCNC programs that leave their start to the
//! machine (a G92 before any move, steps from where the tool stands):
//! rs274 runs them and ger's output from a start other than its zero
//! ([`START`]), so a translation that took the zero for the start fails.
//! Every output is also checked to use only the codes of SPEC §6.
//!
//! Without rs274 every test fails with how to install it; so does a
//! missing rs274 under CI (`CI=true` or `GER_REQUIRE_ORACLE=1`). Elsewhere
//! they are marked ignored, so `cargo test` on a machine without LinuxCNC
//! still runs the rest.

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use libtest_mimic::{Arguments, Failed, Trial};
use std::path::Path;

mod support;

use support::rs274;

fn main() {
    let args = Arguments::from_args();
    let (have_oracle, required) = (rs274::available(), rs274::required());
    let mut trials = Vec::new();
    // `linuxcnc/` holds plain G-code in LinuxCNC's macro language: the
    // program is its own reference. `fanuc/` holds Fanuc Macro B programs
    // (`.nc`, compiled `--from fanuc`), each with its plain reference.
    for area in [
        "eval", "lower", "cycles", "comp", "linuxcnc", "fanuc", "machine",
    ] {
        let dir = support::manifest().join("tests/oracle").join(area);
        let cases = match area {
            "linuxcnc" | "machine" => support::files_with(&dir, "ngc"),
            "fanuc" => support::files_with(&dir, "nc"),
            _ => support::egc_files(&dir),
        };
        for case in cases {
            // Each again with `--arcs r`: R words must place every centre
            // as I/J do (or the arc keeps I/J); one with N words again with
            // `--numbers keep` (`keep`).
            let numbered = std::fs::read_to_string(&case)
                .is_ok_and(|text| text.lines().any(|l| l.trim_start().starts_with('N')));
            let variants: &[&str] = if numbered {
                &["ij", "r", "keep"]
            } else {
                &["ij", "r"]
            };
            for &arcs in variants {
                let stem = case.file_stem().unwrap().to_string_lossy().into_owned();
                let name = match arcs {
                    "ij" => format!("{area}/{stem}"),
                    "keep" => format!("numbers-keep/{area}/{stem}"),
                    _ => format!("arcs-r/{area}/{stem}"),
                };
                let case = case.clone();
                let trial = Trial::test(name, move || {
                    if !have_oracle {
                        return Err(rs274::missing().into());
                    }
                    run_case(&case, arcs)
                });
                trials.push(trial.with_ignored_flag(!have_oracle && !required));
            }
        }
    }
    // `--cycles keep`: the kept cycles must run on LinuxCNC as the
    // original does.
    let root = support::manifest().join("tests/oracle");
    let kept = [
        ("cycles", "cycles-keep"),
        ("cycles_keep", "cycles-keep"),
        ("comp", "comp-keep"),
    ];
    for (folder, label) in kept {
        for case in support::egc_files(&root.join(folder)) {
            if case.with_extension("ngc").exists() {
                continue;
            }
            let name = format!("{label}/{}", case.file_stem().unwrap().to_string_lossy());
            let keep = if label == "comp-keep" {
                "--comp"
            } else {
                "--cycles"
            };
            let trial = Trial::test(name, move || {
                if !have_oracle {
                    return Err(rs274::missing().into());
                }
                run_kept(&case, keep)
            });
            trials.push(trial.with_ignored_flag(!have_oracle && !required));
        }
    }
    // Made-up programs of work offsets, modes and moves: where ger
    // compiles one, its output must move as rs274 moves the input.
    let trial = Trial::test("random/work_offsets", move || {
        if !have_oracle {
            return Err(rs274::missing().into());
        }
        random_work_offsets()
    });
    trials.push(trial.with_ignored_flag(!have_oracle && !required));
    // Made-up programs in LinuxCNC's macro language: the same rule.
    let trial = Trial::test("random/linuxcnc_macros", move || {
        if !have_oracle {
            return Err(rs274::missing().into());
        }
        random_macros()
    });
    trials.push(trial.with_ignored_flag(!have_oracle && !required));
    // The shipped examples have no reference: their output must use only
    // the allowed codes and be a program rs274 runs.
    for case in support::egc_files(&support::manifest().join("examples")) {
        let name = format!("examples/{}", case.file_stem().unwrap().to_string_lossy());
        let trial = Trial::test(name, move || {
            if !have_oracle {
                return Err(rs274::missing().into());
            }
            run_example(&case)
        });
        trials.push(trial.with_ignored_flag(!have_oracle && !required));
    }
    libtest_mimic::run(&args, trials).exit();
}

/// Programs [`random_work_offsets`] makes.
const RANDOM_PROGRAMS: u64 = 400;

/// A made-up program, the same for the same `seed`: moves (G0, G1, G2 R),
/// G10 L2 and L20 on G54 … G59.3 with some of X, Y and Z, the nine
/// selections, G90/G91, G92 and G92.1, G28 and G53. (Not G52: ger keeps it
/// apart from G92 and cancels it at G54, SPEC §4; rs274 keeps both in one
/// register.)
fn random_program(seed: u64) -> String {
    let mut next = numbers(seed);
    const NUMBERS: [&str; 8] = ["0", "5", "10", "-10", "12.5", "100", "-50", "3.25"];
    const SYSTEMS: [&str; 9] = [
        "G54", "G55", "G56", "G57", "G58", "G59", "G59.1", "G59.2", "G59.3",
    ];
    let axes = |next: &mut dyn FnMut(u64) -> u64| {
        let mut words = Vec::new();
        for letter in ["X", "Y", "Z"] {
            if next(2) == 0 {
                words.push(format!("{letter}{}", NUMBERS[next(8) as usize]));
            }
        }
        if words.is_empty() {
            words.push(format!("Z{}", NUMBERS[next(8) as usize]));
        }
        words.join(" ")
    };
    let mut text = String::from("G21 G90 G17\nF500\nG0 X0 Y0 Z10\n");
    for _ in 0..3 + next(12) {
        let line = match next(100) {
            0..=29 => format!("G{} {}", next(2), axes(&mut next)),
            30..=39 => format!("G10 L2 P{} {}", 1 + next(9), axes(&mut next)),
            40..=46 => format!("G10 L20 P{} {}", 1 + next(9), axes(&mut next)),
            47..=59 => SYSTEMS[next(9) as usize].to_string(),
            60..=65 => ["G90", "G91"][next(2) as usize].to_string(),
            66..=69 => "G28".to_string(),
            70..=74 => format!("G92 {}", axes(&mut next)),
            75..=77 => "G92.1".to_string(),
            78..=85 => format!("G53 G0 {}", axes(&mut next)),
            86..=89 => format!(
                "G2 X{} Y{} R{}",
                NUMBERS[next(8) as usize],
                NUMBERS[next(8) as usize],
                [20, 30, 60][next(3) as usize]
            ),
            _ => format!("G1 {}", axes(&mut next)),
        };
        text.push_str(&line);
        text.push('\n');
    }
    text.push_str("M30\n");
    text
}

/// [`RANDOM_PROGRAMS`] programs of [`random_program`]: each one ger
/// compiles must move as rs274 moves it, and most must compile (ger
/// refuses offsets changed under G91 and incremental moves from an unknown
/// point, which these programs make often).
fn random_work_offsets() -> Result<(), Failed> {
    random_trial(
        "random",
        RANDOM_PROGRAMS,
        random_program,
        false,
        RANDOM_PROGRAMS / 3,
    )
}

/// Programs 0 to `count` of `make`: each one ger compiles must move as
/// rs274 moves it, at least `least` must compile, and with `all_run` rs274
/// must run every one (else only those ger compiles are run).
fn random_trial(
    name: &str,
    count: u64,
    make: fn(u64) -> String,
    all_run: bool,
    least: u64,
) -> Result<(), Failed> {
    let work = std::env::temp_dir().join(format!("ger-oracle-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&work).map_err(|e| e.to_string())?;
    let (input, out) = (work.join("random.ngc"), work.join("random.out.nc"));
    let mut compiled = 0;
    for seed in 0..count {
        let text = make(seed);
        std::fs::write(&input, &text).map_err(|e| e.to_string())?;
        let run = || rs274::tool_path(&input, &[]).map_err(|e| format!("seed {seed}: {e}\n{text}"));
        let first = match all_run {
            true => Some(run()?),
            false => None,
        };
        if support::compile(&input, &out).is_err() {
            continue;
        }
        compiled += 1;
        let a = match first {
            Some(a) => a,
            None => run()?,
        };
        let b = rs274::tool_path(&out, &[])
            .map_err(|e| format!("seed {seed}: ger's output fails: {e}\n{text}"))?;
        rs274::same_path(&a, &b, &Default::default()).map_err(|why| {
            let output = std::fs::read_to_string(&out).unwrap_or_default();
            format!("seed {seed}: ger's output moves differently: {why}\n--- program ---\n{text}--- ger output ---\n{output}")
        })?;
    }
    let _ = std::fs::remove_dir_all(&work);
    if compiled < least {
        return Err(format!("only {compiled} of {count} programs compiled").into());
    }
    Ok(())
}

/// Numbers from a seed, the same on every run (xorshift64*): `next(n)` is
/// below `n`.
fn numbers(seed: u64) -> impl FnMut(u64) -> u64 {
    let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    move |n: u64| {
        state ^= state >> 12;
        state ^= state << 25;
        state ^= state >> 27;
        (state.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 33) % n
    }
}

/// Programs [`random_macros`] makes.
const RANDOM_MACRO_PROGRAMS: u64 = 300;

/// A made-up program in LinuxCNC's macro language, the same for the same
/// `seed`, in forms rs274 reads whatever the values: assignments of `[…]`
/// to numbered and named parameters (on one line too), expressions of
/// every operator and function (their arguments kept in their domains;
/// angles at and near multiples of 90°, values within 0.0001 of each
/// other), `if`/`elseif`/`else`, `while`, `do`, `repeat`, `break`, and
/// subroutines that return values (`return [v]`, `endsub [v]`,
/// `#<_value>`). Each coordinate is a value folded into ±50 by `MOD`,
/// which turns the last bit of a value at a step into a move 100 mm off.
fn random_macro_program(seed: u64) -> String {
    let mut next = numbers(seed);
    let mut label = 100;
    let mut text = String::from("G21 G90 G17\nF500\n#<_g> = [1]\nG0 X0 Y0 Z10\n");
    let subs = next(3);
    let breaks = next(2) == 0;
    for k in 0..subs {
        text.push_str(&format!("o<s{k}> sub\n"));
        let vars = ["#1", "#2", "#<_g>"];
        macro_body(&mut next, &mut text, &vars, (1, breaks), k, &mut label);
        if next(2) == 0 {
            label += 1;
            let cond = macro_expr(&mut next, &vars, 1);
            let value = macro_expr(&mut next, &vars, 1);
            text.push_str(&format!(
                "o{label} if [{cond}]\no<s{k}> return [{value}]\no{label} endif\n"
            ));
        }
        let end = match next(2) {
            0 => format!(" [{}]", macro_expr(&mut next, &["#1", "#2"], 1)),
            _ => String::new(),
        };
        text.push_str(&format!("o<s{k}> endsub{end}\n"));
    }
    let vars = ["#31", "#<a>", "#<_g>", "#100"];
    for name in ["#31", "#<a>", "#100"] {
        text.push_str(&format!("{name} = [{}]\n", macro_expr(&mut next, &[], 1)));
    }
    macro_body(&mut next, &mut text, &vars, (0, breaks), subs, &mut label);
    text.push_str("M2\n");
    // rs274 reads lines of 256 characters at most: a longer move is cut to
    // its first word.
    text.lines()
        .map(|line| match line.len() > 250 {
            true => {
                let first = line.find(" Y").or(line.find(" Z")).unwrap_or(line.len());
                format!("{}\n", &line[..first.min(250)])
            }
            false => format!("{line}\n"),
        })
        .collect()
}

/// Statements of [`random_macro_program`] at `depth`, calling the first
/// `subs` subroutines; `breaks`: a program with `break`s and no `do` loop.
fn macro_body(
    next: &mut dyn FnMut(u64) -> u64,
    text: &mut String,
    vars: &[&str],
    (depth, breaks): (u32, bool),
    subs: u64,
    label: &mut u32,
) {
    let fold = |e: String| format!("[[{e}] MOD 100 - 50]");
    for _ in 0..2 + next(5) {
        match next(100) {
            0..=34 => {
                let mut words = Vec::new();
                for letter in ["X", "Y", "Z"] {
                    if next(3) > 0 {
                        words.push(format!("{letter}{}", fold(macro_expr(next, vars, 1))));
                    }
                }
                if words.is_empty() {
                    words.push(format!("X{}", fold(macro_expr(next, vars, 0))));
                }
                text.push_str(&format!("G{} {}\n", next(2), words.join(" ")));
            }
            35..=54 => {
                // Not a loop's counter.
                let settable: Vec<&str> = vars
                    .iter()
                    .copied()
                    .filter(|v| !v.starts_with("#<i"))
                    .collect();
                let target = settable[next(settable.len() as u64) as usize];
                let value = macro_expr(next, vars, 0);
                match next(3) {
                    // Several on a line: every value from before it, and
                    // #<c> read as 0 on the line of its first assignment.
                    0 => text.push_str(&format!(
                        "{target} = [{value}] #<b> = [{target} + 1] #<c> = [#<c> * 2 + 1]\nG1 X{}\n",
                        fold("#<b> + #<c>".into())
                    )),
                    _ => text.push_str(&format!("{target} = [{value}]\n")),
                }
            }
            55..=66 if depth < 2 => {
                *label += 1;
                let l = *label;
                text.push_str(&format!("o{l} if [{}]\n", macro_expr(next, vars, 0)));
                macro_body(next, text, vars, (depth + 1, breaks), subs, label);
                if next(2) == 0 {
                    text.push_str(&format!("o{l} elseif [{}]\n", macro_expr(next, vars, 0)));
                    macro_body(next, text, vars, (depth + 1, breaks), subs, label);
                }
                if next(2) == 0 {
                    text.push_str(&format!("o{l} else\n"));
                    macro_body(next, text, vars, (depth + 1, breaks), subs, label);
                }
                text.push_str(&format!("o{l} endif\n"));
            }
            67..=76 if depth < 2 => {
                *label += 1;
                let l = *label;
                let counter = format!("#<i{l}>");
                let limit = 1 + next(3);
                text.push_str(&format!("{counter} = [0]\n"));
                let looped: Vec<&str> = vars.iter().copied().chain([counter.as_str()]).collect();
                // rs274 ends a `do` loop after its first pass if a `break`
                // left a `while` before it (README): no `do` where there
                // may be a `break`.
                match next(3) {
                    0 if !breaks => {
                        text.push_str(&format!("o{l} do\n"));
                        macro_body(next, text, &looped, (depth + 1, breaks), subs, label);
                        text.push_str(&format!(
                            "{counter} = [{counter} + 1]\no{l} while [{counter} LT {limit}]\n"
                        ));
                    }
                    1 => {
                        text.push_str(&format!("o{l} repeat [{limit}]\n"));
                        macro_body(next, text, &looped, (depth + 1, breaks), subs, label);
                        text.push_str(&format!("o{l} endrepeat\n"));
                    }
                    _ => {
                        text.push_str(&format!("o{l} while [{counter} LT {limit}]\n"));
                        text.push_str(&format!("{counter} = [{counter} + 1]\n"));
                        macro_body(next, text, &looped, (depth + 1, breaks), subs, label);
                        if next(3) == 0 && breaks {
                            *label += 1;
                            let inner = *label;
                            text.push_str(&format!(
                                "o{inner} if [{counter} GT 1]\no{l} break\no{inner} endif\n"
                            ));
                        }
                        text.push_str(&format!("o{l} endwhile\n"));
                    }
                }
            }
            77..=86 if subs > 0 => {
                let k = next(subs);
                let args: Vec<String> = (0..next(3))
                    .map(|_| format!("[{}]", macro_expr(next, vars, 0)))
                    .collect();
                text.push_str(&format!(
                    "o<s{k}> call {}\nG1 X{} Y[#<_value_returned> * 10]\n",
                    args.join(" "),
                    fold("#<_value>".into())
                ));
            }
            87..=92 => text.push_str(["G91\n", "G90\n"][next(2) as usize]),
            _ => text.push_str(&format!(
                "G1 X{} F[{}]\n",
                fold(macro_expr(next, vars, 0)),
                200 + next(5) * 100
            )),
        }
    }
}

/// An expression of [`random_macro_program`] over `vars`.
fn macro_expr(next: &mut dyn FnMut(u64) -> u64, vars: &[&str], depth: u32) -> String {
    const LITERALS: [&str; 16] = [
        "0", "1", "2", "-1", "2.5", "-3.7", "0.5", "10", "90", "180", "270", "360", "45", "30",
        "0.00005", "-0.0002",
    ];
    let leaf = |next: &mut dyn FnMut(u64) -> u64| match next(3) {
        0 if !vars.is_empty() => vars[next(vars.len() as u64) as usize].to_string(),
        _ => LITERALS[next(LITERALS.len() as u64) as usize].to_string(),
    };
    if depth > 2 || next(10) < 3 {
        return leaf(next);
    }
    let sub = |next: &mut dyn FnMut(u64) -> u64| macro_expr(next, vars, depth + 1);
    match next(20) {
        0..=9 => {
            const OPS: [&str; 12] = [
                "+", "-", "*", "EQ", "NE", "GT", "GE", "LT", "LE", "AND", "OR", "XOR",
            ];
            let op = OPS[next(12) as usize];
            format!("[{} {op} {}]", sub(next), sub(next))
        }
        10 => format!("[{} / [ABS[{}] + 1]]", sub(next), sub(next)),
        11 => format!("[{} MOD [ABS[{}] + 1]]", sub(next), sub(next)),
        12 => format!(
            "[ABS[{}] ** {}]",
            sub(next),
            ["2", "0.5", "3", "1.5"][next(4) as usize]
        ),
        13..=15 => match next(3) {
            0 => format!("SIN[{}]", sub(next)),
            1 => format!("COS[{}]", sub(next)),
            _ => format!("TAN[[{}] MOD 80]", sub(next)),
        },
        16 => format!("ATAN[{}]/[{}]", sub(next), sub(next)),
        17 => format!("{}[SIN[{}]]", ["ACOS", "ASIN"][next(2) as usize], sub(next)),
        18 => format!(
            "{}[{}]",
            ["FIX", "FUP", "ROUND", "ABS"][next(4) as usize],
            sub(next)
        ),
        _ => match next(3) {
            0 => format!("SQRT[ABS[{}]]", sub(next)),
            1 => format!("LN[ABS[{}] + 1]", sub(next)),
            _ => format!("EXP[SIN[{}]]", sub(next)),
        },
    }
}

/// [`RANDOM_MACRO_PROGRAMS`] programs of [`random_macro_program`]: rs274
/// runs every one, and each one ger compiles must move as rs274 moves it;
/// two thirds must compile.
fn random_macros() -> Result<(), Failed> {
    let count = RANDOM_MACRO_PROGRAMS;
    random_trial("macros", count, random_macro_program, true, count * 2 / 3)
}

/// A case's name for its scratch files: its area and its stem, since two
/// areas may hold cases of one name (`fanuc/indirect`, `linuxcnc/indirect`)
/// and the trials run at the same time.
fn scratch_name(case: &Path) -> String {
    let area = case.parent().and_then(Path::file_name).unwrap_or_default();
    let stem = case.file_stem().unwrap_or_default();
    format!("{}-{}", area.to_string_lossy(), stem.to_string_lossy())
}

/// Where the machine stands when a `machine/` case starts (machine
/// coordinates, rs274's units), away from zero on every axis.
const START: [f64; 3] = [1.375, -2.625, 0.875];

/// `arcs`: `ij` or `r`, or `keep` for `--numbers keep`.
fn run_case(case: &Path, arcs: &str) -> Result<(), Failed> {
    let stem = format!("{}-{arcs}", scratch_name(case));
    let work = std::env::temp_dir().join(format!("ger-oracle-{}-{stem}", std::process::id()));
    std::fs::create_dir_all(&work).map_err(|e| e.to_string())?;
    let tools = case_tools(case);
    let mut input = case.to_path_buf();
    if !tools.is_empty() {
        // ger reads its tool table from SetTool directives (in mm here).
        let mut text = String::from("SetUnits \"mm\"\n");
        for t in &tools {
            text.push_str(&format!(
                "SetTool {} {} {}\n",
                t.number, t.diameter, t.length
            ));
        }
        text.push_str(&std::fs::read_to_string(case).map_err(|e| e.to_string())?);
        input = work.join(format!("{stem}.egc"));
        std::fs::write(&input, text).map_err(|e| e.to_string())?;
    }
    let out = work.join(format!("{stem}.out.nc"));
    // The case's wizards, wherever its input is written.
    let wizards = case.parent().unwrap().join("wizards");
    let fanuc = case.parent().unwrap().ends_with("fanuc");
    let dir = wizards.to_string_lossy().into_owned();
    let mut args = match arcs {
        "keep" => vec!["--numbers", "keep"],
        _ => vec!["--arcs", arcs],
    };
    if wizards.is_dir() {
        args.extend(["--wizards", &dir]);
    } else if fanuc {
        args.extend(["--from", "fanuc"]);
    }
    support::compile_with(&input, &out, &args)?;
    let text = std::fs::read_to_string(&out).map_err(|e| e.to_string())?;
    check_allowed_codes(&text)?;
    let reference = match case.with_extension("ngc") {
        r if r.exists() => r,
        _ => case.to_path_buf(),
    };
    let start = case.parent().unwrap().ends_with("machine").then_some(START);
    let a = rs274::tool_path_from(&reference, &tools, start)
        .map_err(|e| format!("the reference {} fails: {e}", reference.display()))?;
    let b = rs274::tool_path_from(&out, &tools, start)
        .map_err(|e| format!("ger's output fails: {e}"))?;
    // ger's own tool path (from its IR) is the one its output makes from
    // rs274's zero, where ger's own starts.
    let from_zero;
    let b_zero = match start {
        Some(_) => {
            from_zero =
                rs274::tool_path(&out, &tools).map_err(|e| format!("ger's output fails: {e}"))?;
            &from_zero
        }
        None => &b,
    };
    let own = own_tool_path(&input, &wizards, fanuc)?;
    let own = rs274::Reference::of(own, b.inch);
    rs274::same_path(b_zero, &own, &Default::default())
        .map_err(|why| format!("ger's tool path is not its output's: {why}"))?;
    // Compiling ger's output again changes nothing.
    let again = rs274::Reference::of(own_tool_path(&out, &wizards, fanuc)?, b.inch);
    rs274::same_path(b_zero, &again, &Default::default())
        .map_err(|why| format!("ger's output compiled again moves differently: {why}"))?;
    let _ = std::fs::remove_dir_all(&work);
    match rs274::same_path(&a, &b, &Default::default()) {
        Ok(_) => Ok(()),
        Err(why) => Err(format!(
            "{} and ger's output move differently: {why}\n--- ger output (first 40 lines) ---\n{}",
            reference.display(),
            text.lines().take(40).collect::<Vec<_>>().join("\n")
        )
        .into()),
    }
}

/// The case's tool table (`<name>.tbl`, mm), if it has one.
fn case_tools(case: &Path) -> Vec<rs274::Tool> {
    match std::fs::read_to_string(case.with_extension("tbl")) {
        Ok(text) => rs274::read_tool_table(&text),
        Err(_) => Vec::new(),
    }
}

/// `--cycles keep` or `--comp keep` (`keep`): rs274 must run ger's output
/// as it runs the input.
fn run_kept(case: &Path, keep: &str) -> Result<(), Failed> {
    let stem = scratch_name(case);
    let out = std::env::temp_dir().join(format!("ger-kept-{}-{stem}.nc", std::process::id()));
    support::compile_with(case, &out, &[keep, "keep", "--target", "linuxcnc"])?;
    let text = std::fs::read_to_string(&out).map_err(|e| e.to_string())?;
    let tools = case_tools(case);
    let a = rs274::tool_path(case, &tools).map_err(|e| format!("the input fails: {e}"))?;
    let b = rs274::tool_path(&out, &tools).map_err(|e| format!("ger's output fails: {e}"))?;
    let _ = std::fs::remove_file(&out);
    rs274::same_path(&a, &b, &Default::default())
        .map(|_| ())
        .map_err(|why| {
            format!(
                "{} and ger's output ({keep} keep) move differently: {why}\n--- ger output ---\n{text}",
                case.display()
            )
            .into()
        })
}

/// ger's own tool path of `input`, with the wizards of `folder`, found
/// and compiled as the command line does (`ger::driver::Session`).
fn own_tool_path(
    input: &Path,
    folder: &Path,
    fanuc: bool,
) -> Result<ger::toolpath::ToolPath, Failed> {
    use ger::driver::{discovery::Search, fs::Disk, Program, Session};
    let options = ger::driver::CompileOptions {
        from: fanuc.then_some(ger::eval::Flavour::Fanuc),
        ..Default::default()
    };
    let search = Search {
        wizard_path: vec![folder.to_path_buf()],
        ..Search::default()
    };
    let session = Session::new(&Disk, options, search).map_err(|e| e.to_string())?;
    let mut job = session
        .load(Program::Path(input))
        .map_err(|e| e.to_string())?;
    let (path, diagnostics) = job.tool_path();
    path.ok_or_else(|| ger::diagnostic::render(&job.sources, &diagnostics).into())
}

fn run_example(case: &Path) -> Result<(), Failed> {
    let stem = case.file_stem().unwrap().to_string_lossy().into_owned();
    let out = std::env::temp_dir().join(format!("ger-example-{}-{stem}.nc", std::process::id()));
    let warnings = support::compile(case, &out)?;
    if !warnings.is_empty() {
        return Err(format!("the example has warnings:\n{warnings}").into());
    }
    let text = std::fs::read_to_string(&out).map_err(|e| e.to_string())?;
    check_allowed_codes(&text)?;
    let result = rs274::tool_path(&out, &[]);
    let _ = std::fs::remove_file(&out);
    match result {
        Ok(_) => Ok(()),
        Err(e) => Err(format!("rs274 rejects the output: {e}").into()),
    }
}

/// SPEC §6: only these codes may appear in the output: the plain ones,
/// G54 (the frame known offsets are folded into) and what the passes pass
/// through because it depends on the machine.
fn check_allowed_codes(text: &str) -> Result<(), Failed> {
    const G: [&str; 38] = [
        "0", "1", "2", "3", "4", "17", "18", "19", "20", "21", "90", "00", "01", "54", "55", "56",
        "57", "58", "59", "59.1", "59.2", "59.3", "28", "30", "53", "43", "44", "49", "10", "61",
        "61.1", "64", "96", "97", "92", "92.1", "33", "33.1",
    ];
    const M: [&str; 13] = [
        "0", "1", "3", "4", "5", "6", "7", "8", "9", "30", "2", "00", "01",
    ];
    for (n, line) in text.lines().enumerate() {
        let code = strip_comments(line);
        let bytes = code.as_bytes();
        let mut i = 0;
        while i < bytes.len() {
            let c = bytes[i].to_ascii_uppercase();
            if c.is_ascii_alphabetic() {
                let start = i + 1;
                let mut end = start;
                while end < bytes.len()
                    && (bytes[end].is_ascii_digit() || b".+-".contains(&bytes[end]))
                {
                    end += 1;
                }
                let num = &code[start..end];
                let ok = match c {
                    // `G91 G28 Z0.`: home from an unknown point, passed
                    // through; `G91 G1 X5.`: steps from one (SPEC §4).
                    b'G' => {
                        G.contains(&num)
                            || (num == "91"
                                && ["G28", "G30", "G0 ", "G1 ", "G33 "]
                                    .iter()
                                    .any(|c| code.contains(c)))
                    }
                    b'M' => M.contains(&num),
                    b'X' | b'Y' | b'Z' | b'I' | b'J' | b'K' | b'R' | b'F' | b'S' | b'T' | b'P'
                    | b'N' | b'O' | b'H' | b'L' | b'A' | b'B' | b'C' | b'U' | b'V' | b'W' => true,
                    // G64's naive-CAM tolerance (path control passes through).
                    b'Q' => code.contains("G64"),
                    // G96's limit in rpm (the spindle mode passes through).
                    b'D' => code.contains("G96"),
                    _ => false,
                };
                if !ok {
                    return Err(format!(
                        "output line {} uses `{}{}`, which SPEC §6 does not allow: {line}",
                        n + 1,
                        c as char,
                        num
                    )
                    .into());
                }
                i = end;
            } else {
                i += 1;
            }
        }
    }
    Ok(())
}

fn strip_comments(line: &str) -> String {
    let mut out = String::new();
    let mut depth = 0;
    for ch in line.chars() {
        match ch {
            '(' => depth += 1,
            ')' if depth > 0 => depth -= 1,
            _ if depth == 0 => out.push(ch),
            _ => {}
        }
    }
    out
}
