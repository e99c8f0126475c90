//! The order of execution inside one block (SPEC §2.2), rs274's: whatever
//! order a line writes its codes in, feed, speed and tool come first, then
//! the tool change, spindle, coolant, dwell, the modes (plane, units,
//! distance, compensation, length offset, work offset, path mode, return
//! level), the non-modal codes that take axes (G10, G28, G30, G52, G92), the
//! motion, and last the stops and program end. So `G1 Y40 M8` turns the
//! coolant on before the move and `G28 G91 Z0` goes home through a point
//! given incrementally.
//!
//! Each code takes the words it uses from anywhere in the line. A line
//! with two codes of one modal group (`G0 X1 G1 X2`) keeps Ger's in-order
//! reading: every code takes the words after it.

use crate::ast::{LineStmt, Word, WordValue};

/// A statement of a reordered block: a code and the words it takes.
pub struct Owned {
    pub code: Option<Word>,
    pub args: Vec<Word>,
}

impl Owned {
    pub fn as_stmt(&self) -> LineStmt<'_> {
        LineStmt {
            code: self.code.as_ref(),
            args: &self.args,
        }
    }
}

/// The statements of a line of `words` with two codes or more (a line
/// with fewer keeps its order: `ast::few_statements`) in rs274's order, or
/// `None` when its own order stands (two codes of one modal group, or a
/// code ger does not place).
pub fn in_order(words: &[Word]) -> Option<Vec<Owned>> {
    let codes: Vec<&Word> = words.iter().filter(|w| w.is_code()).collect();
    let kinds: Vec<Kind> = codes.iter().map(|c| kind_of(c)).collect::<Option<_>>()?;
    for (i, kind) in kinds.iter().enumerate() {
        let group = kind.group();
        if group != Group::Alone && kinds[..i].iter().any(|k| k.group() == group) {
            return None;
        }
    }
    let mut stmts: Vec<(u8, Owned)> = codes
        .iter()
        .zip(&kinds)
        .map(|(&c, kind)| {
            (
                kind.rank_of(c),
                Owned {
                    code: Some(c.clone()),
                    args: Vec::new(),
                },
            )
        })
        .collect();
    // F, S and T (and axis words with no code to take them) form a
    // statement of their own: first, or where the motion goes.
    let mut first = Owned {
        code: None,
        args: Vec::new(),
    };
    let mut moves = Owned {
        code: None,
        args: Vec::new(),
    };
    for w in words.iter().filter(|w| !w.is_code()) {
        match taker(w.letter, &codes, &kinds) {
            Some(i) => {
                stmts[i].1.args.push(w.clone());
                // rs274's G64 reads the line's P and Q whoever else does
                // (`G4 P0.5 G64` dwells 0.5 s and blends within 0.5).
                let blend = (0..kinds.len())
                    .find(|&j| j != i && kinds[j] == Kind::PathMode && reads(codes[j], w.letter));
                if let Some(j) = blend {
                    stmts[j].1.args.push(w.clone());
                }
            }
            None if matches!(w.letter, b'F' | b'S' | b'T' | b'N') => first.args.push(w.clone()),
            None => moves.args.push(w.clone()),
        }
    }
    if !first.args.is_empty() {
        stmts.push((0, first));
    }
    if !moves.args.is_empty() {
        stmts.push((Kind::Motion.rank(), moves));
    }
    stmts.sort_by_key(|(rank, _)| *rank);
    Some(stmts.into_iter().map(|(_, s)| s).collect())
}

/// Which code of the line takes a word with this letter: the first, in
/// rs274's order of preference, that reads it (`G64 P0.25 G40`, `G64 P0.1
/// G1 X2`: G64's tolerance; `G92.1 G1 X0`: G1's end); with none that
/// reads it, the first of the kinds that might, whose diagnostic then
/// names it.
fn taker(letter: u8, codes: &[&Word], kinds: &[Kind]) -> Option<usize> {
    let order: &[Kind] = match letter {
        b'X' | b'Y' | b'Z' | b'A' | b'B' | b'C' | b'U' | b'V' | b'W' | b'@' | b'^' => {
            &[Kind::AxisUser, Kind::Motion]
        }
        b'I' | b'J' | b'K' | b'R' => &[Kind::AxisUser, Kind::Motion],
        Word::ROUND | Word::CHAMFER => &[Kind::Motion],
        // (G76's spring passes, LinuxCNC.)
        b'H' => &[Kind::ToolLength, Kind::Motion],
        b'D' => &[Kind::Comp, Kind::SpindleMode],
        // G96's surface speed; else a statement of its own.
        b'S' => {
            return (0..kinds.len())
                .find(|&i| kinds[i] == Kind::SpindleMode && reads(codes[i], letter))
        }
        b'P' | b'Q' | b'L' | b'E' => &[
            Kind::Dwell,
            Kind::AxisUser,
            Kind::Call,
            Kind::OtherM,
            Kind::PathMode,
            Kind::Motion,
        ],
        _ => return None,
    };
    let first_of = |reading: bool| {
        order.iter().find_map(|want| {
            (0..kinds.len()).find(|&i| kinds[i] == *want && (!reading || reads(codes[i], letter)))
        })
    };
    first_of(true).or_else(|| first_of(false))
}

/// Does this code read a word with this letter (of those `taker` hands
/// out)? Not G92.1/G92.2 (no word), G28/G30/G52/G92 (axes only), G0/G1
/// (axes only), G2/G3 (not Q, L, E), G61/G61.1 (none), G64 (P and Q).
fn reads(code: &Word, letter: u8) -> bool {
    let WordValue::Number(n) = &code.value else {
        return true;
    };
    let axis = b"XYZABCUVW@^".contains(&letter);
    match (code.letter, (n.value * 10.0).round() as i64) {
        (b'G', 921 | 922 | 610 | 611 | 400 | 970) => false,
        (b'G', 0 | 10 | 280 | 300 | 520 | 920) => axis,
        (b'G', 20 | 30) => axis || b"IJKRP".contains(&letter),
        (b'G', 640) => matches!(letter, b'P' | b'Q'),
        _ => true,
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    ToolChange,
    Spindle,
    Coolant,
    OtherM,
    Dwell,
    Plane,
    Units,
    Comp,
    ToolLength,
    WorkOffset,
    PathMode,
    /// G7/G8: lathe diameter or radius mode.
    DiameterMode,
    Polar,
    Distance,
    /// G90.1/G91.1.
    ArcDistance,
    /// G93/G94: before the F words of the line.
    FeedMode,
    /// G96/G97: before the S word of the line.
    SpindleMode,
    ReturnLevel,
    AxisUser,
    /// G53: the motion of the line is in machine coordinates.
    MachineCoordinates,
    Motion,
    CycleOff,
    Stop,
    Call,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Group {
    /// Several may share a block (M7 with M8, several user M codes).
    Alone,
    Of(Kind),
}

impl Kind {
    fn group(self) -> Group {
        match self {
            Kind::Coolant | Kind::OtherM => Group::Alone,
            Kind::CycleOff => Group::Of(Kind::Motion),
            other => Group::Of(other),
        }
    }

    /// [`Kind::rank`] of `code`: G91 after the offsets, where rs274 sets
    /// the distance mode, and G90 before them. No offset depends on the
    /// mode, and ger refuses a change of offsets under G91, so each goes
    /// where the offsets change under G90 if the line allows it: `G90 G54`
    /// ends a G91 before G54, `G49 G28 G91 Z0` (a Fanuc program's end)
    /// cancels the length under the G90 before the line.
    fn rank_of(self, code: &Word) -> u8 {
        match (self, &code.value) {
            (Kind::Distance, WordValue::Number(n)) if n.value == 91.0 => 14,
            _ => self.rank(),
        }
    }

    /// rs274's order of execution (interp_execute.cc's list).
    fn rank(self) -> u8 {
        match self {
            Kind::ToolChange => 2,
            Kind::Spindle => 3,
            Kind::Coolant => 4,
            Kind::OtherM => 5,
            Kind::Dwell => 6,
            Kind::Plane => 7,
            Kind::Units => 8,
            Kind::DiameterMode => 8,
            Kind::Comp => 9,
            Kind::ToolLength => 10,
            Kind::WorkOffset => 11,
            Kind::PathMode => 12,
            Kind::Polar => 13,
            // G90 before the offsets, G91 after them ([`Kind::rank_of`]).
            Kind::Distance => 8,
            Kind::ArcDistance => 8,
            // With the F, S and T words (rank 0) and before them.
            Kind::FeedMode | Kind::SpindleMode => 0,
            Kind::ReturnLevel => 15,
            Kind::AxisUser => 16,
            Kind::MachineCoordinates => 17,
            Kind::CycleOff | Kind::Motion => 18,
            Kind::Stop | Kind::Call => 19,
        }
    }
}

/// What a G or M code is, for ordering; `None` for one ger does not place
/// (the line keeps its own order and the code its usual diagnostic).
fn kind_of(w: &Word) -> Option<Kind> {
    let WordValue::Number(n) = &w.value else {
        return None;
    };
    let t = (n.value * 10.0).round();
    if (n.value * 10.0 - t).abs() > 1e-6 || !(0.0..10_000.0).contains(&t) {
        return None;
    }
    let t = t as u32;
    let kind = match (w.letter, t) {
        (b'M', 60) => Kind::ToolChange,
        (b'M', 30 | 40 | 50) => Kind::Spindle,
        (b'M', 70 | 80 | 90) => Kind::Coolant,
        (b'M', 0 | 10 | 20 | 300 | 600) => Kind::Stop,
        (b'M', 980 | 990) => Kind::Call,
        (b'M', 480..=530 | 620..=680 | 1000..=1990) => Kind::OtherM,
        (b'G', 40) => Kind::Dwell,
        (b'G', 170 | 180 | 190) => Kind::Plane,
        (b'G', 200 | 210) => Kind::Units,
        (b'G', 70 | 80) => Kind::DiameterMode,
        (b'G', 400 | 410 | 420 | 411 | 421) => Kind::Comp,
        (b'G', 430 | 440 | 490) => Kind::ToolLength,
        (b'G', 540 | 550 | 560 | 570 | 580 | 590 | 591 | 592 | 593) => Kind::WorkOffset,
        (b'G', 610 | 611 | 640) => Kind::PathMode,
        (b'G', 150 | 160) => Kind::Polar,
        (b'G', 900 | 910) => Kind::Distance,
        (b'G', 901 | 911) => Kind::ArcDistance,
        (b'G', 930 | 940) => Kind::FeedMode,
        (b'G', 960 | 970) => Kind::SpindleMode,
        (b'G', 980 | 990) => Kind::ReturnLevel,
        (b'G', 100 | 280 | 300 | 520 | 920 | 921 | 922) => Kind::AxisUser,
        (b'G', 0 | 10 | 20 | 30 | 50 | 51 | 330 | 331 | 730 | 760 | 810..=890) => Kind::Motion,
        (b'G', 530) => Kind::MachineCoordinates,
        (b'G', 800) => Kind::CycleOff,
        _ => return None,
    };
    Some(kind)
}
