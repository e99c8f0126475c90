//! Codegen: IR → G-code text (SPEC §6). Prints the program after any stage
//! (`--stage`), and the final output with its dialect, numbering, decimals
//! and arc format. It must not change what the program does: every choice
//! here is about spelling, except the final rounding, which it makes
//! consistent (arc centres are printed relative to the start as printed).

use crate::ir::{self, ArcGeometry, Motion, Op, Units};
use crate::source::{LineIndex, Span};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Numbering {
    /// N = the source line that produced the output line.
    #[default]
    Source,
    /// N10, N20, …
    Seq,
    None,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Dialect {
    #[default]
    Generic,
    Fanuc,
    Grbl,
    LinuxCnc,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ArcFormat {
    #[default]
    Ij,
    R,
    Lines,
}

#[derive(Clone, Debug)]
pub struct EmitOptions {
    pub numbering: Numbering,
    pub dialect: Dialect,
    pub arcs: ArcFormat,
    /// Decimals; `None`: 3 for mm, 4 for inch.
    pub decimals: Option<usize>,
    /// Chord tolerance for `--arcs lines`, in output units.
    pub tolerance: f64,
    /// Program number for dialects that want one.
    pub program_number: u32,
}

impl Default for EmitOptions {
    fn default() -> Self {
        EmitOptions {
            numbering: Numbering::Source,
            dialect: Dialect::Generic,
            arcs: ArcFormat::Ij,
            decimals: None,
            tolerance: 0.001,
            program_number: 1,
        }
    }
}

/// Prints the program as it stands after some stage: every statement as
/// written, modal codes included.
pub struct StagePrinter {
    p: Printer,
}

impl StagePrinter {
    pub fn new(units: Units, source: &str, main_file: usize) -> StagePrinter {
        StagePrinter {
            p: Printer::new(EmitOptions::default(), units, source, main_file),
        }
    }

    /// Print the next statements of the program; returns the text not
    /// yet taken (the caller may take it).
    pub fn print(&mut self, stmts: &[ir::Stmt]) -> &mut Vec<u8> {
        for stmt in stmts {
            self.p.begin(stmt.span);
            self.p.op_as_written(&stmt.op);
            self.p.end();
        }
        &mut self.p.out
    }

    /// The rest of the text.
    pub fn finish(self) -> Vec<u8> {
        self.p.out
    }
}

/// Prints the final program: absolute, one unit, only the codes of SPEC §6.
pub struct ProgramPrinter {
    p: Printer,
    /// Machine position per axis; `None` until the program sets it.
    position: [Option<f64>; 3],
}

impl ProgramPrinter {
    pub fn new(
        options: &EmitOptions,
        units: Units,
        source: &str,
        main_file: usize,
    ) -> ProgramPrinter {
        let mut p = Printer::new(options.clone(), units, source, main_file);
        p.header();
        ProgramPrinter {
            p,
            position: [None; 3],
        }
    }

    /// Print the next statements of the program; returns the text not
    /// yet taken (the caller may take it).
    pub fn print(&mut self, stmts: &[ir::Stmt]) -> &mut Vec<u8> {
        let p = &mut self.p;
        for stmt in stmts {
            match &stmt.op {
                Op::Move(m) => {
                    let end = [m.to.x, m.to.y, m.to.z];
                    p.final_move(stmt.span, m, self.position, end);
                    for (pos, e) in self.position.iter_mut().zip(end) {
                        if e.is_some() {
                            *pos = e;
                        }
                    }
                }
                // The header selected G17; repeat a plane only when it changes.
                Op::Plane(plane) if *plane == p.plane => {}
                // F goes on the next cutting move's line (and only if it changed).
                Op::Feed(f) => p.pending_feed = Some(*f),
                op => {
                    if matches!(op, Op::ChangeTool | Op::Stop(_)) {
                        // The operator may move the machine at a tool change or
                        // stop: write every axis of the next move again.
                        p.printed = [None; 3];
                    }
                    p.begin(stmt.span);
                    p.op_as_written(op);
                    p.end();
                }
            }
        }
        &mut p.out
    }

    /// The rest of the text.
    pub fn finish(mut self) -> Vec<u8> {
        if self.p.dialect == Dialect::Fanuc {
            self.p.out.extend_from_slice(b"%\n");
        }
        self.p.out
    }
}

struct Printer {
    /// Bytes, not chars: everything written is ASCII but comments, which
    /// come from `&str`, and every line is whole: the text is UTF-8.
    out: Vec<u8>,
    line: Vec<u8>,
    options: EmitOptions,
    dialect: Dialect,
    decimals: usize,
    /// 10^decimals.
    scale: f64,
    lines: LineIndex,
    main_file: usize,
    seq: u64,
    /// The `N… ` of the source line starting at `numbered_at`.
    number: Vec<u8>,
    numbered_at: Option<u32>,
    /// Last printed value of each axis (in units of 10^-decimals).
    printed: [Option<i64>; 3],
    plane: ir::Plane,
    units: Units,
    /// The tool of the last T word, for dialects that name it at M6.
    selected_tool: Option<u32>,
    /// Final output: a feed waiting for the next cutting move, and the last
    /// feed written.
    pending_feed: Option<f64>,
    printed_feed: Option<i64>,
}

impl Printer {
    fn new(options: EmitOptions, units: Units, source: &str, main_file: usize) -> Printer {
        // Nine decimals at most: a nanometre, and the grid fits an i64.
        let decimals = options
            .decimals
            .unwrap_or(match units {
                Units::Mm => 3,
                Units::Inch => 4,
            })
            .min(9);
        Printer {
            out: Vec::with_capacity((source.len() * 2).min(1 << 20)),
            line: Vec::with_capacity(80),
            dialect: options.dialect,
            options,
            decimals,
            scale: 10f64.powi(decimals as i32),
            lines: LineIndex::new(source),
            main_file,
            seq: 0,
            number: Vec::with_capacity(16),
            numbered_at: None,
            printed: [None; 3],
            plane: ir::Plane::XY,
            units,
            selected_tool: None,
            pending_feed: None,
            printed_feed: None,
        }
    }

    fn header(&mut self) {
        if self.dialect == Dialect::Fanuc {
            self.out.extend_from_slice(b"%\n");
            let number = format!("O{:04}\n", self.options.program_number % 10_000);
            self.out.extend_from_slice(number.as_bytes());
        }
        let units = match self.units {
            Units::Inch => "G20",
            Units::Mm => "G21",
        };
        self.raw_line(&format!("{units} G90 G17"));
    }

    fn numbered(&self) -> Numbering {
        if self.dialect == Dialect::Grbl {
            Numbering::None
        } else {
            self.options.numbering
        }
    }

    fn raw_line(&mut self, text: &str) {
        if self.numbered() == Numbering::Seq {
            self.seq += 10;
            self.out
                .extend_from_slice(format!("N{} ", self.seq).as_bytes());
        }
        self.out.extend_from_slice(text.as_bytes());
        self.out.push(b'\n');
    }

    fn begin(&mut self, span: Span) {
        self.line.clear();
        match self.numbered() {
            Numbering::Source if span.file == self.main_file => {
                // A loop prints many lines from one source line.
                if self.numbered_at != Some(span.start) {
                    self.number.clear();
                    self.number.push(b'N');
                    push_int(&mut self.number, self.lines.line(span.start) as i64);
                    self.number.push(b' ');
                    self.numbered_at = Some(span.start);
                }
                self.line.extend_from_slice(&self.number);
            }
            Numbering::Seq => {
                self.seq += 10;
                self.line.push(b'N');
                push_int(&mut self.line, self.seq as i64);
                self.line.push(b' ');
            }
            _ => {}
        }
    }

    fn end(&mut self) {
        if self.line.last() == Some(&b' ') {
            self.line.pop();
        }
        self.out.extend_from_slice(&self.line);
        self.out.push(b'\n');
    }

    /// A space before the next word, unless the line is empty or has one.
    fn separate(&mut self) {
        if !self.line.is_empty() && self.line.last() != Some(&b' ') {
            self.line.push(b' ');
        }
    }

    /// A word whose value is already on the output grid: `q` units of
    /// 10^-decimals (what [`Printer::word`] would print for `q / scale`).
    fn word_q(&mut self, letter: char, q: i64) {
        self.separate();
        self.line.push(letter as u8);
        push_scaled(&mut self.line, q, self.decimals);
    }

    fn word(&mut self, letter: char, v: f64) {
        self.separate();
        self.line.push(letter as u8);
        push_fixed_bytes(&mut self.line, v, self.decimals);
    }

    fn code(&mut self, text: &str) {
        self.separate();
        self.line.extend_from_slice(text.as_bytes());
    }

    fn axes(&mut self, a: &ir::Axes) {
        for (letter, v) in [('X', a.x), ('Y', a.y), ('Z', a.z)] {
            if let Some(v) = v {
                self.word(letter, v);
            }
        }
    }

    fn op_as_written(&mut self, op: &Op) {
        match op {
            Op::Move(m) => {
                self.code(motion_code(m.motion));
                self.axes(&m.to);
                if let Some(arc) = &m.arc {
                    match arc.geometry {
                        ArcGeometry::Center(c) => {
                            for (letter, v) in [('I', c.x), ('J', c.y), ('K', c.z)] {
                                if let Some(v) = v {
                                    self.word(letter, v);
                                }
                            }
                        }
                        ArcGeometry::Radius(r) => self.word('R', r),
                    }
                    if arc.turns > 1 {
                        self.code(&format!("P{}", arc.turns));
                    }
                }
            }
            Op::Feed(f) => self.word('F', *f),
            Op::Speed(s) => self.word('S', *s),
            Op::SelectTool(t) => {
                self.selected_tool = Some(*t);
                self.code(&format!("T{t}"));
            }
            Op::ChangeTool => {
                if self.dialect == Dialect::Grbl {
                    // GRBL has no tool changer: stop and tell the operator.
                    let text = match self.selected_tool {
                        Some(t) => format!("M0 (change to tool {t})"),
                        None => "M0 (tool change)".to_string(),
                    };
                    self.code(&text);
                } else {
                    self.code("M6");
                }
            }
            Op::Spindle(s) => self.code(match s {
                ir::Spindle::Clockwise => "M3",
                ir::Spindle::CounterClockwise => "M4",
                ir::Spindle::Off => "M5",
            }),
            Op::Coolant(c) => self.code(match c {
                ir::Coolant::Mist => "M7",
                ir::Coolant::Flood => "M8",
                ir::Coolant::Off => "M9",
            }),
            Op::Dwell(seconds) => {
                self.code("G4");
                self.word(
                    if self.dialect == Dialect::Fanuc {
                        'X'
                    } else {
                        'P'
                    },
                    *seconds,
                );
            }
            Op::Stop(ir::Stop::Program) => self.code("M0"),
            Op::Stop(ir::Stop::Optional) => self.code("M1"),
            Op::End => self.code(if self.dialect == Dialect::Grbl {
                "M2"
            } else {
                "M30"
            }),
            Op::Units(Units::Inch) => self.code("G20"),
            Op::Units(Units::Mm) => self.code("G21"),
            Op::Distance(ir::Distance::Absolute) => self.code("G90"),
            Op::Distance(ir::Distance::Incremental) => self.code("G91"),
            Op::Plane(plane) => {
                self.plane = *plane;
                self.code(match plane {
                    ir::Plane::XY => "G17",
                    ir::Plane::ZX => "G18",
                    ir::Plane::YZ => "G19",
                })
            }
            Op::SelectWorkOffset(i) => self.code(&format!("G{}", 53 + *i as u32)),
            Op::SetWorkOffset { index, origin } => {
                self.code(&format!("G10 L2 P{index}"));
                self.axes(origin);
            }
            Op::SetWorkOffsetHere { index, at } => {
                self.code(&format!("G10 L20 P{index}"));
                self.axes(at);
            }
            Op::LocalOffset(a) => {
                self.code("G52");
                self.axes(a);
            }
            Op::SetPosition(a) => {
                self.code("G92");
                self.axes(a);
            }
            Op::CancelPosition => self.code("G92.1"),
            Op::ToolLength { tool, negative } => self.code(&format!(
                "{} H{tool}",
                if *negative { "G44" } else { "G43" }
            )),
            Op::CancelToolLength => self.code("G49"),
            Op::Polar(true) => self.code("G16"),
            Op::Polar(false) => self.code("G15"),
            Op::CompOff => self.code("G40"),
            Op::CycleOff => self.code("G80"),
            Op::Comment(text) => {
                let clean: String = text
                    .chars()
                    .map(|c| {
                        if c == '(' || c == ')' || c == '\n' {
                            ' '
                        } else {
                            c
                        }
                    })
                    .collect();
                self.code(&format!("({clean})"));
            }
        }
    }

    /// `v` on the output grid. Positions are limited well inside it (the
    /// absolute pass); the clamp only makes sure that no input can make a
    /// difference of two overflow.
    fn scaled(&self, v: f64) -> i64 {
        round_to_int(v * self.scale).clamp(-(1 << 61), 1 << 61)
    }

    fn unscaled(&self, n: i64) -> f64 {
        n as f64 / self.scale
    }

    /// A move in the final output: absolute, unchanged axes left out, arc
    /// centres relative to the start point as printed. The absolute pass
    /// guarantees that an arc's plane axes are known.
    fn final_move(
        &mut self,
        span: Span,
        m: &ir::Move,
        start: [Option<f64>; 3],
        end: [Option<f64>; 3],
    ) {
        let end_q = end.map(|v| v.map(|v| self.scaled(v)));
        let start = start.map(|v| v.unwrap_or(0.0));
        let end = std::array::from_fn(|i| end[i].unwrap_or(start[i]));
        let start_q: [i64; 3] =
            std::array::from_fn(|i| self.printed[i].unwrap_or_else(|| self.scaled(start[i])));
        let Some(arc) = m.arc.filter(|_| m.motion.is_arc()) else {
            return self.linear(span, m.motion, end_q);
        };
        let ArcGeometry::Center(c) = arc.geometry else {
            return self.linear(span, ir::Motion::Linear, end_q);
        };
        let center = [
            start[0] + c.x.unwrap_or(0.0),
            start[1] + c.y.unwrap_or(0.0),
            start[2] + c.z.unwrap_or(0.0),
        ];
        let clockwise = m.motion == Motion::ArcCw;
        if self.options.arcs == ArcFormat::Lines {
            let points = crate::geometry::arc_points(
                start,
                end,
                center,
                self.plane,
                clockwise,
                arc.turns,
                self.options.tolerance,
            );
            for point in points {
                let q = point.map(|v| Some(self.scaled(v)));
                self.linear(span, Motion::Linear, q);
            }
            return;
        }
        let end_q: [i64; 3] = std::array::from_fn(|i| end_q[i].unwrap_or(start_q[i]));
        self.begin(span);
        self.code(motion_code(m.motion));
        let (a, b, _) = self.plane.axes();
        for axis in 0..3 {
            // Both in-plane axes always, so a full circle has an end.
            if axis == a || axis == b || Some(end_q[axis]) != self.printed[axis] {
                self.word_q(AXES[axis], end_q[axis]);
                self.printed[axis] = Some(end_q[axis]);
            }
        }
        let full = start_q[a] == end_q[a] && start_q[b] == end_q[b];
        if self.options.arcs == ArcFormat::R && arc.turns == 1 && !full {
            // SPEC §4: of the start and end radii, the larger is used.
            let r = (center[a] - start[a])
                .hypot(center[b] - start[b])
                .max((center[a] - end[a]).hypot(center[b] - end[b]));
            let long = crate::geometry::is_long_arc(start, end, center, self.plane, clockwise);
            self.word('R', if long { -r } else { r });
        } else {
            let printed_center =
                self.round_center(start, end, center, start_q, end_q, clockwise, arc.turns);
            for axis in [a, b] {
                self.word_q(CENTER[axis], printed_center[axis] - start_q[axis]);
            }
        }
        if arc.turns > 1 {
            self.code(&format!("P{}", arc.turns));
        }
        self.feed_word();
        self.end();
    }

    /// Write the pending feed on a cutting move's line, if it changed.
    fn feed_word(&mut self) {
        if let Some(f) = self.pending_feed.take() {
            let q = self.scaled(f);
            if self.printed_feed != Some(q) {
                self.word_q('F', q);
                self.printed_feed = Some(q);
            }
        }
    }

    /// The centre to print, on the output grid. Rounding start, end and
    /// centre independently can turn a half circle by more than the
    /// rounding itself; of the grid points around the exact centre, take
    /// the one that keeps centre, sweep and radius closest to the exact arc.
    #[allow(clippy::too_many_arguments)]
    fn round_center(
        &self,
        start: [f64; 3],
        end: [f64; 3],
        center: [f64; 3],
        start_q: [i64; 3],
        end_q: [i64; 3],
        clockwise: bool,
        turns: u32,
    ) -> [i64; 3] {
        use crate::geometry::sweep;
        let (a, b, _) = self.plane.axes();
        let exact_sweep = sweep(start, end, center, self.plane, clockwise, turns);
        let radius = (start[a] - center[a]).hypot(start[b] - center[b]);
        let s = start_q.map(|q| self.unscaled(q));
        let e = end_q.map(|q| self.unscaled(q));
        let base = center.map(|v| self.scaled(v));
        let error_of = |q: [i64; 3]| {
            let c = q.map(|v| self.unscaled(v));
            let moved = (c[a] - center[a]).hypot(c[b] - center[b]);
            let turned =
                (sweep(s, e, c, self.plane, clockwise, turns) - exact_sweep).abs() * radius;
            let rs = (s[a] - c[a]).hypot(s[b] - c[b]);
            let re = (e[a] - c[a]).hypot(e[b] - c[b]);
            moved.max(turned).max((rs - re).abs())
        };
        // Plain rounding is usually as good as the grid allows.
        let mut best = (error_of(base), base);
        if best.0 <= 0.75 / self.scale {
            return base;
        }
        for da in -1..=1 {
            for db in -1..=1 {
                let mut q = base;
                q[a] += da;
                q[b] += db;
                let error = error_of(q);
                if error < best.0 {
                    best = (error, q);
                }
            }
        }
        best.1
    }

    /// A straight move to the known axes of `end_q`; nothing if none changed.
    fn linear(&mut self, span: Span, motion: Motion, end_q: [Option<i64>; 3]) {
        let changed: [bool; 3] =
            std::array::from_fn(|i| end_q[i].is_some() && end_q[i] != self.printed[i]);
        if !changed.iter().any(|&c| c) {
            return;
        }
        self.begin(span);
        self.code(motion_code(motion));
        for axis in 0..3 {
            if changed[axis] {
                let q = end_q[axis].unwrap_or_default();
                self.word_q(AXES[axis], q);
                self.printed[axis] = Some(q);
            }
        }
        if motion != Motion::Rapid {
            self.feed_word();
        }
        self.end();
    }
}

const AXES: [char; 3] = ['X', 'Y', 'Z'];
const CENTER: [char; 3] = ['I', 'J', 'K'];

fn motion_code(m: Motion) -> &'static str {
    match m {
        Motion::Rapid => "G0",
        Motion::Linear => "G1",
        Motion::ArcCw => "G2",
        Motion::ArcCcw => "G3",
    }
}

fn push_int(out: &mut Vec<u8>, n: i64) {
    if n < 0 {
        out.push(b'-');
    }
    let mut buf = [0u8; 20];
    let start = digits_before(&mut buf, 20, n.unsigned_abs());
    out.extend_from_slice(&buf[start..]);
}

/// Write the decimal digits of `n` (at least one) into `buf`, ending just
/// before `end`; returns where they start.
fn digits_before(buf: &mut [u8], mut end: usize, mut n: u64) -> usize {
    loop {
        end -= 1;
        buf[end] = b'0' + (n % 10) as u8;
        n /= 10;
        if n == 0 {
            return end;
        }
    }
}

/// `x` rounded half away from zero, as `f64::round` (without its libm
/// call); saturates like `as i64` outside the range of `i64`.
fn round_to_int(x: f64) -> i64 {
    // Below 2^52 the truncation and the fraction `x - t` are exact.
    if x.abs() < 4.5e15 {
        let t = x as i64;
        let fraction = x - t as f64;
        if fraction >= 0.5 {
            t + 1
        } else if fraction <= -0.5 {
            t - 1
        } else {
            t
        }
    } else {
        x.round() as i64
    }
}

/// A number with a decimal point and at most `decimals` decimals, trailing
/// zeros removed: `1.`, `-0.25`, `12.5`.
pub fn push_fixed_bytes(out: &mut Vec<u8>, v: f64, decimals: usize) {
    let decimals = decimals.min(9);
    let x = v * 10f64.powi(decimals as i32);
    if !v.is_finite() || v.abs() >= 1e12 || x.abs() >= 1e18 {
        out.extend_from_slice(format!("{v:.decimals$}").as_bytes());
        return;
    }
    push_scaled(out, round_to_int(x), decimals);
}

/// `q` × 10^-`decimals` (at most 18) as [`push_fixed_bytes`] writes it.
/// Written right to left into one buffer: the fraction's digits (its
/// trailing zeros, which come first, skipped), the point, the integer's
/// digits (at least one) and the sign.
fn push_scaled(out: &mut Vec<u8>, q: i64, decimals: usize) {
    let mut buf = [0u8; 32];
    let mut i = buf.len();
    let mut n = q.unsigned_abs();
    let mut significant = false;
    for _ in 0..decimals {
        let digit = (n % 10) as u8;
        n /= 10;
        significant |= digit != 0;
        if significant {
            i -= 1;
            buf[i] = b'0' + digit;
        }
    }
    i -= 1;
    buf[i] = b'.';
    i = digits_before(&mut buf, i, n);
    if q < 0 {
        i -= 1;
        buf[i] = b'-';
    }
    out.extend_from_slice(&buf[i..]);
}

/// [`push_fixed_bytes`] onto a `String`.
pub fn push_fixed(out: &mut String, v: f64, decimals: usize) {
    let mut bytes = Vec::with_capacity(24);
    push_fixed_bytes(&mut bytes, v, decimals);
    out.push_str(&String::from_utf8_lossy(&bytes));
}

#[cfg(test)]
mod tests {
    use super::{push_fixed, round_to_int};

    fn fixed(v: f64, d: usize) -> String {
        let mut s = String::new();
        push_fixed(&mut s, v, d);
        s
    }

    #[test]
    fn numbers_always_have_a_point() {
        assert_eq!(fixed(1.0, 3), "1.");
        assert_eq!(fixed(-0.25, 3), "-0.25");
        assert_eq!(fixed(12.0005, 3), "12.001");
        assert_eq!(fixed(-0.0001, 3), "0.");
        assert_eq!(fixed(0.05, 4), "0.05");
        assert_eq!(fixed(1234.5678, 4), "1234.5678");
    }

    #[test]
    fn rounding_is_half_away_from_zero_like_f64_round() {
        let ties = [0.5, 1.5, 2.5, -0.5, -1.5, -2.5, 0.49999999999999994];
        let edges = [4503599627370495.5, -4503599627370495.5, 4.5e15, 1e18, -1e19];
        for x in ties.into_iter().chain(edges) {
            assert_eq!(round_to_int(x), x.round() as i64, "{x}");
        }
    }

    /// The printer formats integers on the output grid; it must print
    /// what rounding the value and printing its digits would.
    #[test]
    fn fixed_point_matches_rounding_then_printing() {
        fn reference(v: f64, d: usize) -> String {
            let scale = 10u64.pow(d as u32);
            let n = (v * scale as f64).round() as i64;
            let sign = if n < 0 { "-" } else { "" };
            let n = n.unsigned_abs();
            let fraction = format!("{:0width$}", n % scale, width = d);
            format!("{sign}{}.{}", n / scale, fraction.trim_end_matches('0'))
        }
        let mut state = 0x2545_f491_4f6c_dd1du64;
        for i in 0..20_000 {
            // xorshift: values over many magnitudes, both signs.
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let unit = (state >> 11) as f64 / (1u64 << 53) as f64;
            let v = (unit - 0.5) * 10f64.powi((i % 13) as i32 - 4);
            let d = i % 10;
            assert_eq!(fixed(v, d), reference(v, d), "{v} with {d} decimals");
        }
    }
}
