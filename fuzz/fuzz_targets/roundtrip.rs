//! Structure-aware: generate a valid program (moves, arcs by centre and by
//! radius, G90/G91, G20/G21, planes, feeds, spindle, tools, dwells), compile
//! it, compile ger's own output again, and require the same tool path
//! three ways: source, output, output of the output; and the output with
//! `--arcs r` moves as the source does. Output that ger cannot read back,
//! or that moves differently, is a crash.
#![no_main]

use arbitrary::Arbitrary;
use ger::driver::{compile, tool_path, CompileOptions};
use ger::source::Sources;
use ger::toolpath::compare::{compare, Options};
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
enum Cmd {
    Rapid(i16, i16, i8),
    Feed(i16, i16, i8),
    /// An arc by centre offset (tenths of mm) and sweep (degrees).
    Arc { cw: bool, i: i8, j: i8, sweep: u16, dz: i8 },
    /// An arc by radius to a nearby end.
    ArcR { cw: bool, dx: i8, dy: i8, r: u8, long: bool },
    Incremental(bool),
    Inch(bool),
    Plane(u8),
    Feedrate(u16),
    Spindle(u16),
    Tool(u8),
    Dwell(u8),
}

fn num(v: f64) -> String {
    format!("{v:.4}")
}

fn program(cmds: &[Cmd]) -> String {
    let mut text = String::from("G21 G90 G17\nG0 X0 Y0 Z10\nF300\n");
    let mut inch = false;
    for cmd in cmds.iter().take(64) {
        let k = if inch { 1.0 / 25.4 } else { 1.0 };
        let line = match *cmd {
            Cmd::Rapid(x, y, z) => format!(
                "G0 X{} Y{} Z{}",
                num(f64::from(x) / 10.0 * k),
                num(f64::from(y) / 10.0 * k),
                num(f64::from(z) / 10.0 * k)
            ),
            Cmd::Feed(x, y, z) => format!(
                "G1 X{} Y{} Z{}",
                num(f64::from(x) / 10.0 * k),
                num(f64::from(y) / 10.0 * k),
                num(f64::from(z) / 10.0 * k)
            ),
            Cmd::Arc { cw, i, j, sweep, dz } => {
                // End on the circle: written incrementally, exact.
                let (ci, cj) = (f64::from(i) / 10.0, f64::from(j) / 10.0);
                if ci.hypot(cj) < 0.5 {
                    continue;
                }
                let a0 = (-cj).atan2(-ci);
                let turn = f64::from(sweep % 360 + 1).to_radians() * if cw { -1.0 } else { 1.0 };
                let r = ci.hypot(cj);
                let (ex, ey) = (ci + r * (a0 + turn).cos(), cj + r * (a0 + turn).sin());
                format!(
                    "G91 {} X{} Y{} Z{} I{} J{}\nG90",
                    if cw { "G2" } else { "G3" },
                    num(ex * k),
                    num(ey * k),
                    num(f64::from(dz) / 20.0 * k),
                    num(ci * k),
                    num(cj * k)
                )
            }
            Cmd::ArcR { cw, dx, dy, r, long } => {
                let (dx, dy) = (f64::from(dx) / 10.0, f64::from(dy) / 10.0);
                let half = dx.hypot(dy) / 2.0;
                let r = half + f64::from(r) / 10.0 + 0.1;
                if half < 0.05 {
                    continue;
                }
                format!(
                    "G91 {} X{} Y{} R{}\nG90",
                    if cw { "G2" } else { "G3" },
                    num(dx * k),
                    num(dy * k),
                    num(if long { -r } else { r } * k)
                )
            }
            Cmd::Incremental(on) => (if on { "G91" } else { "G90" }).to_string(),
            Cmd::Inch(on) => {
                inch = on;
                (if on { "G20" } else { "G21" }).to_string()
            }
            Cmd::Plane(p) => ["G17", "G18", "G19"][usize::from(p % 3)].to_string(),
            Cmd::Feedrate(f) => format!("F{}", f % 5000 + 1),
            Cmd::Spindle(s) => format!("M3 S{}", s % 20000 + 1),
            Cmd::Tool(t) => format!("T{} M6", t % 20 + 1),
            Cmd::Dwell(d) => format!("G4 P{}", f64::from(d) / 10.0),
        };
        text.push_str(&line);
        text.push('\n');
    }
    text.push_str("G17 G90\nM30\n");
    text
}

/// Four decimals: the output grid is finer than the input's (inch words
/// with four decimals are 2.54 µm apart), so rounding alone cannot move
/// an arc's sweep by the tolerance.
fn options() -> CompileOptions {
    let mut options = CompileOptions::default();
    options.emit.decimals = Some(4);
    options
}

fn compiled(text: &str) -> Option<String> {
    compiled_with(text, options())
}

fn compiled_with(text: &str, options: CompileOptions) -> Option<String> {
    let mut sources = Sources::new();
    let file = sources.add("p.egc", text.to_string());
    compile(&sources, file, &options, None).output
}

fn path(text: &str) -> Option<ger::toolpath::ToolPath> {
    let mut sources = Sources::new();
    let file = sources.add("p.egc", text.to_string());
    tool_path(&sources, file, &options(), None).0
}

fuzz_target!(|cmds: Vec<Cmd>| {
    let source = program(&cmds);
    // Arcs in G18/G19 with XY words, or G91 arcs after an unknown axis,
    // may be refused: then there is nothing to compare.
    let Some(first) = compiled(&source) else { return };
    let second = compiled(&first).unwrap_or_else(|| panic!("ger cannot read its own output:\n{first}"));
    let options = Options { tol: 0.002, ..Options::default() };
    let (a, b, c) = (path(&source), path(&first), path(&second));
    let (Some(a), Some(b), Some(c)) = (a, b, c) else {
        panic!("a path is missing:\n{source}\n---\n{first}");
    };
    if let Err(d) = compare(&a, &b, &options) {
        panic!("source and output move differently: {d}\n{source}\n---\n{first}");
    }
    if let Err(d) = compare(&b, &c, &options) {
        panic!("output and its output move differently: {d}\n{first}\n---\n{second}");
    }
    let mut r = self::options();
    r.emit.arcs = ger::emit::ArcFormat::R;
    let with_r = compiled_with(&source, r).unwrap_or_else(|| panic!("no --arcs r output:\n{source}"));
    let d = path(&with_r).unwrap_or_else(|| panic!("ger cannot read its --arcs r output:\n{with_r}"));
    if let Err(e) = compare(&a, &d, &options) {
        panic!("source and --arcs r output move differently: {e}\n{source}\n---\n{with_r}");
    }
});
