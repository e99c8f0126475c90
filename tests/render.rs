//! `ger render` (SPEC §7, issue 14): the simulation against analytic
//! results (volumes and cross-sections of slots, grooves, holes, circles),
//! the closed-form carving against a brute-force reference on random moves,
//! and the files it writes (PNG chunks and pixels, SVG goldens rendered with
//! resvg, a closed STL whose volume is the part's).

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use ger::driver::CompileOptions;
use ger::render::carve::{self, Frame, Grid, Segment, Shape};
use ger::render::cutter::{Arc, Cutter, Line, Profile};
use ger::render::{RenderOptions, Scene};
use ger::source::Sources;
use proptest::prelude::*;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Compile `program` (.egc) and carve it at `cell`.
fn carved(program: &str, cell: f64) -> (Scene, Grid) {
    carved_with(program, cell, &CompileOptions::default())
}

fn carved_with(program: &str, cell: f64, compile: &CompileOptions) -> (Scene, Grid) {
    let mut sources = Sources::new();
    let file = sources.add("part.egc", program.to_string());
    let (path, diagnostics) = ger::driver::tool_path(&sources, file, compile, None);
    let path =
        path.unwrap_or_else(|| panic!("{}", ger::diagnostic::render(&sources, &diagnostics)));
    let options = RenderOptions {
        resolution: Some(cell),
        ..Default::default()
    };
    let scene = Scene::new(&path, &options).unwrap();
    let mut grid = scene.grid().unwrap();
    assert_eq!(scene.coarser, None);
    scene.carve(&mut grid, &path, &|_, _| {});
    (scene, grid)
}

/// The height the grid has at the cell nearest `(x, y)`, and that cell's
/// centre.
fn sample(grid: &Grid, x: f64, y: f64) -> (f64, f64, f64) {
    let f = grid.frame;
    let i = (((x - f.x0) / f.cell) as usize).min(f.nx - 1);
    let j = (((y - f.y0) / f.cell) as usize).min(f.ny - 1);
    (f64::from(grid.at(i, j)), f.center_x(i), f.center_y(j))
}

fn assert_volume(grid: &Grid, expected: f64) {
    let got = grid.removed_volume();
    assert!(
        ((got - expected) / expected).abs() < 0.005,
        "removed {got}, expected {expected} ({:+.3}%)",
        (got / expected - 1.0) * 100.0
    );
}

/// Every cell's height against `profile(d)`, the height at distance `d`
/// (of the cell's centre, by `distance`) from the path (`None`: uncut),
/// within 1e-3 of the tool radius. Cells whose centre is within `edge` of
/// the cut's rim (`d` = `radius`) may fall either way.
fn assert_profile(
    grid: &Grid,
    distance: impl Fn(f64, f64) -> f64,
    radius: f64,
    edge: f64,
    profile: impl Fn(f64) -> Option<f64>,
) {
    let f = grid.frame;
    let mut checked = 0;
    for j in 0..f.ny {
        for i in 0..f.nx {
            let (x, y) = (f.center_x(i), f.center_y(j));
            let d = distance(x, y);
            if (d - radius).abs() < edge {
                continue;
            }
            let z = f64::from(grid.at(i, j));
            let expected = profile(d).map_or(grid.top, |z| z.min(grid.top));
            assert!(
                (z - expected).abs() <= 1e-3 * radius,
                "at ({x}, {y}), {d} from the path: {z}, expected {expected}"
            );
            checked += 1;
        }
    }
    assert!(checked > f.nx * f.ny / 2);
}

/// Distance in the plane from the segment (x0, y) to (x1, y).
fn from_slot(x0: f64, x1: f64, y0: f64) -> impl Fn(f64, f64) -> f64 {
    move |x: f64, y: f64| (x - x.clamp(x0, x1)).hypot(y - y0)
}

const STOCK: &str = "G21 G90 G17\nSetPart 60 40 10\n";

#[test]
fn a_flat_slot_removes_its_volume_and_cuts_a_square_section() {
    let (_, grid) = carved(
        &format!("{STOCK}SetTool 1 6\nT1 M6\nG0 X10 Y20 Z1\nG1 Z-2 F100\nG1 X40\nG0 Z5\nM30\n"),
        0.05,
    );
    // 2 deep: the slot (30 long, 6 wide) and the discs at its ends.
    assert_volume(&grid, 2.0 * (6.0 * 30.0 + PI * 9.0));
    assert_profile(&grid, from_slot(10.0, 40.0, 20.0), 3.0, 1e-9, |d| {
        (d <= 3.0).then_some(-2.0)
    });
}

#[test]
fn a_ball_groove_removes_its_volume_and_cuts_a_round_section() {
    let (_, grid) = carved(
        &format!(
            "{STOCK}SetTool 1 6 50 \"ball\"\nT1 M6\nG0 X10 Y20 Z1\nG1 Z-2 F100\nG1 X40\nG0 Z5\nM30\n"
        ),
        0.05,
    );
    // The ball's centre is 1 above the top: the section is the circle's
    // segment below a chord 1 from its centre; the ends are one cap 2 deep.
    let (r, d) = (3.0f64, 1.0f64);
    let section = r * r * (d / r).acos() - d * (r * r - d * d).sqrt();
    let cap = PI * 4.0 * (3.0 * r - 2.0) / 3.0;
    assert_volume(&grid, section * 30.0 + cap);
    assert_profile(&grid, from_slot(10.0, 40.0, 20.0), 3.0, 0.0, |d| {
        (d <= 3.0).then(|| -2.0 + 3.0 - (9.0 - d * d).sqrt())
    });
}

#[test]
fn a_vee_line_removes_its_volume_and_cuts_a_vee() {
    let (_, grid) = carved(
        &format!(
            "{STOCK}SetTool 1 6 50 \"vee\"\nT1 M6\nG0 X10 Y20 Z1\nG1 Z-2 F100\nG1 X40\nG0 Z5\nM30\n"
        ),
        0.05,
    );
    // A 90° vee 2 deep: a triangle 4 wide; the ends are one cone.
    assert_volume(&grid, 4.0 * 30.0 + PI * 4.0 * 2.0 / 3.0);
    assert_profile(&grid, from_slot(10.0, 40.0, 20.0), 3.0, 0.0, |d| {
        (d <= 3.0).then_some(-2.0 + d)
    });
}

#[test]
fn a_drilled_hole_removes_its_volume_and_has_a_118_degree_point() {
    let (_, grid) = carved(
        &format!(
            "{STOCK}SetTool 1 6 50 \"drill\"\nT1 M6\nG0 X20 Y20 Z1\nG1 Z-5 F100\nG0 Z5\nM30\n"
        ),
        0.05,
    );
    let rise = 1.0 / 59f64.to_radians().tan();
    let point = 3.0 * rise;
    assert_volume(&grid, PI * 9.0 * (5.0 - point) + PI * 9.0 * point / 3.0);
    assert_profile(&grid, from_slot(20.0, 20.0, 20.0), 3.0, 1e-9, |d| {
        (d <= 3.0).then_some(-5.0 + rise * d)
    });
}

#[test]
fn a_full_circle_groove_removes_its_ring() {
    let (_, grid) = carved(
        &format!("{STOCK}SetTool 1 4\nT1 M6\nG0 X40 Y20 Z1\nG1 Z-1 F100\nG2 X40 Y20 I-10 J0\nG0 Z5\nM30\n"),
        0.05,
    );
    // A ring 4 wide around a circle of radius 10, 1 deep.
    assert_volume(&grid, PI * (12.0f64.powi(2) - 8.0f64.powi(2)));
    let from_circle = |x: f64, y: f64| ((x - 30.0).hypot(y - 20.0) - 10.0).abs();
    assert_profile(&grid, from_circle, 2.0, 1e-9, |d| {
        (d <= 2.0).then_some(-1.0)
    });
}

#[test]
fn a_helix_is_carved_within_a_quarter_cell_of_its_path() {
    // Down 2 in one turn: the ring is cut, deepest where the turn ends.
    let (_, grid) = carved(
        &format!(
            "{STOCK}SetTool 1 4\nT1 M6\nG0 X40 Y20 Z0\nG3 X40 Y20 Z-2 I-10 J0 F100\nG0 Z5\nM30\n"
        ),
        0.05,
    );
    let (end, ..) = sample(&grid, 40.0, 20.0);
    assert!((end + 2.0).abs() < 1e-3, "{end}");
    // Over (30, 30), a quarter turn on, the cutter (radius 2) reaches
    // down to where the tip is 2 asin(0.1) further round.
    let (quarter, ..) = sample(&grid, 30.0, 30.0);
    let turned = (90f64.to_radians() + 2.0 * 0.1f64.asin()) / (2.0 * PI);
    assert!((quarter + 2.0 * turned).abs() < 2e-3, "{quarter}");
}

/// The lowest the cutter reaches over `(x, y)`, by sampling the move
/// densely: an upper bound on the exact answer.
fn brute_force(cutter: &Cutter, line: &Line, x: f64, y: f64, steps: u32) -> Option<f64> {
    let b = line.end();
    (0..=steps)
        .filter_map(|k| {
            let t = f64::from(k) / f64::from(steps);
            let p: Vec<f64> = (0..3).map(|i| line.a[i] + (b[i] - line.a[i]) * t).collect();
            let d = (x - p[0]).hypot(y - p[1]);
            (d <= cutter.radius).then(|| p[2] + cutter.lift(d))
        })
        .reduce(f64::min)
}

fn profile() -> impl Strategy<Value = Profile> {
    prop_oneof![
        Just(Profile::Flat),
        Just(Profile::Ball),
        (0.3f64..2.0).prop_map(|rise| Profile::Cone { rise }),
    ]
}

fn point() -> impl Strategy<Value = [f64; 3]> {
    (1.0f64..9.0, 1.0f64..9.0, -3.0f64..0.5).prop_map(|(x, y, z)| [x, y, z])
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    /// Carving random chained moves agrees with sampling each move densely:
    /// never higher, and lower only by what sampling misses between steps.
    #[test]
    fn carving_agrees_with_brute_force(profile in profile(), radius in 0.3f64..2.0, points in proptest::collection::vec(point(), 2..6)) {
        let cutter = Cutter { radius, profile };
        let frame = Frame::new(0.0, 0.0, 0.125, 80, 80);
        let mut grid = Grid::new(frame, 0.0, -5.0).unwrap();
        let lines: Vec<Line> = points.windows(2).map(|w| Line::new(w[0], w[1])).collect();
        let segments: Vec<Segment> = lines
            .iter()
            .enumerate()
            .map(|(k, &line)| Segment { shape: Shape::Line(line), cutter: 0, rapid: false, move_index: k, continues: k > 0 })
            .collect();
        carve::carve(&mut grid, &segments, &[cutter], &|_, _| {});
        let steps = 1500;
        for j in 0..frame.ny {
            for i in 0..frame.nx {
                let (x, y) = (frame.center_x(i), frame.center_y(j));
                let fast = f64::from(grid.at(i, j));
                let slow = lines
                    .iter()
                    .filter_map(|l| brute_force(&cutter, l, x, y, steps))
                    .fold(0.0f64, f64::min);
                prop_assert!(fast <= slow + 1e-5, "({x}, {y}): carved {fast} above sampled {slow}");
                // Between two samples the tip moves at most this far.
                let step = lines.iter().map(|l| (l.length.powi(2) + l.dz.powi(2)).sqrt()).fold(0.0, f64::max) / f64::from(steps);
                let steep = match profile { Profile::Cone { rise } => rise.max(1.0), _ => 1.0 };
                let slack = 2.0 * step * (1.0 + steep) + if profile == Profile::Ball { (2.0 * radius * step).sqrt() } else { 0.0 };
                if slow < 0.0 {
                    prop_assert!(slow - fast <= slack + 1e-5, "({x}, {y}): carved {fast}, sampled {slow}");
                }
            }
        }
    }

    /// A run of level lines of a flat cutter, carved as one polyline, cuts
    /// the same cells as its segments carved one by one.
    #[test]
    fn flat_runs_carve_as_their_segments(radius in 0.3f64..2.0, z in -3.0f64..0.0, points in proptest::collection::vec((1.0f64..9.0, 1.0f64..9.0), 2..12)) {
        let cutter = Cutter { radius, profile: Profile::Flat };
        let frame = Frame::new(0.0, 0.0, 0.0625, 160, 160);
        let lines: Vec<Line> = points.windows(2).map(|w| Line::new([w[0].0, w[0].1, z], [w[1].0, w[1].1, z])).collect();
        let carve_with = |continues: bool| {
            let segments: Vec<Segment> = lines
                .iter()
                .enumerate()
                .map(|(k, &line)| Segment { shape: Shape::Line(line), cutter: 0, rapid: false, move_index: k, continues: continues && k > 0 })
                .collect();
            let mut grid = Grid::new(frame, 0.0, -5.0).unwrap();
            carve::carve(&mut grid, &segments, &[cutter], &|_, _| {});
            grid
        };
        let (run, one_by_one) = (carve_with(true), carve_with(false));
        let differ = run.z.iter().zip(&one_by_one.z).filter(|(a, b)| a != b).count();
        prop_assert_eq!(differ, 0);
        prop_assert!(run.z.iter().any(|&c| c < 0.0) || lines.iter().all(|l| l.length == 0.0) || z == 0.0);
    }

    /// Carving a level arc (either way round, up to a full turn) agrees
    /// with sampling it densely.
    #[test]
    fn arcs_agree_with_brute_force(
        profile in profile(),
        radius in 0.3f64..2.0,
        center in (3.0f64..7.0, 3.0f64..7.0),
        arc_radius in 0.2f64..3.0,
        start in 0.0f64..std::f64::consts::TAU,
        sweep in -std::f64::consts::TAU..std::f64::consts::TAU,
        z in -3.0f64..0.0,
    ) {
        let cutter = Cutter { radius, profile };
        let frame = Frame::new(0.0, 0.0, 0.125, 80, 80);
        let mut grid = Grid::new(frame, 0.0, -5.0).unwrap();
        let at = |a: f64| [arc_radius * a.cos(), arc_radius * a.sin()];
        // Stored counter-clockwise from `from` to `to`.
        let (from, to) = if sweep >= 0.0 { (at(start), at(start + sweep)) } else { (at(start + sweep), at(start)) };
        let arc = Arc { center: [center.0, center.1], radius: arc_radius, z, from, to, sweep: sweep.abs() };
        let segment = Segment { shape: Shape::Arc(arc), cutter: 0, rapid: false, move_index: 0, continues: false };
        carve::carve(&mut grid, &[segment], &[cutter], &|_, _| {});
        let steps = 2000;
        let step = arc_radius * sweep.abs() / f64::from(steps);
        for j in 0..frame.ny {
            for i in 0..frame.nx {
                let (x, y) = (frame.center_x(i), frame.center_y(j));
                let fast = f64::from(grid.at(i, j));
                let slow = (0..=steps)
                    .filter_map(|k| {
                        let p = at(start + sweep * f64::from(k) / f64::from(steps));
                        let d = (x - center.0 - p[0]).hypot(y - center.1 - p[1]);
                        (d <= radius).then(|| z + cutter.lift(d))
                    })
                    .fold(0.0f64, f64::min);
                prop_assert!(fast <= slow + 1e-5, "({x}, {y}): carved {fast} above sampled {slow}");
                let steep = match profile { Profile::Cone { rise } => rise.max(1.0), _ => 1.0 };
                let slack = 2.0 * step * steep + if profile == Profile::Ball { (2.0 * radius * step).sqrt() } else { 0.0 };
                if slow < 0.0 {
                    prop_assert!(slow - fast <= slack + 1e-5, "({x}, {y}): carved {fast}, sampled {slow}");
                }
            }
        }
    }
}

// ---- the files `ger render` writes ----

fn ger(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_ger"))
        .args(args)
        .env_remove("GER_WIZARDS")
        .output()
        .unwrap()
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ger-render-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const SLOT: &str = "G21 G90 G17\nSetPart 40 20 10\nSetTool 1 6\nT1 M6\nG0 X10 Y10 Z1\nG1 Z-4 F100\nG1 X30\nG0 Z5\nM30\n";

/// Render `SLOT` at 0.1 mm cells to `dir/<output>` with `extra` options;
/// the output's path.
fn render_slot(dir: &Path, output: &str, extra: &[&str]) -> PathBuf {
    std::fs::write(dir.join("slot.egc"), SLOT).unwrap();
    let (input, out_path) = (dir.join("slot.egc"), dir.join(output));
    let mut args = vec![
        "render",
        input.to_str().unwrap(),
        "-o",
        out_path.to_str().unwrap(),
        "--resolution",
        "0.1",
    ];
    args.extend_from_slice(extra);
    let out = ger(&args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out_path
}

#[test]
fn the_depth_png_is_16_bit_with_its_scale() {
    let png = render_slot(&scratch("png"), "slot.png", &[]);
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(png).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let info = reader.info().clone();
    assert_eq!((info.width, info.height), (400, 200));
    assert_eq!(info.color_type, png::ColorType::Grayscale);
    assert_eq!(info.bit_depth, png::BitDepth::Sixteen);
    let text: std::collections::HashMap<String, String> = info
        .uncompressed_latin1_text
        .iter()
        .map(|t| (t.keyword.clone(), t.text.clone()))
        .collect();
    assert_eq!(text["ger:cell"], "0.1");
    assert_eq!(text["ger:z-top"], "0");
    assert_eq!(text["ger:z-bottom"], "-10");
    // 0.1 mm cells: 10,000 pixels a metre.
    assert_eq!(
        info.pixel_dims.map(|d| (d.xppu, d.unit)),
        Some((10_000, png::Unit::Meter))
    );
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    reader.next_frame(&mut pixels).unwrap();
    let at = |col: usize, row: usize| {
        u16::from_be_bytes([
            pixels[(row * 400 + col) * 2],
            pixels[(row * 400 + col) * 2 + 1],
        ])
    };
    // Row 0 is the top of the picture (Y 20); the slot runs along Y 10.
    assert_eq!(at(5, 5), 65535, "uncut stock is white");
    // 4 deep of 10: 60% of the way up from the bottom.
    assert_eq!(at(200, 100), (0.6f64 * 65535.0).round() as u16);
    assert_eq!(at(200, 20), 65535, "beside the slot");
}

#[test]
fn the_shaded_png_is_colour_with_a_legend() {
    let png = render_slot(&scratch("shade"), "slot.png", &["--shade"]);
    let reader = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(png).unwrap()))
        .read_info()
        .unwrap();
    assert_eq!(reader.info().color_type, png::ColorType::Rgb);
    assert!(reader.info().width > 400, "the legend is beside the part");
}

/// A PNG's size and RGB pixels.
fn rgb_png(path: &Path) -> (usize, usize, Vec<u8>) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    assert_eq!(reader.info().color_type, png::ColorType::Rgb);
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut pixels).unwrap();
    (info.width as usize, info.height as usize, pixels)
}

/// A 40 x 20 x 10 plate with a 6 mm hole drilled through at (20, 10).
const THROUGH: &str =
    "G21 G90 G17\nSetPart 40 20 10\nSetTool 1 6\nT1 M6\nG0 X20 Y10 Z1\nG1 Z-11 F100\nG0 Z5\nM30\n";

#[test]
fn the_view_fits_a_screen_and_a_hole_shows_what_is_behind_it() {
    let dir = scratch("view");
    std::fs::write(dir.join("through.egc"), THROUGH).unwrap();
    let input = dir.join("through.egc");
    let draw = |view: &str, extra: &[&str]| {
        let out_path = dir.join(format!("{view}.png"));
        let mut args = vec![
            "render",
            input.to_str().unwrap(),
            "-o",
            out_path.to_str().unwrap(),
            "--view",
            view,
        ];
        args.extend_from_slice(extra);
        let out = ger(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        rgb_png(&out_path)
    };
    // 0.025 mm cells: 1600 x 800 cells, drawn at most 1600 px a side.
    let (w, h, pixels) = draw("top", &[]);
    assert!((1400..=1600).contains(&w.max(h)), "{w} x {h}");
    let background = [246, 246, 246];
    let at = |x: usize, y: usize| &pixels[(y * w + x) * 3..(y * w + x) * 3 + 3];
    // Seen from above: the part's left edge on the middle row, its scale
    // from its height (20 mm), and the hole at X20 Y10, its middle.
    let left = (0..w).find(|&x| at(x, h / 2) != background).unwrap();
    let tall = (0..h).filter(|&y| at(left + 2, y) != background).count();
    let per_mm = tall as f64 / 20.0;
    let top = (0..h).find(|&y| at(left + 2, y) != background).unwrap();
    let (x, y) = (
        left + (20.0 * per_mm) as usize,
        top + (10.0 * per_mm) as usize,
    );
    assert_eq!(at(x, y), background, "the hole is see-through");
    assert_ne!(
        at(x, y - (4.0 * per_mm) as usize),
        background,
        "the stock is drawn"
    );
    // Asked smaller, it is smaller; from the corner the sides show too.
    let (w, h, pixels) = draw("iso", &["--size", "400", "--resolution", "0.1"]);
    assert!((350..=400).contains(&w.max(h)), "{w} x {h}");
    let mut shades: Vec<&[u8]> = pixels
        .chunks_exact(3)
        .filter(|p| *p != background)
        .collect();
    shades.sort();
    shades.dedup();
    assert!(shades.len() >= 3, "top and two sides in different light");
}

#[test]
fn the_shaded_png_fits_a_screen_unless_asked() {
    // 0.1 mm cells over 400 x 200 mm: 4000 x 2000 cells.
    let png = render_slot(
        &scratch("shade-fit"),
        "slot.png",
        &["--shade", "--stock", "400,200,10"],
    );
    let (w, h, _) = rgb_png(&png);
    assert!(w.max(h) <= 1600 && w > 1000, "{w} x {h}");
    let png = render_slot(
        &scratch("shade-size"),
        "slot.png",
        &["--shade", "--size", "500"],
    );
    let (w, h, _) = rgb_png(&png);
    assert!(w.max(h) <= 500 && w > 400, "{w} x {h}");
}

#[test]
fn the_stl_is_closed_and_holds_the_parts_volume() {
    let stl = render_slot(&scratch("stl"), "slot.stl", &[]);
    let mesh = stl_io::read_stl(&mut std::fs::File::open(stl).unwrap()).unwrap();
    // Every edge is walked once each way: closed and consistently wound.
    let mut edges = std::collections::HashMap::new();
    for face in &mesh.faces {
        for k in 0..3 {
            let (a, b) = (face.vertices[k], face.vertices[(k + 1) % 3]);
            *edges.entry((a, b)).or_insert(0) += 1;
        }
    }
    for (&(a, b), &n) in &edges {
        assert_eq!(n, 1, "edge {a}-{b} walked {n} times");
        assert_eq!(edges.get(&(b, a)), Some(&1), "edge {a}-{b} has no twin");
    }
    // Its volume (divergence theorem) is the stock's less the slot's.
    let volume: f64 = mesh
        .faces
        .iter()
        .map(|f| {
            let v: Vec<[f64; 3]> = f
                .vertices
                .iter()
                .map(|&i| {
                    let p = mesh.vertices[i];
                    [f64::from(p[0]), f64::from(p[1]), f64::from(p[2])]
                })
                .collect();
            (v[0][0] * (v[1][1] * v[2][2] - v[1][2] * v[2][1])
                - v[0][1] * (v[1][0] * v[2][2] - v[1][2] * v[2][0])
                + v[0][2] * (v[1][0] * v[2][1] - v[1][1] * v[2][0]))
                / 6.0
        })
        .sum();
    let slot = 4.0 * (6.0 * 20.0 + PI * 9.0);
    let expected = 40.0 * 20.0 * 10.0 - slot;
    // The mesh is the cells' columns: the part's volume, to the cells'
    // steps round the slot's ends.
    assert!(
        (volume - expected).abs() / expected < 0.005 && (volume - expected).abs() / slot < 0.01,
        "volume {volume}, expected {expected}"
    );
}

#[test]
fn the_stl_of_a_plate_with_a_slot_is_small() {
    // 60 x 40 mm at the default 0.025 mm: 3.84 million cells; a slot and
    // a hole drilled through.
    let dir = scratch("stl-size");
    let program = "G21 G90 G17\nSetPart 60 40 10\nSetTool 1 6\nT1 M6\nG0 X15 Y20 Z1\nG1 Z-5 F100\nG1 X45\nG0 Z5\nG0 X50 Y32\nG1 Z-11\nG0 Z5\nM30\n";
    std::fs::write(dir.join("plate.egc"), program).unwrap();
    let (input, output) = (dir.join("plate.egc"), dir.join("plate.stl"));
    let out = ger(&[
        "render",
        input.to_str().unwrap(),
        "-o",
        output.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let bytes = std::fs::metadata(&output).unwrap().len();
    assert!(bytes < 1_000_000, "{bytes} bytes");
    let mesh = stl_io::read_stl(&mut std::fs::File::open(&output).unwrap()).unwrap();
    mesh.validate().unwrap();
}

#[test]
fn render_refuses_what_it_cannot_do_and_leaves_files_alone() {
    let dir = scratch("refuse");
    std::fs::write(dir.join("slot.egc"), SLOT).unwrap();
    std::fs::write(dir.join("bad.egc"), "G21 G90\nG0 X<Undefined>\n").unwrap();
    std::fs::write(dir.join("old.png"), b"old").unwrap();
    let input = dir.join("slot.egc");
    let input = input.to_str().unwrap();
    let out = ger(&[
        "render",
        input,
        "-o",
        dir.join("slot.jpg").to_str().unwrap(),
    ]);
    assert_eq!(
        out.status.code(),
        Some(2),
        "an unknown format is a usage error"
    );
    let out = ger(&[
        "render",
        input,
        "-o",
        dir.join("slot.svg").to_str().unwrap(),
        "--shade",
    ]);
    assert_eq!(out.status.code(), Some(2), "--shade makes a PNG");
    let out = ger(&[
        "render",
        dir.join("bad.egc").to_str().unwrap(),
        "-o",
        dir.join("old.png").to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(std::fs::read(dir.join("old.png")).unwrap(), b"old");
    let out = ger(&[
        "render",
        input,
        "-o",
        dir.join("slot.png").to_str().unwrap(),
        "--resolution",
        "0",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(!dir.join("slot.png").exists());
}

#[test]
fn render_warns_at_the_lines_that_need_a_look() {
    let dir = scratch("warn");
    let program = "G21 G90 G17\nSetPart 40 20 5\nSetTool 1 6\nT1 M6\nG0 X10 Y10 Z1\nG1 Z-6 F100\nG0 X30\nG0 Z5\nM30\n";
    std::fs::write(dir.join("p.egc"), program).unwrap();
    let out = ger(&[
        "render",
        dir.join("p.egc").to_str().unwrap(),
        "-o",
        dir.join("p.png").to_str().unwrap(),
        "--resolution",
        "0.1",
    ]);
    assert!(out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("below the bottom of the stock") && stderr.contains(":6:"),
        "{stderr}"
    );
    assert!(
        stderr.contains("a rapid move cuts the stock") && stderr.contains(":7:"),
        "{stderr}"
    );
    assert!(
        !stderr.contains(":8:"),
        "the rapid up cuts nothing: {stderr}"
    );
}

#[test]
fn a_program_whose_rapids_run_below_its_cuts_is_told_its_z_may_be_inverted() {
    // As some Estlcam posts write it: safe height at Z-20, cuts at Z+2.
    let dir = scratch("inverted");
    let inverted = "G21 G90 G17\nSetTool 1 3\nT1 M6\nG0 Z-20\nG0 X10 Y10\nG0 Z-0.5\nG1 Z2 F100\nG0 Z-20\nG0 X20\nG0 Z-0.5\nG1 Z2\nG0 Z-20\nM30\n";
    let upright = "G21 G90 G17\nSetTool 1 3\nT1 M6\nG0 Z20\nG0 X10 Y10\nG0 Z0.5\nG1 Z-2 F100\nG0 Z20\nG0 X20\nG0 Z0.5\nG1 Z-2\nG0 Z20\nM30\n";
    for (name, program, warned) in [("inverted", inverted, true), ("upright", upright, false)] {
        let input = dir.join(format!("{name}.egc"));
        std::fs::write(&input, program).unwrap();
        let out = ger(&[
            "render",
            input.to_str().unwrap(),
            "-o",
            dir.join(format!("{name}.svg")).to_str().unwrap(),
        ]);
        assert!(out.status.success());
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(
            stderr.matches("Z may be inverted").count(),
            usize::from(warned),
            "{stderr}"
        );
        if warned {
            // Its first rapid with a known height: line 5 (line 4's starts
            // where the machine is, not known).
            let warning = &stderr[stderr.find("Z may be inverted").unwrap()..];
            assert!(
                warning.contains("6 of its 6 rapids") && warning.contains("inverted.egc:5:"),
                "{stderr}"
            );
        }
    }
}

#[test]
fn diff_shows_where_two_programs_cut_differently() {
    let dir = scratch("diff");
    std::fs::write(dir.join("a.egc"), SLOT).unwrap();
    std::fs::write(dir.join("b.egc"), SLOT.replace("X30", "X25")).unwrap();
    let run = |other: &str| {
        ger(&[
            "render",
            dir.join("a.egc").to_str().unwrap(),
            "-o",
            dir.join("d.png").to_str().unwrap(),
            "--resolution",
            "0.1",
            "--diff",
            dir.join(other).to_str().unwrap(),
        ])
    };
    let out = run("a.egc");
    assert!(String::from_utf8_lossy(&out.stderr).contains("cut the same part"));
    let out = run("b.egc");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success() && stderr.contains("cells differ, by up to 4"),
        "{stderr}"
    );
}

/// Golden SVGs: `tests/pictures/<name>.egc` drawn as `<name>.svg` (bless
/// with GER_BLESS=1 and read the diff), and each rendered with resvg.
#[test]
fn svg_goldens() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/pictures");
    let mut names: Vec<PathBuf> = std::fs::read_dir(&root)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "egc"))
        .collect();
    names.sort();
    assert!(!names.is_empty());
    let dir = scratch("svg");
    for program in names {
        let stem = program.file_stem().unwrap().to_string_lossy().into_owned();
        let out_path = dir.join(format!("{stem}.svg"));
        let mut args = vec![
            "render".to_string(),
            program.to_string_lossy().into_owned(),
            "-o".into(),
            out_path.to_string_lossy().into_owned(),
        ];
        if let Ok(extra) = std::fs::read_to_string(program.with_extension("args")) {
            args.extend(extra.split_whitespace().map(String::from));
        }
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let out = ger(&args);
        assert!(
            out.status.success(),
            "{stem}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let svg = std::fs::read_to_string(&out_path).unwrap();
        let golden = program.with_extension("svg");
        if std::env::var_os("GER_BLESS").is_some() {
            std::fs::write(&golden, &svg).unwrap();
        }
        assert_eq!(
            svg,
            std::fs::read_to_string(&golden).unwrap_or_default(),
            "{stem}: the SVG changed (GER_BLESS=1 to accept)"
        );
        // resvg reads it, and draws the path over the stock.
        let tree = resvg::usvg::Tree::from_str(&svg, &resvg::usvg::Options::default()).unwrap();
        let size = tree.size().to_int_size();
        let scale = 400.0 / size.width().max(size.height()) as f32;
        let mut pixmap = resvg::tiny_skia::Pixmap::new(
            (size.width() as f32 * scale).ceil() as u32,
            (size.height() as f32 * scale).ceil() as u32,
        )
        .unwrap();
        resvg::render(
            &tree,
            resvg::tiny_skia::Transform::from_scale(scale, scale),
            &mut pixmap.as_mut(),
        );
        // GER_PICTURES=DIR keeps the rendered pictures, to look at.
        if let Some(keep) = std::env::var_os("GER_PICTURES") {
            pixmap
                .save_png(Path::new(&keep).join(format!("{stem}.png")))
                .unwrap();
        }
        let stock = pixmap
            .pixels()
            .iter()
            .filter(|p| (p.red(), p.green(), p.blue()) == (0xf4, 0xf1, 0xea))
            .count();
        let drawn = pixmap
            .pixels()
            .iter()
            .filter(|p| p.alpha() == 255 && (p.red(), p.green(), p.blue()) != (0xf4, 0xf1, 0xea))
            .count();
        assert!(
            stock > pixmap.pixels().len() / 4,
            "{stem}: the stock is drawn"
        );
        assert!(drawn > 100, "{stem}: the path is drawn ({drawn} pixels)");
    }
}

#[test]
fn the_picture_follows_the_tip_whatever_the_tool_length() {
    // G43 moves the machine by the tool's length; the tip stays where the
    // program puts it, and that is what is cut.
    let plain =
        format!("{STOCK}SetTool 1 6 50\nT1 M6\nG0 X10 Y20 Z1\nG1 Z-2 F100\nG1 X40\nG0 Z5\nM30\n");
    let with_length = plain.replace("T1 M6\n", "T1 M6\nG43 H1\n");
    let mut sources = Sources::new();
    let file = sources.add("part.egc", with_length.clone());
    let compiled = ger::driver::tool_path(&sources, file, &CompileOptions::default(), None)
        .0
        .unwrap();
    assert!(
        compiled.moves.iter().any(|m| m.end[2] > 40.0),
        "compiled, the length is in Z"
    );
    let mut options = CompileOptions::default();
    options.lower.tip_path = true;
    let tip = ger::driver::tool_path(&sources, file, &options, None)
        .0
        .unwrap();
    assert!(
        tip.moves.iter().all(|m| m.end[2] < 10.0),
        "the tip's path has no length in it"
    );
    let (_, a) = carved(&plain, 0.1);
    let (_, b) = carved_with(&with_length, 0.1, &options);
    assert_eq!(a.z, b.z);
}

/// The cutter of a program with no tool table: the one its CAM header
/// describes (Fusion's `(T1 D=2.7 …)`, with `T1` and no `M6`), drawn at
/// that size; else an assumed 1/4 in end mill, with a warning naming it —
/// for `T1` alone, `T1 M6`, and no tool word at all.
#[test]
fn the_cutter_is_the_described_one_or_a_warning_names_the_assumed_one() {
    let fusion = "(T1  D=2.7 CR=0 - ZMIN=-1 - flat end mill)\nG21 G90\nT1\nS10000 M3\n\
                  G0 X0 Y10 Z5\nG1 Z-1 F300\nG1 X40\nG0 Z5\nM30\n";
    let mut sources = Sources::new();
    let file = sources.add("part.nc", fusion.to_string());
    let (path, _) = ger::driver::tool_path(&sources, file, &CompileOptions::default(), None);
    let path = path.unwrap();
    let options = RenderOptions {
        resolution: Some(0.05),
        described: ger::render::described::described_tools(fusion, path.units),
        ..Default::default()
    };
    let scene = Scene::new(&path, &options).unwrap();
    let mut grid = scene.grid().unwrap();
    scene.carve(&mut grid, &path, &|_, _| {});
    // The slot is 2.7 wide: cut 1.2 off its centre line, not 1.5 (a
    // 6.35 mm cutter would cut 3 off it).
    assert!(sample(&grid, 20.0, 11.2).0 < -0.9);
    assert!(sample(&grid, 20.0, 11.5).0 > -0.01);
    assert!(sample(&grid, 20.0, 8.5).0 > -0.01);
    let notes: Vec<String> = scene
        .warnings
        .iter()
        .map(|w| w.to_diagnostic().message)
        .collect();
    assert_eq!(notes.len(), 1, "{notes:?}");
    assert!(notes[0].contains("comment on line 1"), "{notes:?}");

    let dir = scratch("assumed-cutter");
    for (program, says) in [
        (
            "G21\nT1\nG0 X0 Y0 Z1\nG1 Z-1 F100\nX10\nM30\n",
            "tool 1's size is not known",
        ),
        (
            "G21\nT2 M6\nG0 X0 Y0 Z1\nG1 Z-1 F100\nX10\nM30\n",
            "tool 2's size is not known",
        ),
        (
            "G21\nG0 X0 Y0 Z1\nG1 Z-1 F100\nX10\nM30\n",
            "the program names no tool",
        ),
    ] {
        std::fs::write(dir.join("p.nc"), program).unwrap();
        let out = ger(&[
            "render",
            dir.join("p.nc").to_str().unwrap(),
            "-o",
            dir.join("p.svg").to_str().unwrap(),
        ]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{stderr}");
        assert!(stderr.contains(says), "{program}: {stderr}");
        assert!(
            stderr.contains("assumed 1/4 in (6.35 mm) flat end mill"),
            "{stderr}"
        );
        assert!(stderr.contains("--tool-table"), "{stderr}");
    }
}

/// Issue 48: a program that cuts only in X and Y, never setting Z, is told
/// so in those words.
#[test]
fn a_program_that_never_moves_z_is_told_so() {
    let dir = scratch("never-z");
    let part = dir.join("part.egc");
    std::fs::write(&part, "G21 G90\nG0 X0 Y0\nG1 X10 F100\nM30\n").unwrap();
    let out = ger(&[
        "render",
        part.to_str().unwrap(),
        "-o",
        dir.join("part.png").to_str().unwrap(),
    ]);
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("the program never moves Z"), "{stderr}");
}
