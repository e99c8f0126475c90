//! The stock over the run, for the page's playback: `ger render`'s exact
//! heightmap ([`carve::carve`] over a [`Scene`]) carved a stretch of moves
//! at a time, a checkpoint kept after each stretch. The page's grid is
//! `ger render`'s own when it has at most [`PAGE_CELLS`] cells a side,
//! else `ger render`'s at a coarser `--resolution` (a whole multiple of
//! the default cell): either way a real heightmap, so that the page,
//! sweeping the moves after a checkpoint with the same cutters and the
//! same closed forms, shows at any time exactly what `ger render` gives
//! for the program cut there. A checkpoint is the grid's depths, quantised
//! to 16 bits and written as the run-length-coded difference from the one
//! before. With the checkpoints go the moves the page must sweep other
//! than as the line between their drawn ends (level arcs, other arcs as
//! the render's chords, moves of unknown start) — the render's segments.
//! Must not guess a height.

use super::moves::{varint, zigzag};
use crate::ir::{Plane, Units};
use crate::render::carve::{self, Grid};
use crate::render::{rapid_cuts, unknown_ends, RenderOptions, RenderWarning, Scene};
use crate::toolpath::{MoveKind, ToolPath};
use serde_json::{json, Value};

/// The page's grid's longer side, at most (cells).
const PAGE_CELLS: usize = 512;

/// At most this many checkpoints; at least this many moves between two.
const CHECKPOINTS: usize = 96;
const MIN_STRETCH: usize = 1000;

/// The sweep records' kinds and flags (see [`sweeps`]).
const SWEEP_SKIP: u8 = 1;
const SWEEP_ARC: u8 = 2;
const SWEEP_CHORDS: u8 = 3;
const SWEEP_START: u8 = 1 << 2;
const SWEEP_CLOCKWISE: u8 = 1 << 3;

pub(super) struct Carved {
    pub json: Value,
    /// At `ger render`'s own resolution.
    pub removed_mm3: Option<f64>,
    pub warnings: Vec<RenderWarning>,
}

/// Carve `scene` (`ger render`'s, made with `render`), keeping the page
/// grid's checkpoints and the sweep records in `binary`. `quantum`: the
/// moves' positions' step (mm).
pub(super) fn carve(
    scene: &Scene,
    path: &ToolPath,
    render: &RenderOptions,
    quantum: f64,
    binary: &mut Vec<u8>,
    notes: &mut Vec<String>,
) -> Carved {
    let nothing = |notes: &mut Vec<String>, e: &dyn std::fmt::Display| {
        notes.push(format!("no stock drawn: {e}"));
        Carved {
            json: Value::Null,
            removed_mm3: None,
            warnings: Vec::new(),
        }
    };
    let mut grid = match scene.grid() {
        Ok(grid) => grid,
        Err(e) => return nothing(notes, &e),
    };
    let mm_per = Units::mm_per(scene.units);
    let block = grid.frame.nx.max(grid.frame.ny).div_ceil(PAGE_CELLS).max(1);
    let (fine, coarse) = if block > 1 {
        match coarser(scene, path, render, &mut grid, block, notes) {
            Ok((fine, coarse)) => (Some(fine), Some(coarse)),
            Err(e) => return nothing(notes, &e),
        }
    } else {
        (None, None)
    };
    let page_scene = coarse.as_ref().unwrap_or(scene);
    let mut page_grid = match page_scene.grid() {
        Ok(grid) => grid,
        Err(e) => return nothing(notes, &e),
    };
    let (marks, depths, rapid) = checkpoints(page_scene, &mut page_grid, path.moves.len());
    let cell_mm = page_grid.frame.cell * mm_per;
    let volumes: Vec<f64> = depths
        .iter()
        .map(|d| d.iter().sum::<f64>() * cell_mm * cell_mm * mm_per)
        .collect();
    let deepest = depths
        .iter()
        .flatten()
        .fold(page_grid.top - page_grid.bottom, |a, &b| a.max(b))
        .max(1e-9);
    let offset = binary.len();
    encode(&depths, deepest, binary);
    let length = binary.len() - offset;
    let scale = 1.0 / mm_per;
    let sweeps_at = binary.len();
    let sweep_count = sweeps(path, scale, page_grid.frame.cell, quantum, binary);
    notes.push(format!(
        "the stock's heights are kept to 1/65535 of its depth at checkpoints every {} moves; between them the page sweeps the moves as ger render does",
        marks.first().copied().unwrap_or(0)
    ));
    let stock = page_scene.stock;
    let json = json!({
        "min": [stock.min[0] * mm_per, stock.min[1] * mm_per],
        "max": [stock.max[0] * mm_per, stock.max[1] * mm_per],
        "top": stock.top * mm_per,
        "bottom": stock.bottom * mm_per,
        "x0": page_grid.frame.x0 * mm_per,
        "y0": page_grid.frame.y0 * mm_per,
        "cell_mm": cell_mm,
        "nx": page_grid.frame.nx,
        "ny": page_grid.frame.ny,
        "depth_mm": deepest * mm_per,
        "checkpoints": marks.iter().zip(&volumes).map(|(m, v)| json!({"moves": m, "removed_mm3": v})).collect::<Vec<_>>(),
        "offset": offset,
        "length": length,
        "sweeps": {"offset": sweeps_at, "length": binary.len() - sweeps_at, "count": sweep_count},
    });
    let (rapid, removed) = match fine {
        Some((carved, volume)) => (carved.rapid_cuts, Some(volume)),
        None => (rapid, volumes.last().copied()),
    };
    Carved {
        json,
        removed_mm3: removed,
        warnings: rapid_cuts(path, &rapid),
    }
}

/// `ger render`'s grid carved whole (its volume, mm³, and the rapids that
/// cut it) and the scene of the page's coarser grid: `ger render`'s at a
/// cell `block` times its own.
fn coarser(
    scene: &Scene,
    path: &ToolPath,
    render: &RenderOptions,
    grid: &mut Grid,
    block: usize,
    notes: &mut Vec<String>,
) -> Result<((carve::Carved, f64), Scene), crate::render::RenderError> {
    let carved = carve::carve(grid, &scene.segments, &scene.cutters, &|_, _| {});
    let asked = RenderOptions {
        resolution: Some(scene.frame.cell * block as f64),
        ..render.clone()
    };
    let coarse = Scene::new(path, &asked)?;
    notes.push(format!(
        "the stock is ger render's heightmap at --resolution {} ({} x {} cells); its default, {} x {} cells of {}, is too fine for the page",
        crate::render::significant(coarse.frame.cell),
        coarse.frame.nx,
        coarse.frame.ny,
        grid.frame.nx,
        grid.frame.ny,
        crate::render::significant(scene.frame.cell),
    ));
    let volume = grid.removed_volume() * Units::mm_per(scene.units).powi(3);
    Ok(((carved, volume), coarse))
}

/// Carve `scene` into `grid` a stretch at a time: the move counts at the
/// checkpoints, each checkpoint's depths below the top, the rapids that
/// cut.
fn checkpoints(
    scene: &Scene,
    grid: &mut Grid,
    moves: usize,
) -> (Vec<usize>, Vec<Vec<f64>>, Vec<usize>) {
    let stretch = moves.div_ceil(CHECKPOINTS).max(MIN_STRETCH);
    let mut depths = Vec::new();
    let mut marks = Vec::new();
    let mut rapid = Vec::new();
    let mut done = 0;
    let mut upto = 0;
    while upto < moves || marks.is_empty() {
        upto = (upto + stretch).min(moves);
        let end = done + scene.segments[done..].partition_point(|s| s.move_index < upto);
        let carved = carve::carve(grid, &scene.segments[done..end], &scene.cutters, &|_, _| {});
        rapid.extend(carved.rapid_cuts);
        done = end;
        let top = grid.top as f32;
        depths.push(
            grid.z
                .iter()
                .map(|&z| f64::from((top - z).max(0.0)))
                .collect(),
        );
        marks.push(upto);
    }
    (marks, depths, rapid)
}

/// Each checkpoint's depths, as 16-bit fractions of `deepest`, run-length
/// coded against the one before: runs of unchanged cells and runs of
/// changed ones with their differences.
fn encode(checkpoints: &[Vec<f64>], deepest: f64, out: &mut Vec<u8>) {
    let Some(first) = checkpoints.first() else {
        return;
    };
    let mut before = vec![0i64; first.len()];
    for depths in checkpoints {
        let now: Vec<i64> = depths
            .iter()
            .map(|d| ((d / deepest) * 65535.0).round().clamp(0.0, 65535.0) as i64)
            .collect();
        let mut k = 0;
        while k < now.len() {
            let same = now[k..]
                .iter()
                .zip(&before[k..])
                .take_while(|(a, b)| a == b)
                .count();
            let changed = now[k + same..]
                .iter()
                .zip(&before[k + same..])
                .take_while(|(a, b)| a != b)
                .count();
            varint(out, same as u64);
            varint(out, changed as u64);
            for c in k + same..k + same + changed {
                zigzag(out, now[c] - before[c]);
            }
            k += same + changed;
        }
        before = now;
    }
}

/// The moves the page sweeps other than as the line between their drawn
/// ends, as the render's segments have them (`scale`: mm to the scene's
/// units; `cell`: the page grid's, in the scene's units): a record per
/// such move — the move's index after the record before, a head byte
/// (kind, flags), the start when it is not the drawn one (a coordinate
/// unknown before the move), and for a level arc its centre from the
/// start, its sweep in microradians; for another arc the render's chords.
/// The count of records.
fn sweeps(path: &ToolPath, scale: f64, cell: f64, quantum: f64, out: &mut Vec<u8>) -> usize {
    let q = |v: f64| (v / quantum).round() as i64;
    let mut count = 0;
    let mut last = 0;
    for (index, m) in path.moves.iter().enumerate() {
        let (before, after) = unknown_ends(path, index);
        let rapid = matches!(m.kind, MoveKind::Rapid);
        let guessed = (0..3).any(|i| before[i] || after[i]);
        let mut start = m.start;
        let mut moved = false;
        for i in 0..3 {
            if before[i] && !after[i] {
                start[i] = m.end[i];
                moved = true;
            }
        }
        let mut head = if moved { SWEEP_START } else { 0 };
        let mut tail = Vec::new();
        if guessed && rapid {
            head = SWEEP_SKIP;
        } else if let MoveKind::Arc(a) = m.kind {
            let level = a.plane == Plane::XY && ((m.end[2] - start[2]) * scale).abs() < 1e-12;
            if level {
                head |= SWEEP_ARC | if a.clockwise { SWEEP_CLOCKWISE } else { 0 };
                zigzag(&mut tail, q(a.center[0]) - q(start[0]));
                zigzag(&mut tail, q(a.center[1]) - q(start[1]));
                varint(&mut tail, (m.sweep() * 1e6).round().max(0.0) as u64);
            } else {
                head |= SWEEP_CHORDS;
                let chords = crate::render::chords(m, scale, cell);
                varint(&mut tail, chords as u64);
                let mut at = start.map(q);
                for k in 1..chords {
                    let p = m.at(k as f64 / chords as f64).map(q);
                    for i in 0..3 {
                        zigzag(&mut tail, p[i] - at[i]);
                    }
                    at = p;
                }
            }
        }
        if head == 0 {
            continue;
        }
        varint(out, (index - last) as u64);
        out.push(head);
        if head & SWEEP_START != 0 {
            for v in start {
                zigzag(out, q(v));
            }
        }
        out.extend_from_slice(&tail);
        last = index;
        count += 1;
    }
    count
}
