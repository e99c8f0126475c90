//! Property tests: no input makes ger panic, and the lowering preserves the
//! tool path whatever the input's distance mode and units.

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use ger::driver::{compile, CompileOptions, Compiled};
use ger::eval::EvalOptions;
use ger::source::Sources;
use proptest::prelude::*;

fn run(text: &str) -> Compiled {
    let mut sources = Sources::new();
    let file = sources.add("prop.egc", text.to_string());
    let options = CompileOptions {
        eval: EvalOptions {
            max_iterations: 1000,
            max_statements: 100_000,
            ..Default::default()
        },
        ..Default::default()
    };
    compile(&sources, file, &options, None)
}

/// Pieces of the language, glued at random: most soups are wrong, and every
/// one must give diagnostics or output, never a panic or a hang.
const PIECES: &[&str] = &[
    "G0", "G1", "G2", "G3", "G90", "G91", "G20", "G21", "G16", "G15", "G52", "G92", "G43", "G54",
    "G55", "M98", "M99", "M30", "O100", "X1", "Y-2.5", "Z.5", "I1", "J-1", "R2", "F100", "P100",
    "L2", "H1", "X<", ">", "Aa", "Bb", "=", "==", "<", "(", ")", "{", "}", "if", "else", "while",
    ";", "\n", "+", "-", "*", "/", "%", "^", "sin", "(c)", "//x", "\"mm\"", "SetTool", "1", "0",
    "true", "&&", "!", ",", "%\n", "N10", "X", "@", "P0X", "1.2.3",
];

/// Pieces of LinuxCNC's macro language.
const LINUXCNC: &[&str] = &[
    "#1", "#<a>", "#<_b>", "=", "[", "]", "o100", "O200", "sub", "endsub", "call", "if", "elseif",
    "else", "endif", "while", "endwhile", "do", "EQ", "GT", "AND", "MOD", "**", "ATAN", "/", "SIN",
    "G1", "X", "Y#1", "Z[", "F100", "M2", "1", "-2.5", "(c)", ";x", "\n", "#", "##1", "#<",
    "return", "M98", "P100", "M99",
];

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
        let text = String::from_utf8_lossy(&bytes);
        let _ = run(&text);
    }

    #[test]
    fn random_token_soups_never_panic(picks in proptest::collection::vec((0..PIECES.len(), 0..3usize), 0..60)) {
        let text: String = picks
            .iter()
            .map(|&(i, sep)| format!("{}{}", PIECES[i], [" ", "", "\n"][sep]))
            .collect();
        let _ = run(&text);
    }

    /// The same for plain G-code with LinuxCNC's macro language.
    #[test]
    fn random_linuxcnc_soups_never_panic(picks in proptest::collection::vec((0..LINUXCNC.len(), 0..3usize), 0..60)) {
        let text: String = picks
            .iter()
            .map(|&(i, sep)| format!("{}{}", LINUXCNC[i], [" ", "", "\n"][sep]))
            .collect();
        let mut sources = Sources::new();
        let file = sources.add("prop.ngc", text);
        let _ = compile(&sources, file, &CompileOptions::default(), None);
    }
}

/// One random move: a straight move or an arc that ends on its circle.
#[derive(Clone, Debug)]
enum Step {
    Line {
        rapid: bool,
        to: [f64; 3],
    },
    Arc {
        cw: bool,
        center: [f64; 2],
        sweep_deg: f64,
        z: f64,
    },
}

fn step() -> impl Strategy<Value = Step> {
    let coord = -100.0..100.0f64;
    prop_oneof![
        (any::<bool>(), [coord.clone(), coord.clone(), -20.0..5.0f64])
            .prop_map(|(rapid, to)| Step::Line { rapid, to }),
        (
            any::<bool>(),
            [-30.0..30.0f64, -30.0..30.0f64],
            10.0..350.0f64,
            -20.0..5.0f64
        )
            .prop_map(|(cw, center, sweep_deg, z)| Step::Arc {
                cw,
                center,
                sweep_deg,
                z
            }),
    ]
}

/// A resolved move: its G code, absolute end (mm), arc centre offset.
type Resolved = (String, [f64; 3], Option<[f64; 2]>);

/// Absolute end points (mm) and the arc centre offsets of each step.
fn resolve(steps: &[Step]) -> Vec<Resolved> {
    let mut pos = [0.0, 0.0, 10.0];
    let mut out = Vec::new();
    for s in steps {
        match s {
            Step::Line { rapid, to } => {
                pos = *to;
                out.push((if *rapid { "G0" } else { "G1" }.to_string(), pos, None));
            }
            Step::Arc {
                cw,
                center,
                sweep_deg,
                z,
            } => {
                let c = [pos[0] + center[0], pos[1] + center[1]];
                let r = center[0].hypot(center[1]);
                if r < 1.0 {
                    continue;
                }
                let a0 = (pos[1] - c[1]).atan2(pos[0] - c[0]);
                let a1 = a0 + sweep_deg.to_radians() * if *cw { -1.0 } else { 1.0 };
                let end = [c[0] + r * a1.cos(), c[1] + r * a1.sin(), *z];
                out.push((
                    if *cw { "G2" } else { "G3" }.to_string(),
                    end,
                    Some(*center),
                ));
                pos = end;
            }
        }
    }
    out
}

/// The same path written absolute or incremental, in mm or inch.
fn program(moves: &[Resolved], incremental: bool, inch: bool) -> String {
    let k = if inch { 1.0 / 25.4 } else { 1.0 };
    let mut text = format!(
        "SetUnits \"mm\"\n{} G17 G90\nG0 X0 Y0 Z<{}>\nF500\n",
        if inch { "G20" } else { "G21" },
        10.0 * k
    );
    if incremental {
        text.push_str("G91\n");
    }
    let mut pos = [0.0, 0.0, 10.0];
    for (code, end, center) in moves {
        let v: Vec<f64> = (0..3)
            .map(|i| if incremental { end[i] - pos[i] } else { end[i] } * k)
            .collect();
        // Symbolic words carry 12 decimals: no visible input rounding.
        text.push_str(&format!(
            "{code} X<{:.12}> Y<{:.12}> Z<{:.12}>",
            v[0], v[1], v[2]
        ));
        if let Some(c) = center {
            text.push_str(&format!(" I<{:.12}> J<{:.12}>", c[0] * k, c[1] * k));
        }
        text.push('\n');
        pos = *end;
    }
    text
}

/// End points of the moves in ger's output.
fn end_points(output: &str) -> Vec<[f64; 3]> {
    let mut pos = [0.0; 3];
    let mut points = Vec::new();
    for line in output.lines() {
        let words: Vec<&str> = line.split_whitespace().collect();
        if !words
            .iter()
            .any(|w| matches!(*w, "G0" | "G1" | "G2" | "G3"))
        {
            continue;
        }
        for w in &words {
            let axis = match w.as_bytes()[0] {
                b'X' => 0,
                b'Y' => 1,
                b'Z' => 2,
                _ => continue,
            };
            pos[axis] = w[1..].parse().unwrap();
        }
        points.push(pos);
    }
    points
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    #[test]
    fn absolute_incremental_inch_mm_agree(steps in proptest::collection::vec(step(), 1..25)) {
        let moves = resolve(&steps);
        let expected: Vec<[f64; 3]> = moves.iter().map(|m| m.1).collect();
        for (incremental, inch) in [(false, false), (true, false), (false, true), (true, true)] {
            let text = program(&moves, incremental, inch);
            let compiled = run(&text);
            let output = compiled.output.unwrap_or_else(|| {
                panic!("no output for\n{text}\n{:?}", compiled.diagnostics)
            });
            let got = end_points(&output);
            // Moves shorter than the output resolution print nothing.
            let mut it = got.iter().skip(1); // the setup rapid
            let mut last = [0.0, 0.0, 10.0];
            for e in &expected {
                if (0..3).all(|i| (e[i] - last[i]).abs() < 0.0006) {
                    continue;
                }
                let g = it.next().unwrap_or_else(|| panic!("missing move to {e:?}\n{output}"));
                for i in 0..3 {
                    prop_assert!((g[i] - e[i]).abs() <= 0.0006,
                        "axis {} expected {} got {} (incremental={}, inch={})\n{}", i, e[i], g[i], incremental, inch, output);
                }
                last = *g;
            }
        }
    }
}

/// Deep nesting is bounded with an error, never a stack overflow: long
/// operator chains, nested parentheses and unary signs, nested blocks.
#[test]
fn deep_nesting_is_an_error_not_a_crash() {
    let n = 50_000;
    let programs = [
        format!("Aa = {}\n", vec!["1"; n].join("+")),
        format!("Aa = {}1{}\n", "(".repeat(n), ")".repeat(n)),
        format!("Aa = {}1\n", "-".repeat(n)),
        format!(
            "Aa = true\n{}G0 X1\n{}",
            "if (Aa) {\n".repeat(n),
            "}\n".repeat(n)
        ),
        format!("G0 X<{}1>\n", "-".repeat(n)),
    ];
    for text in programs {
        let compiled = run(&text);
        assert!(compiled.output.is_none());
        assert!(!compiled.diagnostics.is_empty());
    }
}

/// A plain line as CAM writes them: some words, spaces or none, an N word
/// or a comment now and then.
fn plain_line() -> impl Strategy<Value = String> {
    use proptest::option::of;
    // Straight moves only, each letter at most once, one code of a modal
    // group: a program that does not compile would compare nothing but
    // its errors.
    let motion = of(prop_oneof![
        Just("G0"),
        Just("G1"),
        Just("G00"),
        Just("G01")
    ]);
    let mode = of(prop_oneof![
        Just("G90"),
        Just("G91"),
        Just("G20"),
        Just("G21"),
        Just("M3 S1000"),
        Just("(a comment)"),
    ]);
    (
        (of(1..9999u32), motion, mode, any::<bool>()),
        (
            of(-500.0..500.0f64),
            of(-500.0..500.0f64),
            of(-50.0..10.0f64),
            of(1.0..2000.0f64),
        ),
    )
        .prop_map(|((n, motion, mode, spaced), (x, y, z, f))| {
            let words: Vec<String> = [
                n.map(|n| format!("N{n}")),
                mode.map(str::to_string),
                motion.map(str::to_string),
                x.map(|v| format!("X{v:.3}")),
                y.map(|v| format!("Y{v:.4}")),
                z.map(|v| format!("Z{v:.2}")),
                f.map(|v| format!("F{v:.0}")),
            ]
            .into_iter()
            .flatten()
            .collect();
            words.join(if spaced { " " } else { "" })
        })
}

/// `line` with a blank after the characters of its words that `picks`
/// chooses (`X-1.5` may become `X - 1. 5`), outside its comments.
fn with_blanks_inside(line: &str, picks: &[bool]) -> String {
    let mut spaced = String::with_capacity(line.len() * 2);
    let mut in_comment = false;
    let mut picks = picks.iter().cycle();
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        spaced.push(c);
        in_comment = match c {
            '(' => true,
            ')' => false,
            _ => in_comment,
        };
        let inside_word = chars
            .peek()
            .is_some_and(|next| next.is_ascii_digit() || matches!(next, '.' | '-'));
        if !in_comment && inside_word && *picks.next().unwrap_or(&false) {
            spaced.push(' ');
        }
    }
    spaced
}

/// Output and diagnostics, as text.
fn outcome(text: &str, fast: bool) -> String {
    let compiled = ger::syntax::with_fast_path(fast, || run(text));
    format!("{:?}\n{:?}", compiled.output, compiled.diagnostics)
}

/// Whether `output` moves as `source` does (ger's own tool paths, within
/// 0.002 mm), or how it differs.
fn same_tool_path(source: &str, output: &str) -> Result<(), String> {
    let path = |text: &str| {
        let mut sources = Sources::new();
        let file = sources.add("p.egc", text.to_string());
        ger::driver::tool_path(&sources, file, &CompileOptions::default(), None).0
    };
    let (a, b) = (
        path(source).expect("a path"),
        path(output).expect("the output's path"),
    );
    let options = ger::toolpath::compare::Options {
        tol: 0.002,
        ..Default::default()
    };
    ger::toolpath::compare::compare(&a, &b, &options)
        .map(|_| ())
        .map_err(|d| d.to_string())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    /// The parser's fast path for plain lines and the grammar give the
    /// same program: same output, same diagnostics, byte for byte.
    #[test]
    fn fast_path_and_grammar_compile_alike(lines in proptest::collection::vec(plain_line(), 1..40)) {
        let text = format!("G21 G90 F100\nG0 X0 Y0 Z5\n{}\nM30\n", lines.join("\n"));
        let fast = outcome(&text, true);
        prop_assert!(!fast.starts_with("None"), "{}", fast);
        prop_assert_eq!(fast, outcome(&text, false));
    }

    /// Spaces inside words (SPEC §2.2) read alike in `.egc` and in plain
    /// G-code, as the words without them, with the fast path and without.
    #[test]
    fn spaces_inside_words_read_alike_in_egc_and_plain(
        lines in proptest::collection::vec((plain_line(), proptest::collection::vec(any::<bool>(), 48)), 1..20)
    ) {
        let program = |lines: Vec<String>| format!("G21 G90 F100\nG0 X0 Y0 Z5\n{}\nM30\n", lines.join("\n"));
        let written = program(lines.iter().map(|(line, _)| line.clone()).collect());
        let spaced = program(lines.iter().map(|(line, picks)| with_blanks_inside(line, picks)).collect());
        let egc = outcome(&spaced, true);
        prop_assert!(!egc.starts_with("None"), "{}\n{}", spaced, egc);
        prop_assert_eq!(&egc, &outcome(&written, true), "{}", spaced);
        prop_assert_eq!(&egc, &outcome(&spaced, false), "{}", spaced);
        // (`.egc` keeps no comment that stands alone on its line.)
        let output = |c: Compiled| without_comments(&c.output.unwrap_or_default());
        prop_assert_eq!(output(run(&spaced)), output(compile_gcode(&spaced)), "{}", spaced);
    }

    /// ger's output is a program ger reads again to the same tool path.
    #[test]
    fn output_compiles_to_the_same_tool_path(steps in proptest::collection::vec(step(), 1..20), inch in any::<bool>()) {
        let moves = resolve(&steps);
        let text = program(&moves, false, inch);
        let first = run(&text).output.expect("the generated program compiles");
        if let Err(d) = same_tool_path(&text, &first) {
            prop_assert!(false, "{}\n--- output ---\n{}", d, first);
        }
    }
}

/// Steps whose arcs are often near a half circle, where an R places the
/// centre worst.
fn step_near_half() -> impl Strategy<Value = Step> {
    prop_oneof![
        step(),
        (
            any::<bool>(),
            [-30.0..30.0f64, -30.0..30.0f64],
            prop_oneof![179.0..181.0f64, 178.0..182.0f64, 5.0..20.0f64],
            -20.0..5.0f64
        )
            .prop_map(|(cw, center, sweep_deg, z)| Step::Arc {
                cw,
                center,
                sweep_deg,
                z
            }),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    /// `--arcs r`: the output moves as the source does, arcs near a half
    /// circle and short arcs included (R words with more decimals, or
    /// I/J where no R places the centre).
    #[test]
    fn r_output_moves_as_the_source(steps in proptest::collection::vec(step_near_half(), 1..20), inch in any::<bool>()) {
        let moves = resolve(&steps);
        let text = program(&moves, false, inch);
        let mut options = CompileOptions::default();
        options.emit.arcs = ger::emit::ArcFormat::R;
        let mut sources = Sources::new();
        let file = sources.add("p.egc", text.clone());
        let first = compile(&sources, file, &options, None).output.expect("the generated program compiles");
        if let Err(d) = same_tool_path(&text, &first) {
            prop_assert!(false, "{}\n--- output ---\n{}", d, first);
        }
    }
}

/// Text a comment may hold: code-like pieces, parentheses, semicolons.
fn comment_text() -> impl Strategy<Value = String> {
    let piece = prop_oneof![
        Just("G0 Z50".to_string()),
        Just("M30".to_string()),
        Just("X99 Y99".to_string()),
        Just("(".to_string()),
        Just(")".to_string()),
        Just(";".to_string()),
        Just("%".to_string()),
        Just("$H".to_string()),
        Just("#1=2".to_string()),
        "[a-z ]{0,8}",
    ];
    proptest::collection::vec(piece, 0..6).prop_map(|v| v.join(" "))
}

/// The output without its comment lines (`N12 (text)`).
fn without_comments(output: &str) -> String {
    output
        .lines()
        .filter(|l| {
            !l.split_once(' ')
                .is_some_and(|(n, rest)| n.starts_with('N') && rest.starts_with('('))
        })
        .map(|l| format!("{l}\n"))
        .collect()
}

fn compile_gcode(text: &str) -> Compiled {
    let mut sources = Sources::new();
    let file = sources.add("prop.nc", text.to_string());
    compile(&sources, file, &CompileOptions::default(), None)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    /// In plain G-code nothing after `;` runs: the program with comments
    /// appended to its lines compiles to exactly the program without them.
    #[test]
    fn text_after_a_semicolon_never_runs(
        lines in proptest::collection::vec(plain_line(), 1..30),
        comments in proptest::collection::vec(proptest::option::of(comment_text()), 30),
    ) {
        let body: Vec<String> = lines.iter().map(|l| l.replace("(a comment)", "")).collect();
        let plain = format!("G21 G90 F100\nG0 X0 Y0 Z5\n{}\nM30\n", body.join("\n"));
        let commented: Vec<String> = body
            .iter()
            .zip(&comments)
            .map(|(l, c)| match c {
                Some(c) => format!("{l} ;{c}"),
                None => l.clone(),
            })
            .collect();
        let with = format!("G21 G90 F100 ; units\nG0 X0 Y0 Z5\n{}\nM30\n", commented.join("\n"));
        let (a, b) = (compile_gcode(&plain), compile_gcode(&with));
        // Every generated program compiles: the outputs are compared.
        prop_assert!(a.output.is_some(), "{:?}", a.diagnostics);
        // The comments are kept, on lines of their own: without them the
        // programs are the same, byte for byte.
        prop_assert_eq!(a.output.as_deref().map(without_comments), b.output.as_deref().map(without_comments));
        prop_assert_eq!(a.diagnostics.len(), b.diagnostics.len());
    }
}

/// The distance from `p` to the segment `a`–`b` (XY).
fn segment_distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let t = (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0);
    (p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dy)
}

/// A convex polygon (its corners on a circle, clockwise, every corner
/// turning more than rs274's 0.05 rad), its outside milled with G41 (climb)
/// by a tool of radius `r`: the returned program and its corners.
fn compensated_polygon(gaps: &[f64], radius: f64, r: f64) -> (String, Vec<[f64; 2]>) {
    let total: f64 = gaps.iter().sum();
    let mut angle: f64 = 0.0;
    let mut corners = Vec::new();
    for g in gaps {
        corners.push([radius * angle.cos(), radius * angle.sin()]);
        // Clockwise.
        angle -= g / total * std::f64::consts::TAU;
    }
    let (v0, v1) = (corners[0], corners[1]);
    let mid = [(v0[0] + v1[0]) / 2.0, (v0[1] + v1[1]) / 2.0];
    // Outside of a clockwise edge is its left: the edge direction turned
    // +90°.
    let len = (v1[0] - v0[0]).hypot(v1[1] - v0[1]);
    let out = [-(v1[1] - v0[1]) / len, (v1[0] - v0[0]) / len];
    let start = [
        mid[0] + out[0] * (3.0 * r + 5.0),
        mid[1] + out[1] * (3.0 * r + 5.0),
    ];
    let mut text = format!(
        "SetTool 1 {}\nG21 G90 G17\nT1 M6\nS5000 M3\nG0 X{:.6} Y{:.6} Z5\nG1 Z-1 F100\nG41 D1 G1 X{:.6} Y{:.6}\n",
        2.0 * r, start[0], start[1], mid[0], mid[1]
    );
    for c in corners.iter().skip(1).chain(std::iter::once(&corners[0])) {
        text.push_str(&format!("G1 X{:.6} Y{:.6}\n", c[0], c[1]));
    }
    text.push_str(&format!("G1 X{:.6} Y{:.6}\n", mid[0], mid[1]));
    text.push_str(&format!(
        "G40 G1 X{:.6} Y{:.6}\nG0 Z5\nM30\n",
        start[0], start[1]
    ));
    (text, corners)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    /// Outside a convex polygon, the compensated path keeps exactly the
    /// tool radius from the outline everywhere between the entry and the
    /// exit: on the offset edges and on the corner arcs (sampled).
    #[test]
    fn compensation_keeps_the_radius(
        gaps in proptest::collection::vec(0.35f64..1.0, 3..9),
        radius in 10.0f64..60.0,
        r_part in 0.05f64..0.4,
        lookahead in any::<bool>(),
    ) {
        // The tool radius: a part of the shortest half edge, so that the
        // entry (offset along the first edge) does not overshoot it.
        let (_, corners) = compensated_polygon(&gaps, radius, 1.0);
        let shortest = (0..corners.len())
            .map(|i| {
                let (a, b) = (corners[i], corners[(i + 1) % corners.len()]);
                (a[0] - b[0]).hypot(a[1] - b[1])
            })
            .fold(f64::INFINITY, f64::min);
        let r = r_part * shortest / 2.0;
        let (text, corners) = compensated_polygon(&gaps, radius, r);
        let mut sources = Sources::new();
        let file = sources.add("poly.egc", text.clone());
        let mut options = CompileOptions::default();
        options.lower.comp_entry_lookahead = lookahead;
        let (path, diagnostics) = ger::driver::tool_path(&sources, file, &options, None);
        let path = path.unwrap_or_else(|| panic!("{}\n{text}", ger::diagnostic::render(&sources, &diagnostics)));
        // Lines 8.. are the profile (line 7 is the entry, the G40 line the exit).
        let last = 8 + corners.len() as u32;
        let outline = |p: [f64; 2]| {
            (0..corners.len())
                .map(|i| segment_distance(p, corners[i], corners[(i + 1) % corners.len()]))
                .fold(f64::INFINITY, f64::min)
        };
        let mut checked = 0;
        for m in path.moves.iter().filter(|m| (8..=last).contains(&m.span.line)) {
            for k in 0..=8 {
                let f = k as f64 / 8.0;
                let p = match m.kind {
                    ger::toolpath::MoveKind::Arc(a) => {
                        let (c, s) = (a.center, m.start);
                        let a0 = (s[1] - c[1]).atan2(s[0] - c[0]);
                        let sweep = m.sweep() * if a.clockwise { -1.0 } else { 1.0 };
                        let rr = (s[0] - c[0]).hypot(s[1] - c[1]);
                        [c[0] + rr * (a0 + f * sweep).cos(), c[1] + rr * (a0 + f * sweep).sin()]
                    }
                    _ => [m.start[0] + f * (m.end[0] - m.start[0]), m.start[1] + f * (m.end[1] - m.start[1])],
                };
                let d = outline(p);
                prop_assert!((d - r).abs() < 1e-6, "{d} from the outline, not {r}, at {p:?} (line {})\n{text}", m.span.line);
                checked += 1;
            }
        }
        prop_assert!(checked > 9 * corners.len());
    }
}

/// A random contour of lines and arcs (I/J centres) from X0 Y0, each move
/// but the last with `,R` or `,C`: the program, and per source line the
/// move as written (end, and an arc's centre and direction) and its corner.
#[allow(clippy::type_complexity)]
fn cornered_contour(
    next: &mut impl FnMut() -> f64,
) -> (
    String,
    Vec<(
        u32,
        [f64; 2],
        [f64; 2],
        Option<([f64; 2], bool)>,
        Option<(bool, f64)>,
    )>,
) {
    let read = |v: f64| format!("{v:.6}").parse::<f64>().unwrap();
    let mut text = String::from("G21 G90 G17\nG0 X0 Y0 Z0\nG1 Z-1 F100\n");
    let (mut at, mut moves) = ([0.0, 0.0], Vec::new());
    let count = 2 + (next() * 5.0) as usize;
    for k in 0..count {
        let line = 4 + k as u32;
        let corner = (k + 1 < count).then(|| (next() < 0.5, read(0.5 + next() * 4.5)));
        let word = match corner {
            Some((true, r)) => format!(" ,R{r:.6}"),
            Some((false, c)) => format!(" ,C{c:.6}"),
            None => String::new(),
        };
        if next() < 0.5 {
            let (len, angle) = (5.0 + next() * 45.0, next() * std::f64::consts::TAU);
            let end = [
                read(at[0] + len * angle.cos()),
                read(at[1] + len * angle.sin()),
            ];
            text += &format!("G1 X{:.6} Y{:.6}{word}\n", end[0], end[1]);
            moves.push((line, at, end, None, corner));
            at = end;
        } else {
            let (radius, angle) = (3.0 + next() * 27.0, next() * std::f64::consts::TAU);
            let ij = [read(radius * angle.cos()), read(radius * angle.sin())];
            let centre = [at[0] + ij[0], at[1] + ij[1]];
            let ccw = next() < 0.5;
            let turn = (0.2 + next() * 5.5) * if ccw { 1.0 } else { -1.0 };
            let (s, c) = turn.sin_cos();
            let v = [at[0] - centre[0], at[1] - centre[1]];
            let end = [
                read(centre[0] + v[0] * c - v[1] * s),
                read(centre[1] + v[0] * s + v[1] * c),
            ];
            let code = if ccw { "G3" } else { "G2" };
            text += &format!(
                "{code} X{:.6} Y{:.6} I{:.6} J{:.6}{word}\n",
                end[0], end[1], ij[0], ij[1]
            );
            moves.push((line, at, end, Some((centre, ccw)), corner));
            at = end;
        }
    }
    text += "G0 Z5\nM30\n";
    (text, moves)
}

/// Random contours of lines and arcs with `,R`/`,C` through the whole
/// compiler: each arc as written keeps its centre, and its ends their
/// distance from it (cut or not); each round has its radius and is tangent
/// to the moves before and after it; each chamfer's ends are c from the
/// corner. Within 1e-9 mm (the tool path is not rounded to the output's
/// decimals).
#[test]
fn corners_into_and_on_arcs_keep_arcs_and_touch_both_moves() {
    let mut seed = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut programs, mut rounds, mut chamfers, mut arcs) = (0, 0, 0, 0);
    let dist = |a: [f64; 3], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
    for _ in 0..3000 {
        let (text, written) = cornered_contour(&mut next);
        let mut sources = Sources::new();
        let file = sources.add("corners.nc", text.clone());
        let (path, _) = ger::driver::tool_path(&sources, file, &CompileOptions::default(), None);
        let Some(path) = path else { continue };
        programs += 1;
        let moves: Vec<_> = path.moves.iter().collect();
        // Where a move goes at its start or end.
        let direction = |m: &ger::toolpath::Move, at_end: bool| -> [f64; 2] {
            let p = if at_end { m.end } else { m.start };
            let v = match m.kind {
                ger::toolpath::MoveKind::Arc(a) => {
                    let n = [p[0] - a.center[0], p[1] - a.center[1]];
                    if a.clockwise {
                        [n[1], -n[0]]
                    } else {
                        [-n[1], n[0]]
                    }
                }
                _ => [m.end[0] - m.start[0], m.end[1] - m.start[1]],
            };
            let l = v[0].hypot(v[1]);
            [v[0] / l, v[1] / l]
        };
        for &(line, start, end, arc, corner) in &written {
            let on_line: Vec<usize> = (0..moves.len())
                .filter(|&i| moves[i].span.line == line)
                .collect();
            if let Some((centre, _)) = arc {
                let m = moves[on_line[0]];
                let ger::toolpath::MoveKind::Arc(a) = m.kind else {
                    panic!("{text}")
                };
                assert!(dist(a.center, centre) < 1e-9, "{text}\n{m:?}");
                assert!(
                    (dist(m.start, centre) - (start[0] - centre[0]).hypot(start[1] - centre[1]))
                        .abs()
                        < 1e-9,
                    "{text}\n{m:?}"
                );
                assert!(
                    (dist(m.end, centre) - (end[0] - centre[0]).hypot(end[1] - centre[1])).abs()
                        < 1e-9,
                    "{text}\n{m:?}"
                );
                arcs += 1;
            }
            let Some((round, size)) = corner else {
                continue;
            };
            let i = *on_line.last().unwrap();
            let (m, after) = (moves[i], moves[i + 1]);
            if round {
                let ger::toolpath::MoveKind::Arc(a) = m.kind else {
                    panic!("{text}")
                };
                assert!(
                    (dist(m.start, [a.center[0], a.center[1]]) - size).abs() < 1e-9,
                    "{text}\n{m:?}"
                );
                assert!(
                    (dist(m.end, [a.center[0], a.center[1]]) - size).abs() < 1e-9,
                    "{text}\n{m:?}"
                );
                let before = moves[i - 1];
                let (d0, d1) = (direction(before, true), direction(m, false));
                let (d2, d3) = (direction(m, true), direction(after, false));
                assert!(
                    (d0[0] - d1[0]).hypot(d0[1] - d1[1]) < 1e-9 * 30.0 / size,
                    "{text}\n{m:?}"
                );
                assert!(
                    (d2[0] - d3[0]).hypot(d2[1] - d3[1]) < 1e-9 * 30.0 / size,
                    "{text}\n{m:?}"
                );
                rounds += 1;
            } else {
                assert!((dist(m.start, end) - size).abs() < 1e-9, "{text}\n{m:?}");
                assert!((dist(m.end, end) - size).abs() < 1e-9, "{text}\n{m:?}");
                chamfers += 1;
            }
        }
    }
    assert!(
        programs > 300 && rounds > 300 && chamfers > 300 && arcs > 300,
        "{programs} programs, {rounds} rounds, {chamfers} chamfers, {arcs} arcs"
    );
}
