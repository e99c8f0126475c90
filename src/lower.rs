//! Lowering: IR → simpler IR, one pass per stage of SPEC §4, applied in
//! the fixed order of [`PASSES`]. A pass is a [`Pass`]: it is fed the
//! statements one at a time, where they lie, and lets each go on (changed
//! or not) or sends zero, one or many statements in its place; it may keep
//! look-ahead state, and flush it in [`Pass::finish`] at the end of the
//! program. The passes are chained as a stream by [`Pipeline`]: no
//! whole-program vector lies between them, so memory is bounded by the
//! batch and by what the passes hold back, and a statement every pass lets
//! go on is never copied. Passes never see the AST and never print.
//!
//! Order: units → polar → offsets → cycles → absolute → corners → comp. Polar runs
//! before offsets (SPEC §4 lists it after): a G90 polar point is relative
//! to the program zero, so it must become a Cartesian program point before
//! the offsets pass folds the program zero away. Cycles run before
//! absolute because their G91 words are not plain increments; corners
//! before comp, which offsets the rounded contour; comp runs last, on
//! absolute machine coordinates.

mod absolute;
mod comp;
mod corners;
mod cycles;
mod error;
mod offsets;
mod pass;
mod polar;
mod position;
mod units;

pub use error::{LowerError, LowerErrorKind};
pub use pass::{
    feed_in_turn, follows_only, Batch, Context, LowerOptions, Out, Pass, PassInfo, CHUNK,
};

use crate::diagnostic::Diagnostic;
use crate::ir::Stmt;
use pass::Problems;

/// Every lowering pass, in the order it runs. `--stage NAME` stops after
/// the pass of that name. A new pass is a file and a line here.
pub const PASSES: &[PassInfo] = &[
    units::PASS,
    polar::PASS,
    offsets::PASS,
    cycles::PASS,
    absolute::PASS,
    corners::PASS,
    comp::PASS,
];

/// The index in [`PASSES`] of the pass named `name`.
pub fn pass_index(name: &str) -> Option<usize> {
    PASSES
        .iter()
        .position(|p| p.name.eq_ignore_ascii_case(name))
}

/// Passes of [`PASSES`] in a row, chained.
pub struct Pipeline {
    passes: Vec<(Box<dyn Pass>, Problems)>,
    /// Each pass's output, reused between batches.
    buffers: Vec<Vec<Stmt>>,
}

impl Pipeline {
    /// The passes of [`PASSES`] in `range` (those up to index `last`:
    /// `0..last + 1`).
    pub fn new(context: &Context<'_>, range: std::ops::Range<usize>) -> Pipeline {
        let end = range.end.min(PASSES.len());
        let passes: Vec<(Box<dyn Pass>, Problems)> = PASSES[range.start.min(end)..end]
            .iter()
            .map(|p| ((p.make)(context), Problems::default()))
            .collect();
        let buffers = passes.iter().map(|_| Vec::new()).collect();
        Pipeline { passes, buffers }
    }

    /// Lower the next statements of the program (`batch` is emptied): what
    /// comes out of the last pass goes to `sink`, in pieces of at most
    /// [`CHUNK`] statements or so, and only while no pass has failed. A
    /// pass that makes many statements of one (a cycle with many pecks)
    /// is passed on as it goes, so memory stays bounded.
    pub fn run(&mut self, batch: &mut Vec<Stmt>, sink: &mut dyn FnMut(&mut Vec<Stmt>)) {
        flow(&mut self.passes, &mut self.buffers, batch, false, sink);
    }

    /// The end of the program: the passes flush in order, the rest goes to
    /// `sink`.
    pub fn finish(&mut self, sink: &mut dyn FnMut(&mut Vec<Stmt>)) {
        flow(
            &mut self.passes,
            &mut self.buffers,
            &mut Vec::new(),
            true,
            sink,
        );
    }

    /// Has a pass reported an error? Then the output will be thrown away.
    pub fn failed(&self) -> bool {
        self.passes.iter().any(|(_, p)| p.errors > 0)
    }

    /// The passes' diagnostics: warnings, and the errors of the first pass
    /// that had any (a later pass's errors may only follow from them), as
    /// when each pass ran over the whole program before the next.
    pub fn diagnostics(self) -> Vec<Diagnostic> {
        let mut out = Vec::new();
        for (_, problems) in self.passes {
            let failed = problems.errors > 0;
            out.extend(problems.list.iter().map(LowerError::to_diagnostic));
            if failed {
                break;
            }
        }
        out
    }
}

/// Run `input` through `passes` (and flush them if `last`), depth first:
/// a pass's output goes on to the next pass whenever it reaches [`CHUNK`]
/// statements (even in the middle of one statement's expansion), and the
/// last pass's to `sink`. After a pass has failed nothing more comes out
/// of it: the later passes' problems would only follow from its own, and
/// are not reported.
///
/// Statements a pass lets go on stay where they lie in `input`; only when
/// the pass drops a statement or sends others are the ones before it moved
/// to the pass's output buffer. A batch of statements every pass lets go
/// on (most of a plain program) is lowered without a copy.
fn flow(
    passes: &mut [(Box<dyn Pass>, Problems)],
    buffers: &mut [Vec<Stmt>],
    input: &mut Vec<Stmt>,
    last: bool,
    sink: &mut dyn FnMut(&mut Vec<Stmt>),
) {
    let (Some(((pass, problems), later)), Some((buffer, later_buffers))) =
        (passes.split_first_mut(), buffers.split_first_mut())
    else {
        if !input.is_empty() {
            sink(input);
        }
        input.clear();
        return;
    };
    let mut output = std::mem::take(buffer);
    let mut next = |o: &mut Vec<Stmt>| flow(later, later_buffers, o, false, sink);
    // input[waiting..] went on where they lie, and are not in `output` yet.
    let mut waiting = pass.feed_each(
        input,
        &mut Batch {
            output: &mut output,
            problems,
            next: &mut next,
        },
    );
    if last {
        let mut out = Out::new(&mut output, problems, &mut next, &mut input[waiting..]);
        pass.finish(&mut out);
        if out.sent_waiting {
            waiting = input.len();
        }
    }
    if problems.errors > 0 {
        output.clear();
    } else if waiting == 0 && output.is_empty() {
        // Every statement went on where it lies.
        if last || !input.is_empty() {
            flow(later, later_buffers, input, last, sink);
        }
    } else {
        output.extend(input.drain(waiting..));
        flow(later, later_buffers, &mut output, last, sink);
    }
    input.clear();
    *buffer = output;
}

#[cfg(test)]
mod tests {
    //! `flow` against a model of the pass contract: each pass, run over the
    //! whole program at once, with plain vectors.
    #![allow(clippy::unwrap_used, clippy::panic)]

    use super::*;
    use crate::ir::{self, Op};

    fn stmt(k: u32) -> Stmt {
        Stmt::new(Op::SelectTool(k), crate::source::Span::default())
    }

    fn number(s: &Stmt) -> u32 {
        match s.op {
            Op::SelectTool(k) => k,
            _ => panic!("not a test statement: {s:?}"),
        }
    }

    /// A pass fed one statement at a time, whatever its `feed_each` does.
    struct InTurn(Box<dyn Pass>);

    impl Pass for InTurn {
        fn feed(&mut self, stmt: &mut Stmt, out: &mut Out<'_>) -> bool {
            self.0.feed(stmt, out)
        }

        fn finish(&mut self, out: &mut Out<'_>) {
            self.0.finish(out)
        }
    }

    /// A made-up program for [`runs_of_moves_are_lowered_as_one_at_a_time`]:
    /// runs of moves (feeds, speeds and comments among them; now and then an
    /// axis out of range, or a -0) between statements that change what the
    /// passes' runs depend on (units, polar, distance, offsets) or show where
    /// they think the tool is (a G92, compensation, a drilling cycle).
    fn made_up_program(seed: u64, length: usize) -> Vec<Stmt> {
        use ir::{Axes, Cycle, CycleKind, Distance, Units};
        let mut random = crate::test_random::Random::new(seed);
        let mut next = |n: u64| random.below(n);
        let mut ops = Vec::new();
        while ops.len() < length {
            if next(4) != 0 {
                for _ in 0..1 + next(60) {
                    let op = match next(20) {
                        0 => Op::Feed(100.0 + next(500) as f64),
                        1 => Op::Speed(next(9000) as f64),
                        2 => Op::Comment(String::from("run")),
                        _ => made_up_move(seed, &mut next),
                    };
                    ops.push(op);
                }
                continue;
            }
            let kind = next(12);
            if (3..=5).contains(&kind) || kind == 10 {
                // Offsets change under G90 only.
                ops.push(Op::Distance(Distance::Absolute));
            }
            ops.push(match kind {
                0 => Op::Distance([Distance::Absolute, Distance::Incremental][next(2) as usize]),
                1 => Op::Units([Units::Inch, Units::Mm][next(2) as usize]),
                2 => Op::Polar(next(8) == 0),
                3 => Op::SetPosition(Axes::xyz(1.0, 2.0, 3.0)),
                4 => Op::CancelPosition,
                5 => Op::LocalOffset(Axes::xyz(5.0, 0.0, 0.0)),
                6 => Op::Comp {
                    side: ir::Side::Left,
                    radius: ir::CompRadius::Diameter(2.0),
                },
                7 => Op::CompOff,
                8 => Op::Cycle(Box::new(Cycle {
                    kind: CycleKind::G81,
                    at: Axes::xyz(10.0, 10.0, -1.0),
                    r: 1.0,
                    q: None,
                    dwell: None,
                    repeats: 1,
                    ijk: [None; 3],
                    starts_run: true,
                    pecks: None,
                    kept: None,
                })),
                9 => Op::CycleOff,
                10 => Op::SelectWorkOffset(1),
                _ => Op::Plane(ir::Plane::XY),
            });
        }
        // A fifth of them without their end (reported at the last statement).
        if !seed.is_multiple_of(5) {
            ops.push(Op::End);
        }
        let span = |line| crate::source::Span {
            file: 0,
            line,
            start: 0,
            end: 0,
        };
        (1..)
            .zip(ops)
            .map(|(line, op)| Stmt::new(op, span(line)))
            .collect()
    }

    /// A move of [`made_up_program`]'s runs: to a point on some of X, Y, Z
    /// and A (in a quarter of the programs now and then out of the
    /// machine's range), in a third of the programs now and then an arc: by
    /// R (the absolute pass finds its centre) or by a centre (checked).
    fn made_up_move(seed: u64, next: &mut impl FnMut(u64) -> u64) -> Op {
        use ir::{Axes, Axis, Motion};
        let mut to = Axes::default();
        for axis in [Axis::X, Axis::Y, Axis::Z, Axis::A] {
            let v = match next(if seed.is_multiple_of(4) { 6 } else { 4000 }) {
                0 => 2e9,
                1 => -0.0,
                _ => (next(200_000) as f64 - 100_000.0) / 1000.0,
            };
            if next(3) != 0 {
                to.set(axis, v);
            }
        }
        let kind = match seed.is_multiple_of(3) {
            true => next(10),
            false => 2 + next(8),
        };
        let (motion, arc) = match kind {
            0 => (Motion::ArcCw, Some(ir::ArcGeometry::Radius(50.0))),
            1 => (
                Motion::ArcCcw,
                Some(ir::ArcGeometry::Center([Some(1.0), None, None])),
            ),
            k => ([Motion::Rapid, Motion::Linear][k as usize % 2], None),
        };
        Op::Move(ir::Move {
            motion,
            to,
            arc: arc.map(|geometry| ir::Arc { geometry, turns: 1 }),
            corner: None,
            lead: None,
        })
    }

    /// Every pass takes a run of moves at once in its `feed_each` (`lower::
    /// follows_only`) as it would one statement at a time: the same
    /// statements out and the same problems, through the six passes, in
    /// batches cut anywhere.
    #[test]
    fn runs_of_moves_are_lowered_as_one_at_a_time() {
        use ir::Units::{Inch, Mm};
        let options = LowerOptions::default();
        let (mut programs_with_output, mut runs) = (0, 0);
        for seed in 1..=200u64 {
            // Output units known and the program's the same, other, or
            // neither known.
            let (output_units, program_units) =
                [(Mm, Some(Mm)), (Mm, Some(Inch)), (Mm, None)][seed as usize % 3];
            let start = ir::Start {
                setup: ir::Setup::default(),
                output_units: Some(output_units),
                program_units,
                // G98 returns to where the tool was: a cycle shows it.
                return_level: [ir::ReturnLevel::R, ir::ReturnLevel::Initial][seed as usize / 4 % 2],
            };
            let context = Context {
                start: &start,
                options: &options,
            };
            let program = made_up_program(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15), 600);
            let mut lowered = Vec::new();
            for in_turn in [true, false] {
                let passes: Vec<(Box<dyn Pass>, Problems)> = PASSES
                    .iter()
                    .map(|p| {
                        let pass = (p.make)(&context);
                        let pass: Box<dyn Pass> = match in_turn {
                            true => Box::new(InTurn(pass)),
                            false => pass,
                        };
                        (pass, Problems::default())
                    })
                    .collect();
                let mut pipeline = Pipeline {
                    buffers: passes.iter().map(|_| Vec::new()).collect(),
                    passes,
                };
                let mut out = Vec::new();
                let mut sink =
                    |o: &mut Vec<Stmt>| out.extend(o.drain(..).map(|s| format!("{s:?}")));
                // Batches cut anywhere, and often just after a statement
                // that is not a run's (so that a run starts the next).
                let (mut batch, mut cut) = (Vec::new(), seed);
                for stmt in &program {
                    batch.push(stmt.clone());
                    cut = cut.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
                    let ends_run = !follows_only(std::slice::from_ref(stmt));
                    if cut >> 59 == 0 || (ends_run && cut >> 63 == 1) {
                        runs += usize::from(!in_turn && follows_only(&batch));
                        pipeline.run(&mut batch, &mut sink);
                    }
                }
                pipeline.run(&mut batch, &mut sink);
                pipeline.finish(&mut sink);
                let problems: Vec<String> = pipeline
                    .passes
                    .iter()
                    .flat_map(|(_, p)| p.list.iter().map(|e| format!("{e:?}")))
                    .collect();
                lowered.push((out, problems));
            }
            assert_eq!(lowered[0], lowered[1], "program {seed}");
            programs_with_output += usize::from(lowered[0].0.len() > 300);
        }
        // The comparison means something: most programs come out whole, and
        // many batches are runs.
        assert!(programs_with_output > 60, "{programs_with_output}");
        assert!(runs > 1000, "{runs}");
    }

    /// Drops every third statement.
    struct Drop3;
    /// Sends more than a chunk of statements before every fifth one, and
    /// three more at the end (which the next pass gets with its own end).
    struct Expand;
    /// Holds every seventh statement back until after the next one.
    #[derive(Default)]
    struct Hold(Option<Stmt>);

    impl Pass for Drop3 {
        fn feed(&mut self, stmt: &mut Stmt, _: &mut Out<'_>) -> bool {
            !number(stmt).is_multiple_of(3)
        }
    }

    impl Pass for Expand {
        fn feed(&mut self, stmt: &mut Stmt, out: &mut Out<'_>) -> bool {
            let k = number(stmt);
            if k % 5 == 1 {
                for j in 0..CHUNK as u32 + 10 {
                    out.push(super::tests::stmt(1_000_000 + k * 10_000 + j));
                }
            }
            true
        }

        fn finish(&mut self, out: &mut Out<'_>) {
            for k in TAIL {
                out.push(stmt(k));
            }
        }
    }

    /// What [`Expand`] sends at the end: the last (2 mod 7) is held back
    /// by [`Hold`] and sent at its end.
    const TAIL: [u32; 3] = [900_000_000, 900_000_001, 900_000_005];

    /// Holds the first statement back until the end of the program, where
    /// it comes after the statements the earlier passes sent at their end.
    #[derive(Default)]
    struct HoldFirst(Option<Stmt>, bool);

    impl Pass for HoldFirst {
        fn feed(&mut self, stmt: &mut Stmt, _: &mut Out<'_>) -> bool {
            if std::mem::replace(&mut self.1, true) {
                return true;
            }
            self.0 = Some(stmt.clone());
            false
        }

        fn finish(&mut self, out: &mut Out<'_>) {
            if let Some(first) = self.0.take() {
                out.push(first);
            }
        }
    }

    /// Fails at statement 50 (and sends nothing on after it).
    struct Fail;

    impl Pass for Fail {
        fn feed(&mut self, stmt: &mut Stmt, out: &mut Out<'_>) -> bool {
            if number(stmt) == 50 {
                let kind = LowerErrorKind::MachineMoveIncremental;
                out.report(LowerError::new(kind, stmt.span));
            }
            true
        }
    }

    impl Pass for Hold {
        fn feed(&mut self, stmt: &mut Stmt, out: &mut Out<'_>) -> bool {
            if let Some(held) = self.0.take() {
                out.push(stmt.clone());
                out.push(held);
                return false;
            }
            if number(stmt) % 7 == 2 {
                self.0 = Some(stmt.clone());
                return false;
            }
            true
        }

        fn finish(&mut self, out: &mut Out<'_>) {
            if let Some(held) = self.0.take() {
                out.push(held);
            }
        }
    }

    /// What the four passes make of `0..n`, pass by pass.
    fn model(n: u32) -> Vec<u32> {
        let dropped: Vec<u32> = (0..n).filter(|k| !k.is_multiple_of(3)).collect();
        let mut expanded = Vec::new();
        for k in dropped {
            if k % 5 == 1 {
                expanded.extend((0..CHUNK as u32 + 10).map(|j| 1_000_000 + k * 10_000 + j));
            }
            expanded.push(k);
        }
        expanded.extend(TAIL);
        let (mut held, mut out) = (None, Vec::new());
        for k in expanded {
            if let Some(h) = held.take() {
                out.extend([k, h]);
            } else if k % 7 == 2 {
                held = Some(k);
            } else {
                out.push(k);
            }
        }
        out.extend(held);
        out.rotate_left(1);
        out
    }

    #[test]
    fn flow_keeps_the_order_of_the_passes_run_one_after_another() {
        for (n, batch) in [(40, 1), (40, 7), (300, 64), (300, 300), (9000, CHUNK)] {
            let mut passes: Vec<(Box<dyn Pass>, Problems)> = vec![
                (Box::new(Drop3), Problems::default()),
                (Box::new(Expand), Problems::default()),
                (Box::new(Hold::default()), Problems::default()),
                (Box::new(HoldFirst::default()), Problems::default()),
            ];
            let mut buffers = vec![Vec::new(), Vec::new(), Vec::new(), Vec::new()];
            let mut got = Vec::new();
            let mut sink = |o: &mut Vec<Stmt>| got.extend(o.drain(..).map(|s| number(&s)));
            let all: Vec<u32> = (0..n).collect();
            for part in all.chunks(batch) {
                let mut input = part.iter().map(|&k| stmt(k)).collect();
                flow(&mut passes, &mut buffers, &mut input, false, &mut sink);
                assert!(input.is_empty());
            }
            flow(&mut passes, &mut buffers, &mut Vec::new(), true, &mut sink);
            assert_eq!(got, model(n), "{n} statements in batches of {batch}");
        }
    }

    /// (In batches of 64 and more nothing at all comes out: the batch with
    /// the failure is thrown away whole.)
    #[test]
    fn after_a_pass_fails_nothing_more_comes_out_of_it() {
        for batch in [1, 7, 64, 300] {
            let mut passes: Vec<(Box<dyn Pass>, Problems)> = vec![
                (Box::new(Drop3), Problems::default()),
                (Box::new(Fail), Problems::default()),
                (Box::new(Hold::default()), Problems::default()),
            ];
            let mut buffers = vec![Vec::new(), Vec::new(), Vec::new()];
            let mut got = Vec::new();
            let mut sink = |o: &mut Vec<Stmt>| got.extend(o.drain(..).map(|s| number(&s)));
            let all: Vec<u32> = (0..300).collect();
            for part in all.chunks(batch) {
                let mut input = part.iter().map(|&k| stmt(k)).collect();
                flow(&mut passes, &mut buffers, &mut input, false, &mut sink);
            }
            flow(&mut passes, &mut buffers, &mut Vec::new(), true, &mut sink);
            assert!(got.iter().all(|&k| k < 50), "batches of {batch}: {got:?}");
            assert_eq!(passes[1].1.errors, 1);
        }
    }

    #[test]
    fn a_batch_every_pass_lets_go_on_is_not_copied() {
        let mut passes: Vec<(Box<dyn Pass>, Problems)> =
            vec![(Box::new(Expand), Problems::default())];
        let mut buffers = vec![Vec::new()];
        let mut input: Vec<Stmt> = [2, 3, 4].into_iter().map(stmt).collect();
        let at = input.as_ptr();
        let mut seen = None;
        let mut sink = |o: &mut Vec<Stmt>| {
            seen = Some(o.as_ptr());
            o.clear();
        };
        flow(&mut passes, &mut buffers, &mut input, false, &mut sink);
        assert_eq!(seen, Some(at));
    }
}
