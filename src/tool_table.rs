//! `--tool-table FILE`: LinuxCNC's tool table format, one tool a line:
//! `T1 P1 D6.35 Z75 ;comment` — T the tool number, D its diameter, Z its
//! length; P (the pocket) and the other words LinuxCNC writes (X Y A B C
//! U V W I J Q) are read and ignored. It fills the table `SetTool` fills
//! (in the output's units, SPEC §3, unless `--tool-units` names the
//! table's: the evaluator converts at the start); a `SetTool` in the
//! program for the same tool wins.

use crate::diagnostic::{error, Diagnostic, DiagnosticExt, Located, Wording};
use crate::ir::{Tool, ToolShape};
use crate::source::{FileId, Span};
use std::collections::BTreeMap;

/// The tools of a table, or every line that is wrong.
pub fn parse(text: &str, file: FileId) -> Result<BTreeMap<u32, Tool>, Vec<TableError>> {
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
                    errors.push(TableError::new(
                        TableErrorKind::Twice {
                            tool: number,
                            first,
                        },
                        at,
                    ));
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
) -> Result<Option<Entry>, TableError> {
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
        let written = || line[start..i].to_string();
        if !b"TPDZXYABCUVWIJQ".contains(&letter) {
            return Err(TableError::new(TableErrorKind::UnknownWord(written()), at));
        }
        let value: f64 = word
            .parse()
            .ok()
            .filter(|v: &f64| v.is_finite())
            .ok_or_else(|| TableError::new(TableErrorKind::NotANumber(written()), at))?;
        match letter {
            b'T' => {
                if value < 0.0 || value.fract() != 0.0 || value > 99_999.0 {
                    return Err(TableError::new(TableErrorKind::ToolNumber, at));
                }
                number = Some((value as u32, at));
            }
            b'D' => {
                if !(0.0..=crate::ir::MAX_LENGTH).contains(&value) {
                    return Err(TableError::new(TableErrorKind::Diameter, at));
                }
                diameter = Some(value);
            }
            b'Z' => {
                if value.abs() > crate::ir::MAX_LENGTH {
                    return Err(TableError::new(TableErrorKind::Length, at));
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
        return Err(TableError::new(TableErrorKind::NoTool, span(0, line.len())));
    };
    let Some(diameter) = diameter else {
        return Err(TableError::new(TableErrorKind::NoDiameter(number), at));
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

/// What can be wrong with a line of a tool table.
#[derive(Clone, Debug, PartialEq)]
pub enum TableErrorKind {
    /// A word of a letter the format does not have (as written).
    UnknownWord(String),
    /// A letter without a number after it (as written).
    NotANumber(String),
    ToolNumber,
    Diameter,
    Length,
    NoTool,
    NoDiameter(u32),
    /// The same tool again; the span of its first line.
    Twice {
        tool: u32,
        first: Span,
    },
}

/// What goes wrong, and where: see [`TableErrorKind`].
pub type TableError = Located<TableErrorKind>;

impl Wording for TableErrorKind {
    fn wording(&self, at: Span) -> Diagnostic {
        match self {
            TableErrorKind::UnknownWord(word) => error(
                format!("unexpected `{word}` in a tool table"),
                at,
                "a tool line has T, P, D, Z (and X Y A B C U V W I J Q) words",
            )
            .with_help("LinuxCNC's format: `T1 P1 D6.35 Z75 ;comment`"),
            TableErrorKind::NotANumber(word) => error(
                format!("`{word}` is not a number"),
                at,
                "expected a number after the letter",
            ),
            TableErrorKind::ToolNumber => error("invalid tool number", at, "a whole number from 0"),
            TableErrorKind::Diameter => {
                error("invalid tool diameter", at, "a diameter is not negative")
            }
            TableErrorKind::Length => error("invalid tool length", at, "out of range"),
            TableErrorKind::NoTool => error("a tool line without T", at, "T names the tool"),
            TableErrorKind::NoDiameter(tool) => error(
                format!("tool {tool} has no diameter"),
                at,
                "D gives the diameter",
            ),
            TableErrorKind::Twice { tool, first } => error(
                format!("tool {tool} is in the table twice"),
                at,
                "again here",
            )
            .with_secondary(*first, "first here"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_wrong_line_is_reported_with_its_kind() {
        let text =
            "T1 D3\nT1 D4\nK5\nT2 Zx\nT-1 D1\nT3 D-1\nT4 D1 Z1e99\nP5 D1\nT6 Z1\n  ; a comment\n";
        let errors = match parse(text, 0) {
            Err(errors) => errors,
            Ok(tools) => panic!("parsed {tools:?}"),
        };
        let kinds: Vec<(u32, TableErrorKind)> = errors
            .iter()
            .map(|e| (e.span.line, e.kind.clone()))
            .collect();
        let first = Span::new(0, 1, 0, 2);
        assert_eq!(
            kinds,
            [
                (2, TableErrorKind::Twice { tool: 1, first }),
                (3, TableErrorKind::UnknownWord("K5".into())),
                (4, TableErrorKind::NotANumber("Zx".into())),
                (5, TableErrorKind::ToolNumber),
                (6, TableErrorKind::Diameter),
                (7, TableErrorKind::Length),
                (8, TableErrorKind::NoTool),
                (9, TableErrorKind::NoDiameter(6)),
            ]
        );
        // Each says itself at its line.
        assert!(errors
            .iter()
            .all(|e| e.to_diagnostic().labels[0].range == e.span.range()));
    }
}
