//! The stock over the run, for the page's playback: `ger render`'s exact
//! heightmap ([`carve::carve`] over the same [`Scene`]) carved a stretch
//! of moves at a time, a checkpoint kept after each stretch. A checkpoint
//! is the grid's depths averaged over display cells (so the removed volume
//! the page sums is the grid's), quantised to 16 bits and written as the
//! run-length-coded difference from the checkpoint before. Must not guess
//! a height: between checkpoints the page sweeps, and says so.

use super::moves::{varint, zigzag};
use crate::ir::Units;
use crate::render::carve::{self, Grid};
use crate::render::{rapid_cuts, RenderWarning, Scene};
use crate::toolpath::ToolPath;
use serde_json::{json, Value};

/// The shown grid's longer side, at most.
const DISPLAY_CELLS: usize = 512;

/// At most this many checkpoints; at least this many moves between two.
const CHECKPOINTS: usize = 64;
const MIN_STRETCH: usize = 1000;

pub(super) struct Carved {
    pub json: Value,
    pub removed_mm3: Option<f64>,
    pub warnings: Vec<RenderWarning>,
}

/// Carve `scene`'s segments, keeping the checkpoints in `binary`.
pub(super) fn carve(
    scene: &Scene,
    path: &ToolPath,
    binary: &mut Vec<u8>,
    notes: &mut Vec<String>,
) -> Carved {
    let mut grid = match scene.grid() {
        Ok(grid) => grid,
        Err(e) => {
            notes.push(format!("no stock drawn: {e}"));
            return Carved {
                json: Value::Null,
                removed_mm3: None,
                warnings: Vec::new(),
            };
        }
    };
    let moves = path.moves.len();
    let stretch = moves.div_ceil(CHECKPOINTS).max(MIN_STRETCH);
    let display = Display::of(&grid);
    let mut depths: Vec<Vec<f64>> = Vec::new();
    let mut marks = Vec::new();
    let mut rapid = Vec::new();
    let mut done = 0;
    let mut upto = 0;
    while upto < moves || marks.is_empty() {
        upto = (upto + stretch).min(moves);
        let end = done + scene.segments[done..].partition_point(|s| s.move_index < upto);
        let carved = carve::carve(
            &mut grid,
            &scene.segments[done..end],
            &scene.cutters,
            &|_, _| {},
        );
        rapid.extend(carved.rapid_cuts);
        done = end;
        depths.push(display.depths(&grid));
        marks.push(upto);
    }
    let mm_per = Units::mm_per(scene.units);
    let cell_mm = grid.frame.cell * mm_per;
    let volumes: Vec<f64> = depths
        .iter()
        .map(|d| d.iter().sum::<f64>() * grid.frame.cell * grid.frame.cell * mm_per.powi(3))
        .collect();
    let deepest = depths
        .iter()
        .flat_map(|d| display.means(d))
        .fold(grid.top - grid.bottom, f64::max)
        .max(1e-9);
    let offset = binary.len();
    display.encode(&depths, deepest, binary);
    if display.block > 1 {
        notes.push(format!(
            "the stock is ger render's heightmap of {} x {} cells of {cell_mm:.4} mm, shown as {} x {} cells, each the mean of {} x {}",
            grid.frame.nx, grid.frame.ny, display.nx, display.ny, display.block, display.block
        ));
    }
    notes.push(format!(
        "the stock is exact at checkpoints every {stretch} moves; between them the page sweeps the cut again on the shown cells (approximately)"
    ));
    let stock = scene.stock;
    let json = json!({
        "min": [stock.min[0] * mm_per, stock.min[1] * mm_per],
        "max": [stock.max[0] * mm_per, stock.max[1] * mm_per],
        "top": stock.top * mm_per,
        "bottom": stock.bottom * mm_per,
        "exact": {"nx": grid.frame.nx, "ny": grid.frame.ny, "cell_mm": cell_mm},
        "block": display.block,
        "nx": display.nx,
        "ny": display.ny,
        "depth_mm": deepest * mm_per,
        "checkpoints": marks.iter().zip(&volumes).map(|(m, v)| json!({"moves": m, "removed_mm3": v})).collect::<Vec<_>>(),
        "offset": offset,
        "length": binary.len() - offset,
    });
    Carved {
        json,
        removed_mm3: volumes.last().copied(),
        warnings: rapid_cuts(path, &rapid),
    }
}

/// The shown cells: blocks of `block` x `block` of the grid's.
struct Display {
    block: usize,
    nx: usize,
    ny: usize,
    /// The grid's.
    grid_nx: usize,
    grid_ny: usize,
}

impl Display {
    fn of(grid: &Grid) -> Display {
        let (nx, ny) = (grid.frame.nx, grid.frame.ny);
        let block = nx.max(ny).div_ceil(DISPLAY_CELLS).max(1);
        Display {
            block,
            nx: nx.div_ceil(block),
            ny: ny.div_ceil(block),
            grid_nx: nx,
            grid_ny: ny,
        }
    }

    /// The summed depth below the top of each shown cell's grid cells.
    fn depths(&self, grid: &Grid) -> Vec<f64> {
        let mut sums = vec![0.0; self.nx * self.ny];
        let top = grid.top as f32;
        for (j, row) in grid.z.chunks(self.grid_nx).enumerate() {
            let shown = &mut sums[(j / self.block) * self.nx..][..self.nx];
            for (i, &z) in row.iter().enumerate() {
                shown[i / self.block] += f64::from((top - z).max(0.0));
            }
        }
        sums
    }

    /// How many grid cells shown cell `k` holds.
    fn count(&self, k: usize) -> f64 {
        let (i, j) = (k % self.nx, k / self.nx);
        let w = self.block.min(self.grid_nx - i * self.block);
        let h = self.block.min(self.grid_ny - j * self.block);
        (w * h) as f64
    }

    fn means<'a>(&'a self, sums: &'a [f64]) -> impl Iterator<Item = f64> + 'a {
        sums.iter().enumerate().map(|(k, s)| s / self.count(k))
    }

    /// Each checkpoint's mean depths, as 16-bit fractions of `deepest`,
    /// run-length coded against the one before: runs of unchanged cells
    /// and runs of changed ones with their differences.
    fn encode(&self, checkpoints: &[Vec<f64>], deepest: f64, out: &mut Vec<u8>) {
        let mut before = vec![0i64; self.nx * self.ny];
        for sums in checkpoints {
            let now: Vec<i64> = self
                .means(sums)
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
}
