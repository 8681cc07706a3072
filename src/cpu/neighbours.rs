//! `neighbours`: bin particles into square cells of half the kernel's support with a counting
//! sort (count, prefix scan, scatter), then list each particle's neighbours and axis ghosts
//! with their separation and kernel gradient. Within a cell particles keep ascending index
//! order, so every neighbour loop visits them in the same order on every run. The gathers of
//! one step (`sph_rates`, `sph_filter`, `sph_forces`) read the list instead of searching the
//! cells again: the search and the kernel gradient were most of their time.

use rayon::prelude::*;

use crate::kernel::Kernel;

/// Particles binned by cell, and the neighbours of each at the positions binned.
#[derive(Clone, Debug, Default)]
pub struct CellGrid {
    /// Cell edge (m): half the kernel support radius, so a neighbour search visits 5×5 cells
    /// (25 h² of candidates instead of the 36 h² of 3×3 cells of the full support).
    pub cell: f32,
    pub z0: f32,
    pub n_r: u32,
    pub n_z: u32,
    /// `sorted[cell_start[c]..cell_start[c + 1]]` are the particles of cell c.
    pub cell_start: Vec<u32>,
    pub sorted: Vec<u32>,
    /// Scratch of `run`: each particle's cell.
    pub cell_of: Vec<u32>,
    /// The neighbours of particles `[k·PAIR_CHUNK, (k + 1)·PAIR_CHUNK)` in chunk k, each
    /// particle's in [`for_each_neighbour`]'s order.
    chunks: Vec<PairChunk>,
}

/// Particles per chunk of the neighbour list: each chunk is filled by one task.
const PAIR_CHUNK: usize = 256;

#[derive(Clone, Debug, Default)]
struct PairChunk {
    /// `pairs[start[k]..start[k + 1]]` are the neighbours of the chunk's k-th particle.
    start: Vec<u32>,
    pairs: Vec<Pair>,
}

/// A neighbour as the gathers read it: [`Neighbour`] with the kernel's `dW/d|x| / |x|`.
#[derive(Clone, Copy, Debug)]
pub struct Pair {
    /// j, with [`MIRROR`] set for j's axis ghost.
    j_mirror: u32,
    /// x_i − x_j (x_j mirrored for a ghost).
    pub dr: f32,
    pub dz: f32,
    pub dist: f32,
    /// `dW/d|x| / |x|`, 0 for coincident particles (`Kernel::coincident`).
    df: f32,
}

/// The bit of `Pair::j_mirror` that marks an axis ghost.
const MIRROR: u32 = 1 << 31;

impl Pair {
    #[inline]
    pub fn j(&self) -> usize {
        (self.j_mirror & !MIRROR) as usize
    }

    #[inline]
    pub fn mirror(&self) -> bool {
        self.j_mirror & MIRROR != 0
    }

    /// ∇_i W_ij, the same bits as `Kernel::grad(dr, dz, dist)` (but for the sign of a zero
    /// between coincident particles).
    #[inline]
    pub fn grad(&self) -> [f32; 2] {
        [self.df * self.dr, self.df * self.dz]
    }
}

/// Cells searched on each side of a particle's own cell.
pub(crate) const REACH: u32 = 2;

/// Cells are capped so that a particle thrown far away cannot make the grid huge; such a
/// particle is clamped into an edge cell (the distance test keeps the result right) and the
/// solver stops the run when a particle escapes (see `integrate`).
pub(crate) const MAX_CELLS_PER_AXIS: u32 = 1 << 14;

impl CellGrid {
    /// The neighbours and axis ghosts of particle i within the kernel's support, at the
    /// positions `run` binned.
    #[inline]
    pub fn neighbours(&self, i: usize) -> &[Pair] {
        let chunk = &self.chunks[i / PAIR_CHUNK];
        let k = i % PAIR_CHUNK;
        &chunk.pairs[chunk.start[k] as usize..chunk.start[k + 1] as usize]
    }

    fn index(&self, r: f32, z: f32) -> (u32, u32) {
        let ir = ((r / self.cell).max(0.0) as u32).min(self.n_r - 1);
        let iz = (((z - self.z0) / self.cell).max(0.0) as u32).min(self.n_z - 1);
        (ir, iz)
    }

    /// Call `f(j)` for every particle j in the 5×5 cells around (r, z) (j may be far: the
    /// caller tests the distance).
    #[inline]
    pub fn for_each_candidate(&self, r: f32, z: f32, mut f: impl FnMut(usize)) {
        let (ir, iz) = self.index(r, z);
        let r_lo = ir.saturating_sub(REACH);
        let r_hi = (ir + REACH).min(self.n_r - 1);
        let z_lo = iz.saturating_sub(REACH);
        let z_hi = (iz + REACH).min(self.n_z - 1);
        for cz in z_lo..=z_hi {
            let row = cz * self.n_r;
            let start = self.cell_start[(row + r_lo) as usize] as usize;
            let end = self.cell_start[(row + r_hi + 1) as usize] as usize;
            for &j in &self.sorted[start..end] {
                f(j as usize);
            }
        }
    }
}

/// Rebuild the grid and the neighbour list for the current positions.
pub fn run(grid: &mut CellGrid, r: &[f32], z: &[f32], kernel: &Kernel) {
    let support = kernel.support();
    bin(grid, r, z, support);
    let n = r.len();
    let chunks = n.div_ceil(PAIR_CHUNK);
    grid.chunks.resize_with(chunks, PairChunk::default);
    let mut chunk_list = std::mem::take(&mut grid.chunks);
    let g = &*grid;
    chunk_list
        .par_iter_mut()
        .enumerate()
        .for_each(|(c, chunk)| {
            chunk.start.clear();
            chunk.pairs.clear();
            chunk.start.push(0);
            for i in c * PAIR_CHUNK..((c + 1) * PAIR_CHUNK).min(n) {
                for_each_neighbour(g, r, z, i, support, |nb| {
                    chunk.pairs.push(Pair {
                        j_mirror: nb.j as u32 | if nb.mirror { MIRROR } else { 0 },
                        dr: nb.dr,
                        dz: nb.dz,
                        dist: nb.dist,
                        df: if kernel.coincident(nb.dist) {
                            0.0
                        } else {
                            kernel.dw(nb.dist) / nb.dist
                        },
                    });
                });
                chunk.start.push(chunk.pairs.len() as u32);
            }
        });
    grid.chunks = chunk_list;
}

/// Rebuild the cells for the current positions. Cells are numbered row by row (z outer), so
/// the cells of a row searched are one contiguous run of `sorted`.
fn bin(grid: &mut CellGrid, r: &[f32], z: &[f32], support: f32) {
    let n = r.len();
    let mut r_max = 0.0f32;
    let mut z_min = f32::MAX;
    let mut z_max = f32::MIN;
    for i in 0..n {
        r_max = r_max.max(r[i]);
        z_min = z_min.min(z[i]);
        z_max = z_max.max(z[i]);
    }
    if n == 0 {
        z_min = 0.0;
        z_max = 0.0;
    }
    grid.cell = support / REACH as f32;
    grid.z0 = z_min;
    grid.n_r = ((r_max / grid.cell) as u32 + 1).min(MAX_CELLS_PER_AXIS);
    grid.n_z = (((z_max - z_min) / grid.cell) as u32 + 1).min(MAX_CELLS_PER_AXIS);
    let cells = (grid.n_r * grid.n_z) as usize;
    grid.cell_start.clear();
    grid.cell_start.resize(cells + 1, 0);
    grid.cell_of.resize(n, 0);
    for i in 0..n {
        let (ir, iz) = grid.index(r[i], z[i]);
        let c = iz * grid.n_r + ir;
        grid.cell_of[i] = c;
        grid.cell_start[c as usize + 1] += 1;
    }
    for c in 0..cells {
        grid.cell_start[c + 1] += grid.cell_start[c];
    }
    grid.sorted.resize(n, 0);
    let mut fill: Vec<u32> = grid.cell_start[..cells].to_vec();
    for i in 0..n {
        let c = grid.cell_of[i] as usize;
        grid.sorted[fill[c] as usize] = i as u32;
        fill[c] += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cell search finds exactly the pairs a brute-force search finds.
    #[test]
    fn finds_every_neighbour() {
        let mut r = Vec::new();
        let mut z = Vec::new();
        let mut seed = 12345u32;
        for _ in 0..400 {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            r.push((seed % 1000) as f32 * 1e-4);
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            z.push(-((seed % 1000) as f32) * 1e-4);
        }
        let kernel = Kernel::new(0.0035);
        let support = kernel.support();
        let mut grid = CellGrid::default();
        run(&mut grid, &r, &z, &kernel);
        for i in 0..r.len() {
            let mut found = Vec::new();
            grid.for_each_candidate(r[i], z[i], |j| {
                if (r[i] - r[j]).hypot(z[i] - z[j]) < support {
                    found.push(j)
                }
            });
            found.sort();
            let brute: Vec<usize> = (0..r.len())
                .filter(|&j| (r[i] - r[j]).hypot(z[i] - z[j]) < support)
                .collect();
            assert_eq!(found, brute, "particle {i}");
        }
    }

    /// The list holds what the cell search visits, in its order, with the kernel's gradient to
    /// the bit: the gathers that read it sum the same terms as a search would.
    #[test]
    fn the_list_is_the_search() {
        let n = 700; // more than one chunk
        let r: Vec<f32> = (0..n).map(|k| (k % 20) as f32 * 1.1e-3 + 1e-4).collect();
        let z: Vec<f32> = (0..n)
            .map(|k| -((k / 20) as f32) * 1.0e-3 - (k % 7) as f32 * 1e-5)
            .collect();
        let kernel = Kernel::new(1.5e-3);
        let mut grid = CellGrid::default();
        run(&mut grid, &r, &z, &kernel);
        let mut ghosts = 0;
        for i in 0..n {
            let mut searched = Vec::new();
            for_each_neighbour(&grid, &r, &z, i, kernel.support(), |nb| searched.push(nb));
            let listed = grid.neighbours(i);
            assert_eq!(listed.len(), searched.len(), "particle {i}");
            for (l, s) in listed.iter().zip(&searched) {
                assert_eq!((l.j(), l.mirror()), (s.j, s.mirror), "particle {i}");
                assert_eq!(
                    [l.dr, l.dz, l.dist].map(f32::to_bits),
                    [s.dr, s.dz, s.dist].map(f32::to_bits)
                );
                let g = kernel.grad(s.dr, s.dz, s.dist);
                assert_eq!(l.grad().map(f32::to_bits), g.map(f32::to_bits));
                ghosts += s.mirror as usize;
            }
        }
        assert!(ghosts > 0);
    }
}

/// One neighbour of particle i: a real particle j, or the mirror image of j across the axis
/// (r → −r, v_r → −v_r, S_rz → −S_rz; physics.md §3 axis ghosts).
#[derive(Clone, Copy, Debug)]
pub struct Neighbour {
    pub j: usize,
    /// x_i − x_j (x_j mirrored when `mirror`).
    pub dr: f32,
    pub dz: f32,
    pub dist: f32,
    pub mirror: bool,
}

/// Call `f` for every neighbour of particle i within `support`: first the real ones (j ≠ i),
/// then, near the axis, the axis ghosts (j = i included). A ghost of j is never nearer than j
/// itself, so the ghosts are found among the same candidates. (Two sweeps, not one, so that the
/// GPU twin, shaders/neighbour_loop.wgsl, can skip the ghost sweep away from the axis; the
/// order of the sums is the same on both sides.)
#[inline]
pub fn for_each_neighbour(
    grid: &CellGrid,
    r: &[f32],
    z: &[f32],
    i: usize,
    support: f32,
    mut f: impl FnMut(Neighbour),
) {
    let (ri, zi) = (r[i], z[i]);
    let s2 = support * support;
    grid.for_each_candidate(ri, zi, |j| {
        let dr = ri - r[j];
        let dz = zi - z[j];
        let d2 = dr * dr + dz * dz;
        if d2 < s2 && j != i {
            f(Neighbour {
                j,
                dr,
                dz,
                dist: d2.sqrt(),
                mirror: false,
            });
        }
    });
    if ri < support {
        grid.for_each_candidate(ri, zi, |j| {
            let dr = ri + r[j];
            let dz = zi - z[j];
            let d2 = dr * dr + dz * dz;
            if d2 < s2 {
                f(Neighbour {
                    j,
                    dr,
                    dz,
                    dist: d2.sqrt(),
                    mirror: true,
                });
            }
        });
    }
}
