//! `neighbours` on the GPU (shaders/neighbours.wgsl, the scan in shaders/scan.wgsl, the lists
//! in shaders/neighbour_list.wgsl); CPU twins `cpu::neighbours::run` and
//! `cpu::neighbours::for_each_neighbour`. The grid it builds (GridInfo of shaders/grid.wgsl,
//! `cell_start`, `sorted`) and each particle's neighbour list are what `sph_rates` and
//! `sph_forces` walk.

use super::scan::PrefixScan;
use super::shader::Program;
use super::state::GpuParticles;
use super::{Gpu, GpuError, Kernel};

/// The grid on the GPU: `GridInfo` words, `cell_start` (capacity + 1 entries) and `sorted`;
/// the neighbour lists: `nbr` (NBR_MAX per particle, column-major) and `nbr_count`; and `kin`,
/// each particle's (r, z, v_r, v_z) packed for the gathers (shaders/neighbour_loop.wgsl).
pub struct GpuGrid {
    pub info: wgpu::Buffer,
    pub cell_start: wgpu::Buffer,
    pub sorted: wgpu::Buffer,
    pub nbr: wgpu::Buffer,
    pub nbr_count: wgpu::Buffer,
    pub kin: wgpu::Buffer,
    /// What sph_rates reads of a neighbour, packed for one load (neighbours.wgsl `pack`):
    /// (m̃/ρ, (m̃/ρ) ρ, m̃, hoop_radius(r)).
    pub rate_pair: wgpu::Buffer,
}

/// Neighbours a list holds per particle (shaders/neighbour_loop.wgsl NBR_MAX). A concrete
/// lattice at h = 1.5 Δ has about 28 within the support, up to 35 where the projectile has
/// compacted it (measured on the Forrestal 277 m/s shot); a particle with more is walked on the
/// grid instead, so this bounds memory, not correctness.
pub const NBR_MAX: usize = 64;

impl GpuGrid {
    /// The bindings of a pass that walks the neighbours (neighbour_loop.wgsl), by their WGSL
    /// names, with `kin` the kinematics walked: this grid's own, or the filtered ones.
    pub fn walk_bindings<'a>(
        &'a self,
        kin: &'a wgpu::Buffer,
    ) -> [(&'static str, &'a wgpu::Buffer); 6] {
        [
            ("grid", &self.info),
            ("cell_start", &self.cell_start),
            ("sorted", &self.sorted),
            ("kin", kin),
            ("nbr", &self.nbr),
            ("nbr_count", &self.nbr_count),
        ]
    }

    /// The grid's buffers for `n` particles and `capacity` cells, with `info` as given.
    fn new(
        gpu: &Gpu,
        info: &[u32],
        cell_start: wgpu::Buffer,
        n: usize,
    ) -> Result<GpuGrid, GpuError> {
        gpu.check_binding_size("the neighbour lists", (4 * NBR_MAX * n) as u64)?;
        Ok(GpuGrid {
            info: gpu.buffer("grid info", info),
            cell_start,
            sorted: gpu.zeros::<u32>("sorted", n),
            nbr: gpu.zeros::<u32>("neighbour lists", NBR_MAX * n),
            nbr_count: gpu.zeros::<u32>("neighbour counts", n),
            kin: gpu.zeros::<[f32; 4]>("packed kinematics", n),
            rate_pair: gpu.zeros::<[f32; 4]>("packed rate data", n),
        })
    }
}

/// The `list` kernel over a grid.
struct ListKernel {
    kernel: Kernel,
    bind: wgpu::BindGroup,
}

impl ListKernel {
    fn new(gpu: &Gpu, grid: &GpuGrid, sph_uniform: &wgpu::Buffer) -> Result<ListKernel, GpuError> {
        let kernel = gpu.kernel(Program::NeighbourList, "list", &[])?;
        let bindings = [&[("u", sph_uniform)][..], &grid.walk_bindings(&grid.kin)].concat();
        let bind = kernel.bind(gpu, &bindings)?;
        Ok(ListKernel { kernel, bind })
    }
}

/// `GridInfo` words of shaders/grid.wgsl: the bound keys, n_r, n_z, cell, z0, cells, capacity,
/// overflow, list_radius, moved2.
const INFO_WORDS: usize = 12;
const INFO_CAPACITY: usize = 8;
#[cfg(test)]
const INFO_OVERFLOW: usize = 9;
const INFO_LIST_RADIUS: usize = 10;
/// Byte offset of `moved2` in GridInfo (copied to the step's read-back).
pub const MOVED2_OFFSET: u64 = 4 * 11;

/// The neighbour search: the counting sort of the particles into cells and the lists (the
/// build), and the packed kinematics every step. The displacement watch that says when the
/// lists must be built again is the integration's (integrate.wgsl, from `x_build`).
pub struct NeighboursPass {
    bounds: Kernel,
    setup: Kernel,
    clear: Kernel,
    count: Kernel,
    scan: PrefixScan,
    scatter: Kernel,
    sort_cells: Kernel,
    list: ListKernel,
    pack: Kernel,
    bind: wgpu::BindGroup,
    n: u32,
    /// Workgroups of the grid-stride loops over the cells.
    cell_groups: u32,
    /// The particles' positions at the last build (the integration's displacement watch).
    x_build: wgpu::Buffer,
    // Kept alive for the bind group.
    _scratch: [wgpu::Buffer; 2],
}

impl NeighboursPass {
    /// The pass and the grid it fills, for up to `capacity` cells (beyond that the grid
    /// coarsens), with lists of the particles within `list_radius` (at least the support).
    pub fn new(
        gpu: &Gpu,
        particles: &GpuParticles,
        sph_uniform: &wgpu::Buffer,
        capacity: u32,
        list_radius: f32,
    ) -> Result<(NeighboursPass, GpuGrid), GpuError> {
        let kernel = |entry: &str| gpu.kernel(Program::Neighbours, entry, &[]);
        let capacity = capacity.max(1);
        gpu.check_binding_size("the neighbour grid's cells", 4 * (capacity as u64 + 1))?;
        let n = particles.len;
        // The bound keys start at the identities of their reductions (neighbours.wgsl setup
        // resets them the same way after each use).
        let mut words = [0u32; INFO_WORDS];
        words[0] = 0x8000_0000; // float_key(0.0)
        words[1] = u32::MAX;
        words[INFO_CAPACITY] = capacity;
        words[INFO_LIST_RADIUS] = list_radius.to_bits();
        let cell_start = gpu.zeros::<u32>("cell_start", capacity as usize + 1);
        let grid = GpuGrid::new(gpu, &words, cell_start, n)?;
        let cell_of = gpu.zeros::<u32>("cell_of", n);
        let rank = gpu.zeros::<u32>("rank in cell", n);
        let x_build = gpu.zeros::<[f32; 2]>("positions at the build", n);
        let bounds = kernel("bounds")?;
        let bind = bounds.bind(
            gpu,
            &[
                ("u", sph_uniform),
                ("grid", &grid.info),
                ("cell_start", &grid.cell_start),
                ("sorted", &grid.sorted),
                ("cell_of", &cell_of),
                ("rank", &rank),
                ("r", &particles.r),
                ("z", &particles.z),
                ("vr", &particles.vr),
                ("vz", &particles.vz),
                ("kin", &grid.kin),
                ("x_build", &x_build),
                ("mass", &particles.mass),
                ("rho", &particles.rho),
                ("m_tilde", &particles.m_tilde),
                ("area", &particles.area),
                ("rate_pair", &grid.rate_pair),
            ],
        )?;
        let pass = NeighboursPass {
            bounds,
            setup: kernel("setup")?,
            clear: kernel("clear")?,
            count: kernel("count")?,
            scan: PrefixScan::new(gpu, &grid.cell_start, capacity + 1)?,
            scatter: kernel("scatter")?,
            sort_cells: kernel("sort_cells")?,
            list: ListKernel::new(gpu, &grid, sph_uniform)?,
            pack: kernel("pack")?,
            bind,
            n: n as u32,
            cell_groups: (capacity + 1)
                .div_ceil(super::WORKGROUP)
                .min(gpu.limits.max_compute_workgroups_per_dimension),
            x_build,
            _scratch: [cell_of, rank],
        };
        Ok((pass, grid))
    }

    /// Every step, before the gathers: the packed kinematics and the areas m̃ and m̃/ρ (and the
    /// watch reset), then the grid and the lists when `build`.
    pub fn record(&self, pass: &mut wgpu::ComputePass, build: bool) {
        self.pack.dispatch(pass, &self.bind, self.n);
        if !build {
            return;
        }
        self.bounds.dispatch_fold(pass, &self.bind, self.n);
        self.setup.dispatch_groups(pass, &self.bind, 1);
        self.clear
            .dispatch_groups(pass, &self.bind, self.cell_groups);
        self.count.dispatch(pass, &self.bind, self.n);
        self.scan.record(pass);
        self.scatter.dispatch(pass, &self.bind, self.n);
        self.sort_cells
            .dispatch_groups(pass, &self.bind, self.cell_groups);
        self.list.kernel.dispatch(pass, &self.list.bind, self.n);
    }

    pub fn x_build(&self) -> &wgpu::Buffer {
        &self.x_build
    }
}

/// Cells to allocate for a target: four times the lattice's own count at cells of half the
/// support, room for the cloud to bulge and splash before the grid coarsens.
pub fn capacity(r: &[f32], z: &[f32], support: f32) -> u32 {
    let cell = support / 2.0;
    let r_max = r.iter().copied().fold(0.0f32, f32::max);
    let (lo, hi) = z
        .iter()
        .fold((f32::MAX, f32::MIN), |(lo, hi), &z| (lo.min(z), hi.max(z)));
    let cells = ((r_max / cell) as u64 + 1) * (((hi - lo).max(0.0) / cell) as u64 + 1);
    (4 * cells).min(u32::MAX as u64 / 2) as u32
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::cpu::neighbours::CellGrid;
    use crate::gpu::concrete::tests::{smoke, SMOKE_STEPS};
    use crate::gpu::params::SphUniform;
    use crate::gpu::{run_once, test_gpu};

    /// A grid the CPU built, uploaded as the GPU stores it (the bound keys are unused), for the
    /// gather passes' tests: with the neighbour lists built on it, or with every list marked
    /// overflowed (`lists` false), so that the gathers walk the grid.
    pub(crate) fn upload_cpu_grid(
        gpu: &crate::gpu::Gpu,
        particles: &crate::state::Particles,
        sph_uniform: &wgpu::Buffer,
        g: &CellGrid,
        h: f32,
        lists: bool,
    ) -> GpuGrid {
        let cells = g.n_r * g.n_z;
        let mut info = [0u32; INFO_WORDS];
        info[3] = g.n_r;
        info[4] = g.n_z;
        info[5] = g.cell.to_bits();
        info[6] = g.z0.to_bits();
        info[7] = cells;
        info[INFO_CAPACITY] = cells;
        info[INFO_LIST_RADIUS] = (2.0 * g.cell).to_bits();
        let n = particles.len();
        let grid = GpuGrid::new(gpu, &info, gpu.buffer("cell_start", &g.cell_start), n).unwrap();
        gpu.write(&grid.sorted, &g.sorted);
        let p = particles;
        let kin: Vec<[f32; 4]> = (0..n).map(|i| [p.r[i], p.z[i], p.vr[i], p.vz[i]]).collect();
        gpu.write(&grid.kin, &kin);
        // sph_rates' packed data as `pack` makes it, from the particles' areas.
        let pairs: Vec<[f32; 4]> = (0..n)
            .map(|i| {
                let (a, r) = (p.area[i], crate::cpu::sph_rates::hoop_radius(p.r[i], h));
                [a, a * p.rho[i], p.m_tilde[i], r]
            })
            .collect();
        gpu.write(&grid.rate_pair, &pairs);
        if lists {
            let list = ListKernel::new(gpu, &grid, sph_uniform).unwrap();
            run_once(gpu, |p| list.kernel.dispatch(p, &list.bind, n as u32)).unwrap();
        } else {
            gpu.write(&grid.nbr_count, &vec![NBR_MAX as u32 + 1; n]);
        }
        grid
    }

    /// What the GPU built for a set of particles.
    struct Built {
        grid: CellGrid,
        overflow: u32,
        /// Per particle: its listed neighbours as (j, mirror), or None where the list overflowed.
        lists: Vec<Option<Vec<(usize, bool)>>>,
        /// The areas `pack` wrote, m̃ and m̃/ρ, and sph_rates' packed data.
        m_tilde: Vec<f32>,
        area: Vec<f32>,
        rate_pair: Vec<[f32; 4]>,
    }

    /// Build the GPU grid and lists for `particles` (twice, to exercise the reset of the
    /// bounds) and read them back.
    fn gpu_build(
        particles: &crate::state::Particles,
        sph: &crate::state::SphParams,
        capacity: u32,
    ) -> Built {
        let gpu = test_gpu();
        // Poisoned areas, so that what `pack` does not write shows.
        let mut start = particles.clone();
        start.m_tilde.fill(f32::NAN);
        start.area.fill(f32::NAN);
        let gp = GpuParticles::upload(&gpu, &start);
        let uniform = gpu.uniform("sph", &SphUniform::new(sph, gp.len));
        let radius = sph.kernel.support() * (1.0 + crate::cpu::neighbours::LIST_SKIN);
        let (pass, grid) = NeighboursPass::new(&gpu, &gp, &uniform, capacity, radius).unwrap();
        run_once(&gpu, |p| pass.record(p, true)).unwrap();
        run_once(&gpu, |p| pass.record(p, true)).unwrap();
        let info: Vec<u32> = gpu.read(&grid.info, INFO_WORDS).unwrap();
        let n = particles.len();
        let cells = (info[3] * info[4]) as usize;
        let nbr: Vec<u32> = gpu.read(&grid.nbr, NBR_MAX * n).unwrap();
        let counts: Vec<u32> = gpu.read(&grid.nbr_count, n).unwrap();
        let lists = (0..n)
            .map(|i| {
                let count = counts[i] as usize;
                (count <= NBR_MAX).then(|| {
                    (0..count)
                        .map(|k| {
                            let e = nbr[k * n + i];
                            ((e & 0x7fff_ffff) as usize, e & 0x8000_0000 != 0)
                        })
                        .collect()
                })
            })
            .collect();
        let mut built = CellGrid::default();
        built.cell = f32::from_bits(info[5]);
        built.z0 = f32::from_bits(info[6]);
        built.n_r = info[3];
        built.n_z = info[4];
        built.cell_start = gpu.read(&grid.cell_start, cells + 1).unwrap();
        built.sorted = gpu.read(&grid.sorted, n).unwrap();
        Built {
            grid: built,
            overflow: info[INFO_OVERFLOW],
            lists,
            m_tilde: gpu.read(&gp.m_tilde, n).unwrap(),
            area: gpu.read(&gp.area, n).unwrap(),
            rate_pair: gpu.read(&grid.rate_pair, n).unwrap(),
        }
    }

    /// On the smoke state (the nose has cratered the target), the GPU's grid for lists with the
    /// skin is the CPU's, exactly: same shape, same cell starts, same order within every cell;
    /// and each list holds the candidates cpu::neighbours::for_each_neighbour visits within the
    /// lists' radius, in its order.
    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn grid_and_lists_match_cpu_exactly() {
        let sim = smoke(SMOKE_STEPS, &[]);
        let sph = sim.sph.unwrap();
        let p = &sim.particles;
        let support = crate::cpu::integrate::support(&sph);
        let mut cpu = CellGrid::default();
        crate::cpu::neighbours::run(&mut cpu, &p.r, &p.z, &sph.kernel);
        let built = gpu_build(p, &sph, capacity(&p.r, &p.z, support));
        let g = &built.grid;
        assert_eq!((g.n_r, g.n_z, built.overflow), (cpu.n_r, cpu.n_z, 0));
        assert_eq!((g.cell, g.z0), (cpu.cell, cpu.z0));
        assert_eq!(g.cell_start, cpu.cell_start);
        assert_eq!(g.sorted, cpu.sorted);
        let mut ghosts = 0;
        let radius = support * (1.0 + crate::cpu::neighbours::LIST_SKIN);
        for (i, list) in built.lists.iter().enumerate() {
            let mut want = Vec::new();
            crate::cpu::neighbours::for_each_neighbour(&cpu, &p.r, &p.z, i, radius, |nb| {
                want.push((nb.j, nb.mirror))
            });
            ghosts += want.iter().filter(|x| x.1).count();
            assert_eq!(list.as_ref(), Some(&want), "particle {i}");
        }
        assert!(ghosts > 0, "the lists hold axis ghosts");
        // The areas for the gathers, as cpu::sph_rates::run computes them.
        let mut rates = p.clone();
        crate::cpu::sph_rates::run(&mut rates, &cpu, &sph, None);
        for (name, a, b) in [
            ("m_tilde", &built.m_tilde, &rates.m_tilde),
            ("area", &built.area, &rates.area),
        ] {
            let e = crate::gpu::concrete::tests::field_error(a, b);
            assert!(e <= 1.0e-5, "{name}: relative error {e:e}");
        }
        // The packed data is the areas `pack` wrote, ρ and r, as the rates would make them.
        let h = sph.h;
        for i in 0..p.len() {
            let (a, mt) = (built.area[i], built.m_tilde[i]);
            let want = [
                a,
                a * p.rho[i],
                mt,
                crate::cpu::sph_rates::hoop_radius(p.r[i], h),
            ];
            assert_eq!(
                built.rate_pair[i].map(f32::to_bits),
                want.map(f32::to_bits),
                "{i}"
            );
        }
    }

    /// With too few cells allocated the grid coarsens, and the 5×5-cell search still finds
    /// every neighbour within the support.
    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn coarsened_grid_still_finds_every_neighbour() {
        let sim = smoke(0, &[]);
        let sph = sim.sph.unwrap();
        let p = &sim.particles;
        let support = crate::cpu::integrate::support(&sph);
        let built = gpu_build(p, &sph, 40);
        let grid = &built.grid;
        assert_eq!(built.overflow, 1);
        assert!(grid.n_r * grid.n_z <= 40 && grid.cell >= support / 2.0);
        for i in (0..p.len()).step_by(7) {
            let mut found = Vec::new();
            grid.for_each_candidate(p.r[i], p.z[i], |j| {
                if (p.r[i] - p.r[j]).hypot(p.z[i] - p.z[j]) < support {
                    found.push(j)
                }
            });
            found.sort();
            let brute: Vec<usize> = (0..p.len())
                .filter(|&j| (p.r[i] - p.r[j]).hypot(p.z[i] - p.z[j]) < support)
                .collect();
            assert_eq!(found, brute, "particle {i}");
        }
    }
}
