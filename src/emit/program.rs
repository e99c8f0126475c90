//! The final program (SPEC §6): absolute moves with unchanged axes left
//! out, F on the cutting move it applies to, arc centres relative to the
//! start point as printed, and the target's prologue and epilogue.

use super::printer::{motion_code, move_code, Printer};
use super::{ArcFormat, EmitOptions, Target, Unrunnable, Why};
use crate::diagnostic::{warning, Diagnostic, DiagnosticExt, Located};
use crate::geometry::{self, Point};
use crate::ir::{self, ArcGeometry, Axis, Motion, Op, Units};
use crate::source::Span;

mod fitting;

use crate::diagnostic::note;
use crate::emit::fit::{self, Piece};
use fitting::{exact_of, MOST_HELD};

/// Prints the final program: absolute, one unit, only the codes of SPEC §6
/// and what the passes passed through.
pub struct ProgramPrinter {
    p: Printer,
    arcs: ArcFormat,
    tolerance: f64,
    /// 1 µm in the output units (a number that is at most 1 µm in either
    /// where they are not known): how far `--arcs r` may move a centre.
    micron: f64,
    /// `--arcs r`: the arcs written with I/J all the same (the first one's
    /// line, and how many).
    not_r: Option<(Span, usize)>,
    /// Path control the target cannot run as written (grbl: none of it;
    /// Fanuc: G61.1, G64's P and Q): the first one's line, and how many.
    path_control_lost: Option<(Span, usize)>,
    /// The first dwell longer than the target counts (grbl), and its
    /// seconds.
    dwell_too_long: Option<(Span, f64)>,
    /// Machine position per axis, as the absolute pass knows it.
    position: ir::Position,
    /// Last printed value of each axis, on the output grid; `None` makes
    /// the next move that has the axis write it.
    printed: [Option<i64>; 9],
    /// A feed waiting for the next cutting move, and the last feed written.
    pending_feed: Option<f64>,
    printed_feed: Option<i64>,
    /// `--arcs fit`: the run of lines held back.
    fitting: Option<Box<fitting::Fitting>>,
    /// What the target cannot run, each code once (at most
    /// [`MOST_REFUSED`]).
    refused: Vec<Located<Unrunnable>>,
}

/// Distinct codes a target refuses that are reported.
const MOST_REFUSED: usize = 50;

impl ProgramPrinter {
    /// `units`: the output units, if known (a program that never states
    /// them gets no G20/G21).
    pub fn new(
        options: &EmitOptions,
        units: Option<Units>,
        source_len: usize,
        main_file: usize,
    ) -> ProgramPrinter {
        let mut p = Printer::new(
            options.numbering,
            options.target,
            options.decimals,
            units,
            main_file,
            source_len * 2,
        );
        p.joins = true;
        if let Some(prologue) = options.target.prologue(options.program_number) {
            p.raw(&prologue);
        }
        p.raw_line(match units {
            Some(Units::Inch) => "G20 G90 G17",
            Some(Units::Mm) => "G21 G90 G17",
            None => "G90 G17",
        });
        ProgramPrinter {
            p,
            arcs: options.arcs,
            tolerance: options.tolerance.unwrap_or(0.001),
            micron: match units {
                Some(Units::Mm) => 0.001,
                Some(Units::Inch) | None => 0.001 / 25.4,
            },
            not_r: None,
            path_control_lost: None,
            dwell_too_long: None,
            position: [None; 9],
            printed: [None; 9],
            pending_feed: None,
            printed_feed: None,
            fitting: options
                .arcs
                .fits()
                .then(|| fitting::Fitting::new(options.tolerance, units)),
            refused: Vec::new(),
        }
    }

    /// Print the next statements of the program; returns the text not
    /// yet taken (the caller may take it).
    pub fn print(&mut self, stmts: &[ir::Stmt]) -> &mut Vec<u8> {
        for stmt in stmts {
            if self.refuses(stmt) || self.held(stmt) {
                continue;
            }
            match &stmt.op {
                Op::Move(m) => {
                    self.final_move(stmt, m);
                    m.to.place(&mut self.position, Some);
                    continue;
                }
                Op::IncrementalMove(m) => {
                    self.steps(stmt, m);
                    continue;
                }
                Op::Cycle(c) => {
                    self.kept_cycle(stmt, c);
                    continue;
                }
                // The header selected G17; repeat a plane only when it changes.
                Op::Plane(plane) if *plane == self.p.plane => continue,
                // A unit switch written in the output (the program's first
                // G20/G21, after moves or an F in the machine's units): an F
                // waiting for a move was given before it, in the units before
                // it, so it is written on a line of its own before it: grbl
                // converts a line's F by that line's G20/G21, LinuxCNC reads
                // the two lines as it read the one.
                Op::Units(_) if self.pending_feed.is_some() => {
                    if let Some(q) = self.new_feed() {
                        self.p.begin_stmt(stmt);
                        self.p.word_q(b'F', q);
                        self.p.end();
                    }
                    self.p.begin_stmt(stmt);
                    self.p.op(&stmt.op);
                    self.p.end();
                    continue;
                }
                // F goes on the next cutting move's line (and only if it changed).
                Op::Feed(f) => {
                    self.pending_feed = Some(*f);
                    continue;
                }
                // The operator may move the machine at a tool change or a
                // stop: write every axis of the next move again.
                Op::ChangeTool | Op::Stop(_) => self.printed = [None; 9],
                // Nothing to write, and the output's tool has not moved.
                Op::ReadPosition(_) | Op::InverseTimeFloor(_) => continue,
                Op::PathControl(pc) if self.p.target.loses(pc) => {
                    let lost = self.path_control_lost.get_or_insert((stmt.span, 0));
                    lost.1 += 1;
                    if self.p.target == Target::Grbl {
                        continue;
                    }
                }
                // Where the tool is, in program coordinates, is no longer
                // known (the absolute pass forgets the same axes).
                Op::MachineMove(_)
                | Op::Home { .. }
                | Op::SelectWorkOffset(_)
                | Op::SetWorkOffset { .. }
                | Op::SetWorkOffsetHere { .. }
                | Op::ToolLength { .. }
                | Op::CancelToolLength
                | Op::CancelPosition => self.forget(stmt.op.unknown_after()),
                // A G92 passed through: the same numbers name other points.
                Op::SetPosition(a) => {
                    self.forget(|axis| a.has(axis));
                    a.place(&mut self.position, Some);
                }
                Op::Dwell(seconds) if self.p.target.longest_dwell() < *seconds => {
                    self.dwell_too_long.get_or_insert((stmt.span, *seconds));
                }
                Op::Speed(_)
                | Op::SpindleMode(_)
                | Op::SelectTool(_)
                | Op::Spindle(_)
                | Op::Coolant(_)
                | Op::Dwell(_)
                | Op::End
                | Op::Units(_)
                | Op::Distance(_)
                | Op::ArcCenters(_)
                | Op::InverseTime(_)
                | Op::Plane(_)
                | Op::LocalOffset(_)
                | Op::Polar(_)
                | Op::DiameterMode(_)
                | Op::ReturnLevel(_)
                | Op::CycleOff
                | Op::Comp { .. }
                | Op::CompOff
                | Op::PathControl(_)
                // (The absolute pass made splines arcs.)
                | Op::Spline(_)
                // It ends where it started.
                | Op::RigidTap(_)
                | Op::Comment(_)
                | Op::SetToolData(_)
                | Op::Passthrough(_) => {}
            }
            self.p.stmt(stmt);
        }
        &mut self.p.out
    }

    /// Whether the target cannot run `stmt`: then it is reported (each
    /// code once) and not written. Arcs written as lines have no turns.
    fn refuses(&mut self, stmt: &ir::Stmt) -> bool {
        let Some(refusal) = self.p.target.cannot_run(&stmt.op) else {
            return false;
        };
        if refusal.why == Why::Turns && self.arcs == ArcFormat::Lines {
            return false;
        }
        let known = self.refused.iter().any(|r| r.kind.code == refusal.code);
        if !known && self.refused.len() < MOST_REFUSED {
            self.refused.push(Located::new(refusal, stmt.span));
        }
        true
    }

    /// The codes the target cannot run, as errors at their first lines.
    pub fn refused(&self) -> impl Iterator<Item = Diagnostic> + '_ {
        self.refused.iter().map(Located::to_diagnostic)
    }

    /// `--arcs r`: a warning that some arcs are written with I/J.
    pub fn arcs_not_r(&self) -> Option<Diagnostic> {
        let (first, n) = self.not_r?;
        let arcs = if n == 1 { "an arc" } else { "arcs" };
        let why = "an R would move the centre a controller finds by more than the output's last \
                   digit or 0.001 mm: an arc near a half circle, a short arc of a large radius, or \
                   a centre off the middle of its ends (two radii that differ)";
        let fitted = if self.fitting.is_some() {
            "; or, for an arc fitted to lines, take it beyond `--tolerance` of them"
        } else {
            ""
        };
        Some(
            warning(
                format!("{n} {arcs} written with I/J, not R"),
                first,
                "the first of them",
            )
            .with_note(format!("{why}{fitted}"))
            .with_help("more decimals (`--decimals`) let more arcs be written with R"),
        )
    }

    /// Path control the target runs otherwise, or not at all: a warning.
    pub fn path_control_lost(&self) -> Option<Diagnostic> {
        let (first, n) = self.path_control_lost?;
        let times = if n == 1 {
            String::new()
        } else {
            format!(" ({n} times)")
        };
        Some(match self.p.target {
            Target::Grbl => warning(
                format!("path control dropped{times}"),
                first,
                "grbl has no G61, G61.1 or G64",
            )
            .with_note("grbl always blends corners within its junction deviation ($11)"),
            _ => warning(
                format!("path control written as Fanuc's{times}"),
                first,
                "Fanuc has no G61.1 and no P or Q on G64",
            )
            .with_note("G61.1 is written G61 (exact stop), G64 without its tolerances"),
        })
    }

    /// A dwell longer than the target counts: a warning (grbl counts
    /// 50 ms steps in 16 bits, so `G4 P4000` waits 723.2 s there).
    pub fn dwell_too_long(&self) -> Option<Diagnostic> {
        let (at, seconds) = self.dwell_too_long?;
        let longest = self.p.target.longest_dwell();
        Some(
            warning(
                format!("a dwell of {seconds} s is longer than {} counts", self.p.target.controller()),
                at,
                format!("at most {longest} s"),
            )
            .with_note(format!(
                "{} counts a dwell in 50 ms steps in 16 bits: a longer one wraps round and ends early",
                self.p.target.controller()
            ))
            .with_help("several shorter dwells, one after another; or, if P was meant in milliseconds, `--from fanuc`"),
        )
    }

    pub fn finish(mut self) -> Vec<u8> {
        self.print_held();
        self.p.close();
        if let Some(epilogue) = self.p.target.epilogue() {
            self.p.raw(epilogue);
        }
        self.p.out
    }

    fn forget(&mut self, axes: impl Fn(Axis) -> bool) {
        for axis in Axis::ALL {
            if axes(axis) {
                self.position[axis.index()] = None;
                self.printed[axis.index()] = None;
            }
        }
    }

    /// An incremental move (`G91 G1 X5.` then `G90`): its axes must be
    /// written again when next given absolutely.
    fn steps(&mut self, stmt: &ir::Stmt, m: &ir::Move) {
        self.p.begin_move(stmt);
        self.p.code("G91");
        self.p.code(move_code(m));
        for (axis, v) in m.to.iter() {
            let i = axis.index();
            self.p.word(axis.letter(), v);
            self.position[i] = self.position[i].map(|p| p + v);
            self.printed[i] = None;
        }
        match m.lead {
            Some(lead) => self.p.lead_word(lead),
            None if m.motion != Motion::Rapid => self.feed_word(),
            None => {}
        }
        self.p.end();
        self.p.back_to_absolute(stmt);
    }

    /// A move: the absolute pass guarantees that an arc's plane axes are
    /// known and that its centre is given.
    fn final_move(&mut self, stmt: &ir::Stmt, m: &ir::Move) {
        let mut end_q: [Option<i64>; 9] = [None; 9];
        for (axis, v) in m.to.iter() {
            end_q[axis.index()] = Some(self.p.scaled(v));
        }
        if let Some(lead) = m.lead {
            return self.thread(stmt, &end_q, lead);
        }
        let arc = m.arc.filter(|_| m.motion.is_arc());
        let Some(ArcGeometry::Center(c)) = arc.map(|a| a.geometry) else {
            return self.linear(stmt, m.motion, &end_q);
        };
        let turns = arc.map_or(1, |a| a.turns);
        let start: Point = std::array::from_fn(|i| self.position[i].unwrap_or(0.0));
        let end: Point = std::array::from_fn(|i| m.to.get(Axis::ALL[i]).unwrap_or(start[i]));
        let center: Point = std::array::from_fn(|i| start[i] + c[i].unwrap_or(0.0));
        let clockwise = m.motion == Motion::ArcCw;
        if self.arcs == ArcFormat::Lines {
            return self.arc_as_lines(stmt, m, [start, end, center], clockwise, turns);
        }
        let start_q: [i64; 3] =
            std::array::from_fn(|i| self.printed[i].unwrap_or_else(|| self.p.scaled(start[i])));
        let end3: [i64; 3] = std::array::from_fn(|i| end_q[i].unwrap_or(start_q[i]));
        self.p.begin_move(stmt);
        self.p.code(motion_code(m.motion));
        let (a, b, _) = self.p.plane.axes();
        for axis in Axis::ALL {
            let i = axis.index();
            // The plane's axes from the rounded end; any other axis only
            // where the move gives it (an axis the program never set must
            // not be written as 0).
            let q = if i == a || i == b {
                Some(end3[i])
            } else {
                end_q[i]
            };
            let Some(q) = q else { continue };
            // Both in-plane axes always, so a full circle has an end.
            if i == a || i == b || Some(q) != self.printed[i] {
                self.p.word_q(axis.letter(), q);
                self.printed[i] = Some(q);
            }
        }
        let full = start_q[a] == end3[a] && start_q[b] == end3[b];
        // (A full circle, or more than one turn, has no R.)
        let wants_r = self.arcs.writes_r() && turns == 1 && !full;
        let r_word = wants_r
            .then(|| self.r_word([start, end, center], start_q, end3, clockwise))
            .flatten();
        if let Some((r, decimals)) = r_word {
            self.p.word_decimals(b'R', r, decimals);
        } else {
            if wants_r {
                let (_, n) = self.not_r.get_or_insert((stmt.span, 0));
                *n += 1;
            }
            let printed_center =
                self.round_center([start, end, center], start_q, end3, clockwise, turns);
            for (axis, letter) in [(a, CENTER[a]), (b, CENTER[b])] {
                self.p.word_q(letter, printed_center[axis] - start_q[axis]);
            }
        }
        if turns > 1 {
            self.p.code(&format!("P{turns}"));
        }
        self.feed_word();
        self.p.end();
    }

    /// `--arcs lines`: chords within the tolerance; extra axes move in
    /// proportion, as they do along the arc.
    fn arc_as_lines(
        &mut self,
        stmt: &ir::Stmt,
        m: &ir::Move,
        [start, end, center]: [Point; 3],
        clockwise: bool,
        turns: u32,
    ) {
        let points = geometry::arc_points(
            start,
            end,
            center,
            self.p.plane,
            clockwise,
            turns,
            self.tolerance,
        );
        let n = points.len();
        for (k, point) in points.into_iter().enumerate() {
            let fraction = (k + 1) as f64 / n as f64;
            let q: [Option<i64>; 9] = std::array::from_fn(|i| {
                if i < 3 {
                    return Some(self.p.scaled(point[i]));
                }
                let axis = Axis::ALL[i];
                let to = m.to.get(axis)?;
                let from = self.position[i].unwrap_or(to);
                Some(self.p.scaled(from + (to - from) * fraction))
            });
            self.linear(stmt, Motion::Linear, &q);
        }
    }

    /// A cycle the output keeps (`--cycles keep`): on one line with its
    /// feed; the controller leaves the tool over the hole at the level
    /// the cycle ends at, and the next move writes every axis again.
    fn kept_cycle(&mut self, stmt: &ir::Stmt, c: &ir::Cycle) {
        self.p.begin_move(stmt);
        self.p.op(&stmt.op);
        self.feed_word();
        self.p.end();
        for (axis, v) in c.at.iter() {
            self.position[axis.index()] = Some(v);
        }
        let (_, _, n) = self.p.plane.axes();
        self.position[n] = c.kept.map(|k| k.ends_at);
        self.printed = [None; 9];
    }

    /// Write the pending feed on a cutting move's line, if it changed.
    fn feed_word(&mut self) {
        if let Some(q) = self.new_feed() {
            self.p.word_q(b'F', q);
        }
    }

    /// The waiting feed, taken, on the output grid, if it differs from the
    /// last one written (it is then the last one written).
    fn new_feed(&mut self) -> Option<i64> {
        let q = self.p.scaled(self.pending_feed.take()?);
        (self.printed_feed != Some(q)).then(|| {
            self.printed_feed = Some(q);
            q
        })
    }

    /// The centre to print, on the output grid. Rounding start, end and
    /// centre independently can turn a half circle by more than the
    /// rounding itself; of the grid points around the exact centre, take
    /// the one that keeps centre, sweep and radius closest to the exact arc.
    fn round_center(
        &self,
        [start, end, center]: [Point; 3],
        start_q: [i64; 3],
        end_q: [i64; 3],
        clockwise: bool,
        turns: u32,
    ) -> [i64; 3] {
        use crate::geometry::sweep;
        let plane = self.p.plane;
        let (a, b, _) = plane.axes();
        let radius = (start[a] - center[a]).hypot(start[b] - center[b]);
        let s = start_q.map(|q| self.p.unscaled(q));
        let e = end_q.map(|q| self.p.unscaled(q));
        let base = center.map(|v| self.p.scaled(v));
        let good = 0.75 * self.p.unscaled(1);
        // How much the printed arc's two radii differ other than the given
        // arc's do (a spiral stays the spiral it is).
        let given = radius - (end[a] - center[a]).hypot(end[b] - center[b]);
        let radii_differ = |c: [f64; 3]| {
            let rs = (s[a] - c[a]).hypot(s[b] - c[b]);
            let re = (e[a] - c[a]).hypot(e[b] - c[b]);
            (rs - re - given).abs()
        };
        // The arc on the grid already (its numbers printed as the program
        // gave them): the centre does not move and the sweep does not turn,
        // so `error_of(base)` below is the difference of the radii alone.
        let in_plane = |p: [f64; 3], q: [f64; 3]| {
            p[a].to_bits() == q[a].to_bits() && p[b].to_bits() == q[b].to_bits()
        };
        let c = base.map(|q| self.p.unscaled(q));
        if in_plane(s, start) && in_plane(e, end) && in_plane(c, center) && radii_differ(c) <= good
        {
            return base;
        }
        let exact_sweep = sweep(start, end, center, plane, clockwise, turns);
        let error_of = |q: [i64; 3]| {
            let c = q.map(|v| self.p.unscaled(v));
            let moved = (c[a] - center[a]).hypot(c[b] - center[b]);
            let turned = (sweep(s, e, c, plane, clockwise, turns) - exact_sweep).abs() * radius;
            moved.max(turned).max(radii_differ(c))
        };
        // Plain rounding is usually as good as the grid allows.
        let mut best = (error_of(base), base);
        if best.0 <= good {
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

    /// `--arcs r`: the R of an arc from the printed start to the printed
    /// end, and its decimals: the output's, or more (up to 6) where the
    /// centre a controller finds from them would be more than a unit of
    /// the output grid, or 1 µm if more, from the arc's centre (or its
    /// sweep turn the end that far). SPEC §4: of the start and end radii,
    /// the larger is used. `None` where no R of 6 decimals places the
    /// centre so: the arc is written with I/J. That is an arc near a half
    /// circle, whose centre moves by far more than the rounding of R and
    /// of the ends; a short arc of a large radius, whose centre the
    /// rounded ends hardly fix; or a centre off the bisector of its ends
    /// (radii that differ: a slight spiral, which no R gives).
    fn r_word(
        &self,
        [start, end, center]: [Point; 3],
        start_q: [i64; 3],
        end_q: [i64; 3],
        clockwise: bool,
    ) -> Option<(f64, usize)> {
        let plane = self.p.plane;
        let (a, b, _) = plane.axes();
        let r = (center[a] - start[a])
            .hypot(center[b] - start[b])
            .max((center[a] - end[a]).hypot(center[b] - end[b]));
        let long = geometry::is_long_arc(start, end, center, plane, clockwise);
        let r = if long { -r } else { r };
        let s = start_q.map(|q| self.p.unscaled(q));
        let e = end_q.map(|q| self.p.unscaled(q));
        let exact_sweep = geometry::sweep(start, end, center, plane, clockwise, 1);
        let good = self.p.unscaled(1).max(self.micron);
        let most = self.p.decimals.max(6);
        (self.p.decimals..=most).find_map(|decimals| {
            let scale = 10f64.powi(decimals as i32);
            let printed = crate::emit::number::to_grid(r, scale) as f64 / scale;
            let c = geometry::center_from_radius(s, e, printed, plane, clockwise, 0.0).ok()?;
            let moved = (c[a] - center[a]).hypot(c[b] - center[b]);
            let turned =
                (geometry::sweep(s, e, c, plane, clockwise, 1) - exact_sweep).abs() * r.abs();
            (moved.max(turned) <= good).then_some((printed, decimals))
        })
    }

    /// A G33 to the known axes of `end_q`; nothing if none changed. No F:
    /// its feed is the spindle's, and rs274 refuses one.
    fn thread(&mut self, stmt: &ir::Stmt, end_q: &[Option<i64>; 9], lead: f64) {
        if self.changed_axes(end_q) == 0 {
            return;
        }
        self.p.begin_move(stmt);
        self.p.code("G33");
        self.axis_words(end_q);
        self.p.lead_word(lead);
        self.p.end();
    }

    /// Which axes of `end_q` differ from what was printed, a bit each.
    fn changed_axes(&self, end_q: &[Option<i64>; 9]) -> u16 {
        let mut changed = 0u16;
        for (i, q) in end_q.iter().enumerate() {
            if q.is_some() && *q != self.printed[i] {
                changed |= 1 << i;
            }
        }
        changed
    }

    /// The words of the axes of `end_q` that changed, in printing order.
    fn axis_words(&mut self, end_q: &[Option<i64>; 9]) {
        let mut changed = self.changed_axes(end_q);
        while changed != 0 {
            let i = changed.trailing_zeros() as usize;
            changed &= changed - 1;
            if let Some(q) = end_q[i] {
                self.p.word_q(Axis::ALL[i].letter(), q);
                self.printed[i] = Some(q);
            }
        }
    }

    /// A straight move to the known axes of `end_q`; nothing if none changed.
    fn linear(&mut self, stmt: &ir::Stmt, motion: Motion, end_q: &[Option<i64>; 9]) {
        if self.changed_axes(end_q) == 0 {
            return;
        }
        self.p.begin_move(stmt);
        self.p.code(motion_code(motion));
        self.axis_words(end_q);
        if motion != Motion::Rapid {
            self.feed_word();
        }
        self.p.end();
    }
}

const CENTER: [u8; 3] = [b'I', b'J', b'K'];

/// A stretch of a held run that [`fit`] proved an arc: from vertex
/// `first` to vertex `last`, about `center` (on the grid, in the plane's
/// first and second axes).
struct FittedArc {
    first: usize,
    last: usize,
    center: [i64; 2],
    clockwise: bool,
}

/// `--arcs fit`: the printer's side of [`fitting::Fitting`].
impl ProgramPrinter {
    /// `--arcs fit`: hold the statement back if it joins the run (or
    /// repeats its feed); otherwise print the run held and say no.
    pub(super) fn held(&mut self, stmt: &ir::Stmt) -> bool {
        let Some(fitting) = self.fitting.as_deref() else {
            return false;
        };
        match &stmt.op {
            Op::Feed(f) if !fitting.moves.is_empty() && Some(self.p.scaled(*f)) == fitting.feed => {
                return true;
            }
            Op::Move(m) if self.joins(stmt, m) => {
                self.hold(stmt, m);
                return true;
            }
            _ => {}
        }
        self.print_held();
        if let Some(fitting) = self.fitting.as_deref_mut() {
            match stmt.op {
                Op::InverseTime(on) => fitting.inverse_time = on,
                Op::Comp { .. } => fitting.compensating = true,
                Op::CompOff => fitting.compensating = false,
                _ => {}
            }
        }
        false
    }

    /// Whether a move may join a run: a straight feed in the plane's axes
    /// from a known point, on a line of its own. Where only the machine
    /// knows the normal axis (a program that never sets Z), a move that
    /// leaves it alone joins too: its arc is flat, and written without it.
    fn joins(&self, stmt: &ir::Stmt, m: &ir::Move) -> bool {
        let Some(fitting) = self.fitting.as_deref() else {
            return false;
        };
        let (a, b, n) = self.p.plane.axes();
        let plane_axes = (1 << a) | (1 << b) | (1 << n);
        m.motion == Motion::Linear
            && m.lead.is_none()
            && m.arc.is_none()
            && !stmt.block_delete
            && !fitting.inverse_time
            && !fitting.compensating
            && m.to.bits() & !plane_axes == 0
            && [a, b].iter().all(|&i| self.position[i].is_some())
            && (self.position[n].is_some() || m.to.get(Axis::ALL[n]).is_none())
    }

    fn hold(&mut self, stmt: &ir::Stmt, m: &ir::Move) {
        let (a, b, n) = self.p.plane.axes();
        if self.fitting.as_ref().is_some_and(|f| f.moves.is_empty()) {
            let exact = [a, b, n].map(|i| self.position[i].unwrap_or(0.0));
            let printed = [a, b, n].map(|i| {
                self.printed[i].unwrap_or_else(|| self.p.scaled(exact_of(&self.position, i)))
            });
            let feed = self
                .pending_feed
                .map(|f| self.p.scaled(f))
                .or(self.printed_feed);
            let Some(fitting) = self.fitting.as_deref_mut() else {
                return;
            };
            fitting.exact.push(exact);
            fitting.printed.push(printed);
            fitting.feed = feed;
        }
        m.to.place(&mut self.position, Some);
        let exact = [a, b, n].map(|i| exact_of(&self.position, i));
        let Some(fitting) = self.fitting.as_deref_mut() else {
            return;
        };
        let before = fitting.printed[fitting.printed.len() - 1];
        let mut printed = before;
        for (k, &i) in [a, b, n].iter().enumerate() {
            if let Some(v) = m.to.get(Axis::ALL[i]) {
                printed[k] = self.p.scaled(v);
            }
        }
        fitting.exact.push(exact);
        fitting.printed.push(printed);
        fitting.moves.push(stmt.clone());
        if fitting.moves.len() >= MOST_HELD {
            self.print_held();
        }
    }

    /// Print the run held: its arcs, and its other moves as they are.
    pub(super) fn print_held(&mut self) {
        let Some(fitting) = self.fitting.as_deref_mut() else {
            return;
        };
        if fitting.moves.is_empty() {
            return;
        }
        let moves = std::mem::take(&mut fitting.moves);
        let exact = std::mem::take(&mut fitting.exact);
        let printed = std::mem::take(&mut fitting.printed);
        let run = fit::Run {
            exact: &exact,
            printed: &printed,
            scale: 1.0 / self.p.unscaled(1),
            tolerance: fitting.tolerance,
        };
        let pieces = if moves.len() < fit::MIN_SEGMENTS {
            Vec::new()
        } else {
            run.fit()
        };
        // The position is the run's end already; lines are printed as
        // `final_move` prints them, which reads only the printed state.
        if pieces.iter().any(|p| matches!(p, Piece::Arc { .. })) {
            // The lines first, to count what the arcs save; then the run
            // again, from the same state, with its arcs.
            let from = self.p.out.len();
            let mark = self.p.mark();
            let state = (self.printed, self.pending_feed, self.printed_feed);
            self.print_pieces(&moves, &run, &[]);
            let lines = self.p.out.len() - from;
            self.p.rewind(mark);
            (self.printed, self.pending_feed, self.printed_feed) = state;
            self.print_pieces(&moves, &run, &pieces);
            let arcs = self.p.out.len() - from;
            if let Some(fitting) = self.fitting.as_deref_mut() {
                fitting.bytes_saved += lines - arcs.min(lines);
            }
        } else {
            self.print_pieces(&moves, &run, &[]);
        }
        if let Some(fitting) = self.fitting.as_deref_mut() {
            // The vectors' room is kept for the next run.
            fitting.moves = moves;
            fitting.moves.clear();
            fitting.exact = exact;
            fitting.exact.clear();
            fitting.printed = printed;
            fitting.printed.clear();
        }
    }

    /// The held `moves` as `pieces` say (lines where they say nothing).
    fn print_pieces(&mut self, moves: &[ir::Stmt], run: &fit::Run<'_>, pieces: &[Piece]) {
        let mut k = 0;
        let mut pieces = pieces.iter();
        while k < moves.len() {
            match pieces.next() {
                Some(&Piece::Arc {
                    segments,
                    center,
                    clockwise,
                }) => {
                    let arc = FittedArc {
                        first: k,
                        last: k + segments,
                        center,
                        clockwise,
                    };
                    self.fitted_arc(&moves[k..k + segments], run, &arc);
                    if let Some(fitting) = self.fitting.as_deref_mut() {
                        fitting.lines_fitted += segments;
                        fitting.arcs += 1;
                        fitting.first.get_or_insert(moves[k].span);
                    }
                    k += segments;
                }
                Some(Piece::Line) | None => {
                    if let Op::Move(m) = &moves[k].op {
                        self.final_move(&moves[k], m);
                    }
                    k += 1;
                }
            }
        }
    }

    /// An arc as [`fit`] proved it in place of `moves`, numbered by the
    /// first one's line; under `--arcs fit-r` with R where `--arcs r`
    /// would write one and the arc about the centre a controller finds
    /// from it is proven too.
    fn fitted_arc(&mut self, moves: &[ir::Stmt], run: &fit::Run<'_>, arc: &FittedArc) {
        let span = moves[0].span;
        let (start, end) = (run.printed[arc.first], run.printed[arc.last]);
        let (a, b, n) = self.p.plane.axes();
        let r_word = if self.arcs.writes_r() {
            let r_word = self.fitted_r(run, arc);
            if r_word.is_none() {
                let (_, n) = self.not_r.get_or_insert((span, 0));
                *n += 1;
            }
            r_word
        } else {
            None
        };
        self.p.begin(span, false, moves[0].number);
        self.p.code(if arc.clockwise { "G2" } else { "G3" });
        for axis in Axis::ALL {
            let i = axis.index();
            let q = match i {
                _ if i == a => end[0],
                _ if i == b => end[1],
                // (Not written where only the machine knows it.)
                _ if i == n && self.position[n].is_some() && self.printed[n] != Some(end[2]) => {
                    end[2]
                }
                _ => continue,
            };
            self.p.word_q(axis.letter(), q);
            self.printed[i] = Some(q);
        }
        if let Some((r, decimals)) = r_word {
            self.p.word_decimals(b'R', r, decimals);
        } else {
            self.p.word_q(CENTER[a], arc.center[0] - start[0]);
            self.p.word_q(CENTER[b], arc.center[1] - start[1]);
        }
        self.feed_word();
        if self.fitting.as_ref().is_some_and(|f| f.name_runs) {
            self.name_run(moves);
        }
        self.p.end();
    }

    /// `--stage fit`: a comment naming the moves an arc replaces and
    /// their lines in the main file (none for moves of a called file).
    fn name_run(&mut self, moves: &[ir::Stmt]) {
        let n = moves.len();
        let lines = moves
            .first()
            .zip(moves.last())
            .map(|(first, last)| (self.p.main_line(first.span), self.p.main_line(last.span)));
        let text = match lines {
            Some((Some(first), Some(last))) if first == last => {
                format!("fit: {n} moves, line {first}")
            }
            Some((Some(first), Some(last))) => format!("fit: {n} moves, lines {first}-{last}"),
            _ => format!("fit: {n} moves"),
        };
        self.p.comment(&text);
    }

    /// `--stage fit`: each fitted arc names the source lines it replaces.
    pub fn name_fitted_runs(&mut self) {
        if let Some(fitting) = self.fitting.as_deref_mut() {
            fitting.name_runs = true;
        }
    }

    /// The R of a fitted arc and its decimals, if [`Self::r_word`] gives
    /// one for the arc as proven (its printed ends and centre) and the
    /// arc about the centre a controller finds from that R is proven as
    /// well (it may lie up to a micron off the proven one).
    fn fitted_r(&self, run: &fit::Run<'_>, arc: &FittedArc) -> Option<(f64, usize)> {
        let (a, b, n) = self.p.plane.axes();
        let in_axes = |plane: [i64; 3]| {
            let mut q = [0; 3];
            (q[a], q[b], q[n]) = (plane[0], plane[1], plane[2]);
            q
        };
        let (start_q, end_q) = (
            in_axes(run.printed[arc.first]),
            in_axes(run.printed[arc.last]),
        );
        let center_q = in_axes([arc.center[0], arc.center[1], 0]);
        let [start, end, center] =
            [start_q, end_q, center_q].map(|q| q.map(|v| self.p.unscaled(v)));
        let (r, decimals) = self.r_word([start, end, center], start_q, end_q, arc.clockwise)?;
        let found =
            geometry::center_from_radius(start, end, r, self.p.plane, arc.clockwise, 0.0).ok()?;
        run.proves(arc.first, arc.last, [found[a], found[b]], arc.clockwise)
            .then_some((r, decimals))
    }

    /// `--arcs fit`: a note of how many lines were written as how many arcs.
    pub fn arcs_fitted(&self) -> Option<Diagnostic> {
        let fitting = self.fitting.as_deref()?;
        let first = fitting.first?;
        Some(note(
            format!(
                "{} lines written as {} arcs, {} bytes shorter (`--arcs {}`, within {})",
                fitting.lines_fitted,
                fitting.arcs,
                fitting.bytes_saved,
                if self.arcs.writes_r() { "fit-r" } else { "fit" },
                fitting.tolerance
            ),
            first,
            "the first of them",
        ))
    }
}
