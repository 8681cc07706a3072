//! `integrate` on the GPU (shaders/integrate.wgsl); CPU twin `cpu::integrate`.

use super::shader::Program;
use super::state::{GpuElements, GpuNodes, GpuParticles};
use super::timestep::{DtSlots, DT_FROM_CLOCK};
use super::{Gpu, GpuError, Kernel};

/// Status words (shaders/step.wgsl): the smallest index of an entity that went wrong.
pub const STATUS_INVERTED_ELEMENT: usize = 0;
pub const STATUS_PARTICLE_NONFINITE: usize = 1;
pub const STATUS_PARTICLE_ESCAPED: usize = 2;
pub const STATUS_NODE_NONFINITE: usize = 3;
pub const STATUS_NODE_ESCAPED: usize = 4;
pub const STATUS_WORDS: usize = 8;
/// A status word with nothing to report.
pub const STATUS_CLEAR: u32 = u32::MAX;

/// The integration of particles and nodes in one dispatch, with a bind group for each place it
/// takes Δt from (`DtSlot`: the clock's slots 0 and 1, or the clock's Δt).
pub struct IntegratePass {
    kernel: Kernel,
    binds: [wgpu::BindGroup; 3],
    /// The larger of the particle and node counts.
    items: u32,
}

/// Buffers the integration accumulates into (summed by the host at output time).
pub struct Accumulators {
    /// Boundary z-impulse per particle (fixed particles) and per node (wall), N s.
    pub particle_impulse: wgpu::Buffer,
    pub node_impulse: wgpu::Buffer,
    /// Kinetic energy the wall took, per node (J).
    pub node_lost: wgpu::Buffer,
    /// Stand-ins for the particles' bindings in a scene without a target (never touched: its
    /// particle count is 0), one for the read-only bindings and one for the writable ones, as
    /// a buffer may not be bound both ways in one dispatch.
    pub unused: [wgpu::Buffer; 2],
}

impl Accumulators {
    pub fn new(gpu: &Gpu, n_particles: usize, n_nodes: usize) -> Accumulators {
        Accumulators {
            particle_impulse: gpu.zeros::<f32>("particle impulse", n_particles),
            node_impulse: gpu.zeros::<f32>("node impulse", n_nodes),
            node_lost: gpu.zeros::<f32>("node wall loss", n_nodes),
            unused: [0, 1].map(|_| gpu.zeros::<[f32; 4]>("unused", 1)),
        }
    }
}

/// What the integration of a scene with a target binds besides the particles: the neighbour
/// search's positions at the last build and its GridInfo (the displacement watch), and the
/// contact's bounding-box keys and hit list where it has a contact.
pub struct TargetBindings<'a> {
    pub particles: &'a GpuParticles,
    pub x_build: &'a wgpu::Buffer,
    pub grid_info: &'a wgpu::Buffer,
    pub contact: Option<(&'a wgpu::Buffer, &'a wgpu::Buffer)>,
}

impl IntegratePass {
    /// `target` is None for a scene without one.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        gpu: &Gpu,
        step: &wgpu::Buffer,
        clock: &wgpu::Buffer,
        status: &wgpu::Buffer,
        slots: &DtSlots,
        target: Option<TargetBindings>,
        nodes: &GpuNodes,
        elements: &GpuElements,
        acc: &Accumulators,
    ) -> Result<IntegratePass, GpuError> {
        let kernel = gpu.kernel(Program::Integrate, "main", &[])?;
        let [read, write] = &acc.unused;
        let p: [&wgpu::Buffer; 15] = match &target {
            Some(t) => [
                &t.particles.r,
                &t.particles.z,
                &t.particles.vr,
                &t.particles.vz,
                &t.particles.ar,
                &t.particles.az,
                &t.particles.mass,
                &t.particles.fixed,
                &acc.particle_impulse,
                &t.particles.de_work,
                &t.particles.energy,
                t.x_build,
                t.grid_info,
                // Without slaves (the step uniform's n_slaves is 0) they are never touched.
                t.contact.map_or(write, |c| c.0),
                t.contact.map_or(write, |c| c.1),
            ],
            None => [
                write, write, write, write, read, read, read, read, write, read, write, read,
                write, write, write,
            ],
        };
        let n = nodes;
        let bind = |slot: u32| {
            kernel.bind(
                gpu,
                &[
                    ("u", step),
                    ("clock", clock),
                    ("status", status),
                    ("source", slots.get(slot)),
                    ("r", p[0]),
                    ("z", p[1]),
                    ("vr", p[2]),
                    ("vz", p[3]),
                    ("ar", p[4]),
                    ("az", p[5]),
                    ("mass", p[6]),
                    ("fixed", p[7]),
                    ("impulse", p[8]),
                    ("de_work", p[9]),
                    ("energy", p[10]),
                    ("x_build", p[11]),
                    ("grid_words", p[12]),
                    ("node_r", &n.r),
                    ("node_z", &n.z),
                    ("node_vr", &n.vr),
                    ("node_vz", &n.vz),
                    ("node_fr", &n.fr),
                    ("node_fz", &n.fz),
                    ("node_mass", &n.mass),
                    ("on_axis", &n.on_axis),
                    ("node_impulse", &acc.node_impulse),
                    ("node_lost", &acc.node_lost),
                    ("box_keys", p[13]),
                    ("hits", p[14]),
                    ("elem_offsets", &n.elem_offsets),
                    ("elem_refs", &n.elem_refs),
                    ("force", &elements.force),
                ],
            )
        };
        let binds = [bind(0)?, bind(1)?, bind(DT_FROM_CLOCK)?];
        let n_particles = target.map_or(0, |t| t.particles.len as u32);
        Ok(IntegratePass {
            kernel,
            binds,
            items: n_particles.max(nodes.len as u32),
        })
    }

    /// Velocities and positions of particles and nodes over the Δt of `source` (a slot of the
    /// clock's minima, or `DT_FROM_CLOCK`).
    pub fn record(&self, pass: &mut wgpu::ComputePass, source: u32) {
        self.kernel
            .dispatch(pass, &self.binds[source as usize], self.items);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::contact_detect::{float_key, EMPTY_BOX};
    use crate::gpu::params::StepUniform;
    use crate::gpu::{run_once, test_gpu};
    use crate::solver::{Model, Simulation};

    fn smoke(steps: usize) -> Model {
        let scene =
            crate::scene::load(std::path::Path::new("cases/smoke.toml"), &[]).expect("smoke case");
        let mut sim = Simulation::new(&scene).expect("smoke builds");
        for _ in 0..steps {
            sim.step().expect("smoke steps");
        }
        sim.into_model().expect("smoke's state")
    }

    fn uniform(sim: &Model) -> StepUniform {
        let sph = sim.sph.expect("smoke has a target");
        StepUniform {
            n_particles: sim.particles.len() as u32,
            n_nodes: sim.projectile.nodes.len() as u32,
            n_elements: sim.projectile.elements.len() as u32,
            escape: 1.0e3,
            r_min: 0.1 * sph.h,
            h: sph.h,
            alpha: sph.alpha,
            beta: sph.beta,
            cfl: sim.scene.run.cfl as f32,
            has_fem: 1,
            ..Default::default()
        }
    }

    /// Largest |a − b| relative to the largest |b| of the field.
    fn field_error(a: &[f32], b: &[f32]) -> f32 {
        let scale = b
            .iter()
            .fold(0.0f32, |m, x| m.max(x.abs()))
            .max(f32::MIN_POSITIVE);
        a.iter()
            .zip(b)
            .fold(0.0f32, |m, (x, y)| m.max((x - y).abs()))
            / scale
    }

    /// The moved² word of a stand-in for the grid's words.
    const MOVED2: usize = (crate::gpu::neighbours::MOVED2_OFFSET / 4) as usize;

    /// One integration agrees with the CPU twin on the smoke state; the next takes its Δt from
    /// the slot of running minima (`sph_forces` and `fem_stress` fill it); each integration
    /// empties the other parity's slot, box and the hit list; the displacement watch holds the
    /// largest move since the build and the box the nodes' extent.
    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn integrate_and_timestep_match_cpu() {
        use crate::gpu::timestep::{clock_words, slot_dt, DtSlots, DT_FROM_CLOCK};
        let gpu = test_gpu();
        let mut sim = smoke(60);
        // Set some of the target moving (the smoke's is still at rest), each particle at its
        // own speed.
        for i in (0..sim.particles.len()).step_by(7) {
            sim.particles.vz[i] -= 50.0 + 0.01 * i as f32;
        }
        let dt = sim.dt;
        let u = StepUniform {
            n_slaves: 1,
            ..uniform(&sim)
        };
        let step = gpu.uniform("step", &u);
        // Slot and box 1 hold stale values, the hit list a count.
        let stale = [1.0f32.to_bits(), 2.0f32.to_bits()];
        let mut words = clock_words(dt, false);
        words[4..].copy_from_slice(&stale);
        let clock = gpu.buffer("clock", &words);
        let box_keys = gpu.buffer("box keys", &[EMPTY_BOX, [7; 4]]);
        let hits = gpu.buffer("hits", &[5u32]);
        let status = gpu.buffer("status", &[STATUS_CLEAR; STATUS_WORDS]);
        let gp = GpuParticles::upload(&gpu, &sim.particles);
        // The nodes' forces poisoned: the integration gathers its own from the elements'.
        let mut poisoned = sim.projectile.nodes.clone();
        poisoned.fr.iter_mut().for_each(|f| *f = f32::NAN);
        poisoned.fz.iter_mut().for_each(|f| *f = f32::NAN);
        let gn = GpuNodes::upload(&gpu, &poisoned);
        let ge = GpuElements::upload(&gpu, &sim.projectile.elements);
        let acc = Accumulators::new(&gpu, gp.len, gn.len);
        let slots = DtSlots::new(&gpu);
        // The lists "built" where the particles are now.
        let x_build: Vec<[f32; 2]> = (0..sim.particles.len())
            .map(|i| [sim.particles.r[i], sim.particles.z[i]])
            .collect();
        let x_build = gpu.buffer("x_build", &x_build);
        let grid_words = gpu.buffer("grid words", &[0u32; MOVED2 + 1]);
        let pass = IntegratePass::new(
            &gpu,
            &step,
            &clock,
            &status,
            &slots,
            Some(TargetBindings {
                particles: &gp,
                x_build: &x_build,
                grid_info: &grid_words,
                contact: Some((&box_keys, &hits)),
            }),
            &gn,
            &ge,
            &acc,
        )
        .unwrap();
        // Parity 0, from the clock's Δt.
        run_once(&gpu, |p| pass.record(p, DT_FROM_CLOCK)).unwrap();

        let mut cpu = sim.particles.clone();
        let sph = sim.sph.unwrap();
        crate::cpu::integrate::particles(&mut cpu, &sph, dt, 1.0e3).unwrap();
        let mut nodes = sim.projectile.nodes.clone();
        crate::cpu::fem_forces::run(&mut nodes, &sim.projectile.elements);
        assert!(
            nodes.fz.iter().any(|&f| f != 0.0),
            "the projectile is loaded"
        );
        crate::cpu::integrate::nodes(&mut nodes, dt, None, 1.0e3).unwrap();
        let mut back = sim.particles.clone();
        gp.download(&gpu, &mut back).unwrap();
        let mut back_nodes = nodes.clone();
        gn.download(&gpu, &mut back_nodes).unwrap();
        // The nodal forces gathered in CSR order, as the CPU sums them: the same bits.
        for (name, a, b) in [
            ("fr", &back_nodes.fr, &nodes.fr),
            ("fz", &back_nodes.fz, &nodes.fz),
        ] {
            let differ = a.iter().zip(b).filter(|(x, y)| x.to_bits() != y.to_bits());
            assert_eq!(differ.count(), 0, "{name}: not the CPU's gather");
        }
        // x + dt·(v + dt·a): one rounding per operation on each side; a fused multiply-add on
        // the GPU moves the result by at most an ulp of the field, ~1e-7 relative.
        for (name, a, b) in [
            ("r", &back.r, &cpu.r),
            ("z", &back.z, &cpu.z),
            ("vr", &back.vr, &cpu.vr),
            ("vz", &back.vz, &cpu.vz),
            ("energy", &back.energy, &cpu.energy),
            ("node r", &back_nodes.r, &nodes.r),
            ("node z", &back_nodes.z, &nodes.z),
            ("node vr", &back_nodes.vr, &nodes.vr),
            ("node vz", &back_nodes.vz, &nodes.vz),
        ] {
            let e = field_error(a, b);
            assert!(e < 1.0e-6, "{name}: relative error {e:e}");
        }
        let moved2 = (0..back.len())
            .map(|i| {
                let (dr, dz) = (
                    back.r[i] - sim.particles.r[i],
                    back.z[i] - sim.particles.z[i],
                );
                dr * dr + dz * dz
            })
            .fold(0.0f32, f32::max);
        let watched = f32::from_bits(gpu.read::<u32>(&grid_words, MOVED2 + 1).unwrap()[MOVED2]);
        assert!(moved2 > 0.0, "the particles move");
        assert!(
            (watched - moved2).abs() <= 1e-5 * moved2,
            "watch {watched:e} against {moved2:e}"
        );

        // The box of parity 0: the nodes' extent (r from 0), to the bit; parity 1's emptied
        // and the hit list with it.
        let extent = |n: &crate::state::Nodes| {
            [
                float_key(n.r.iter().fold(0.0f32, |m, &r| m.max(r))),
                float_key(n.z.iter().fold(f32::MAX, |m, &z| m.min(z))),
                float_key(n.z.iter().fold(-f32::MAX, |m, &z| m.max(z))),
            ]
        };
        let keys: Vec<u32> = gpu.read(&box_keys, 8).unwrap();
        assert_eq!(keys[..3], extent(&back_nodes));
        assert_eq!(keys[4..7], EMPTY_BOX[..3]);
        assert_eq!(gpu.read::<u32>(&hits, 1).unwrap(), [0]);

        // The integration from the clock left the clock's Δt alone and emptied slot 1.
        let words: Vec<u32> = gpu.read(&clock, 6).unwrap();
        assert_eq!(words[0], dt.to_bits());
        assert_eq!(&words[4..], &[f32::MAX.to_bits(); 2]);

        // The next integration (parity 1) takes the Δt of slot 1's minima (the CPU's
        // candidates here) to the bit, says who set it, empties slot 0 and box 0, and folds
        // box 1.
        let minima = [
            crate::cpu::timestep::particle_dt(&back, &sph).to_bits(),
            crate::cpu::timestep::element_dt(&sim.projectile.elements).to_bits(),
        ];
        gpu.write_at(&clock, 4, &minima);
        let next = slot_dt(minima[0], minima[1], u.cfl);
        gpu.write_at(&clock, 2, &stale);
        run_once(&gpu, |p| pass.record(p, 1)).unwrap();
        let words: Vec<u32> = gpu.read(&clock, 6).unwrap();
        assert_eq!(words[0], next.to_bits());
        assert_eq!(words[1], u32::from(words[5] <= words[4]));
        assert_eq!(&words[2..4], &[f32::MAX.to_bits(); 2]);
        gn.download(&gpu, &mut back_nodes).unwrap();
        let keys: Vec<u32> = gpu.read(&box_keys, 8).unwrap();
        assert_eq!(keys[4..7], extent(&back_nodes));
        assert_eq!(keys[..3], EMPTY_BOX[..3]);
        let st: Vec<u32> = gpu.read(&status, STATUS_WORDS).unwrap();
        assert!(
            st.iter().all(|&w| w == STATUS_CLEAR),
            "no instability: {st:?}"
        );
    }

    /// A non-finite velocity is flagged with the particle's index.
    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn integrate_flags_a_non_finite_particle() {
        let gpu = test_gpu();
        let mut sim = smoke(0);
        sim.particles.az[17] = f32::NAN;
        sim.particles.fixed[17] = 0;
        let u = uniform(&sim);
        let step = gpu.uniform("step", &u);
        let clock = gpu.buffer("clock", &crate::gpu::timestep::clock_words(sim.dt, false));
        let status = gpu.buffer("status", &[STATUS_CLEAR; STATUS_WORDS]);
        let gp = GpuParticles::upload(&gpu, &sim.particles);
        let gn = GpuNodes::upload(&gpu, &sim.projectile.nodes);
        let ge = GpuElements::upload(&gpu, &sim.projectile.elements);
        let acc = Accumulators::new(&gpu, gp.len, gn.len);
        let slots = crate::gpu::timestep::DtSlots::new(&gpu);
        let x_build = gpu.zeros::<[f32; 2]>("x_build", gp.len);
        let grid_words = gpu.zeros::<u32>("grid words", MOVED2 + 1);
        let pass = IntegratePass::new(
            &gpu,
            &step,
            &clock,
            &status,
            &slots,
            Some(TargetBindings {
                particles: &gp,
                x_build: &x_build,
                grid_info: &grid_words,
                contact: None,
            }),
            &gn,
            &ge,
            &acc,
        )
        .unwrap();
        run_once(&gpu, |p| {
            pass.record(p, crate::gpu::timestep::DT_FROM_CLOCK)
        })
        .unwrap();
        let st: Vec<u32> = gpu.read(&status, STATUS_WORDS).unwrap();
        assert_eq!(st[STATUS_PARTICLE_NONFINITE], 17);
        assert_eq!(st[STATUS_NODE_NONFINITE], STATUS_CLEAR);
    }
}
