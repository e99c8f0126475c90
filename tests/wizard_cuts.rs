//! The cutting wizards on the heightmap `ger render` carves (issue 48).
//! Entries: over every standard cutting wizard and each of its entry
//! modes, the tool never goes down into material it has not cut yet faster
//! than the plunge feed. Checked move by move: a move that sinks faster
//! than the plunge feed (a rapid, or a feed whose vertical part is quicker)
//! must end where the moves before it have already cut the material under
//! the whole cutter; the checker itself is checked on plunges at the
//! cutting feed. Shapes: Profile, Chamfer and Drill against the drawing
//! (volumes, no cut inside the part, the outline within a cell, the tabs
//! standing at their height).

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use ger::driver::CompileOptions;
use ger::render::carve::{self, Grid};
use ger::render::{RenderOptions, Scene};
use ger::source::Sources;
use ger::toolpath::{MoveKind, ToolPath};
use ger::wizard::{standard_library, Library, WizardEngine};
use std::f64::consts::PI;

/// The stock under every program: 100 x 80 x 10 mm, its top at Z0.
const STOCK: &str =
    "G21 G90 G17\nSetPart 100 80 10\nSetTool 1 6\nSetTool 2 12 50 \"vee90\"\nF600\n";
/// The cutting feed of every program, and a third of it.
const PLUNGE: f64 = 200.0;
/// Cell of the heightmap (mm).
const CELL: f64 = 0.1;

fn compiled(program: &str) -> ToolPath {
    let mut sources = Sources::new();
    let file = sources.add("part.egc", program.to_string());
    let mut engine = WizardEngine::new(Library::new(standard_library(), &mut sources));
    let (path, diagnostics) = ger::driver::tool_path(
        &sources,
        file,
        &CompileOptions::default(),
        Some(&mut engine),
    );
    path.unwrap_or_else(|| panic!("{}", ger::diagnostic::render(&sources, &diagnostics)))
}

/// The highest cell under the cutter's face (within its radius, less two
/// cells for the rim) at `(x, y)`.
fn highest_under(grid: &Grid, x: f64, y: f64, radius: f64) -> f64 {
    let f = grid.frame;
    let reach = radius - 2.0 * f.cell;
    let mut top = f64::NEG_INFINITY;
    for j in 0..f.ny {
        let cy = f.center_y(j);
        if (cy - y).abs() > reach {
            continue;
        }
        for i in 0..f.nx {
            let cx = f.center_x(i);
            if (cx - x).hypot(cy - y) <= reach {
                top = top.max(f64::from(grid.at(i, j)));
            }
        }
    }
    top
}

/// Each move that sinks faster than `plunge` into material not cut by the
/// moves before it: (its source line, its vertical speed, how deep into
/// uncut material it ends).
fn fast_entries(program: &str, plunge: f64) -> Vec<(usize, f64, f64)> {
    let path = compiled(program);
    let options = RenderOptions {
        resolution: Some(CELL),
        ..Default::default()
    };
    let scene = Scene::new(&path, &options).unwrap();
    let mut grid = scene.grid().unwrap();
    let mut carved = 0;
    let mut found = Vec::new();
    for (index, m) in path.moves.iter().enumerate() {
        let drop = m.start[2] - m.end[2];
        if drop <= 1e-9 {
            continue;
        }
        let speed = match m.kind {
            MoveKind::Rapid => f64::INFINITY,
            MoveKind::Feed | MoveKind::Arc(_) => m.state.feed * drop / m.length(),
        };
        if speed <= plunge * (1.0 + 1e-9) {
            continue;
        }
        let upto = scene
            .segments
            .iter()
            .position(|s| s.move_index >= index)
            .unwrap_or(scene.segments.len());
        if upto > carved {
            carve::carve(
                &mut grid,
                &scene.segments[carved..upto],
                &scene.cutters,
                &|_, _| {},
            );
            carved = upto;
        }
        let radius =
            scene.cutters[scene.segments[upto.min(scene.segments.len() - 1)].cutter].radius;
        let above = highest_under(&grid, m.end[0], m.end[1], radius) - m.end[2];
        if above > 1e-3 {
            found.push((m.span.line as usize, speed, above));
        }
    }
    found
}

fn assert_enters_gently(program: &str) {
    let program = format!("{STOCK}G0 X50 Y40 Z5\n{program}\nM30\n");
    let found = fast_entries(&program, PLUNGE);
    assert!(
        found.is_empty(),
        "moves going down into uncut material faster than the plunge feed \
         (line, mm/min, mm into material): {found:?}\n{program}"
    );
}

#[test]
fn the_checker_finds_a_plunge_at_the_cutting_feed() {
    let program = format!("{STOCK}G0 X50 Y40 Z5\nG1 Z-2\nG1 X60\nG1 Z-4 F200\nG0 Z5\nM30\n");
    let found = fast_entries(&program, PLUNGE);
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(
        found[0].0,
        STOCK.lines().count() + 2,
        "the line of `G1 Z-2`"
    );
    assert!((found[0].2 - 2.0).abs() < 1e-3, "{found:?}");
}

#[test]
fn the_checker_finds_a_wizard_plunging_at_the_cutting_feed() {
    // a plunge feed as fast as the cutting feed: what every pocket did before
    let program = format!("{STOCK}G0 X50 Y40 Z5\nPocket 40 30 5 2 0.4 0 0 600 \"plunge\"\nM30\n");
    let found = fast_entries(&program, PLUNGE);
    assert_eq!(found.len(), 3, "one plunge per depth pass: {found:?}");
}

#[test]
fn pockets_enter_gently_in_every_mode() {
    for entry in ["auto", "helix", "ramp", "plunge"] {
        for sizes in ["40 30", "20 20", "40 8"] {
            if entry == "helix" && sizes == "40 8" {
                continue;
            }
            assert_enters_gently(&format!("Pocket {sizes} 5 2 0.4 0 0 0 \"{entry}\""));
            assert_enters_gently(&format!(
                "Pocket {sizes} 5 2 0.4 0 0 0 \"{entry}\" 3 0.5 \"conventional\""
            ));
        }
    }
}

#[test]
fn circle_pockets_enter_gently_in_every_mode() {
    for entry in ["auto", "helix", "ramp", "plunge"] {
        assert_enters_gently(&format!("CirclePocket 30 5 2 0.4 0 0 0 \"{entry}\""));
        assert_enters_gently(&format!(
            "CirclePocket 12 4 1.5 0.4 0 0 0 \"{entry}\" 3 0.3 \"conventional\""
        ));
    }
}

#[test]
fn slots_enter_gently_in_every_mode() {
    for entry in ["auto", "helix", "ramp", "plunge"] {
        assert_enters_gently(&format!("Slot 30 12 5 30 2 0 0.4 0 0 \"{entry}\""));
        if entry != "helix" {
            assert_enters_gently(&format!("Slot 30 6 3 0 1 0 0.4 0 0 \"{entry}\""));
        }
    }
}

#[test]
fn helix_facing_and_spiral_enter_gently() {
    assert_enters_gently("Helix 20 6 1.5");
    assert_enters_gently("Helix 7 3");
    assert_enters_gently("G0 X10 Y10\nFacing 60 40 1");
    for entry in ["auto", "helix", "ramp", "plunge"] {
        assert_enters_gently(&format!("spiral(3, 15, 50, 40, -2, 5, 0, 0, \"{entry}\")"));
    }
}

#[test]
fn profiles_and_chamfers_enter_gently() {
    for entry in ["auto", "plunge"] {
        for side in ["outside", "inside"] {
            assert_enters_gently(&format!(
                "Profile 60 40 6 5 \"{side}\" 2 3 8 2 0 0 \"climb\" 0 0 0 \"{entry}\""
            ));
            assert_enters_gently(&format!(
                "Profile 30 30 5 15 \"{side}\" 2 0 0 0 0.5 0 \"conventional\" 0 0 0 \"{entry}\""
            ));
            assert_enters_gently(&format!(
                "M6 T2\nChamfer 60 40 2 5 \"{side}\" \"climb\" 0 0 0 \"{entry}\""
            ));
        }
    }
}

/// Compile and carve `program` on the 100 x 80 x 10 stock at `CELL`.
fn carved(program: &str) -> Grid {
    let path = compiled(&format!("{STOCK}{program}\nM30\n"));
    let options = RenderOptions {
        resolution: Some(CELL),
        ..Default::default()
    };
    let scene = Scene::new(&path, &options).unwrap();
    let mut grid = scene.grid().unwrap();
    scene.carve(&mut grid, &path, &|_, _| {});
    grid
}

/// Signed distance from `(x, y)` to the rounded rectangle `w` x `h` with
/// corners `r` centred on (50, 40): negative inside.
fn from_outline(x: f64, y: f64, w: f64, h: f64, r: f64) -> f64 {
    let qx = (x - 50.0).abs() - (w / 2.0 - r);
    let qy = (y - 40.0).abs() - (h / 2.0 - r);
    qx.max(0.0).hypot(qy.max(0.0)) + qx.max(qy).min(0.0) - r
}

/// Each cell's height with its signed distance from the outline.
fn cells(grid: &Grid, w: f64, h: f64, r: f64) -> Vec<(f64, f64)> {
    let f = grid.frame;
    let mut out = Vec::with_capacity(f.nx * f.ny);
    for j in 0..f.ny {
        for i in 0..f.nx {
            let d = from_outline(f.center_x(i), f.center_y(j), w, h, r);
            out.push((d, f64::from(grid.at(i, j))));
        }
    }
    out
}

fn assert_near(got: f64, expected: f64, relative: f64, what: &str) {
    assert!(
        ((got - expected) / expected).abs() < relative,
        "{what}: {got}, expected {expected} ({:+.3}%)",
        (got / expected - 1.0) * 100.0
    );
}

#[test]
fn an_outside_profile_cuts_its_groove_and_nothing_of_the_part() {
    let (w, h, r, depth, tool) = (60.0, 40.0, 5.0, 6.0, 6.0);
    let grid = carved("G0 X50 Y40 Z5\nProfile 60 40 6 5 \"outside\" 2 0 0 0 0.5");
    let perimeter = 2.0 * (w + h) - 8.0 * r + 2.0 * PI * r;
    let band = tool + 0.5;
    assert_near(
        grid.removed_volume(),
        (perimeter * band + PI * band * band) * depth,
        0.005,
        "removed volume",
    );
    for (d, z) in cells(&grid, w, h, r) {
        if d < -CELL {
            assert_eq!(z, 0.0, "the part is cut {d} inside its outline");
        } else if d > CELL && d < band - CELL {
            assert!((z + depth).abs() < 1e-3, "{z} at {d} from the outline");
        } else if d > band + CELL {
            assert_eq!(z, 0.0, "cut {d} outside the outline");
        }
    }
}

#[test]
fn an_inside_circle_profile_cuts_its_ring() {
    let (radius, depth, tool) = (15.0, 5.0, 6.0);
    let grid = carved("G0 X50 Y40 Z5\nProfile 30 30 5 15 \"inside\" 2.5");
    let inner = radius - tool;
    assert_near(
        grid.removed_volume(),
        PI * (radius * radius - inner * inner) * depth,
        0.005,
        "removed volume",
    );
    for (d, z) in cells(&grid, 30.0, 30.0, radius) {
        if d > CELL {
            assert_eq!(z, 0.0, "cut {d} outside the hole");
        } else if d < -CELL && d > -tool + CELL {
            assert!((z + depth).abs() < 1e-3, "{z} at {d} from the outline");
        }
    }
}

/// Area of one tab standing on a straight side, between `lo` and `hi`
/// from the part's edge: what neither the finishing path (a tool radius
/// out) nor the roughing path (`allowance` further) reaches, each with a
/// gap of tab_w + tool around the tab, added up on a fine grid.
fn tab_area(tool: f64, allowance: f64, tab_w: f64, lo: f64, hi: f64) -> f64 {
    let (r, gap) = (tool / 2.0, (tab_w + tool) / 2.0);
    let reached = |u: f64, v: f64, path: f64| {
        let along = (gap - u.abs()).max(0.0);
        along.hypot(v - path) <= r
    };
    let step = 0.005;
    let mut area = 0.0;
    let mut v = lo + step / 2.0;
    while v < hi {
        let mut u = -gap + step / 2.0;
        while u < gap {
            if !reached(u, v, r) && !reached(u, v, r + allowance) {
                area += step * step;
            }
            u += step;
        }
        v += step;
    }
    area
}

#[test]
fn a_profile_leaves_its_tabs_standing_at_their_height() {
    let (w, h, r, depth, tool, tab_w, tab_h, allowance) =
        (60.0, 40.0, 5.0, 6.0, 6.0, 8.0, 2.0, 0.5);
    // two tabs: the middles of the left and right sides
    let grid = carved(&format!(
        "G0 X50 Y40 Z5\nProfile {w} {h} {depth} {r} \"outside\" 2 2 {tab_w} {tab_h} {allowance}"
    ));
    let band = tool + allowance;
    let z_tab = -depth + tab_h;
    let mut tab_cells = 0;
    for (d, z) in cells(&grid, w, h, r) {
        if d < -CELL {
            assert_eq!(z, 0.0, "the part is cut {d} inside its outline");
        } else if d > CELL && d < band - CELL {
            if (z - z_tab).abs() < 1e-3 {
                tab_cells += 1;
            } else {
                assert!((z + depth).abs() < 1e-3, "{z} at {d} from the outline");
            }
        }
    }
    assert_near(
        f64::from(tab_cells) * CELL * CELL,
        2.0 * tab_area(tool, allowance, tab_w, CELL, band - CELL),
        0.03,
        "area of the tabs",
    );
}

#[test]
fn a_chamfer_cuts_a_vee_of_its_width_along_the_edge() {
    let (w, h, r, chamfer) = (60.0, 40.0, 5.0, 2.0);
    let grid = carved(&format!(
        "M6 T2\nG0 X50 Y40 Z5\nChamfer {w} {h} {chamfer} {r}"
    ));
    // on a flat top, a vee groove: chamfer wide on each side, as deep
    let perimeter = 2.0 * (w + h) - 8.0 * r + 2.0 * PI * r;
    assert_near(
        grid.removed_volume(),
        chamfer * chamfer * perimeter,
        0.01,
        "removed volume",
    );
    for (d, z) in cells(&grid, w, h, r) {
        let expected = (d.abs() - chamfer).min(0.0);
        assert!(
            (z - expected).abs() < 1.5 * CELL,
            "{z} at {d} from the edge, expected {expected}"
        );
    }
}

#[test]
fn drill_keeps_its_cycles_and_drills_every_hole() {
    let program = "G0 X20 Y20 Z5\nS1000 M3\nDrill 6 3 2 10 15 2";
    let grid = carved(program);
    assert_near(
        grid.removed_volume(),
        6.0 * PI * 9.0 * 6.0,
        0.005,
        "removed volume",
    );
    let mut sources = Sources::new();
    let file = sources.add("part.egc", format!("{STOCK}{program}\nM30\n"));
    let mut engine = WizardEngine::new(Library::new(standard_library(), &mut sources));
    let mut options = CompileOptions::default();
    options.lower.keep_cycles = true;
    options.emit.target = ger::emit::Target::LinuxCnc;
    let compiled = ger::driver::compile(&sources, file, &options, Some(&mut engine));
    let text = compiled.output.unwrap_or_else(|| {
        panic!(
            "{}",
            ger::diagnostic::render(&sources, &compiled.diagnostics)
        )
    });
    // one normalised cycle block per hole
    assert_eq!(text.matches("G83").count(), 6, "{text}");
}
