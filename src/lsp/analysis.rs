//! What the editor server knows of one document: it compiled through the
//! driver's session (the editor's unsaved text, the files it has open over
//! the disk), its diagnostics at their places, and after each line that
//! moves the tool, where the tool is and when. Pure: text and a
//! file-system view in, data out; no protocol here.

use super::index::{first_comment, Index};
use crate::diagnostic::{plain, Level, Plain};
use crate::driver::discovery::{folder_of, Search};
use crate::driver::fs::FileSystem;
use crate::driver::project::{self, ProjectError};
use crate::driver::{CompileOptions, Job, Program, Session};
use crate::eval::Seen;
use crate::ir::Units;
use crate::plan::{clock_per_move, Limits};
use crate::source::Sources;
use crate::syntax::Language;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// A place in a document: 0-based line and UTF-16 column, as LSP counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct At {
    pub line: u32,
    pub column: u32,
}

/// A diagnostic of the document, at its place in it.
#[derive(Clone, Debug, PartialEq)]
pub struct Found {
    pub level: Level,
    pub from: At,
    pub to: At,
    pub message: String,
    /// Other places in the document it points at, with what is said there.
    pub related: Vec<(At, At, String)>,
}

/// After a line that moves: where the tool is (output units) and when.
#[derive(Clone, Debug, PartialEq)]
pub struct ToolAt {
    /// The end of the line, where the hint stands.
    pub at: At,
    pub label: String,
}

/// An entry of the document's outline.
#[derive(Clone, Debug, PartialEq)]
pub struct Outlined {
    pub kind: OutlineKind,
    pub name: String,
    pub from: At,
    pub to: At,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutlineKind {
    Subprogram,
    /// A wizard or directive call.
    Call,
    /// A loop: `while`, `do`, `repeat`.
    Loop,
    ToolChange,
}

/// A wizard as the editor shows it.
#[derive(Clone, Debug, PartialEq)]
pub struct WizardEntry {
    pub name: String,
    /// What `ger wizards NAME` prints.
    pub manual: String,
    pub summary: String,
    /// Its parameters, each with its default if it has one.
    pub params: Vec<(String, Option<String>)>,
    /// Its `.rhai` file; `None` for the standard library's.
    pub file: Option<PathBuf>,
}

/// A subprogram of another file (a LinuxCNC subroutine file).
#[derive(Clone, Debug, PartialEq)]
pub struct ElsewhereSub {
    pub key: String,
    pub file: PathBuf,
    pub from: At,
    pub to: At,
    pub comment: Option<String>,
}

/// One document analysed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Analysis {
    pub diagnostics: Vec<Found>,
    pub tool_at: Vec<ToolAt>,
    pub outline: Vec<Outlined>,
    /// Its names and their places.
    pub index: Index,
    /// The wizards it can call.
    pub wizards: Vec<WizardEntry>,
    /// The subprograms of the subroutine files it can call.
    pub elsewhere: Vec<ElsewhereSub>,
}

/// A document loaded with what it needs, as `ger compile` would load it.
struct Loaded {
    job: Job,
    machine: Option<crate::driver::machine::Machine>,
    language: crate::syntax::Language,
}

/// Load the document `path` whose text is `text`, with the options of
/// the `ger.toml` above it (else `ger compile`'s defaults); `Err`: why
/// it cannot be, in words.
fn load(fs: &dyn FileSystem, path: &Path, text: &str) -> Result<Loaded, Vec<String>> {
    let (mut options, mut search) = (CompileOptions::default(), Search::default());
    let machine =
        match project::configure(fs, folder_of(path), &mut options, &mut search, &|_| false) {
            Ok(project) => project.and_then(|p| p.machine),
            Err((sources, ProjectError::Invalid(d))) => {
                return Err(d.iter().map(|d| outside(&sources, &plain(d))).collect())
            }
            Err((_, ProjectError::Unread(why))) => return Err(vec![why]),
        };
    let session = Session::new(fs, options, search).map_err(|e| vec![format!("ger.toml: {e}")])?;
    let name = path.display().to_string();
    let program = Program::Text {
        name: &name,
        path: Some(path),
        text: text.to_string(),
    };
    let job = session.load(program).map_err(|e| vec![e.to_string()])?;
    let language = session.options().language(&name);
    Ok(Loaded {
        job,
        machine,
        language,
    })
}

/// Analyse the document `path` whose text is `text`, with the options of
/// the `ger.toml` above it (else `ger compile`'s defaults).
pub fn analyse(fs: &dyn FileSystem, path: &Path, text: &str) -> Analysis {
    analyse_unless(fs, path, text, &Arc::default()).unwrap_or_default()
}

/// [`analyse`], given up (`None`) as soon as `cancel` is set: the
/// editor has newer text.
pub fn analyse_unless(
    fs: &dyn FileSystem,
    path: &Path,
    text: &str,
    cancel: &Arc<AtomicBool>,
) -> Option<Analysis> {
    let Loaded {
        mut job,
        machine,
        language,
    } = match load(fs, path, text) {
        Ok(loaded) => loaded,
        Err(messages) => return Some(at_top(text, messages)),
    };
    job.options.eval.cancel = Some(Arc::clone(cancel));
    let cancelled = || cancel.load(Ordering::Relaxed);
    let outcome = job.outcome();
    if cancelled() {
        return None;
    }
    let lines = LineStarts::new(text);
    let diagnostics = outcome
        .diagnostics
        .iter()
        .map(|d| found(&job, &lines, &plain(d)))
        .collect();
    let limits = machine.as_ref().and_then(|m| Limits::of(m).ok());
    let tool_at = match &outcome.tool_path {
        Some(path) => tool_positions(&job, &lines, path, limits.as_ref()),
        None => Vec::new(),
    };
    if cancelled() {
        return None;
    }
    let (program, _) = crate::syntax::parse_program_as(text, 0, language);
    let mut outline = outline(text, &lines, &program);
    if let Some(path) = &outcome.tool_path {
        for event in &path.events {
            if let crate::toolpath::EventKind::ToolChange(t) = event.kind {
                if event.span.file_id() == job.file {
                    let (from, to) = (event.span.start as usize, event.span.end as usize);
                    outline.push(Outlined {
                        kind: OutlineKind::ToolChange,
                        name: format!("T{t} (tool change)"),
                        from: lines.at(text, from),
                        to: lines.at(text, to),
                    });
                }
            }
        }
    }
    outline.sort_by_key(|o| o.from);
    if cancelled() {
        return None;
    }
    Some(Analysis {
        diagnostics,
        tool_at,
        outline,
        index: Index::of_program(&program, text),
        wizards: wizards(&job),
        elsewhere: elsewhere(&job, language),
    })
}

/// The values the document's variables have where it reads and sets
/// them, by the byte offset of the place: a run of its own, only when
/// the editor asks (a hover on a variable); `None` as soon as `cancel`
/// is set.
pub fn watch_unless(
    fs: &dyn FileSystem,
    path: &Path,
    text: &str,
    cancel: &Arc<AtomicBool>,
) -> Option<HashMap<usize, Seen>> {
    let Ok(mut loaded) = load(fs, path, text) else {
        return Some(HashMap::new());
    };
    loaded.job.options.eval.cancel = Some(Arc::clone(cancel));
    let file = loaded.job.file as u32;
    let seen = loaded.job.watch().seen;
    if cancel.load(Ordering::Relaxed) {
        return None;
    }
    Some(
        seen.into_iter()
            .filter(|((f, _), _)| *f == file)
            .map(|((_, start), seen)| (start as usize, seen))
            .collect(),
    )
}

/// The document formatted ([`super::format`]), checked: its tool path
/// compiled before and after is the same, else `Err` says why it is left
/// as it is; `None` as soon as `cancel` is set.
pub fn formatted_unless(
    fs: &dyn FileSystem,
    path: &Path,
    text: &str,
    numbers: super::format::Numbers,
    cancel: &Arc<AtomicBool>,
) -> Option<Result<String, String>> {
    let checked = formatted(fs, path, text, numbers, cancel);
    (!cancel.load(Ordering::Relaxed)).then_some(checked)
}

fn formatted(
    fs: &dyn FileSystem,
    path: &Path,
    text: &str,
    numbers: super::format::Numbers,
    cancel: &Arc<AtomicBool>,
) -> Result<String, String> {
    let refused = "formatting needs a program that compiles (its tool path is checked)";
    let tool_path = |loaded: Loaded| -> Result<crate::toolpath::ToolPath, String> {
        let mut job = loaded.job;
        job.options.eval.cancel = Some(Arc::clone(cancel));
        job.tool_path().0.ok_or_else(|| refused.to_string())
    };
    let loaded = load(fs, path, text).map_err(|why| why.join("\n"))?;
    let egc = loaded.language == Language::Egc;
    let before = tool_path(loaded)?;
    let after_text = super::format::format(text, egc, numbers);
    if after_text == text {
        return Ok(after_text);
    }
    let after = tool_path(load(fs, path, &after_text).map_err(|why| why.join("\n"))?)?;
    let exact = crate::toolpath::compare::Options {
        tol: 1e-9,
        feed_tol: 1e-12,
        ..Default::default()
    };
    let same_events = before.events.len() == after.events.len()
        && before
            .events
            .iter()
            .zip(&after.events)
            .all(|(a, b)| a.kind == b.kind && a.after_move == b.after_move);
    match crate::toolpath::compare::compare(&before, &after, &exact) {
        Ok(_) if same_events => Ok(after_text),
        Ok(_) => Err(
            "formatting would change the program's tool changes, stops or dwells: left as it is"
                .into(),
        ),
        Err(d) => Err(format!(
            "formatting would change the tool path ({}): left as it is",
            d.message
        )),
    }
}

/// The wizards the job can call, as the editor shows them.
fn wizards(job: &Job) -> Vec<WizardEntry> {
    job.wizards()
        .iter()
        .map(|w| {
            let params = match &w.declaration {
                Ok(d) => d
                    .params
                    .iter()
                    .map(|p| (p.name.clone(), p.default.as_ref().map(|d| d.to_string())))
                    .collect(),
                Err(_) => Vec::new(),
            };
            WizardEntry {
                name: w.name.clone(),
                manual: w.manual(),
                summary: w.described().1,
                params,
                file: (w.origin != "stdlib").then(|| PathBuf::from(&w.origin)),
            }
        })
        .collect()
}

/// The subprograms of the subroutine files the job reads.
fn elsewhere(job: &Job, language: crate::syntax::Language) -> Vec<ElsewhereSub> {
    let mut out = Vec::new();
    for &file in &job.options.library {
        let text = job.sources.text(file);
        let lines = LineStarts::new(text);
        for sub in Index::of(text, language).subs {
            out.push(ElsewhereSub {
                comment: first_comment(text, sub.whole.clone()),
                key: sub.key,
                file: PathBuf::from(job.sources.name(file)),
                from: lines.at(text, sub.at.start),
                to: lines.at(text, sub.at.end),
            });
        }
    }
    out
}

/// The outline of `text` as its front end reads it: subprograms, wizard
/// and directive calls, loops.
fn outline(text: &str, lines: &LineStarts, program: &crate::ast::Program) -> Vec<Outlined> {
    use crate::ast::{Stmt, StmtKind};
    let names = &program.names;
    let mut out = Vec::new();
    let place = |from: u32, to: u32| (lines.at(text, from as usize), lines.at(text, to as usize));
    for sub in &program.subprograms {
        let end = sub.body.last().map_or(sub.span.end, |s| s.span.end);
        let (from, to) = place(sub.span.start, end);
        let name = sub.name.describe(names);
        out.push(Outlined {
            kind: OutlineKind::Subprogram,
            name,
            from,
            to,
        });
    }
    fn walk(stmts: &[Stmt], f: &mut dyn FnMut(&Stmt)) {
        for stmt in stmts {
            f(stmt);
            match &stmt.kind {
                StmtKind::If(if_) => {
                    if_.branches.iter().for_each(|(_, body)| walk(body, f));
                    if let Some(body) = &if_.otherwise {
                        walk(body, f);
                    }
                }
                StmtKind::While(w) => walk(&w.body, f),
                StmtKind::Repeat(r) => walk(&r.body, f),
                _ => {}
            }
        }
    }
    let bodies = std::iter::once(&program.main).chain(program.subprograms.iter().map(|s| &s.body));
    for body in bodies {
        walk(body, &mut |stmt| {
            let (kind, name) = match &stmt.kind {
                StmtKind::Call { name, .. } => (OutlineKind::Call, names.text(*name).to_string()),
                StmtKind::While(w) if w.test_after => (OutlineKind::Loop, "do … while".into()),
                StmtKind::While(_) => (OutlineKind::Loop, "while".into()),
                StmtKind::Repeat(_) => (OutlineKind::Loop, "repeat".into()),
                _ => return,
            };
            let (from, to) = place(stmt.span.start, stmt.span.end);
            out.push(Outlined {
                kind,
                name,
                from,
                to,
            });
        });
    }
    out
}

/// What to show on hovering the place `at` of `text`: the meaning of the
/// G or M code there (not in a comment).
pub fn hover(text: &str, at: At) -> Option<String> {
    let line = text.lines().nth(at.line as usize)?;
    // The byte of the UTF-16 column.
    let mut units = 0;
    let column = line
        .char_indices()
        .find(|(_, c)| {
            units += c.len_utf16();
            units > at.column as usize
        })
        .map_or(line.len(), |(i, _)| i);
    let bytes = line.as_bytes();
    let in_comment = line[..column].contains(';')
        || line[..column].matches('(').count() > line[..column].matches(')').count();
    if in_comment || column >= bytes.len() {
        return None;
    }
    // Back to the letter: over digits and a point.
    let mut start = column;
    while start > 0 && (bytes[start].is_ascii_digit() || bytes[start] == b'.') {
        start -= 1;
    }
    let letter = bytes[start].to_ascii_uppercase();
    if letter != b'G' && letter != b'M' {
        return None;
    }
    // A letter that ends a name (`ProgM3`) is not a word's.
    if start > 0 && (bytes[start - 1].is_ascii_alphanumeric() || bytes[start - 1] == b'_') {
        return None;
    }
    let digits: String = line[start + 1..]
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == '.')
        .collect();
    let number: f64 = digits.parse().ok()?;
    super::codes::lookup(letter, number).map(super::codes::Code::markdown)
}

/// Messages about something outside the document, shown at its top.
fn at_top(text: &str, messages: Vec<String>) -> Analysis {
    let end = LineStarts::new(text).at(text, text.find('\n').unwrap_or(text.len()));
    let diagnostics = messages
        .into_iter()
        .map(|message| Found {
            level: Level::Error,
            from: At { line: 0, column: 0 },
            to: end,
            message,
            related: Vec::new(),
        })
        .collect();
    Analysis {
        diagnostics,
        ..Analysis::default()
    }
}

/// A diagnostic about another file, in words: `file:line: message`.
fn outside(sources: &Sources, d: &Plain) -> String {
    match d.places.first() {
        Some(p) => {
            let line = sources.get(p.file).map_or(1, |f| f.line_of(p.range.start));
            format!("{}:{line}: {}", sources.name(p.file), d.message)
        }
        None => d.message.clone(),
    }
}

/// A diagnostic placed in the document; one about another file (a
/// wizard, a subroutine file) at the document's top, naming it.
fn found(job: &Job, lines: &LineStarts, d: &Plain) -> Found {
    let text = job.sources.text(job.file);
    let mut notes = d.notes.join("\n");
    if !notes.is_empty() {
        notes.insert(0, '\n');
    }
    let in_document: Vec<_> = d.places.iter().filter(|p| p.file == job.file).collect();
    let (from, to, message) = match d.places.first() {
        Some(p) if p.file == job.file => {
            let label = if p.label.is_empty() {
                String::new()
            } else {
                format!(" ({})", p.label)
            };
            let (from, to) = (lines.at(text, p.range.start), lines.at(text, p.range.end));
            (from, to, format!("{}{label}{notes}", d.message))
        }
        _ => {
            let top = At { line: 0, column: 0 };
            (top, top, format!("{}{notes}", outside(&job.sources, d)))
        }
    };
    let related = in_document
        .iter()
        .skip(usize::from(
            d.places.first().is_some_and(|p| p.file == job.file),
        ))
        .map(|p| {
            (
                lines.at(text, p.range.start),
                lines.at(text, p.range.end),
                p.label.clone(),
            )
        })
        .collect();
    Found {
        level: d.level,
        from,
        to,
        message,
        related,
    }
}

/// After each line of the document that moves the tool: its position at
/// the line's last move (output units) and the time from the start.
fn tool_positions(
    job: &Job,
    lines: &LineStarts,
    path: &crate::toolpath::ToolPath,
    limits: Option<&Limits>,
) -> Vec<ToolAt> {
    let text = job.sources.text(job.file);
    let clock = clock_per_move(path, limits);
    let scale = match path.units {
        Some(Units::Inch) => 1.0 / 25.4,
        _ => 1.0,
    };
    let mut out: Vec<ToolAt> = Vec::new();
    let mut seen = std::collections::HashMap::new();
    for (m, t) in path.moves.iter().zip(&clock) {
        if m.span.file_id() != job.file || m.span.line == 0 {
            continue;
        }
        let line = m.span.line - 1;
        let end = lines.line_end(text, line as usize);
        let label = format!(
            "→ X{} Y{} Z{} · {}",
            short(m.end[0] * scale),
            short(m.end[1] * scale),
            short(m.end[2] * scale),
            minutes(*t)
        );
        let hint = ToolAt {
            at: lines.at(text, end),
            label,
        };
        // A line's hint is its last move's; lines in the order first met.
        match seen.entry(line) {
            std::collections::hash_map::Entry::Occupied(at) => out[*at.get()] = hint,
            std::collections::hash_map::Entry::Vacant(at) => {
                at.insert(out.len());
                out.push(hint);
            }
        }
    }
    out
}

/// A coordinate as a person reads it: at most 3 decimals, no trailing
/// zeros.
fn short(v: f64) -> String {
    let text = format!("{:.3}", v);
    let text = text.trim_end_matches('0').trim_end_matches('.');
    match text {
        "-0" => "0".into(),
        t => t.into(),
    }
}

/// `m:ss` (or `h:mm:ss`).
fn minutes(seconds: f64) -> String {
    let s = seconds.max(0.0).round() as u64;
    match s >= 3600 {
        true => format!("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60),
        false => format!("{}:{:02}", s / 60, s % 60),
    }
}

/// Where each line of a text starts, to turn byte offsets into LSP places.
pub(super) struct LineStarts {
    starts: Vec<usize>,
}

impl LineStarts {
    pub(super) fn new(text: &str) -> LineStarts {
        let mut starts = vec![0];
        starts.extend(text.match_indices('\n').map(|(i, _)| i + 1));
        LineStarts { starts }
    }

    /// The place of byte `offset` (clamped to the text, to a character).
    pub(super) fn at(&self, text: &str, offset: usize) -> At {
        let mut offset = offset.min(text.len());
        while !text.is_char_boundary(offset) {
            offset -= 1;
        }
        let line = self.starts.partition_point(|&s| s <= offset) - 1;
        let column = text[self.starts[line]..offset].encode_utf16().count();
        At {
            line: line as u32,
            column: column as u32,
        }
    }

    /// The byte offset of the place `at` (clamped to its line).
    pub(super) fn offset(&self, text: &str, at: At) -> usize {
        let Some(&start) = self.starts.get(at.line as usize) else {
            return text.len();
        };
        let end = self.line_end(text, at.line as usize);
        let mut units = 0;
        text[start..end]
            .char_indices()
            .find(|(_, c)| {
                units += c.len_utf16();
                units > at.column as usize
            })
            .map_or(end, |(i, _)| start + i)
    }

    /// The byte offset of the end of line `line` (before its line end).
    pub(super) fn line_end(&self, text: &str, line: usize) -> usize {
        let end = self.starts.get(line + 1).map_or(text.len(), |&s| s - 1);
        let end = end.min(text.len());
        match text[..end].ends_with('\r') {
            true => end - 1,
            false => end,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::driver::fs::Memory;

    #[test]
    fn an_error_is_at_its_place_and_each_moving_line_says_where_the_tool_is() {
        let fs = Memory::new();
        let text = "G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F600\nG1 X10 Y5\nG1 X<Nope>\nM30\n";
        let a = analyse(&fs, Path::new("/p/part.egc"), text);
        assert_eq!(a.diagnostics.len(), 1, "{:?}", a.diagnostics);
        let d = &a.diagnostics[0];
        assert_eq!((d.level, d.from.line), (Level::Error, 4), "{d:?}");
        assert!(d.from.column >= 4, "{d:?}");
        let fixed = text.replace("X<Nope>", "X20");
        let a = analyse(&fs, Path::new("/p/part.egc"), &fixed);
        assert!(a.diagnostics.iter().all(|d| d.level != Level::Error));
        let labels: Vec<_> = a
            .tool_at
            .iter()
            .map(|h| (h.at.line, h.label.as_str()))
            .collect();
        // At 10 mm/s: 6 mm down (0.6 s), 11.18 mm (1.72 s), 10 mm (2.72 s).
        assert_eq!(
            labels,
            [
                (1, "→ X0 Y0 Z5 · 0:00"),
                (2, "→ X0 Y0 Z-1 · 0:01"),
                (3, "→ X10 Y5 Z-1 · 0:02"),
                (4, "→ X20 Y5 Z-1 · 0:03"),
            ]
        );
        assert_eq!(
            a.tool_at[0].at,
            At {
                line: 1,
                column: 11
            }
        );
    }

    #[test]
    fn the_hints_clock_is_planned_on_the_machine_of_ger_toml() {
        // 100 mm at 100 mm/s: 1 s by length / feed. At 10 mm/s² the move
        // is a triangle peaking at √(10 · 100) = 31.6 mm/s: 2 · 31.6 / 10
        // = 6.3 s.
        let text = "G21 G90\nG1 X100 F6000\nM30\n";
        let mut fs = Memory::new();
        let path = Path::new("/p/part.nc");
        let clock = |a: &Analysis| a.tool_at.last().map(|h| h.label.clone());
        let unplanned = clock(&analyse(&fs, path, text)).unwrap();
        assert!(unplanned.ends_with("· 0:01"), "{unplanned}");
        let axis = "max-velocity = 6000\nmax-acceleration = 10\n";
        let machine = format!(
            "[machine]\ncontroller = \"grbl\"\nunits = \"mm\"\n\
             [machine.x]\n{axis}[machine.y]\n{axis}[machine.z]\n{axis}"
        );
        fs.insert("/p/ger.toml", machine);
        let planned = clock(&analyse(&fs, path, text)).unwrap();
        assert!(planned.ends_with("· 0:06"), "{planned}");
    }

    #[test]
    fn hovering_a_code_tells_its_meaning_and_words() {
        let text = "G21 G90 (G83 in a comment)\nN10 G83 X1 Y2 Z-3 R1 Q0.5\ng38.2 Z-5\nM3 S1000\nMoveM3 = 1\n";
        let at = |line, column| At { line, column };
        let g83 = hover(text, at(1, 5)).unwrap();
        assert!(g83.starts_with("**G83**: peck drilling"), "{g83}");
        assert!(g83.contains("X Y Z R Q F, L/K repeats") && g83.contains("canned cycle"));
        assert!(hover(text, at(0, 13)).is_none(), "in a comment");
        assert!(hover(text, at(2, 2)).unwrap().starts_with("**G38.2**"));
        assert!(hover(text, at(3, 0))
            .unwrap()
            .contains("spindle on, clockwise"));
        assert!(hover(text, at(4, 5)).is_none(), "a name's letters");
        assert!(hover(text, at(1, 9)).is_none(), "an axis word");
    }

    #[test]
    fn the_outline_has_subprograms_calls_loops_and_tool_changes() {
        let fs = Memory::new();
        let text = "G21 G90\nT1 M6\nG0 X0 Y0 Z5 F300\nCount = 0\nwhile (Count < 2) {\n  Count = Count + 1\n}\n\
                    Pocket 20 10 2\nM98 P100\nM30\nO100\nG0 X1\nM99\n";
        let a = analyse(&fs, Path::new("/p/part.egc"), text);
        let outline: Vec<_> = a
            .outline
            .iter()
            .map(|o| (o.kind, o.name.as_str(), o.from.line))
            .collect();
        assert_eq!(
            outline,
            [
                (OutlineKind::ToolChange, "T1 (tool change)", 1),
                (OutlineKind::Loop, "while", 4),
                (OutlineKind::Call, "Pocket", 7),
                (OutlineKind::Subprogram, "O100", 10),
            ],
            "{:?}",
            a.diagnostics
        );
    }

    #[test]
    fn places_count_utf16_and_line_ends_skip_the_cr() {
        let text = "(é😀)\r\nG0 X1\r\n";
        let lines = LineStarts::new(text);
        assert_eq!(
            lines.at(text, text.find(')').unwrap()),
            At { line: 0, column: 4 }
        );
        assert_eq!(lines.line_end(text, 1), text.len() - 2);
    }
}
