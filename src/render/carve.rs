//! The simulation: a heightmap of the stock, one f32 per cell, from which
//! every move removes exactly its swept volume (SPEC §7). Each cell keeps
//! the lowest height any cutter reached over its centre. The rows are cut
//! into bands that the cores carve independently (rayon), each band taking
//! the moves that touch it in program order, so the bytes are the same on
//! any number of cores.

use super::cutter::{crossing, Arc, Cutter, Line, LineSweep, Profile};
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
    /// 1 / cell: a division per row of every move costs more than the
    /// rest of the row's bookkeeping.
    per_cell: f64,
}

impl Frame {
    pub fn new(x0: f64, y0: f64, cell: f64, nx: usize, ny: usize) -> Frame {
        Frame {
            x0,
            y0,
            cell,
            nx,
            ny,
            per_cell: 1.0 / cell,
        }
    }

    pub fn center_x(&self, i: usize) -> f64 {
        self.x0 + (i as f64 + 0.5) * self.cell
    }

    pub fn center_y(&self, j: usize) -> f64 {
        self.y0 + (j as f64 + 0.5) * self.cell
    }

    /// The cells whose centres lie in `[lo, hi]`, clipped to the grid.
    pub fn columns(&self, lo: f64, hi: f64) -> Option<(usize, usize)> {
        Self::clip(self.x0, self.per_cell, self.nx, lo, hi)
    }

    /// The rows whose centres lie in `[lo, hi]`, clipped to the grid.
    pub fn rows(&self, lo: f64, hi: f64) -> Option<(usize, usize)> {
        Self::clip(self.y0, self.per_cell, self.ny, lo, hi)
    }

    #[inline]
    fn clip(origin: f64, per_cell: f64, n: usize, lo: f64, hi: f64) -> Option<(usize, usize)> {
        // By truncating casts, not `ceil`/`floor`: without SSE4.1 those are
        // library calls, and this runs for every row of every move.
        // Signed integers: unsigned conversions take several instructions.
        let a = (lo - origin) * per_cell - 0.5;
        let b = (hi - origin) * per_cell - 0.5;
        // NaN bounds (from a NaN coordinate) select nothing.
        if a.is_nan() || b.is_nan() || a > b || b < 0.0 {
            return None;
        }
        let last_cell = n as i64 - 1;
        let t = a.max(-1.0).min(last_cell as f64 + 1.0) as i64;
        let first = (t + i64::from((t as f64) < a)).max(0);
        let last = (b.min(last_cell as f64) as i64).min(last_cell);
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

    /// Whether a height is cut through the stock (at or below its bottom).
    pub fn through(&self, z: f32) -> bool {
        f64::from(z) <= self.bottom + (self.top - self.bottom) * 1e-6
    }

    /// The grid in blocks of `b` x `b` cells, for a picture or a mesh that
    /// cannot hold every cell: a block is cut through when most of its
    /// cells are, else at the lowest of its other cells (a cut narrower
    /// than a block stays visible, a wall between two holes stays).
    pub fn reduced(&self, b: usize) -> Grid {
        let f = self.frame;
        if b <= 1 {
            return self.clone();
        }
        let (mx, my) = (f.nx.div_ceil(b), f.ny.div_ceil(b));
        let mut lowest = vec![f32::INFINITY; mx * my];
        let mut holes = vec![0u32; mx * my];
        for j in 0..f.ny {
            let row = &self.z[j * f.nx..(j + 1) * f.nx];
            let out = (j / b) * mx;
            for (i, &z) in row.iter().enumerate() {
                let k = out + i / b;
                if self.through(z) {
                    holes[k] += 1;
                } else {
                    lowest[k] = lowest[k].min(z);
                }
            }
        }
        let z = (0..mx * my)
            .map(|k| {
                let (i, j) = (k % mx, k / mx);
                let cells = (b.min(f.nx - i * b) * b.min(f.ny - j * b)) as u32;
                match 2 * holes[k] > cells || lowest[k].is_infinite() {
                    true => self.bottom as f32,
                    false => lowest[k],
                }
            })
            .collect();
        Grid {
            frame: Frame::new(f.x0, f.y0, f.cell * b as f64, mx, my),
            top: self.top,
            bottom: self.bottom,
            z,
        }
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
            let mut at = 0;
            while at < list.len() {
                let k = list[at] as usize;
                let seg = &segments[k];
                // A run of level feeds of one flat cutter, each from where
                // the one before ended, is carved as one polyline.
                let run = flat_run(segments, cutters, &list[at..]);
                if run >= 2 {
                    band.carve_flat_run(&segments[k..k + run], &cutters[seg.cutter]);
                    at += run;
                    continue;
                }
                // The sweep that carries on from this one, if it does.
                let next = segments
                    .get(k + 1)
                    .filter(|n| n.continues && !n.rapid && n.cutter == seg.cutter);
                if band.carve(seg, next, &cutters[seg.cutter]) && seg.rapid {
                    cut.push(seg.move_index);
                }
                at += 1;
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

/// How many segments from the start of `list` form a run that
/// [`Band::carve_flat_run`] can carve: level feeds along lines, with one
/// flat cutter at one height, each continuing the one before, consecutive
/// in the program.
fn flat_run(segments: &[Segment], cutters: &[Cutter], list: &[u32]) -> usize {
    let level = |s: &Segment| match &s.shape {
        Shape::Line(l) if !s.rapid && l.dz == 0.0 => {
            (cutters[s.cutter].profile == Profile::Flat).then_some((s.cutter, l.a[2]))
        }
        Shape::Line(_) | Shape::Arc(_) => None,
    };
    let Some(first) = list.first().and_then(|&k| level(&segments[k as usize])) else {
        return 0;
    };
    let mut run = 1;
    while let Some(&k) = list.get(run) {
        let seg = &segments[k as usize];
        if k != list[0] + run as u32 || !seg.continues || level(seg) != Some(first) {
            break;
        }
        run += 1;
    }
    run
}

struct Band<'a> {
    frame: &'a Frame,
    first_row: usize,
    cells: &'a mut [f32],
    tolerance: f64,
}

impl Band<'_> {
    /// Carve a run of level lines of one flat cutter at one height, each
    /// starting where the one before ended (see [`flat_run`]): on each
    /// row, the cells within the radius of the polyline, as the union of
    /// the segments' spans. Per row, each joint's disc is worked out once
    /// and the cells are filled once per stretch of the union, not once
    /// per segment.
    fn carve_flat_run(&mut self, run: &[Segment], cutter: &Cutter) {
        let frame = self.frame;
        let r = cutter.radius;
        let r2 = r * r;
        let lines: Vec<&Line> = run
            .iter()
            .filter_map(|s| match &s.shape {
                Shape::Line(l) => Some(l),
                Shape::Arc(_) => None,
            })
            .collect();
        let Some(first) = lines.first() else {
            return;
        };
        let z = first.a[2] as f32;
        let (mut y_min, mut y_max) = (first.a[1], first.a[1]);
        for l in &lines {
            let end = l.a[1] + l.v[1];
            y_min = y_min.min(end);
            y_max = y_max.max(end);
        }
        let rows_here = self.cells.len() / frame.nx;
        let Some((first_row, last_row)) = frame.rows(y_min - r, y_max + r) else {
            return;
        };
        let first_row = first_row.max(self.first_row);
        let last_row = last_row.min(self.first_row + rows_here - 1);
        let chord = |dy: f64| {
            let q = r2 - dy * dy;
            (q >= 0.0).then(|| q.sqrt())
        };
        for row in first_row..=last_row {
            let y = frame.center_y(row);
            let at = (row - self.first_row) * frame.nx;
            let cells = &mut self.cells[at..at + frame.nx];
            let mut fill = |(lo, hi): (f64, f64)| {
                if let Some((i0, i1)) = frame.columns(lo, hi) {
                    for c in &mut cells[i0..=i1] {
                        *c = c.min(z);
                    }
                }
            };
            let mut union: Option<(f64, f64)> = None;
            let mut w_start = chord(y - first.a[1]);
            for l in &lines {
                let (ax, ay) = (l.a[0], l.a[1]);
                let (bx, by) = (ax + l.v[0], ay + l.v[1]);
                let w_end = chord(y - by);
                let (dy_a, dy_b) = (y - ay, y - by);
                // Far from the row on one side: nothing of it here.
                if (dy_a > r && dy_b > r) || (dy_a < -r && dy_b < -r) {
                    w_start = w_end;
                    continue;
                }
                let mut lo = f64::INFINITY;
                let mut hi = f64::NEG_INFINITY;
                for (x, w) in [(ax, w_start), (bx, w_end)] {
                    if let Some(w) = w {
                        lo = lo.min(x - w);
                        hi = hi.max(x + w);
                    }
                }
                if l.length > 0.0 {
                    // The band's long edges, the line offset by r each way.
                    let (nx, ny) = (-l.v[1] / l.length * r, l.v[0] / l.length * r);
                    for side in [1.0, -1.0] {
                        let p = (ax + side * nx, ay + side * ny);
                        let q = (bx + side * nx, by + side * ny);
                        if let Some(x) = crossing(p, q, y) {
                            lo = lo.min(x);
                            hi = hi.max(x);
                        }
                    }
                }
                w_start = w_end;
                if lo > hi {
                    continue;
                }
                union = match union {
                    Some((u0, u1)) if lo <= u1 && hi >= u0 => Some((u0.min(lo), u1.max(hi))),
                    Some(done) => {
                        fill(done);
                        Some((lo, hi))
                    }
                    None => Some((lo, hi)),
                };
            }
            if let Some(done) = union {
                fill(done);
            }
        }
    }

    /// Carve one segment into the band's rows; whether it lowered any cell
    /// by more than the tolerance.
    fn carve(&mut self, seg: &Segment, next: Option<&Segment>, cutter: &Cutter) -> bool {
        let frame = self.frame;
        let r = cutter.radius;
        let b = seg.bounds();
        let rows_here = self.cells.len() / frame.nx;
        let Some((first, last)) = frame.rows(b[1] - r, b[3] + r) else {
            return false;
        };
        let first = first.max(self.first_row);
        let last = last.min(self.first_row + rows_here - 1);
        // A line's sweep is worked out once for all its rows.
        let sweep = match &seg.shape {
            Shape::Line(line) => Ok(LineSweep::new(*cutter, *line)),
            Shape::Arc(arc) => Err(arc),
        };
        let next = match next.map(|n| &n.shape) {
            Some(Shape::Line(line)) if !seg.rapid => Some(LineSweep::new(*cutter, *line)),
            _ => None,
        };
        let mut cut = false;
        for row in first..=last {
            let y = frame.center_y(row);
            let at = (row - self.first_row) * frame.nx;
            let cells = &mut self.cells[at..at + frame.nx];
            cut |= match &sweep {
                Ok(sweep) => {
                    carve_line_row(frame, cells, sweep, next.as_ref(), y, seg, self.tolerance)
                }
                Err(arc) => carve_arc_row(frame, cells, arc, cutter, y, self.tolerance),
            };
        }
        cut
    }
}

fn carve_line_row(
    frame: &Frame,
    cells: &mut [f32],
    sweep: &LineSweep,
    next: Option<&LineSweep>,
    y: f64,
    seg: &Segment,
    tolerance: f64,
) -> bool {
    let Some(((lo, hi), start)) = sweep.spans(y) else {
        return false;
    };
    let Some((i0, i1)) = frame.columns(lo, hi) else {
        return false;
    };
    let mut pieces = [(i0, i1), (1, 0)];
    if seg.continues {
        let inset = frame.cell * 1e-6;
        if let Some((d0, d1)) = start.and_then(|(s0, s1)| frame.columns(s0 + inset, s1 - inset)) {
            // The cells before and after the stretch carved already.
            let before = if d0 > i0 {
                (i0, (d0 - 1).min(i1))
            } else {
                (1, 0)
            };
            let after = if d1 < i1 {
                ((d1 + 1).max(i0), i1)
            } else {
                (1, 0)
            };
            pieces = [before, after];
        }
    }
    let line = &sweep.line;
    let level_flat = sweep.cutter.profile == Profile::Flat && line.dz.abs() < 1e-12;
    let mut cut = false;
    for (p0, p1) in pieces {
        if p0 > p1 {
            continue;
        }
        let row = &mut cells[p0..=p1];
        if level_flat {
            let z = line.a[2] as f32;
            if seg.rapid {
                cut |= row.iter().any(|&c| f64::from(c - z) > tolerance);
            }
            for c in row.iter_mut() {
                *c = c.min(z);
            }
            continue;
        }
        // Nothing on this row goes below the floor: where the stock is
        // already there, the cutter cannot touch it.
        let floor = sweep.row_floor(y) as f32;
        if row.iter().fold(f32::NEG_INFINITY, |m, &c| m.max(c)) <= floor {
            continue;
        }
        for (k, c) in row.iter_mut().enumerate() {
            if *c <= floor {
                continue;
            }
            if let Some(z) = sweep.lowest(frame.center_x(p0 + k), y, seg.continues, next) {
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
