//! GPU twins of `state::{Particles, Nodes, Elements}`: one storage buffer per field, the same
//! names, the same element types, so a shader reads exactly what its CPU twin reads.

use super::{Batched, Gpu, GpuError, Part, ReadBatch};
use crate::state::{Elements, Nodes, Particles};

/// Declares a struct of buffers mirroring a CPU struct's fields, with upload and download; the
/// `fixed` fields, which no pass changes, are uploaded and never read back.
macro_rules! mirror {
    ($name:ident, $cpu:ty, len = $len:ident, [$($field:ident: $t:ty),* $(,)?]
     $(, fixed [$($fixed:ident: $ft:ty),* $(,)?])?) => {
        pub struct $name {
            pub len: usize,
            $(pub $field: wgpu::Buffer,)*
            $($(pub $fixed: wgpu::Buffer,)*)?
        }

        impl $name {
            pub fn upload(gpu: &Gpu, s: &$cpu) -> $name {
                $name {
                    len: s.$len.len(),
                    $($field: gpu.buffer::<$t>(concat!(stringify!($name), ".", stringify!($field)), &s.$field),)*
                    $($($fixed: gpu.buffer::<$ft>(concat!(stringify!($name), ".", stringify!($fixed)), &s.$fixed),)*)?
                }
            }

            /// Overwrite every changing field on the GPU with the CPU values (same lengths).
            pub fn write(&self, gpu: &Gpu, s: &$cpu) {
                $(gpu.write::<$t>(&self.$field, &s.$field);)*
            }

            /// Read every field back into `s` (same lengths), in one round trip.
            pub fn download(&self, gpu: &Gpu, s: &mut $cpu) -> Result<(), GpuError> {
                let mut batch = ReadBatch::new();
                let parts = self.queue(&mut batch, s);
                let encoder = gpu
                    .device
                    .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
                Self::take(&batch.read(gpu, encoder)?, &parts, s);
                Ok(())
            }

            /// Add a read of every field (the lengths of `s`'s) to `batch`.
            pub fn queue<'a>(&'a self, batch: &mut ReadBatch<'a>, s: &$cpu) -> Vec<Part> {
                vec![$(batch.add::<$t>(&self.$field, s.$field.len()),)*]
            }

            /// Fill `s` from what `queue`'s parts read.
            pub fn take(read: &Batched, parts: &[Part], s: &mut $cpu) {
                let mut parts = parts.iter();
                $(s.$field = read.take::<$t>(*parts.next().expect("one part per field"));)*
            }
        }
    };
}

mirror!(GpuParticles, Particles, len = r, [
    r: f32, z: f32, vr: f32, vz: f32, ar: f32, az: f32, mass: f32, rho: f32, energy: f32,
    strain_energy: f32,
    p: f32, s_rr: f32, s_zz: f32, s_rz: f32, s_tt: f32, damage: f32, mu_max: f32, eps_p: f32,
    sound: f32, l_rr: f32, l_rz: f32, l_zr: f32, l_zz: f32, drho: f32, de_visc: f32, de_work: f32,
    mu_visc: f32, visc_switch: f32, m_tilde: f32, area: f32, hoop_weight: f32,
    l_visc: [f32; 4], stress_rho2: [f32; 3], art_stress: [f32; 3],
    fixed: u32,
]);

mirror!(GpuNodes, Nodes, len = r, [
    r: f32, z: f32, vr: f32, vz: f32, fr: f32, fz: f32, mass: f32, on_axis: u32,
], fixed [
    // With wall images the GPU's CSR also names the master segments' reactions
    // (`cpu::wall::csr`), so it is not the host's.
    elem_offsets: u32, elem_refs: u32,
]);

mirror!(GpuElements, Elements, len = nodes, [
    nodes: [u32; 3], cells: u32, volume0: f32, s_rr: f32, s_zz: f32, s_rz: f32, s_tt: f32, p: f32,
    energy: f32, eps_p: f32, temperature: f32, damage: f32, failed: u32, force: [f32; 6],
    dt: f32, plastic_work: f32,
]);

#[cfg(test)]
mod tests {
    use super::*;

    /// Every field makes the round trip CPU → GPU → CPU unchanged.
    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn particles_round_trip() {
        let gpu = crate::gpu::test_gpu();
        let mut p = Particles::default();
        let n = 37;
        for i in 0..n {
            let x = i as f32;
            p.r.push(x * 1e-3);
            p.z.push(-x);
            p.vr.push(x + 0.5);
            p.vz.push(x * 2.0);
            p.stress_rho2.push([x, -x, 2.0 * x]);
            p.fixed.push(i as u32 % 2);
        }
        for v in [
            &mut p.ar,
            &mut p.az,
            &mut p.mass,
            &mut p.rho,
            &mut p.energy,
            &mut p.strain_energy,
            &mut p.p,
            &mut p.s_rr,
            &mut p.s_zz,
            &mut p.s_rz,
            &mut p.s_tt,
            &mut p.damage,
            &mut p.mu_max,
            &mut p.eps_p,
            &mut p.sound,
            &mut p.l_rr,
            &mut p.l_rz,
            &mut p.l_zr,
            &mut p.l_zz,
            &mut p.drho,
            &mut p.de_visc,
            &mut p.de_work,
            &mut p.mu_visc,
            &mut p.visc_switch,
            &mut p.m_tilde,
            &mut p.area,
            &mut p.hoop_weight,
        ] {
            *v = (0..n).map(|i| i as f32 * 0.25).collect();
        }
        p.art_stress = vec![[1.0, 2.0, 3.0]; n];
        let g = GpuParticles::upload(&gpu, &p);
        let mut back = p.clone();
        back.r.iter_mut().for_each(|x| *x = 0.0);
        back.stress_rho2.iter_mut().for_each(|x| *x = [0.0; 3]);
        g.download(&gpu, &mut back).unwrap();
        assert_eq!(back.r, p.r);
        assert_eq!(back.stress_rho2, p.stress_rho2);
        assert_eq!(back.fixed, p.fixed);
        assert_eq!(back.area, p.area);
        assert_eq!(back.hoop_weight, p.hoop_weight);
    }
}
