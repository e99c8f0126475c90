//! The simulation: a heightmap of the stock, one f32 per cell, from which
//! every move removes exactly its swept volume (SPEC §7). Each cell keeps
//! the lowest height any cutter reached over its centre. The rows are cut
//! into bands that the cores carve independently (rayon), each band taking
//! the moves that touch it in program order, so the bytes are the same on
//! any number of cores.

use super::cutter::{Arc, Cutter, Line, Profile};
use rayon::prelude::*;

/// Where the cells are. Cell `(i, j)` has its centre at
/// `x0 + (i + ½)·cell, y0 + (j + ½)·cell`; row 0 is the lowest y.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    pub x0: f64,
    pub y0: f64,
    pub cell: f64,
    pub nx: usize,
    pub ny: usize,
}

impl Frame {
    pub fn center_x(&self, i: usize) -> f64 {
        self.x0 + (i as f64 + 0.5) * self.cell
    }

    pub fn center_y(&self, j: usize) -> f64 {
        self.y0 + (j as f64 + 0.5) * self.cell
    }

    /// The cells whose centres lie in `[lo, hi]`, clipped to the grid.
    pub fn columns(&self, lo: f64, hi: f64) -> Option<(usize, usize)> {
        Self::clip(self.x0, self.cell, self.nx, lo, hi)
    }

    /// The rows whose centres lie in `[lo, hi]`, clipped to the grid.
    pub fn rows(&self, lo: f64, hi: f64) -> Option<(usize, usize)> {
        Self::clip(self.y0, self.cell, self.ny, lo, hi)
    }

    fn clip(origin: f64, cell: f64, n: usize, lo: f64, hi: f64) -> Option<(usize, usize)> {
        let first = ((lo - origin) / cell - 0.5).ceil().max(0.0);
        let last = ((hi - origin) / cell - 0.5).floor().min(n as f64 - 1.0);
        (first <= last).then_some((first as usize, last as usize))
    }
}

/// The stock as a grid of heights, one f32 per cell.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    pub frame: Frame,
    pub top: f64,
    pub bottom: f64,
    pub z: Vec<f32>,
}

impl Grid {
    /// Uncut stock; `None` when the grid would not fit in memory.
    pub fn new(frame: Frame, top: f64, bottom: f64) -> Option<Grid> {
        let n = frame.nx.checked_mul(frame.ny)?;
        let mut z = Vec::new();
        z.try_reserve_exact(n).ok()?;
        z.resize(n, top as f32);
        Some(Grid {
            frame,
            top,
            bottom,
            z,
        })
    }

    pub fn at(&self, i: usize, j: usize) -> f32 {
        self.z[j * self.frame.nx + i]
    }

    /// The volume removed from the stock (below its top), in cubed units.
    pub fn removed_volume(&self) -> f64 {
        let top = self.top as f32;
        let depth: f64 = self.z.iter().map(|&z| f64::from((top - z).max(0.0))).sum();
        depth * self.frame.cell * self.frame.cell
    }
}

/// The path of the tip during one simulated move.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    Line(Line),
    /// A level arc in the XY plane (others become lines).
    Arc(Arc),
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    pub shape: Shape,
    /// Index into the cutters.
    pub cutter: usize,
    pub rapid: bool,
    /// The tool path's move it belongs to.
    pub move_index: usize,
    /// It starts where the segment before it ended, with the same cutter:
    /// the disc at its start is already carved.
    pub continues: bool,
}

impl Segment {
    /// `[min x, min y, max x, max y]` of the tip's path.
    fn bounds(&self) -> [f64; 4] {
        match &self.shape {
            Shape::Line(l) => {
                let b = l.end();
                [
                    l.a[0].min(b[0]),
                    l.a[1].min(b[1]),
                    l.a[0].max(b[0]),
                    l.a[1].max(b[1]),
                ]
            }
            Shape::Arc(a) => a.bounds(),
        }
    }

    /// The lowest tip height along the segment.
    pub fn lowest_tip(&self) -> f64 {
        match &self.shape {
            Shape::Line(l) => l.a[2].min(l.a[2] + l.dz),
            Shape::Arc(a) => a.z,
        }
    }
}

/// Rows per band: small enough to share out, big enough that a move
/// rarely visits many.
const BAND_ROWS: usize = 32;

/// What carving found: the moves that are rapids and removed material.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Carved {
    pub rapid_cuts: Vec<usize>,
}

/// Carve every segment into the grid. `progress` is told each band done
/// (of how many).
pub fn carve(
    grid: &mut Grid,
    segments: &[Segment],
    cutters: &[Cutter],
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Carved {
    let frame = grid.frame;
    let bands = frame.ny.div_ceil(BAND_ROWS).max(1);
    let mut lists: Vec<Vec<u32>> = vec![Vec::new(); bands];
    for (k, seg) in segments.iter().enumerate() {
        let r = cutters[seg.cutter].radius;
        let b = seg.bounds();
        if let Some((first, last)) = frame.rows(b[1] - r, b[3] + r) {
            if frame.columns(b[0] - r, b[2] + r).is_some() {
                for list in &mut lists[first / BAND_ROWS..=last / BAND_ROWS] {
                    list.push(k as u32);
                }
            }
        }
    }
    // A rapid that lowers the stock by more than this cuts it.
    let tolerance = (frame.cell * 1e-3).max((grid.top.abs() + grid.bottom.abs()) * 1e-6);
    let done = std::sync::atomic::AtomicUsize::new(0);
    let nx = frame.nx;
    let mut found: Vec<usize> = grid
        .z
        .par_chunks_mut(BAND_ROWS * nx)
        .zip(lists.par_iter())
        .enumerate()
        .flat_map_iter(|(band, (cells, list))| {
            let mut band = Band {
                frame: &frame,
                first_row: band * BAND_ROWS,
                cells,
                tolerance,
            };
            let mut cut = Vec::new();
            for &k in list {
                let seg = &segments[k as usize];
                if band.carve(seg, &cutters[seg.cutter]) && seg.rapid {
                    cut.push(seg.move_index);
                }
            }
            let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
            progress(n, bands);
            cut
        })
        .collect();
    found.sort_unstable();
    found.dedup();
    Carved { rapid_cuts: found }
}

struct Band<'a> {
    frame: &'a Frame,
    first_row: usize,
    cells: &'a mut [f32],
    tolerance: f64,
}

impl Band<'_> {
    /// Carve one segment into the band's rows; whether it lowered any cell
    /// by more than the tolerance.
    fn carve(&mut self, seg: &Segment, cutter: &Cutter) -> bool {
        let frame = self.frame;
        let r = cutter.radius;
        let b = seg.bounds();
        let rows_here = self.cells.len() / frame.nx;
        let Some((first, last)) = frame.rows(b[1] - r, b[3] + r) else {
            return false;
        };
        let first = first.max(self.first_row);
        let last = last.min(self.first_row + rows_here - 1);
        let mut cut = false;
        for row in first..=last {
            let y = frame.center_y(row);
            let at = (row - self.first_row) * frame.nx;
            let cells = &mut self.cells[at..at + frame.nx];
            cut |= match &seg.shape {
                Shape::Line(line) => {
                    carve_line_row(frame, cells, line, cutter, y, seg, self.tolerance)
                }
                Shape::Arc(arc) => carve_arc_row(frame, cells, arc, cutter, y, self.tolerance),
            };
        }
        cut
    }
}

fn carve_line_row(
    frame: &Frame,
    cells: &mut [f32],
    line: &Line,
    cutter: &Cutter,
    y: f64,
    seg: &Segment,
    tolerance: f64,
) -> bool {
    let r = cutter.radius;
    let Some((lo, hi)) = line.span(r, y) else {
        return false;
    };
    let Some((i0, i1)) = frame.columns(lo, hi) else {
        return false;
    };
    let flat = cutter.profile == Profile::Flat;
    // A flat cutter that does not go down reaches, over the disc where it
    // starts, no lower than where it starts: the segment before it carved
    // that already.
    let mut pieces = [(i0, i1), (1, 0)];
    if seg.continues && flat && line.dz >= -1e-12 {
        if let Some(w) = super::cutter::chord_half(r, y - line.a[1]) {
            let inset = frame.cell * 1e-6;
            if let Some((d0, d1)) = frame.columns(line.a[0] - w + inset, line.a[0] + w - inset) {
                pieces = [(i0, d0.saturating_sub(1)), (d1 + 1, i1)];
                if d0 == 0 {
                    pieces[0] = (1, 0);
                }
            }
        }
    }
    let mut cut = false;
    for (p0, p1) in pieces {
        if p0 > p1 {
            continue;
        }
        let row = &mut cells[p0..=p1];
        if flat && line.dz.abs() < 1e-12 {
            let z = line.a[2] as f32;
            if seg.rapid {
                cut |= row.iter().any(|&c| f64::from(c - z) > tolerance);
            }
            for c in row.iter_mut() {
                *c = c.min(z);
            }
        } else {
            for (k, c) in row.iter_mut().enumerate() {
                if let Some(z) = cutter.lowest_on_line(line, frame.center_x(p0 + k), y) {
                    let z = z as f32;
                    if f64::from(*c - z) > tolerance {
                        cut = true;
                    }
                    *c = c.min(z);
                }
            }
        }
    }
    cut && seg.rapid
}

fn carve_arc_row(
    frame: &Frame,
    cells: &mut [f32],
    arc: &Arc,
    cutter: &Cutter,
    y: f64,
    tolerance: f64,
) -> bool {
    let mut cut = false;
    for (lo, hi) in arc.spans(cutter.radius, y).into_iter().flatten() {
        let Some((i0, i1)) = frame.columns(lo, hi) else {
            continue;
        };
        for (k, c) in cells[i0..=i1].iter_mut().enumerate() {
            if let Some(z) = cutter.lowest_on_arc(arc, frame.center_x(i0 + k), y) {
                let z = z as f32;
                if f64::from(*c - z) > tolerance {
                    cut = true;
                }
                *c = c.min(z);
            }
        }
    }
    cut
}
