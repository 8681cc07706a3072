//! The wall images on the GPU (shaders/walls.wgsl, shaders/wall_images.wgsl; CPU twin
//! `cpu::wall`): `find` gives each particle its wall before the rates, the gathers take the
//! images, `sums` hands their reaction to the master segments' entries of the nodal forces,
//! which the integration gathers with the elements' through the node CSR (`csr`).

use super::neighbours::GpuGrid;
use super::params::WallUniform;
use super::shader::Program;
use super::state::GpuNodes;
use super::timestep::DtSlots;
use super::{Gpu, GpuError, Kernel};
use crate::cpu::wall::Wall;
use crate::mesh::MasterSegment;
use crate::state::Nodes;

/// Each particle's wall and the ring force its images exert on it: what the gathers bind
/// (one-entry placeholders in a scene without images, which compiles the images out).
pub struct WallBuffers {
    /// Whether the scene takes images (the gathers' IMAGES).
    pub images: bool,
    pub walls: wgpu::Buffer,
    pub wall_force: wgpu::Buffer,
}

impl WallBuffers {
    pub fn new(gpu: &Gpu, n: usize, images: bool) -> Result<WallBuffers, GpuError> {
        let n = if images { n.max(1) } else { 1 };
        gpu.check_binding_size("the particles' walls", (n * size_of::<Wall>()) as u64)?;
        Ok(WallBuffers {
            images,
            walls: gpu.buffer("walls", &vec![Wall::default(); n]),
            wall_force: gpu.zeros::<[f32; 2]>("wall force", n),
        })
    }
}

/// The node → force-entry CSR of the integration's gather with the master segments' reactions:
/// each node's elements (`Nodes::elem_refs`, 3·element + local), then the segments it ends, in
/// ascending order, as entries past the `n_elements` elements' (3·(n_elements + m) + 0 for
/// node A, + 1 for node B), which is the order `cpu::wall::react` adds them in.
pub fn csr(nodes: &Nodes, n_elements: usize, masters: &[MasterSegment]) -> (Vec<u32>, Vec<u32>) {
    let mut ends: Vec<Vec<u32>> = vec![Vec::new(); nodes.len()];
    for (m, seg) in masters.iter().enumerate() {
        let at = 3 * (n_elements + m) as u32;
        ends[seg.a as usize].push(at);
        ends[seg.b as usize].push(at + 1);
    }
    let (mut offsets, mut refs) = (vec![0u32], Vec::new());
    for (n, end) in ends.iter().enumerate() {
        let (lo, hi) = (
            nodes.elem_offsets[n] as usize,
            nodes.elem_offsets[n + 1] as usize,
        );
        refs.extend_from_slice(&nodes.elem_refs[lo..hi]);
        refs.extend_from_slice(end);
        offsets.push(refs.len() as u32);
    }
    (offsets, refs)
}

pub struct WallsPass {
    find: Kernel,
    sums: Kernel,
    /// One bind group for each parity of the integration the box is from.
    binds: [wgpu::BindGroup; 2],
    _uniform: wgpu::Buffer,
    /// Per master segment, the z-impulse its reaction gave the projectile so far (N s).
    pub impulse: wgpu::Buffer,
    n_particles: u32,
    n_masters: u32,
}

/// What the walls pass reads and writes besides its own.
pub struct WallsSetup<'a> {
    pub buffers: &'a WallBuffers,
    pub grid: &'a GpuGrid,
    pub nodes: &'a GpuNodes,
    /// The elements' nodal forces with the segments' entries past them.
    pub force: &'a wgpu::Buffer,
    pub masters: &'a [MasterSegment],
    /// The step's clock (its Δt).
    pub clock: &'a wgpu::Buffer,
    pub n_particles: usize,
    pub n_elements: usize,
    pub box_keys: &'a wgpu::Buffer,
    pub slots: &'a DtSlots,
    pub support: f32,
    /// The mirror line's depth inside the surface (m).
    pub offset: f32,
    /// The neighbour lists' radius (the support with the skin): a particle with a wall is
    /// within it of its foot where the lists binned it (it has moved less than half the skin).
    pub list_radius: f32,
}

impl WallsPass {
    pub fn new(gpu: &Gpu, s: &WallsSetup) -> Result<WallsPass, GpuError> {
        let u = WallUniform {
            n_particles: s.n_particles as u32,
            n_masters: s.masters.len() as u32,
            n_elements: s.n_elements as u32,
            support: s.support,
            offset: s.offset,
            // The box is the integration's, before the correction moved the nodes by the
            // global shift's s·Δt: a support's margin is far more than that.
            box_margin: s.support,
            grow: s.list_radius,
        };
        let uniform = gpu.uniform("walls", &u);
        let m: Vec<[u32; 4]> = s
            .masters
            .iter()
            .map(|m| [m.element, m.a, m.b, m.c])
            .collect();
        let masters = gpu.buffer("wall masters", &m);
        let impulse = gpu.zeros::<f32>("wall impulse", s.masters.len().max(1));
        let find = gpu.kernel(Program::Walls, "find", &[])?;
        let sums = gpu.kernel(Program::Walls, "sums", &[])?;
        let bind = |slot: u32| {
            find.bind(
                gpu,
                &[
                    ("u", &uniform),
                    ("kin", &s.grid.kin),
                    ("masters", &masters),
                    ("node_r", &s.nodes.r),
                    ("node_z", &s.nodes.z),
                    ("node_vr", &s.nodes.vr),
                    ("node_vz", &s.nodes.vz),
                    ("box_keys", s.box_keys),
                    ("box_slot", s.slots.get(slot)),
                    ("walls", &s.buffers.walls),
                    ("grid", &s.grid.info),
                    ("cell_start", &s.grid.cell_start),
                    ("sorted", &s.grid.sorted),
                    ("wall_force", &s.buffers.wall_force),
                    ("force", s.force),
                    ("clock", s.clock),
                    ("wall_impulse", &impulse),
                ],
            )
        };
        Ok(WallsPass {
            binds: [bind(0)?, bind(1)?],
            find,
            sums,
            _uniform: uniform,
            impulse,
            n_particles: s.n_particles as u32,
            n_masters: s.masters.len() as u32,
        })
    }

    /// Find the walls at the configuration the integration of `parity` reached (its box).
    pub fn record_find(&self, pass: &mut wgpu::ComputePass, parity: u32) {
        self.find
            .dispatch(pass, &self.binds[parity as usize], self.n_particles);
    }

    /// Sum the images' reactions onto the segments' force entries.
    pub fn record_sums(&self, pass: &mut wgpu::ComputePass) {
        if self.n_masters > 0 {
            self.sums
                .dispatch_groups(pass, &self.binds[0], self.n_masters);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::wall::{segment_sums, NO_WALL};
    use crate::gpu::concrete::tests::{field_error, smoke, SMOKE_STEPS};
    use crate::gpu::contact_detect::{float_key, EMPTY_BOX};
    use crate::gpu::neighbours::tests::upload_cpu_grid;
    use crate::gpu::params::SphUniform;
    use crate::gpu::sph_forces::tests::pairs;
    use crate::gpu::sph_forces::SphForcesPass;
    use crate::gpu::sph_rates::tests::check_gradients;
    use crate::gpu::sph_rates::SphRatesPass;
    use crate::gpu::state::GpuParticles;
    use crate::gpu::{run_once, test_gpu};

    /// Each of the images' GPU passes agrees with its CPU twin on the smoke state with images
    /// (the nose in the crater, the lining's walls found): `find` the same walls, the gathers
    /// the same rates, forces and ring forces with the CPU's walls, `sums` the same segment
    /// sums of the CPU's ring forces; and the integration's CSR reaches them.
    fn compare(lists: bool) {
        let gpu = test_gpu();
        let images = ["contact.kernel=\"images\"".to_string()];
        let sim = smoke(SMOKE_STEPS, &images);
        let sph = sim.sph.expect("smoke has a target");
        let cpu_walls = &sim.walls.walls;
        let lining = cpu_walls.iter().filter(|w| w.on()).count();
        eprintln!("walls: {lining} of {} particles have one", cpu_walls.len());
        assert!(lining > 10, "the smoke state has no lining");

        // find: the same walls as the CPU at the same positions.
        let p = &sim.particles;
        let (n, nodes) = (p.len(), &sim.projectile.nodes);
        let masters = &sim.projectile.masters;
        let n_e = sim.projectile.elements.len();
        // The areas the neighbours pass packs (`pack`) at these positions, as the CPU's rates
        // make them.
        let mut cpu = p.clone();
        crate::cpu::sph_rates::run(&mut cpu, &sim.grid, &sph, Some(&sim.walls.walls));
        let gp = GpuParticles::upload(&gpu, p);
        let uniform = gpu.uniform("sph", &SphUniform::new(&sph, n));
        let grid = upload_cpu_grid(&gpu, &cpu, &uniform, &sim.grid, sph.h, lists);
        let gn = GpuNodes::upload(&gpu, nodes);
        let bounds = crate::cpu::wall::node_box(nodes);
        let box_keys = gpu.buffer(
            "box",
            &[
                [
                    float_key(bounds[0]),
                    float_key(bounds[1]),
                    float_key(bounds[2]),
                    0,
                ],
                EMPTY_BOX,
            ],
        );
        let buffers = WallBuffers::new(&gpu, n, true).unwrap();
        gpu.write(
            &buffers.walls,
            &vec![
                Wall {
                    seg: 7,
                    ..Wall::default()
                };
                n
            ],
        );
        let mut entries = vec![[f32::NAN; 6]; n_e];
        entries.extend(vec![[0.0; 6]; masters.len()]);
        let force = gpu.buffer("force", &entries);
        let dt = 1.0e-7f32;
        let clock = gpu.buffer("clock", &crate::gpu::timestep::clock_words(dt, false));
        let slots = DtSlots::new(&gpu);
        let support = sph.kernel.support();
        let pass = WallsPass::new(
            &gpu,
            &WallsSetup {
                buffers: &buffers,
                grid: &grid,
                nodes: &gn,
                force: &force,
                masters,
                clock: &clock,
                n_particles: n,
                n_elements: n_e,
                box_keys: &box_keys,
                slots: &slots,
                support,
                offset: sim.walls.offset,
                list_radius: support,
            },
        )
        .unwrap();
        run_once(&gpu, |c| pass.record_find(c, 0)).unwrap();
        let found: Vec<Wall> = gpu.read(&buffers.walls, n).unwrap();
        let other = (0..n).filter(|&i| found[i].seg != cpu_walls[i].seg).count();
        assert_eq!(
            other, 0,
            "{other} particles with another wall than the CPU's"
        );
        for (name, get) in [
            ("qr", (|w: &Wall| w.qr) as fn(&Wall) -> f32),
            ("qz", |w| w.qz),
            ("nr", |w| w.nr),
            ("nz", |w| w.nz),
            ("vz", |w| w.vz),
            ("wa", |w| w.wa),
        ] {
            let on = |ws: &[Wall]| -> Vec<f32> { ws.iter().filter(|w| w.on()).map(get).collect() };
            let e = field_error(&on(&found), &on(cpu_walls));
            eprintln!("walls {name}: relative error {e:e}");
            assert!(e <= 1.0e-5, "{name}: relative error {e:e}");
        }
        assert!(found.iter().all(|w| w.on() || w.seg == NO_WALL));

        // The gathers with the CPU's walls, against the CPU's.
        gpu.write(&buffers.walls, cpu_walls);
        let mut start = p.clone();
        start.m_tilde.clone_from(&cpu.m_tilde);
        start.area.clone_from(&cpu.area);
        start.hoop_weight.fill(f32::NAN);
        start.drho.fill(f32::NAN);
        gp.write(&gpu, &start);
        let rates = SphRatesPass::new(&gpu, &gp, &grid, &uniform, &sph, &buffers).unwrap();
        run_once(&gpu, |c| rates.record(c)).unwrap();
        let mut back = start.clone();
        gp.download(&gpu, &mut back).unwrap();
        check_gradients(&format!("images, lists {lists}"), &back, &cpu);
        let e = field_error(&back.hoop_weight, &cpu.hoop_weight);
        eprintln!("images: hoop_weight relative error {e:e}");
        assert!(e <= 1.0e-5, "hoop_weight: relative error {e:e}");

        let mut start = p.clone();
        crate::cpu::sph_forces::prologue(&mut start, &sph);
        let mut cpu = start.clone();
        let reaction = crate::cpu::sph_forces::run(&mut cpu, &sim.grid, &sph, Some(cpu_walls));
        start.ar.fill(f32::NAN);
        start.az.fill(f32::NAN);
        start.de_work.fill(f32::NAN);
        gp.write(&gpu, &start);
        let pairs = pairs(&gpu, &start);
        let forces = SphForcesPass::new(
            &gpu, &gp, &pairs, &grid, &uniform, &clock, &slots, &sph, &buffers,
        )
        .unwrap();
        run_once(&gpu, |c| forces.record(c, 1)).unwrap();
        let mut back = start.clone();
        gp.download(&gpu, &mut back).unwrap();
        for (name, a, b) in [
            ("ar", &back.ar, &cpu.ar),
            ("az", &back.az, &cpu.az),
            ("de_work", &back.de_work, &cpu.de_work),
            ("de_visc", &back.de_visc, &cpu.de_visc),
            ("mu_visc", &back.mu_visc, &cpu.mu_visc),
        ] {
            let e = field_error(a, b);
            eprintln!("images: {name} relative error {e:e}");
            assert!(e <= 1.0e-5, "{name}: relative error {e:e}");
        }
        let ring: Vec<[f32; 2]> = gpu.read(&buffers.wall_force, n).unwrap();
        for k in 0..2 {
            let on = |f: &[[f32; 2]]| -> Vec<f32> {
                (0..n)
                    .filter(|&i| cpu_walls[i].on())
                    .map(|i| f[i][k])
                    .collect()
            };
            let e = field_error(&on(&ring), &on(&reaction));
            eprintln!("images: wall_force[{k}] relative error {e:e}");
            assert!(e <= 1.0e-5, "wall_force[{k}]: relative error {e:e}");
        }

        // sums of the CPU's ring forces: every segment's, the elements' entries untouched.
        gpu.write(&buffers.wall_force, &reaction);
        run_once(&gpu, |c| pass.record_sums(c)).unwrap();
        let got: Vec<[f32; 6]> = gpu.read(&force, n_e + masters.len()).unwrap();
        assert!(got[..n_e].iter().flatten().all(|x| x.is_nan()));
        let want = segment_sums(cpu_walls, &reaction, masters.len());
        let loaded = want.iter().filter(|s| s.iter().any(|&x| x != 0.0)).count();
        eprintln!("sums: {loaded} of {} segments loaded", masters.len());
        assert!(loaded > 2, "no segment takes a reaction");
        for k in 0..4 {
            let g: Vec<f32> = got[n_e..].iter().map(|f| -f[k]).collect();
            let w: Vec<f32> = want.iter().map(|s| s[k]).collect();
            let e = field_error(&g, &w);
            eprintln!("sums[{k}]: relative error {e:e}");
            assert!(e <= 1.0e-5, "sums[{k}]: relative error {e:e}");
        }
        assert!(got[n_e..].iter().all(|f| f[4] == 0.0 && f[5] == 0.0));
        // The next sums book what the integration took of these over its Δt.
        let none: Vec<f32> = gpu.read(&pass.impulse, masters.len()).unwrap();
        assert!(none.iter().all(|&x| x == 0.0));
        run_once(&gpu, |c| pass.record_sums(c)).unwrap();
        let booked: Vec<f32> = gpu.read(&pass.impulse, masters.len()).unwrap();
        let expected: Vec<f32> = got[n_e..].iter().map(|f| (f[1] + f[3]) * dt).collect();
        assert_eq!(booked, expected);
    }

    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn wall_images_match_cpu() {
        compare(true);
    }

    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn wall_images_match_cpu_on_the_grid() {
        compare(false);
    }

    /// The integration's CSR with the walls: each node's elements as before, then the segments
    /// it ends in ascending order, pointing at their A or B entries.
    #[test]
    fn csr_appends_the_segments_a_node_ends() {
        let sim = smoke(1, &[]);
        let (nodes, masters) = (&sim.projectile.nodes, &sim.projectile.masters);
        let n_e = sim.projectile.elements.len();
        let (offsets, refs) = csr(nodes, n_e, masters);
        assert_eq!(offsets.len(), nodes.len() + 1);
        assert_eq!(refs.len(), nodes.elem_refs.len() + 2 * masters.len());
        for k in 0..nodes.len() {
            let (lo, hi) = (offsets[k] as usize, offsets[k + 1] as usize);
            let own = &nodes.elem_refs
                [nodes.elem_offsets[k] as usize..nodes.elem_offsets[k + 1] as usize];
            assert_eq!(&refs[lo..lo + own.len()], own);
            let ends: Vec<u32> = masters
                .iter()
                .enumerate()
                .flat_map(|(m, s)| {
                    let at = 3 * (n_e + m) as u32;
                    [(s.a, at), (s.b, at + 1)]
                })
                .filter(|&(node, _)| node == k as u32)
                .map(|(_, code)| code)
                .collect();
            assert_eq!(&refs[lo + own.len()..hi], &ends[..]);
        }
    }
}
