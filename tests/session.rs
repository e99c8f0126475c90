//! The library's entry point as its callers meet it (`ger::driver`): a
//! program that is not on disk (an editor's buffer, a test's map of
//! files) compiles with its wizards, subroutine files and tool table found
//! through the file-system view, and its tool path names each move's line.

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use ger::driver::discovery::Search;
use ger::driver::fs::{Disk, FileSystem, Memory};
use ger::driver::{CompileOptions, Job, LoadError, OptionError, Program, Session};
use ger::toolpath::MoveKind;
use std::path::Path;

/// A shop's folder, in memory: a program calling a wizard beside it, a
/// LinuxCNC program calling a subroutine file beside it, a tool table.
fn shop() -> Memory<'static> {
    let mut fs = Memory::new();
    fs.insert(
        "/shop/wizards/Square.rhai",
        "//! A square of side `size` from the current point, at its depth.\n\
         //! @param size the side\n\
         let x = pos_x();\n\
         let y = pos_y();\n\
         line(x + size, y);\n\
         line(x + size, y + size);\n\
         line(x, y + size);\n\
         line(x, y);\n",
    );
    fs.insert(
        "/shop/plate.egc",
        "SetUnits \"mm\"\nG0 X0 Y0 Z5\nG1 Z-1 F300\nSquare 10\nG0 Z5\nM30\n",
    );
    fs.insert(
        "/shop/sub.ngc",
        "G21 G90\nG0 X0 Y0 Z5\no<corner> call [3]\nM2\n",
    );
    fs.insert(
        "/shop/corner.ngc",
        "o<corner> sub\nG1 X#1 F100\nG1 Y#1\no<corner> endsub\nM2\n",
    );
    fs.insert("/shop/tools.tbl", "T1 P1 D4 Z0 ;4 mm end mill\n");
    fs
}

// A test helper, not a test: clippy's allowance for tests misses it.
#[allow(clippy::expect_used)]
fn session<'fs>(fs: &'fs dyn FileSystem, search: Search) -> Session<'fs> {
    Session::new(fs, CompileOptions::default(), search).expect("valid options")
}

#[test]
fn a_program_in_memory_finds_its_wizard_beside_it() {
    let fs = shop();
    let mut job = session(&fs, Search::default())
        .load(Program::Path(Path::new("/shop/plate.egc")))
        .unwrap_or_else(|e| panic!("{e}"));
    let outcome = job.outcome();
    let text = outcome.output.expect("compiles");
    assert!(text.contains("X10."), "{text}");
    let path = outcome.tool_path.expect("a tool path");
    // The wizard's four feed moves are each the call's line (4).
    let square: Vec<_> = path
        .moves
        .iter()
        .filter(|m| matches!(m.kind, MoveKind::Feed) && m.start[2] == m.end[2])
        .collect();
    assert_eq!(square.len(), 4);
    for m in &square {
        assert_eq!(job.line_of(m.span), ("/shop/plate.egc", 4));
    }
    let last = square.last().unwrap();
    assert_eq!(last.end, [0.0, 0.0, -1.0]);
    assert_eq!(last.state.feed, 300.0);
}

#[test]
fn a_linuxcnc_program_finds_its_subroutine_file_beside_it() {
    let fs = shop();
    let mut job = session(&fs, Search::default())
        .load(Program::Path(Path::new("/shop/sub.ngc")))
        .unwrap_or_else(|e| panic!("{e}"));
    let outcome = job.outcome();
    assert!(outcome.output.is_some(), "{:?}", outcome.diagnostics);
    let path = outcome.tool_path.unwrap();
    let feeds: Vec<_> = path
        .moves
        .iter()
        .filter(|m| matches!(m.kind, MoveKind::Feed))
        .collect();
    assert_eq!(feeds.len(), 2);
    assert_eq!(feeds[1].end, [3.0, 3.0, 5.0]);
    // The moves are the subroutine file's lines 2 and 3.
    assert_eq!(job.line_of(feeds[0].span), ("/shop/corner.ngc", 2));
    assert_eq!(job.line_of(feeds[1].span), ("/shop/corner.ngc", 3));
}

#[test]
fn an_unsaved_buffer_is_compiled_instead_of_the_file() {
    let disk = shop();
    let mut buffers = Memory::over(&disk);
    buffers.insert(
        "/shop/plate.egc",
        "SetUnits \"mm\"\nG0 X0 Y0 Z5\nG1 Z-1 F300\nSquare 25\nM30\n",
    );
    let mut job = session(&buffers, Search::default())
        .load(Program::Path(Path::new("/shop/plate.egc")))
        .unwrap_or_else(|e| panic!("{e}"));
    let text = job.compile().output.expect("compiles");
    assert!(text.contains("X25."), "{text}");
    // A text given directly, standing for a file of the folder, finds the
    // folder's wizards too.
    let mut job = session(&disk, Search::default())
        .load(Program::Text {
            name: "/shop/unsaved.egc",
            path: Some(Path::new("/shop/unsaved.egc")),
            text: "SetUnits \"mm\"\nG0 X0 Y0 Z1\nG1 Z-1 F300\nSquare 7\nM30\n".into(),
        })
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(job.compile().output.expect("compiles").contains("X7."));
}

#[test]
fn the_tool_table_is_read_through_the_view_and_its_errors_are_at_its_lines() {
    let mut fs = shop();
    let search = Search {
        tool_table: Some("/shop/tools.tbl".into()),
        ..Search::default()
    };
    let job = session(&fs, search.clone())
        .load(Program::Path(Path::new("/shop/plate.egc")))
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(job.options.eval.tools[&1].diameter, 4.0);
    fs.insert("/shop/tools.tbl", "T1 P1 Dx\n");
    match session(&fs, search).load(Program::Path(Path::new("/shop/plate.egc"))) {
        Err(e @ LoadError::ToolTable { .. }) => {
            assert_eq!(e.exit_status(), 1);
            assert!(e.to_string().contains("tools.tbl:1"), "{e}");
        }
        Err(e) => panic!("{e}"),
        Ok(_) => panic!("a bad tool table was read"),
    }
}

#[test]
fn what_cannot_be_read_is_a_load_error_naming_it() {
    let fs = shop();
    let missing = session(&fs, Search::default()).load(Program::Path(Path::new("/shop/none.nc")));
    assert!(
        matches!(&missing, Err(LoadError::Unread(why)) if why.contains("/shop/none.nc")),
        "{:?}",
        missing.err().map(|e| e.to_string())
    );
    let search = Search {
        wizard_dirs: vec!["/elsewhere".into()],
        ..Search::default()
    };
    let folder = session(&fs, search).load(Program::Path(Path::new("/shop/plate.egc")));
    assert!(matches!(&folder, Err(LoadError::Unread(why)) if why.contains("/elsewhere")));
}

#[test]
fn options_no_compile_can_run_with_are_refused_by_the_library() {
    let fs = shop();
    let mut options = CompileOptions::default();
    options.lower.keep_cycles = true;
    let refused = Session::new(&fs, options, Search::default()).err();
    assert_eq!(refused, Some(OptionError::CyclesKeptWithout));
    let mut options = CompileOptions::default();
    options.emit.tolerance = Some(0.0);
    let refused = Session::new(&fs, options, Search::default()).err();
    assert_eq!(refused, Some(OptionError::ToleranceOrDecimals));
    let mut options = CompileOptions::default();
    options.emit.target = ger::emit::Target::LinuxCnc;
    options.lower.keep_comp = true;
    assert!(Session::new(&fs, options, Search::default()).is_ok());
}

/// The binary goes through the same session: its output for a shipped
/// example is the session's on the disk.
#[test]
fn the_binary_writes_what_the_session_compiles() {
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/bolt_flange.egc");
    let mut job = session(&Disk, Search::default())
        .load(Program::Path(&example))
        .unwrap_or_else(|e| panic!("{e}"));
    let ours = job.compile().output.expect("compiles");
    let ger = std::process::Command::new(env!("CARGO_BIN_EXE_ger"))
        .arg("compile")
        .arg(&example)
        .output()
        .unwrap();
    assert!(ger.status.success());
    assert_eq!(String::from_utf8(ger.stdout).unwrap(), ours);
}

/// A Fanuc Macro B program named `.nc`, with no flag: its `WHILE`, `IF`,
/// `G65` and vacant arguments are Fanuc's (SPEC §2.8), so its tool path
/// is the one `--from fanuc` gives.
#[test]
fn a_macro_b_program_needs_no_flag() {
    let mut fs = Memory::new();
    fs.insert(
        "/shop/holes.nc",
        "G21 G90 G17\n\
         #1 = 0\n\
         WHILE [#1 LT 3] DO1\n\
         G65 P9010 X[#1 * 10] Y5.\n\
         #1 = #1 + 1\n\
         END1\n\
         IF [#1 EQ 3] GOTO 20\n\
         G0 X99.\n\
         N20 G4 P500\n\
         M30\n\
         O9010\n\
         IF [#3 NE #0] GOTO 5\n\
         #3 = -2.\n\
         N5 G0 X#24 Y#25 Z5.\n\
         G1 Z#3 F100.\n\
         G0 Z5.\n\
         M99\n",
    );
    let path_with = |options: CompileOptions| {
        let session = Session::new(&fs, options, Search::default()).expect("valid options");
        let mut job = session
            .load(Program::Path(Path::new("/shop/holes.nc")))
            .unwrap_or_else(|e| panic!("{e}"));
        let outcome = job.outcome();
        outcome
            .tool_path
            .unwrap_or_else(|| panic!("{:?}", outcome.diagnostics))
    };
    let fanuc = CompileOptions {
        from: Some(ger::eval::Flavour::Fanuc),
        ..CompileOptions::default()
    };
    let (plain, flagged) = (path_with(CompileOptions::default()), path_with(fanuc));
    let feeds: Vec<_> = plain
        .moves
        .iter()
        .filter(|m| matches!(m.kind, MoveKind::Feed))
        .map(|m| m.end)
        .collect();
    assert_eq!(
        feeds,
        [[0.0, 5.0, -2.0], [10.0, 5.0, -2.0], [20.0, 5.0, -2.0]]
    );
    assert_eq!(plain, flagged);
}

#[test]
fn a_tool_path_fed_from_the_file_in_parts_is_the_whole_programs() {
    // A plain program (read a part at a time) and one whose subprogram
    // comes after its call (read in parts, then again whole: the sink
    // starts over): each planned as the whole path is.
    let dir = std::env::temp_dir().join(format!("ger-session-feed-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let plain = "G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F600\nG1 X10\nG2 X20 Y0 I5 J0\nG1 Y10\nM30\n";
    let late = "G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F600\no100 call [4]\nM2\n\
                o100 sub\nG1 X#1\nG3 X[#1 * 2] Y0 I[#1 / 2] J0\no100 endsub\n";
    let limits = ger::plan::Limits {
        controller: ger::driver::machine::Controller::Grbl,
        max_rate: [50.0; 3],
        max_accel: [200.0; 3],
        rapid_rate: None,
        max_path_rate: f64::INFINITY,
        max_path_accel: f64::INFINITY,
        junction_deviation: 0.01,
        path_tolerance: 0.0,
        arc_tolerance: 0.002,
        blocks: 16,
        tool_change_s: 0.0,
        spindle_start_s: 0.0,
        steps_per_mm: [None; 3],
    };
    for (name, text) in [("plain.nc", plain), ("late.ngc", late)] {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        let s = session(&Disk, Search::default());
        let mut tally = ger::plan::Tally::new(Some(&limits), false);
        let Ok(finished) = s.feed_tool_path(Program::Path(&path), &mut tally) else {
            panic!("{name} not loaded");
        };
        assert!(finished.report.compiled(), "{name}");
        let fed = tally.finish();
        let Ok(mut job) = s.load(Program::Path(&path)) else {
            panic!("{name} not loaded");
        };
        let whole = job.tool_path().0.unwrap();
        let planned = ger::plan::plan(&whole, Some(&limits));
        assert!(fed.time_s.unwrap() > 0.0, "{name}");
        assert_eq!(fed.time_s, planned.time_s, "{name}");
        assert_eq!(fed.cut_mm, planned.cut_mm, "{name}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A sink slower than the compile (as grbl's planner with steps is): it
/// records each move's end and line and each event's place, and sleeps
/// now and then, so that the evaluator fills the batches in flight and
/// waits for the back end (`threads.rs`'s throttle).
#[derive(Default)]
struct SlowSink {
    moves: Vec<([f64; 3], u32)>,
    events: Vec<usize>,
}

impl ger::toolpath::PathSink for SlowSink {
    fn feed_move(&mut self, m: &ger::toolpath::Move) {
        if self.moves.len().is_multiple_of(64) {
            std::thread::sleep(std::time::Duration::from_micros(200));
        }
        self.moves.push((m.end, m.span.line));
    }
    fn feed_event(&mut self, e: &ger::toolpath::Event) {
        self.events.push(e.after_move);
    }
    fn restart(&mut self) {
        *self = SlowSink::default();
    }
    fn heavy(&self) -> bool {
        true
    }
}

#[test]
fn a_sink_slower_than_the_compile_gets_every_move_in_order() {
    // 40,000 moves (about 40 batches) with a dwell every 1,000: the
    // evaluator runs ahead, waits for the back end, goes on; every move and
    // event reaches the sink once, in the program's order, as in the whole
    // path.
    let dir = std::env::temp_dir().join(format!("ger-session-slow-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut text = String::from("G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F600\n");
    for i in 0..40_000 {
        text.push_str(&format!("G1 X{} Y{}\n", i % 397, i % 101));
        if i % 1000 == 999 {
            text.push_str("G4 P0.1\n");
        }
    }
    text.push_str("M30\n");
    let path = dir.join("long.nc");
    std::fs::write(&path, &text).unwrap();
    let s = session(&Disk, Search::default());
    let mut sink = SlowSink::default();
    let Ok(finished) = s.feed_tool_path(Program::Path(&path), &mut sink) else {
        panic!("not loaded");
    };
    assert!(finished.report.compiled());
    let Ok(mut job) = s.load(Program::Path(&path)) else {
        panic!("not loaded");
    };
    let whole = job.tool_path().0.unwrap();
    let expected: Vec<([f64; 3], u32)> = whole.moves.iter().map(|m| (m.end, m.span.line)).collect();
    assert_eq!(sink.moves.len(), 40_002);
    assert!(
        sink.moves == expected,
        "the moves differ from the whole path's"
    );
    let events: Vec<usize> = whole.events.iter().map(|e| e.after_move).collect();
    // The 40 dwells and the program's end.
    assert_eq!(events.len(), 41);
    assert_eq!(sink.events, events);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Each move's kind and end, and each tool's cutter as the picture draws it.
type MovesAndCutters = (
    Vec<(MoveKind, [f64; 3])>,
    Vec<(u32, ger::render::cutter::Cutter)>,
);

/// `f` of the job of `text`, a program in memory called `name`.
fn with_job<R>(name: &str, text: &str, f: impl FnOnce(&mut Job) -> R) -> R {
    let fs = Memory::new();
    let mut job = session(&fs, Search::default())
        .load(Program::Text {
            name,
            path: None,
            text: text.into(),
        })
        .unwrap_or_else(|e| panic!("{e}"));
    f(&mut job)
}

/// The moves of `text` (a program in memory) and its cutters.
fn path_and_cutters(text: &str) -> MovesAndCutters {
    let outcome = with_job("part.egc", text, |job| job.outcome());
    let path = outcome
        .tool_path
        .unwrap_or_else(|| panic!("{:?}", outcome.diagnostics));
    let cutters = ger::render::cutters_by_tool(&path, 1.0, &[]);
    let moves = path.moves.iter().map(|m| (m.kind, m.end)).collect();
    (moves, cutters)
}

#[test]
fn a_tool_set_by_g10_is_the_tool_wizards_and_pictures_see() {
    let program = |tool: &str| {
        format!("{tool}\nG21 G90 G17\nT1 M6\nG0 X50 Y40 Z10\nF400\nPocket 40 30 5 2\nM30\n")
    };
    let cases = [
        ("SetTool 1 6", "G10 L1 P1 R3"),
        ("SetTool 1 6\nG21 G0 Z10", "G21 G0 Z10\nG10 L10 P1 R3 Z0"),
        // Under G20 in a metric program: R is in inches where it is given
        // (not the default tool's 1/4 in).
        ("SetTool 1 3.175", "G21\nG20 G10 L1 P1 R0.0625\nG21"),
    ];
    for (set_tool, g10) in cases {
        let (table_moves, table_cutters) = path_and_cutters(&program(set_tool));
        let (moves, cutters) = path_and_cutters(&program(g10));
        // The pocket's stepover and wall offset follow the diameter.
        assert_eq!(moves.len(), table_moves.len(), "{g10}");
        for (a, b) in moves.iter().zip(&table_moves) {
            assert_eq!(a.0, b.0, "{g10}");
            assert!(
                (0..3).all(|i| (a.1[i] - b.1[i]).abs() < 1e-9),
                "{g10}: {a:?} {b:?}"
            );
        }
        assert_eq!(cutters, table_cutters, "{g10}");
    }
}

#[test]
fn a_length_set_by_g10_alone_makes_the_studio_draw_the_tips_path() {
    let lengths_given = |text: &str| {
        with_job("part.ngc", text, |job| {
            job.tool_path().0.expect("compiles").lengths_given
        })
    };
    let program = |g10: &str| format!("G21 G90\n{g10}\nT1 M6\nG43 H1\nG0 X0 Y0 Z5\nM2\n");
    assert!(lengths_given(&program("G10 L1 P1 Z50")));
    assert!(lengths_given(&program("G0 Z10\nG10 L10 P1 Z0")));
    assert!(!lengths_given(&program("G10 L1 P1 R3")));
}
