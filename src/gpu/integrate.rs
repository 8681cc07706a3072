//! `integrate` on the GPU (shaders/integrate.wgsl); CPU twin `cpu::integrate`.

use super::shader::Program;
use super::state::{GpuNodes, GpuParticles};
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

/// The integration of particles and nodes.
pub struct IntegratePass {
    particles: Option<(Kernel, wgpu::BindGroup)>,
    nodes: (Kernel, wgpu::BindGroup),
    n_particles: u32,
    n_nodes: u32,
}

/// Buffers the integration accumulates into (summed by the host at output time).
pub struct Accumulators {
    /// Boundary z-impulse per particle (fixed particles) and per node (wall), N s.
    pub particle_impulse: wgpu::Buffer,
    pub node_impulse: wgpu::Buffer,
    /// Kinetic energy the wall took, per node (J).
    pub node_lost: wgpu::Buffer,
    /// One-element stand-ins for the bindings an entry point does not use (never written):
    /// the particles' `lost`, the nodes' `energy` and `de_work`.
    pub unused: [wgpu::Buffer; 2],
}

impl Accumulators {
    pub fn new(gpu: &Gpu, n_particles: usize, n_nodes: usize) -> Accumulators {
        Accumulators {
            particle_impulse: gpu.zeros::<f32>("particle impulse", n_particles),
            node_impulse: gpu.zeros::<f32>("node impulse", n_nodes),
            node_lost: gpu.zeros::<f32>("node wall loss", n_nodes),
            unused: [gpu.zeros::<f32>("unused", 1), gpu.zeros::<f32>("unused", 1)],
        }
    }
}

impl IntegratePass {
    /// `particles` is None for a scene without a target.
    pub fn new(
        gpu: &Gpu,
        step: &wgpu::Buffer,
        clock: &wgpu::Buffer,
        status: &wgpu::Buffer,
        particles: Option<&GpuParticles>,
        nodes: &GpuNodes,
        acc: &Accumulators,
    ) -> Result<IntegratePass, GpuError> {
        let integrate = |entry: &str| gpu.kernel(Program::Integrate, entry, &[]);
        let particles_pass = match particles {
            Some(p) => {
                let k = integrate("particles")?;
                let b = k.bind(
                    gpu,
                    &[
                        ("u", step),
                        ("clock", clock),
                        ("status", status),
                        ("r", &p.r),
                        ("z", &p.z),
                        ("vr", &p.vr),
                        ("vz", &p.vz),
                        ("ar", &p.ar),
                        ("az", &p.az),
                        ("mass", &p.mass),
                        ("flag", &p.fixed),
                        ("impulse", &acc.particle_impulse),
                        ("lost", &acc.unused[0]),
                        ("de_work", &p.de_work),
                        ("energy", &p.energy),
                    ],
                )?;
                Some((k, b))
            }
            None => None,
        };
        let k = integrate("nodes")?;
        let n = nodes;
        let nodes_bind = k.bind(
            gpu,
            &[
                ("u", step),
                ("clock", clock),
                ("status", status),
                ("r", &n.r),
                ("z", &n.z),
                ("vr", &n.vr),
                ("vz", &n.vz),
                ("ar", &n.fr),
                ("az", &n.fz),
                ("mass", &n.mass),
                ("flag", &n.on_axis),
                ("impulse", &acc.node_impulse),
                ("lost", &acc.node_lost),
                ("de_work", &acc.unused[1]),
                ("energy", &acc.unused[0]),
            ],
        )?;
        Ok(IntegratePass {
            particles: particles_pass,
            nodes: (k, nodes_bind),
            n_particles: particles.map_or(0, |p| p.len as u32),
            n_nodes: nodes.len as u32,
        })
    }

    /// Velocities and positions of particles and nodes over the clock's Δt.
    pub fn record(&self, pass: &mut wgpu::ComputePass) {
        if let Some((k, b)) = &self.particles {
            k.dispatch(pass, b, self.n_particles);
        }
        self.nodes.0.dispatch(pass, &self.nodes.1, self.n_nodes);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::params::StepUniform;
    use crate::gpu::state::GpuElements;
    use crate::gpu::timestep::TimestepPass;
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

    /// One integration and one Δt reduction agree with the CPU twins on the smoke state.
    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn integrate_and_timestep_match_cpu() {
        let gpu = test_gpu();
        let sim = smoke(60);
        let dt = sim.dt;
        let u = uniform(&sim);
        let step = gpu.uniform("step", &u);
        let clock = gpu.buffer("clock", &crate::gpu::timestep::clock_words(dt, false));
        let status = gpu.buffer("status", &[STATUS_CLEAR; STATUS_WORDS]);
        let gp = GpuParticles::upload(&gpu, &sim.particles);
        let gn = GpuNodes::upload(&gpu, &sim.projectile.nodes);
        let ge = GpuElements::upload(&gpu, &sim.projectile.elements);
        let acc = Accumulators::new(&gpu, gp.len, gn.len);
        let pass = IntegratePass::new(&gpu, &step, &clock, &status, Some(&gp), &gn, &acc).unwrap();
        let timestep = TimestepPass::new(&gpu, &step, &clock, Some(&gp), Some(&ge), &gn.r).unwrap();
        run_once(&gpu, |p| {
            pass.record(p);
            timestep.record(p);
        })
        .unwrap();

        let mut cpu = sim.particles.clone();
        let sph = sim.sph.unwrap();
        crate::cpu::integrate::particles(&mut cpu, &sph, dt, 1.0e3).unwrap();
        let mut nodes = sim.projectile.nodes.clone();
        crate::cpu::integrate::nodes(&mut nodes, dt, None, 1.0e3).unwrap();
        let mut back = sim.particles.clone();
        gp.download(&gpu, &mut back).unwrap();
        let mut back_nodes = nodes.clone();
        gn.download(&gpu, &mut back_nodes).unwrap();
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

        // The next Δt, from the integrated particle state and the elements' dt.
        let expect = crate::cpu::timestep::particle_dt(&back, &sph)
            .min(crate::cpu::timestep::element_dt(&sim.projectile.elements))
            * u.cfl;
        let words: Vec<u32> = gpu.read(&clock, 2).unwrap();
        let got = f32::from_bits(words[0]);
        // h/(c + |v| + …): a handful of roundings, and the driver may use a faster division.
        assert!(
            ((got - expect) / expect).abs() < 1.0e-5,
            "dt {got:e} against {expect:e}"
        );
        assert_eq!(words[1], f32::MAX.to_bits(), "the running minimum resets");
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
        let acc = Accumulators::new(&gpu, gp.len, gn.len);
        let pass = IntegratePass::new(&gpu, &step, &clock, &status, Some(&gp), &gn, &acc).unwrap();
        run_once(&gpu, |p| pass.record(p)).unwrap();
        let st: Vec<u32> = gpu.read(&status, STATUS_WORDS).unwrap();
        assert_eq!(st[STATUS_PARTICLE_NONFINITE], 17);
        assert_eq!(st[STATUS_NODE_NONFINITE], STATUS_CLEAR);
    }
}
