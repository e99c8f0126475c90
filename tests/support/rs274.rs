//! LinuxCNC's standalone interpreter `rs274` as the reference for what a
//! program means: run it on a program, read its canonical calls into
//! ger's tool-path type (machine coordinates, mm), so that two programs'
//! paths can be compared with `ger::toolpath::compare`.
//!
//! How it is run (what rs274 needs, learnt from `../shared/oracle`):
//! a fresh parameter file each run (rs274 writes it back at exit), a tool
//! table in inches (rs274's machine units), every block prefixed with
//! `N<source line>` so the N column of its output names the line, one
//! rs274 at a time (two at once crash: a file lock serialises them across
//! test processes), and a time limit.
//!
//! A spline (G5, G5.1) rs274 prints as `NURBS_FEED(n, ...)`, without its
//! shape or its end (LinuxCNC's task layer makes it arcs): compared with a
//! program that cuts it, the other path's moves from the spline's source
//! line (the N words ger writes) stand in for it, so that everything
//! around it is compared, and where it leaves the tool. Its shape is
//! checked against the curve itself elsewhere (`geometry::spline`).

use ger::ir::{PathControl, Plane, Spindle, Stop};
use ger::source::Span;
use ger::toolpath::{ArcPath, Event, EventKind, Move, MoveKind, Point, State, ToolPath};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const INSTALL: &str = "install LinuxCNC's rs274 with `apt-get install linuxcnc-uspace` \
                       (Debian/Ubuntu), then run the tests again";

/// Is rs274 installed? Looked up on `PATH`, never run: even `rs274
/// --help` truncates the tool data file (`~/.tool.mmap`) every rs274
/// maps, so a probe beside another test's rs274 killed it (SIGBUS).
pub fn available() -> bool {
    use std::os::unix::fs::PermissionsExt;
    std::env::var_os("PATH").is_some_and(|paths| {
        std::env::split_paths(&paths).any(|dir| {
            std::fs::metadata(dir.join("rs274"))
                .is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
        })
    })
}

/// Must the differential tests run (CI)? Then a missing rs274 fails them.
pub fn required() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true" || v == "1")
        || std::env::var("GER_REQUIRE_ORACLE").is_ok_and(|v| v == "1")
}

/// The message of a test that cannot run.
pub fn missing() -> String {
    format!("rs274 is not installed: {INSTALL}")
}

/// A tool of the table: number, diameter and length in mm.
#[derive(Clone, Copy, Debug)]
pub struct Tool {
    pub number: u32,
    pub diameter: f64,
    pub length: f64,
}

/// Read a LinuxCNC tool table (`T1 P1 D6 Z50 ;comment`), lengths in mm.
pub fn read_tool_table(text: &str) -> Vec<Tool> {
    let mut tools = Vec::new();
    for line in text.lines() {
        let fields = line.split(';').next().unwrap_or("");
        let get = |k: char| {
            fields
                .split_whitespace()
                .find(|f| f.starts_with(k) || f.starts_with(k.to_ascii_lowercase()))
                .and_then(|f| f[1..].parse::<f64>().ok())
        };
        if let Some(t) = get('T') {
            tools.push(Tool {
                number: t as u32,
                diameter: get('D').unwrap_or(0.0),
                length: get('Z').unwrap_or(0.0),
            });
        }
    }
    tools
}

/// The program's tool path as rs274 runs it, or rs274's error with its
/// source line.
pub fn tool_path(program: &Path, tools: &[Tool]) -> Result<Reference, String> {
    tool_path_from(program, tools, None)
}

/// [`tool_path`] with the machine first moved to `start` (machine
/// coordinates, rs274's units: a `G53 G0` block numbered 0): where a
/// program leaves its start to the machine (`G92 X0 Y0 Z0` before any
/// move, steps from where the tool stands), a start other than rs274's
/// zero shows whether a translation kept that, or took the zero for it.
pub fn tool_path_from(
    program: &Path,
    tools: &[Tool],
    start: Option<[f64; 3]>,
) -> Result<Reference, String> {
    let (calls, n_words) = run(program, tools, start)?;
    let inch = calls
        .iter()
        .any(|c| c.name == "USE_LENGTH_UNITS" && c.args.contains("INCH"));
    let (path, splines) = normalize(&calls);
    Ok(Reference {
        path,
        inch,
        splines,
        n_words,
    })
}

/// A path read from rs274, and whether it printed inches.
pub struct Reference {
    pub path: ToolPath,
    pub inch: bool,
    /// Each spline: the index of the move that stands for it (its shape
    /// and end unknown), and its source line.
    pub splines: Vec<(usize, u32)>,
    /// The N word each line of the program had (ger's source line).
    pub n_words: std::collections::HashMap<u32, u32>,
}

impl Reference {
    /// A path made otherwise (ger's own), with no spline.
    pub fn of(path: ToolPath, inch: bool) -> Reference {
        Reference {
            path,
            inch,
            splines: Vec::new(),
            n_words: Default::default(),
        }
    }

    /// The path with each spline replaced by `other`'s moves from its
    /// source line (by `other`'s N words), the move after it starting
    /// where they end.
    fn with_splines_of(&self, other: &Reference) -> Result<ToolPath, String> {
        let mut path = self.path.clone();
        let mut shift = 0usize;
        for &(at, line) in &self.splines {
            let run: Vec<Move> = other
                .path
                .moves
                .iter()
                .filter(|m| other.n_words.get(&m.span.line) == Some(&line))
                .cloned()
                .collect();
            let Some(last) = run.last().map(|m| m.end) else {
                return Err(format!(
                    "rs274 cuts a spline at line {line}; the other program has no move from that line"
                ));
            };
            let at = at + shift;
            let added = run.len() - 1;
            path.moves.splice(at..=at, run);
            if let Some(next) = path.moves.get_mut(at + added + 1) {
                next.start = last;
            }
            for e in path.events.iter_mut().filter(|e| e.after_move > at) {
                e.after_move += added;
            }
            shift += added;
        }
        Ok(path)
    }

    /// rs274 prints 4 decimals: what a coordinate may be off by, in mm.
    pub fn quantum(&self) -> f64 {
        if self.inch {
            0.0001 * 25.4
        } else {
            0.0001
        }
    }
}

/// Compare a program with its translation, as the differential tests do:
/// within `tol` plus both paths' print resolution.
pub fn same_path(
    a: &Reference,
    b: &Reference,
    options: &ger::toolpath::compare::Options,
) -> Result<usize, String> {
    let options = ger::toolpath::compare::Options {
        tol: options.tol + a.quantum() + b.quantum(),
        ..options.clone()
    };
    let (pa, pb) = (a.with_splines_of(b)?, b.with_splines_of(a)?);
    ger::toolpath::compare::compare(&pa, &pb, &options).map_err(|d| d.to_string())
}

/// One canonical call: the source line (from the N word) and the call.
struct Call {
    line: u32,
    name: String,
    args: String,
}

/// The calls, and each line's N word as the program had it.
type Calls = (Vec<Call>, std::collections::HashMap<u32, u32>);

fn run(program: &Path, tools: &[Tool], start: Option<[f64; 3]>) -> Result<Calls, String> {
    let bytes = std::fs::read(program).map_err(|e| format!("{}: {e}", program.display()))?;
    let text = String::from_utf8_lossy(&bytes).replace("\r\n", "\n");
    let work = tempdir()?;
    let var = work.join("rs274.var");
    std::fs::write(&var, "").map_err(|e| e.to_string())?;
    let table = work.join("rs274.tbl");
    let mut tbl = String::new();
    if tools.is_empty() {
        // Any `T.. M6` works: tools 1..999, no size, no length.
        for t in 1..1000 {
            tbl.push_str(&format!("T{t} P{t} D0 Z0\n"));
        }
    }
    for t in tools {
        tbl.push_str(&format!(
            "T{0} P{0} D{1:.9} Z{2:.9}\n",
            t.number,
            t.diameter / 25.4,
            t.length / 25.4
        ));
    }
    std::fs::write(&table, tbl).map_err(|e| e.to_string())?;
    let name = program.file_name().unwrap_or_default();
    let numbered = work.join(name);
    let (mut numbered_text, n_words) = number_lines(&text);
    if let Some([x, y, z]) = start {
        // After a leading `%` line, which must stay first.
        let at = match numbered_text.trim_start().starts_with('%') {
            true => numbered_text
                .find('\n')
                .map_or(numbered_text.len(), |n| n + 1),
            false => 0,
        };
        numbered_text.insert_str(at, &format!("N0 G53 G0 X{x} Y{y} Z{z}\n"));
    }
    std::fs::write(&numbered, numbered_text).map_err(|e| e.to_string())?;

    let lock = std::fs::File::create(std::env::temp_dir().join("ger-rs274.lock"))
        .map_err(|e| e.to_string())?;
    lock.lock().map_err(|e| e.to_string())?;
    let child = Command::new("rs274")
        .arg("-g")
        .arg("-v")
        .arg(&var)
        .arg("-t")
        .arg(&table)
        .arg(&numbered)
        .current_dir(program.parent().unwrap_or(Path::new(".")))
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot run rs274: {e}; {INSTALL}"))?;
    let output = wait(child, Duration::from_secs(60));
    drop(lock);
    let _ = std::fs::remove_dir_all(&work);
    let output = output?;
    let stdout = String::from_utf8_lossy(&output.stdout);
    let mut calls = Vec::new();
    for line in stdout.lines() {
        if let Some(call) = parse_call(line) {
            calls.push(call);
        }
    }
    if !output.status.success() {
        let stderr = String::from_utf8_lossy(&output.stderr);
        let errors: Vec<&str> = stderr
            .lines()
            .filter(|l| {
                !l.trim().is_empty()
                    && !l.starts_with("executing")
                    && !l.starts_with("link (updating")
                    && !l.starts_with("Out-of-range")
            })
            .collect();
        let failed = format!("rs274 failed ({})", output.status);
        let message = errors.first().copied().unwrap_or(&failed);
        let line = errors
            .get(1)
            .and_then(|b| n_word(b.trim_start_matches([' ', '/'])));
        return Err(match line {
            Some(n) => format!("rs274: {message} at line {n}"),
            None => format!("rs274: {message}"),
        });
    }
    Ok((calls, n_words))
}

fn tempdir() -> Result<std::path::PathBuf, String> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static NEXT: AtomicUsize = AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!(
        "ger-rs274-{}-{}",
        std::process::id(),
        NEXT.fetch_add(1, Ordering::Relaxed)
    ));
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    Ok(dir)
}

/// Wait for rs274, killing it after `limit` (an endless loop).
fn wait(mut child: std::process::Child, limit: Duration) -> Result<std::process::Output, String> {
    let start = Instant::now();
    // Read the pipes on threads, so a full pipe cannot block rs274.
    let mut out = child.stdout.take();
    let mut err = child.stderr.take();
    let read_out = std::thread::spawn(move || {
        let mut v = Vec::new();
        if let Some(o) = out.as_mut() {
            let _ = std::io::Read::read_to_end(o, &mut v);
        }
        v
    });
    let read_err = std::thread::spawn(move || {
        let mut v = Vec::new();
        if let Some(e) = err.as_mut() {
            let _ = std::io::Read::read_to_end(e, &mut v);
        }
        v
    });
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break status,
            Ok(None) if start.elapsed() > limit => {
                let _ = child.kill();
                let _ = child.wait();
                return Err(format!("rs274 ran longer than {limit:?} (endless loop?)"));
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(2)),
            Err(e) => return Err(e.to_string()),
        }
    };
    Ok(std::process::Output {
        status,
        stdout: read_out.join().unwrap_or_default(),
        stderr: read_err.join().unwrap_or_default(),
    })
}

/// The line number of an `N…` word at the start of `text`.
fn n_word(text: &str) -> Option<u32> {
    let rest = text.strip_prefix(['N', 'n'])?;
    let digits: String = rest
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == ' ')
        .filter(char::is_ascii_digit)
        .collect();
    digits.parse().ok()
}

/// Every block prefixed with `N<line>` (an N word it has is replaced, and
/// kept in the map by line); blank lines and `%` lines are left alone.
fn number_lines(text: &str) -> (String, std::collections::HashMap<u32, u32>) {
    let mut n_words = std::collections::HashMap::new();
    let mut out = String::with_capacity(text.len() + text.len() / 4);
    for (i, line) in text.split('\n').enumerate() {
        let n = i + 1;
        let lead_len = line.len() - line.trim_start_matches([' ', '\t', '/']).len();
        let (lead, rest) = line.split_at(lead_len);
        if rest.trim().is_empty() || rest.starts_with('%') {
            out.push_str(line);
        } else if rest.starts_with(['N', 'n'])
            && rest[1..]
                .trim_start()
                .starts_with(|c: char| c.is_ascii_digit())
        {
            // Replace the N word: N, spaces and digits.
            if let Some(was) = n_word(rest) {
                n_words.insert(n as u32, was);
            }
            let after = rest[1..].trim_start_matches(|c: char| c.is_ascii_digit() || c == ' ');
            out.push_str(&format!("{lead}N{n} {after}"));
        } else {
            out.push_str(&format!("{lead}N{n} {rest}"));
        }
        out.push('\n');
    }
    out.pop();
    (out, n_words)
}

/// `   12 N0034  STRAIGHT_FEED(1.0000, 2.0000, ...)`
fn parse_call(line: &str) -> Option<Call> {
    let mut rest = line.trim_start();
    let seq_end = rest.find(|c: char| !c.is_ascii_digit())?;
    if seq_end == 0 {
        return None;
    }
    rest = rest[seq_end..].trim_start().strip_prefix('N')?;
    let n_end = rest.find(|c: char| c != '.' && !c.is_ascii_digit())?;
    let line_number = rest[..n_end].parse().unwrap_or(0);
    rest = rest[n_end..].trim_start();
    let open = rest.find('(')?;
    let close = rest.rfind(')')?;
    Some(Call {
        line: line_number,
        name: rest[..open].trim().to_string(),
        args: rest[open + 1..close].to_string(),
    })
}

fn numbers(args: &str) -> Vec<f64> {
    args.split([',', ' '])
        .filter_map(|t| t.trim().parse().ok())
        .collect()
}

/// The machine state while reading the calls.
struct Machine {
    /// mm per program unit.
    scale: f64,
    g5x: [f64; 6],
    g92: [f64; 6],
    tlo: [f64; 6],
    plane: Plane,
    state: State,
    selected: Option<u32>,
    position: [f64; 6],
    path: ToolPath,
}

impl Machine {
    /// A program point (x y z a b c) in machine coordinates, mm.
    fn to_machine(&self, p: &[f64]) -> [f64; 6] {
        std::array::from_fn(|i| {
            let v = p.get(i).copied().unwrap_or(0.0);
            let k = if i < 3 { self.scale } else { 1.0 };
            v * k + self.g92[i] + self.g5x[i] + self.tlo[i]
        })
    }

    fn push(&mut self, kind: MoveKind, end: [f64; 6], line: u32) {
        let start: Point = [self.position[0], self.position[1], self.position[2]];
        self.position = end;
        self.path.moves.push(Move {
            kind,
            start,
            end: [end[0], end[1], end[2]],
            extra: [end[3], end[4], end[5], 0.0, 0.0, 0.0],
            state: self.state,
            span: span(line),
            guessed: [false; 3],
        });
    }

    fn event(&mut self, kind: EventKind, line: u32) {
        self.path.events.push(Event {
            kind,
            after_move: self.path.moves.len(),
            span: span(line),
        });
    }

    /// The offsets of a `SET_*` call: lengths in the units active now.
    fn offsets(&self, v: &[f64]) -> [f64; 6] {
        std::array::from_fn(|i| {
            v.get(i).copied().unwrap_or(0.0) * if i < 3 { self.scale } else { 1.0 }
        })
    }
}

fn span(line: u32) -> Span {
    Span {
        file: 0,
        line,
        start: 0,
        end: 0,
    }
}

/// The path of the calls, and its splines ([`Reference::splines`]).
fn normalize(calls: &[Call]) -> (ToolPath, Vec<(usize, u32)>) {
    let mut splines = Vec::new();
    let mut m = Machine {
        scale: 1.0,
        g5x: [0.0; 6],
        g92: [0.0; 6],
        tlo: [0.0; 6],
        plane: Plane::XY,
        state: State::default(),
        selected: None,
        position: [0.0; 6],
        path: ToolPath::default(),
    };
    let wraps = cycle_wraps(calls);
    for (i, call) in calls.iter().enumerate() {
        if wraps.contains(&i) {
            continue;
        }
        let v = numbers(&call.args);
        match call.name.as_str() {
            "STRAIGHT_TRAVERSE" => m.push(MoveKind::Rapid, m.to_machine(&v), call.line),
            "STRAIGHT_FEED" | "STRAIGHT_PROBE" => {
                m.push(MoveKind::Feed, m.to_machine(&v), call.line)
            }
            "ARC_FEED" if v.len() >= 6 => arc(&mut m, &v, call.line),
            // G33.1: down to the point and back, reversing the spindle.
            "RIGID_TAP" => {
                let back = m.position;
                m.push(MoveKind::Feed, m.to_machine(&v), call.line);
                m.push(MoveKind::Feed, back, call.line);
            }
            // In the XY plane at the same Z; where it ends, unknown.
            "NURBS_FEED" => {
                splines.push((m.path.moves.len(), call.line));
                let mut end = m.position;
                end[0] = f64::NAN;
                end[1] = f64::NAN;
                m.push(MoveKind::Feed, end, call.line);
            }
            "USE_LENGTH_UNITS" => {
                m.scale = if call.args.contains("INCH") {
                    25.4
                } else {
                    1.0
                }
            }
            "SET_G5X_OFFSET" => m.g5x = m.offsets(v.get(1..).unwrap_or(&[])),
            "SET_G92_OFFSET" => m.g92 = m.offsets(&v),
            "USE_TOOL_LENGTH_OFFSET" => m.tlo = m.offsets(&v),
            "SELECT_PLANE" => {
                m.plane = match call.args.trim() {
                    a if a.ends_with("XZ") => Plane::ZX,
                    a if a.ends_with("YZ") => Plane::YZ,
                    _ => Plane::XY,
                }
            }
            // G33: the feeds between are K (mm) per spindle revolution.
            "START_SPEED_FEED_SYNC" => m.state.lead = v.first().map(|k| k * m.scale),
            "STOP_SPEED_FEED_SYNCH" => m.state.lead = None,
            "SET_FEED_RATE" => m.state.feed = v.first().copied().unwrap_or(0.0) * m.scale,
            "SELECT_TOOL" => m.selected = v.first().map(|&t| t as u32),
            "CHANGE_TOOL" | "CHANGE_TOOL_NUMBER" => {
                let t = match (call.name.as_str(), m.selected) {
                    ("CHANGE_TOOL", Some(t)) => t,
                    _ => v.first().map_or(0, |&t| t as u32),
                };
                m.state.tool = t;
                m.event(EventKind::ToolChange(t), call.line);
            }
            "SET_SPINDLE_SPEED" => m.state.rpm = v.get(1).copied().unwrap_or(0.0),
            "START_SPINDLE_CLOCKWISE" => m.state.spindle = Some(Spindle::Clockwise),
            "START_SPINDLE_COUNTERCLOCKWISE" => m.state.spindle = Some(Spindle::CounterClockwise),
            "STOP_SPINDLE_TURNING" => m.state.spindle = None,
            "FLOOD_ON" => m.state.flood = true,
            "FLOOD_OFF" => m.state.flood = false,
            "MIST_ON" => m.state.mist = true,
            "MIST_OFF" => m.state.mist = false,
            "DWELL" => m.event(
                EventKind::Dwell(v.first().copied().unwrap_or(0.0)),
                call.line,
            ),
            "PROGRAM_STOP" => m.event(EventKind::Stop(Stop::Program), call.line),
            "OPTIONAL_PROGRAM_STOP" => m.event(EventKind::Stop(Stop::Optional), call.line),
            "PROGRAM_END" => m.event(EventKind::End, call.line),
            "SET_MOTION_CONTROL_MODE" => {
                m.state.path_control = path_control(&call.args, &v, m.scale)
            }
            "SET_NAIVECAM_TOLERANCE" => {
                if let PathControl::Blend { naive, .. } = &mut m.state.path_control {
                    *naive = v.first().map(|q| q * m.scale);
                }
            }
            _ => {}
        }
    }
    (m.path, splines)
}

/// The path-control calls rs274 wraps each canned cycle in: exact path
/// for its moves, then the program's mode again, both at the cycle's
/// line (two modes on one line: no program sets that). The program's
/// state stays as it was; ger writes a cycle's moves without them.
fn cycle_wraps(calls: &[Call]) -> std::collections::HashSet<usize> {
    let mut wraps = std::collections::HashSet::new();
    let control = |c: &Call| c.name == "SET_MOTION_CONTROL_MODE";
    for (i, call) in calls.iter().enumerate() {
        if !control(call) || !call.args.contains("EXACT_PATH") || call.line == 0 {
            continue;
        }
        let Some(j) = (i + 1..calls.len()).find(|&j| control(&calls[j])) else {
            continue;
        };
        if calls[j].line == call.line {
            wraps.extend([i, j]);
            if calls
                .get(j + 1)
                .is_some_and(|c| c.name == "SET_NAIVECAM_TOLERANCE")
            {
                wraps.insert(j + 1);
            }
        }
    }
    wraps
}

/// `SET_MOTION_CONTROL_MODE(CANON_CONTINUOUS, tolerance)`, the tolerance in
/// the units active now.
fn path_control(args: &str, v: &[f64], scale: f64) -> PathControl {
    match args {
        a if a.contains("EXACT_PATH") => PathControl::ExactPath,
        a if a.contains("EXACT_STOP") => PathControl::ExactStop,
        _ => PathControl::Blend {
            tolerance: v.first().map(|p| p * scale),
            naive: None,
        },
    }
}

/// `ARC_FEED(first_end, second_end, first_axis, second_axis, rotation,
/// axis_end, a, b, c)`: the plane's axes in rs274's order (G18: Z, X).
fn arc(m: &mut Machine, v: &[f64], line: u32) {
    let (first_end, second_end, first_c, second_c, rotation, axis_end) =
        (v[0], v[1], v[2], v[3], v[4] as i32, v[5]);
    // Which program axis each of (first, second, axis) is.
    let order: [usize; 3] = match m.plane {
        Plane::XY => [0, 1, 2],
        Plane::ZX => [2, 0, 1],
        Plane::YZ => [1, 2, 0],
    };
    let mut end = [0.0; 6];
    let mut center = [0.0; 6];
    for (k, &axis) in order.iter().enumerate() {
        end[axis] = [first_end, second_end, axis_end][k];
        center[axis] = [first_c, second_c, axis_end][k];
    }
    for i in 0..3 {
        end[3 + i] = v.get(6 + i).copied().unwrap_or(0.0);
    }
    let end = m.to_machine(&end);
    let mut c = m.to_machine(&center);
    // The centre in the start point's plane.
    let normal = order[2];
    c[normal] = m.position[normal];
    m.push(
        MoveKind::Arc(ArcPath {
            center: [c[0], c[1], c[2]],
            plane: m.plane,
            clockwise: rotation < 0,
            turns: rotation.unsigned_abs().max(1),
        }),
        end,
        line,
    );
}
