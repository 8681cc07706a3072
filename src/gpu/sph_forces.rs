//! `sph_forces` on the GPU (shaders/sph_forces.wgsl); CPU twin `cpu::sph_forces::run`.

use super::neighbours::GpuGrid;
use super::shader::Program;
use super::state::GpuParticles;
use super::timestep::DtSlots;
use super::{Gpu, GpuError, Kernel};

/// Particle accelerations: `prologue` writes stress_rho2 (and art_stress when the artificial
/// stress is on) from p, rho and the deviator; `forces` gathers over the grid's neighbours
/// and axis ghosts and writes ar, az, de_visc, mu_visc and de_work (fixed particles included, as on
/// the CPU), and folds each particle's stable step into a slot of the clock's running minima (a
/// bind group for each).
pub struct SphForcesPass {
    prologue: Kernel,
    forces: Kernel,
    prologue_bind: wgpu::BindGroup,
    forces_binds: [wgpu::BindGroup; 2],
    n: u32,
    // The packed neighbour data (pair_s, pair_c), kept alive for the bind groups.
    _pairs: [wgpu::Buffer; 2],
}

impl SphForcesPass {
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        gpu: &Gpu,
        particles: &GpuParticles,
        grid: &GpuGrid,
        sph_uniform: &wgpu::Buffer,
        clock: &wgpu::Buffer,
        slots: &DtSlots,
        art_stress: bool,
        balsara: bool,
    ) -> Result<SphForcesPass, GpuError> {
        let art = [
            ("ART_STRESS", f64::from(u8::from(art_stress))),
            ("BALSARA", f64::from(u8::from(balsara))),
        ];
        let prologue = gpu.kernel(Program::SphForces, "prologue", &art)?;
        let forces = gpu.kernel(Program::SphForces, "forces", &art)?;
        let p = particles;
        let pair_s = gpu.zeros::<[f32; 4]>("sph_forces pair_s", p.len);
        let pair_c = gpu.zeros::<[f32; 4]>("sph_forces pair_c", p.len);
        let own = [
            ("u", sph_uniform),
            ("rho", &p.rho),
            ("p", &p.p),
            ("s_rr", &p.s_rr),
            ("s_zz", &p.s_zz),
            ("s_rz", &p.s_rz),
            ("s_tt", &p.s_tt),
            ("sound", &p.sound),
            ("m_tilde", &p.m_tilde),
            ("visc_switch", &p.visc_switch),
            ("hoop_weight", &p.hoop_weight),
            ("stress_rho2", &p.stress_rho2),
            ("art_stress", &p.art_stress),
            ("pair_s", &pair_s),
            ("pair_c", &pair_c),
            ("ar", &p.ar),
            ("az", &p.az),
            ("de_visc", &p.de_visc),
            ("mu_visc", &p.mu_visc),
            ("de_work", &p.de_work),
            ("clock", clock),
        ];
        let buffers = [&grid.walk_bindings(&grid.kin)[..], &own].concat();
        let with_slot = |slot: u32| [&buffers[..], &[("fold_slot", slots.get(slot))]].concat();
        Ok(SphForcesPass {
            prologue_bind: prologue.bind(gpu, &with_slot(0))?,
            forces_binds: [
                forces.bind(gpu, &with_slot(0))?,
                forces.bind(gpu, &with_slot(1))?,
            ],
            prologue,
            forces,
            n: p.len as u32,
            _pairs: [pair_s, pair_c],
        })
    }

    /// Record the prologue and the gather, folding the stable steps into the clock's `slot`.
    pub fn record(&self, pass: &mut wgpu::ComputePass, slot: u32) {
        self.prologue.dispatch(pass, &self.prologue_bind, self.n);
        self.forces
            .dispatch(pass, &self.forces_binds[slot as usize], self.n);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::concrete::tests::{field_error, smoke, SMOKE_STEPS};
    use crate::gpu::neighbours::tests::upload_cpu_grid;
    use crate::gpu::params::SphUniform;
    use crate::gpu::{run_once, test_gpu};

    /// One sph_forces pass agrees with cpu::sph_forces::run on the smoke state.
    fn compare(overrides: &[String], lists: bool) {
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
            &mut start.de_work,
            &mut start.mu_visc,
        ] {
            v.fill(f32::NAN);
        }
        start.stress_rho2.fill([f32::NAN; 3]);
        start.art_stress.fill([f32::NAN; 3]);
        let gp = GpuParticles::upload(&gpu, &start);
        let uniform = gpu.uniform("sph", &SphUniform::new(&sph, gp.len));
        let grid = upload_cpu_grid(&gpu, &start, &uniform, &sim.grid, lists);
        let clock = gpu.buffer("clock", &crate::gpu::timestep::clock_words(sim.dt, false));
        let slots = crate::gpu::timestep::DtSlots::new(&gpu);
        let pass = SphForcesPass::new(
            &gpu,
            &gp,
            &grid,
            &uniform,
            &clock,
            &slots,
            art_on,
            sph.balsara,
        )
        .unwrap();
        run_once(&gpu, |p| pass.record(p, 1)).unwrap();
        let mut back = start.clone();
        gp.download(&gpu, &mut back).unwrap();

        // The particles' stable steps folded into slot 1 (and nothing into slot 0): the CPU's
        // least, from the GPU's own μ_max. h/(c + |v| + …): a handful of roundings, and the
        // driver may use a faster division.
        let words: Vec<u32> = gpu.read(&clock, 6).unwrap();
        assert_eq!(&words[2..4], &[f32::MAX.to_bits(); 2]);
        assert_eq!(words[5], f32::MAX.to_bits());
        let folded = f32::from_bits(words[4]);
        let least = crate::cpu::timestep::particle_dt(&back, &sph);
        assert!(
            ((folded - least) / least).abs() < 1.0e-5,
            "folded {folded:e} against {least:e}"
        );

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
            ("de_work", back.de_work.clone(), cpu.de_work.clone()),
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
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn sph_forces_match_cpu() {
        compare(&[], true);
    }

    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn sph_forces_on_overflowed_lists_match_cpu() {
        compare(&[], false);
    }

    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn sph_forces_with_artificial_stress_match_cpu() {
        compare(&["target.artificial_stress=true".into()], true);
    }

    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn sph_forces_with_balsara_switch_match_cpu() {
        compare(&["target.viscosity_switch=\"balsara\"".into()], true);
    }
}
