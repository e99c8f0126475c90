//! `--arcs fit`'s closing figures (issue 47): for every program of
//! `../shared/real` that has lines to fit, and for the shipped examples
//! written with `--arcs lines`, the moves and bytes of the plain output
//! (`--arcs ij`) and of the fitted one, and two deviations. The tool
//! paths compared: the input's against the fitted output's, by the
//! project's own comparison (`toolpath::compare`, sampled every
//! `GER_FIT_STEP` mm, default 0.01), the least tolerance that passes.
//! Its order-aware matching can lose its place where a path retraces
//! itself closer than the tolerance (a V-carve's medial axis), so each
//! arc is also measured against the lines it replaced, found by the
//! `(fit: …, lines a-b)` comments of `--stage fit`: every vertex to the
//! arc and every point of the arc to the lines, on the printed text,
//! apart from the proof. Then the speed: `ger compile` against `ger
//! compile --arcs fit` on the 200,000-move plain program of
//! `benches/vs_rs274.py` (medians of `GER_FIT_RUNS`, default 5, taken
//! in turn).
//!
//! `cargo bench --bench arcs_fit`; prints a Markdown table. Without
//! `../shared/real` only the examples are measured.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use ger::driver::{compile, tool_path, CompileOptions, Stage};
use ger::emit::ArcFormat;
use ger::source::Sources;
use ger::toolpath::compare::{compare, Options};
use ger::toolpath::ToolPath;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

fn main() {
    let step = env_or("GER_FIT_STEP", 0.01);
    let runs = env_or("GER_FIT_RUNS", 5.0) as usize;
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    println!(
        "| program | moves before → after | bytes before → after | tool paths compared (tolerance) | each arc against its lines |"
    );
    println!("|---|---|---|---|---|");
    let real = root.join("../shared/real");
    if !real.is_dir() {
        println!("\n(../shared/real absent: the shipped examples alone)");
    }
    let mut unchanged = Vec::new();
    let only = std::env::var("GER_FIT_ONLY").unwrap_or_default();
    for path in files(&real) {
        if !path.to_string_lossy().contains(&only) {
            continue;
        }
        let text = String::from_utf8_lossy(&std::fs::read(&path).unwrap()).into_owned();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        match measure(&name, &text, step) {
            Some(row) => println!("{row}"),
            None => unchanged.push(name),
        }
    }
    if !unchanged.is_empty() {
        println!(
            "\nNothing fitted (or not compiled): {}",
            unchanged.join(", ")
        );
    }
    // (`GER_FIT_ONLY=<part of a name>` measures those real programs alone.)
    if !only.is_empty() {
        return;
    }
    for example in files(&root.join("examples")) {
        if example.extension().is_none_or(|e| e != "egc") {
            continue;
        }
        let stem = example.file_stem().unwrap().to_string_lossy().into_owned();
        let text = std::fs::read_to_string(&example).unwrap();
        let mut options = CompileOptions::default();
        options.emit.arcs = ArcFormat::Lines;
        let Some(lines) = compiled(&format!("{stem}.egc"), &text, &options).0 else {
            continue;
        };
        let name = format!("{stem}.ngc");
        if let Some(row) = measure(&name, &lines, step) {
            println!(
                "{}",
                row.replacen(
                    &name,
                    &format!("examples/{stem}, as `--arcs lines` output"),
                    1
                )
            );
        }
    }
    speed(root, runs);
}

fn env_or(name: &str, default: f64) -> f64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    files.retain(|p| {
        p.is_file()
            && !p
                .extension()
                .is_some_and(|e| e == "tsv" || e == "sh" || e == "md")
    });
    files.sort();
    files
}

/// The output of `text` (read as a file named `name`) and its tool path.
fn compiled(
    name: &str,
    text: &str,
    options: &CompileOptions,
) -> (Option<String>, Option<ToolPath>) {
    let mut sources = Sources::new();
    let file = sources.add(name, text.to_string());
    let output = compile(&sources, file, options, None).output;
    let path = tool_path(&sources, file, options, None).0;
    (output, path)
}

/// A row of the table, or `None` if nothing was fitted.
fn measure(name: &str, text: &str, step: f64) -> Option<String> {
    let plain = compiled(name, text, &CompileOptions::default());
    let (Some(before), Some(input_path)) = plain else {
        return None;
    };
    let mut options = CompileOptions::default();
    options.emit.arcs = ArcFormat::Fit;
    let after = compiled(name, text, &options).0?;
    let (moves_before, moves_after) = (moves(&before), moves(&after));
    if moves_after == moves_before {
        return None;
    }
    // The fitted output read back as plain G-code: what a controller runs.
    let fitted_path = compiled("fitted.ngc", &after, &CompileOptions::default()).1?;
    // (A program's first G20 or G21 is written where it comes.)
    let has = |code: &str| before.lines().any(|l| l.split(' ').any(|w| w == code));
    let (inch, units) = (has("G20"), has("G20") || has("G21"));
    // The default tolerance in mm (0.0002 in where the units are inches;
    // 0.0002 where they are unknown).
    let tolerance = match (inch, units) {
        (true, _) => 0.00508,
        (_, true) => 0.005,
        // In the tool path, a program without units is in mm.
        (_, false) => 0.0002,
    };
    let deviation = match largest_deviation(&input_path, &fitted_path, step, tolerance) {
        Ok(d) => format!("{d:.4} mm ({tolerance} mm)"),
        Err(why) => format!("beyond {:.4} mm: {why}", 4.0 * tolerance),
    };
    options.stage = Some(Stage::Fit);
    let named = compiled(name, text, &options).0?;
    let mm = if inch { 25.4 } else { 1.0 };
    let (per_arc, measured, skipped) = per_arc_deviation(&before, &named, tolerance / mm);
    let skipped = if skipped > 0 {
        format!(", {skipped} not measured")
    } else {
        String::new()
    };
    let per_arc = format!("{:.4} mm ({measured} arcs{skipped})", per_arc * mm);
    let less = |a: usize, b: usize| 100.0 * (a as f64 - b as f64) / a as f64;
    Some(format!(
        "| {name}{} | {} → {} (−{:.0} %) | {} → {} (−{:.0} %) | {deviation} | {per_arc} |",
        match (inch, units) {
            (true, _) => " (inch)",
            (_, false) => " (no units)",
            _ => "",
        },
        thousands(moves_before),
        thousands(moves_after),
        less(moves_before, moves_after),
        thousands(before.len()),
        thousands(after.len()),
        less(before.len(), after.len()),
    ))
}

/// The moves (G0–G3 lines) of an output.
fn moves(text: &str) -> usize {
    text.lines()
        .filter(|l| l.split(' ').any(|w| matches!(w, "G0" | "G1" | "G2" | "G3")))
        .count()
}

/// The least tolerance (mm, within 5 %) at which the sampled paths
/// agree, searched upward from 0.1 µm: a pass at any tolerance bounds
/// the deviation, but a fail does not prove it larger (the order-aware
/// matching, like `compare.py`'s, can lose its place among features
/// smaller than a large tolerance, so a larger one may fail where a
/// smaller passed). Up to four times `tolerance`; else the difference
/// there.
fn largest_deviation(a: &ToolPath, b: &ToolPath, step: f64, tolerance: f64) -> Result<f64, String> {
    let differ = |tol: f64| {
        let options = Options {
            tol,
            sample: Some(step),
            ..Options::default()
        };
        compare(a, b, &options).err().map(|d| d.to_string())
    };
    let mut tol = 1e-4;
    while tol <= 4.0 * tolerance {
        if differ(tol).is_none() {
            return Ok(tol);
        }
        tol *= 1.05;
    }
    let why = differ(4.0 * tolerance).unwrap_or_default();
    Err(why.lines().next().unwrap_or_default().to_string())
}

/// One move of an output: where it starts and ends, its motion code, its
/// N word, its I/J (an arc's), and the lines of the
/// `(fit: n moves, lines a-b)` comment of `--stage fit`.
struct Printed {
    n: Option<u32>,
    motion: u8,
    start: [f64; 3],
    end: [f64; 3],
    ij: Option<[f64; 2]>,
    /// The first and last source line of a fitted arc's run.
    fit: Option<(u32, u32)>,
    xy: bool,
}

/// The moves of an output of ger (absolute, an unchanged axis left out).
fn printed_moves(text: &str) -> Vec<Printed> {
    let (mut at, mut xy, mut out) = ([0.0f64; 3], true, Vec::new());
    for line in text.lines() {
        let (words, comment) = line.split_once('(').unwrap_or((line, ""));
        let (mut n, mut motion, mut end, mut ij) = (None, None, at, [None, None]);
        for word in words.trim_start_matches('/').split_whitespace() {
            let (letter, value) = word.split_at(1);
            let v: f64 = value.parse().unwrap_or(f64::NAN);
            match letter {
                "N" => n = Some(v as u32),
                "G" if matches!(value, "0" | "1" | "2" | "3") => motion = Some(v as u8),
                "G" if value == "17" => xy = true,
                "G" if value == "18" || value == "19" => xy = false,
                "X" => end[0] = v,
                "Y" => end[1] = v,
                "Z" => end[2] = v,
                "I" => ij[0] = Some(v),
                "J" => ij[1] = Some(v),
                _ => {}
            }
        }
        let Some(motion) = motion else { continue };
        let fit = comment
            .split_once("line")
            .map(|(_, lines)| lines.trim_start_matches('s').trim().trim_end_matches(')'))
            .and_then(|lines| {
                let (a, b) = lines.split_once('-').unwrap_or((lines, lines));
                Some((a.parse().ok()?, b.parse().ok()?))
            });
        out.push(Printed {
            n,
            motion,
            start: at,
            end,
            ij: ij[0].zip(ij[1]).map(|(i, j)| [i, j]),
            fit,
            xy,
        });
        at = end;
    }
    out
}

/// The largest distance, in output units, between each arc of `fitted`
/// (`--stage fit` output, I/J) and the lines of `plain` it replaced,
/// both ways, measured on the printed text apart from the proof: the arc
/// run as the proof and a controller run it (angle, radius and the
/// normal axis linear from start to end), sampled every `tolerance / 20`;
/// each sample to the nearest segment and each vertex to the nearest
/// chord of samples, searched in order in a window (a nearer point
/// outside it is missed, so the figure can only be too large). And the
/// arcs measured, and those that could not be (another plane).
fn per_arc_deviation(plain: &str, fitted: &str, tolerance: f64) -> (f64, usize, usize) {
    let lines = printed_moves(plain);
    let (mut worst, mut measured, mut skipped) = (0.0f64, 0, 0);
    for arc in printed_moves(fitted) {
        let (Some((a, b)), Some(ij)) = (arc.fit, arc.ij) else {
            continue;
        };
        // The run's lines as printed (a move that goes nowhere is not).
        let within = |l: &Printed| l.n.is_some_and(|n| (a..=b).contains(&n)) && l.motion == 1;
        let Some(first) = lines.iter().position(within) else {
            skipped += 1;
            continue;
        };
        if !arc.xy {
            skipped += 1;
            continue;
        }
        let mut vertices = vec![lines[first].start];
        vertices.extend(
            lines[first..]
                .iter()
                .take_while(|l| within(l))
                .map(|l| l.end),
        );
        let samples = arc_samples(&arc, ij, tolerance / 20.0);
        worst = worst.max(one_way(&samples, &vertices, false));
        worst = worst.max(one_way(&vertices, &samples, true));
        measured += 1;
    }
    (worst, measured, skipped)
}

/// Points along a printed arc at most `spacing` apart.
fn arc_samples(arc: &Printed, ij: [f64; 2], spacing: f64) -> Vec<[f64; 3]> {
    use std::f64::consts::TAU;
    let c = [arc.start[0] + ij[0], arc.start[1] + ij[1]];
    let (vs, ve) = (
        [arc.start[0] - c[0], arc.start[1] - c[1]],
        [arc.end[0] - c[0], arc.end[1] - c[1]],
    );
    let (rs, re) = (vs[0].hypot(vs[1]), ve[0].hypot(ve[1]));
    let a0 = vs[1].atan2(vs[0]);
    let turn = ve[1].atan2(ve[0]) - a0;
    let sweep = if arc.motion == 2 {
        -(-turn).rem_euclid(TAU)
    } else {
        turn.rem_euclid(TAU)
    };
    let k = ((sweep.abs() * rs.max(re) / spacing).ceil() as usize).clamp(2, 200_000);
    (0..=k)
        .map(|i| {
            let t = i as f64 / k as f64;
            let (a, r) = (a0 + sweep * t, rs + (re - rs) * t);
            [
                c[0] + r * a.cos(),
                c[1] + r * a.sin(),
                arc.start[2] + (arc.end[2] - arc.start[2]) * t,
            ]
        })
        .collect()
}

/// The largest distance from a point of `from` to the polyline `to`,
/// both in order (each point's nearest segment searched in a window
/// about the last one's).
fn one_way(from: &[[f64; 3]], to: &[[f64; 3]], dense_target: bool) -> f64 {
    // A vertex's nearest sample may lie far ahead of the last one's
    // (segments of uneven length): that search goes to the end.
    let per = (to.len() / from.len().max(1)).max(1);
    let (back, ahead) = if dense_target {
        (per + 64, to.len())
    } else {
        (8, 64)
    };
    let (mut at, mut worst) = (0usize, 0.0f64);
    for p in from {
        let window = at.saturating_sub(back)..(at + ahead).min(to.len() - 1);
        let (j, d) = window
            .map(|j| (j, segment_distance(*p, to[j], to[j + 1])))
            .fold((at, f64::MAX), |b, c| if c.1 < b.1 { c } else { b });
        worst = worst.max(d);
        at = j;
    }
    worst
}

fn segment_distance(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let ab = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let ap = [p[0] - a[0], p[1] - a[1], p[2] - a[2]];
    let len2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
    let t = if len2 > 0.0 {
        ((ap[0] * ab[0] + ap[1] * ab[1] + ap[2] * ab[2]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let d = [0, 1, 2].map(|i| p[i] - (a[i] + ab[i] * t));
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

fn thousands(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// `ger compile` against `ger compile --arcs fit` on the benchmark's
/// 200,000-move plain program (written by `vs_rs274.py`'s
/// `plain_program`, so it is the same program), `-o` a file.
fn speed(root: &Path, runs: usize) {
    let dir = std::env::temp_dir().join(format!("ger-arcs-fit-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let program = dir.join("plain.ngc");
    let script = format!(
        "import sys; sys.path.insert(0, {:?}); from vs_rs274 import plain_program; \
         open({:?}, 'w').write(plain_program(200000))",
        root.join("benches").display().to_string(),
        program.display().to_string()
    );
    let made = Command::new("python3").args(["-c", &script]).status();
    if !made.is_ok_and(|s| s.success()) {
        println!("\nspeed: python3 could not write the benchmark's program");
        return;
    }
    let ger = env!("CARGO_BIN_EXE_ger");
    let out = dir.join("out.ngc");
    let run = |fit: bool| {
        let mut cmd = Command::new(ger);
        cmd.arg("compile").arg(&program).arg("-o").arg(&out);
        if fit {
            cmd.args(["--arcs", "fit"]);
        }
        let t = Instant::now();
        let status = cmd.stderr(std::process::Stdio::null()).status().unwrap();
        assert!(status.success());
        t.elapsed().as_secs_f64()
    };
    let (mut plain, mut fit) = (Vec::new(), Vec::new());
    for _ in 0..runs {
        plain.push(run(false));
        fit.push(run(true));
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let (p, f) = (median(&mut plain), median(&mut fit));
    println!(
        "\n200,000-move plain program (medians of {runs}, in turn): plain {p:.3} s, \
         --arcs fit {f:.3} s: {:.2}× (goal ≤ 1.5×)",
        f / p
    );
    let _ = std::fs::remove_dir_all(dir);
}
