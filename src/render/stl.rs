//! The carved part as a closed binary STL mesh: the top surface through
//! the cell centres, four walls and a bottom at the stock's bottom. A grid
//! with more than [`MAX_CELLS`] cells is meshed over blocks of cells, each
//! at its lowest height (so no cut is lost), and the caller says so.

use super::carve::Grid;
use std::io::Write;
use stl_io::{Normal, Triangle, Vertex};

/// At most this many mesh points (two triangles each, about 100 bytes).
pub const MAX_CELLS: usize = 1_000_000;

/// How many cells of the grid one mesh point stands for, on a side.
pub fn block(grid: &Grid) -> usize {
    let cells = grid.frame.nx * grid.frame.ny;
    ((cells as f64 / MAX_CELLS as f64).sqrt().ceil() as usize).max(1)
}

/// Write the mesh.
pub fn write(grid: &Grid, out: &mut impl Write) -> std::io::Result<()> {
    let b = block(grid);
    let f = grid.frame;
    let (mx, my) = (f.nx.div_ceil(b), f.ny.div_ceil(b));
    // The lowest height of each block.
    let mut heights = vec![f32::INFINITY; mx * my];
    for j in 0..f.ny {
        for i in 0..f.nx {
            let h = &mut heights[(j / b) * mx + i / b];
            *h = h.min(grid.at(i, j));
        }
    }
    // At least two points a side; the outer ones on the stock's edges.
    let (px, py) = (mx.max(2), my.max(2));
    let width = f.nx as f64 * f.cell;
    let depth = f.ny as f64 * f.cell;
    let x_of = |i: usize| (f.x0 + width * i as f64 / (px - 1) as f64) as f32;
    let y_of = |j: usize| (f.y0 + depth * j as f64 / (py - 1) as f64) as f32;
    let bottom = grid.bottom as f32;
    // A cut through the stock leaves a skin a thousandth of it thick, so
    // that the top never meets the bottom and the mesh stays closed.
    let floor = bottom + ((grid.top - grid.bottom) * 1e-3) as f32;
    let top = |i: usize, j: usize| {
        let h = heights[(j * my / py).min(my - 1) * mx + (i * mx / px).min(mx - 1)];
        Vertex::new([x_of(i), y_of(j), h.max(floor)])
    };
    let low = |i: usize, j: usize| Vertex::new([x_of(i), y_of(j), bottom]);
    let (top, low) = (&top, &low);
    // The top: a b c d counter-clockwise seen from above.
    let surface = (0..py - 1).flat_map(move |j| {
        (0..px - 1).flat_map(move |i| {
            let (a, b, c, d) = (top(i, j), top(i + 1, j), top(i + 1, j + 1), top(i, j + 1));
            [facet(a, b, c), facet(a, c, d)]
        })
    });
    // The walls, each from its bottom edge p → q (counter-clockwise round
    // the stock seen from above) up to the top; the bottom is a fan from
    // its centre over the same edges, so each edge has exactly two faces.
    let center = Vertex::new([
        (f.x0 + width / 2.0) as f32,
        (f.y0 + depth / 2.0) as f32,
        bottom,
    ]);
    let (n, e) = (py - 1, px - 1);
    let mut edges = Vec::with_capacity(2 * (e + n));
    for i in 0..e {
        edges.push(((i, 0), (i + 1, 0)));
        edges.push(((i + 1, n), (i, n)));
    }
    for j in 0..n {
        edges.push(((e, j), (e, j + 1)));
        edges.push(((0, j + 1), (0, j)));
    }
    let count = 2 * e * n + 3 * edges.len();
    let walls = edges.into_iter().flat_map(move |((i, j), (k, l))| {
        let (p, q) = (low(i, j), low(k, l));
        [
            facet(p, q, top(k, l)),
            facet(p, top(k, l), top(i, j)),
            facet(center, q, p),
        ]
    });
    // Made as they are written: a million-point mesh is 100 MB of triangles.
    stl_io::write_stl(
        out,
        Counted {
            inner: surface.chain(walls),
            left: count,
        },
    )
}

/// An iterator that knows its length (`write_stl` writes the count first).
struct Counted<I> {
    inner: I,
    left: usize,
}

impl<I: Iterator<Item = Triangle>> Iterator for Counted<I> {
    type Item = Triangle;

    fn next(&mut self) -> Option<Triangle> {
        let next = self.inner.next()?;
        self.left = self.left.saturating_sub(1);
        Some(next)
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        (self.left, Some(self.left))
    }
}

impl<I: Iterator<Item = Triangle>> ExactSizeIterator for Counted<I> {}

/// A triangle with its normal (zero for a degenerate one).
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
