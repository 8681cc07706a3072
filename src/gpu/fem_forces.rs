//! `fem_forces` on the GPU (shaders/fem_forces.wgsl); CPU twin `cpu::fem_forces::run`. Its
//! test is `gpu::fem_stress`'s `fem_forces_matches_cpu`, which runs it after the stress pass.

use super::shader::Program;
use super::state::{GpuElements, GpuNodes};
use super::{Gpu, GpuError, Kernel};

/// `fem_forces` gathers the element forces into the nodes' fr, fz through the node → element
/// CSR, in the order the CPU sums them.
pub struct FemForcesPass {
    kernel: Kernel,
    bind: wgpu::BindGroup,
    n_nodes: u32,
}

impl FemForcesPass {
    /// `fem_uniform` holds a `params::FemUniform`.
    pub fn new(
        gpu: &Gpu,
        nodes: &GpuNodes,
        elements: &GpuElements,
        fem_uniform: &wgpu::Buffer,
    ) -> Result<FemForcesPass, GpuError> {
        let kernel = gpu.kernel(Program::FemForces, "main", &[])?;
        let (n, e) = (nodes, elements);
        let bind = kernel.bind(
            gpu,
            &[
                ("u", fem_uniform),
                ("elem_offsets", &n.elem_offsets),
                ("elem_refs", &n.elem_refs),
                ("force", &e.force),
                ("fr", &n.fr),
                ("fz", &n.fz),
            ],
        )?;
        Ok(FemForcesPass {
            kernel,
            bind,
            n_nodes: n.len as u32,
        })
    }

    /// Record `fem_forces`: one thread per node; after `fem_stress` in the same pass (the
    /// dispatches are ordered, so it sees the element forces just written).
    pub fn record(&self, pass: &mut wgpu::ComputePass) {
        self.kernel.dispatch(pass, &self.bind, self.n_nodes);
    }
}
