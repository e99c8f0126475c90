//! Canned cycle blocks (G73, G74, G81–G89): the words a block gives, the
//! words it may leave out, and the checks rs274 makes before it drills.
//! What the block does to the tool is the cycles pass's business
//! (`lower/cycles.rs`); here each block becomes one complete
//! [`ir::Cycle`].
//!
//! rs274's rules (LinuxCNC 2.9, `interp_convert.cc` / `interp_cycles.cc`):
//! R and the depth may be left out only by a block of the same cycle as
//! the one before it (a repeat), and so may Q (G73, G83), P (G82, G86,
//! G88, G89) and I/J/K (G87); the values kept are shared by all cycles
//! (G84 and G74 dwell for the last P given to any cycle, 0 at first). A
//! run of cycles starts at the first cycle block after any other motion
//! code or G80; where the tool is then is the G98 level of the run.

use super::codes::error::{CodeError, CodeErrorKind};
use super::evaluator::Evaluator;
use super::options::Flavour;
use super::polar::PolarStep;
use super::state::Sticky;
use super::words::WordValues;
use crate::diagnostic::{error, warning, Diagnostic, DiagnosticExt, Located, Wording};
use crate::ir::{self, Axis, CycleKind, Op};
use crate::source::Span;

/// More pecks than this in one hole is a mistake (a tiny Q).
pub const MAX_PECKS: u32 = 10_000;

/// The cycle a G code in tenths names.
pub(super) fn kind_of(t: u32) -> Option<CycleKind> {
    Some(match t {
        730 => CycleKind::G73,
        740 => CycleKind::G74,
        810 => CycleKind::G81,
        820 => CycleKind::G82,
        830 => CycleKind::G83,
        840 => CycleKind::G84,
        850 => CycleKind::G85,
        860 => CycleKind::G86,
        870 => CycleKind::G87,
        880 => CycleKind::G88,
        890 => CycleKind::G89,
        _ => return None,
    })
}

/// A cycle block that lacks a word it needs.
fn missing(kind: CycleKind, what: char, help: &'static str, at: Span) -> Diagnostic {
    CycleBlockError::new(CycleBlockErrorKind::Missing { kind, what, help }, at).into()
}

fn takes_dwell(kind: CycleKind) -> bool {
    matches!(
        kind,
        CycleKind::G76
            | CycleKind::G87Fanuc
            | CycleKind::G82
            | CycleKind::G84
            | CycleKind::G74
            | CycleKind::G86
            | CycleKind::G88
            | CycleKind::G89
    )
}

/// Cycles whose first block must give P (G84 and G74 need not).
fn needs_dwell(kind: CycleKind) -> bool {
    matches!(
        kind,
        CycleKind::G82 | CycleKind::G86 | CycleKind::G88 | CycleKind::G89
    )
}

fn pecks(kind: CycleKind) -> bool {
    matches!(kind, CycleKind::G73 | CycleKind::G83)
}

/// The spindle direction a cycle needs, if it needs one.
fn spindle_needed(kind: CycleKind) -> Option<Option<ir::Spindle>> {
    match kind {
        CycleKind::G84 => Some(Some(ir::Spindle::Clockwise)),
        CycleKind::G74 => Some(Some(ir::Spindle::CounterClockwise)),
        CycleKind::G76 | CycleKind::G86 | CycleKind::G87 | CycleKind::G87Fanuc | CycleKind::G88 => {
            Some(None)
        }
        _ => None,
    }
}

/// The pecks of one hole, as rs274 counts them: the depth goes down by Q
/// from R while it is above the bottom, in the program's numbers (so a
/// Q that divides the depth exactly in decimal may give one more peck
/// than arithmetic says, as it does on LinuxCNC). `None` past
/// [`MAX_PECKS`].
pub fn count_pecks(r: f64, bottom: f64, q: f64) -> Option<u32> {
    let mut n = 0;
    let mut d = r - q;
    while d > bottom {
        n += 1;
        if n > MAX_PECKS {
            return None;
        }
        d -= q;
    }
    Some(n)
}

/// The hole of a cycle block: its words on the plane's three axes (the
/// normal one is the bottom), taken from `w`. An axis off the plane is an
/// error, and so is a block with none of the three.
fn hole_words(
    kind: CycleKind,
    w: &mut WordValues,
    plane: ir::Plane,
    at_code: Span,
) -> Result<ir::Axes, Diagnostic> {
    if let Some((letter, at)) = [b'A', b'B', b'C', b'U', b'V', b'W']
        .into_iter()
        .find_map(|l| w.given(l).map(|s| (l, s)))
    {
        return Err(
            CycleBlockError::new(CycleBlockErrorKind::OtherAxis(letter as char), at).into(),
        );
    }
    let (a, b, n) = plane.axes();
    let mut at = ir::Axes::default();
    for axis in [a, b, n].map(|i| Axis::ALL[i]) {
        if let Some((v, _)) = w.take(axis.letter()) {
            at.set(axis, v);
        }
    }
    if at.is_empty() {
        return Err(CycleBlockError::new(CycleBlockErrorKind::NoHole(kind), at_code).into());
    }
    Ok(at)
}

impl Evaluator<'_> {
    /// A cycle block: `kind` given by its G code (`code` is its span), or
    /// repeated by axis words (`code` is `None`).
    pub(super) fn cycle_block(
        &mut self,
        kind: CycleKind,
        code: Option<Span>,
        w: &mut WordValues,
        span: Span,
    ) -> Result<(), Diagnostic> {
        let at_code = code.unwrap_or(span);
        self.warn_return_level(at_code);
        self.check_units_in_run(at_code)?;
        // A block of the same cycle may leave out what the last one gave.
        let repeat = self.cycles.kind == Some(kind);
        let polar = self.polar_words(w)?;
        let mut at = hole_words(kind, w, self.modal.plane, at_code)?;
        let n = Axis::ALL[self.modal.plane.axes().2];
        // A word as given, else the last block's (a repeat may leave it
        // out), else missing.
        let sticky = self.cycles.sticky;
        let last = |v: f64| repeat.then_some(v);
        let r = w
            .take(b'R')
            .map(|(r, _)| r)
            .or(last(sticky.r))
            .ok_or_else(|| {
                let help = "R is the level the hole starts from: `G81 X10 Y5 Z-3 R1`";
                missing(kind, 'R', help, at_code)
            })?;
        let depth = at.get(n).or(last(sticky.depth)).ok_or_else(|| {
            let help = "the normal axis of the plane gives the hole's bottom";
            missing(kind, n.letter() as char, help, at_code)
        })?;
        at.set(n, depth);
        let q = self.cycle_peck(kind, w, repeat, at_code)?;
        let dwell = self.cycle_dwell(kind, w, repeat, at_code)?;
        let (ijk, repeats) = self.offsets_and_repeats(kind, w, repeat, at_code)?;
        self.check_machine_for_cycle(kind, r, depth, n, at_code)?;
        let pecks = match q {
            Some(q) if pecks(kind) && self.modal.distance == ir::Distance::Absolute => {
                Some(count_pecks(r, depth, q).ok_or_else(|| -> Diagnostic {
                    CycleBlockError::new(CycleBlockErrorKind::TooManyPecks, at_code).into()
                })?)
            }
            _ => None,
        };
        self.cycles.sticky = Sticky {
            r,
            depth,
            q: q.unwrap_or(sticky.q),
            p: dwell.unwrap_or(sticky.p),
            ijk: if kind == CycleKind::G87 {
                ijk.map(|v| v.unwrap_or(0.0))
            } else {
                sticky.ijk
            },
        };
        let starts_run = !self.cycles.run_open;
        self.cycles.run_open = true;
        let cycle = ir::Cycle {
            kind,
            at,
            r,
            q,
            dwell,
            repeats,
            ijk,
            starts_run,
            pecks,
            kept: None,
        };
        self.cycles.kind = Some(kind);
        self.modal.synced = None;
        match polar {
            Some(step) if repeats > 1 => self.polar_repeats(cycle, step, span),
            _ => self.emit(Op::Cycle(Box::new(cycle)), span),
        }
    }

    /// A G91 cycle block with polar words and L repeats: each hole a block
    /// of its own, one polar step on from the last (rs274 steps the
    /// radius and angle before each hole, not X and Y).
    fn polar_repeats(
        &mut self,
        cycle: ir::Cycle,
        step: PolarStep,
        span: Span,
    ) -> Result<(), Diagnostic> {
        let mut from = step.from;
        for hole in 0..cycle.repeats {
            let to = step.next(from).ok_or_else(|| -> Diagnostic {
                let kind = CodeErrorKind::PolarAtOrigin { incremental: true };
                CodeError::new(kind, span).into()
            })?;
            let mut one = cycle;
            one.repeats = 1;
            one.starts_run = cycle.starts_run && hole == 0;
            one.at.set(Axis::X, to.0 - from.0);
            one.at.set(Axis::Y, to.1 - from.1);
            self.emit(Op::Cycle(Box::new(one)), span)?;
            from = to;
        }
        Ok(())
    }

    /// LinuxCNC keeps the run's G98 level (the Z it started from, and
    /// under G91 what R is measured from) as a number, in the units it was
    /// set in: after G20/G21 within a run it means another height.
    fn check_units_in_run(&mut self, at_code: Span) -> Result<(), Diagnostic> {
        match self.cycles.units_changed_at {
            Some(units) if self.cycles.run_open => {
                let kind = CycleBlockErrorKind::UnitsChangedInRun { units };
                Err(CycleBlockError::new(kind, at_code).into())
            }
            _ => {
                self.cycles.units_changed_at = None;
                Ok(())
            }
        }
    }

    /// What the machine must be for the cycle to run: R above the bottom,
    /// the spindle as the cycle needs it, a feed, and not G93.
    fn check_machine_for_cycle(
        &self,
        kind: CycleKind,
        r: f64,
        depth: f64,
        n: Axis,
        at_code: Span,
    ) -> Result<(), Diagnostic> {
        match kind {
            CycleKind::G87Fanuc => self.check_back_bore(r, depth, n, at_code)?,
            _ => self.check_levels(r, depth, n, at_code)?,
        }
        if let Some(needed) = spindle_needed(kind) {
            self.check_spindle(kind, needed, at_code)?;
        }
        if self.modal.feed.is_none() {
            return Err(CycleBlockError::new(CycleBlockErrorKind::NoFeed, at_code).into());
        }
        if self.modal.inverse_time {
            let kind = CycleBlockErrorKind::InverseTime;
            return Err(CycleBlockError::new(kind, at_code).into());
        }
        if self.modal.at_zero_feed() {
            return Err(CycleBlockError::new(CycleBlockErrorKind::ZeroFeed, at_code).into());
        }
        Ok(())
    }

    /// The depth of each peck of a pecking cycle (its Q, or the last
    /// block's); `None` for a cycle that does not peck.
    fn cycle_peck(
        &self,
        kind: CycleKind,
        w: &mut WordValues,
        repeat: bool,
        at_code: Span,
    ) -> Result<Option<f64>, Diagnostic> {
        if matches!(kind, CycleKind::G76 | CycleKind::G87Fanuc) {
            return self.boring_shift(w, repeat);
        }
        if !pecks(kind) {
            return Ok(None);
        }
        let q = match w.take(b'Q') {
            Some((q, qspan)) if q <= 0.0 => {
                return Err(
                    CycleBlockError::new(CycleBlockErrorKind::PeckNotPositive, qspan).into(),
                )
            }
            given => given.map(|(q, _)| q),
        };
        let help = "Q is the depth of each peck: `G83 X10 Z-12 R1 Q3`";
        let q = q.or(repeat.then_some(self.cycles.sticky.q));
        q.map(Some).ok_or_else(|| missing(kind, 'Q', help, at_code))
    }

    /// Fanuc's G76's Q: how far the tool moves off the wall at the bottom
    /// before it leaves (0 when not given, as on Fanuc).
    fn boring_shift(&self, w: &mut WordValues, repeat: bool) -> Result<Option<f64>, Diagnostic> {
        match w.take(b'Q') {
            Some((q, qspan)) if q < 0.0 => {
                Err(CycleBlockError::new(CycleBlockErrorKind::NegativeShift, qspan).into())
            }
            Some((q, _)) => Ok(Some(q)),
            None => Ok(Some(if repeat { self.cycles.sticky.q } else { 0.0 })),
        }
    }

    /// The dwell at the bottom, in seconds, of a cycle that dwells (its P,
    /// or the last block's); `None` for one that does not.
    fn cycle_dwell(
        &mut self,
        kind: CycleKind,
        w: &mut WordValues,
        repeat: bool,
        at_code: Span,
    ) -> Result<Option<f64>, Diagnostic> {
        // Fanuc's G86 (and Haas's) has no dwell word: a P there is refused
        // as any unexpected word is.
        let fanuc_g86 = kind == CycleKind::G86 && self.options.from == Flavour::Fanuc;
        // Haas's G81 and G73 (read as Fanuc's) dwell when given P; rs274
        // refuses it. Only then, and on a repeat of a block that did.
        let haas =
            matches!(kind, CycleKind::G81 | CycleKind::G73) && self.options.from == Flavour::Fanuc;
        if haas {
            let p = match w.take_number(b'P') {
                Some((p, pspan, _)) => Some(self.seconds(p, pspan)?),
                None => self.cycles.last_dwell.filter(|_| repeat),
            };
            self.cycles.last_dwell = p;
            return Ok(p);
        }
        if !takes_dwell(kind) || fanuc_g86 {
            self.cycles.last_dwell = None;
            return Ok(None);
        }
        let p = match w.take_number(b'P') {
            Some((p, pspan, _)) => Some(self.seconds(p, pspan)?),
            None => (repeat || !needs_dwell(kind)).then_some(self.cycles.sticky.p),
        };
        let help = "P is the dwell at the bottom in seconds: `G82 X10 Z-3 R1 P0.5`";
        self.cycles.last_dwell = p;
        p.map(Some).ok_or_else(|| missing(kind, 'P', help, at_code))
    }

    /// A warning, once, when a cycle comes before any G98/G99: where it
    /// returns is the machine's power-up state.
    fn warn_return_level(&mut self, at_code: Span) {
        if self.cycles.return_level_stated {
            return;
        }
        let from = self.options.from;
        self.warn_once((b'G', 989), || {
                let (level, who) = match from.power_up_return_level() {
                    ir::ReturnLevel::Initial => ("the initial level (G98)", "Fanuc, Haas and Mach3 do"),
                    ir::ReturnLevel::R => ("the R plane (G99)", "LinuxCNC does"),
                };
                warning(
                    "the program does not say G98 or G99",
                    at_code,
                    format!("this cycle returns to {level}, as {who} at power-up"),
                )
                .with_note("where a cycle returns between holes is the machine's state until the program sets it")
                .with_help("write G98 or G99 before the first cycle, or choose the controller with --from")
            });
    }

    /// G87's I, J, K (the others' K is Fanuc's hole count), and the
    /// number of holes from L or K.
    fn offsets_and_repeats(
        &self,
        kind: CycleKind,
        w: &mut WordValues,
        repeat: bool,
        at_code: Span,
    ) -> Result<(ir::Center, u32), Diagnostic> {
        let mut ijk: ir::Center = [None; 3];
        let mut fanuc_k = None;
        if kind == CycleKind::G87 {
            for (i, letter) in [b'I', b'J', b'K'].into_iter().enumerate() {
                let given = w.take(letter).map(|(v, _)| v);
                let help =
                    "G87 needs I, J (the offset to pass the bar) and K (the back-bore level)";
                let v = given.or(repeat.then_some(self.cycles.sticky.ijk[i]));
                ijk[i] = Some(v.ok_or_else(|| missing(kind, letter as char, help, at_code))?);
            }
        } else {
            fanuc_k = w.take(b'K');
        }
        let repeats = match (w.take(b'L'), fanuc_k) {
            (Some(_), Some((_, kspan))) => {
                return Err(CycleBlockError::new(CycleBlockErrorKind::BothLAndK, kspan).into())
            }
            (Some((l, lspan)), None) | (None, Some((l, lspan))) => {
                if l < 1.0 || l.fract() != 0.0 || l > MAX_PECKS as f64 {
                    return Err(
                        CycleBlockError::new(CycleBlockErrorKind::RepeatCount, lspan).into(),
                    );
                }
                l as u32
            }
            (None, None) => 1,
        };
        Ok((ijk, repeats))
    }

    /// Fanuc's G87: R (where the tool goes down to) below the top of the
    /// back bore (under G91 measured up from R).
    fn check_back_bore(&self, r: f64, top: f64, n: Axis, at_code: Span) -> Result<(), Diagnostic> {
        let incremental = self.modal.distance == ir::Distance::Incremental;
        if (incremental && top <= 0.0) || (!incremental && r >= top) {
            let kind = CycleBlockErrorKind::BackBoreLevels {
                axis: n.letter() as char,
            };
            return Err(CycleBlockError::new(kind, at_code).into());
        }
        Ok(())
    }

    /// R above the hole's bottom (under G91 the depth goes down from R).
    fn check_levels(&self, r: f64, depth: f64, n: Axis, at_code: Span) -> Result<(), Diagnostic> {
        let axis = n.letter() as char;
        if r < depth && self.modal.distance == ir::Distance::Absolute {
            return Err(CycleBlockError::new(
                CycleBlockErrorKind::RBelowBottom { r, axis, depth },
                at_code,
            )
            .into());
        }
        if self.modal.distance == ir::Distance::Incremental && depth > 0.0 {
            return Err(CycleBlockError::new(
                CycleBlockErrorKind::BottomAboveR { axis, depth },
                at_code,
            )
            .into());
        }
        Ok(())
    }

    fn check_spindle(
        &self,
        kind: CycleKind,
        needed: Option<ir::Spindle>,
        at: Span,
    ) -> Result<(), Diagnostic> {
        let turning = self.modal.spindle != ir::Spindle::Off;
        let label = match needed {
            _ if !turning => "the spindle is not turning here",
            Some(dir) if dir != self.modal.spindle => match dir {
                ir::Spindle::Clockwise => "the spindle turns counter-clockwise (M4) here",
                _ => "the spindle turns clockwise (M3) here",
            },
            _ => return Ok(()),
        };
        let help = match kind {
            CycleKind::G84 => "G84 taps right-hand: start the spindle with M3",
            CycleKind::G74 => "G74 taps left-hand: start the spindle with M4",
            _ => "start the spindle with M3 or M4 before the cycle",
        };
        Err(CycleBlockError::new(CycleBlockErrorKind::NoSpindle { kind, label, help }, at).into())
    }
}

/// What a canned cycle block gets wrong.
#[derive(Clone, Debug, PartialEq)]
pub enum CycleBlockErrorKind {
    /// An A B C U V W word.
    OtherAxis(char),
    NoHole(CycleKind),
    /// A word the first block of a run must give, and how to give it.
    Missing {
        kind: CycleKind,
        what: char,
        help: &'static str,
    },
    PeckNotPositive,
    /// G76's Q below 0.
    NegativeShift,
    BothLAndK,
    RepeatCount,
    RBelowBottom {
        r: f64,
        axis: char,
        depth: f64,
    },
    /// Under G91 the depth is measured from R and must go down.
    BottomAboveR {
        axis: char,
        depth: f64,
    },
    /// Fanuc's G87 with R not below the top of the back bore.
    BackBoreLevels {
        axis: char,
    },
    NoFeed,
    /// A cycle after F0 (rs274: "Cannot feed with zero feed rate").
    ZeroFeed,
    /// A cycle under G93.
    InverseTime,
    TooManyPecks,
    /// A block continuing a run of cycles after G20/G21 (at `units`)
    /// changed the units inside it.
    UnitsChangedInRun {
        units: Span,
    },
    /// The spindle is off or turns the wrong way.
    NoSpindle {
        kind: CycleKind,
        label: &'static str,
        help: &'static str,
    },
}

/// What goes wrong, and where: see [`CycleBlockErrorKind`].
pub type CycleBlockError = Located<CycleBlockErrorKind>;

impl Wording for CycleBlockErrorKind {
    fn wording(&self, at: Span) -> Diagnostic {
        match self {
            CycleBlockErrorKind::OtherAxis(letter) => error(
                format!("`{letter}` in a canned cycle"),
                at,
                "a cycle moves only X, Y and Z",
            ),
            CycleBlockErrorKind::NoHole(kind) => error(
                format!("G{} without a hole", kind.code()),
                at,
                "no X, Y or Z here",
            )
            .with_help("give the hole's position and depth: `G81 X10 Y5 Z-3 R1`"),
            CycleBlockErrorKind::Missing { kind, what, help } => error(
                format!("G{} without {what}", kind.code()),
                at,
                "the first block of a cycle gives it",
            )
            .with_help(*help),
            CycleBlockErrorKind::PeckNotPositive => error(
                "a peck depth that is not positive",
                at,
                "Q must be more than 0",
            ),
            CycleBlockErrorKind::NegativeShift => error(
                "a negative shift",
                at,
                "G76's Q is how far the tool moves off the wall: 0 or more",
            )
            .with_note("the direction is the machine's (a parameter): ger shifts along +X in G17"),
            CycleBlockErrorKind::BothLAndK => error(
                "both L and K",
                at,
                "L and Fanuc's K both count the holes; give one",
            ),
            CycleBlockErrorKind::RepeatCount => error(
                "a repeat count that is not a whole number from 1",
                at,
                format!("the count of holes, 1 to {MAX_PECKS}"),
            ),
            CycleBlockErrorKind::RBelowBottom { r, axis, depth } => error(
                "R below the hole's bottom",
                at,
                format!("R{r} is below {axis}{depth}"),
            )
            .with_help("R is the level the hole starts from, above its bottom"),
            CycleBlockErrorKind::BottomAboveR { axis, depth } => error(
                "R below the hole's bottom",
                at,
                format!("under G91 {axis}{depth} is measured from R, and goes up"),
            ),
            CycleBlockErrorKind::BackBoreLevels { axis } => error(
                "G87 with R not below the back bore",
                at,
                format!("Fanuc's G87 goes down to R under the part and feeds up to {axis}"),
            )
            .with_help("R is the level below the part, the depth word the top of the back bore: `G87 X0 Y0 Z-10 R-25 Q0.5`"),
            CycleBlockErrorKind::NoFeed => error(
                "a canned cycle before any feed rate",
                at,
                "no F word has been given yet",
            )
            .with_help("set the feed on this line or before it: `G81 X10 Z-3 R1 F100`"),
            CycleBlockErrorKind::ZeroFeed => error(
                "a canned cycle at a zero feed rate",
                at,
                "the feed rate is 0 here",
            )
            .with_note("its feeds would never end: rs274 refuses it (\"Cannot feed with zero feed rate\")")
            .with_help("set a feed above 0 on this line or before it: `G81 X10 Z-3 R1 F100`"),
            CycleBlockErrorKind::InverseTime => error(
                "a canned cycle under G93",
                at,
                "inverse time feed is on",
            )
            .with_note("rs274 refuses canned cycles in inverse time")
            .with_help("switch to G94 and give a feed per minute before the cycle"),
            CycleBlockErrorKind::TooManyPecks => error(
                format!("more than {MAX_PECKS} pecks in one hole"),
                at,
                "Q is very small for this depth",
            ),
            CycleBlockErrorKind::UnitsChangedInRun { units } => error(
                "a canned cycle continues after the units changed",
                at,
                "this block goes on from the run's first block",
            )
            .with_secondary(*units, "the units change here, inside the run")
            .with_note("LinuxCNC keeps the level the run started from as a number in the old units: this block would retract to, or measure R from, another height")
            .with_help("end the run with G80 before G20/G21, and start the cycle again"),
            CycleBlockErrorKind::NoSpindle { kind, label, help } => {
                error(format!("G{} needs the spindle", kind.code()), at, *label).with_help(*help)
            }
        }
    }
}
