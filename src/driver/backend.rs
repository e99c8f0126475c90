//! The back end as the evaluator's sink: lowering passes and the printer
//! over each batch of statements, then dropped, so the whole program is
//! never held (ARCHITECTURE.md, "Streaming"). Knows nothing of how the
//! program was read.

use super::options::{CompileOptions, Stage};
use super::scan::{grid_decimals, input_decimals, FileScan};
use super::travel::TravelCheck;
use crate::diagnostic::Diagnostic;
use crate::emit::{self, ArcFormat};
use crate::ir;
use crate::lower::{self, Pipeline};
use crate::source::FileId;
use crate::toolpath::{Builder as ToolPathBuilder, PathSink, ToolPath};
use std::io::Write;
use std::time::{Duration, Instant};

/// Where the back end's result goes.
pub(super) enum Output<'a> {
    Text(&'a mut (dyn Write + Send)),
    Path(&'a mut Option<ToolPath>),
    /// The tool path's moves handed on as each batch makes them.
    Moves(&'a mut dyn PathSink),
}

/// What the back end needs to know of the source: its length (to size the
/// output's buffer) and the most decimals its numbers are written with.
pub(super) enum SourceFacts<'a> {
    Text(&'a str),
    /// Of a file read a part at a time, found by [`scan_file`].
    Known(FileScan),
}

impl SourceFacts<'_> {
    pub(super) fn len(&self) -> usize {
        match self {
            SourceFacts::Text(text) => text.len(),
            SourceFacts::Known(file) => file.len,
        }
    }

    /// The O number the program starts with, if any.
    pub(super) fn program_number(&self) -> Option<u32> {
        match self {
            SourceFacts::Text(text) => super::scan::program_number(text),
            SourceFacts::Known(file) => file.program_number,
        }
    }

    pub(super) fn decimals(&self) -> usize {
        match self {
            SourceFacts::Text(text) => input_decimals(text),
            SourceFacts::Known(file) => file.decimals,
        }
    }
}

/// The back end as the evaluator's sink: each batch of statements is
/// lowered up to the requested stage and printed, then dropped, so the
/// whole program is never held in memory (ARCHITECTURE.md, "streaming").
pub(super) struct Backend<'s> {
    pub(super) source: SourceFacts<'s>,
    pub(super) file: FileId,
    pub(super) options: &'s CompileOptions,
    pub(super) out: Output<'s>,
    /// The first write that failed; nothing more is written after it.
    pub(super) write_error: Option<std::io::Error>,
    /// Made by the first batch, when the setup and units are known.
    pub(super) started: Option<Started>,
    /// How many of the passes the evaluator's thread runs before it hands
    /// a batch on ([`PASSES_AHEAD`]); the back end runs the others.
    pub(super) ahead: usize,
    /// Those passes, given back when the program has been lowered (for
    /// their diagnostics).
    pub(super) lowered_ahead: Option<Pipeline>,
    /// The time those passes took (in `lower_time` too), inside the
    /// evaluator's.
    pub(super) lower_time_ahead: Duration,
    pub(super) lower_time: Duration,
    pub(super) emit_time: Duration,
}

/// The passes the evaluator's thread runs when the back end has a thread
/// of its own: units, polar, offsets and cycles. Chosen when the back end
/// was the slower thread on a plain program (57 % of the samples, `perf`,
/// the 2M program; 2026-11-28); since its printer got lighter the
/// evaluator is the busier, but one, two or three ahead give the same wall
/// time (a batch's lines come over from the other core in whichever pass
/// first touches them there). ARCHITECTURE.md, "Streaming" and "The ninth
/// stop". Where the moves go to a sink that is heavier than the last
/// passes (`ger stats`'s planner on grbl), the evaluator's thread runs
/// every pass (docs/performance.md, "Two threads for stats").
const PASSES_AHEAD: usize = 4;

pub(super) struct Started {
    /// `None` for `--stage expand`.
    pub(super) lowering: Option<Pipeline>,
    printer: Printer,
    /// The machine's travel, checked on the lowered program.
    travel: Option<TravelCheck>,
}

pub(super) enum Printer {
    Stage(emit::StagePrinter),
    Program(Box<emit::ProgramPrinter>),
    /// [`tool_path`]: the path is built instead of text.
    Path(Box<crate::toolpath::Builder>),
}

impl<'s> Backend<'s> {
    pub(super) fn new(
        source: SourceFacts<'s>,
        file: FileId,
        options: &'s CompileOptions,
        out: Output<'s>,
    ) -> Backend<'s> {
        Backend {
            source,
            file,
            options,
            out,
            write_error: None,
            started: None,
            ahead: 0,
            lowered_ahead: None,
            lower_time_ahead: Duration::ZERO,
            lower_time: Duration::ZERO,
            emit_time: Duration::ZERO,
        }
    }

    /// The last pass to run, if any.
    fn last_pass(&self) -> Option<usize> {
        match self.options.stage {
            Some(Stage::Lower(pass)) => Some(pass),
            Some(Stage::Parse | Stage::Expand) => None,
            Some(Stage::Fit) | None => Some(lower::PASSES.len() - 1),
        }
    }

    /// How the passes lower.
    pub(super) fn lower_options(&self) -> lower::LowerOptions {
        match self.out {
            // A tool path is built from moves: cycles are always expanded
            // and compensation resolved.
            Output::Path(_) | Output::Moves(_) => lower::LowerOptions {
                keep_cycles: false,
                keep_comp: false,
                ..self.options.lower.clone()
            },
            _ => self.options.lower.clone(),
        }
    }

    /// The passes the evaluator's thread is to run ([`PASSES_AHEAD`], and
    /// none past the last), and their options.
    pub(super) fn ahead(&self) -> (usize, lower::LowerOptions) {
        let ahead = match &self.out {
            // The moves' sink (`ger stats`'s planner) runs on the back
            // end's thread: where it is the heavier work, every pass runs
            // on the evaluator's.
            Output::Moves(sink) if sink.heavy() => lower::PASSES.len(),
            _ => PASSES_AHEAD,
        };
        let passes = self.last_pass().map_or(0, |last| ahead.min(last + 1));
        (passes, self.lower_options())
    }

    pub(super) fn started(&self, start: &ir::Start) -> Started {
        let (len, file) = (self.source.len(), self.file);
        let last = self.last_pass();
        let options = self.lower_options();
        let context = lower::Context {
            start,
            options: &options,
        };
        // What the first pass starts from is what is printed, unless the
        // units pass has run.
        let units = match last {
            Some(last) if last >= lower::pass_index("units").unwrap_or(0) => start.output_units,
            _ => start.program_units,
        };
        let whole = self.options.stage.is_none();
        Started {
            travel: match self.options.travel {
                Some(travel) if whole => Some(TravelCheck::new(travel, units)),
                _ => None,
            },
            lowering: last.map(|last| Pipeline::new(&context, self.ahead..last + 1)),
            printer: match self.options.stage {
                _ if matches!(self.out, Output::Path(_) | Output::Moves(_)) => {
                    Printer::Path(Box::new(ToolPathBuilder::new(units, &start.setup)))
                }
                Some(Stage::Fit) | None => {
                    let mut emit = self.options.emit.clone();
                    // A Fanuc user's O1234 stays O1234.
                    if let Some(number) = self.source.program_number() {
                        emit.program_number = number;
                    }
                    if emit.decimals.is_none() {
                        emit.decimals = Some(grid_decimals(self.source.decimals(), units));
                    }
                    let fit = self.options.stage == Some(Stage::Fit);
                    if fit && !emit.arcs.fits() {
                        emit.arcs = if emit.arcs.writes_r() {
                            ArcFormat::FitR
                        } else {
                            ArcFormat::Fit
                        };
                    }
                    let mut printer = emit::ProgramPrinter::new(&emit, units, len, file);
                    if fit {
                        printer.name_fitted_runs();
                    }
                    Printer::Program(Box::new(printer))
                }
                Some(_) => Printer::Stage(emit::StagePrinter::new(units, len, file)),
            },
        }
    }

    /// The passes' diagnostics, and the rest of the output unless a pass
    /// failed; and whether the output was written.
    pub(super) fn finish(mut self) -> (Vec<Diagnostic>, std::io::Result<()>) {
        let written = self.write_error.map_or(Ok(()), Err);
        let Some(Started {
            lowering,
            mut printer,
            mut travel,
        }) = self.started
        else {
            return (Vec::new(), written);
        };
        let mut diagnostics = Vec::new();
        // The evaluator's passes come first: after one failed, nothing of
        // the later ones is reported (as with [`Pipeline::diagnostics`]).
        if let Some(ahead) = self.lowered_ahead {
            let failed = ahead.failed();
            diagnostics = ahead.diagnostics();
            if failed {
                return (diagnostics, written);
            }
        }
        if let Some(mut lowering) = lowering {
            lowering.finish(&mut |rest| {
                if let Some(travel) = travel.as_mut() {
                    rest.iter().for_each(|s| travel.feed(s));
                }
                printer.print(rest);
                rest.clear();
            });
            let failed = lowering.failed();
            diagnostics.extend(lowering.diagnostics());
            if failed {
                return (diagnostics, written);
            }
        }
        diagnostics.extend(travel.iter().flat_map(TravelCheck::finish));
        if let Printer::Program(p) = &printer {
            diagnostics.extend(p.refused());
            diagnostics.extend(p.arcs_not_r());
            diagnostics.extend(p.path_control_lost());
            diagnostics.extend(p.dwell_too_long());
            diagnostics.extend(p.arcs_fitted());
        }
        if let (Printer::Path(builder), Output::Moves(sink)) = (&mut printer, &mut self.out) {
            builder.drain_into(&mut **sink);
        }
        match (printer.finish(), self.out) {
            (Ok(rest), Output::Text(out)) => {
                (diagnostics, written.and_then(|()| out.write_all(&rest)))
            }
            (Err(path), Output::Path(slot)) => {
                *slot = Some(*path);
                (diagnostics, written)
            }
            // The moves were handed on as they came.
            _ => (diagnostics, written),
        }
    }
}

/// The printed text is written out once there is this much of it.
const WRITE_AT: usize = 64 * 1024;

impl Printer {
    /// Print the statements; the text not yet written (none for a path).
    fn print(&mut self, stmts: &[ir::Stmt]) -> Option<&mut Vec<u8>> {
        match self {
            Printer::Stage(p) => Some(p.print(stmts)),
            Printer::Program(p) => Some(p.print(stmts)),
            Printer::Path(b) => {
                for stmt in stmts {
                    b.feed(stmt);
                }
                None
            }
        }
    }

    /// The rest of the text, or the path.
    pub(super) fn finish(self) -> Result<Vec<u8>, Box<ToolPath>> {
        match self {
            Printer::Stage(p) => Ok(p.finish()),
            Printer::Program(p) => Ok(p.finish()),
            Printer::Path(b) => Err(Box::new(b.finish())),
        }
    }
}

impl ir::Sink for Backend<'_> {
    fn start(&mut self, start: &ir::Start) {
        self.started = Some(self.started(start));
    }

    fn batch(&mut self, batch: &mut Vec<ir::Stmt>) {
        let Some(started) = &mut self.started else {
            batch.clear();
            return;
        };
        let t0 = Instant::now();
        let mut emit_time = Duration::ZERO;
        let (printer, out, write_error) =
            (&mut started.printer, &mut self.out, &mut self.write_error);
        let travel = &mut started.travel;
        let mut print = |stmts: &mut Vec<ir::Stmt>| {
            let t = Instant::now();
            if let Some(travel) = travel.as_mut() {
                stmts.iter().for_each(|s| travel.feed(s));
            }
            print_and_write(printer, out, write_error, stmts);
            emit_time += t.elapsed();
        };
        match &mut started.lowering {
            Some(lowering) => lowering.run(batch, &mut print),
            None => print(batch),
        }
        batch.clear();
        self.lower_time += t0.elapsed() - emit_time;
        self.emit_time += emit_time;
    }
}

/// Print statements (and empty them); hand the text on in large writes.
fn print_and_write(
    printer: &mut Printer,
    out: &mut Output<'_>,
    write_error: &mut Option<std::io::Error>,
    stmts: &mut Vec<ir::Stmt>,
) {
    let text = printer.print(stmts);
    stmts.clear();
    let Some(text) = text else {
        if let (Printer::Path(builder), Output::Moves(sink)) = (printer, out) {
            builder.drain_into(&mut **sink);
        }
        return;
    };
    if text.len() >= WRITE_AT {
        if let (None, Output::Text(out)) = (&write_error, out) {
            if let Err(e) = out.write_all(text) {
                *write_error = Some(e);
            }
        }
        text.clear();
    }
}
