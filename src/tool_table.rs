//! `--tool-table FILE`: LinuxCNC's tool table format, one tool a line:
//! `T1 P1 D6.35 Z75 ;comment` — T the tool number, D its diameter, Z its
//! length; P (the pocket) and the other words LinuxCNC writes (X Y A B C
//! U V W I J Q) are read and ignored. It fills the table `SetTool` fills,
//! in the same units (the output's, SPEC §3); a `SetTool` in the program
//! for the same tool wins.

use crate::diagnostic::{error, Diagnostic, DiagnosticExt};
use crate::ir::{Tool, ToolShape};
use crate::source::{FileId, Span};
use std::collections::BTreeMap;

/// The tools of a table, or every line that is wrong.
pub fn parse(text: &str, file: FileId) -> Result<BTreeMap<u32, Tool>, Vec<Diagnostic>> {
    let mut tools = BTreeMap::new();
    let mut defined: BTreeMap<u32, Span> = BTreeMap::new();
    let mut errors = Vec::new();
    let mut offset = 0;
    for (index, raw) in text.split('\n').enumerate() {
        let line_start = offset;
        offset += raw.len() + 1;
        let content = raw.split(';').next().unwrap_or("").trim_end_matches('\r');
        let span = |start: usize, end: usize| {
            Span::new(file, index as u32 + 1, line_start + start, line_start + end)
        };
        match parse_line(content, &span) {
            Ok(None) => {}
            Ok(Some((number, tool, at))) => {
                if let Some(first) = defined.insert(number, at) {
                    errors.push(
                        error(
                            format!("tool {number} is in the table twice"),
                            at,
                            "again here",
                        )
                        .with_secondary(first, "first here"),
                    );
                }
                tools.insert(number, tool);
            }
            Err(d) => errors.push(d),
        }
        if errors.len() >= 50 {
            break;
        }
    }
    if errors.is_empty() {
        Ok(tools)
    } else {
        Err(errors)
    }
}

type Entry = (u32, Tool, Span);

fn parse_line(
    line: &str,
    span: &dyn Fn(usize, usize) -> Span,
) -> Result<Option<Entry>, Diagnostic> {
    let bytes = line.as_bytes();
    let mut i = 0;
    let mut number = None;
    let mut diameter = None;
    let mut length = None;
    while i < bytes.len() {
        if bytes[i].is_ascii_whitespace() {
            i += 1;
            continue;
        }
        let start = i;
        let letter = bytes[i].to_ascii_uppercase();
        i += 1;
        while i < bytes.len() && !bytes[i].is_ascii_whitespace() {
            i += 1;
        }
        let word = &line[start + 1..i];
        let at = span(start, i);
        if !b"TPDZXYABCUVWIJQ".contains(&letter) {
            return Err(error(
                format!("unexpected `{}` in a tool table", &line[start..i]),
                at,
                "a tool line has T, P, D, Z (and X Y A B C U V W I J Q) words",
            )
            .with_help("LinuxCNC's format: `T1 P1 D6.35 Z75 ;comment`"));
        }
        let value: f64 = word
            .parse()
            .ok()
            .filter(|v: &f64| v.is_finite())
            .ok_or_else(|| {
                error(
                    format!("`{}` is not a number", &line[start..i]),
                    at,
                    "expected a number after the letter",
                )
            })?;
        match letter {
            b'T' => {
                if value < 0.0 || value.fract() != 0.0 || value > 99_999.0 {
                    return Err(error("invalid tool number", at, "a whole number from 0"));
                }
                number = Some((value as u32, at));
            }
            b'D' => {
                if !(0.0..=crate::ir::MAX_LENGTH).contains(&value) {
                    return Err(error(
                        "invalid tool diameter",
                        at,
                        "a diameter is not negative",
                    ));
                }
                diameter = Some(value);
            }
            b'Z' => {
                if value.abs() > crate::ir::MAX_LENGTH {
                    return Err(error("invalid tool length", at, "out of range"));
                }
                length = Some(value);
            }
            _ => {}
        }
    }
    let Some((number, at)) = number else {
        if line.trim().is_empty() {
            return Ok(None);
        }
        return Err(error(
            "a tool line without T",
            span(0, line.len()),
            "T names the tool",
        ));
    };
    let Some(diameter) = diameter else {
        return Err(error(
            format!("tool {number} has no diameter"),
            at,
            "D gives the diameter",
        ));
    };
    Ok(Some((
        number,
        Tool {
            diameter,
            length,
            shape: ToolShape::Flat,
        },
        at,
    )))
}
