//! `ger render` (SPEC §7): the part the program will cut. The compiled
//! tool path ([`crate::toolpath`]) is turned into segments of the tip's
//! path with the cutter that runs them ([`Scene`]), carved into a
//! heightmap of the stock ([`carve`]), and written as a depth or shaded
//! PNG ([`image`]), an STL mesh ([`stl`]), or the tool path itself as SVG
//! ([`svg`]). Everything here is in the program's output units; where the
//! program states none, its numbers are taken as millimetres (SPEC §3).

pub mod carve;
pub mod cutter;
pub mod described;
pub mod image;
pub mod stl;
pub mod svg;
pub mod view;

use crate::diagnostic::{warning, Diagnostic, DiagnosticExt};
use crate::ir::{Plane, Tool, ToolShape, Units};
use crate::source::Span;
use crate::toolpath::{Move, MoveKind, ToolPath};
use carve::{Frame, Grid, Segment, Shape};
use cutter::{Arc, Cutter, Line};

#[derive(Clone, Debug)]
pub struct RenderOptions {
    /// The cell size; default 0.001 in or 0.025 mm.
    pub resolution: Option<f64>,
    /// Coarser cells when the grid would have more.
    pub max_cells: u64,
    /// `--stock X,Y,Z`: the stock's size, placed as `SetPart` places it.
    pub stock: Option<[f64; 3]>,
    /// The cutters the program's comments describe
    /// ([`described::described_tools`]), for tools the table lacks.
    pub described: Vec<described::Described>,
}

impl Default for RenderOptions {
    fn default() -> RenderOptions {
        RenderOptions {
            resolution: None,
            max_cells: 40_000_000,
            stock: None,
            described: Vec::new(),
        }
    }
}

/// The stock block, in program coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stock {
    pub min: [f64; 2],
    pub max: [f64; 2],
    pub top: f64,
    pub bottom: f64,
}

/// What is drawn: the stock, the cutters, the tip's path as segments.
#[derive(Clone, Debug)]
pub struct Scene {
    pub units: Option<Units>,
    pub stock: Stock,
    /// The cells over the stock.
    pub frame: Frame,
    /// Why the cells are coarser than asked, if they are.
    pub coarser: Option<String>,
    pub cutters: Vec<Cutter>,
    pub segments: Vec<Segment>,
    /// Warnings at source lines (unknown positions, cuts below the stock,
    /// tools not in the table).
    pub warnings: Vec<RenderWarning>,
}

/// The default tool (SPEC §3): a 1/4 in flat end mill.
const DEFAULT_TOOL: Tool = Tool {
    diameter: 6.35,
    length: None,
    shape: ToolShape::Flat,
};

/// At most this many segments: a program that needs more is refused.
const MAX_SEGMENTS: usize = 10_000_000;

/// How many warnings of one kind are shown one by one.
const SHOWN: usize = 5;

#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RenderError {
    #[error(
        "nothing to draw: the program makes no cutting move and sets no stock (SetPart or --stock)"
    )]
    NothingToDraw,
    #[error(
        "nothing to draw: the program never moves Z, so how deep it cuts is not known; move Z (`G0 Z5`, then `G1 Z-1` to cut) or set the stock (SetPart or --stock)"
    )]
    NeverMovesZ,
    #[error("the stock has no size: {0}")]
    EmptyStock(String),
    #[error("the grid of {cells} cells does not fit in memory; give a coarser --resolution")]
    TooLarge { cells: u64 },
    #[error("the tool path has more than {MAX_SEGMENTS} segments at this resolution; give a coarser --resolution")]
    TooManySegments,
    #[error("--resolution must be a positive number")]
    BadResolution,
}

impl Scene {
    /// The scene of a compiled tool path.
    pub fn new(path: &ToolPath, options: &RenderOptions) -> Result<Scene, RenderError> {
        let units = path.units;
        // The tool path is in mm; the scene in the output units.
        let scale = 1.0 / Units::mm_per(units);
        let mut warnings = Vec::new();
        let (cutters, cutter_of) = cutters(path, scale, &options.described, &mut warnings);
        let stock = stock(path, options, scale, &cutters, &cutter_of)?;
        let (cell, coarser) = resolution(units, options, &stock)?;
        let (nx, ny) = dimensions(&stock, cell);
        let frame = Frame::new(stock.min[0], stock.min[1], cell, nx, ny);
        let segments = segments(path, scale, cell, &cutter_of, &mut warnings)?;
        below_stock(path, scale, &stock, &mut warnings);
        warnings.extend(inverted_z(path, scale));
        Ok(Scene {
            units,
            stock,
            frame,
            coarser,
            cutters,
            segments,
            warnings,
        })
    }

    /// The empty grid over the stock.
    pub fn grid(&self) -> Result<Grid, RenderError> {
        let f = self.frame;
        Grid::new(f, self.stock.top, self.stock.bottom).ok_or(RenderError::TooLarge {
            cells: f.nx as u64 * f.ny as u64,
        })
    }

    /// Carve the whole program; the warnings for rapids that cut.
    pub fn carve(
        &self,
        grid: &mut Grid,
        path: &ToolPath,
        progress: &(dyn Fn(usize, usize) + Sync),
    ) -> Vec<RenderWarning> {
        let carved = carve::carve(grid, &self.segments, &self.cutters, progress);
        rapid_cuts(path, &carved.rapid_cuts)
    }
}

/// The warnings for the rapids (move indices) that removed material.
pub fn rapid_cuts(path: &ToolPath, moves: &[usize]) -> Vec<RenderWarning> {
    let spans: Vec<_> = moves.iter().map(|&k| path.moves[k].span).collect();
    repeated(&spans, WarningKind::RapidCuts)
}

/// The cell size, and a note when `--max-cells` made it coarser.
fn resolution(
    units: Option<Units>,
    options: &RenderOptions,
    stock: &Stock,
) -> Result<(f64, Option<String>), RenderError> {
    let asked = options.resolution.unwrap_or(match units {
        Some(Units::Inch) => 0.001,
        Some(Units::Mm) | None => 0.025,
    });
    if !(asked.is_finite() && asked > 0.0) {
        return Err(RenderError::BadResolution);
    }
    let max = options.max_cells.max(1) as f64;
    let cells = |cell: f64| {
        let (nx, ny) = dimensions(stock, cell);
        nx as f64 * ny as f64
    };
    let wanted = cells(asked);
    if wanted <= max {
        return Ok((asked, None));
    }
    // Coarser until the grid fits (a thin stock keeps one row, so the
    // area alone does not say), rounded up to two significant digits.
    let mut cell = asked;
    for _ in 0..64 {
        let n = cells(cell);
        if n <= max {
            break;
        }
        cell *= (n / max).sqrt().max(1.01);
        let magnitude = 10f64.powf(cell.log10().floor() - 1.0);
        cell = (cell / magnitude).ceil() * magnitude;
    }
    if cells(cell) > max {
        return Err(RenderError::TooLarge {
            cells: wanted as u64,
        });
    }
    Ok((
        cell,
        Some(format!(
            "cells of {} would make {wanted:.0} of them; drawn with cells of {} instead (--max-cells {})",
            length(asked, units),
            length(cell, units),
            options.max_cells
        )),
    ))
}

/// The grid's columns and rows over the stock at `cell`.
fn dimensions(stock: &Stock, cell: f64) -> (usize, usize) {
    let count = |size: f64| ((size / cell).round().min(1e15) as usize).max(1);
    (
        count(stock.max[0] - stock.min[0]),
        count(stock.max[1] - stock.min[1]),
    )
}

/// The cutters the program uses, and each move's cutter: the tool table's
/// (or `SetTool`'s), else the one a comment describes, else an assumed
/// 1/4 in flat end mill, with a warning that names it. A move before any
/// tool change has the tool a `T` word selected, else tool 1 (SPEC §3).
fn cutters(
    path: &ToolPath,
    scale: f64,
    described: &[described::Described],
    warnings: &mut Vec<RenderWarning>,
) -> (Vec<Cutter>, Vec<usize>) {
    let default = Cutter::of(&DEFAULT_TOOL, scale);
    let mut cutters: Vec<Cutter> = Vec::new();
    let mut index_of = |c: Cutter| match cutters.iter().position(|&k| k == c) {
        Some(k) => k,
        None => {
            cutters.push(c);
            cutters.len() - 1
        }
    };
    let first_tool = first_named(path);
    let named = |t: u32| {
        path.moves
            .iter()
            .any(|m| m.state.tool == t || m.state.selected == t)
    };
    let descriptions = descriptions_by_tool(path, described, first_tool);
    let mut told: Vec<u32> = Vec::new();
    let mut of_move = Vec::with_capacity(path.moves.len());
    for m in &path.moves {
        let number = tool_of(m, first_tool);
        let first = !told.contains(&number);
        let cutter = if let Some(tool) = path.setup.tools.get(&number) {
            // The table is in the output units already, as the scene is.
            Cutter::of(tool, 1.0)
        } else if let Some(d) = descriptions.get(&number) {
            if first {
                let kind = WarningKind::DescribedCutter {
                    tool: number,
                    line: d.line,
                    text: d.text.clone(),
                };
                warnings.push(RenderWarning {
                    kind,
                    span: m.span,
                    more: 0,
                });
            }
            Cutter::of(&d.cutter, 1.0)
        } else {
            if first {
                let kind = WarningKind::AssumedCutter {
                    tool: number,
                    named: named(number),
                };
                warnings.push(RenderWarning {
                    kind,
                    span: m.span,
                    more: 0,
                });
            }
            default
        };
        if first {
            told.push(number);
        }
        of_move.push(index_of(cutter));
    }
    if cutters.is_empty() {
        cutters.push(default);
    }
    (cutters, of_move)
}

/// Each tool's cutter as the picture draws it, in the order the program
/// first cuts with it (`ger view`'s legend and its sweep between
/// checkpoints).
pub fn cutters_by_tool(
    path: &ToolPath,
    scale: f64,
    described: &[described::Described],
) -> Vec<(u32, Cutter)> {
    let (cutters, of_move) = cutters(path, scale, described, &mut Vec::new());
    let first = first_named(path);
    let mut out: Vec<(u32, Cutter)> = Vec::new();
    for (m, &c) in path.moves.iter().zip(&of_move) {
        let number = tool_of(m, first);
        if !out.iter().any(|&(n, _)| n == number) {
            out.push((number, cutters[c]));
        }
    }
    out
}

/// The tool a move cuts with: the one loaded (M6), else the one a `T`
/// word selected, else (before any) the first the program names.
pub(crate) fn tool_of(m: &crate::toolpath::Move, first_named: u32) -> u32 {
    match (m.state.tool, m.state.selected) {
        (0, 0) => first_named,
        (0, selected) => selected,
        (loaded, _) => loaded,
    }
}

/// The first tool the program loads or selects; tool 1 if it names none
/// (SPEC §3).
pub(crate) fn first_named(path: &ToolPath) -> u32 {
    path.moves
        .iter()
        .find_map(|m| {
            [m.state.tool, m.state.selected]
                .into_iter()
                .find(|&t| t != 0)
        })
        .unwrap_or(1)
}

/// Each tool's described cutter: the first comment about it; one about
/// no tool only when the program cuts with one tool.
fn descriptions_by_tool(
    path: &ToolPath,
    described: &[described::Described],
    first_named: u32,
) -> std::collections::BTreeMap<u32, described::Described> {
    let mut by_tool = std::collections::BTreeMap::new();
    for d in described {
        if let Some(tool) = d.tool {
            by_tool.entry(tool).or_insert_with(|| d.clone());
        }
    }
    let one_tool = path
        .moves
        .iter()
        .all(|m| tool_of(m, first_named) == first_named);
    if let Some(d) = described.iter().find(|d| d.tool.is_none()) {
        if one_tool && by_tool.is_empty() {
            by_tool.insert(first_named, d.clone());
        }
    }
    by_tool
}

/// The stock: `--stock`, else `SetPart` (placed by `SetZero`), else the
/// cut's bounds plus `SetMargin` (default: the largest cutter's radius)
/// all round, its top at Z=0.
fn stock(
    path: &ToolPath,
    options: &RenderOptions,
    scale: f64,
    cutters: &[Cutter],
    cutter_of: &[usize],
) -> Result<Stock, RenderError> {
    let zero = path.setup.zero.unwrap_or([0.0; 3]);
    if let Some(size) = options.stock.or(path.setup.part) {
        if !size.iter().all(|v| v.is_finite() && *v > 0.0) {
            return Err(RenderError::EmptyStock(format!(
                "{} x {} x {}",
                size[0], size[1], size[2]
            )));
        }
        return Ok(Stock {
            min: [-zero[0], -zero[1]],
            max: [size[0] - zero[0], size[1] - zero[1]],
            top: zero[2],
            bottom: zero[2] - size[2],
        });
    }
    let mut b = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    let mut lowest: f64 = 0.0;
    let mut widest: f64 = 0.0;
    for (index, (m, &c)) in path.moves.iter().zip(cutter_of).enumerate() {
        let (before, after) = unknown_ends(path, index);
        if matches!(m.kind, MoveKind::Rapid) || before.iter().chain(&after).any(|&g| g) {
            continue;
        }
        let r = cutters[c].radius;
        widest = widest.max(r);
        for k in 0..=16 {
            let p = m.at(f64::from(k) / 16.0).map(|v| v * scale);
            b = [
                b[0].min(p[0] - r),
                b[1].min(p[1] - r),
                b[2].max(p[0] + r),
                b[3].max(p[1] + r),
            ];
            lowest = lowest.min(p[2]);
        }
    }
    if !b[0].is_finite() {
        // no move starts at a Z the program set, and the last changes none
        let never_z = path.moves.iter().all(|m| m.guessed[2])
            && path.moves.last().is_some_and(|m| m.end[2] == m.start[2]);
        return Err(if never_z {
            RenderError::NeverMovesZ
        } else {
            RenderError::NothingToDraw
        });
    }
    let margin = path.setup.margin.unwrap_or(widest);
    Ok(Stock {
        min: [b[0] - margin, b[1] - margin],
        max: [b[2] + margin, b[3] + margin],
        top: 0.0,
        bottom: lowest - margin.max(widest),
    })
}

/// The tip's path as segments: level XY arcs exactly, other arcs as chords
/// whose sag stays under a quarter cell, lines as they are. Rapids whose
/// ends are not known are left out (the machine is somewhere else); other
/// moves from an unknown position are drawn from where they end, with a
/// warning.
fn segments(
    path: &ToolPath,
    scale: f64,
    cell: f64,
    cutter_of: &[usize],
    warnings: &mut Vec<RenderWarning>,
) -> Result<Vec<Segment>, RenderError> {
    let mut out: Vec<Segment> = Vec::with_capacity(path.moves.len());
    let mut unknown = Vec::new();
    let mut last_end: Option<([f64; 3], usize)> = None;
    for (index, m) in path.moves.iter().enumerate() {
        let (before, after) = unknown_ends(path, index);
        let cutter = cutter_of[index];
        let rapid = matches!(m.kind, MoveKind::Rapid);
        let guessed = (0..3).any(|i| before[i] || after[i]);
        if guessed {
            if rapid {
                last_end = None;
                continue;
            }
            unknown.push(m.span);
        }
        let end = m.end.map(|v| v * scale);
        let mut start = m.start.map(|v| v * scale);
        for i in 0..3 {
            if before[i] && !after[i] {
                start[i] = end[i];
            }
        }
        let continues = last_end == Some((start, cutter));
        let level_xy = matches!(m.kind, MoveKind::Arc(a) if a.plane == Plane::XY)
            && (end[2] - start[2]).abs() < 1e-12;
        let chords = if level_xy { 1 } else { chords(m, scale, cell) };
        if out.len().saturating_add(chords) > MAX_SEGMENTS {
            return Err(RenderError::TooManySegments);
        }
        let mut push = |shape: Shape, continues: bool| {
            let segment = Segment {
                shape,
                cutter,
                rapid,
                move_index: index,
                continues,
            };
            match out.last_mut() {
                Some(last) if continues && !rapid => {
                    if let Some(merged) = extended(last, &segment) {
                        *last = merged;
                        return;
                    }
                    out.push(segment);
                }
                _ => out.push(segment),
            }
        };
        match m.kind {
            MoveKind::Arc(a) if level_xy => {
                let center = [a.center[0] * scale, a.center[1] * scale];
                let rel = |p: [f64; 3]| [p[0] - center[0], p[1] - center[1]];
                let (from, to) = if a.clockwise {
                    (rel(end), rel(start))
                } else {
                    (rel(start), rel(end))
                };
                push(
                    Shape::Arc(Arc {
                        center,
                        radius: from[0].hypot(from[1]),
                        z: start[2],
                        from,
                        to,
                        sweep: m.sweep(),
                    }),
                    continues,
                );
            }
            MoveKind::Arc(_) => {
                let mut from = start;
                for k in 1..=chords {
                    let to = if k == chords {
                        end
                    } else {
                        m.at(k as f64 / chords as f64).map(|v| v * scale)
                    };
                    push(Shape::Line(Line::new(from, to)), continues || k > 1);
                    from = to;
                }
            }
            MoveKind::Rapid | MoveKind::Feed => push(Shape::Line(Line::new(start, end)), continues),
        }
        last_end = Some((end, cutter));
    }
    warnings.extend(repeated(&unknown, WarningKind::UnknownPosition));
    Ok(out)
}

/// `last` and `next` as one segment, when `next` carries straight on from
/// `last` (a line split in collinear pieces sweeps what the whole does).
fn extended(last: &Segment, next: &Segment) -> Option<Segment> {
    let (Shape::Line(a), Shape::Line(b)) = (&last.shape, &next.shape) else {
        return None;
    };
    if last.rapid || last.cutter != next.cutter {
        return None;
    }
    let u = [a.v[0], a.v[1], a.dz];
    let w = [b.v[0], b.v[1], b.dz];
    let dot = u[0] * w[0] + u[1] * w[1] + u[2] * w[2];
    let cross = [
        u[1] * w[2] - u[2] * w[1],
        u[2] * w[0] - u[0] * w[2],
        u[0] * w[1] - u[1] * w[0],
    ];
    let sine = cross.iter().map(|c| c * c).sum::<f64>().sqrt();
    let lengths = dot.abs().max(1e-300);
    // Collinear to 1e-12 of the lengths, and the same way on.
    (dot > 0.0 && sine <= 1e-12 * lengths).then(|| Segment {
        shape: Shape::Line(Line::new(a.a, b.end())),
        ..*last
    })
}

/// Which of X Y Z are unknown at the start and at the end of move
/// `index` (at the end: as at the next move's start).
pub(crate) fn unknown_ends(path: &ToolPath, index: usize) -> ([bool; 3], [bool; 3]) {
    let before = path.moves[index].guessed;
    let after = path
        .moves
        .get(index + 1)
        .map_or(before, |next| next.guessed);
    (before, after)
}

/// How many chords keep an arc's sag under a quarter cell.
pub(crate) fn chords(m: &Move, scale: f64, cell: f64) -> usize {
    let MoveKind::Arc(a) = m.kind else {
        return 1;
    };
    let (p, q, _) = a.plane.axes();
    let radius = (m.start[p] - a.center[p]).hypot(m.start[q] - a.center[q]) * scale;
    let sag = cell / 4.0;
    let step = if radius <= sag {
        std::f64::consts::PI
    } else {
        2.0 * (1.0 - sag / radius).acos()
    };
    ((m.sweep() / step).ceil() as usize).max(1)
}

/// Warn about moves that take the tip below the stock's bottom (a move
/// that climbs out from there is not warned again), once per source line.
fn below_stock(path: &ToolPath, scale: f64, stock: &Stock, warnings: &mut Vec<RenderWarning>) {
    let mut spans = Vec::new();
    let mut seen = std::collections::HashSet::new();
    for (index, m) in path.moves.iter().enumerate() {
        let (before, after) = unknown_ends(path, index);
        if before[2] || after[2] {
            continue;
        }
        let (from, to) = (m.start[2] * scale, m.end[2] * scale);
        if to <= from && to < stock.bottom - 1e-9 && seen.insert(m.span) {
            spans.push(m.span);
        }
    }
    let units = path.units;
    warnings.extend(repeated(
        &spans,
        WarningKind::BelowStock {
            bottom: stock.bottom,
            units,
        },
    ));
}

/// One warning when most rapids end below the deepest point a feed ends
/// at: the program's Z probably points into the stock (some Estlcam
/// posts), so it would be drawn as a solid block cut by its rapids.
fn inverted_z(path: &ToolPath, scale: f64) -> Option<RenderWarning> {
    let known = |index: usize| {
        let (before, after) = unknown_ends(path, index);
        !(before[2] || after[2])
    };
    let moves = || path.moves.iter().enumerate().filter(|&(k, _)| known(k));
    let deepest = moves()
        .filter(|(_, m)| !matches!(m.kind, MoveKind::Rapid))
        .map(|(_, m)| m.end[2])
        .fold(f64::INFINITY, f64::min);
    let rapids = moves().filter(|(_, m)| matches!(m.kind, MoveKind::Rapid));
    let (mut count, mut below, mut first) = (0, 0, None);
    for (_, m) in rapids {
        count += 1;
        if m.end[2] < deepest - 1e-6 {
            below += 1;
            first = first.or(Some(m.span));
        }
    }
    let span = first.filter(|_| 2 * below > count)?;
    Some(RenderWarning {
        kind: WarningKind::InvertedZ {
            below,
            rapids: count,
            deepest: deepest * scale,
            units: path.units,
        },
        span,
        more: 0,
    })
}

/// One warning for each of the first few spans, the last saying how many
/// more there are.
fn repeated(spans: &[Span], kind: WarningKind) -> Vec<RenderWarning> {
    let shown = spans.len().min(SHOWN);
    spans[..shown]
        .iter()
        .enumerate()
        .map(|(k, &span)| RenderWarning {
            kind: kind.clone(),
            span,
            more: if k + 1 == shown {
                spans.len() - shown
            } else {
                0
            },
        })
        .collect()
}

/// A number as a person reads it: 4 significant digits, no trailing zeros
/// (`0.0026`, `-3.931`, `-11.79`, `1250`).
pub fn significant(v: f64) -> String {
    if !v.is_finite() || v == 0.0 {
        return if v.is_finite() {
            "0".into()
        } else {
            v.to_string()
        };
    }
    let decimals = (3 - v.abs().log10().floor() as i32).clamp(0, 17) as usize;
    let text = format!("{v:.decimals$}");
    let text = match text.contains('.') {
        true => text.trim_end_matches('0').trim_end_matches('.'),
        false => &text,
    };
    match text {
        "-0" => "0".into(),
        t => t.into(),
    }
}

/// The name of the scene's unit of length (a program that states none is
/// taken as millimetres).
pub fn unit_name(units: Option<Units>) -> &'static str {
    match units {
        Some(Units::Inch) => "in",
        Some(Units::Mm) | None => "mm",
    }
}

/// A length with its unit: `0.0026 in`, `-3.931 mm`.
pub fn length(v: f64, units: Option<Units>) -> String {
    format!("{} {}", significant(v), unit_name(units))
}

/// What the picture warns about, at a source line.
#[derive(Clone, Debug, PartialEq)]
pub enum WarningKind {
    /// No table, `SetTool` or comment gives the tool's size: drawn as an
    /// assumed 1/4 in flat end mill. `named`: the program names the tool
    /// (a `T` word); else it names none.
    AssumedCutter { tool: u32, named: bool },
    /// The tool is drawn as a comment of the program describes it.
    DescribedCutter { tool: u32, line: u32, text: String },
    /// A cutting move from or to an axis the program has not set.
    UnknownPosition,
    /// A move takes the tip below the stock's bottom.
    BelowStock { bottom: f64, units: Option<Units> },
    /// A rapid removed material.
    RapidCuts,
    /// Most rapids end below the deepest feed: Z may point into the stock.
    InvertedZ {
        below: usize,
        rapids: usize,
        deepest: f64,
        units: Option<Units>,
    },
}

#[derive(Clone, Debug, PartialEq)]
pub struct RenderWarning {
    pub kind: WarningKind,
    pub span: Span,
    /// How many more of the same kind were not shown after this one.
    pub more: usize,
}

impl RenderWarning {
    pub fn to_diagnostic(&self) -> Diagnostic {
        let d = match &self.kind {
            WarningKind::AssumedCutter { tool, named } => warning(
                match named {
                    true => format!("tool {tool}'s size is not known: drawn as an assumed 1/4 in (6.35 mm) flat end mill"),
                    false => "the program names no tool: drawn with an assumed 1/4 in (6.35 mm) flat end mill".to_string(),
                },
                self.span,
                "the first cut with it",
            )
            .with_help(format!(
                "give the real cutter with --tool-table FILE (LinuxCNC's format: `T{tool} P{tool} D3.175`) or `SetTool {tool} diameter` in .egc"
            )),
            WarningKind::DescribedCutter { tool, line, text } => crate::diagnostic::note(
                format!("tool {tool} is drawn as the program's comment on line {line} describes it: ({text})"),
                self.span,
                "the first cut with it",
            )
            .with_help("a --tool-table or SetTool entry takes its place"),
            WarningKind::UnknownPosition => warning(
                "the tool position is not known here",
                self.span,
                "this move starts or ends at an axis the program has not set (or a machine move lost)",
            )
            .with_help(
                "drawn from where the move ends, with unset axes at 0; the machine may be elsewhere",
            ),
            WarningKind::BelowStock { bottom, units } => warning(
                "the cut goes below the bottom of the stock",
                self.span,
                "the tool reaches below the stock here",
            )
            .with_help(format!(
                "the stock's bottom is at Z{} (a through cut?)",
                length(*bottom, *units)
            )),
            WarningKind::RapidCuts => warning(
                "a rapid move cuts the stock",
                self.span,
                "this rapid removes material",
            )
            .with_help("check the safe height before this move"),
            WarningKind::InvertedZ {
                below,
                rapids,
                deepest,
                units,
            } => warning(
                format!(
                    "the program's Z may be inverted: {below} of its {rapids} rapids end below its deepest cut (Z{})",
                    length(*deepest, *units)
                ),
                self.span,
                "the first rapid below the deepest cut",
            )
            .with_help(
                "the picture takes +Z as up, out of the stock; if this program's Z points down, into it, the part is drawn as its rapids cut it: check the post-processor's Z direction",
            ),
        };
        match self.more {
            0 => d,
            more => d.with_notes(vec![format!("{more} more like it not shown")]),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_shown_at_four_significant_digits_with_their_unit() {
        assert_eq!(significant(0.0026000000000000003), "0.0026");
        assert_eq!(significant(-3.93125), "-3.931");
        assert_eq!(significant(-11.79375), "-11.79");
        assert_eq!(significant(9.99996), "10");
        assert_eq!(significant(12345.6), "12346");
        assert_eq!(significant(-0.00001), "-0.00001");
        assert_eq!(significant(0.0), "0");
        assert_eq!(length(-10.0, Some(Units::Mm)), "-10 mm");
        assert_eq!(length(0.0025, Some(Units::Inch)), "0.0025 in");
    }
}
