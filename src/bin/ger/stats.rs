//! `ger stats`: the program's run time on the machine of `ger.toml`
//! (`ger::plan`), lengths and tools, as a table or one JSON object.

use crate::args::Options;
use crate::{load_failed, session_and_machine};
use ger::diagnostic::render;
use ger::plan::{Figures, Limits, Tally};
use std::process::ExitCode;

/// `ger stats INPUT [--json]`.
pub fn print_stats(input: &str, options: &Options, json: bool) -> ExitCode {
    let (mut session, machine) = match session_and_machine(input, options, None) {
        Ok(loaded) => loaded,
        Err(code) => return code,
    };
    let limits = match machine.as_ref().map(Limits::of) {
        None => None,
        Some(Ok(limits)) => Some(limits),
        Some(Err(why)) => {
            eprintln!("error: ger.toml's [machine] cannot be planned with: {why}");
            return ExitCode::from(2);
        }
    };
    let program = match crate::program(input) {
        Ok(program) => program,
        Err(code) => return code,
    };
    // Planned as the back end makes the moves, on the back end's thread
    // (the evaluator's runs every lowering pass), the file read a part at
    // a time as a compile reads it: neither the path nor the text is held.
    let mut tally = Tally::new(limits.as_ref(), false);
    let finished = session.feed_tool_path(program, &mut tally);
    let lengths_known = tally.lengths_known();
    let mut figures = tally.finish();
    let finished = match finished {
        Ok(finished) => finished,
        Err(e) => return load_failed(e),
    };
    if let Some(e) = finished.read_error {
        eprintln!("error: cannot read `{input}`: {e}");
        return ExitCode::from(2);
    }
    if finished.lines_unshown {
        eprintln!("note: `{input}` could not be read again to show its lines");
    }
    let diagnostics = &finished.report.diagnostics;
    eprint!("{}", render(&finished.job.sources, diagnostics));
    if diagnostics.iter().any(ger::diagnostic::is_error) {
        return ExitCode::from(1);
    }
    if lengths_known {
        let mut job = finished.job;
        tip_bounds(&mut figures, |tips| match input {
            // Standard input is read once: the job holds it whole.
            "-" => {
                job.options.lower.tip_path = true;
                job.feed_tool_path(tips);
            }
            path => {
                session.set_tip_path(true);
                let path = ger::driver::Program::Path(std::path::Path::new(path));
                let _ = session.feed_tool_path(path, tips);
            }
        });
    }
    let controller = machine.map(|m| match m.controller {
        ger::driver::machine::Controller::Grbl => "grbl",
        ger::driver::machine::Controller::LinuxCnc => "linuxcnc",
    });
    if json {
        let object = serde_json::json!({
            "units": "mm",
            "planned_on": controller,
            "time_s": figures.time_s,
            "feed_time_s": figures.feed_time_s,
            "cut_mm": figures.cut_mm,
            "rapid_mm": figures.rapid_mm,
            "dwell_s": figures.dwell_s,
            "tool_changes": figures.tool_changes,
            "spindle_starts": figures.spindle_starts,
            "tools": figures.tools,
            "operations": figures.operations,
        });
        println!("{object}");
    } else {
        print!("{}", table(&figures, controller));
    }
    ExitCode::SUCCESS
}

/// The tools' and operations' bounds where the tip cuts: with tool
/// lengths known, `G43` folds them into the moves (the machine's
/// controlled point, which the times are of), so the tip's path is made
/// again by `feed` for its bounds alone (length / feed, no planner).
fn tip_bounds(figures: &mut Figures, feed: impl FnOnce(&mut Tally<'_>)) {
    let mut tips = Tally::new(None, false);
    feed(&mut tips);
    let tips = tips.finish();
    let same = |a: &Figures| {
        a.tools.len() == figures.tools.len() && a.operations.len() == figures.operations.len()
    };
    if !same(&tips) {
        return;
    }
    for (tool, tip) in figures.tools.iter_mut().zip(tips.tools) {
        tool.bounds = tip.bounds;
    }
    for (op, tip) in figures.operations.iter_mut().zip(tips.operations) {
        op.bounds = tip.bounds;
    }
}

/// The figures as a person reads them.
fn table(f: &Figures, controller: Option<&str>) -> String {
    let mut out = String::new();
    let line = |out: &mut String, text: String| {
        out.push_str(&text);
        out.push('\n');
    };
    match (f.time_s, controller) {
        (Some(t), Some(c)) => line(
            &mut out,
            format!(
                "run time        {}  (planned as {c} plans it; length / feed: {})",
                clock(t),
                clock(f.feed_time_s)
            ),
        ),
        _ => line(
            &mut out,
            format!(
                "run time        {}  (length / feed only, rapids not timed: no [machine] in ger.toml)",
                clock(f.feed_time_s)
            ),
        ),
    }
    line(&mut out, format!("cut             {:.1} mm", f.cut_mm));
    line(&mut out, format!("rapid           {:.1} mm", f.rapid_mm));
    line(
        &mut out,
        format!(
            "dwells {:.1} s, tool changes {}, spindle starts {}",
            f.dwell_s, f.tool_changes, f.spindle_starts
        ),
    );
    for t in &f.tools {
        let time = t.time_s.map_or(clock(t.feed_time_s), clock);
        let bounds = t.bounds.map_or(String::from("no cut"), |[lo, hi]| {
            format!(
                "X {:.3}…{:.3}  Y {:.3}…{:.3}  Z {:.3}…{:.3}",
                lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]
            )
        });
        line(
            &mut out,
            format!(
                "tool {:<4}       {time}  cut {:.1} mm  {bounds}",
                t.tool, t.cut_mm
            ),
        );
    }
    if f.operations.len() > 1 {
        for op in &f.operations {
            let time = op.time_s.map_or(clock(op.feed_time_s), clock);
            line(
                &mut out,
                format!(
                    "operation at line {:<5} tool {:<4} {time}  cut {:.1} mm  rapid {:.1} mm",
                    op.line, op.tool, op.cut_mm, op.rapid_mm
                ),
            );
        }
    }
    out
}

/// Seconds as `h:mm:ss` (or `m:ss.s` under an hour).
fn clock(seconds: f64) -> String {
    let s = seconds.max(0.0);
    match s >= 3600.0 {
        true => {
            let whole = s.round() as u64;
            format!("{}:{:02}:{:02}", whole / 3600, whole / 60 % 60, whole % 60)
        }
        false => format!("{}:{:04.1}", (s / 60.0).floor() as u64, s % 60.0),
    }
}
