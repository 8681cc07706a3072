//! `timestep` on the GPU (shaders/timestep.wgsl): the next Δt into the clock, a min-reduction
//! over the particles' and elements' stable steps; CPU twin `cpu::timestep` with
//! `Simulation::stable_dt`.

use super::shader::Program;
use super::state::{GpuElements, GpuParticles};
use super::{Gpu, GpuError, Kernel};

/// The clock's first words (params.wgsl `Clock`): the step `dt`, empty running minima, and
/// whether the elements set `dt`.
pub fn clock_words(dt: f32, fem_limited: bool) -> [u32; 4] {
    [
        dt.to_bits(),
        f32::MAX.to_bits(),
        f32::MAX.to_bits(),
        u32::from(fem_limited),
    ]
}

/// The Δt reduction.
pub struct TimestepPass {
    particle_dt: Option<(Kernel, wgpu::BindGroup)>,
    element_dt: Option<(Kernel, wgpu::BindGroup)>,
    finish: (Kernel, wgpu::BindGroup),
    n_particles: u32,
    n_elements: u32,
}

impl TimestepPass {
    /// `particles` is None for a scene without a target, `elements` None for a rigid
    /// projectile (its stable step does not take part); `any` is a buffer of at least one f32
    /// for the slots an entry point does not read.
    pub fn new(
        gpu: &Gpu,
        step: &wgpu::Buffer,
        clock: &wgpu::Buffer,
        particles: Option<&GpuParticles>,
        elements: Option<&GpuElements>,
        any: &wgpu::Buffer,
    ) -> Result<TimestepPass, GpuError> {
        let timestep = |entry: &str| gpu.kernel(Program::Timestep, entry, &[]);
        // The reductions' bindings a–d: what their entry point reads (timestep.wgsl), with one
        // buffer in the slots an entry point leaves unused.
        let reduction = |entry: &str, reads: [&wgpu::Buffer; 4]| {
            let k = timestep(entry)?;
            let [a, b, c, d] = reads;
            let bind = k.bind(
                gpu,
                &[
                    ("u", step),
                    ("clock", clock),
                    ("a", a),
                    ("b", b),
                    ("c", c),
                    ("d", d),
                ],
            )?;
            Ok::<_, GpuError>((k, bind))
        };
        Ok(TimestepPass {
            particle_dt: particles
                .map(|p| reduction("particle_dt", [&p.sound, &p.vr, &p.vz, &p.mu_visc]))
                .transpose()?,
            element_dt: elements
                .map(|e| reduction("element_dt", [&e.dt; 4]))
                .transpose()?,
            finish: reduction("finish", [any; 4])?,
            n_particles: particles.map_or(0, |p| p.len as u32),
            n_elements: elements.map_or(0, |e| e.len as u32),
        })
    }

    /// The next Δt into the clock, from the particles' and elements' current state.
    pub fn record(&self, pass: &mut wgpu::ComputePass) {
        if let Some((k, b)) = &self.particle_dt {
            k.dispatch_fold(pass, b, self.n_particles);
        }
        if let Some((k, b)) = &self.element_dt {
            k.dispatch_fold(pass, b, self.n_elements);
        }
        self.finish.0.dispatch_groups(pass, &self.finish.1, 1);
    }
}
