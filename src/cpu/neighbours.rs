//! `neighbours`: bin particles into square cells of half the kernel's support with a counting
//! sort (count, prefix scan, scatter). Within a cell particles keep ascending index order, so
//! every neighbour loop visits them in the same order on every run.

/// Particles binned by cell.
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
}

/// Cells searched on each side of a particle's own cell.
pub(crate) const REACH: u32 = 2;

/// Cells are capped so that a particle thrown far away cannot make the grid huge; such a
/// particle is clamped into an edge cell (the distance test keeps the result right) and the
/// solver stops the run when a particle escapes (see `integrate`).
pub(crate) const MAX_CELLS_PER_AXIS: u32 = 1 << 14;

impl CellGrid {
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

/// Rebuild the grid for the current positions. Cells are numbered row by row (z outer), so the
/// cells of a row searched are one contiguous run of `sorted`.
pub fn run(grid: &mut CellGrid, r: &[f32], z: &[f32], support: f32) {
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
        let support = 0.007;
        let mut grid = CellGrid::default();
        run(&mut grid, &r, &z, support);
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
