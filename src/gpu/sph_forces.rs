//! `sph_forces` on the GPU (shaders/sph_forces.wgsl); CPU twin `cpu::sph_forces::run`.

use super::state::GpuParticles;
use super::{source, Gpu, Kernel, Slot};

/// Bindings of shaders/sph_forces.wgsl, shared by both entry points: SphUniform, the grid
/// (GridInfo, cell_start, sorted), 12 read fields, then stress_rho2 and art_stress (written by
/// `prologue`, read by `forces`) and the four outputs of `forces`.
const SLOTS: [Slot; 22] = [
    Slot::Uniform,
    Slot::Read,
    Slot::Read,
    Slot::Read,
    Slot::Read,
    Slot::Read,
    Slot::Read,
    Slot::Read,
    Slot::Read,
    Slot::Read,
    Slot::Read,
    Slot::Read,
    Slot::Read,
    Slot::Read,
    Slot::Read,
    Slot::Read,
    Slot::ReadWrite,
    Slot::ReadWrite,
    Slot::ReadWrite,
    Slot::ReadWrite,
    Slot::ReadWrite,
    Slot::ReadWrite,
];

/// Particle accelerations: `prologue` writes stress_rho2 (and art_stress when the artificial
/// stress is on) from p, rho and the deviator; `forces` gathers over the grid's neighbours
/// and axis ghosts and writes ar, az, de_visc and mu_visc (fixed particles included, as on
/// the CPU).
pub struct SphForcesPass {
    prologue: Kernel,
    forces: Kernel,
    prologue_bind: wgpu::BindGroup,
    forces_bind: wgpu::BindGroup,
    n: u32,
}

impl SphForcesPass {
    pub fn new(
        gpu: &Gpu,
        particles: &GpuParticles,
        grid_info: &wgpu::Buffer,
        cell_start: &wgpu::Buffer,
        sorted: &wgpu::Buffer,
        sph_uniform: &wgpu::Buffer,
    ) -> Result<SphForcesPass, String> {
        let src = source(&[
            include_str!("../../shaders/params.wgsl"),
            include_str!("../../shaders/grid.wgsl"),
            include_str!("../../shaders/sph_forces.wgsl"),
        ]);
        let prologue = gpu.kernel("sph_forces.prologue", &src, "prologue", &SLOTS)?;
        let forces = gpu.kernel("sph_forces.forces", &src, "forces", &SLOTS)?;
        let p = particles;
        let buffers = [
            sph_uniform,
            grid_info,
            cell_start,
            sorted,
            &p.r,
            &p.z,
            &p.vr,
            &p.vz,
            &p.rho,
            &p.p,
            &p.s_rr,
            &p.s_zz,
            &p.s_rz,
            &p.s_tt,
            &p.sound,
            &p.m_tilde,
            &p.stress_rho2,
            &p.art_stress,
            &p.ar,
            &p.az,
            &p.de_visc,
            &p.mu_visc,
        ];
        Ok(SphForcesPass {
            prologue_bind: prologue.bind(gpu, &buffers),
            forces_bind: forces.bind(gpu, &buffers),
            prologue,
            forces,
            n: p.len as u32,
        })
    }

    pub fn record(&self, pass: &mut wgpu::ComputePass) {
        self.prologue.dispatch(pass, &self.prologue_bind, self.n);
        self.forces.dispatch(pass, &self.forces_bind, self.n);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::neighbours::CellGrid;
    use crate::gpu::concrete::tests::{field_error, smoke, SMOKE_STEPS};
    use crate::gpu::params::SphUniform;
    use crate::gpu::{run_once, test_gpu};

    /// The CPU grid as the GPU stores it: GridInfo (shaders/grid.wgsl; the bound keys unused),
    /// cell_start and sorted.
    fn upload_grid(gpu: &Gpu, g: &CellGrid) -> [wgpu::Buffer; 3] {
        let cells = g.n_r * g.n_z;
        let info = [
            0,
            0,
            0,
            g.n_r,
            g.n_z,
            g.cell.to_bits(),
            g.z0.to_bits(),
            cells,
            cells,
            0,
        ];
        [
            gpu.buffer("grid info", &info),
            gpu.buffer("cell_start", &g.cell_start),
            gpu.buffer("sorted", &g.sorted),
        ]
    }

    /// One sph_forces pass agrees with cpu::sph_forces::run on the smoke state.
    fn compare(overrides: &[String]) {
        let gpu = test_gpu();
        let sim = smoke(SMOKE_STEPS, overrides);
        let sph = sim.sph.expect("smoke has a target");
        let art_on = sph.art_stress_eps > 0.0;
        let mut cpu = sim.particles.clone();
        crate::cpu::sph_forces::run(&mut cpu, &sim.grid, &sph);

        // The GPU starts from poisoned outputs, so whatever it does not write shows.
        let mut start = sim.particles.clone();
        for v in [
            &mut start.ar,
            &mut start.az,
            &mut start.de_visc,
            &mut start.mu_visc,
        ] {
            v.fill(f32::NAN);
        }
        start.stress_rho2.fill([f32::NAN; 3]);
        start.art_stress.fill([f32::NAN; 3]);
        let gp = GpuParticles::upload(&gpu, &start);
        let [info, cell_start, sorted] = upload_grid(&gpu, &sim.grid);
        let uniform = gpu.uniform("sph", &SphUniform::new(&sph, gp.len));
        let pass = SphForcesPass::new(&gpu, &gp, &info, &cell_start, &sorted, &uniform).unwrap();
        run_once(&gpu, |p| pass.record(p)).unwrap();
        let mut back = start.clone();
        gp.download(&gpu, &mut back).unwrap();

        let heated = cpu.de_visc.iter().filter(|&&x| x != 0.0).count();
        let tensile = cpu
            .art_stress
            .iter()
            .filter(|a| a.iter().any(|&x| x != 0.0))
            .count();
        eprintln!("sph_forces (art stress {art_on}): {heated} heated, {tensile} with R ≠ 0");
        assert!(heated > 0, "no viscosity in the smoke state");
        assert!(
            !art_on || tensile > 0,
            "no artificial stress in the smoke state"
        );

        let col = |v: &[[f32; 3]], k: usize| -> Vec<f32> { v.iter().map(|a| a[k]).collect() };
        let mut fields = vec![
            ("ar", back.ar.clone(), cpu.ar.clone()),
            ("az", back.az.clone(), cpu.az.clone()),
            ("de_visc", back.de_visc.clone(), cpu.de_visc.clone()),
            ("mu_visc", back.mu_visc.clone(), cpu.mu_visc.clone()),
        ];
        for k in 0..3 {
            fields.push((
                "stress_rho2",
                col(&back.stress_rho2, k),
                col(&cpu.stress_rho2, k),
            ));
            if art_on {
                fields.push((
                    "art_stress",
                    col(&back.art_stress, k),
                    col(&cpu.art_stress, k),
                ));
            }
        }
        for (name, a, b) in &fields {
            let e = field_error(a, b);
            eprintln!("sph_forces {name}: relative error {e:e}");
            assert!(e <= 1.0e-5, "{name}: relative error {e:e}");
        }
    }

    #[test]
    fn sph_forces_match_cpu() {
        compare(&[]);
    }

    #[test]
    fn sph_forces_with_artificial_stress_match_cpu() {
        compare(&["target.artificial_stress=true".into()]);
    }
}
