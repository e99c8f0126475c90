//! Diagnostics: the one place that knows codespan-reporting. Every stage
//! has an enum of its problems, found as a [`Located`] kind and told in
//! words by its [`Wording`], which makes a [`Diagnostic`];
//! this module builds and renders them. It does no I/O: rendering returns a
//! `String` that the CLI prints.
//!
//! Rendering shows only the lines the labels point at, cut from the
//! sources into a small excerpt: a line longer than [`MAX_SHOWN`]
//! characters is shown as a window around the label (a one-line 600 KB
//! program is not dumped to the terminal), with the real line and column
//! numbers.

use crate::source::{Sources, Span};
use codespan_reporting::diagnostic::{Diagnostic as CsDiagnostic, Label, Severity};
use codespan_reporting::files::{Error as FilesError, Files};
use codespan_reporting::term;
use std::ops::Range;

pub type Diagnostic = CsDiagnostic<usize>;

/// Characters of one source line a diagnostic shows at most.
pub const MAX_SHOWN: usize = 200;

/// An error with a primary label at `span`.
pub fn error(
    message: impl std::fmt::Display,
    span: Span,
    label: impl std::fmt::Display,
) -> Diagnostic {
    CsDiagnostic::error()
        .with_message(message)
        .with_labels(vec![
            Label::primary(span.file_id(), span.range()).with_message(label)
        ])
}

/// A warning with a primary label at `span`.
pub fn warning(
    message: impl std::fmt::Display,
    span: Span,
    label: impl std::fmt::Display,
) -> Diagnostic {
    CsDiagnostic::warning()
        .with_message(message)
        .with_labels(vec![
            Label::primary(span.file_id(), span.range()).with_message(label)
        ])
}

/// A note (a message for the user, not a problem) at `span`.
pub fn note(
    message: impl std::fmt::Display,
    span: Span,
    label: impl std::fmt::Display,
) -> Diagnostic {
    CsDiagnostic::note()
        .with_message(message)
        .with_labels(vec![
            Label::primary(span.file_id(), span.range()).with_message(label)
        ])
}

/// A problem a stage finds, as data: which one (`kind`, an enum of the
/// stage's) and where. Its wording lives in the kind's [`Wording`].
#[derive(Clone, Debug, PartialEq)]
pub struct Located<K> {
    pub kind: K,
    pub span: Span,
}

/// How a stage's kind of problem is told to the user, at a span.
pub trait Wording {
    fn wording(&self, at: Span) -> Diagnostic;
}

impl<K> Located<K> {
    pub fn new(kind: K, span: Span) -> Located<K> {
        Located { kind, span }
    }
}

impl<K: Wording> Located<K> {
    pub fn to_diagnostic(&self) -> Diagnostic {
        self.kind.wording(self.span)
    }
}

impl<K: Wording> From<Located<K>> for Diagnostic {
    fn from(e: Located<K>) -> Diagnostic {
        e.to_diagnostic()
    }
}

/// Builder helpers shared by every stage's `to_diagnostic()`.
pub trait DiagnosticExt {
    fn with_secondary(self, span: Span, label: impl std::fmt::Display) -> Self;
    fn with_help(self, help: impl std::fmt::Display) -> Self;
}

impl DiagnosticExt for Diagnostic {
    fn with_secondary(mut self, span: Span, label: impl std::fmt::Display) -> Self {
        self.labels
            .push(Label::secondary(span.file_id(), span.range()).with_message(label));
        self
    }

    fn with_help(mut self, help: impl std::fmt::Display) -> Self {
        self.notes.push(format!("help: {}", help));
        self
    }
}

pub fn is_error(d: &Diagnostic) -> bool {
    matches!(d.severity, Severity::Error | Severity::Bug)
}

/// Render diagnostics as codespan's plain-text report (no colour, so that the
/// output is byte-for-byte reproducible in golden tests).
pub fn render(sources: &Sources, diagnostics: &[Diagnostic]) -> String {
    let config = term::Config::default();
    let mut out = String::new();
    for d in diagnostics {
        let (excerpt, d) = Excerpt::cut(sources, d);
        if term::emit_to_string(&mut out, &config, &excerpt, &d).is_err() {
            out.push_str(&format!("{}: {}\n", severity_name(d.severity), d.message));
        }
    }
    out
}

fn severity_name(s: Severity) -> &'static str {
    match s {
        Severity::Bug => "bug",
        Severity::Error => "error",
        Severity::Warning => "warning",
        Severity::Note => "note",
        Severity::Help => "help",
    }
}

/// The lines one diagnostic shows, as small files codespan renders from.
struct Excerpt {
    /// By the original file id.
    files: Vec<Option<ExcerptFile>>,
}

struct ExcerptFile {
    name: String,
    text: String,
    lines: Vec<ExcerptLine>,
}

struct ExcerptLine {
    /// 1-based line number in the original file.
    number: usize,
    /// The whole excerpt line (with its `…` markers) in the excerpt's text.
    range: Range<usize>,
    /// The part of it that is original text.
    shown: Range<usize>,
    /// Original byte offsets of the line's start and of the shown part.
    line_start: usize,
    window_start: usize,
    /// Characters of the original line cut before the shown part.
    cut_chars: usize,
}

impl Excerpt {
    /// The excerpt for `d`, and `d` with its labels moved into it.
    fn cut(sources: &Sources, d: &Diagnostic) -> (Excerpt, Diagnostic) {
        let mut excerpt = Excerpt { files: Vec::new() };
        // The lines each label covers, and for a long line the window
        // around the first label that points into it.
        let mut wanted: Vec<(usize, usize, usize)> = Vec::new();
        for label in &d.labels {
            let Some(file) = sources.get(label.file_id) else {
                continue;
            };
            let first = file.line_of(label.range.start);
            let last = file.line_of(label.range.end.max(label.range.start + 1) - 1);
            for line in first..=last.min(first + 20) {
                if !wanted.iter().any(|w| w.0 == label.file_id && w.1 == line) {
                    wanted.push((label.file_id, line, label.range.start));
                }
            }
        }
        wanted.sort();
        // codespan shows a line between two labelled ones, and `·` for a
        // longer gap: keep the line it will ask for.
        let between: Vec<(usize, usize, usize)> = wanted
            .windows(2)
            .filter(|w| w[0].0 == w[1].0 && w[0].1 + 2 == w[1].1)
            .map(|w| (w[0].0, w[0].1 + 1, usize::MAX))
            .collect();
        wanted.extend(between);
        wanted.sort();
        for (file_id, line, focus) in wanted {
            let Some(file) = sources.get(file_id) else {
                continue;
            };
            if excerpt.files.len() <= file_id {
                excerpt.files.resize_with(file_id + 1, || None);
            }
            let ef = excerpt.files[file_id].get_or_insert_with(|| ExcerptFile {
                name: file.name.clone(),
                text: String::new(),
                lines: Vec::new(),
            });
            let (line_start, full) = file.line_text(line);
            let focus = if focus == usize::MAX {
                0
            } else {
                focus.saturating_sub(line_start)
            };
            let (shown, cut_before, cut_after) = window(full, focus);
            let start = ef.text.len();
            if cut_before > 0 {
                ef.text.push('…');
            }
            let shown_start = ef.text.len();
            ef.text.push_str(shown);
            let shown_end = ef.text.len();
            if cut_after {
                ef.text.push('…');
            }
            let end = ef.text.len();
            ef.text.push('\n');
            ef.lines.push(ExcerptLine {
                number: line,
                range: start..end,
                shown: shown_start..shown_end,
                line_start,
                window_start: line_start + cut_before,
                cut_chars: full[..cut_before].chars().count(),
            });
        }
        let mut moved = d.clone();
        for label in &mut moved.labels {
            let Some(Some(ef)) = excerpt.files.get(label.file_id) else {
                continue;
            };
            label.range = ef.map(label.range.start)..ef.map(label.range.end);
            if label.range.end < label.range.start {
                label.range.end = label.range.start;
            }
        }
        (excerpt, moved)
    }
}

/// At most [`MAX_SHOWN`] characters of `line` around byte `focus`: the
/// shown part, the bytes cut before it, and whether some are cut after.
fn window(line: &str, focus: usize) -> (&str, usize, bool) {
    if line.chars().count() <= MAX_SHOWN {
        return (line, 0, false);
    }
    let boundary = |mut i: usize| {
        i = i.min(line.len());
        while !line.is_char_boundary(i) {
            i -= 1;
        }
        i
    };
    let half = MAX_SHOWN / 2;
    let start = boundary(focus.saturating_sub(half));
    let end = boundary(start + MAX_SHOWN);
    (&line[start..end], start, end < line.len())
}

impl ExcerptFile {
    /// An original byte offset as an offset into the excerpt text.
    fn map(&self, original: usize) -> usize {
        match self.lines.iter().rev().find(|l| l.line_start <= original) {
            Some(l) => {
                let inside = original.saturating_sub(l.window_start);
                l.shown.start + inside.min(l.shown.len())
            }
            None => 0,
        }
    }

    /// The 0-based original line index of an excerpt offset (codespan
    /// sees the original numbering, so it marks gaps as the file has them).
    fn line_at(&self, offset: usize) -> usize {
        self.lines
            .iter()
            .rev()
            .find(|l| l.range.start <= offset)
            .map_or(0, |l| l.number - 1)
    }

    /// The excerpt line of a 0-based original line index.
    fn line(&self, index: usize) -> Option<&ExcerptLine> {
        self.lines.iter().find(|l| l.number == index + 1)
    }
}

impl<'a> Files<'a> for Excerpt {
    type FileId = usize;
    type Name = &'a str;
    type Source = &'a str;

    fn name(&'a self, id: usize) -> Result<&'a str, FilesError> {
        self.file(id).map(|f| f.name.as_str())
    }

    fn source(&'a self, id: usize) -> Result<&'a str, FilesError> {
        self.file(id).map(|f| f.text.as_str())
    }

    fn line_index(&'a self, id: usize, byte_index: usize) -> Result<usize, FilesError> {
        self.file(id).map(|f| f.line_at(byte_index))
    }

    fn line_number(&'a self, id: usize, line_index: usize) -> Result<usize, FilesError> {
        self.file(id)?;
        Ok(line_index + 1)
    }

    fn column_number(
        &'a self,
        id: usize,
        line_index: usize,
        byte_index: usize,
    ) -> Result<usize, FilesError> {
        let f = self.file(id)?;
        let Some(l) = f.line(line_index) else {
            return Ok(1);
        };
        let to = byte_index.clamp(l.shown.start, l.shown.end);
        let shown = f
            .text
            .get(l.shown.start..to)
            .map_or(0, |s| s.chars().count());
        Ok(l.cut_chars + shown + 1)
    }

    fn line_range(&'a self, id: usize, line_index: usize) -> Result<Range<usize>, FilesError> {
        let f = self.file(id)?;
        // A line not in the excerpt shows empty (codespan asks only for
        // the lines around labels, which are all there).
        Ok(f.line(line_index)
            .map_or(f.text.len()..f.text.len(), |l| l.range.clone()))
    }
}

impl Excerpt {
    fn file(&self, id: usize) -> Result<&ExcerptFile, FilesError> {
        self.files
            .get(id)
            .and_then(Option::as_ref)
            .ok_or(FilesError::FileMissing)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_long_line_is_shown_around_the_caret() {
        let mut sources = Sources::new();
        let mut text = "G1 X1 ".repeat(10_000);
        let at = text.len();
        text.push_str("Q5 G1 X2\n");
        let file = sources.add("long.nc", text);
        let d = error("bad word", Span::new(file, 1, at, at + 2), "here");
        let shown = render(&sources, &[d]);
        assert!(shown.contains(&format!("long.nc:1:{}", at + 1)), "{shown}");
        assert!(shown.contains("Q5"), "{shown}");
        let longest = shown.lines().map(|l| l.chars().count()).max().unwrap_or(0);
        assert!(longest < MAX_SHOWN + 20, "{shown}");
    }

    #[test]
    fn short_lines_render_whole() {
        let mut sources = Sources::new();
        let file = sources.add("a.nc", "G0 X1\nG1 Y2 Q3\n");
        let d = error(
            "unexpected Q",
            Span::new(file, 2, 12, 14),
            "no code uses it",
        );
        let shown = render(&sources, &[d]);
        assert!(shown.contains("a.nc:2:7"), "{shown}");
        assert!(shown.contains("2 │ G1 Y2 Q3"), "{shown}");
    }
}

/// How bad a [`Plain`] diagnostic is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Level {
    Error,
    Warning,
    Note,
}

/// A diagnostic as plain data, for a caller that is not a terminal (the
/// editor server): its level, message, places and notes.
#[derive(Clone, Debug, PartialEq)]
pub struct Plain {
    pub level: Level,
    pub message: String,
    /// The primary place first.
    pub places: Vec<Place>,
    pub notes: Vec<String>,
}

/// A place a diagnostic points at: a file of the [`Sources`], a byte
/// range, what is said there.
#[derive(Clone, Debug, PartialEq)]
pub struct Place {
    pub file: usize,
    pub range: Range<usize>,
    pub label: String,
    pub primary: bool,
}

/// `d` as plain data.
pub fn plain(d: &Diagnostic) -> Plain {
    let level = match d.severity {
        Severity::Error | Severity::Bug => Level::Error,
        Severity::Warning => Level::Warning,
        Severity::Note | Severity::Help => Level::Note,
    };
    let mut places: Vec<Place> = d
        .labels
        .iter()
        .map(|l| Place {
            file: l.file_id,
            range: l.range.clone(),
            label: l.message.clone(),
            primary: l.style == codespan_reporting::diagnostic::LabelStyle::Primary,
        })
        .collect();
    places.sort_by_key(|p| !p.primary);
    Plain {
        level,
        message: d.message.clone(),
        places,
        notes: d.notes.clone(),
    }
}
