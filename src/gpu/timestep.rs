//! `timestep` on the GPU (shaders/timestep.wgsl): the next Δt's candidates folded into one of
//! the clock's two slots of running minima, which the integration (shaders/integrate.wgsl)
//! makes the step of; CPU twin `cpu::timestep` with `Simulation::stable_dt`.

use super::params::DtSlot;
use super::shader::Program;
use super::state::{GpuElements, GpuParticles};
use super::{Gpu, GpuError, Kernel};

/// `DtSlot` for an integration that takes the clock's Δt as the host set it.
pub const DT_FROM_CLOCK: u32 = 2;

/// The clock's words (params.wgsl `Clock`): the step `dt`, whether the elements set it, and
/// two empty slots of running minima.
pub fn clock_words(dt: f32, fem_limited: bool) -> [u32; 6] {
    [
        dt.to_bits(),
        u32::from(fem_limited),
        f32::MAX.to_bits(),
        f32::MAX.to_bits(),
        f32::MAX.to_bits(),
        f32::MAX.to_bits(),
    ]
}

/// Byte offset of the clock's slots of running minima.
pub const CLOCK_SLOTS: u64 = 8;

/// The step the integration makes of a slot's minima (integrate.wgsl `step_dt`): the least
/// candidate times the CFL number, one f32 product, rounded as the GPU rounds it.
pub fn slot_dt(sph_bits: u32, fem_bits: u32, cfl: f32) -> f32 {
    f32::from_bits(sph_bits.min(fem_bits)) * cfl
}

/// The three `DtSlot` uniforms, by value (0, 1, `DT_FROM_CLOCK`).
pub struct DtSlots([wgpu::Buffer; 3]);

impl DtSlots {
    pub fn new(gpu: &Gpu) -> DtSlots {
        DtSlots([0, 1, DT_FROM_CLOCK].map(|slot| gpu.uniform("dt slot", &DtSlot { slot })))
    }

    pub fn get(&self, slot: u32) -> &wgpu::Buffer {
        &self.0[slot as usize]
    }
}

/// The Δt reduction: one dispatch folding particles and elements, with a bind group for each
/// slot.
pub struct TimestepPass {
    fold: Kernel,
    binds: [wgpu::BindGroup; 2],
    /// The larger of the counts folded.
    items: u32,
}

impl TimestepPass {
    /// `particles` is None for a scene without a target, `elements` None for a rigid
    /// projectile (its stable step does not take part; the step uniform's `has_fem` is 0);
    /// `any` is a buffer of at least one f32 for the side a scene lacks.
    pub fn new(
        gpu: &Gpu,
        step: &wgpu::Buffer,
        clock: &wgpu::Buffer,
        slots: &DtSlots,
        particles: Option<&GpuParticles>,
        elements: Option<&GpuElements>,
        any: &wgpu::Buffer,
    ) -> Result<TimestepPass, GpuError> {
        let fold = gpu.kernel(Program::Timestep, "fold", &[])?;
        let [sound, vr, vz, mu_visc] =
            particles.map_or([any; 4], |p| [&p.sound, &p.vr, &p.vz, &p.mu_visc]);
        let element_dt = elements.map_or(any, |e| &e.dt);
        let bind = |slot: u32| {
            fold.bind(
                gpu,
                &[
                    ("u", step),
                    ("clock", clock),
                    ("target_slot", slots.get(slot)),
                    ("sound", sound),
                    ("vr", vr),
                    ("vz", vz),
                    ("mu_visc", mu_visc),
                    ("element_dt", element_dt),
                ],
            )
        };
        let binds = [bind(0)?, bind(1)?];
        let n_particles = particles.map_or(0, |p| p.len as u32);
        let n_elements = elements.map_or(0, |e| e.len as u32);
        Ok(TimestepPass {
            fold,
            binds,
            items: n_particles.max(n_elements),
        })
    }

    /// The next Δt's candidates into the clock's `slot`, from the particles' and elements'
    /// current state.
    pub fn record(&self, pass: &mut wgpu::ComputePass, slot: u32) {
        self.fold
            .dispatch_fold(pass, &self.binds[slot as usize], self.items);
    }
}
