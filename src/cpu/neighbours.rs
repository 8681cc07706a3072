//! `neighbours`: bin particles into square cells of half the lists' radius with a counting
//! sort (count, prefix scan, scatter), then list each particle's candidates: the neighbours and
//! axis ghosts within the kernel's support grown by a skin (`LIST_SKIN`). The candidates stay
//! complete until some particle has moved half the skin, so they are built again only then; every
//! step keeps those within the support, with their separation and kernel gradient, in the order
//! the search found them, as the GPU's gathers walk its lists. Within a cell particles keep
//! ascending index order, so every neighbour loop visits them in the same order on every run. The
//! gathers of one step (`sph_rates`, `sph_filter`, `sph_forces`) read the list instead of
//! searching the cells again.

use rayon::prelude::*;

use crate::kernel::Kernel;

/// The neighbour lists hold the particles within the support grown by this fraction of it, so
/// they stay complete until some particle has moved half of the growth, and are built only then
/// (on both backends). Measured on lavapipe at 10⁵ particles (`penetrate bench`): a build costs
/// about as much as both gathers together; a skin of 0.05 adds nothing measurable to the
/// gathers, 0.1 adds a third.
pub const LIST_SKIN: f32 = 0.05;

/// The lists are built again once a particle may have moved this fraction of the half-skin (the
/// rest is margin for f32 round-off of the displacements).
pub const SKIN_USE: f32 = 0.9;

/// How far a particle may move from where the lists were built before they must be built again
/// (m), for a kernel of `support` and lists of `skin`.
pub fn list_slack(support: f32, skin: f32) -> f32 {
    SKIN_USE * 0.5 * skin * support
}

/// Particles binned by cell where the lists were built, each particle's candidates there, and
/// its neighbours at the positions the last `run` was given.
#[derive(Clone, Debug, Default)]
pub struct CellGrid {
    /// Cell edge (m): half the lists' radius, so a search visits 5×5 cells (25 cells² of
    /// candidates instead of the 36 of 3×3 cells of the whole radius).
    pub cell: f32,
    pub z0: f32,
    pub n_r: u32,
    pub n_z: u32,
    /// `sorted[cell_start[c]..cell_start[c + 1]]` are the particles of cell c.
    pub cell_start: Vec<u32>,
    pub sorted: Vec<u32>,
    /// Scratch of `bin`: each particle's cell.
    pub cell_of: Vec<u32>,
    /// The positions the cells and the candidates are of (empty: none yet, or moved since).
    built_r: Vec<f32>,
    built_z: Vec<f32>,
    /// Whether `candidates` are those of `built_r`, `built_z` (not after a restart).
    listed: bool,
    /// The candidates of particles `[k·PAIR_CHUNK, (k + 1)·PAIR_CHUNK)` in chunk k, each
    /// particle's in [`for_each_neighbour`]'s order: j, with [`MIRROR`] set for j's axis ghost.
    candidates: Vec<Chunk<u32>>,
    /// The neighbours within the support, chunked as `candidates` and in their order.
    chunks: Vec<Chunk<Pair>>,
    /// Times the candidates were built at new positions.
    pub builds: u64,
}

/// Particles per chunk of the lists: each chunk is filled by one task.
const PAIR_CHUNK: usize = 256;

#[derive(Clone, Debug)]
struct Chunk<T> {
    /// `items[start[k]..start[k + 1]]` are the chunk's k-th particle's.
    start: Vec<u32>,
    items: Vec<T>,
}

impl<T> Default for Chunk<T> {
    fn default() -> Self {
        Chunk {
            start: Vec::new(),
            items: Vec::new(),
        }
    }
}

impl<T> Chunk<T> {
    /// Fill with the items `each(i, push)` pushes for every particle i of chunk `c` of `n`.
    fn fill(&mut self, c: usize, n: usize, mut each: impl FnMut(usize, &mut Vec<T>)) {
        self.start.clear();
        self.items.clear();
        self.start.push(0);
        for i in c * PAIR_CHUNK..((c + 1) * PAIR_CHUNK).min(n) {
            each(i, &mut self.items);
            self.start.push(self.items.len() as u32);
        }
    }

    fn of(&self, k: usize) -> &[T] {
        &self.items[self.start[k] as usize..self.start[k + 1] as usize]
    }
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

/// The bit of a listed j that marks an axis ghost.
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
        self.chunks[i / PAIR_CHUNK].of(i % PAIR_CHUNK)
    }

    /// The positions the candidates were built at (empty when they must be built again).
    pub fn built_at(&self) -> (&[f32], &[f32]) {
        (&self.built_r, &self.built_z)
    }

    /// Take `r`, `z` as the positions the candidates were built at, and `builds` as the builds
    /// so far (a restart's): the next `run` lists the candidates there, as the run that wrote
    /// them had.
    pub fn restore(&mut self, r: Vec<f32>, z: Vec<f32>, builds: u64) {
        self.built_r = r;
        self.built_z = z;
        self.builds = builds;
        self.listed = false;
    }

    /// Build the candidates again at the next `run` (the positions were all moved).
    pub fn invalidate(&mut self) {
        self.built_r.clear();
        self.built_z.clear();
    }

    /// Whether some particle at (r, z) may be nearer a particle than the candidates allow for:
    /// it has moved more than `slack` from where they were built (or a position is not a
    /// number, or there are none).
    fn stale(&self, r: &[f32], z: &[f32], slack: f32) -> bool {
        let n = r.len();
        self.built_r.len() != n
            || self.built_z.len() != n
            || (0..n).any(|i| {
                let (dr, dz) = (r[i] - self.built_r[i], z[i] - self.built_z[i]);
                let moved = (dr * dr + dz * dz).sqrt();
                moved > slack || moved.is_nan()
            })
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

/// Bring the neighbour lists to the positions (r, z): the candidates built again where some
/// particle has moved too far since they were, then those within the support
/// (docs/architecture.md, "Neighbour search").
pub fn run(grid: &mut CellGrid, r: &[f32], z: &[f32], kernel: &Kernel) {
    let support = kernel.support();
    let radius = support * (1.0 + LIST_SKIN);
    if grid.stale(r, z, list_slack(support, LIST_SKIN)) {
        grid.built_r.clear();
        grid.built_r.extend_from_slice(r);
        grid.built_z.clear();
        grid.built_z.extend_from_slice(z);
        build(grid, radius);
        grid.builds += 1;
    } else if !grid.listed {
        // A restart's: the lists the run had.
        build(grid, radius);
    }
    let n = r.len();
    let s2 = support * support;
    grid.chunks
        .resize_with(n.div_ceil(PAIR_CHUNK), Chunk::default);
    let mut chunks = std::mem::take(&mut grid.chunks);
    let g = &*grid;
    chunks.par_iter_mut().enumerate().for_each(|(c, chunk)| {
        let candidates = &g.candidates[c];
        chunk.fill(c, n, |i, pairs| {
            let (ri, zi) = (r[i], z[i]);
            for &e in candidates.of(i % PAIR_CHUNK) {
                let j = (e & !MIRROR) as usize;
                let dr = if e & MIRROR != 0 {
                    ri + r[j]
                } else {
                    ri - r[j]
                };
                let dz = zi - z[j];
                let d2 = dr * dr + dz * dz;
                if d2 < s2 {
                    let dist = d2.sqrt();
                    pairs.push(Pair {
                        j_mirror: e,
                        dr,
                        dz,
                        dist,
                        df: if kernel.coincident(dist) {
                            0.0
                        } else {
                            kernel.dw(dist) / dist
                        },
                    });
                }
            }
        });
    });
    grid.chunks = chunks;
}

/// The cells and every particle's candidates within `radius`, at the positions `built_r`,
/// `built_z`.
fn build(grid: &mut CellGrid, radius: f32) {
    let (r, z) = (
        std::mem::take(&mut grid.built_r),
        std::mem::take(&mut grid.built_z),
    );
    bin(grid, &r, &z, radius);
    let n = r.len();
    grid.candidates
        .resize_with(n.div_ceil(PAIR_CHUNK), Chunk::default);
    let mut candidates = std::mem::take(&mut grid.candidates);
    let g = &*grid;
    candidates
        .par_iter_mut()
        .enumerate()
        .for_each(|(c, chunk)| {
            chunk.fill(c, n, |i, list| {
                for_each_neighbour(g, &r, &z, i, radius, |nb| {
                    list.push(nb.j as u32 | if nb.mirror { MIRROR } else { 0 })
                });
            });
        });
    grid.candidates = candidates;
    grid.built_r = r;
    grid.built_z = z;
    grid.listed = true;
}

/// Bin the positions (r, z) into cells of half `radius`. Cells are numbered row by row (z
/// outer), so the cells of a row searched are one contiguous run of `sorted`.
fn bin(grid: &mut CellGrid, r: &[f32], z: &[f32], radius: f32) {
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
    grid.cell = radius / REACH as f32;
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

    /// Particles moved less than the lists' slack keep their candidates: the lists are not
    /// built again, hold exactly the pairs within the support at the new positions, in the
    /// order the search found them where the lists were built; a move past the slack builds
    /// them again where the particles are.
    #[test]
    fn moved_particles_keep_their_candidates_until_the_slack() {
        let n = 700;
        let r0: Vec<f32> = (0..n).map(|k| (k % 20) as f32 * 1.1e-3 + 1e-4).collect();
        let z0: Vec<f32> = (0..n).map(|k| -((k / 20) as f32) * 1.0e-3).collect();
        let kernel = Kernel::new(1.5e-3);
        let support = kernel.support();
        let slack = list_slack(support, LIST_SKIN);
        let mut grid = CellGrid::default();
        run(&mut grid, &r0, &z0, &kernel);
        assert_eq!(grid.builds, 1);
        // Each particle moved in its own direction by at most the slack: pairs come within the
        // support that were not, and others leave it.
        let turn = |k: usize| k as f32 * 2.399_963;
        let r: Vec<f32> = (0..n)
            .map(|k| (r0[k] + 0.98 * slack * turn(k).cos()).max(0.0))
            .collect();
        let z: Vec<f32> = (0..n)
            .map(|k| z0[k] + 0.98 * slack * turn(k).sin())
            .collect();
        let mut fresh = CellGrid::default();
        run(&mut fresh, &r, &z, &kernel);
        run(&mut grid, &r, &z, &kernel);
        assert_eq!(grid.builds, 1, "moved within the slack: not built again");
        let mut changed = 0;
        for i in 0..n {
            let kept: Vec<(usize, bool)> = grid
                .neighbours(i)
                .iter()
                .map(|p| (p.j(), p.mirror()))
                .collect();
            // In the order of the search where the lists were built.
            let mut then = Vec::new();
            let radius = support * (1.0 + LIST_SKIN);
            for_each_neighbour(&grid, &r0, &z0, i, radius, |nb| {
                then.push((nb.j, nb.mirror))
            });
            let want: Vec<(usize, bool)> = then
                .into_iter()
                .filter(|&(j, m)| {
                    let dr = if m { r[i] + r[j] } else { r[i] - r[j] };
                    dr * dr + (z[i] - z[j]).powi(2) < support * support
                })
                .collect();
            assert_eq!(kept, want, "particle {i}");
            // The same pairs as a search at the new positions.
            let mut now: Vec<(usize, bool)> = fresh
                .neighbours(i)
                .iter()
                .map(|p| (p.j(), p.mirror()))
                .collect();
            let mut sorted = kept.clone();
            now.sort();
            sorted.sort();
            assert_eq!(sorted, now, "particle {i}");
            let before: Vec<usize> = (0..n)
                .filter(|&j| j != i && (r0[i] - r0[j]).hypot(z0[i] - z0[j]) < support)
                .collect();
            let after: Vec<usize> = kept.iter().filter(|p| !p.1).map(|p| p.0).collect();
            changed += (before != after) as usize;
        }
        assert!(
            changed > 0,
            "the move must change some particle's neighbours"
        );
        let r2: Vec<f32> = r.iter().map(|&x| x + 1.01 * slack).collect();
        run(&mut grid, &r2, &z, &kernel);
        assert_eq!(grid.builds, 2, "moved past the slack: built again");
        assert_eq!(grid.built_at().0, &r2[..]);
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

/// Call `f` for every particle within `radius` of particle i (the lists' radius, or the
/// support): first the real ones (j ≠ i), then, near the axis, the axis ghosts (j = i
/// included). A ghost of j is never nearer than j itself, so the ghosts are found among the same
/// candidates. (Two sweeps, not one, so that the GPU twin, shaders/neighbour_loop.wgsl, can skip
/// the ghost sweep away from the axis; the order of the sums is the same on both sides.)
#[inline]
pub fn for_each_neighbour(
    grid: &CellGrid,
    r: &[f32],
    z: &[f32],
    i: usize,
    radius: f32,
    mut f: impl FnMut(Neighbour),
) {
    let (ri, zi) = (r[i], z[i]);
    let s2 = radius * radius;
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
    if ri < radius {
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
