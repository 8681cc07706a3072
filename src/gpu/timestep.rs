//! The time step on the GPU (shaders/step.wgsl): `sph_forces` and `fem_stress` fold the next
//! Δt's candidates into one of the clock's two slots of running minima, which the integration
//! (shaders/integrate.wgsl) makes the step of; CPU twin `cpu::timestep` with
//! `Simulation::stable_dt`.

use super::params::DtSlot;
use super::Gpu;

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
