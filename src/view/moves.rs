//! The moves as the page reads them: one record per move, positions
//! quantised to the output's resolution and written as differences from
//! the move before (zigzag varints), arcs sampled into chords, each
//! record with its tool, source line, output line and the time the move
//! ends. Must not drop a move: the page draws exactly `count` of them.

use crate::ir::Units;
use crate::render::{first_named, tool_of};
use crate::toolpath::{MoveKind, ToolPath};
use serde_json::{json, Value};

/// Arcs are drawn as chords whose sag stays under this (mm).
const ARC_SAG_MM: f64 = 0.02;

/// At most this many chords per arc (a helix of many turns).
const MAX_CHORDS: usize = 4096;

const KIND_RAPID: u8 = 0;
const KIND_FEED: u8 = 1;
const KIND_ARC: u8 = 2;
const TOOL_CHANGE: u8 = 1 << 2;
const LINE_NEXT: u8 = 1 << 3;
const LINE_DELTA: u8 = 2 << 3;
const LINE_FILE: u8 = 3 << 3;
const OUT_NEXT: u8 = 1 << 5;
const OUT_DELTA: u8 = 2 << 5;
const OUT_SAME: u8 = 3 << 5;
const START_JUMP: u8 = 1 << 7;

/// How far ahead in the output a move's line is looked for.
const OUTPUT_WINDOW: usize = 4096;

/// The records appended to `binary`; the header's part that says how to
/// read them. `clock`: each move's end time (s); `output_lines`: each
/// output line's source line.
pub(super) fn encode(
    path: &ToolPath,
    clock: &[f64],
    output_lines: &[u32],
    binary: &mut Vec<u8>,
    notes: &mut Vec<String>,
) -> Value {
    // The output's resolution: 0.001 mm, or 0.0001 in.
    let quantum = match path.units {
        Some(Units::Inch) => 0.00254,
        Some(Units::Mm) | None => 0.001,
    };
    let offset = binary.len();
    let q = |p: [f64; 3]| p.map(|v| (v / quantum).round() as i64);
    let first = first_named(path);
    let mut tools: Vec<u32> = Vec::new();
    let start = path.moves.first().map_or([0; 3], |m| q(m.start));
    let mut at = start;
    let mut state = Previous::default();
    let mut capped = 0usize;
    let mut outputs = OutputWalk::new(output_lines);
    for (index, m) in path.moves.iter().enumerate() {
        let number = tool_of(m, first);
        let tool = match tools.iter().position(|&t| t == number) {
            Some(k) => k,
            None => {
                tools.push(number);
                tools.len() - 1
            }
        };
        let main = m.span.file_id();
        let line = m.span.line;
        let output = outputs.find(line);
        let (mut head, mut tail) = labels(m, index == 0, tool, output, &state);
        let from = q(m.start);
        if from != at {
            head |= START_JUMP;
            for i in 0..3 {
                zigzag(&mut tail, from[i] - at[i]);
            }
            at = from;
        }
        if let MoveKind::Arc(_) = m.kind {
            let chords = chords(m);
            capped += usize::from(chords == MAX_CHORDS);
            varint(&mut tail, (chords - 1) as u64);
            for k in 1..chords {
                let p = q(m.at(k as f64 / chords as f64));
                for i in 0..3 {
                    zigzag(&mut tail, p[i] - at[i]);
                }
                at = p;
            }
        }
        let end = q(m.end);
        for i in 0..3 {
            zigzag(&mut tail, end[i] - at[i]);
        }
        at = end;
        let ms = (clock.get(index).copied().unwrap_or(0.0) * 1000.0).round() as i64;
        varint(&mut tail, (ms - state.ms).max(0) as u64);
        binary.push(head);
        binary.extend_from_slice(&tail);
        state = Previous {
            tool,
            file: main,
            line,
            output: if output == 0 { state.output } else { output },
            ms: ms.max(state.ms),
        };
    }
    if capped > 0 {
        notes.push(format!(
            "{capped} arcs of many turns drawn with {MAX_CHORDS} chords each: their chords sag more than {ARC_SAG_MM} mm"
        ));
    }
    notes.push(format!(
        "arcs are drawn as chords within {ARC_SAG_MM} mm; positions to {quantum} mm"
    ));
    json!({
        "count": path.moves.len(),
        "quantum_mm": quantum,
        "start": start,
        "offset": offset,
        "length": binary.len() - offset,
        "tool_numbers": tools,
    })
}

/// A record's head byte and its words before the positions: its kind,
/// and its tool, source line and output line where they change.
fn labels(
    m: &crate::toolpath::Move,
    first: bool,
    tool: usize,
    output: usize,
    state: &Previous,
) -> (u8, Vec<u8>) {
    let (main, line) = (m.span.file_id(), m.span.line);
    let mut head = match m.kind {
        MoveKind::Rapid => KIND_RAPID,
        MoveKind::Feed => KIND_FEED,
        MoveKind::Arc(_) => KIND_ARC,
    };
    let mut tail = Vec::with_capacity(16);
    if first || tool != state.tool {
        head |= TOOL_CHANGE;
        varint(&mut tail, tool as u64);
    }
    if main != state.file {
        head |= LINE_FILE;
        varint(&mut tail, main as u64);
        varint(&mut tail, u64::from(line));
    } else if line == state.line.wrapping_add(1) {
        head |= LINE_NEXT;
    } else if line != state.line {
        head |= LINE_DELTA;
        zigzag(&mut tail, i64::from(line) - i64::from(state.line));
    }
    match output {
        0 => {}
        o if o == state.output => head |= OUT_SAME,
        o if o == state.output + 1 => head |= OUT_NEXT,
        o => {
            head |= OUT_DELTA;
            zigzag(&mut tail, o as i64 - state.output as i64);
        }
    }
    (head, tail)
}

/// The record before, that the next one is written against.
#[derive(Default)]
struct Previous {
    tool: usize,
    file: usize,
    line: u32,
    output: usize,
    ms: i64,
}

/// Each move's output line (1-based; 0: not found): the next output line
/// made by the move's source line, walking forward as the moves do.
struct OutputWalk<'a> {
    lines: &'a [u32],
    cursor: usize,
}

impl<'a> OutputWalk<'a> {
    fn new(lines: &'a [u32]) -> OutputWalk<'a> {
        OutputWalk { lines, cursor: 0 }
    }

    fn find(&mut self, line: u32) -> usize {
        let window = self.lines.len().min(self.cursor + OUTPUT_WINDOW);
        match self.lines[self.cursor.min(window)..window]
            .iter()
            .position(|&l| l == line)
        {
            Some(k) => {
                self.cursor += k + 1;
                self.cursor
            }
            None => 0,
        }
    }
}

/// How many chords draw an arc within [`ARC_SAG_MM`].
fn chords(m: &crate::toolpath::Move) -> usize {
    let MoveKind::Arc(a) = m.kind else {
        return 1;
    };
    let (p, q, _) = a.plane.axes();
    let radius = (m.start[p] - a.center[p]).hypot(m.start[q] - a.center[q]);
    let step = if radius <= ARC_SAG_MM {
        std::f64::consts::FRAC_PI_2
    } else {
        2.0 * (1.0 - ARC_SAG_MM / radius).acos()
    };
    let n = (m.sweep() / step).ceil();
    if n.is_finite() {
        (n as usize).clamp(2, MAX_CHORDS)
    } else {
        MAX_CHORDS
    }
}

/// Little-endian base-128 (the checkpoints' encoding too).
pub(super) fn varint(out: &mut Vec<u8>, mut v: u64) {
    while v >= 0x80 {
        out.push((v as u8) | 0x80);
        v >>= 7;
    }
    out.push(v as u8);
}

pub(super) fn zigzag(out: &mut Vec<u8>, v: i64) {
    varint(out, ((v << 1) ^ (v >> 63)) as u64);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zigzag_varints_round_small_numbers_to_one_byte() {
        let mut out = Vec::new();
        zigzag(&mut out, -1);
        zigzag(&mut out, 63);
        zigzag(&mut out, 64);
        assert_eq!(out, vec![1, 126, 128, 1]);
    }
}
