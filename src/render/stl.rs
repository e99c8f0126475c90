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
    let top = |i: usize, j: usize| {
        let h = heights[(j * my / py).min(my - 1) * mx + (i * mx / px).min(mx - 1)];
        Vertex::new([x_of(i), y_of(j), h])
    };
    let bottom = grid.bottom as f32;
    let low = |i: usize, j: usize| Vertex::new([x_of(i), y_of(j), bottom]);
    let mut triangles: Vec<Triangle> = Vec::with_capacity(2 * px * py + 4 * (px + py));
    let mut quad = |a: Vertex, b: Vertex, c: Vertex, d: Vertex| {
        // a b c d counter-clockwise seen from outside.
        triangles.push(facet(a, b, c));
        triangles.push(facet(a, c, d));
    };
    for j in 0..py - 1 {
        for i in 0..px - 1 {
            quad(top(i, j), top(i + 1, j), top(i + 1, j + 1), top(i, j + 1));
        }
    }
    for i in 0..px - 1 {
        // South wall (facing -y) and north wall (facing +y).
        quad(low(i, 0), low(i + 1, 0), top(i + 1, 0), top(i, 0));
        let n = py - 1;
        quad(low(i + 1, n), low(i, n), top(i, n), top(i + 1, n));
    }
    for j in 0..py - 1 {
        // West wall (facing -x) and east wall (facing +x).
        quad(low(0, j + 1), low(0, j), top(0, j), top(0, j + 1));
        let n = px - 1;
        quad(low(n, j), low(n, j + 1), top(n, j + 1), top(n, j));
    }
    quad(
        low(0, 0),
        low(0, py - 1),
        low(px - 1, py - 1),
        low(px - 1, 0),
    );
    stl_io::write_stl(out, triangles.iter())
}

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
