//! Standard-library and example wizards, checked by geometry: each program
//! is compiled by the real binary, its output run through rs274
//! (`support/rs274.rs`), and the tool path measured —
//! hole positions, pocket containment and floor coverage, spiral radii,
//! Bézier end points — never the text.
//!
//! Like `tests/oracle.rs`: without rs274 they fail under CI and are
//! ignored elsewhere.

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use ger::toolpath::MoveKind;
use libtest_mimic::{Arguments, Failed, Trial};

mod support;
use support::{manifest, rs274};

type Point = [f64; 3];

/// A move of the tool path (machine coordinates, mm).
#[derive(Debug, Clone)]
struct Move {
    kind: String,
    start: Point,
    end: Point,
    center: Option<Point>,
    /// Arcs: degrees swept, positive counter-clockwise about the normal.
    sweep: f64,
}

impl Move {
    fn cuts(&self) -> bool {
        self.kind != "rapid"
    }
}

/// Compile `program` (with the repository's `wizards/` beside it) and
/// return rs274's tool path of the output.
fn tool_path(name: &str, program: &str) -> Result<Vec<Move>, Failed> {
    let work = std::env::temp_dir().join(format!("ger-wizards-{}-{name}", std::process::id()));
    let beside = work.join("wizards");
    std::fs::create_dir_all(&beside).map_err(|e| e.to_string())?;
    for entry in std::fs::read_dir(manifest().join("wizards")).map_err(|e| e.to_string())? {
        let path = entry.map_err(|e| e.to_string())?.path();
        if path.extension().is_some_and(|x| x == "rhai") {
            std::fs::copy(&path, beside.join(path.file_name().unwrap()))
                .map_err(|e| e.to_string())?;
        }
    }
    let part = work.join("part.egc");
    let out = work.join("part.nc");
    std::fs::write(&part, program).map_err(|e| e.to_string())?;
    support::compile(&part, &out)?;
    let result = rs274::tool_path(&out, &[]);
    let _ = std::fs::remove_dir_all(&work);
    let reference = result.map_err(|e| format!("rs274 rejected the output: {e}"))?;
    Ok(reference
        .path
        .moves
        .iter()
        .map(|m| {
            let (kind, center, sign) = match m.kind {
                MoveKind::Rapid => ("rapid", None, 0.0),
                MoveKind::Feed => ("feed", None, 0.0),
                MoveKind::Arc(a) => ("arc", Some(a.center), if a.clockwise { -1.0 } else { 1.0 }),
            };
            Move {
                kind: kind.to_string(),
                start: m.start,
                end: m.end,
                center,
                sweep: m.sweep().to_degrees() * sign,
            }
        })
        .collect())
}

/// Distance from `p` to the segment `a`–`b` in XY.
fn segment_distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let t = if len2 == 0.0 {
        0.0
    } else {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0)
    };
    (p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dy)
}

fn near(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

/// XY of the bottoms of plunges: feed moves that go straight down to `z`.
fn holes(path: &[Move], z: f64) -> Vec<[f64; 2]> {
    path.iter()
        .filter(|m| {
            m.cuts()
                && near(m.end[2], z, 1e-3)
                && near(m.start[0], m.end[0], 1e-6)
                && near(m.start[1], m.end[1], 1e-6)
                && m.start[2] > m.end[2]
        })
        .map(|m| [m.end[0], m.end[1]])
        .collect()
}

fn same_holes(got: &[[f64; 2]], want: &[[f64; 2]]) -> Result<(), Failed> {
    if got.len() != want.len() {
        return Err(format!("{} holes, expected {}: {got:?}", got.len(), want.len()).into());
    }
    for (g, w) in got.iter().zip(want) {
        if !(near(g[0], w[0], 2e-3) && near(g[1], w[1], 2e-3)) {
            return Err(format!("hole at {g:?}, expected {w:?} (in order)\nall: {got:?}").into());
        }
    }
    Ok(())
}

/// Points along the cutting moves at depth `z`, every `step` mm (arcs
/// followed along their circle).
fn floor_points(path: &[Move], z: f64, step: f64) -> Vec<[f64; 2]> {
    let mut pts = Vec::new();
    for m in path
        .iter()
        .filter(|m| m.cuts() && near(m.start[2], z, 1e-3) && near(m.end[2], z, 1e-3))
    {
        match (m.kind.as_str(), m.center) {
            ("arc", Some(c)) => {
                let r = (m.start[0] - c[0]).hypot(m.start[1] - c[1]);
                let a0 = (m.start[1] - c[1]).atan2(m.start[0] - c[0]);
                let sweep = m.sweep.to_radians();
                let n = ((sweep.abs() * r / step).ceil() as usize).max(8);
                for i in 0..=n {
                    let a = a0 + sweep * i as f64 / n as f64;
                    pts.push([c[0] + r * a.cos(), c[1] + r * a.sin()]);
                }
            }
            _ => {
                let len = (m.end[0] - m.start[0]).hypot(m.end[1] - m.start[1]);
                let n = ((len / step).ceil() as usize).max(1);
                for i in 0..=n {
                    let t = i as f64 / n as f64;
                    pts.push([
                        m.start[0] + (m.end[0] - m.start[0]) * t,
                        m.start[1] + (m.end[1] - m.start[1]) * t,
                    ]);
                }
            }
        }
    }
    pts
}

/// Every grid point of the region (`inside`) is within `radius` of the
/// tool centre's path at the floor: the floor is cleared.
fn covered(
    path: &[Move],
    z: f64,
    radius: f64,
    bbox: [f64; 4],
    inside: impl Fn(f64, f64) -> bool,
) -> Result<(), Failed> {
    let pts = floor_points(path, z, 0.25);
    if pts.is_empty() {
        return Err(format!("no cutting moves at Z{z}").into());
    }
    let mut y = bbox[1];
    while y <= bbox[3] + 1e-9 {
        let mut x = bbox[0];
        while x <= bbox[2] + 1e-9 {
            if inside(x, y) {
                let d = pts
                    .iter()
                    .map(|p| (p[0] - x).hypot(p[1] - y))
                    .fold(f64::INFINITY, f64::min);
                if d > radius + 0.15 {
                    return Err(format!("floor point ({x:.2}, {y:.2}) is {d:.3} mm from the tool centre path (tool radius {radius})").into());
                }
            }
            x += 0.5;
        }
        y += 0.5;
    }
    Ok(())
}

/// A named check.
type Case = (&'static str, fn() -> Result<(), Failed>);

fn cases() -> Vec<Case> {
    vec![
        ("holesLine", || {
            let p = tool_path(
                "holesline",
                "G21 G90 G17\nG0 X0 Y0 Z10\nF200\nholesLine(4, 10, 5, 20, 30, -3, 5)\nM30\n",
            )?;
            let want: Vec<[f64; 2]> = (0..4)
                .map(|k| [20.0 + 10.0 * k as f64, 30.0 + 5.0 * k as f64])
                .collect();
            same_holes(&holes(&p, -3.0), &want)?;
            // Between holes the tool travels at Zseg.
            for m in p
                .iter()
                .filter(|m| m.kind == "rapid" && (m.start[0] != m.end[0] || m.start[1] != m.end[1]))
            {
                if m.start[2] < 5.0 - 1e-3 {
                    return Err(format!("rapid across XY below Zseg: {m:?}").into());
                }
            }
            Ok(())
        }),
        ("circArray", || {
            let p = tool_path(
                "circarray",
                "G21 G90 G17\nG0 X0 Y0 Z10\nF200\ncircArray(6, 25, 50, 40, -2, 5)\nM30\n",
            )?;
            let want: Vec<[f64; 2]> = (0..6)
                .map(|k| {
                    let a = (60.0 * k as f64).to_radians();
                    [50.0 + 25.0 * a.cos(), 40.0 + 25.0 * a.sin()]
                })
                .collect();
            same_holes(&holes(&p, -2.0), &want)
        }),
        ("BoltCircle", || {
            let p = tool_path(
                "boltcircle",
                "G21 G90 G17\nG0 X100 Y50 Z10\nF200\nBoltCircle 8 30 4\nM30\n",
            )?;
            let want: Vec<[f64; 2]> = (0..8)
                .map(|k| {
                    let a = (45.0 * k as f64).to_radians();
                    [100.0 + 30.0 * a.cos(), 50.0 + 30.0 * a.sin()]
                })
                .collect();
            same_holes(&holes(&p, -4.0), &want)
        }),
        ("Pocket", || {
            let p = tool_path(
                "pocket",
                "SetTool 1 6\nG21 G90 G17\nG0 X50 Y40 Z10\nF400\nPocket 40 30 5 2\nM30\n",
            )?;
            let r = 3.0;
            let (x0, x1, y0, y1) = (30.0 + r, 70.0 - r, 25.0 + r, 55.0 - r);
            let min_z = p.iter().map(|m| m.end[2]).fold(f64::INFINITY, f64::min);
            if !near(min_z, -5.0, 1e-3) {
                return Err(format!("deepest point Z{min_z}, expected -5").into());
            }
            for m in p.iter().filter(|m| m.end[2] < -1e-6 || m.start[2] < -1e-6) {
                for q in [m.start, m.end] {
                    if q[0] < x0 - 1e-3 || q[0] > x1 + 1e-3 || q[1] < y0 - 1e-3 || q[1] > y1 + 1e-3
                    {
                        return Err(format!(
                            "tool centre {q:?} outside the pocket inset by the radius"
                        )
                        .into());
                    }
                }
                // A rapid straight up out of the pocket is fine; sideways or
                // down inside the material is not.
                let vertical_up = near(m.start[0], m.end[0], 1e-6)
                    && near(m.start[1], m.end[1], 1e-6)
                    && m.end[2] > m.start[2];
                if m.kind == "rapid" && !vertical_up {
                    return Err(format!("rapid inside the material: {m:?}").into());
                }
            }
            // What a round tool can reach: the pocket with its corners
            // rounded by the tool radius.
            let reachable = |x: f64, y: f64| {
                let dx = (x0 - x).max(x - x1).max(0.0);
                let dy = (y0 - y).max(y - y1).max(0.0);
                dx.hypot(dy) <= r
            };
            covered(&p, -5.0, r, [30.0, 25.0, 70.0, 55.0], reachable)
        }),
        ("CirclePocket", || {
            let p = tool_path(
                "circlepocket",
                "SetTool 1 6\nG21 G90 G17\nG0 X50 Y40 Z10\nF400\nCirclePocket 30 4 2\nM30\n",
            )?;
            let limit = 15.0 - 3.0;
            for m in p.iter().filter(|m| m.end[2] < -1e-6) {
                let d = (m.end[0] - 50.0).hypot(m.end[1] - 40.0);
                if d > limit + 1e-3 {
                    return Err(format!(
                        "tool centre {:?} is {d} from the centre (limit {limit})",
                        m.end
                    )
                    .into());
                }
            }
            covered(&p, -4.0, 3.0, [35.0, 25.0, 65.0, 55.0], |x, y| {
                (x - 50.0).hypot(y - 40.0) <= 15.0
            })
        }),
        ("CirclePocket under G90.1", || {
            // The wizard's arc centres are relative whatever the caller's
            // mode; the caller's G90.1 holds again after it (the last arc's
            // centre given as coordinates).
            let program = |centers: &str, last_arc: &str| {
                format!(
                    "SetTool 1 6\nG21 G90 G17\nG0 X50 Y40 Z10\nF400\n{centers}\n\
                     CirclePocket 30 4 2\nG0 X50 Y40\nG1 Z-1\n{last_arc}\nM30\n"
                )
            };
            let relative = tool_path("pocket-g911", &program("G91.1", "G2 X60 Y40 I5 J0"))?;
            let absolute = tool_path("pocket-g901", &program("G90.1", "G2 X60 Y40 I55 J40"))?;
            if relative.len() != absolute.len() {
                return Err(
                    format!("{} moves, {} under G90.1", relative.len(), absolute.len()).into(),
                );
            }
            let same = |a: Point, b: Point| (0..3).all(|i| near(a[i], b[i], 1e-6));
            for (a, b) in relative.iter().zip(&absolute) {
                let centres = match (a.center, b.center) {
                    (Some(x), Some(y)) => same(x, y),
                    (x, y) => x.is_none() && y.is_none(),
                };
                if a.kind != b.kind || !same(a.start, b.start) || !same(a.end, b.end) || !centres {
                    return Err(format!("{a:?}\nunder G90.1: {b:?}").into());
                }
            }
            match relative.last() {
                Some(m)
                    if m.kind == "arc" && m.center.is_some_and(|c| same(c, [55.0, 40.0, -1.0])) =>
                {
                    Ok(())
                }
                m => Err(format!("the last move is not the arc about X55 Y40: {m:?}").into()),
            }
        }),
        ("spiral", || {
            let p = tool_path(
                "spiral",
                "SetTool 1 3\nG21 G90 G17\nG0 X0 Y0 Z10\nF300\nspiral(3, 15, 50, 40, -1, 5)\nM30\n",
            )?;
            let cut: Vec<&Move> = p
                .iter()
                .filter(|m| m.cuts() && near(m.end[2], -1.0, 1e-3) && near(m.start[2], -1.0, 1e-3))
                .collect();
            // the spiral starts where the entry (a helix) comes back to the centre
            let first = cut
                .iter()
                .rposition(|m| near(m.end[0], 50.0, 1e-6) && near(m.end[1], 40.0, 1e-6))
                .map_or(0, |i| i + 1);
            let cut = &cut[first..];
            if cut.len() < 20 {
                return Err(format!("only {} spiral segments", cut.len()).into());
            }
            // Archimedean: the radius grows by `Pitch` per turn, from 0 to Rext.
            let mut turned = 0.0f64;
            let mut prev = [cut[0].start[0] - 50.0, cut[0].start[1] - 40.0];
            for m in cut {
                let v = [m.end[0] - 50.0, m.end[1] - 40.0];
                let (a0, a1) = (prev[1].atan2(prev[0]), v[1].atan2(v[0]));
                let mut da = a1 - a0;
                while da > std::f64::consts::PI {
                    da -= std::f64::consts::TAU;
                }
                while da < -std::f64::consts::PI {
                    da += std::f64::consts::TAU;
                }
                if prev[0].hypot(prev[1]) > 1e-6 {
                    turned += da.abs();
                }
                let r = v[0].hypot(v[1]);
                let expected = 3.0 * turned / std::f64::consts::TAU;
                if r > 0.5 && !near(r, expected, 0.1) {
                    return Err(format!(
                        "radius {r:.3} after {:.1} turns, expected {expected:.3}",
                        turned / std::f64::consts::TAU
                    )
                    .into());
                }
                prev = v;
            }
            let end = cut.last().unwrap().end;
            let r_end = (end[0] - 50.0).hypot(end[1] - 40.0);
            if !near(r_end, 15.0, 2e-3) {
                return Err(format!("spiral ends at radius {r_end}, expected 15").into());
            }
            Ok(())
        }),
        ("Bezier", || {
            let p = tool_path(
                "bezier",
                "G21 G90 G17\nG0 X0 Y0 Z1\nG1 Z-1 F300\nBezier 10 30 40 30 50 0 0.01\nM30\n",
            )?;
            let cut: Vec<&Move> = p
                .iter()
                .filter(|m| m.cuts() && near(m.end[2], -1.0, 1e-3) && near(m.start[2], -1.0, 1e-3))
                .collect();
            let end = cut.last().ok_or("no Bézier moves")?.end;
            if !(near(end[0], 50.0, 1e-3) && near(end[1], 0.0, 1e-3)) {
                return Err(format!("Bézier ends at {end:?}, expected (50, 0)").into());
            }
            // Every vertex lies on the curve B(t) (within the tolerance).
            let curve = |t: f64| {
                let u = 1.0 - t;
                let b = [u * u * u, 3.0 * u * u * t, 3.0 * u * t * t, t * t * t];
                [
                    b[1] * 10.0 + b[2] * 40.0 + b[3] * 50.0,
                    b[1] * 30.0 + b[2] * 30.0,
                ]
            };
            let samples: Vec<[f64; 2]> = (0..=4000).map(|i| curve(i as f64 / 4000.0)).collect();
            for m in &cut {
                let d = samples
                    .iter()
                    .map(|s| (s[0] - m.end[0]).hypot(s[1] - m.end[1]))
                    .fold(f64::INFINITY, f64::min);
                if d > 0.02 {
                    return Err(format!("vertex {:?} is {d:.4} mm off the curve", m.end).into());
                }
            }
            if cut.len() < 10 {
                return Err(format!("only {} segments for a 0.01 mm tolerance", cut.len()).into());
            }
            Ok(())
        }),
        ("Helix", || {
            let p = tool_path(
                "helix",
                "SetTool 1 6\nG21 G90 G17\nG0 X50 Y40 Z10\nF300\nHelix 20 6 1.5\nM30\n",
            )?;
            let min_z = p.iter().map(|m| m.end[2]).fold(f64::INFINITY, f64::min);
            if !near(min_z, -6.0, 1e-3) {
                return Err(format!("bottom at Z{min_z}, expected -6").into());
            }
            for m in p.iter().filter(|m| m.end[2] < -1e-6) {
                let d = (m.end[0] - 50.0).hypot(m.end[1] - 40.0);
                if d > 7.0 + 1e-3 {
                    return Err(
                        format!("tool centre {:?} outside the bore (limit 7)", m.end).into(),
                    );
                }
            }
            if !p
                .iter()
                .any(|m| m.kind == "arc" && m.start[2] > m.end[2] + 0.1)
            {
                return Err("no helical arcs".into());
            }
            Ok(())
        }),
        ("Slot", || {
            let p = tool_path(
                "slot",
                "SetTool 1 6\nG21 G90 G17\nG0 X20 Y30 Z10\nF300\nSlot 40 10 3 30\nM30\n",
            )?;
            let (a, b) = (
                [20.0, 30.0],
                [
                    20.0 + 40.0 * 30f64.to_radians().cos(),
                    30.0 + 40.0 * 30f64.to_radians().sin(),
                ],
            );
            let to_axis = |x: f64, y: f64| segment_distance([x, y], a, b);
            let min_z = p.iter().map(|m| m.end[2]).fold(f64::INFINITY, f64::min);
            if !near(min_z, -3.0, 1e-3) {
                return Err(format!("bottom at Z{min_z}, expected -3").into());
            }
            for m in p.iter().filter(|m| m.end[2] < -1e-6) {
                let d = to_axis(m.end[0], m.end[1]);
                if d > 5.0 - 3.0 + 1e-3 {
                    return Err(format!(
                        "tool centre {:?} is {d} from the slot's axis (limit 2)",
                        m.end
                    )
                    .into());
                }
            }
            covered(&p, -3.0, 3.0, [10.0, 20.0, 60.0, 55.0], |x, y| {
                to_axis(x, y) <= 5.0
            })
        }),
        ("Facing", || {
            let p = tool_path(
                "facing",
                "SetTool 1 10\nG21 G90 G17\nG0 X0 Y0 Z10\nF600\nFacing 50 30 0.5\nM30\n",
            )?;
            // Every plunge happens off the face.
            for m in p.iter().filter(|m| m.cuts() && m.end[2] < m.start[2]) {
                if (0.0..=50.0).contains(&m.end[0]) && (0.0..=30.0).contains(&m.end[1]) {
                    return Err(format!("plunge onto the face at {:?}", m.end).into());
                }
            }
            covered(&p, -0.5, 5.0, [0.0, 0.0, 50.0, 30.0], |_, _| true)
        }),
        ("EngraveGrid (user wizard beside the part)", || {
            let p = tool_path(
                "engravegrid",
                "G21 G90 G17\nG0 X5 Y5 Z10\nF200\nEngraveGrid 3 2 10 0.2\nM30\n",
            )?;
            let cuts: Vec<&Move> = p
                .iter()
                .filter(|m| m.cuts() && near(m.start[2], -0.2, 1e-3) && near(m.end[2], -0.2, 1e-3))
                .collect();
            let on_cut = |x: f64, y: f64| {
                cuts.iter().any(|m| {
                    segment_distance([x, y], [m.start[0], m.start[1]], [m.end[0], m.end[1]]) < 1e-3
                })
            };
            // The grid's lines are engraved end to end, and nothing else is.
            for i in 0..=30 {
                let t = i as f64;
                for x in [5.0, 15.0, 25.0, 35.0] {
                    if !on_cut(x, 5.0 + t * 20.0 / 30.0) {
                        return Err(format!(
                            "line X{x} not engraved at Y{}",
                            5.0 + t * 20.0 / 30.0
                        )
                        .into());
                    }
                }
                for y in [5.0, 15.0, 25.0] {
                    if !on_cut(5.0 + t, y) {
                        return Err(format!("line Y{y} not engraved at X{}", 5.0 + t).into());
                    }
                }
            }
            for m in &cuts {
                for q in [m.start, m.end] {
                    let on_line = [5.0, 15.0, 25.0, 35.0].iter().any(|&x| near(q[0], x, 1e-3))
                        || [5.0, 15.0, 25.0].iter().any(|&y| near(q[1], y, 1e-3));
                    if !on_line {
                        return Err(format!("engraved off the grid at {q:?}").into());
                    }
                }
            }
            Ok(())
        }),
        ("RoundedRect (user wizard beside the part)", || {
            let p = tool_path(
                "roundedrect",
                "G21 G90 G17\nG0 X50 Y40 Z10\nF300\nRoundedRect 60 30 5 2\nM30\n",
            )?;
            let arcs: Vec<&Move> = p.iter().filter(|m| m.kind == "arc").collect();
            if arcs.len() != 4 {
                return Err(format!("{} corner arcs, expected 4", arcs.len()).into());
            }
            for m in p.iter().filter(|m| m.cuts() && near(m.end[2], -2.0, 1e-3)) {
                if !(near(m.end[0], 20.0, 1e-3)
                    || near(m.end[0], 80.0, 1e-3)
                    || near(m.end[1], 25.0, 1e-3)
                    || near(m.end[1], 55.0, 1e-3))
                {
                    return Err(format!(
                        "profile point {:?} is not on the rectangle's edges",
                        m.end
                    )
                    .into());
                }
            }
            Ok(())
        }),
    ]
}

fn main() {
    let args = Arguments::from_args();
    let (have, required) = (rs274::available(), rs274::required());
    let trials = cases()
        .into_iter()
        .map(|(name, f)| {
            Trial::test(name, move || {
                if !have {
                    return Err(rs274::missing().into());
                }
                f()
            })
            .with_ignored_flag(!have && !required)
        })
        .collect();
    libtest_mimic::run(&args, trials).exit();
}
