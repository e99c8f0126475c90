//! The differential harness checks itself: pairs of programs that move
//! the tool the same way must compare equal, and pairs that differ by one
//! thing must be told apart, with that thing named. Written by hand from
//! the G-code meaning (LinuxCNC's manual), not from the harness's output.

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use ger::toolpath::compare::Options;
use libtest_mimic::{Arguments, Failed, Trial};

mod support;
use support::rs274;

/// (name, A, B, the difference expected in the message; "" = same path)
const PAIRS: &[(&str, &str, &str, &str)] = &[
    (
        "same_with_comments_and_n_words",
        "G21 G90 G0 X1 Y2 Z3\nG1 X4 F100\nM2\n",
        "N5 G21 G90 (move) G0 X1 Y2 Z3\n; nothing\nN7 G1 X4 F100\nM2\n",
        "",
    ),
    (
        "exact_stop_is_not_exact_path",
        "G21 G0 X0 Y0\nG61.1\nG1 X4 F100\nM2\n",
        "G21 G0 X0 Y0\nG61\nG1 X4 F100\nM2\n",
        "path control",
    ),
    (
        "blend_tolerance_differs",
        "G21 G0 X0 Y0\nG64 P0.01\nG1 X4 F100\nM2\n",
        "G21 G0 X0 Y0\nG64 P0.02\nG1 X4 F100\nM2\n",
        "path control",
    ),
    (
        "blend_tolerance_in_inch_and_mm",
        "G20 G0 X0 Y0\nG64 P0.001\nG1 X1 F10\nM2\n",
        "G21 G0 X0 Y0\nG64 P0.0254 Q0.0254\nG1 X25.4 F254\nM2\n",
        "",
    ),
    (
        "naive_cam_tolerance_differs",
        "G21 G0 X0 Y0\nG64 P0.01\nG1 X4 F100\nM2\n",
        "G21 G0 X0 Y0\nG64 P0.01 Q0.05\nG1 X4 F100\nM2\n",
        "path control",
    ),
    (
        "end_point_off_by_10_um",
        "G21 G0 X1 Y2\nG1 X4 F100\nM2\n",
        "G21 G0 X1 Y2\nG1 X4.01 F100\nM2\n",
        "end point differs",
    ),
    (
        "inch_program_and_its_mm_translation",
        "G20 G90 G0 X1 Y1\nG1 X2 F10\nG2 X3 Y2 I0 J1\nM2\n",
        "G21 G90 G0 X25.4 Y25.4\nG1 X50.8 F254\nG2 X76.2 Y50.8 I0 J25.4\nM2\n",
        "",
    ),
    (
        "dwell_time_differs",
        "G21 G0 X0 Y0 Z5\nG1 Z-1 F100\nG4 P1\nG0 Z5\nM2\n",
        "G21 G0 X0 Y0 Z5\nG1 Z-1 F100\nG4 P2\nG0 Z5\nM2\n",
        "pause 1",
    ),
    (
        "dwell_place_differs",
        "G21 G0 X0 Y0 Z5\nG1 Z-1 F100\nG4 P1\nG0 Z5\nM2\n",
        "G21 G0 X0 Y0 Z5\nG1 Z-1 F100\nG0 Z5\nG4 P1\nM2\n",
        "pause 1",
    ),
    (
        "stop_missing",
        "G21 G0 X0 Y0 Z5\nM0\nG1 Z-1 F100\nM2\n",
        "G21 G0 X0 Y0 Z5\nG1 Z-1 F100\nM2\n",
        "dwells and stops",
    ),
    (
        "g81_is_its_moves",
        "G21 G90 G17 G0 X0 Y0 Z5\nF100\nG98 G81 X10 Y10 Z-2 R1\nG80\nM2\n",
        "G21 G90 G17 G0 X0 Y0 Z5\nG0 X10 Y10\nG0 Z1\nG1 Z-2 F100\nG0 Z5\nM2\n",
        "",
    ),
    (
        "feed_differs",
        "G21 G0 X0 Y0\nG1 X4 F100\nM2\n",
        "G21 G0 X0 Y0\nG1 X4 F110\nM2\n",
        "feed",
    ),
    (
        "rapid_instead_of_feed",
        "G21 G0 X0 Y0\nG1 X4 F100\nM2\n",
        "G21 G0 X0 Y0\nG0 X4 F100\nM2\n",
        "kind",
    ),
    (
        "xz_arc_direction",
        "G21 G18 G0 X0 Z0\nG2 X10 Z0 I5 K0 F100\nM2\n",
        "G21 G18 G0 X0 Z0\nG3 X10 Z0 I5 K0 F100\nM2\n",
        "arc",
    ),
    (
        "work_offset_folded",
        "G21 G10 L2 P2 X100 Y50 Z-10\nG55 G0 X1 Y1 Z1\nM2\n",
        "G21 G0 X101 Y51 Z-9\nM2\n",
        "",
    ),
    (
        "split_line_needs_merging",
        "G21 G0 X0 Y0\nG1 X10 F100\nM2\n",
        "G21 G0 X0 Y0\nG1 X5 F100\nG1 X10\nM2\n",
        "end point differs by 5.0",
    ),
    // rs274 prints a spline without its shape: B's moves from its line
    // (by their N words) stand in for it, and where it ends must agree.
    (
        "spline_stands_in",
        "G21 G0 X0 Y0 F100\nG5.1 X10 Y0 I5 J5\nG91 G1 X1\nM2\n",
        "G21 G0 X0 Y0 F100\nN2 G1 X5 Y2.5\nN2 G1 X10 Y0\nG91 G1 X1\nM2\n",
        "",
    ),
    (
        "spline_end_differs",
        "G21 G0 X0 Y0 F100\nG5.1 X10 Y0 I5 J5\nG91 G1 X1\nM2\n",
        "G21 G0 X0 Y0 F100\nN2 G1 X5 Y2.5\nN2 G1 X9 Y0\nG91 G1 X1\nM2\n",
        "end point differs",
    ),
    (
        "tool_changes_differ",
        "G21 T1 M6\nG0 X1\nM2\n",
        "G21 T2 M6\nG0 X1\nM2\n",
        "tool change",
    ),
];

fn run_pair(name: &str, a: &str, b: &str, expected: &str) -> Result<(), Failed> {
    let dir = std::env::temp_dir().join(format!("ger-harness-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    let (pa, pb) = (
        dir.join(format!("{name}_a.ngc")),
        dir.join(format!("{name}_b.ngc")),
    );
    std::fs::write(&pa, a).map_err(|e| e.to_string())?;
    std::fs::write(&pb, b).map_err(|e| e.to_string())?;
    let ra = rs274::tool_path(&pa, &[])?;
    let rb = rs274::tool_path(&pb, &[])?;
    let _ = std::fs::remove_file(&pa);
    let _ = std::fs::remove_file(&pb);
    if ra.path.moves.is_empty() {
        return Err("A has no moves: the harness read nothing".into());
    }
    match (rs274::same_path(&ra, &rb, &Options::default()), expected) {
        (Ok(_), "") => Ok(()),
        (Ok(n), _) => {
            Err(format!("{n} moves compared equal; expected a difference ({expected})").into())
        }
        (Err(why), "") => Err(format!("expected the same path: {why}").into()),
        (Err(why), _) if why.contains(expected) => Ok(()),
        (Err(why), _) => Err(format!("expected a difference in {expected}, got: {why}").into()),
    }
}

fn main() {
    let args = Arguments::from_args();
    let (have, required) = (rs274::available(), rs274::required());
    let mut trials: Vec<Trial> = PAIRS
        .iter()
        .map(|&(name, a, b, expected)| {
            Trial::test(name, move || {
                if !have {
                    return Err(rs274::missing().into());
                }
                run_pair(name, a, b, expected)
            })
            .with_ignored_flag(!have && !required)
        })
        .collect();
    // Merging collinear splits makes the split line equal again.
    trials.push(
        Trial::test("merged_split_line_is_the_same", move || {
            if !have {
                return Err(rs274::missing().into());
            }
            let dir = std::env::temp_dir().join(format!("ger-harness-m-{}", std::process::id()));
            std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
            let (pa, pb) = (dir.join("a.ngc"), dir.join("b.ngc"));
            std::fs::write(&pa, "G21 G0 X0 Y0\nG1 X10 F100\nG2 X20 Y0 I5 J0\nM2\n")
                .map_err(|e| e.to_string())?;
            std::fs::write(
                &pb,
                "G21 G0 X0 Y0\nG1 X5 F100\nG1 X10\nG2 X15 Y5 I5 J0\nG2 X20 Y0 I0 J-5\nM2\n",
            )
            .map_err(|e| e.to_string())?;
            let (ra, rb) = (rs274::tool_path(&pa, &[])?, rs274::tool_path(&pb, &[])?);
            let merged = Options {
                merge: true,
                ..Options::default()
            };
            rs274::same_path(&ra, &rb, &merged)?;
            let sampled = Options {
                sample: Some(0.1),
                ..Options::default()
            };
            rs274::same_path(&ra, &rb, &sampled)?;
            // A reversed path has the same points but is not the same cut.
            std::fs::write(&pb, "G21 G0 X20 Y0\nG3 X10 Y0 I-5 J0 F100\nG1 X0\nM2\n")
                .map_err(|e| e.to_string())?;
            let rb = rs274::tool_path(&pb, &[])?;
            if rs274::same_path(&ra, &rb, &sampled).is_ok() {
                return Err("a reversed path compared equal when sampled".into());
            }
            Ok(())
        })
        .with_ignored_flag(!have && !required),
    );
    // A start away from rs274's zero tells a program that leaves its
    // start to the machine from one that takes the zero for it.
    trials.push(
        Trial::test("start_elsewhere_tells_the_machine_s_frame", move || {
            if !have {
                return Err(rs274::missing().into());
            }
            start_elsewhere()
        })
        .with_ignored_flag(!have && !required),
    );
    libtest_mimic::run(&args, trials).exit();
}

/// Pairs the same from rs274's zero and different from elsewhere: a G92
/// at the start against none, steps against the same numbers absolute.
fn start_elsewhere() -> Result<(), Failed> {
    let dir = std::env::temp_dir().join(format!("ger-harness-s-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    let pairs = [
        (
            "G21 G92 X0 Y0 Z0\nG0 X1 Y2 Z3\nM2\n",
            "G21 G0 X1 Y2 Z3\nM2\n",
        ),
        ("G21 G91 G0 X1 Y2 Z3\nM2\n", "G21 G90 G0 X1 Y2 Z3\nM2\n"),
    ];
    for (a, b) in pairs {
        let (pa, pb) = (dir.join("a.ngc"), dir.join("b.ngc"));
        std::fs::write(&pa, a).map_err(|e| e.to_string())?;
        std::fs::write(&pb, b).map_err(|e| e.to_string())?;
        let (ra, rb) = (rs274::tool_path(&pa, &[])?, rs274::tool_path(&pb, &[])?);
        rs274::same_path(&ra, &rb, &Options::default())
            .map_err(|why| format!("from zero, {a:?} and {b:?} differ: {why}"))?;
        let start = Some([1.5, -2.0, 0.5]);
        let ra = rs274::tool_path_from(&pa, &[], start)?;
        let rb = rs274::tool_path_from(&pb, &[], start)?;
        match rs274::same_path(&ra, &rb, &Options::default()) {
            Err(why) if why.contains("end point differs") => {}
            Err(why) => return Err(format!("{a:?} and {b:?}: {why}").into()),
            Ok(_) => return Err(format!("from elsewhere, {a:?} and {b:?} compared equal").into()),
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    Ok(())
}
