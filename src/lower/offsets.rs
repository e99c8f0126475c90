//! Pass offsets (SPEC §4.2): G54–G59.3 (origins from `SetOffset`, changed
//! by G10 L2/L20), G52, G92/G92.1 and G43/G44/G49 folded into the
//! coordinates when their values are known. Under G90 an axis word gets
//! the active offsets added; G91 moves are unchanged. An axis left out
//! keeps its machine position, as on LinuxCNC.
//!
//! What the program does not state is passed through, never guessed: a
//! work offset with unknown values and a tool length offset with no known
//! length stay in the output, with a warning, and the coordinates under
//! them stay as written. Known work offsets are measured from G54, the
//! program zero: selecting one writes `G54` (the output's frame) once.
//! Changing an offset under G91 is an error. Lengths are in the output
//! units (the units pass ran first).
//!
//! A `G10 L2` is folded (left out of the output) only where leaving it out
//! changes nothing the machine does: after the program has selected a
//! system (before that, the machine's own system is active, and may be the
//! one it changes), and when it leaves its system's X, Y and Z known.
//! Otherwise it goes to the machine, which then has the values the
//! program gave; a `G10 L2 P1` that does changes the output's own frame,
//! and systems folded after it are measured from where it put G54
//! (`machine`). A `G10 L20 P1` passed through leaves G54 to the machine:
//! a system ger knows can then no longer be written in its terms, and is
//! selected as it is only where the machine was given its values. A
//! `G10 L20` passed through gets the point with the shifts ger folds.
//! `G10 L2` values are machine coordinates: `machine` takes G54 at
//! machine zero until the program sets it there, and a system folded on
//! that assumption is reported once (`folds_from_machine_zero`).
//!
//! A `G92` at a point ger does not know (`G92 X0 Y0 Z0` before any move:
//! the origin is wherever the tool stands) goes to the machine, with the
//! shifts ger folds added, so the output's coordinates from there are in
//! its frame, and the point it names is known in them. The machine then
//! has a G92 of its own: a `G92.1` goes to it too.
//!
//! A `G10 L10`/`L11` (a tool's length from where the tool stands) is made
//! the `G10 L1` it amounts to, from the position, the shifts and the
//! length in force; one that needs what only the machine knows is an
//! error.

use super::error::{LowerError, LowerErrorKind, Unmeasurable};
use super::pass::{feed_in_turn, follows_only, Batch, Context, Out, Pass, PassInfo};
use crate::ir::{self, Axes, Axis, Distance, Op, Position, Stmt};
use crate::source::Span;
use std::collections::BTreeMap;

pub const PASS: PassInfo = PassInfo {
    name: "offsets",
    make: |cx| Box::new(OffsetsPass::new(cx)),
};

/// The frame the output's coordinates are in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Frame {
    /// Whatever the machine is in when the program starts.
    Initial,
    /// G54: known work offsets are folded into it.
    G54,
    /// A work offset with unknown values, passed through (index 2..=9).
    Passed(u8),
}

struct OffsetsPass {
    /// Origins of G54..G59.3 (index 1..=9) per axis, measured from G54.
    systems: [[Option<f64>; 9]; 10],
    /// The origins the machine has, where ger knows them (measured as
    /// `systems` are): G54's, which the output's G54 frame is, zero until a
    /// `G10` that sets G54 goes to the machine (unknown after a `G10 L20
    /// P1` at an unknown point); the others', those `G10 L2` passed through
    /// gave it. A folded `G10` leaves the machine's as they were.
    machine: [[Option<f64>; 9]; 10],
    /// Where the machine's G54 was last set by a statement passed through.
    machine_g54_since: Option<Span>,
    /// The work offset the program selected (1 = G54).
    active: u8,
    frame: Frame,
    /// G52 and G92 shifts.
    local: [f64; 9],
    g92: [f64; 9],
    /// The machine has a G92 the program passed through.
    passed_g92: bool,
    /// The folded tool length offset (Z).
    tool_length: f64,
    /// A G43/G44 with an unknown length is active in the output.
    passed_length: bool,
    /// The tool length offset rs274 has in force (G44's negative), even
    /// where `tip_path` folds none; `None`: the machine's.
    length_in_force: Option<f64>,
    /// G41/G42 is on: the point in its plane is the comp pass's.
    comp: bool,
    /// `LowerOptions::tip_path`: tool lengths are taken as zero.
    tip_path: bool,
    plane: ir::Plane,
    tools: BTreeMap<u32, ir::Tool>,
    distance: Distance,
    incremental_since: Option<Span>,
    /// G90.1: arc centres are coordinates, shifted as X/Y/Z are.
    centers: Distance,
    /// Position per axis in the output's coordinates, once known.
    position: Position,
    /// Work offsets already reported as unknown.
    warned: u16,
    /// Systems (bit 1..=9) some of whose X, Y, Z a `G10 L2` gave: machine
    /// coordinates, measured from machine zero, which `machine` takes as
    /// G54's origin until the program sets G54 on the machine.
    from_l2: u16,
    /// Those reported as folded on that assumption.
    warned_l2: u16,
}

impl OffsetsPass {
    fn new(cx: &Context<'_>) -> OffsetsPass {
        let mut systems = [[None; 9]; 10];
        systems[1] = [Some(0.0); 9];
        for (&index, origin) in &cx.start.setup.work_offsets {
            let mut o = [Some(0.0); 9];
            for (axis, &v) in origin.iter().enumerate() {
                o[axis] = Some(v);
            }
            systems[index as usize] = o;
        }
        OffsetsPass {
            systems,
            machine: {
                let mut machine = [[None; 9]; 10];
                machine[1] = [Some(0.0); 9];
                machine
            },
            machine_g54_since: None,
            active: 1,
            frame: Frame::Initial,
            local: [0.0; 9],
            g92: [0.0; 9],
            passed_g92: false,
            tool_length: 0.0,
            passed_length: false,
            length_in_force: Some(0.0),
            comp: false,
            tip_path: cx.options.tip_path,
            plane: ir::Plane::XY,
            tools: cx.start.setup.tools.clone(),
            distance: Distance::Absolute,
            incremental_since: None,
            centers: Distance::Incremental,
            position: [None; 9],
            warned: 0,
            from_l2: 0,
            warned_l2: 0,
        }
    }

    /// The system a G10's P names (P0: the active one).
    fn system(&self, p: u8) -> u8 {
        match p {
            0 => self.active,
            p => p,
        }
    }

    fn known(&self, index: u8) -> bool {
        self.systems[index as usize][..3]
            .iter()
            .all(Option::is_some)
    }

    /// The machine's G54 is known, so a known system can be written in
    /// its terms.
    fn g54_usable(&self) -> bool {
        self.machine[1][..3].iter().all(Option::is_some)
    }

    /// The machine has the X, Y and Z of system `index` that ger knows.
    fn machine_has(&self, index: u8) -> bool {
        let i = index as usize;
        self.known(index) && self.machine[i][..3] == self.systems[i][..3]
    }

    /// System `index` is written in G54's terms from here: where a `G10
    /// L2` gave its values (machine coordinates) and the program never set
    /// G54 on the machine, that takes the machine's G54 to be at machine
    /// zero (as in a fresh LinuxCNC parameter file), which ger cannot
    /// know: said once per system.
    fn folds_from_machine_zero(&mut self, index: u8, span: Span, out: &mut Out<'_>) {
        let bit = 1 << index;
        if self.machine_g54_since.is_some() || self.from_l2 & bit == 0 || self.warned_l2 & bit != 0
        {
            return;
        }
        self.warned_l2 |= bit;
        out.report(LowerError::new(
            LowerErrorKind::WorkOffsetFromMachineZero { index },
            span,
        ));
    }

    /// What is added to a G90 coordinate of `axis`.
    fn shift(&self, axis: usize) -> f64 {
        let work = match self.frame {
            Frame::G54 => {
                self.systems[self.active as usize][axis].unwrap_or(0.0)
                    - self.machine[1][axis].unwrap_or(0.0)
            }
            Frame::Initial | Frame::Passed(_) => 0.0,
        };
        work + self.others(axis)
    }

    /// The shifts of `axis` besides the work offset's: G52, G92, the tool
    /// length.
    fn others(&self, axis: usize) -> f64 {
        self.local[axis] + self.g92[axis] + if axis == 2 { self.tool_length } else { 0.0 }
    }

    /// Absolute axis words to the output's coordinates; the position follows.
    fn place(&mut self, to: &mut Axes) {
        for axis in Axis::ALL {
            let Some(v) = to.get(axis) else { continue };
            let i = axis.index();
            match self.distance {
                Distance::Absolute => {
                    let value = v + self.shift(i);
                    to.set(axis, value);
                    self.position[i] = Some(value);
                }
                Distance::Incremental => self.position[i] = self.position[i].map(|p| p + v),
            }
        }
    }

    /// Forget the axes a machine move leaves unknown.
    fn forget_after(&mut self, op: &Op) {
        let unknown = op.unknown_after();
        for axis in Axis::ALL {
            if unknown(axis) {
                self.position[axis.index()] = None;
            }
        }
    }

    /// Switch the output to G54 (from the machine's initial frame or a
    /// passed-through one): nothing is known of the position there.
    fn enter_g54(&mut self, stmt: &Stmt, out: &mut Out<'_>) {
        if self.frame != Frame::G54 {
            self.frame = Frame::G54;
            self.position = [None; 9];
            out.push(stmt.with_op(Op::SelectWorkOffset(1)));
        }
    }

    /// An offset changed under G91 is an error: reported,
    /// and the statement goes no further.
    fn refused_under_incremental(&self, op: &Op, span: Span, out: &mut Out<'_>) -> bool {
        let refused = self.distance == Distance::Incremental && Self::changes_offsets(op);
        if refused {
            out.report(LowerError::new(
                LowerErrorKind::OffsetsUnderIncremental {
                    since: self.incremental_since,
                },
                span,
            ));
        }
        refused
    }

    fn changes_offsets(op: &Op) -> bool {
        matches!(
            op,
            Op::SelectWorkOffset(_)
                | Op::SetWorkOffset { .. }
                | Op::SetWorkOffsetHere { .. }
                | Op::LocalOffset(_)
                | Op::SetPosition(_)
                | Op::CancelPosition
                | Op::ToolLength { .. }
                | Op::CancelToolLength
        )
    }
}

impl Pass for OffsetsPass {
    /// A run of moves under G90 changes no offset: each shift is worked
    /// out once for the run, not for every axis of every move.
    fn feed_each(&mut self, input: &mut [Stmt], to: &mut Batch<'_, '_>) -> usize {
        let centers = self.centers == Distance::Absolute;
        if self.distance != Distance::Absolute || centers || !follows_only(input) {
            return feed_in_turn(self, input, to);
        }
        let shift: [f64; 9] = std::array::from_fn(|i| self.shift(i));
        for stmt in input.iter_mut() {
            if let Op::Move(m) = &mut stmt.op {
                // As `place` does.
                m.to.shift_by(&shift);
                m.to.place(&mut self.position, Some);
            }
        }
        0
    }

    fn feed(&mut self, stmt: &mut Stmt, out: &mut Out<'_>) -> bool {
        let (span, block_delete) = (stmt.span, stmt.block_delete);
        if self.refused_under_incremental(&stmt.op, span, out) {
            return false;
        }
        match &mut stmt.op {
            Op::Distance(d) => {
                self.set_distance(*d, span);
                true
            }
            Op::SetToolData(data) => self.set_tool_data(data, span, out),
            Op::Move(m) => {
                self.place_move(m);
                true
            }
            Op::RigidTap(t) => self.place_tap(t),
            // Its control points are relative to its ends.
            Op::Spline(s) => {
                self.place(&mut s.to);
                true
            }
            Op::ArcCenters(d) => {
                self.centers = *d;
                true
            }
            Op::InverseTime(_) | Op::InverseTimeFloor(_) => true,
            Op::Cycle(c) => {
                self.place_cycle(c);
                true
            }
            Op::Plane(p) => {
                self.plane = *p;
                true
            }
            // Machine coordinates ignore the work offsets and the tool's
            // length alike (rs274: `G53 G0 Z0` under G43 goes to machine
            // Z0 whatever the length): written as they are. A point read
            // back is the tool's offset point, which only the comp pass
            // knows.
            Op::MachineMove(_) | Op::ReadPosition(_) => {
                self.forget_after(&stmt.op);
                true
            }
            Op::Home { via, .. } => {
                self.place(via);
                self.forget_after(&stmt.op);
                true
            }
            Op::SelectWorkOffset(i) => {
                let index = *i;
                self.select_work_offset(index, stmt, out)
            }
            Op::SetWorkOffset { index, origin } => {
                let (index, origin) = (*index, *origin);
                self.set_work_offset(index, &origin, stmt, out)
            }
            Op::SetWorkOffsetHere { index, at } => {
                let index = *index;
                self.set_work_offset_here(index, at, (span, block_delete), out)
            }
            Op::LocalOffset(a) => {
                for (axis, v) in a.iter() {
                    self.local[axis.index()] = v;
                }
                false
            }
            Op::SetPosition(a) => self.set_position(a),
            Op::CancelPosition => self.cancel_position(),
            Op::ToolLength { tool, negative } => {
                let (tool, negative) = (*tool, *negative);
                self.tool_length_offset(tool, negative, stmt, out)
            }
            Op::CancelToolLength => self.cancel_tool_length(),
            Op::Comp { .. } | Op::CompOff => {
                self.comp = matches!(stmt.op, Op::Comp { .. });
                true
            }
            Op::Feed(_)
            | Op::Speed(_)
            | Op::SpindleMode(_)
            | Op::SelectTool(_)
            | Op::ChangeTool
            | Op::Spindle(_)
            | Op::Coolant(_)
            | Op::Dwell(_)
            | Op::Stop(_)
            | Op::End
            | Op::Units(_)
            | Op::Polar(_)
            | Op::DiameterMode(_)
            | Op::ReturnLevel(_)
            | Op::CycleOff
            | Op::PathControl(_)
            | Op::Comment(_)
            | Op::Passthrough(_)
            // (Made by the absolute pass, after this one.)
            | Op::IncrementalMove(_) => true,
        }
    }
}

impl OffsetsPass {
    /// G90/G91, and where G91 began.
    fn set_distance(&mut self, d: Distance, span: Span) {
        self.distance = d;
        if d == Distance::Incremental {
            self.incremental_since = Some(span);
        }
    }

    /// A move's words, and an absolute arc centre's, to the output's
    /// coordinates.
    #[inline]
    fn place_move(&mut self, m: &mut ir::Move) {
        self.place(&mut m.to);
        if let Some(ir::Arc {
            geometry: ir::ArcGeometry::Center(center),
            ..
        }) = &mut m.arc
        {
            if self.centers == Distance::Absolute {
                // The centre's coordinates: in the frame of X/Y/Z,
                // whether those are given under G90 or G91.
                for (i, c) in center.iter_mut().enumerate() {
                    if let Some(c) = c {
                        *c += self.shift(i);
                    }
                }
            }
        }
    }

    /// A rigid tap's point placed; it ends where it started. Goes on.
    fn place_tap(&mut self, t: &mut ir::RigidTap) -> bool {
        let before = self.position;
        self.place(&mut t.to);
        self.position = before;
        true
    }

    /// A canned cycle's holes and R plane to the output's coordinates.
    fn place_cycle(&mut self, c: &mut ir::Cycle) {
        if self.distance == Distance::Absolute {
            // R lies on the drilling axis: the plane's normal.
            let normal = self.plane.axes().2;
            c.r += self.shift(normal);
        }
        self.place(&mut c.at);
        // Where a cycle leaves the tool is the cycles pass's business: the
        // drilling axis, and the holes under G91, are not known here.
        let (a, b, n) = self.plane.axes();
        self.position[n] = None;
        if self.distance == Distance::Incremental {
            self.position[a] = None;
            self.position[b] = None;
        }
    }

    /// G49: whether it goes on. Only a length the machine applies needs
    /// cancelling there.
    fn cancel_tool_length(&mut self) -> bool {
        self.tool_length = 0.0;
        self.length_in_force = Some(0.0);
        let passed = self.passed_length;
        if passed {
            self.passed_length = false;
            self.position[2] = None;
        }
        passed
    }

    /// G54–G59.3: folded when its values are known, else passed through
    /// (with a warning the first time). Whether the statement goes on.
    fn select_work_offset(&mut self, index: u8, stmt: &Stmt, out: &mut Out<'_>) -> bool {
        // SPEC §4.2: G54 cancels G52.
        if index == 1 {
            self.local = [0.0; 9];
        }
        if self.known(index) {
            if !self.g54_usable() && self.machine_has(index) {
                // The values are the program's, on the machine already.
                self.active = index;
                self.frame = Frame::Passed(index);
                self.position = [None; 9];
                return true;
            }
            if !self.g54_usable() {
                out.report(LowerError::new(
                    LowerErrorKind::WorkOffsetOverMachineG54 {
                        index,
                        since: self.machine_g54_since,
                    },
                    stmt.span,
                ));
                return false;
            }
            self.folds_from_machine_zero(index, stmt.span, out);
            self.active = index;
            self.enter_g54(stmt, out);
            return false;
        }
        if self.warned & (1 << index) == 0 {
            self.warned |= 1 << index;
            out.report(LowerError::new(
                LowerErrorKind::WorkOffsetUnknown { index },
                stmt.span,
            ));
        }
        self.active = index;
        self.frame = Frame::Passed(index);
        self.position = [None; 9];
        true
    }

    /// G10 L2: the origin of a system (P0: the active one). Folded, or
    /// passed through to the machine (module doc); whether it goes on.
    fn set_work_offset(
        &mut self,
        index: u8,
        origin: &Axes,
        stmt: &Stmt,
        out: &mut Out<'_>,
    ) -> bool {
        let index = self.system(index);
        for (axis, v) in origin.iter() {
            self.systems[index as usize][axis.index()] = Some(v);
            if axis.index() < 3 {
                self.from_l2 |= 1 << index;
            }
        }
        let folds = self.frame != Frame::Initial
            && self.known(index)
            && (self.frame != Frame::Passed(index) || self.g54_usable());
        if !folds {
            for (axis, v) in origin.iter() {
                self.machine[index as usize][axis.index()] = Some(v);
            }
            if index == 1 {
                self.machine_g54_since = Some(stmt.span);
            }
            // The machine's active system may be the one it changes.
            self.position = [None; 9];
            return true;
        }
        if self.frame == Frame::Passed(index) {
            self.enter_g54(stmt, out);
        }
        if index == self.active {
            self.folds_from_machine_zero(index, stmt.span, out);
        }
        false
    }

    /// G10 L20: a system moved so that the current point has `at`. Folded
    /// when the point is known in G54's frame; else the machine does it
    /// (after homing, `G10 L20 P1 X0 Y0 Z50` is how grbl programs set their
    /// zero): passed through, and that system's values are the machine's
    /// from here. Whether the statement goes on. Passed through, `at`
    /// takes the shifts ger folds (G52, G92, a known tool length): the
    /// machine has none of them, and the program's point is its point
    /// with them.
    fn set_work_offset_here(
        &mut self,
        index: u8,
        at: &mut Axes,
        (span, block_delete): (Span, bool),
        out: &mut Out<'_>,
    ) -> bool {
        let index = self.system(index);
        // A G92 of the machine's own lies between the output's
        // coordinates and G54's.
        let known = self.frame == Frame::G54
            && !self.passed_g92
            && at.iter().all(|(axis, _)| {
                self.position[axis.index()].is_some() && self.machine[1][axis.index()].is_some()
            });
        if !known && self.frame == Frame::G54 && index == self.active && index != 1 {
            // The active system is written in G54's terms: the machine is
            // in G54. From here it must be in that system, whose other
            // values must then be the program's.
            let i = index as usize;
            let rest =
                (0..3).all(|a| at.has(Axis::ALL[a]) || self.machine[i][a] == self.systems[i][a]);
            if !rest {
                out.report(LowerError::new(
                    LowerErrorKind::WorkOffsetHereFolded { index },
                    span,
                ));
                return false;
            }
            let mut select = Stmt::new(Op::SelectWorkOffset(index), span);
            select.block_delete = block_delete;
            out.push(select);
        }
        if !known {
            out.report(LowerError::new(
                LowerErrorKind::WorkOffsetSetByMachine { index },
                span,
            ));
            self.systems[index as usize] = [None; 9];
            for (axis, _) in at.iter() {
                self.machine[index as usize][axis.index()] = None;
            }
            if index == 1 {
                self.machine_g54_since = Some(span);
            }
            if index == self.active {
                self.frame = Frame::Passed(index);
                self.position = [None; 9];
            }
            at.shift_by(&std::array::from_fn(|i| self.others(i)));
            return true;
        }
        for (axis, v) in at.iter() {
            let i = axis.index();
            if let (Some(p), Some(g54)) = (self.position[i], self.machine[1][i]) {
                // The point measured from G54's origin, as `systems` are.
                self.systems[index as usize][i] = Some(p + g54 - v - self.others(i));
            }
        }
        // Measured from where the tool is, not from machine zero.
        if Axis::ALL[..3].iter().all(|&a| at.has(a)) {
            self.from_l2 &= !(1 << index);
        }
        false
    }

    /// G92: the G92 shift chosen so that the current point reads `a`,
    /// where that point is known; else the machine's (module doc).
    /// Whether the statement goes on.
    fn set_position(&mut self, a: &mut Axes) -> bool {
        let known = a
            .iter()
            .all(|(axis, _)| self.position[axis.index()].is_some());
        let given = *a;
        for (axis, v) in given.iter() {
            let i = axis.index();
            // The machine's G92 replaces the program's on these axes.
            self.g92[i] = 0.0;
            if known {
                self.g92[i] = self.position[i].unwrap_or(0.0) - v - self.shift(i);
            } else {
                let value = v + self.shift(i);
                a.set(axis, value);
                self.position[i] = Some(value);
            }
        }
        self.passed_g92 |= !known;
        !known
    }

    /// G92.1: whether it goes on (only the machine can cancel its own).
    fn cancel_position(&mut self) -> bool {
        self.g92 = [0.0; 9];
        let passed = std::mem::take(&mut self.passed_g92);
        if passed {
            self.position = [None; 9];
        }
        passed
    }

    /// G43/G44: folded when the tool's length is known, else passed
    /// through with a warning. Whether the statement goes on.
    fn tool_length_offset(
        &mut self,
        tool: Option<u32>,
        negative: bool,
        stmt: &Stmt,
        out: &mut Out<'_>,
    ) -> bool {
        let length = tool.and_then(|t| self.tools.get(&t)).and_then(|t| t.length);
        self.length_in_force = length.map(|l| if negative { -l } else { l });
        if self.tip_path {
            // The tip's path: whatever the length, the tip is where the
            // program says.
            self.tool_length = 0.0;
            return false;
        }
        if let Some(length) = length {
            self.tool_length = if negative { -length } else { length };
            if self.passed_length {
                // The machine's own offset is still on: cancel it.
                self.passed_length = false;
                self.position[2] = None;
                out.push(stmt.with_op(Op::CancelToolLength));
            }
            return false;
        }
        out.report(LowerError::new(
            LowerErrorKind::ToolLengthUnknown {
                tool: tool.unwrap_or(0),
            },
            stmt.span,
        ));
        self.tool_length = 0.0;
        self.passed_length = true;
        self.position[2] = None;
        true
    }
}

impl OffsetsPass {
    /// G10 L1/L10/L11: the tool's data from here on. An L10 or L11 Z is
    /// made the length it sets (rs274's convert_setup_tool), so that what
    /// goes on is an L1; where that needs what only the machine knows, an
    /// error. Whether the statement goes on.
    fn set_tool_data(&mut self, data: &mut ir::ToolData, span: Span, out: &mut Out<'_>) -> bool {
        if let (Some(z), true) = (data.length, data.measured != ir::Measured::Given) {
            match self.measured_length(data.measured, z) {
                Ok(length) => data.length = Some(length),
                Err(unknown) => {
                    let l = data.measured.l_number();
                    out.report(LowerError::new(
                        LowerErrorKind::ToolLengthNotMeasurable { l, unknown },
                        span,
                    ));
                    return false;
                }
            }
        }
        data.measured = ir::Measured::Given;
        data.apply(&mut self.tools, true);
        true
    }

    /// The length with which the current point reads `z`: with the
    /// offsets in force (L10), or in G59.3 without G92 and G52 (L11: the
    /// machine position less G59.3's origin). Both start from the point
    /// without the tool length offset in force.
    fn measured_length(&self, measured: ir::Measured, z: f64) -> Result<f64, Unmeasurable> {
        let z_axis = Axis::Z.index();
        let Some(in_force) = self.length_in_force else {
            return Err(Unmeasurable::LengthInForce);
        };
        if self.comp && self.plane != ir::Plane::XY {
            return Err(Unmeasurable::CompOnZ);
        }
        let Some(at) = self.position[z_axis] else {
            return Err(Unmeasurable::Position);
        };
        // The output's coordinate with rs274's length in force, not the
        // folded one (they differ under `tip_path`).
        let bare = at - self.tool_length + in_force;
        match measured {
            ir::Measured::Given | ir::Measured::Here => {
                Ok(bare - (self.shift(z_axis) - self.tool_length) - z)
            }
            ir::Measured::InFixture => {
                if self.passed_g92 {
                    return Err(Unmeasurable::MachineG92);
                }
                let fixture = match self.frame {
                    // The output's coordinates are measured from G59.3.
                    Frame::Passed(9) => 0.0,
                    Frame::G54 => {
                        let g59_3 = self.systems[9][z_axis].ok_or(Unmeasurable::Fixture)?;
                        let g54 = self.machine[1][z_axis].ok_or(Unmeasurable::MachineG54)?;
                        g59_3 - g54
                    }
                    Frame::Initial | Frame::Passed(_) => return Err(Unmeasurable::MachineFrame),
                };
                Ok(bare - fixture - z)
            }
        }
    }
}
