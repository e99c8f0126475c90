//! The command line's contract (SPEC §1): exit codes, atomic output that
//! leaves an existing file alone on error, `-o` equal to the input refused,
//! `-` for stdin, deterministic bytes, wizard discovery.

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn ger(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ger"))
        .args(args)
        .current_dir(cwd)
        .env_remove("GER_WIZARDS")
        .output()
        .expect("run ger")
}

/// `ger args` with `input` on its standard input.
fn ger_with_stdin(args: &[&str], cwd: &Path, input: &str) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_ger"))
        .args(args)
        .current_dir(cwd)
        .env_remove("GER_WIZARDS")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run ger");
    let mut stdin = child.stdin.take().expect("its standard input");
    stdin.write_all(input.as_bytes()).expect("write to ger");
    drop(stdin);
    child.wait_with_output().expect("run ger")
}

/// `ger args` with the program read whole: a folder of subroutines (an
/// empty one) is read before the program, which is then not compiled from
/// its file a part at a time.
fn ger_whole(args: &[&str], cwd: &Path) -> Output {
    std::fs::create_dir_all(cwd.join("no-subroutines")).unwrap();
    let mut whole = args.to_vec();
    whole.extend(["--subroutines", "no-subroutines"]);
    ger(&whole, cwd)
}

/// A run that exited with 0 (else its diagnostics are the failure's message).
fn assert_success(r: &Output) {
    assert_eq!(
        r.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&r.stderr)
    );
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ger-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A scratch folder holding `good.egc` and `bad.egc`.
fn scratch_with_programs(name: &str) -> PathBuf {
    let dir = scratch(name);
    std::fs::write(dir.join("good.egc"), GOOD).unwrap();
    std::fs::write(dir.join("bad.egc"), BAD).unwrap();
    dir
}

const GOOD: &str = "G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X10\nM30\n";
const BAD: &str = "G21 G90\nG0 X<Undefined>\n";
/// An error after 20,000 moves: far more output than is held back before
/// it is written to the temporary file.
const BAD_LATE: &str = "G21 G90\nG0 X0 Y0\nIi = 0\nwhile (Ii < 20000) {\n  G0 X<Ii / 10>\n  Ii = Ii + 1\n}\nG0 X<Undefined>\nM30\n";

#[test]
fn exit_codes() {
    let dir = scratch_with_programs("exit");
    assert_eq!(ger(&["check", "good.egc"], &dir).status.code(), Some(0));
    assert_eq!(ger(&["check", "bad.egc"], &dir).status.code(), Some(1));
    assert_eq!(ger(&["check", "missing.egc"], &dir).status.code(), Some(2));
    assert_eq!(
        ger(&["compile", "--stage", "nonsense", "good.egc"], &dir)
            .status
            .code(),
        Some(2)
    );
    assert_eq!(
        ger(&["compile", "--frobnicate", "good.egc"], &dir)
            .status
            .code(),
        Some(2)
    );
}

#[test]
fn output_is_atomic_and_untouched_on_error() {
    let dir = scratch_with_programs("atomic");
    std::fs::write(dir.join("out.nc"), "previous\n").unwrap();
    std::fs::write(dir.join("bad_late.egc"), BAD_LATE).unwrap();
    for bad in ["bad.egc", "bad_late.egc"] {
        let r = ger(&["compile", bad, "-o", "out.nc"], &dir);
        assert_eq!(r.status.code(), Some(1));
        assert_eq!(
            std::fs::read_to_string(dir.join("out.nc")).unwrap(),
            "previous\n"
        );
        // Standard output gets a program only when it is whole.
        let r = ger(&["compile", bad], &dir);
        assert_eq!(r.status.code(), Some(1));
        assert!(r.stdout.is_empty(), "{} bytes on stdout", r.stdout.len());
    }
    let r = ger(&["compile", "good.egc", "-o", "out.nc"], &dir);
    assert_success(&r);
    let written = std::fs::read_to_string(dir.join("out.nc")).unwrap();
    assert!(written.contains("G1 X10."), "{written}");
    // No temporary file is left behind.
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty());
}

/// `-o` naming a FIFO (a machine's pipe) or a device (`/dev/null`): it is
/// opened and sent the program once whole, never replaced by a file (as
/// root, a rename over `/dev/null` would replace the device).
#[cfg(unix)]
#[test]
fn an_output_that_is_not_a_file_is_written_not_replaced() {
    use std::os::unix::fs::FileTypeExt;
    let dir = scratch_with_programs("fifo");
    std::fs::write(dir.join("plain.ngc"), GOOD).unwrap();
    let made = Command::new("mkfifo").arg(dir.join("machine")).status();
    assert!(made.is_ok_and(|s| s.success()), "mkfifo");
    for program in ["good.egc", "plain.ngc"] {
        let fifo = dir.join("machine");
        // The machine's end: opening it waits for ger's.
        let machine = std::thread::spawn(move || std::fs::read_to_string(fifo));
        let r = ger(&["compile", program, "-o", "machine"], &dir);
        assert_success(&r);
        let kind = std::fs::metadata(dir.join("machine")).unwrap().file_type();
        // (Checked before the machine's end is waited for: a FIFO replaced
        // by a file would leave it waiting.)
        assert!(kind.is_fifo(), "{program}: the FIFO was replaced: {kind:?}");
        let got = machine.join().unwrap().unwrap();
        assert_eq!(got.as_bytes(), &ger(&["compile", program], &dir).stdout[..]);
        assert!(got.contains("G1 X10."), "{got}");
    }
}

/// `-o` naming a symbolic link (to the folder a machine reads): the
/// program replaces the link's target, and the link stays; on an error
/// neither changes.
#[cfg(unix)]
#[test]
fn an_output_through_a_link_replaces_the_target_not_the_link() {
    let dir = scratch_with_programs("link");
    std::fs::create_dir_all(dir.join("machine")).unwrap();
    std::fs::write(dir.join("machine/part.nc"), "previous\n").unwrap();
    // A relative link, and a link to it.
    std::os::unix::fs::symlink("machine/part.nc", dir.join("part.nc")).unwrap();
    std::os::unix::fs::symlink("part.nc", dir.join("again.nc")).unwrap();
    let is_link = |name: &str| {
        let meta = std::fs::symlink_metadata(dir.join(name)).unwrap();
        meta.file_type().is_symlink()
    };
    let r = ger(&["compile", "bad.egc", "-o", "again.nc"], &dir);
    assert_eq!(r.status.code(), Some(1));
    let target = std::fs::read_to_string(dir.join("machine/part.nc")).unwrap();
    assert_eq!(target, "previous\n");
    let r = ger(&["compile", "good.egc", "-o", "again.nc"], &dir);
    assert_success(&r);
    assert!(
        is_link("part.nc") && is_link("again.nc"),
        "a link was replaced"
    );
    let target = std::fs::read_to_string(dir.join("machine/part.nc")).unwrap();
    assert_eq!(
        target.as_bytes(),
        &ger(&["compile", "good.egc"], &dir).stdout[..]
    );
    // Links in a loop: an error, and nothing is written.
    std::os::unix::fs::symlink("loop2", dir.join("loop1")).unwrap();
    std::os::unix::fs::symlink("loop1", dir.join("loop2")).unwrap();
    let r = ger(&["compile", "good.egc", "-o", "loop1"], &dir);
    assert_eq!(r.status.code(), Some(2));
    assert!(is_link("loop1") && is_link("loop2"));
}

/// The file `-o` replaces keeps its permissions (a machine's account that
/// may read it still can); a new one gets the usual ones.
#[cfg(unix)]
#[test]
fn a_replaced_output_keeps_its_permissions() {
    use std::os::unix::fs::PermissionsExt;
    let dir = scratch_with_programs("mode");
    let out = dir.join("out.nc");
    std::fs::write(&out, "previous\n").unwrap();
    std::fs::set_permissions(&out, std::fs::Permissions::from_mode(0o640)).unwrap();
    let r = ger(&["compile", "good.egc", "-o", "out.nc"], &dir);
    assert_success(&r);
    let mode = std::fs::metadata(&out).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode, 0o640);
    assert!(std::fs::read_to_string(&out).unwrap().contains("G1 X10."));
}

#[test]
fn output_equal_to_input_is_refused() {
    let dir = scratch("same");
    std::fs::write(dir.join("part.egc"), GOOD).unwrap();
    let r = ger(&["compile", "part.egc", "-o", "./part.egc"], &dir);
    assert_eq!(r.status.code(), Some(2));
    assert_eq!(std::fs::read_to_string(dir.join("part.egc")).unwrap(), GOOD);
}

#[test]
fn stdin_and_determinism() {
    let dir = scratch("stdin");
    let run = || {
        let mut child = Command::new(env!("CARGO_BIN_EXE_ger"))
            .args(["compile", "-"])
            .current_dir(&dir)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .spawn()
            .unwrap();
        child
            .stdin
            .take()
            .unwrap()
            .write_all(GOOD.as_bytes())
            .unwrap();
        child.wait_with_output().unwrap()
    };
    let (a, b) = (run(), run());
    assert_eq!(a.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&a.stdout).contains("G1 X10."));
    assert_eq!(a.stdout, b.stdout, "same input, same bytes");
}

#[test]
fn wizard_search_order() {
    let dir = scratch("wizards");
    let beside = dir.join("wizards");
    let flag = dir.join("flagged");
    std::fs::create_dir_all(&beside).unwrap();
    std::fs::create_dir_all(&flag).unwrap();
    // The same name in two places: `--wizards` wins over `wizards/`, which
    // wins over the standard library's `Pocket`.
    std::fs::write(beside.join("Mark.rhai"), "//! beside\nline_z(-1.0);\n").unwrap();
    std::fs::write(flag.join("Mark.rhai"), "//! flagged\nline_z(-2.0);\n").unwrap();
    std::fs::write(beside.join("Pocket.rhai"), "//! my pocket\nline_z(-3.0);\n").unwrap();
    std::fs::write(beside.join("_helper.rhai"), "fn x() {}\n").unwrap();
    let part = "G21 G90 G0 X0 Y0 Z1\nF100\nMark\nPOCKET\nM30\n";
    std::fs::write(dir.join("part.egc"), part).unwrap();
    let r = ger(&["compile", "--numbers", "none", "part.egc"], &dir);
    let out = String::from_utf8_lossy(&r.stdout);
    assert!(out.contains("G1 Z-1.") && out.contains("G1 Z-3."), "{out}");
    let r = ger(
        &[
            "compile",
            "--numbers",
            "none",
            "--wizards",
            "flagged",
            "part.egc",
        ],
        &dir,
    );
    let out = String::from_utf8_lossy(&r.stdout);
    assert!(out.contains("G1 Z-2.") && !out.contains("Z-1."), "{out}");
    // GER_WIZARDS comes after `wizards/` beside the part.
    let r = Command::new(env!("CARGO_BIN_EXE_ger"))
        .args(["wizards", "mark", "--part", "part.egc"])
        .env("GER_WIZARDS", &flag)
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(String::from_utf8_lossy(&r.stdout).contains("beside"));
    let list = ger(&["wizards", "--part", "part.egc"], &dir);
    let list = String::from_utf8_lossy(&list.stdout);
    assert!(
        list.contains("my pocket") && list.contains("holesLine") && !list.contains("_helper"),
        "{list}"
    );
    assert_eq!(
        ger(&["wizards", "--wizards", "no-such-dir"], &dir)
            .status
            .code(),
        Some(2)
    );
}

#[test]
fn an_unwritable_output_still_shows_the_diagnostics() {
    let dir = scratch_with_programs("unwritable");
    // A program with errors: its diagnostics and exit 1, whatever the file.
    let r = ger(&["compile", "bad.egc", "-o", "missing/out.nc"], &dir);
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("bad.egc:2"), "{stderr}");
    assert!(!stderr.contains("cannot write"), "{stderr}");
    // A good program that cannot be written: exit 2 and why.
    let r = ger(&["compile", "good.egc", "-o", "missing/out.nc"], &dir);
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("cannot write output"), "{stderr}");
}

/// `--tool-table`: LinuxCNC's format fills the table `SetTool` fills (a
/// length folds G43); the program's `SetTool` wins; a wrong line is an
/// error at its line of the table, and nothing is written.
#[test]
fn tool_table() {
    let dir = scratch("tool-table");
    std::fs::write(
        dir.join("tools.tbl"),
        "T1 P1 D6.35 Z75 ;end mill\nT2 P2 D3 Z40\n\nT7 P7 D0 X0 Z10 ; probe\n",
    )
    .unwrap();
    std::fs::write(dir.join("bad.tbl"), "T1 P1 D6.35 Z75\nT2 P2 D3 Q\n").unwrap();
    let program = "G21 G90\nT2 M6\nG43 H2\nG0 X0 Y0 Z10\nM30\n";
    std::fs::write(dir.join("tl.nc"), program).unwrap();
    std::fs::write(dir.join("own.egc"), format!("SetTool 2 3 5\n{program}")).unwrap();
    let out = ger(&["compile", "tl.nc", "--tool-table", "tools.tbl"], &dir);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(text.contains("Z50."), "{text}");
    assert!(!text.contains("G43"), "{text}");
    let out = ger(&["compile", "own.egc", "--tool-table", "tools.tbl"], &dir);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("Z15."), "{text}");
    let out = ger(
        &["compile", "tl.nc", "--tool-table", "bad.tbl", "-o", "x.nc"],
        &dir,
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr.contains("bad.tbl:2:"), "{stderr}");
    assert!(!dir.join("x.nc").exists());
    let out = ger(&["compile", "tl.nc", "--tool-table", "missing.tbl"], &dir);
    assert_eq!(out.status.code(), Some(2));
}

/// `--tool-units` (or `tool_units` in ger.toml): the table is in those
/// units, whatever the program's (a LinuxCNC table is in the machine's);
/// a `SetTool` stays in the output's.
#[test]
fn tool_table_units() {
    let dir = scratch("tool-units");
    std::fs::write(dir.join("inch.tbl"), "T2 P2 D0.125 Z2\n").unwrap();
    let program = "G21 G90\nT2 M6\nG43 H2\nG0 X0 Y0 Z10\nM30\n";
    std::fs::write(dir.join("tl.nc"), program).unwrap();
    std::fs::write(dir.join("own.egc"), format!("SetTool 2 3 5\n{program}")).unwrap();
    let z = |args: &[&str]| {
        let out = ger(args, &dir);
        let text = String::from_utf8_lossy(&out.stdout).into_owned();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        text.lines()
            .find(|l| l.contains("G0"))
            .unwrap_or_default()
            .to_string()
    };
    let table = ["--tool-table", "inch.tbl"];
    // Today's reading without the option: the output's units.
    assert!(z(&[&["compile", "tl.nc"][..], &table].concat()).contains("Z12."));
    let inch = [&["compile", "tl.nc", "--tool-units", "inch"][..], &table].concat();
    assert!(z(&inch).contains("Z60.8"), "{}", z(&inch));
    let own = [&["compile", "own.egc", "--tool-units", "inch"][..], &table].concat();
    assert!(z(&own).contains("Z15."), "{}", z(&own));
    std::fs::write(
        dir.join("ger.toml"),
        "[compile]\ntool-table = \"inch.tbl\"\ntool_units = \"inch\"\n",
    )
    .unwrap();
    assert!(z(&["compile", "tl.nc"]).contains("Z60.8"));
    // The command line wins over the file.
    assert!(z(&["compile", "tl.nc", "--tool-units", "mm"]).contains("Z12."));
}

/// Compensation with a tool ger has no diameter for is an error, and each
/// way out its help names compiles the program: the diameter given, or
/// the compensation left to the controller.
#[test]
fn compensation_with_an_unknown_tool_names_its_ways_out() {
    let dir = scratch("comp-unknown-tool");
    let program = "G21 G90 G17\nF300\nG0 X0 Y0 Z5\nG41 D7 G1 X20 Y0\nG1 X40\nG40 G1 X60 Y0\nM30\n";
    std::fs::write(dir.join("comp.nc"), program).unwrap();
    std::fs::write(dir.join("tools.tbl"), "T7 P7 D6 Z0\n").unwrap();
    let out = ger(&["compile", "comp.nc", "-o", "x.nc"], &dir);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("tool 7 is not in the tool table"),
        "{stderr}"
    );
    for way in [
        "`SetTool 7 diameter`",
        "--tool-table",
        "--comp keep --target fanuc or linuxcnc",
    ] {
        assert!(stderr.contains(way), "{way}: {stderr}");
    }
    assert!(!dir.join("x.nc").exists());
    // The diameter given: the tool centre is 3 mm to the left of the path.
    let out = ger(&["compile", "comp.nc", "--tool-table", "tools.tbl"], &dir);
    assert_success(&out);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(!text.contains("G41"), "{text}");
    assert!(text.contains("Y3."), "{text}");
    // Left to the controller: G41 D7 written as it was.
    for target in ["linuxcnc", "fanuc"] {
        let out = ger(
            &["compile", "comp.nc", "--comp", "keep", "--target", target],
            &dir,
        );
        assert_success(&out);
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(text.contains("G41 D7"), "{target}: {text}");
    }
}

#[test]
fn subroutine_folders() {
    // `o<name> call` reads name.ngc from --subroutines, then beside the
    // program; a folder that is not there is a usage error.
    let dir = scratch("subroutines");
    std::fs::create_dir_all(dir.join("lib")).unwrap();
    std::fs::write(
        dir.join("main.ngc"),
        "G21 G90\nG0 X0 Y0 Z1\no<edge> call [7]\nM2\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("lib/edge.ngc"),
        "o<edge> sub\nG1 X#1 F100\no<edge> endsub\nM2\n",
    )
    .unwrap();
    let out = ger(&["compile", "main.ngc"], &dir);
    assert_eq!(out.status.code(), Some(1), "not beside the program");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("no subprogram o<edge>"), "{stderr}");
    let out = ger(&["compile", "main.ngc", "--subroutines", "lib"], &dir);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(String::from_utf8_lossy(&out.stdout).contains("G1 X7. F100."));
    let out = ger(&["compile", "main.ngc", "--subroutines", "nowhere"], &dir);
    assert_eq!(out.status.code(), Some(2));
}

/// A plain program written to a file or to standard output, or checked,
/// is compiled from the file a part at a time (its text is not held): the
/// same bytes and warnings as from a whole read, its warnings shown with
/// their lines (read again for them), and a syntax error far into it
/// leaves the existing output alone and standard output empty. That this
/// path is the one taken shows only in memory; `tests/streaming.rs`
/// compiles from a reader directly.
#[test]
fn a_plain_program_compiled_to_a_file_is_read_in_parts() {
    let dir = scratch("plain-parts");
    let mut text = String::from("G21 G90 G17\nM100\nG0 X0 Y0 Z2\nG1 Z-1 F300\n");
    for i in 0..30_000 {
        text.push_str(&format!(
            "G1 X{:.3} Y{:.3} (pass {i})\n",
            i as f64 * 0.01,
            (i % 7) as f64
        ));
    }
    text.push_str("G0 Z5\nM30\n");
    std::fs::write(dir.join("long.ngc"), &text).unwrap();
    let whole = ger_whole(&["compile", "long.ngc"], &dir);
    assert!(whole.stdout.len() > 500_000, "{}", whole.stdout.len());
    let to_stdout = ger(&["compile", "long.ngc"], &dir);
    assert_eq!(to_stdout.stdout, whole.stdout);
    // No temporary file to be had: held in memory instead.
    let no_tmp = Command::new(env!("CARGO_BIN_EXE_ger"))
        .args(["compile", "long.ngc"])
        .current_dir(&dir)
        .env("TMPDIR", dir.join("missing"))
        .output()
        .unwrap();
    assert_eq!(no_tmp.status.code(), Some(0));
    assert_eq!(no_tmp.stdout, whole.stdout);
    let to_file = ger(&["compile", "long.ngc", "-o", "long.out"], &dir);
    assert_eq!(to_file.status.code(), Some(0));
    assert_eq!(std::fs::read(dir.join("long.out")).unwrap(), whole.stdout);
    let warned = String::from_utf8_lossy(&to_file.stderr);
    assert!(
        warned.contains("M100 is passed through") && warned.contains("2 │ M100"),
        "{warned}"
    );
    for other in [&whole, &to_stdout, &ger(&["check", "long.ngc"], &dir)] {
        assert_eq!(warned, String::from_utf8_lossy(&other.stderr));
    }
    // A number with two points near the end: an error at its line, and
    // the output of the earlier run stays.
    let broken = text.replace("X299.900", "X299.9.0");
    std::fs::write(dir.join("long.ngc"), broken).unwrap();
    let failed = ger(&["compile", "long.ngc", "-o", "long.out"], &dir);
    assert_eq!(failed.status.code(), Some(1));
    let said = String::from_utf8_lossy(&failed.stderr);
    assert!(said.contains("long.ngc:29995:4"), "{said}");
    assert_eq!(std::fs::read(dir.join("long.out")).unwrap(), whole.stdout);
    for failed in [
        ger(&["compile", "long.ngc"], &dir),
        ger(&["check", "long.ngc"], &dir),
    ] {
        assert_eq!(failed.status.code(), Some(1));
        assert!(failed.stdout.is_empty(), "{} bytes", failed.stdout.len());
        assert_eq!(String::from_utf8_lossy(&failed.stderr), said);
    }
}

/// A file is read once: its first lines (about 256 KB) say how its
/// numbers are printed, and each part after them is checked as it is read
/// (`driver::first_look`). One found otherwise far into it (a number
/// with more decimals, in a word or a comment, a lone CR, a control
/// character) is scanned whole and compiled again: the same bytes, the
/// same diagnostics and exit code as a whole read, said once.
#[test]
fn a_file_not_as_its_first_lines_said_is_compiled_again() {
    let dir = scratch("first-look");
    let mut text = String::from("G21 G90 G17\nM100\nG0 X0 Y0 Z2\nG1 Z-1 F300\n");
    for i in 0..30_000 {
        let x = i as f64 * 0.01;
        text.push_str(&format!("G1 X{x:.3} Y{:.3}\n", (i % 7) as f64));
    }
    text.push_str("G0 Z5\nM30\n");
    assert!(text.len() > 2 * (1 << 18), "{}", text.len());
    // Line 29,005 of 30,006.
    let late = |line: &str| {
        assert!(text.contains("\nG1 X290.000 Y6.000\n"));
        text.replacen("\nG1 X290.000 Y6.000\n", line, 1)
    };
    let cases = [
        ("as_its_start.ngc", text.clone(), "X290. Y6."),
        (
            "decimals.ngc",
            late("\nG1 X290.12345 Y6\n"),
            "X290.12345 Y6.",
        ),
        (
            "comment.ngc",
            late("\nG1 X290 Y6 (X0.1234567)\n"),
            "X290. Y6.",
        ),
        ("lone_cr.ngc", late("\nG1 X290\rY6.00001\n"), "Y6.00001"),
        ("control.ngc", late("\nG1 X290 Y6 \u{1}\n"), ""),
    ];
    for (name, text, printed) in cases {
        std::fs::write(dir.join(name), &text).unwrap();
        let whole = ger_whole(&["compile", name], &dir);
        let shown = String::from_utf8_lossy(&whole.stdout);
        assert!(shown.contains(printed), "{name}: {printed}");
        std::fs::remove_file(dir.join("out.nc")).ok();
        let to_file = ger(&["compile", name, "-o", "out.nc"], &dir);
        let written = std::fs::read(dir.join("out.nc")).unwrap_or_default();
        assert!(written == whole.stdout, "{name}");
        let to_stdout = ger(&["compile", name], &dir);
        assert!(to_stdout.stdout == whole.stdout, "{name}");
        for other in [&to_file, &to_stdout, &ger(&["check", name], &dir)] {
            assert_eq!(other.status.code(), whole.status.code(), "{name}");
            assert_eq!(
                String::from_utf8_lossy(&other.stderr),
                String::from_utf8_lossy(&whole.stderr),
                "{name}"
            );
        }
    }
}

/// An output of megabytes, its writeback started while it is written (each
/// 256 KB), or held aside for standard output: what a whole read gives.
#[test]
fn a_long_output_written_to_a_file_is_whole() {
    let dir = scratch("long-output");
    let egc = "G21 G90 G17\nG0 X0 Y0 Z2\nG1 Z-1 F300\nIi = 0\n\
               while (Ii < 120000) {\n  G1 X<Ii % 997 * 0.013> Y<Ii % 89 * 0.7>\n  Ii = Ii + 1\n}\n\
               G0 Z5\nM30\n";
    std::fs::write(dir.join("long.egc"), egc).unwrap();
    let whole = ger_whole(&["compile", "long.egc"], &dir);
    assert_eq!(whole.status.code(), Some(0));
    assert!(whole.stdout.len() > 2 << 20, "{}", whole.stdout.len());
    let to_file = ger(&["compile", "long.egc", "-o", "long.nc"], &dir);
    assert_eq!(to_file.status.code(), Some(0));
    assert!(std::fs::read(dir.join("long.nc")).unwrap() == whole.stdout);
    let to_stdout = ger(&["compile", "long.egc"], &dir);
    assert!(to_stdout.stdout == whole.stdout);
}

/// Any program written to a file or to standard output is compiled from
/// its file a part at a time, a loop body or an `if` in one part, a
/// subroutine kept for the parts after it; one whose last part needs the
/// whole program (it calls a subroutine written after the call) is compiled
/// whole instead, from the start: the output and the diagnostics are those
/// of a whole read, said once.
#[test]
fn any_program_compiled_to_a_file_is_read_in_parts_or_whole() {
    let dir = scratch("any-parts");
    let mut egc = String::from("G21 G90 G17\nM100\nG0 X0 Y0 Z2\nG1 Z-1 F300\nIi = 0\n");
    let sub = "o<peck> sub\nG1 Z-1 F100\n(up)\nG0 Z2\no<peck> endsub\n";
    let mut ngc = String::from("G21 G90 G17\nM100\n");
    for i in 0..3_000 {
        egc.push_str(&format!(
            "while (Ii < {}) {{\n  G1 X<Ii * 0.01> Y{}\n  Ii = Ii + 1\n}}\n",
            (i + 1) * 3,
            i % 7
        ));
        egc.push_str(&format!(
            "if (Ii % 2 == 0) {{\n  G1 Z-1.5\n}} else {{\n  G1 Z-1\n}}\nG1 X{i}.5 (pass {i})\n"
        ));
        ngc.push_str(&format!(
            "#1 = {i}\nG0 X[#1 * 0.1] Y{}\no<peck> call\n",
            i % 7
        ));
    }
    egc.push_str("G0 Z5\nM30\n");
    ngc.push_str("G0 Z5\nM2\n");
    std::fs::write(dir.join("long.egc"), &egc).unwrap();
    let kept = ngc.replacen("M100\n", &format!("M100\n{sub}"), 1);
    std::fs::write(dir.join("kept.ngc"), kept).unwrap();
    // Called once, at the end, before the subroutine is written more than
    // a part (16 KB) further on: found out in the last part run, after
    // most of the output.
    let later = ngc
        .replace("o<peck> call\n", "")
        .replace("M2\n", "o<peck> call\nM2\n");
    let notes = "(the subroutine, written after the end of the program)\n".repeat(2_000);
    std::fs::write(dir.join("later.ngc"), later + notes.as_str() + sub).unwrap();
    for name in ["long.egc", "kept.ngc", "later.ngc"] {
        let whole = ger_whole(&["compile", name], &dir);
        assert_eq!(whole.status.code(), Some(0), "{name}");
        let to_file = ger(&["compile", name, "-o", "long.out"], &dir);
        assert_eq!(to_file.status.code(), Some(0), "{name}");
        assert_eq!(
            std::fs::read(dir.join("long.out")).unwrap(),
            whole.stdout,
            "{name}"
        );
        let to_stdout = ger(&["compile", name], &dir);
        assert_eq!(to_stdout.stdout, whole.stdout, "{name}");
        let warned = String::from_utf8_lossy(&to_file.stderr);
        assert_eq!(
            warned.matches("M100 is passed through").count(),
            1,
            "{name}: {warned}"
        );
        for other in [&whole, &to_stdout, &ger(&["check", name], &dir)] {
            assert_eq!(warned, String::from_utf8_lossy(&other.stderr), "{name}");
        }
    }
}

/// A named pipe is read once: `-o` compiles it whole (reading a pipe a
/// second time would find nothing, or wait for ever).
#[test]
fn a_pipe_is_read_once() {
    let dir = scratch("fifo");
    let fifo = dir.join("part.ngc");
    let made = Command::new("mkfifo").arg(&fifo).status();
    if !made.is_ok_and(|s| s.success()) {
        eprintln!("no mkfifo here: skipped");
        return;
    }
    let writer = {
        let fifo = fifo.clone();
        std::thread::spawn(move || {
            // Blocks until ger opens the pipe; one program, then the end.
            let mut pipe = std::fs::OpenOptions::new().write(true).open(fifo).unwrap();
            pipe.write_all(GOOD.as_bytes()).unwrap();
        })
    };
    let mut child = Command::new(env!("CARGO_BIN_EXE_ger"))
        .args(["compile", "part.ngc", "-o", "part.out"])
        .current_dir(&dir)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let started = std::time::Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if started.elapsed() > std::time::Duration::from_secs(30) {
            let _ = child.kill();
            panic!("ger waited for a second read of the pipe");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    };
    writer.join().unwrap();
    assert!(status.success());
    let out = std::fs::read_to_string(dir.join("part.out")).unwrap();
    assert!(out.contains("G1 X10.") && out.contains("M30"), "{out}");
}

/// Under valgrind (which gives a program no vDSO it can read): a compile
/// on two threads runs as it runs without it, to the same bytes. rustix's
/// own vDSO reader, used for the processor a thread is on
/// (`driver::this_cpu`), read past valgrind's mapping and the process
/// died of SIGSEGV; through the C library it does not. Skipped where
/// valgrind is not installed, unless `GER_REQUIRE_VALGRIND=1` (CI).
#[test]
fn a_two_thread_compile_runs_under_valgrind() {
    let present = Command::new("valgrind")
        .arg("--version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !present {
        let required = std::env::var("GER_REQUIRE_VALGRIND").is_ok_and(|v| v == "1");
        assert!(
            !required,
            "valgrind is not installed: `apt-get install valgrind`, then run the tests again"
        );
        eprintln!("skipped: valgrind is not installed");
        return;
    }
    let dir = scratch("valgrind");
    // Enough moves for several batches, so the back end's thread runs.
    let mut program = String::from("G21 G90 G17\nG0 X0 Y0 Z5\nG1 Z-1 F800\n");
    for i in 0..6000 {
        program.push_str(&format!("G1 X{}.5 Y{}\n", i % 97, i % 31));
    }
    program.push_str("M30\n");
    std::fs::write(dir.join("many.ngc"), &program).unwrap();
    let plain = ger(&["compile", "many.ngc", "-o", "plain.nc"], &dir);
    assert_success(&plain);
    let under = Command::new("valgrind")
        .args(["--tool=none", "--quiet", env!("CARGO_BIN_EXE_ger")])
        .args(["compile", "many.ngc", "-o", "valgrind.nc"])
        .current_dir(&dir)
        .env_remove("GER_WIZARDS")
        .output()
        .expect("run valgrind");
    assert_success(&under);
    let (a, b) = (
        std::fs::read(dir.join("plain.nc")).unwrap(),
        std::fs::read(dir.join("valgrind.nc")).unwrap(),
    );
    assert!(a.len() > 6000 * 8, "{} bytes", a.len());
    assert_eq!(a, b, "the same bytes under valgrind");
}

/// `-o -` is standard output, as `-` is standard input: the program comes
/// out there and no file named `-` is made.
#[test]
fn dash_output_is_standard_output() {
    let dir = scratch("dash_output");
    std::fs::write(dir.join("good.egc"), GOOD).unwrap();
    let to_dash = ger(&["compile", "good.egc", "-o", "-"], &dir);
    assert_success(&to_dash);
    let plain = ger(&["compile", "good.egc"], &dir);
    assert!(String::from_utf8_lossy(&to_dash.stdout).contains("G1 X10."));
    assert_eq!(to_dash.stdout, plain.stdout);
    assert!(!dir.join("-").exists(), "a file named `-` was made");
}

/// `ger.toml` found from the program's folder upward: its `[compile]`
/// options apply, a flag on the command line wins, and a wrong value is an
/// error at its line (exit 2) before anything is compiled.
#[test]
fn the_project_file_gives_options_and_flags_win() {
    let dir = scratch("project");
    std::fs::create_dir_all(dir.join("jobs")).unwrap();
    std::fs::write(
        dir.join("ger.toml"),
        "[compile]\nnumbers = \"none\"\narcs = \"r\"\n",
    )
    .unwrap();
    let program = "G21 G90\nG0 X0 Y0\nG1 X10 F100\nG2 X20 Y0 I5 J0\nM30\n";
    std::fs::write(dir.join("jobs/a.nc"), program).unwrap();
    let r = ger(&["compile", "jobs/a.nc"], &dir);
    assert_success(&r);
    let text = String::from_utf8(r.stdout).unwrap();
    assert!(text.contains("\nG2 X20. Y0. R5.\n"), "{text}");
    let r = ger(&["compile", "jobs/a.nc", "--arcs", "ij"], &dir);
    assert_success(&r);
    let text = String::from_utf8(r.stdout).unwrap();
    assert!(text.contains("\nG2 X20. Y0. I5. J0.\n"), "{text}");

    std::fs::write(dir.join("ger.toml"), "[compile]\n\ncycles = \"maybe\"\n").unwrap();
    std::fs::write(dir.join("jobs/out.nc"), "old").unwrap();
    let r = ger(&["compile", "jobs/a.nc", "-o", "jobs/out.nc"], &dir);
    assert_eq!(r.status.code(), Some(2));
    let stderr = String::from_utf8(r.stderr).unwrap();
    assert!(stderr.contains("ger.toml:3:10"), "{stderr}");
    assert_eq!(
        std::fs::read_to_string(dir.join("jobs/out.nc")).unwrap(),
        "old"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `ger machine import`: a grbl `$$` dump on standard input becomes a
/// `[machine]` table; a file of neither kind is refused.
#[test]
fn machine_import_reads_a_grbl_dump() {
    let dir = scratch("machine-import");
    let mut child = Command::new(env!("CARGO_BIN_EXE_ger"))
        .args(["machine", "import", "-"])
        .current_dir(&dir)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let dump = "$11=0.010\n$12=0.002\n$110=5000.000\n$120=250.000\n$132=80.000\nok\n";
    child
        .stdin
        .take()
        .unwrap()
        .write_all(dump.as_bytes())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    assert_success(&out);
    let table = String::from_utf8(out.stdout).unwrap();
    assert!(
        table.starts_with("[machine]\ncontroller = \"grbl\"\n"),
        "{table}"
    );
    assert!(table.contains("junction-deviation = 0.01\n"), "{table}");
    assert!(
        table.contains("[machine.z]\nmin = -80.0\nmax = 0.0\n"),
        "{table}"
    );
    std::fs::write(dir.join("notes.txt"), "hello\n").unwrap();
    let r = ger(&["machine", "import", "notes.txt"], &dir);
    assert_eq!(r.status.code(), Some(2));
    let _ = std::fs::remove_dir_all(&dir);
}

/// `cycles = "keep"` or `comp = "keep"` in ger.toml with a target that
/// cannot keep them is an error at its line of the file; a target on the
/// command line that can, or a flag that overrides the key, makes it fine.
#[test]
fn kept_cycles_or_comp_without_a_target_that_keeps_them_is_wrong_at_its_line() {
    let dir = scratch("kept");
    std::fs::write(dir.join("p.nc"), "G21 G90\nG0 X0 Y0\nM30\n").unwrap();
    for (table, key) in [
        (
            "target = \"grbl\"\ncycles = \"keep\"\n",
            "3 │ cycles = \"keep\"",
        ),
        ("comp = \"keep\"\n", "2 │ comp = \"keep\""),
    ] {
        std::fs::write(dir.join("ger.toml"), format!("[compile]\n{table}")).unwrap();
        let r = ger(&["compile", "p.nc"], &dir);
        assert_eq!(r.status.code(), Some(2), "{table}");
        let stderr = String::from_utf8_lossy(&r.stderr);
        assert!(
            stderr.contains("ger.toml:") && stderr.contains(key),
            "{stderr}"
        );
        assert_success(&ger(&["compile", "p.nc", "--target", "fanuc"], &dir));
    }
    assert_success(&ger(&["compile", "p.nc", "--comp", "resolve"], &dir));
    let _ = std::fs::remove_dir_all(&dir);
}

/// `ger stats`: without a machine, length / feed only (no planned time);
/// with ger.toml's `[machine]`, the planned time, longer than length /
/// feed on a slow machine; `--json` one object with the documented keys.
#[test]
fn stats_plans_on_the_machine_of_the_project_file() {
    let dir = scratch("stats");
    let program = "G21 G90\nT1 M6\nS1000 M3\nG0 X0 Y0 Z5\nG1 Z-1 F600\n\
                   G1 X100 F6000\nY100\nX0\nY0\nG0 Z5\nM30\n";
    std::fs::write(dir.join("p.nc"), program).unwrap();
    let r = ger(&["stats", "p.nc", "--json"], &dir);
    assert_success(&r);
    let out = String::from_utf8(r.stdout).unwrap();
    assert!(out.contains("\"time_s\":null"), "{out}");
    assert!(out.contains("\"feed_time_s\":4.6"), "{out}"); // 6 mm at 10 mm/s + 400 at 100
    assert!(out.contains("\"cut_mm\":406"), "{out}");
    assert!(out.contains("\"tools\":[{"), "{out}");
    std::fs::write(
        dir.join("ger.toml"),
        "[machine]\ncontroller = \"grbl\"\nunits = \"mm\"\n\
         [machine.x]\nmax-velocity = 6000\nmax-acceleration = 50\n\
         [machine.y]\nmax-velocity = 6000\nmax-acceleration = 50\n\
         [machine.z]\nmax-velocity = 600\nmax-acceleration = 50\n",
    )
    .unwrap();
    let r = ger(&["stats", "p.nc", "--json"], &dir);
    assert_success(&r);
    let out = String::from_utf8(r.stdout).unwrap();
    let planned = |key: &str| -> f64 {
        let at = out.find(&format!("\"{key}\":")).unwrap() + key.len() + 3;
        let end = out[at..].find([',', '}']).unwrap();
        out[at..at + end].parse().unwrap()
    };
    // At 50 mm/s² each 100 mm side stops at its corner (100 mm/s needs
    // 100 mm to reach): 4 triangles of 2·√(50·100)/50 = 2.83 s at least.
    assert!(planned("time_s") > planned("feed_time_s") + 6.0, "{out}");
    assert!(out.contains("\"planned_on\":\"grbl\""), "{out}");
    let r = ger(&["stats", "p.nc"], &dir);
    assert_success(&r);
    let table = String::from_utf8(r.stdout).unwrap();
    assert!(table.starts_with("run time "), "{table}");
    assert!(table.contains("planned as grbl plans it"), "{table}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `ger stats`' bounds are where the tip cuts: a tool length the program
/// gives (`G10 L1`) and `G43` fold into the moves (the machine's
/// controlled point, 50 mm above the tip), read from a file and from
/// standard input alike.
#[test]
fn stats_bounds_are_the_tips_where_tool_lengths_are_folded_in() {
    let dir = scratch("stats_tip");
    let program = "G21 G90 G17\nG10 L1 P1 R3 Z50\nT1 M6\nG43 H1\nG0 X0 Y0 Z5\n\
                   G1 Z-5 F300\nG1 X10\nG49\nM30\n";
    std::fs::write(dir.join("p.nc"), program).unwrap();
    let from_file = ger(&["stats", "p.nc", "--json"], &dir);
    assert_success(&from_file);
    let from_stdin = ger_with_stdin(&["stats", "-", "--json"], &dir, program);
    assert_success(&from_stdin);
    for r in [from_file, from_stdin] {
        let out = String::from_utf8(r.stdout).unwrap();
        assert!(
            out.contains("\"bounds\":[[0.0,0.0,-5.0],[10.0,0.0,5.0]]"),
            "{out}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Travel limits (`[machine.x] min`/`max`): a move past them where the
/// machine position is known (a `G53` move, or G54's origin set by the
/// program) is an error at its line naming the axis and by how much, in
/// `check` and `compile`; where G54's origin is the machine's, one
/// warning says where it must lie (X: −300 … 0 minus the program's 0 …
/// 120 and its arc's bulge to 130).
#[test]
fn moves_past_the_machine_travel_are_errors_where_the_offset_is_known() {
    let dir = scratch("travel");
    std::fs::write(
        dir.join("ger.toml"),
        "[machine]\ncontroller = \"linuxcnc\"\nunits = \"mm\"\n\
         [machine.x]\nmin = -300\nmax = 0\n[machine.z]\nmin = -100\nmax = 0\n",
    )
    .unwrap();
    let unknown = "G21 G90 G17\nG0 X0 Y0 Z5\nG1 X120 F500\nG3 X120 Y20 I0 J10\nM30\n";
    std::fs::write(dir.join("unknown.nc"), unknown).unwrap();
    let r = ger(&["compile", "unknown.nc"], &dir);
    assert_success(&r);
    let warned = String::from_utf8_lossy(&r.stderr);
    assert!(
        warned.contains("warning: travel limits checked only where"),
        "{warned}"
    );
    assert!(warned.contains("X -300.000 … -130.000"), "{warned}");
    assert!(warned.contains("Z -105.000 … -5.000"), "{warned}");
    // G54 at X-200 Z-50: X reaches -200 + 130 = -70, fine; Z5 is -45.
    // At X-100 the arc's bulge passes X0 by 30 mm; G53 Z10 by 10 mm.
    let known = "G21 G90 G17\nG10 L2 P1 X-100 Y0 Z-50\nG0 X0 Y0 Z5\nG1 X120 F500\n\
                 G3 X120 Y20 I0 J10\nG53 G0 Z10\nM30\n";
    std::fs::write(dir.join("known.nc"), known).unwrap();
    for command in ["compile", "check"] {
        let r = ger(&[command, "known.nc"], &dir);
        assert_eq!(r.status.code(), Some(1), "{command}");
        let stderr = String::from_utf8_lossy(&r.stderr);
        assert!(
            stderr.contains("error: X leaves the machine's travel by 30.000 mm")
                && stderr.contains("4 │ G1 X120 F500"),
            "{stderr}"
        );
        assert!(
            stderr.contains("2 moves go past it, the furthest by 30.000 mm"),
            "{stderr}"
        );
        assert!(
            stderr.contains("error: Z leaves the machine's travel by 10.000 mm")
                && stderr.contains("6 │ G53 G0 Z10"),
            "{stderr}"
        );
        assert!(!stderr.contains("warning: travel"), "{stderr}");
    }
    let inside = known
        .replace("X-100", "X-200")
        .replace("G53 G0 Z10", "G53 G0 Z0");
    std::fs::write(dir.join("inside.nc"), inside).unwrap();
    let r = ger(&["check", "inside.nc"], &dir);
    assert_success(&r);
    assert!(
        r.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&r.stderr)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A travel of X and Y only (−300 … 0 mm each), in `ger.toml` of `dir`.
fn travel_xy(dir: &Path) {
    std::fs::write(
        dir.join("ger.toml"),
        "[machine]\ncontroller = \"grbl\"\nunits = \"mm\"\n\
         [machine.x]\nmin = -300\nmax = 0\n[machine.y]\nmin = -300\nmax = 0\n\
         [machine.z]\nmin = -100\nmax = 0\n",
    )
    .unwrap();
}

/// An arc's bulge counts when only its plane's axes are known: a laser's
/// program that never sets Z. Its circle about (100, 0) spans X 0 … 200,
/// Y −100 … 100; with G54 at X−150 Y−150 it passes X's maximum by 250 and
/// both ends of Y by 50.
#[test]
fn an_arcs_bulge_is_checked_without_a_z() {
    let dir = scratch("travel_no_z");
    travel_xy(&dir);
    let laser = "G21 G90 G17\nG0 X0 Y0\nM4 S1000\nG2 X0 Y0 I100 J0 F1000\nM5\nM30\n";
    std::fs::write(dir.join("laser.nc"), laser).unwrap();
    let r = ger(&["check", "laser.nc"], &dir);
    assert_success(&r);
    let warned = String::from_utf8_lossy(&r.stderr);
    assert!(
        warned.contains("X -300.000 … -200.000, Y -200.000 … -100.000 mm"),
        "{warned}"
    );
    let known = "G21 G90 G17\nG10 L2 P1 X-150 Y-150 Z-50\nG54\nG0 X0 Y0\n\
                 G2 X0 Y0 I200 J0 F100\nM30\n";
    std::fs::write(dir.join("known.nc"), known).unwrap();
    let r = ger(&["check", "known.nc"], &dir);
    assert_eq!(r.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert!(
        stderr.contains("error: X leaves the machine's travel by 250.000 mm"),
        "{stderr}"
    );
    assert_eq!(
        stderr
            .matches("error: Y leaves the machine's travel by 50.000 mm")
            .count(),
        2,
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// G28/G30 go to their intermediate point first, a move like any other:
/// with G54's Z at −50, `G28 Z80` passes Z's maximum (0) by 30 mm, and so
/// does `G91 G28 Z80` from Z0. The home itself is the machine's.
#[test]
fn a_homes_intermediate_point_is_checked_against_the_travel() {
    let dir = scratch("travel_home");
    travel_xy(&dir);
    let start = "G21 G90 G17\nG10 L2 P1 X-150 Y-150 Z-50\nG54\nG0 X0 Y0 Z0\n";
    for (name, home) in [
        ("g28", "G28 Z80"),
        ("g91", "G91 G28 Z80\nG90"),
        ("g30", "G30 Z80"),
    ] {
        let program = format!("{start}{home}\nM30\n");
        std::fs::write(dir.join(format!("{name}.nc")), program).unwrap();
        let r = ger(&["check", &format!("{name}.nc")], &dir);
        assert_eq!(r.status.code(), Some(1), "{name}");
        let stderr = String::from_utf8_lossy(&r.stderr);
        assert!(
            stderr.contains("error: Z leaves the machine's travel by 30.000 mm")
                && stderr.contains("5 │ G"),
            "{stderr}"
        );
    }
    let inside = format!("{start}G28 Z20\nM30\n");
    std::fs::write(dir.join("inside.nc"), inside).unwrap();
    let r = ger(&["check", "inside.nc"], &dir);
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert!(!stderr.contains("travel"), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// An F before the program's first G20/G21 is in the machine's units
/// (LinuxCNC sets F before G20/G21 of its line). grbl converts a block's F
/// by that block's G20/G21: the F goes on a line of its own before the
/// G20, where every controller reads it in the units before it.
#[test]
fn a_feed_before_the_first_units_has_a_line_of_its_own() {
    let dir = scratch("feed_before_units");
    std::fs::write(dir.join("p.nc"), "G20 G90 G1 X1 F60\nM30\n").unwrap();
    for target in ["grbl", "linuxcnc", "fanuc", "generic"] {
        let r = ger(&["compile", "--target", target, "p.nc"], &dir);
        assert_success(&r);
        let text = String::from_utf8(r.stdout).unwrap();
        let lines: Vec<Vec<&str>> = text
            .lines()
            .map(|line| line.split(' ').filter(|w| !w.starts_with('N')).collect())
            .collect();
        let feed = lines.iter().position(|l| l == &["F60."]);
        let units = lines.iter().position(|l| l == &["G20"]);
        assert!(
            feed.is_some() && feed.map(|f| f + 1) == units,
            "{target}:\n{text}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every list in `--help` is complete (issue 48): the stages, targets and
/// standard wizards the help names are the library's registries.
#[test]
fn the_help_lists_every_stage_target_and_wizard() {
    let dir = std::env::temp_dir();
    let text = |args: &[&str]| {
        let out = ger(args, &dir);
        assert!(out.status.success(), "{args:?}");
        String::from_utf8(out.stdout).unwrap()
    };
    let compile = text(&["compile", "--help"]);
    let stage_line = compile
        .lines()
        .find(|l| l.contains("after this stage"))
        .unwrap();
    for stage in ger::driver::Stage::names() {
        assert!(
            stage_line.contains(stage),
            "--stage {stage} missing: {stage_line}"
        );
    }
    for (_, target) in ger::emit::Target::ALL {
        assert!(compile.contains(target), "--target {target} missing");
    }
    let wizards = text(&["wizards", "--help"]);
    for wizard in ger::wizard::standard_library() {
        assert!(
            wizards.contains(&wizard.name),
            "wizard {} missing",
            wizard.name
        );
    }
}

/// `numbers = "keep"` in `ger.toml`: the program's own N words stay
/// (`N160` is not renumbered by its source line), and a line without one
/// gets none.
#[test]
fn the_project_file_keeps_the_programs_numbers() {
    let dir = scratch("project_numbers");
    std::fs::write(dir.join("ger.toml"), "[compile]\nnumbers = \"keep\"\n").unwrap();
    let program = "N10 G21 G90\nN160 G0 X1 Y0\nG1 X10 F100\nN170 M30\n";
    std::fs::write(dir.join("a.nc"), program).unwrap();
    let r = ger(&["compile", "a.nc"], &dir);
    assert_success(&r);
    let text = String::from_utf8(r.stdout).unwrap();
    assert!(
        text.contains("\nN160 G0 X1. Y0.\nG1 X10. F100.\nN170 M30\n"),
        "{text}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
