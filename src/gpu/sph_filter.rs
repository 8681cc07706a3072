//! `sph_filter` on the GPU (shaders/sph_filter.wgsl); CPU twin `cpu::sph_filter::run`. It runs
//! inside `sph_rates`, between the gradient of the particles' velocities and the gradient of
//! the filtered ones.

use super::neighbours::GpuGrid;
use super::shader::Program;
use super::state::GpuParticles;
use super::{Gpu, GpuError, Kernel};

/// The velocity filter: each particle's (r, z, v̄_r, v̄_z) into `kin_filtered`, kin's layout.
pub struct SphFilterPass {
    kernel: Kernel,
    bind: wgpu::BindGroup,
    kin_filtered: wgpu::Buffer,
    n: u32,
}

impl SphFilterPass {
    pub fn new(
        gpu: &Gpu,
        particles: &GpuParticles,
        grid: &GpuGrid,
        sph_uniform: &wgpu::Buffer,
    ) -> Result<SphFilterPass, GpuError> {
        let p = particles;
        let kernel = gpu.kernel(Program::SphFilter, "filter_velocity", &[])?;
        let kin_filtered = gpu.zeros::<[f32; 4]>("filtered kinematics", p.len);
        let own = [
            ("u", sph_uniform),
            ("area", &p.area),
            ("l_rr", &p.l_rr),
            ("l_rz", &p.l_rz),
            ("l_zr", &p.l_zr),
            ("l_zz", &p.l_zz),
            ("kin_filtered", &kin_filtered),
        ];
        let bind = kernel.bind(gpu, &[&grid.walk_bindings(&grid.kin)[..], &own].concat())?;
        Ok(SphFilterPass {
            kernel,
            bind,
            kin_filtered,
            n: p.len as u32,
        })
    }

    /// The filtered kinematics, for the second gradient to read in kin's place.
    pub fn kin_filtered(&self) -> &wgpu::Buffer {
        &self.kin_filtered
    }

    pub fn record(&self, pass: &mut wgpu::ComputePass) {
        self.kernel.dispatch(pass, &self.bind, self.n);
    }
}
