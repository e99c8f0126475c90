//! The line writer: N numbers, words and codes of one output line at a
//! time, and the spelling of every statement as written. It decides
//! nothing about what to print; the stage and program printers do.

use super::number::{push_fixed_bytes, push_int, push_line_word, push_scaled, to_grid};
use super::{Numbering, Target};
use crate::ir::{self, ArcGeometry, CompRadius, Motion, Op, Passthrough, Units};
use crate::source::Span;

pub(super) struct Printer {
    /// Bytes, not chars: everything written is ASCII but comments and
    /// passed-through lines, which come from `&str`, and every line is
    /// whole: the text is UTF-8.
    pub out: Vec<u8>,
    /// Where the line being written starts in `out` (lines are written in
    /// place: each is whole before `out` is taken, but for the line end of
    /// an open line).
    line_start: usize,
    numbering: Numbering,
    pub target: Target,
    pub decimals: usize,
    /// 10^decimals.
    scale: f64,
    main_file: u32,
    /// The last `--numbers seq` number (`--arcs fit` rewinds it); under
    /// `--numbers keep`, the last source line whose N was written.
    pub seq: u64,
    /// The arc plane as printed so far.
    pub plane: ir::Plane,
    /// The tool of the last T word, for targets that name it at M6.
    selected_tool: Option<u32>,
    /// Whether codes share the line of their source line's move (the
    /// final program; `--stage` prints a statement a line).
    pub joins: bool,
    /// The line just written, while the next statements of its source
    /// line may still join it.
    open: Option<OpenLine>,
    /// G93 printed and in force (a stage before `absolute`): an F is the
    /// inverse of a time, not a length, and keeps all its digits.
    inverse_time: bool,
}

/// A line of codes that run before the motion of their block: the rest
/// of its source line may join it (codes later in rs274's order of
/// execution, then the move).
#[derive(Clone, Copy, PartialEq, Eq)]
struct OpenLine {
    file: u32,
    line: u32,
    block_delete: bool,
    /// The last code's place in rs274's order ([`Target::before_motion`]).
    rank: u8,
}

/// The motion's place in a block: after every code that may share its line.
const MOTION: u8 = u8::MAX;

/// Where the printer is, to go back to: the text and the numbering as
/// they were (`--arcs fit` prints a run twice).
#[derive(Clone, Copy)]
pub(super) struct Mark {
    len: usize,
    line_start: usize,
    open: Option<OpenLine>,
    seq: u64,
}

impl Printer {
    pub fn new(
        numbering: Numbering,
        target: Target,
        decimals: Option<usize>,
        units: Option<Units>,
        main_file: usize,
        capacity: usize,
    ) -> Printer {
        // In unknown units, enough for inches.
        let decimals = decimals
            .unwrap_or(match units {
                Some(Units::Mm) => 3,
                Some(Units::Inch) | None => 4,
            })
            .min(super::MOST_DECIMALS);
        Printer {
            out: Vec::with_capacity(capacity.min(1 << 20)),
            line_start: 0,
            numbering: if target.takes_line_numbers() {
                numbering
            } else {
                Numbering::None
            },
            target,
            decimals,
            scale: 10f64.powi(decimals as i32),
            main_file: main_file as u32,
            seq: 0,
            plane: ir::Plane::XY,
            selected_tool: None,
            joins: false,
            open: None,
            inverse_time: false,
        }
    }

    pub fn mark(&self) -> Mark {
        Mark {
            len: self.out.len(),
            line_start: self.line_start,
            open: self.open,
            seq: self.seq,
        }
    }

    /// Back to `mark`.
    pub fn rewind(&mut self, mark: Mark) {
        self.out.truncate(mark.len);
        (self.line_start, self.open, self.seq) = (mark.line_start, mark.open, mark.seq);
    }

    /// End the open line. Its line end waits for what comes next (which
    /// may join it): the caller may take the text written so far at any
    /// statement, and what it writes must not depend on where.
    pub fn close(&mut self) {
        if self.open.take().is_some() {
            self.out.push(b'\n');
        }
    }

    /// Go on with the open line if `stmt` may join it (same source line,
    /// and after all of it in rs274's order: `rank`, or the motion); the
    /// line is open after it with `rank`, or closed.
    fn join_or_begin(&mut self, stmt: &ir::Stmt, rank: u8) {
        let line = OpenLine {
            file: stmt.span.file,
            line: stmt.span.line,
            block_delete: stmt.block_delete,
            rank,
        };
        let joins = self.open.is_some_and(|open| {
            open.rank < line.rank && OpenLine { rank: 0, ..open } == OpenLine { rank: 0, ..line }
        });
        if joins {
            // (The line may have been taken: its words go on after a
            // space, measured from here.)
            self.line_start = self.out.len();
            self.out.push(b' ');
        } else {
            self.begin_stmt(stmt);
        }
        self.open = (self.joins && rank != MOTION && stmt.span.line > 0).then_some(line);
    }

    /// Start the line of a move from `stmt`, on the codes of its source
    /// line written before it where they may share it.
    pub fn begin_move(&mut self, stmt: &ir::Stmt) {
        self.join_or_begin(stmt, MOTION);
    }

    /// A line ger makes up (the header): numbered only by `seq`.
    pub fn raw_line(&mut self, text: &str) {
        self.close();
        self.line_start = self.out.len();
        if self.numbering == Numbering::Seq {
            self.seq_number();
        }
        self.out.extend_from_slice(text.as_bytes());
        self.end();
    }

    /// Text written as it is, outside the numbering (tape marks).
    pub fn raw(&mut self, text: &str) {
        self.close();
        self.out.extend_from_slice(text.as_bytes());
    }

    fn seq_number(&mut self) {
        self.seq += 10;
        self.out.push(b'N');
        push_int(&mut self.out, self.seq as i64);
        self.out.push(b' ');
    }

    /// Start the line of `stmt`.
    pub fn begin_stmt(&mut self, stmt: &ir::Stmt) {
        self.begin(stmt.span, stmt.block_delete, stmt.number);
    }

    /// Start the line of a statement from `span`, whose source line has
    /// the N word `number`.
    pub fn begin(&mut self, span: Span, block_delete: bool, number: Option<u32>) {
        self.close();
        self.line_start = self.out.len();
        if block_delete {
            self.out.push(b'/');
        }
        match self.numbering {
            Numbering::Source if self.main_line(span).is_some() => {
                push_line_word(&mut self.out, span.line);
            }
            Numbering::Seq => self.seq_number(),
            // Once per source line: on the first output line it makes, the
            // first time it runs (a loop's next turns, a jump back, repeat
            // no N).
            Numbering::Keep
                if self
                    .main_line(span)
                    .is_some_and(|l| u64::from(l) > self.seq) =>
            {
                if let Some(n) = number {
                    self.seq = u64::from(span.line);
                    self.out.push(b'N');
                    push_int(&mut self.out, i64::from(n));
                    self.out.push(b' ');
                }
            }
            Numbering::Source | Numbering::Keep | Numbering::None => {}
        }
    }

    /// The line of the main file `span` starts on, if it is there.
    pub fn main_line(&self, span: Span) -> Option<u32> {
        (span.file == self.main_file && span.line > 0).then_some(span.line)
    }

    pub fn end(&mut self) {
        if self.out.len() > self.line_start && self.out.last() == Some(&b' ') {
            self.out.pop();
        }
        if self.open.is_none() {
            self.out.push(b'\n');
        }
    }

    /// A space before the next word, unless the line is empty or has one.
    fn separate(&mut self) {
        if self.out.len() > self.line_start && self.out.last() != Some(&b' ') {
            self.out.push(b' ');
        }
    }

    /// A word whose value is already on the output grid: `q` units of
    /// 10^-decimals (what [`Printer::word`] would print for `q / scale`).
    pub fn word_q(&mut self, letter: u8, q: i64) {
        self.separate();
        self.out.push(letter);
        push_scaled(&mut self.out, q, self.decimals);
    }

    pub fn word(&mut self, letter: u8, v: f64) {
        self.word_decimals(letter, v, self.decimals);
    }

    /// [`Printer::word`] with `decimals` of its own (an R that needs more
    /// than the grid's).
    pub fn word_decimals(&mut self, letter: u8, v: f64, decimals: usize) {
        self.separate();
        self.out.push(letter);
        push_fixed_bytes(&mut self.out, v, decimals);
    }

    /// A word with an integer value (`T3`, `P2`, `H1`).
    fn int_word(&mut self, letter: u8, n: u32) {
        self.separate();
        self.out.push(letter);
        push_int(&mut self.out, n as i64);
    }

    pub fn code(&mut self, text: &str) {
        self.separate();
        self.out.extend_from_slice(text.as_bytes());
    }

    fn axes(&mut self, a: &ir::Axes) {
        for (axis, v) in a.iter() {
            self.word(axis.letter(), v);
        }
    }

    /// `v` on the output grid. Positions are limited well inside it (the
    /// absolute pass); the clamp only makes sure that no input can make a
    /// difference of two overflow.
    pub fn scaled(&self, v: f64) -> i64 {
        to_grid(v, self.scale).clamp(-(1 << 61), 1 << 61)
    }

    pub fn unscaled(&self, n: i64) -> f64 {
        n as f64 / self.scale
    }

    /// A statement on its own line, as written.
    pub fn stmt(&mut self, stmt: &ir::Stmt) {
        if let Op::ReadPosition(_) | Op::InverseTimeFloor(_) = stmt.op {
            // Not a code: what the source's controller does at a tool
            // change; the least feed under G93 its controller gives.
            return;
        }
        if let (Op::SetToolData(_), Target::Grbl) = (&stmt.op, self.target) {
            // grbl keeps no tool table: ger has folded the values where
            // they are used, and a G43 or G41 left to the machine is
            // refused at its own line.
            return;
        }
        if let Op::Passthrough(Passthrough::Line(text)) = &stmt.op {
            // A controller command (`$H`) takes no N word.
            self.close();
            self.line_start = self.out.len();
            if stmt.block_delete {
                self.out.push(b'/');
            }
            self.out.extend_from_slice(text.as_bytes());
            return self.end();
        }
        match self.target.before_motion(&stmt.op) {
            Some(rank) => self.join_or_begin(stmt, rank),
            None => self.begin_stmt(stmt),
        }
        self.op(&stmt.op);
        self.end();
        if let Op::Home {
            incremental: true, ..
        }
        | Op::IncrementalMove(_) = &stmt.op
        {
            self.back_to_absolute(stmt);
        }
    }

    /// G90 after `stmt`, written under G91, on a line of its own (one
    /// block cannot hold both distance modes).
    pub fn back_to_absolute(&mut self, stmt: &ir::Stmt) {
        self.begin(stmt.span, stmt.block_delete, None);
        self.code("G90");
        self.end();
    }

    /// The words of one statement, as written.
    pub fn op(&mut self, op: &Op) {
        match op {
            Op::Move(m) => self.move_words(m),
            Op::MachineMove(m) => {
                self.code("G53");
                self.move_words(m);
            }
            Op::IncrementalMove(m) => {
                self.code("G91");
                self.move_words(m);
            }
            Op::Home {
                home,
                via,
                incremental,
            } => self.home_words(*home, via, *incremental),
            // `F0.0001` under G93 is a move of 10,000 minutes, not `F0.`.
            Op::Feed(f) if self.inverse_time => self.word_decimals(b'F', *f, super::MOST_DECIMALS),
            Op::Feed(f) => self.word(b'F', *f),
            Op::Speed(s) => self.word(b'S', *s),
            Op::SpindleMode(ir::SpindleMode::Rpm) => self.code("G97"),
            Op::SpindleMode(ir::SpindleMode::SurfaceSpeed { speed, max_rpm }) => {
                self.code("G96");
                if let Some(d) = max_rpm {
                    self.word(b'D', *d);
                }
                self.word(b'S', *speed);
            }
            Op::SelectTool(t) => {
                self.selected_tool = Some(*t);
                self.int_word(b'T', *t);
            }
            Op::ChangeTool => {
                let text = self.target.tool_change(self.selected_tool);
                self.code(&text);
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
                self.word(self.target.dwell_letter(), *seconds);
            }
            Op::Stop(ir::Stop::Program) => self.code("M0"),
            Op::Stop(ir::Stop::Optional) => self.code("M1"),
            Op::End => self.code(self.target.program_end()),
            Op::Units(Units::Inch) => self.code("G20"),
            Op::Units(Units::Mm) => self.code("G21"),
            Op::Distance(ir::Distance::Absolute) => self.code("G90"),
            Op::Distance(ir::Distance::Incremental) => self.code("G91"),
            Op::ArcCenters(ir::Distance::Absolute) => self.code("G90.1"),
            Op::ArcCenters(ir::Distance::Incremental) => self.code("G91.1"),
            Op::InverseTime(on) => {
                self.inverse_time = *on;
                self.code(if *on { "G93" } else { "G94" })
            }
            Op::Plane(plane) => {
                self.plane = *plane;
                self.code(match plane {
                    ir::Plane::XY => "G17",
                    ir::Plane::ZX => "G18",
                    ir::Plane::YZ => "G19",
                })
            }
            Op::SelectWorkOffset(i) => self.code(ir::work_offset_code(*i).unwrap_or_default()),
            Op::SetToolData(data) => self.g10_tool(data),
            Op::SetWorkOffset { index, origin } => self.g10_words("G10 L2", *index, origin),
            Op::SetWorkOffsetHere { index, at } => self.g10_words("G10 L20", *index, at),
            Op::LocalOffset(a) => self.code_axes("G52", a),
            Op::SetPosition(a) => self.code_axes("G92", a),
            Op::CancelPosition => self.code("G92.1"),
            Op::ToolLength { tool, negative } => self.tool_length_words(*tool, *negative),
            Op::CancelToolLength => self.code("G49"),
            Op::Polar(true) => self.code("G16"),
            Op::Polar(false) => self.code("G15"),
            Op::DiameterMode(true) => self.code("G7"),
            Op::DiameterMode(false) => self.code("G8"),
            Op::ReturnLevel(ir::ReturnLevel::Initial) => self.code("G98"),
            Op::ReturnLevel(ir::ReturnLevel::R) => self.code("G99"),
            Op::Cycle(c) => self.cycle_words(c),
            Op::Spline(s) => self.spline_words(s),
            Op::RigidTap(t) => self.rigid_tap_words(t),
            Op::CycleOff => self.code("G80"),
            Op::Comp { side, radius } => self.comp_words(*side, *radius),
            Op::CompOff => self.code("G40"),
            Op::PathControl(pc) => self.path_control_words(*pc),
            Op::ReadPosition(_) | Op::InverseTimeFloor(_) => {}
            Op::Comment(text) => self.comment(text),
            Op::Passthrough(Passthrough::MCode { number, words }) => {
                self.int_word(b'M', *number);
                for &(letter, v) in words {
                    self.word(letter, v);
                }
            }
            Op::Passthrough(Passthrough::Line(text)) => self.code(text),
        }
    }

    /// G28/G30 and the via point; G91 first for zero steps from here.
    fn home_words(&mut self, home: ir::Home, via: &ir::Axes, incremental: bool) {
        if incremental {
            self.code("G91");
        }
        self.code(match home {
            ir::Home::G28 => "G28",
            ir::Home::G30 => "G30",
        });
        self.axes(via);
    }

    /// G10 L2/L20 P`index` and the axes.
    fn g10_words(&mut self, code: &str, index: u8, axes: &ir::Axes) {
        self.code(code);
        self.int_word(b'P', index as u32);
        self.axes(axes);
    }

    /// G10 L1 P`tool` and the values given (L10/L11: in a stage before
    /// the offsets pass, which makes them L1).
    fn g10_tool(&mut self, data: &ir::ToolData) {
        self.code(match data.measured {
            ir::Measured::Given => "G10 L1",
            ir::Measured::Here => "G10 L10",
            ir::Measured::InFixture => "G10 L11",
        });
        self.int_word(b'P', data.tool);
        let [q, i, j] = data.lathe;
        let words = [
            (b'R', data.radius),
            (b'Z', data.length),
            (b'Q', q),
            (b'I', i),
            (b'J', j),
        ];
        for (letter, v) in words {
            if let Some(v) = v {
                self.word(letter, v);
            }
        }
    }

    /// A code followed by axis words (G52, G92).
    fn code_axes(&mut self, code: &str, axes: &ir::Axes) {
        self.code(code);
        self.axes(axes);
    }

    /// G5 X Y I J P Q or G5.1 X Y I J: only a stage before the absolute
    /// pass, which makes splines arcs, prints one.
    fn spline_words(&mut self, s: &ir::Spline) {
        let words: &[(u8, f64)] = match s.kind {
            ir::SplineKind::Cubic { start, end } => &[
                (b'I', start[0]),
                (b'J', start[1]),
                (b'P', end[0]),
                (b'Q', end[1]),
            ],
            ir::SplineKind::Quadratic { control } => &[(b'I', control[0]), (b'J', control[1])],
        };
        let code = match s.kind {
            ir::SplineKind::Cubic { .. } => "G5",
            ir::SplineKind::Quadratic { .. } => "G5.1",
        };
        self.code_axes(code, &s.to);
        for &(letter, v) in words {
            self.word(letter, v);
        }
    }

    /// G43/G44, with H where the tool is named.
    fn tool_length_words(&mut self, tool: Option<u32>, negative: bool) {
        self.code(if negative { "G44" } else { "G43" });
        if let Some(tool) = tool {
            self.int_word(b'H', tool);
        }
    }

    /// A comment, with any parenthesis or line end inside it made a space
    /// (it must not close early or run on as code).
    pub fn comment(&mut self, text: &str) {
        self.separate();
        self.out.push(b'(');
        for c in text.chars() {
            let c = if matches!(c, '(' | ')' | '\n' | '\r') {
                ' '
            } else {
                c
            };
            let mut buf = [0u8; 4];
            self.out
                .extend_from_slice(c.encode_utf8(&mut buf).as_bytes());
        }
        self.out.push(b')');
    }

    fn move_words(&mut self, m: &ir::Move) {
        self.code(move_code(m));
        self.axes(&m.to);
        if let Some(lead) = m.lead {
            self.lead_word(lead);
        }
        // Only a stage before the corners pass has one (`--stage units`).
        if let Some(corner) = m.corner {
            let (letter, size) = match corner {
                ir::Corner::Round(r) => (b'R', r),
                ir::Corner::Chamfer(c) => (b'C', c),
            };
            self.separate();
            self.out.extend_from_slice(&[b',', letter]);
            push_fixed_bytes(&mut self.out, size, self.decimals);
        }
        let Some(arc) = &m.arc else { return };
        match arc.geometry {
            ArcGeometry::Center(c) => {
                for (letter, v) in [b'I', b'J', b'K'].into_iter().zip(c) {
                    if let Some(v) = v {
                        self.word(letter, v);
                    }
                }
            }
            ArcGeometry::Radius(r) => self.word(b'R', r),
        }
        if arc.turns > 1 {
            self.int_word(b'P', arc.turns);
        }
    }

    fn cycle_words(&mut self, c: &ir::Cycle) {
        if let Some(kept) = c.kept {
            self.code(match kept.level {
                ir::ReturnLevel::Initial => "G98",
                ir::ReturnLevel::R => "G99",
            });
        }
        self.separate();
        self.out.push(b'G');
        push_int(&mut self.out, c.kind.code() as i64);
        self.axes(&c.at);
        for (letter, v) in [(b'R', Some(c.r)), (b'Q', c.q)] {
            if let Some(v) = v {
                self.word(letter, v);
            }
        }
        if let Some(seconds) = c.dwell {
            match self.target {
                // Fanuc's cycle P is in milliseconds.
                Target::Fanuc => self.int_word(b'P', (seconds * 1000.0).round() as u32),
                Target::Generic | Target::Grbl | Target::LinuxCnc => self.word(b'P', seconds),
            }
        }
        for (letter, v) in [b'I', b'J', b'K'].into_iter().zip(c.ijk) {
            if let Some(v) = v {
                self.word(letter, v);
            }
        }
        if c.repeats != 1 {
            self.int_word(b'L', c.repeats);
        }
    }

    fn rigid_tap_words(&mut self, t: &ir::RigidTap) {
        self.code("G33.1");
        self.axes(&t.to);
        self.lead_word(t.lead);
        if let Some(i) = t.speedup {
            self.word(b'I', i);
        }
    }

    /// G33's K: two digits more than positions, as a pitch's error grows
    /// with every turn of the thread.
    pub fn lead_word(&mut self, lead: f64) {
        let decimals = self.decimals + 2;
        self.word_decimals(b'K', lead, decimals);
    }

    /// G61, G61.1, G64 P Q; on Fanuc G61 (its exact stop) and a bare
    /// G64 (it has no tolerance words). Grbl has none: the program
    /// printer leaves them out.
    fn path_control_words(&mut self, pc: ir::PathControl) {
        let fanuc = self.target == Target::Fanuc;
        match pc {
            ir::PathControl::ExactPath => self.code("G61"),
            ir::PathControl::ExactStop if fanuc => self.code("G61"),
            ir::PathControl::ExactStop => self.code("G61.1"),
            ir::PathControl::Blend { tolerance, naive } => {
                self.code("G64");
                if fanuc {
                    return;
                }
                // A tolerance is often finer than the grid of positions
                // (P0.0005 in mm): two digits more keep it.
                let decimals = self.decimals + 2;
                for (letter, v) in [(b'P', tolerance), (b'Q', naive)] {
                    if let Some(v) = v {
                        self.word_decimals(letter, v, decimals);
                    }
                }
            }
        }
    }

    fn comp_words(&mut self, side: ir::Side, radius: CompRadius) {
        let left = side == ir::Side::Left;
        match radius {
            CompRadius::Tool(tool) => {
                self.code(if left { "G41" } else { "G42" });
                self.int_word(b'D', tool);
            }
            CompRadius::LoadedTool => self.code(if left { "G41" } else { "G42" }),
            CompRadius::Diameter(d) => {
                self.code(if left { "G41.1" } else { "G42.1" });
                self.word(b'D', d);
            }
        }
    }
}

/// A move's code: G33 for a thread, else its motion's.
pub(super) fn move_code(m: &ir::Move) -> &'static str {
    match m.lead {
        Some(_) => "G33",
        None => motion_code(m.motion),
    }
}

pub(super) fn motion_code(m: Motion) -> &'static str {
    match m {
        Motion::Rapid => "G0",
        Motion::Linear => "G1",
        Motion::ArcCw => "G2",
        Motion::ArcCcw => "G3",
    }
}

#[cfg(test)]
mod tests {
    use super::push_line_word;

    /// Lines one after another (across a digit more and a thousand), the
    /// same line again, jumps back and forth, around each power of ten and
    /// past the tables' million, and the last line number: every word as
    /// formatting the number writes it.
    #[test]
    fn line_numbers_are_written_as_formatted() {
        let mut lines: Vec<u32> = (1..=1200).collect();
        lines.extend([1200, 1200, 5, 6, 9, 10, 9, 99, 100, 101, 999_999, 1_000_000]);
        lines.extend([
            10_000, 10_001, 100_000, 100_001, 123_456, 999_000, 999_001, 1_000_001,
        ]);
        lines.extend([u32::MAX - 2, u32::MAX - 1, u32::MAX, u32::MAX, 1, 2]);
        let (mut got, mut expected) = (Vec::new(), String::new());
        for line in lines {
            push_line_word(&mut got, line);
            expected.push_str(&format!("N{line} "));
        }
        assert_eq!(String::from_utf8(got).unwrap(), expected);
    }
}
