//! The carved part as a closed binary STL mesh (SPEC §7). Each cell is a
//! column of material from the stock's bottom up to its height (a cell cut
//! through is none), so the mesh holds exactly the grid's volume: cells of
//! one height are merged into rectangles on top, the walls between
//! columns of different heights are kept, and the bottom is merged too.
//! Every face's edges are split where another face has a corner on them,
//! so that each edge is shared by exactly two triangles, wound one way
//! each (a slicer needs no repair). A grid whose mesh would be too large
//! is meshed over blocks of cells, each at its lowest height, and the
//! caller says so. Must not carve, or change a height but to part two
//! columns that touch only along an edge (see [`unpinch`]).

use super::carve::Grid;
use std::collections::HashMap;
use std::io::Write;
use stl_io::{Normal, Triangle, Vertex};

/// At most this many runs of equal heights along the rows: a grid with
/// more (a surface of ever-changing heights) is meshed in blocks.
pub const MAX_RUNS: usize = 100_000;

/// The mesh, and how it was made.
pub struct Mesh {
    pub triangles: Vec<Triangle>,
    /// How many cells a side one column stands for.
    pub block: usize,
    /// Columns raised to part two that touched only along an edge.
    pub raised: usize,
}

/// The columns of the mesh: heights (the stock's bottom where cut through
/// or outside) and where the grid's lines are.
struct Columns {
    nx: usize,
    ny: usize,
    z: Vec<f32>,
    bottom: f32,
    xs: Vec<f32>,
    ys: Vec<f32>,
}

impl Columns {
    fn of(grid: &Grid, b: usize) -> Columns {
        let g = grid.reduced(b);
        let f = g.frame;
        let bottom = grid.bottom as f32;
        let (x_end, y_end) = (
            grid.frame.x0 + grid.frame.nx as f64 * grid.frame.cell,
            grid.frame.y0 + grid.frame.ny as f64 * grid.frame.cell,
        );
        let z =
            g.z.iter()
                .map(|&z| if g.through(z) { bottom } else { z })
                .collect();
        Columns {
            nx: f.nx,
            ny: f.ny,
            z,
            bottom,
            // The last line on the stock's edge, where a block overhangs it.
            xs: (0..=f.nx)
                .map(|i| (f.x0 + i as f64 * f.cell).min(x_end) as f32)
                .collect(),
            ys: (0..=f.ny)
                .map(|j| (f.y0 + j as f64 * f.cell).min(y_end) as f32)
                .collect(),
        }
    }

    /// The height at (i, j); outside the grid, the bottom.
    fn at(&self, i: isize, j: isize) -> f32 {
        if i < 0 || j < 0 || i as usize >= self.nx || j as usize >= self.ny {
            self.bottom
        } else {
            self.z[j as usize * self.nx + i as usize]
        }
    }

    /// Runs of one height along the rows: what the mesh's size follows.
    fn runs(&self) -> usize {
        self.z
            .chunks_exact(self.nx)
            .map(|row| 1 + row.windows(2).filter(|w| w[0] != w[1]).count())
            .sum()
    }
}

/// The mesh of a carved grid, in blocks when it would be too large.
pub fn mesh(grid: &Grid) -> Mesh {
    let mut b = 1;
    let mut columns = Columns::of(grid, b);
    loop {
        let runs = columns.runs();
        if runs <= MAX_RUNS {
            break;
        }
        let grow = ((runs as f64 / MAX_RUNS as f64).sqrt() * b as f64).ceil() as usize;
        b = grow.max(b + 1);
        columns = Columns::of(grid, b);
    }
    let raised = unpinch(&mut columns);
    let faces = faces(&columns);
    Mesh {
        triangles: triangles(&columns, &faces),
        block: b,
        raised,
    }
}

/// Two columns that meet only along a vertical edge (diagonal neighbours
/// above both others at some height) would make an edge of four faces; the
/// lower of the two others is raised to the lower of the pair, until no
/// corner has such a pair. Heights only rise, so this ends.
fn unpinch(c: &mut Columns) -> usize {
    let mut raised = 0;
    let mut work = Vec::new();
    for j in 1..c.ny {
        for i in 1..c.nx {
            work.push((i, j));
            while let Some((i, j)) = work.pop() {
                raised += unpinch_corner(c, i, j, &mut work);
            }
        }
    }
    raised
}

/// Part the corner at the lines (i, j) if it pinches; the corners to look
/// at again go on `work`.
fn unpinch_corner(c: &mut Columns, i: usize, j: usize, work: &mut Vec<(usize, usize)>) -> usize {
    let k = |a: usize, b: usize| b * c.nx + a;
    let (sw, se, nw, ne) = (k(i - 1, j - 1), k(i, j - 1), k(i - 1, j), k(i, j));
    let mut raised = 0;
    for (pair, (a, b)) in [((sw, ne), (se, nw)), ((se, nw), (sw, ne))] {
        let high = c.z[pair.0].min(c.z[pair.1]);
        let low = if c.z[a] >= c.z[b] { a } else { b };
        if high > c.z[low] {
            c.z[low] = high;
            raised += 1;
            let (li, lj) = (low % c.nx, low / c.nx);
            for (ci, cj) in [(li, lj), (li + 1, lj), (li, lj + 1), (li + 1, lj + 1)] {
                if (1..c.nx).contains(&ci) && (1..c.ny).contains(&cj) {
                    work.push((ci, cj));
                }
            }
        }
    }
    raised
}

/// A corner of a face: the grid line across, the line along, the height.
type Corner = (u32, u32, f32);

/// The faces of the columns, each a rectangle wound counter-clockwise
/// seen from outside.
fn faces(c: &Columns) -> Vec<[Corner; 4]> {
    let mut out = Vec::new();
    let at = |i: usize, j: usize| c.z[j * c.nx + i];
    // Tops: rectangles of one height; the bottom: rectangles of columns.
    for (rect, z) in rectangles(c.nx, c.ny, |i, j| {
        (at(i, j) > c.bottom).then(|| at(i, j).to_bits())
    }) {
        let z = f32::from_bits(z);
        out.push(rect.map(|(x, y)| (x, y, z)));
    }
    for (rect, _) in rectangles(c.nx, c.ny, |i, j| (at(i, j) > c.bottom).then_some(0)) {
        let [a, b, cc, d] = rect.map(|(x, y)| (x, y, c.bottom));
        out.push([a, d, cc, b]);
    }
    walls(c, &mut out);
    out
}

/// Greedy rectangles of cells with the same key (`None`: no face), each
/// as its corners counter-clockwise seen from above.
fn rectangles(
    nx: usize,
    ny: usize,
    key: impl Fn(usize, usize) -> Option<u32>,
) -> Vec<([(u32, u32); 4], u32)> {
    let mut done = vec![false; nx * ny];
    let mut out = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let Some(k) = key(i, j).filter(|_| !done[j * nx + i]) else {
                continue;
            };
            let same = |a: usize, b: usize| !done[b * nx + a] && key(a, b) == Some(k);
            let mut i1 = i + 1;
            while i1 < nx && same(i1, j) {
                i1 += 1;
            }
            let mut j1 = j + 1;
            while j1 < ny && (i..i1).all(|a| same(a, j1)) {
                j1 += 1;
            }
            for b in j..j1 {
                done[b * nx + i..b * nx + i1].fill(true);
            }
            let (x0, y0, x1, y1) = (i as u32, j as u32, i1 as u32, j1 as u32);
            out.push(([(x0, y0), (x1, y0), (x1, y1), (x0, y1)], k));
        }
    }
    out
}

/// The walls between columns of different heights (and between a column
/// and the outside), merged along a line while the two heights stay.
fn walls(c: &Columns, out: &mut Vec<[Corner; 4]>) {
    // Along the lines y = j: the column south (j - 1) and north (j).
    for j in 0..=c.ny {
        let pair = |i: usize| {
            (
                c.at(i as isize, j as isize - 1),
                c.at(i as isize, j as isize),
            )
        };
        for (i0, i1, (south, north)) in runs(c.nx, pair) {
            let (lo, hi) = (south.min(north), south.max(north));
            let (a, b) = (i0 as u32, i1 as u32);
            let j = j as u32;
            // Facing -y when the north column is the higher.
            out.push(match north > south {
                true => [(a, j, lo), (b, j, lo), (b, j, hi), (a, j, hi)],
                false => [(b, j, lo), (a, j, lo), (a, j, hi), (b, j, hi)],
            });
        }
    }
    // Along the lines x = i: the column west (i - 1) and east (i); the
    // corner's first coordinate is still across x. Row by row (a column
    // at a time would read the grid across its rows), each line's run
    // kept open until its pair of heights changes.
    let wall = |i: usize, j0: usize, j1: usize, (west, east): (f32, f32)| {
        let (lo, hi) = (west.min(east), west.max(east));
        let (a, b, i) = (j0 as u32, j1 as u32, i as u32);
        // Facing +x when the west column is the higher.
        match west > east {
            true => [(i, a, lo), (i, b, lo), (i, b, hi), (i, a, hi)],
            false => [(i, b, lo), (i, a, lo), (i, a, hi), (i, b, hi)],
        }
    };
    let mut open: Vec<(usize, (f32, f32))> = Vec::with_capacity(c.nx + 1);
    for j in 0..c.ny {
        for i in 0..=c.nx {
            let pair = (
                c.at(i as isize - 1, j as isize),
                c.at(i as isize, j as isize),
            );
            if j == 0 {
                open.push((0, pair));
            } else if open[i].1 != pair {
                let (j0, was) = open[i];
                if was.0 != was.1 {
                    out.push(wall(i, j0, j, was));
                }
                open[i] = (j, pair);
            }
        }
    }
    for (i, &(j0, was)) in open.iter().enumerate() {
        if was.0 != was.1 {
            out.push(wall(i, j0, c.ny, was));
        }
    }
}

/// Runs `[k0, k1)` of `n` places along a line where the two heights are
/// the same and differ from each other.
fn runs(n: usize, pair: impl Fn(usize) -> (f32, f32)) -> Vec<(usize, usize, (f32, f32))> {
    let mut out = Vec::new();
    let mut k = 0;
    while k < n {
        let p = pair(k);
        let mut end = k + 1;
        while end < n && pair(end) == p {
            end += 1;
        }
        if p.0 != p.1 {
            out.push((k, end, p));
        }
        k = end;
    }
    out
}

/// The faces' corners on each line of the mesh: along x (keyed by y and
/// height), along y (by x and height) and up (by x and y).
struct Lines {
    along_x: HashMap<(u32, u32), Vec<u32>>,
    along_y: HashMap<(u32, u32), Vec<u32>>,
    up: HashMap<(u32, u32), Vec<f32>>,
}

impl Lines {
    fn of(faces: &[[Corner; 4]]) -> Lines {
        let mut lines = Lines {
            along_x: HashMap::new(),
            along_y: HashMap::new(),
            up: HashMap::new(),
        };
        for &(x, y, z) in faces.iter().flatten() {
            lines.along_x.entry((y, z.to_bits())).or_default().push(x);
            lines.along_y.entry((x, z.to_bits())).or_default().push(y);
            lines.up.entry((x, y)).or_default().push(z);
        }
        for v in lines.along_x.values_mut().chain(lines.along_y.values_mut()) {
            v.sort_unstable();
            v.dedup();
        }
        for v in lines.up.values_mut() {
            v.sort_unstable_by(f32::total_cmp);
            v.dedup();
        }
        lines
    }

    /// The corners strictly between `a` and `b` (an edge along one axis),
    /// in order from `a`.
    fn between(&self, a: Corner, b: Corner, out: &mut Vec<Corner>) {
        let start = out.len();
        if a.1 == b.1 && a.2 == b.2 {
            let (lo, hi) = (a.0.min(b.0), a.0.max(b.0));
            if let Some(xs) = self.along_x.get(&(a.1, a.2.to_bits())) {
                out.extend(inner(xs, &lo, &hi).iter().map(|&x| (x, a.1, a.2)));
            }
            if a.0 > b.0 {
                out[start..].reverse();
            }
        } else if a.0 == b.0 && a.2 == b.2 {
            let (lo, hi) = (a.1.min(b.1), a.1.max(b.1));
            if let Some(ys) = self.along_y.get(&(a.0, a.2.to_bits())) {
                out.extend(inner(ys, &lo, &hi).iter().map(|&y| (a.0, y, a.2)));
            }
            if a.1 > b.1 {
                out[start..].reverse();
            }
        } else if let Some(zs) = self.up.get(&(a.0, a.1)) {
            let (lo, hi) = (a.2.min(b.2), a.2.max(b.2));
            let first = zs.partition_point(|z| *z <= lo);
            let last = zs.partition_point(|z| *z < hi);
            out.extend(zs[first..last.max(first)].iter().map(|&z| (a.0, a.1, z)));
            if a.2 > b.2 {
                out[start..].reverse();
            }
        }
    }
}

/// The values of a sorted list strictly between `lo` and `hi`.
fn inner<'a, T: Ord>(sorted: &'a [T], lo: &T, hi: &T) -> &'a [T] {
    let first = sorted.partition_point(|v| v <= lo);
    let last = sorted.partition_point(|v| v < hi);
    &sorted[first..last.max(first)]
}

/// Each face with its edges split at the corners on them, as triangles: a
/// fan from a corner whose two sides are not split, else from the face's
/// centre.
fn triangles(c: &Columns, faces: &[[Corner; 4]]) -> Vec<Triangle> {
    let lines = Lines::of(faces);
    let point = |p: Corner| Vertex::new([c.xs[p.0 as usize], c.ys[p.1 as usize], p.2]);
    let mut out = Vec::with_capacity(faces.len() * 2);
    let mut ring: Vec<Corner> = Vec::new();
    let mut starts = [0usize; 4];
    for face in faces {
        ring.clear();
        for k in 0..4 {
            starts[k] = ring.len();
            ring.push(face[k]);
            lines.between(face[k], face[(k + 1) % 4], &mut ring);
        }
        let n = ring.len();
        // Side k runs from starts[k] to starts[k + 1]; a corner with no
        // point on either side next to it sees every other edge whole.
        let plain = |k: usize| {
            let end = if k == 3 { n } else { starts[k + 1] };
            end - starts[k] == 1
        };
        match (0..4).find(|&k| plain(k) && plain((k + 3) % 4)) {
            Some(k) => {
                let apex = starts[k];
                for s in 1..n - 1 {
                    let (p, q) = ((apex + s) % n, (apex + s + 1) % n);
                    out.push(facet(point(ring[apex]), point(ring[p]), point(ring[q])));
                }
            }
            None => {
                let corners = face.map(point);
                let centre = Vertex::new(std::array::from_fn(|a| {
                    corners.iter().map(|v| v[a]).sum::<f32>() / 4.0
                }));
                for s in 0..n {
                    let (p, q) = (ring[s], ring[(s + 1) % n]);
                    out.push(facet(centre, point(p), point(q)));
                }
            }
        }
    }
    out
}

/// Write the mesh as binary STL.
pub fn write(mesh: &Mesh, out: &mut impl Write) -> std::io::Result<()> {
    stl_io::write_stl(out, mesh.triangles.iter())
}

/// A triangle with its normal.
fn facet(a: Vertex, b: Vertex, c: Vertex) -> Triangle {
    let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let n = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    let n = if len > 0.0 {
        n.map(|k| k / len)
    } else {
        [0.0; 3]
    };
    Triangle {
        normal: Normal::new(n),
        vertices: [a, b, c],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::carve::Frame;

    /// Each edge walked once each way, and the volume (divergence theorem).
    fn closed_volume(mesh: &Mesh) -> f64 {
        let key = |v: Vertex| [v[0].to_bits(), v[1].to_bits(), v[2].to_bits()];
        let mut edges = HashMap::new();
        let mut volume = 0.0;
        for t in &mesh.triangles {
            for k in 0..3 {
                let e = (key(t.vertices[k]), key(t.vertices[(k + 1) % 3]));
                *edges.entry(e).or_insert(0) += 1;
            }
            let v = t.vertices.map(|p| [p[0], p[1], p[2]].map(f64::from));
            volume += (v[0][0] * (v[1][1] * v[2][2] - v[1][2] * v[2][1])
                - v[0][1] * (v[1][0] * v[2][2] - v[1][2] * v[2][0])
                + v[0][2] * (v[1][0] * v[2][1] - v[1][1] * v[2][0]))
                / 6.0;
        }
        for (&(a, b), &n) in &edges {
            assert_eq!((n, edges.get(&(b, a))), (1, Some(&1)), "edge {a:?} {b:?}");
        }
        volume
    }

    fn grid(heights: &[&[f32]]) -> Grid {
        let (nx, ny) = (heights[0].len(), heights.len());
        let mut g = Grid::new(Frame::new(0.0, 0.0, 1.0, nx, ny), 0.0, -4.0).unwrap();
        for (j, row) in heights.iter().enumerate() {
            g.z[j * nx..(j + 1) * nx].copy_from_slice(row);
        }
        g
    }

    #[test]
    fn columns_of_many_heights_and_holes_make_a_closed_mesh_of_their_volume() {
        let g = grid(&[
            &[0.0, -1.0, -1.0, -4.0],
            &[-2.0, -1.0, -3.0, -4.0],
            &[0.0, 0.0, -3.0, -2.5],
        ]);
        let mesh = mesh(&g);
        assert_eq!(mesh.raised, 0);
        let expected = 4.0 * 12.0 - g.removed_volume();
        assert!((closed_volume(&mesh) - expected).abs() < 1e-4);
    }

    #[test]
    fn columns_that_touch_only_along_an_edge_are_parted() {
        // Diagonal neighbours above both others at one corner, and two
        // through holes touching at another.
        let g = grid(&[&[0.0, -2.0, -4.0], &[-3.0, -1.0, 0.0], &[0.0, -4.0, -1.0]]);
        let mesh = mesh(&g);
        assert!(mesh.raised > 0);
        let volume = closed_volume(&mesh);
        assert!(volume > 4.0 * 9.0 - g.removed_volume(), "only raised");
    }
}
