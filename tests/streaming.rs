//! The back end is streamed: the evaluator sends statements in batches and
//! each pass keeps its state between them. The output must not depend on
//! where the batches are cut. Every program of the repository is compiled
//! with batches of 1 and 7 statements and in one batch (the whole program
//! at once, as a pass over a complete program would see it), at every
//! stage and in the final output, and the text and diagnostics compared.
//! A generated program longer than the default batch checks the default
//! too.

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use ger::diagnostic::render;
use ger::driver::discovery::Search;
use ger::driver::fs::Disk;
use ger::driver::{compile, CompileOptions, Stage};
use ger::eval::EvalOptions;
use ger::source::Sources;
use ger::wizard::{Library, WizardEngine, WizardSource};
use std::path::{Path, PathBuf};

mod support;

use support::Corpus;

/// The options of these tests: `from`, `stage`, batches of `batch`.
fn options(from: Option<ger::eval::Flavour>, stage: Option<Stage>, batch: usize) -> CompileOptions {
    CompileOptions {
        eval: EvalOptions {
            batch,
            // Every batch that size (the default's first are smaller).
            first_batch: batch,
            // Runaway-loop cases: the same error, sooner.
            max_iterations: 100_000,
            ..EvalOptions::default()
        },
        from,
        stage,
        ..CompileOptions::default()
    }
}

/// The wizards of `wizards/` (which some test programs call) and the
/// standard library, in `sources`, found as the command line finds them.
fn engine(sources: &mut Sources) -> WizardEngine {
    let search = Search {
        wizard_path: vec![support::manifest().join("wizards")],
        ..Search::default()
    };
    let found = ger::driver::discovery::wizards(&Disk, &search, None).unwrap();
    WizardEngine::new(Library::new(found, sources))
}

/// Text and rendered diagnostics of one compile.
fn run(path: &Path, text: &str, stage: Option<Stage>, batch: usize) -> String {
    run_with(path, text, &options(None, stage, batch))
}

/// [`run`] with `options`.
fn run_with(path: &Path, text: &str, options: &CompileOptions) -> String {
    let mut sources = Sources::new();
    let file = sources.add(path.to_string_lossy(), text.to_string());
    let mut engine = engine(&mut sources);
    let compiled = compile(&sources, file, options, Some(&mut engine));
    format!(
        "{}\n--- diagnostics ---\n{}",
        compiled.output.as_deref().unwrap_or("<no output>"),
        render(&sources, &compiled.diagnostics)
    )
}

fn programs() -> Vec<PathBuf> {
    let root = support::manifest();
    let mut dirs = vec![
        root.join("examples"),
        root.join("tests/oracle/eval"),
        root.join("tests/oracle/lower"),
    ];
    for entry in std::fs::read_dir(root.join("tests/cases"))
        .unwrap()
        .flatten()
    {
        dirs.push(entry.path());
    }
    dirs.iter().flat_map(|d| support::egc_files(d)).collect()
}

/// The stages after parsing.
fn stages() -> impl Iterator<Item = Option<Stage>> {
    Stage::names()
        .filter_map(Stage::from_name)
        .filter(|s| *s != Stage::Parse)
        .map(Some)
}

#[test]
fn output_does_not_depend_on_the_batch_size() {
    let programs = programs();
    assert!(
        programs.len() > 150,
        "found only {} programs",
        programs.len()
    );
    let mut compared = 0;
    for path in &programs {
        let text = std::fs::read_to_string(path).unwrap();
        let same = |stage: Option<Stage>, batches: &[usize]| {
            let whole = run(path, &text, stage, usize::MAX);
            for &batch in batches {
                let cut = run(path, &text, stage, batch);
                assert!(
                    cut == whole,
                    "{} at stage {stage:?}: batches of {batch} give\n{cut}\nin one batch:\n{whole}",
                    path.display()
                );
            }
            whole
        };
        let output = same(None, &[1, 7]);
        compared += 1;
        // A program with errors stops before the back end, at any stage.
        if output.starts_with("<no output>") {
            continue;
        }
        for stage in stages() {
            same(stage, &[1]);
            compared += 1;
        }
    }
    assert!(compared > 700, "compared {compared}");
}

/// A program of about 9,000 statements crosses the default batch several
/// times, with the modal state (G91, G16, offsets, units) live across the
/// cuts, and an error in the middle of the lowering.
#[test]
fn a_long_program_streams_like_a_short_one() {
    let mut text = String::from("SetOffset 55 10 20 0\nG21 G90 G17 G54\nG0 X0 Y0 Z5\nF500\n");
    text.push_str("Ii = 0\nwhile (Ii < 1500) {\n");
    text.push_str("  if (Ii % 300 == 0) { G55 } else if (Ii % 300 == 150) { G54 }\n");
    text.push_str("  G91 G1 X0.5 Y<sin(Ii)>\n  G90\n");
    text.push_str("  G16 G1 X<10 + Ii / 100> Y<Ii * 7> G15\n");
    text.push_str("  if (Ii % 500 == 499) { G20 G1 X1 G21 }\n");
    text.push_str("  Ii = Ii + 1\n}\nG0 Z5\nM30\n");
    let path = Path::new("long.egc");
    let whole = run(path, &text, None, usize::MAX);
    assert!(whole.lines().count() > 3000, "{}", &whole[..200]);
    for batch in [1, 1000, EvalOptions::default().batch] {
        assert!(run(path, &text, None, batch) == whole, "batch {batch}");
    }
    // The default's: 64 statements first, doubling to 1,024.
    let default = EvalOptions::default();
    assert!(default.first_batch < default.batch);
    assert!(run_with(path, &text, &CompileOptions::default()) == whole);
    // An arc that cannot be made, after 9,000 statements: reported the same.
    let broken = text.replace("G0 Z5\nM30", "G2 X0 Y0 R0.001\nM30");
    let whole = run(path, &broken, None, usize::MAX);
    assert!(whole.contains("arc radius too small"), "{whole}");
    assert_eq!(run(path, &broken, None, 1000), whole);
}

/// Any program is read a part at a time, its parts cut outside every
/// block (`chunk::cuts`), unless it needs the whole program (subprograms,
/// calls, `GOTO`). Every program of the repository (and, in a test of its
/// own, of `../shared/real`) gives the same output and diagnostics read whole
/// and read in parts of about 1, 40 and 4096 bytes, in its own language
/// and flavour and as Fanuc's; with the wizards, whose calls can fall in
/// any part.
#[test]
fn any_program_read_in_parts_is_read_as_a_whole() {
    let (cut, whole_only, read_in_parts) = any_program_in_parts(Corpus::Own);
    // The corpus has both kinds: cut, and read whole.
    assert!(cut > 150, "only {cut} programs are cut in parts");
    assert!(
        whole_only > 10,
        "only {whole_only} programs need to be read whole"
    );
    assert!(
        read_in_parts > 1000,
        "only {read_in_parts} compiles from a reader"
    );
}

/// [`any_program_read_in_parts_is_read_as_a_whole`] on `../shared/real`.
#[test]
#[cfg_attr(not(shared_real), ignore = "../shared/real absent")]
fn any_program_read_in_parts_is_read_as_a_whole_on_shared_real() {
    let (cut, whole_only, _) = any_program_in_parts(Corpus::SharedReal);
    assert!(cut + whole_only > 30, "only {} programs", cut + whole_only);
}

/// The checks of [`any_program_read_in_parts_is_read_as_a_whole`] on
/// `corpus`: how many programs were cut in parts, how many need a whole
/// read, and how many compiles from a reader were compared.
fn any_program_in_parts(corpus: Corpus) -> (usize, usize, usize) {
    use ger::eval::Flavour;
    use ger::source::Locator;
    use ger::syntax::chunk::{cuts, with_part_size};
    use ger::syntax::Language;
    let (mut cut, mut whole_only, mut read_in_parts) = (0, 0, 0);
    for (path, text) in &support::programs(corpus) {
        let language = Language::of_file(&path.to_string_lossy());
        let parts = with_part_size(Some(40), || {
            cuts(text, &Locator::new(0, text), language).map(|c| c.len())
        });
        match parts {
            Some(n) if n > 1 => cut += 1,
            Some(_) => {}
            None => whole_only += 1,
        }
        for from in [None, Some(Flavour::Fanuc)] {
            // `checked`: through `compile_to`, which reads in parts only a
            // plain program (what it writes cannot be taken back);
            // `compile` cuts as it goes and starts again when it must.
            let compile_with = |part: Option<usize>, stage: Option<Stage>, checked: bool| {
                with_part_size(part, || {
                    let mut sources = Sources::new();
                    let file = sources.add(path.to_string_lossy(), text.clone());
                    let mut engine = engine(&mut sources);
                    let options = options(from, stage, EvalOptions::default().batch);
                    let (output, diagnostics) = if checked {
                        let mut out = Vec::new();
                        let report = ger::driver::compile_to(
                            &sources,
                            file,
                            &options,
                            Some(&mut engine),
                            &mut out,
                        );
                        let output = report.succeeded().then(|| String::from_utf8(out).unwrap());
                        (output, report.diagnostics)
                    } else {
                        let compiled = compile(&sources, file, &options, Some(&mut engine));
                        (compiled.output, compiled.diagnostics)
                    };
                    format!(
                        "{}\n--- diagnostics ---\n{}",
                        output.as_deref().unwrap_or("<no output>"),
                        render(&sources, &diagnostics)
                    )
                })
            };
            let whole = compile_with(None, None, false);
            for (part, checked) in [
                (1, false),
                (40, false),
                (4096, false),
                (1, true),
                (40, true),
            ] {
                let parts = compile_with(Some(part), None, checked);
                assert!(
                    parts == whole,
                    "{} ({from:?}) in parts of {part} (checked: {checked}):\n{parts}\nwhole:\n{whole}",
                    path.display()
                );
            }
            // From a reader, its text never held: the same, or read whole
            // (as `ger compile -o` then does) exactly when the parts of the
            // text held whole say so.
            let options = options(from, None, EvalOptions::default().batch);
            for part in [1, 4096] {
                match from_reader(path, text, &options, part, true) {
                    Read::Compiled(read) => {
                        read_in_parts += 1;
                        assert!(
                            read == whole,
                            "{} ({from:?}) read in parts of {part}:\n{read}\nwhole:\n{whole}",
                            path.display()
                        );
                    }
                    Read::Whole => {
                        let at = Locator::new(0, text);
                        let cut = with_part_size(Some(part), || cuts(text, &at, language));
                        assert!(cut.is_none(), "{} read whole", path.display());
                    }
                    Read::Refused => {}
                }
            }
            // Every stage's text, where there is one.
            if from.is_some() || whole.starts_with("<no output>") {
                continue;
            }
            for stage in stages() {
                let whole = compile_with(None, stage, false);
                let parts = compile_with(Some(40), stage, false);
                assert!(
                    parts == whole,
                    "{} at stage {stage:?} in parts of 40:\n{parts}\nwhole:\n{whole}",
                    path.display()
                );
            }
        }
    }
    (cut, whole_only, read_in_parts)
}

/// Plain programs of words, comments and commands only are read a part at
/// a time (`syntax::chunk`). Every plain program of the repository (and,
/// in a test of its own, of `../shared/real`) gives the same output and
/// diagnostics read whole and read in parts of about 1, 40 and 4096 bytes
/// (a part ends at a line end), as LinuxCNC's G-code and as Fanuc's; and
/// compiled from a reader without its text (`driver::compile_file`).
#[test]
fn a_plain_program_read_in_parts_is_read_as_a_whole() {
    let (in_parts, from_readers) = plain_programs_in_parts(Corpus::Own);
    assert!(in_parts > 20, "only {in_parts} programs are read in parts");
    assert!(
        from_readers > 40,
        "only {from_readers} compiles from a reader"
    );
}

/// [`a_plain_program_read_in_parts_is_read_as_a_whole`] on `../shared/real`.
#[test]
#[cfg_attr(not(shared_real), ignore = "../shared/real absent")]
fn a_plain_program_read_in_parts_is_read_as_a_whole_on_shared_real() {
    let (in_parts, _) = plain_programs_in_parts(Corpus::SharedReal);
    assert!(in_parts > 10, "only {in_parts} programs are read in parts");
}

/// The checks of [`a_plain_program_read_in_parts_is_read_as_a_whole`] on
/// `corpus`: how many programs were read in parts, and how many compiles
/// from a reader were compared.
fn plain_programs_in_parts(corpus: Corpus) -> (usize, usize) {
    use ger::eval::Flavour;
    use ger::syntax::chunk::with_part_size;
    use ger::syntax::Language;
    let (mut in_parts, mut from_readers) = (0, 0);
    // Any other program is read whole either way: nothing to compare.
    for (path, text) in &support::plain_programs(corpus) {
        in_parts += 1;
        for from in [Flavour::LinuxCnc, Flavour::Fanuc] {
            let compile_with = |part: Option<usize>| {
                with_part_size(part, || {
                    let mut sources = Sources::new();
                    let file = sources.add(path.to_string_lossy(), text.clone());
                    let options = CompileOptions {
                        input: Some(Language::Gcode),
                        from: Some(from),
                        ..CompileOptions::default()
                    };
                    let compiled = compile(&sources, file, &options, None);
                    format!(
                        "{}\n--- diagnostics ---\n{}",
                        compiled.output.as_deref().unwrap_or("<no output>"),
                        render(&sources, &compiled.diagnostics)
                    )
                })
            };
            let whole = compile_with(None);
            for part in [1, 40, 4096] {
                let parts = compile_with(Some(part));
                assert!(
                    parts == whole,
                    "{} ({from:?}) in parts of {part}:\n{parts}\nwhole:\n{whole}",
                    path.display()
                );
            }
            // Compiled from a reader, its text never held (`ger compile -o`).
            let options = CompileOptions {
                input: Some(Language::Gcode),
                from: Some(from),
                ..CompileOptions::default()
            };
            for part in [1, 4096] {
                let read = from_reader(path, text, &options, part, false);
                assert!(
                    read == Read::Compiled(whole.clone()),
                    "{} ({from:?}) read in parts of {part}:\n{read:?}\nwhole:\n{whole}",
                    path.display()
                );
            }
            from_readers += 1;
        }
    }
    (in_parts, from_readers)
}

/// A wizard's `gcode("M98 P1000")` line calls a subprogram that only
/// running the program shows; one written after the call (Fanuc's, after
/// `M30`) is not among the parts read: the program is read whole, as if
/// it were short, not reported missing.
#[test]
fn a_wizard_calling_a_subprogram_written_later_reads_the_program_whole() {
    use ger::eval::Flavour;
    use ger::syntax::chunk::with_part_size;
    let text = "O0001\nG21 G90\nG0 X0 Y0 Z5\nCallSub()\nG1 X1 Y0 F100\nM30\nO1000\nG0 X5 Y5\nM99\n";
    let compile_in = |part: Option<usize>| {
        with_part_size(part, || {
            let mut sources = Sources::new();
            let file = sources.add("wz.nc", text.to_string());
            let wizard = WizardSource {
                name: "CallSub".into(),
                text: "gcode(\"M98 P1000\");".into(),
                origin: "test".into(),
            };
            let mut engine = WizardEngine::new(Library::new(vec![wizard], &mut sources));
            let options = options(Some(Flavour::Fanuc), None, EvalOptions::default().batch);
            let compiled = compile(&sources, file, &options, Some(&mut engine));
            let diagnostics = render(&sources, &compiled.diagnostics);
            (compiled.output, diagnostics)
        })
    };
    let whole = compile_in(None);
    assert!(
        whole.0.as_deref().is_some_and(|o| o.contains("X5.")),
        "{whole:?}"
    );
    for part in [1, 40] {
        assert_eq!(compile_in(Some(part)), whole, "in parts of {part}");
    }
}

/// A named subroutine written again after the program's end: the parts
/// after the end are read with the program's names, so the second `o<a>`
/// is the first's number, and the error is the whole read's.
#[test]
fn a_subroutine_written_twice_after_the_end_is_an_error_in_parts() {
    use ger::syntax::chunk::with_part_size;
    // The second: a subroutine's number, in its error, is the whole
    // read's (`o<name>`s are numbered after the names a program starts
    // with, in both).
    for (text, error) in [
        ("#<x> = 1\no<a> sub\nG0 X1\no<a> endsub\nG0 X0 Y0 Z1\no<a> call\nM2\nG0 X2\no<a> sub\nG0 X3\no<a> endsub\n", "defined twice"),
        ("G21\nG0 X0\no<foo> sub\nG1 X1 F100\nM30\n", "has no M99"),
    ] {
        let compile_in = |part: Option<usize>| {
            with_part_size(part, || {
                let mut sources = Sources::new();
                let file = sources.add("twice.ngc", text.to_string());
                let compiled = compile(&sources, file, &CompileOptions::default(), None);
                (compiled.output, render(&sources, &compiled.diagnostics))
            })
        };
        let whole = compile_in(None);
        assert!(whole.1.contains(error), "{whole:?}");
        for part in [1, 40] {
            assert_eq!(compile_in(Some(part)), whole, "in parts of {part}");
        }
    }
}

/// What follows a plain program's end (rs274 reads none of it but the
/// subprograms): one note, the same whole and in parts, whether the part
/// with the end is read as plain lines, cut as it goes, or the program
/// needs a whole read (a call of a subprogram written after the end).
#[test]
fn what_follows_the_end_is_read_alike_in_parts() {
    let prose = "These notes are not G-code: a = b : c\n  EMC_ABORT = 1, // x\n";
    for text in [
        format!("G21 G90 F100\nG1 X1\nG1 X2\nM2\n{prose}"),
        format!("G21 G90 F100\n#1 = 2\nG1 X#1\nM30\n{prose}o<a> sub\nG1 X3\no<a> endsub\n{prose}"),
        format!("G21 G90 F100\no<a> call\nM2\n{prose}o<a> sub\nG1 X3\no<a> endsub\n%\n{prose}"),
        format!("G21 G90 F100\nM98 P1000\nM30\n{prose}O1000\nG1 X4\nM99\n"),
        format!("o<a> sub\nG1 X3\no<a> endsub\nM2\n{prose}"),
    ] {
        let (output, _) = read_alike_in_parts("ended.ngc", &text, "not read", &[1, 4096]);
        assert!(output.is_some(), "{text}");
    }
}

/// A tape (a program whose first line is `%`) ends at its next `%` line,
/// M2/M30 or not: nothing after it is read and one note says so, the same
/// whole and in parts, whether the text is read as plain lines, cut as it
/// goes or whole, and from a file.
#[test]
fn a_tape_ends_at_its_closing_percent_alike_in_parts() {
    let after = "G0 X99\nThese notes are not G-code: a = b\n(comment)\n%\nG0 X98\n";
    for text in [
        format!("%\nG21 G90 F100\nG1 X1\nG1 X2\n%\n{after}"),
        format!("\n%\nG21 G90 F100\n#1 = 2\nG1 X#1\n%\n{after}M30\n"),
        format!("%\nG21 G90 F100\no<a> call\nM2\no<a> sub\nG1 X3\no<a> endsub\n%\n{after}"),
        format!("%\nO0001\nG21 G90 F100\nM98 P1000\nM30\nO1000\nG1 X4\nM99\n%\n{after}"),
    ] {
        let note = "after the tape's end are not read";
        let (output, shown) = read_alike_in_parts("tape.nc", &text, note, &[1, 40, 4096]);
        let output = output.unwrap_or_else(|| panic!("{text}\n{shown}"));
        assert!(
            !output.contains("X99") && !output.contains("X98"),
            "{output}"
        );
    }
}

/// `text`, written to a file `name`, compiled whole: its output and
/// diagnostics, which say `note` once; the same read in parts of 1 and 40
/// bytes and, where it compiles, from the file in parts of `file_parts`.
fn read_alike_in_parts(
    name: &str,
    text: &str,
    note: &str,
    file_parts: &[usize],
) -> (Option<String>, String) {
    use ger::syntax::chunk::with_part_size;
    let dir = std::env::temp_dir().join(format!("ger-alike-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    let compile_in = |part: Option<usize>| {
        with_part_size(part, || {
            let mut sources = Sources::new();
            let file = sources.add(path.to_string_lossy(), text.to_string());
            let compiled = compile(&sources, file, &CompileOptions::default(), None);
            (compiled.output, render(&sources, &compiled.diagnostics))
        })
    };
    let whole = compile_in(None);
    assert_eq!(whole.1.matches(note).count(), 1, "{text}\n{}", whole.1);
    for part in [1, 40] {
        assert_eq!(compile_in(Some(part)), whole, "{text} in parts of {part}");
    }
    let options = CompileOptions::default();
    for &part in file_parts {
        if let Read::Compiled(read) = from_reader(&path, text, &options, part, false) {
            let (output, shown) = (whole.0.as_deref().unwrap_or("<no output>"), &whole.1);
            assert_eq!(
                read,
                format!("{output}\n--- diagnostics ---\n{shown}"),
                "{text}"
            );
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
    whole
}

/// `path` (its decoded `text`) compiled from a reader in parts of about
/// `part` bytes, its text never held, as `ger compile -o` compiles it
/// (`driver::scan_file`, `driver::compile_file`), with the wizards of
/// `wizards/` and the standard library if `wizards`: its text (`<no
/// output>` on errors) and diagnostics.
fn from_reader(
    path: &Path,
    text: &str,
    options: &CompileOptions,
    part: usize,
    wizards: bool,
) -> Read {
    use ger::driver::{compile_file, scan_file};
    use ger::syntax::chunk::with_part_size;
    let raw = std::fs::read(path).unwrap();
    let Some(scan) = scan_file(&mut raw.as_slice()).unwrap() else {
        return Read::Refused;
    };
    let read = with_part_size(Some(part), || {
        let mut sources = Sources::new();
        let file = sources.add(path.to_string_lossy(), String::new());
        let mut engine = engine(&mut sources);
        let engine = wizards.then_some(&mut engine as &mut dyn ger::eval::WizardHost);
        let mut out = Vec::new();
        let name = path.to_string_lossy();
        let report = compile_file(
            &mut raw.as_slice(),
            &name,
            file,
            scan,
            options,
            engine,
            &mut out,
        )
        .unwrap()
        .compiled()?;
        sources.set_text(file, text.to_string());
        let output = String::from_utf8(out).unwrap();
        Some(format!(
            "{}\n--- diagnostics ---\n{}",
            if report.succeeded() {
                output.as_str()
            } else {
                "<no output>"
            },
            render(&sources, &report.diagnostics)
        ))
    });
    read.map_or(Read::Whole, Read::Compiled)
}

/// What [`from_reader`] did.
#[derive(Debug, PartialEq)]
enum Read {
    /// The scan refused the file (a control character, a lone CR): it is
    /// read whole.
    Refused,
    /// A part needs the whole program.
    Whole,
    /// The text and diagnostics.
    Compiled(String),
}

/// `ger compile` scans a file in two halves at once
/// (`driver::scan_path`): the answer must be the one reader's,
/// wherever the middle falls (files of every length from 0 to 80 bytes of
/// each kind), with a byte-order mark, CRLF and lone CR (refused), Latin-1
/// comments, the most decimals in either half.
#[test]
fn a_file_scanned_in_halves_is_scanned_as_one() {
    use ger::driver::{scan_file, scan_path};
    let kinds: [&[u8]; 7] = [
        b"G1 X1\nG1 X2.5\nG1 Y3\nG1 X1.123456\nM30\n",
        b"\xef\xbb\xbfG0 X1\nG1 X2.25 (a)\nM30",
        b"G0 X1\r\nG1 X2.5\r\nG1 Y1.75\r\nM30\r\n",
        b"G0 X1\nG1 X2\nG1 X3\rM30\r",
        b"G0 X1\nG1 X2\nG1 X3.5\n#1 = 2\nM30\n",
        b"G0 X1 (\xb0)\nG1 X2 (\xe9t\xe9)\nG1 Y3.25\nM30\n",
        b"G0 X1\nG1 X2\n\xef\xbb\xbfG1 X3\nM30\n",
    ];
    let dir = std::env::temp_dir().join(format!("ger-halves-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("p.ngc");
    let (mut scanned, mut refused, mut most) = (0, 0, 0);
    for kind in kinds {
        let long: Vec<u8> = kind.iter().copied().cycle().take(kind.len() * 2).collect();
        for len in 0..=long.len().min(80) {
            let bytes = &long[..len];
            std::fs::write(&path, bytes).unwrap();
            let one = scan_file(&mut &bytes[..]).unwrap();
            let halves = scan_path(&Disk, &path).unwrap();
            assert_eq!(halves, one, "{:?}", String::from_utf8_lossy(bytes));
            match one {
                Some(scan) => {
                    scanned += 1;
                    most += usize::from(scan.decimals == 6);
                }
                None => refused += 1,
            }
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(
        scanned > 300 && refused > 30 && most > 30,
        "{scanned} scanned ({most} with six decimals), {refused} refused"
    );
}

/// `driver::first_look` reads a small file through (`scan_path`'s
/// answer) and a large one's first lines only; a compile from a reader
/// with that answer stops at a part that has more decimals
/// (`Streamed::Rescan`), and with the whole scan's answer compiles.
#[test]
fn a_first_look_is_checked_part_by_part() {
    use ger::driver::{compile_file, first_look, scan_path, Streamed};
    let dir = std::env::temp_dir().join(format!("ger-first-look-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("p.ngc");
    let small = "G21 G1 X1.25 F100\nG1 X2.125\nM30\n";
    std::fs::write(&path, small).unwrap();
    assert_eq!(
        first_look(&Disk, &path).unwrap(),
        scan_path(&Disk, &path).unwrap()
    );
    let mut text = String::from("G21 G90\nG1 Z-1 F300\n");
    for i in 0..40_000 {
        text.push_str(&format!(
            "G1 X{:.3} Y{:.2}\n",
            i as f64 * 0.001,
            (i % 9) as f64
        ));
    }
    let late = format!("{text}G1 X1.12345\nM30\n");
    std::fs::write(&path, &late).unwrap();
    let first = first_look(&Disk, &path).unwrap().expect("a plain file");
    let whole = scan_path(&Disk, &path).unwrap().expect("a plain file");
    assert!(first.partial && !whole.partial);
    assert_eq!((first.decimals, whole.decimals), (3, 5));
    assert_eq!(first.len as u64, std::fs::metadata(&path).unwrap().len());
    let compiled = |scan| {
        let mut out = Vec::new();
        let bytes = late.as_bytes();
        let options = CompileOptions::default();
        compile_file(&mut &bytes[..], "p.ngc", 0, scan, &options, None, &mut out).unwrap()
    };
    assert!(matches!(compiled(first), Streamed::Rescan));
    let report = compiled(whole).compiled().expect("compiled");
    assert!(report.succeeded(), "{:?}", report.diagnostics);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A line of a made-up file for [`a_file_read_once_is_compiled_as_read_whole`]:
/// the `n`th point of a path, as a move with one to six decimals, or an arc
/// by its radius (whose centre is worked out, and printed on the output's
/// grid), and lines with words in comments, CRLF and lone CR line ends,
/// control characters, Latin-1 bytes.
fn made_up_line(kind: u8, n: u32) -> Vec<u8> {
    let x = f64::from(n % 1000) * 0.125;
    let y = x / 4.0;
    let line = match kind {
        0 => format!("G1 X{x:.1} Y{y:.2}\n"),
        1..=4 => format!("G1 X{x:.3} Y{y:.3}\n"),
        5 => format!("G1 X{x:.4} Y{y:.4}\n"),
        6 => format!("G1 X{x:.3} Y{y:.3} Z-{:.5}\n", x / 7.0),
        7 => format!("G1 X{x:.3} Y{y:.3} (X{:.7} at {n})\n", x / 9.0),
        8 => format!("G1 X{x:.3} Y{y:.3}\r\n"),
        9 => format!("G1 X{x:.2}\rY{y:.6}\n"),
        10 => format!("G1 X{x} Y{y} \u{1}\n"),
        11 => {
            return [
                b"(caf\xe9)".as_slice(),
                format!("G1 X{x:.4} Y{y}\n").as_bytes(),
            ]
            .concat()
        }
        // As a CAM program writes them: three decimals throughout.
        _ if n % 10 == 5 => format!("G2 X{x:.3} Y{y:.3} R5\n"),
        _ => format!("G1 X{x:.3} Y{y:.3} F300\n"),
    };
    line.into_bytes()
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]

    /// A file compiled from its file after a first look at its first lines
    /// (`driver::first_look_within`; checked part by part, scanned whole
    /// and compiled again when a part is not as they said, as `ger` does)
    /// gives what its decoded text compiled whole gives, or is refused and
    /// read whole where the whole scan refuses it.
    #[test]
    fn a_file_read_once_is_compiled_as_read_whole(
        // A rare kind, at some line, in a file of moves.
        rare in proptest::collection::vec((0u8..12, 0usize..3000), 0..4),
        lines in 1500usize..3000,
        part in proptest::sample::select(vec![40usize, 4096, 16384]),
    ) {
        use ger::driver::{compile_file, first_look_within, scan_path, Streamed};
        let mut bytes = b"G21 G90 G17\nG0 X0 Y0 Z2\nG1 Z-1 F300\n".to_vec();
        for n in 0..lines {
            let kind = rare.iter().find(|(_, at)| *at == n).map_or(12, |(k, _)| *k);
            bytes.extend(made_up_line(kind, n as u32));
        }
        bytes.extend_from_slice(b"M30\n");
        let dir = std::env::temp_dir().join(format!("ger-read-once-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("p.ngc");
        std::fs::write(&path, &bytes).unwrap();
        let text = ger::source::decode(bytes.clone()).unwrap_or_default();
        let shown = |sources: &Sources, out: Vec<u8>, report: &ger::driver::Report| {
            let out = if report.succeeded() { String::from_utf8(out).unwrap() } else { String::new() };
            (out, render(sources, &report.diagnostics))
        };
        let mut sources = Sources::new();
        let file = sources.add("p.ngc", text.clone());
        let whole = {
            let mut out = Vec::new();
            let report = ger::driver::compile_to(&sources, file, &CompileOptions::default(), None, &mut out);
            shown(&sources, out, &report)
        };
        let streamed = |scan| {
            let mut out = Vec::new();
            let compiled = ger::syntax::chunk::with_part_size(Some(part), || {
                compile_file(&mut &bytes[..], "p.ngc", file, scan, &CompileOptions::default(), None, &mut out)
            });
            (compiled.unwrap(), out)
        };
        let first = first_look_within(&Disk, &path, 1).unwrap();
        let exact = scan_path(&Disk, &path).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        let Some(first) = first else {
            // Refused from its first lines: the whole scan refuses it too.
            proptest::prop_assert!(exact.is_none());
            return Ok(());
        };
        let read = match streamed(first) {
            (Streamed::Compiled(report), out) => Some((report, out)),
            (Streamed::Rescan, _) => exact.map(|exact| match streamed(exact) {
                (Streamed::Compiled(report), out) => (report, out),
                _ => panic!("the whole scan's answer compiles"),
            }),
            (Streamed::Whole, _) => panic!("a plain program is never read whole"),
        };
        match read {
            Some((report, out)) => {
                proptest::prop_assert!(exact.is_some(), "compiled where the whole scan refuses");
                proptest::prop_assert_eq!(shown(&sources, out, &report), whole);
            }
            // Read whole, as `ger` then does.
            None => proptest::prop_assert!(exact.is_none()),
        }
    }
}

/// A plain file read from a reader in parts (`driver::compile_file`)
/// with a byte-order mark, CRLF line ends and Latin-1 comments (decoded
/// line by line) gives what the decoded text compiled whole gives.
#[test]
fn a_file_with_a_bom_and_latin1_lines_reads_in_parts_as_whole() {
    use ger::driver::{compile_file, scan_file};
    let bytes: &[u8] = b"\xef\xbb\xbfG21 G90\r\nG0 X1 (25\xb0)\r\nG1 X2.5 F100 (\xe9t\xe9)\r\n\
                         G1 Y3 (caf\xc3\xa9)\r\nG1 X1 (\xb0)\r\nM30\r\n";
    let text = ger::source::decode(bytes.to_vec()).unwrap();
    let whole = {
        let mut sources = Sources::new();
        let file = sources.add("p.ngc", text.clone());
        compile(&sources, file, &CompileOptions::default(), None)
    };
    let facts = scan_file(&mut &bytes[..]).unwrap().expect("a plain file");
    for part in [1, 8, 40, 4096] {
        let mut out = Vec::new();
        let report = ger::syntax::chunk::with_part_size(Some(part), || {
            compile_file(
                &mut &bytes[..],
                "p.ngc",
                0,
                facts,
                &CompileOptions::default(),
                None,
                &mut out,
            )
        })
        .unwrap()
        .compiled()
        .expect("read in parts");
        assert!(report.succeeded(), "{:?}", report.diagnostics);
        assert_eq!(
            Some(String::from_utf8(out).unwrap()),
            whole.output,
            "in parts of {part}"
        );
    }
}

/// The diagnostics of a program compiled from its file show the lines
/// they are about, read again a part at a time (`driver::lines_shown`,
/// `Sources::set_lines`: memory grows with the lines shown, not with the
/// file), exactly as with the file's whole text: every program of the
/// repository with diagnostics, and files made for the edges (a last line
/// with no line end, CRLF, a byte-order mark and Latin-1, errors a line or
/// two apart, a long line cut around its label).
#[test]
fn diagnostics_shown_from_some_lines_are_those_of_the_whole_text() {
    use ger::driver::{lines_shown, scan_file};
    let long = format!(
        "G0 X1 ({})\nG0 X<Undefined> ({})\nM30\n",
        "a".repeat(300),
        "b".repeat(300)
    );
    let made: Vec<(String, Vec<u8>)> = [
        &b"G21 G90\nG0 Z5\nDepth ="[..],
        b"G21 G90\r\nG0 X<Undefined>\r\nG0 Y1\r\nG0 Y<Nor>\r\nM30\r\n",
        b"\xef\xbb\xbfG21 G90 (\xe9t\xe9)\nG0 X<A> (\xb0)\nG0 X<B>\nM30\n",
        b"G21 G90\nG0 X<A>\nG0 X1\nG0 X<B>\nG0 X<C>\nM30\n",
        long.as_bytes(),
        b"",
        b"G0 X<A>",
    ]
    .iter()
    .enumerate()
    .map(|(k, bytes)| (format!("made{k}.egc"), bytes.to_vec()))
    .collect();
    let found = programs()
        .into_iter()
        .map(|path| (path.display().to_string(), std::fs::read(&path).unwrap()));
    let mut compared = 0;
    for (name, bytes) in made.into_iter().chain(found) {
        // Only a file the scan accepts is compiled from its file.
        if scan_file(&mut &bytes[..]).unwrap().is_none() {
            continue;
        }
        let Ok(text) = ger::source::decode(bytes.clone()) else {
            continue;
        };
        let mut sources = Sources::new();
        let file = sources.add(name.clone(), text);
        let compiled = compile(&sources, file, &CompileOptions::default(), None);
        if compiled.diagnostics.is_empty() {
            continue;
        }
        let whole = render(&sources, &compiled.diagnostics);
        let lines = lines_shown(&mut &bytes[..], file, &compiled.diagnostics).unwrap();
        let mut some = Sources::new();
        some.add(name.clone(), String::new());
        some.set_lines(file, lines);
        assert_eq!(render(&some, &compiled.diagnostics), whole, "{name}");
        compared += 1;
    }
    assert!(
        compared > 100,
        "{compared} programs with diagnostics compared"
    );
}

/// The statement limit counts what loops, subprogram calls and jumps back
/// make, not a program's own lines, each run once (a big plain file is no
/// runaway, and is read a part at a time): a plain program of three times
/// the limit compiles; a loop, a subprogram repeated and a `GOTO` loop
/// that make as much stop at the limit, with one error.
#[test]
fn the_statement_limit_counts_what_is_repeated() {
    let limit = 100;
    let compile_text = |name: &str, text: String| {
        let mut sources = Sources::new();
        let file = sources.add(name, text);
        let mut options = CompileOptions {
            eval: EvalOptions {
                max_statements: limit,
                ..EvalOptions::default()
            },
            ..CompileOptions::default()
        };
        if name.ends_with(".nc") {
            options.from = Some(ger::eval::Flavour::Fanuc);
        }
        compile(&sources, file, &options, None)
    };
    let moves: String = (0..3 * limit).map(|i| format!("G1 X{i} F100\n")).collect();
    let plain = compile_text("plain.ngc", format!("G21 G90\n{moves}M30\n"));
    assert!(plain.diagnostics.is_empty(), "{:?}", plain.diagnostics);
    let output = plain.output.expect("a plain program compiles");
    assert!(output.matches("G1").count() >= 3 * limit);
    let repeated = [
        (
            "loop.egc",
            "G21 G90\nIi = 0\nwhile (Ii < 300) {\n  G1 X<Ii> F100\n  Ii = Ii + 1\n}\nM30\n",
        ),
        (
            "sub.nc",
            "O0001\nG21 G90\nM98 P1000 L300\nM30\nO1000\nG1 X1 F100\nG1 X2\nM99\n",
        ),
        (
            // Stopped at the first loop: the second says nothing.
            "loops.egc",
            "G21 G90\nIi = 0\nwhile (Ii < 300) {\n  G1 X<Ii> F100\n  Ii = Ii + 1\n}\n\
             while (Ii < 600) {\n  G1 Y<Ii>\n  Ii = Ii + 1\n}\nM30\n",
        ),
        (
            "goto.nc",
            "O0001\nG21 G90\n#1 = 0\nN10 G1 X#1 F100\n#1 = #1 + 1\nIF [#1 LT 300] GOTO 10\nM30\n",
        ),
    ];
    for (name, text) in repeated {
        let compiled = compile_text(name, text.to_string());
        let over: Vec<_> = compiled
            .diagnostics
            .iter()
            .filter(|d| d.message.contains("make more than 100 statements"))
            .collect();
        assert_eq!(over.len(), 1, "{name}: {:?}", compiled.diagnostics);
    }
}
