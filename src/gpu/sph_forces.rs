//! `sph_forces` on the GPU (shaders/sph_forces.wgsl); CPU twin `cpu::sph_forces::run`.

use super::neighbours::GpuGrid;
use super::shader::Program;
use super::state::GpuParticles;
use super::timestep::DtSlots;
use super::walls::WallBuffers;
use super::{Gpu, GpuError, Kernel};
use crate::state::SphParams;

/// Particle accelerations: `forces` gathers over the grid's neighbours and axis ghosts what
/// `concrete` packed (`ConcretePass::pairs`, and art_stress when the artificial stress is on)
/// and writes ar, az, de_visc, mu_visc and de_work (fixed particles included, as on the CPU),
/// and folds each particle's stable step into a slot of the clock's running minima (a bind
/// group for each).
pub struct SphForcesPass {
    forces: Kernel,
    binds: [wgpu::BindGroup; 2],
    n: u32,
}

impl SphForcesPass {
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        gpu: &Gpu,
        particles: &GpuParticles,
        pairs: &[wgpu::Buffer; 2],
        grid: &GpuGrid,
        sph_uniform: &wgpu::Buffer,
        clock: &wgpu::Buffer,
        slots: &DtSlots,
        params: &SphParams,
        walls: &WallBuffers,
    ) -> Result<SphForcesPass, GpuError> {
        let constants = [
            (
                "ART_STRESS",
                f64::from(u8::from(params.art_stress_eps > 0.0)),
            ),
            ("BALSARA", f64::from(u8::from(params.balsara))),
            (
                "RECONSTRUCT",
                f64::from(u8::from(params.reconstruct_viscosity)),
            ),
            ("IMAGES", f64::from(u8::from(walls.images))),
        ];
        let forces = gpu.kernel(Program::SphForces, "forces", &constants)?;
        let p = particles;
        let own = [
            ("u", sph_uniform),
            ("p", &p.p),
            ("s_tt", &p.s_tt),
            ("hoop_weight", &p.hoop_weight),
            ("art_stress", &p.art_stress),
            ("pair_s", &pairs[0]),
            ("pair_c", &pairs[1]),
            ("ar", &p.ar),
            ("az", &p.az),
            ("de_visc", &p.de_visc),
            ("mu_visc", &p.mu_visc),
            ("de_work", &p.de_work),
            ("clock", clock),
            ("l_visc", &p.l_visc),
            ("walls", &walls.walls),
            ("wall_force", &walls.wall_force),
        ];
        let buffers = [&grid.walk_bindings(&grid.kin)[..], &own].concat();
        let bind = |slot: u32| {
            let with_slot = [&buffers[..], &[("fold_slot", slots.get(slot))]].concat();
            forces.bind(gpu, &with_slot)
        };
        Ok(SphForcesPass {
            binds: [bind(0)?, bind(1)?],
            forces,
            n: p.len as u32,
        })
    }

    /// Record the gather, folding the stable steps into the clock's `slot`.
    pub fn record(&self, pass: &mut wgpu::ComputePass, slot: u32) {
        self.forces
            .dispatch(pass, &self.binds[slot as usize], self.n);
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::gpu::concrete::tests::{field_error, smoke, SMOKE_STEPS};
    use crate::gpu::neighbours::tests::upload_cpu_grid;
    use crate::gpu::params::SphUniform;
    use crate::gpu::{run_once, test_gpu};

    /// What `concrete` leaves for the gather (`ConcretePass::pairs`), from the CPU prologue's
    /// stress_rho2 in `p`.
    pub(crate) fn pairs(gpu: &Gpu, p: &crate::state::Particles) -> [wgpu::Buffer; 2] {
        let s: Vec<[f32; 4]> = (0..p.len())
            .map(|j| {
                let [a, b, c] = p.stress_rho2[j];
                [a, b, c, p.m_tilde[j]]
            })
            .collect();
        let c: Vec<[f32; 4]> = (0..p.len())
            .map(|j| [p.sound[j], p.rho[j], p.visc_switch[j], 0.0])
            .collect();
        [gpu.buffer("pair_s", &s), gpu.buffer("pair_c", &c)]
    }

    /// One sph_forces pass agrees with cpu::sph_forces::run on the smoke state, given what
    /// the CPU's prologue makes of it.
    fn compare(overrides: &[String], lists: bool) {
        let gpu = test_gpu();
        let sim = smoke(SMOKE_STEPS, overrides);
        let sph = sim.sph.expect("smoke has a target");
        let art_on = sph.art_stress_eps > 0.0;
        let mut cpu = sim.particles.clone();
        crate::cpu::sph_forces::run(&mut cpu, &sim.grid, &sph, None);

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
        crate::cpu::sph_forces::prologue(&mut start, &sph);
        let pairs = pairs(&gpu, &start);
        let gp = GpuParticles::upload(&gpu, &start);
        let uniform = gpu.uniform("sph", &SphUniform::new(&sph, gp.len));
        let grid = upload_cpu_grid(&gpu, &start, &uniform, &sim.grid, sph.h, lists);
        let clock = gpu.buffer("clock", &crate::gpu::timestep::clock_words(sim.dt, false));
        let slots = crate::gpu::timestep::DtSlots::new(&gpu);
        let pass = SphForcesPass::new(
            &gpu,
            &gp,
            &pairs,
            &grid,
            &uniform,
            &clock,
            &slots,
            &sph,
            &crate::gpu::sph_rates::tests::no_walls(&gpu),
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

        let fields = [
            ("ar", &back.ar, &cpu.ar),
            ("az", &back.az, &cpu.az),
            ("de_visc", &back.de_visc, &cpu.de_visc),
            ("de_work", &back.de_work, &cpu.de_work),
            ("mu_visc", &back.mu_visc, &cpu.mu_visc),
        ];
        for (name, a, b) in fields {
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

    /// With the reconstructed viscosity, which must move the CPU's heating on the smoke state,
    /// or the comparison would not test it.
    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn sph_forces_with_reconstructed_viscosity_match_cpu() {
        let set = ["target.viscosity_jump=\"reconstructed\"".to_string()];
        let sim = smoke(SMOKE_STEPS, &set);
        let sph = sim.sph.expect("smoke has a target");
        let raw = SphParams {
            reconstruct_viscosity: false,
            ..sph
        };
        let (mut with, mut without) = (sim.particles.clone(), sim.particles.clone());
        crate::cpu::sph_forces::run(&mut with, &sim.grid, &sph, None);
        crate::cpu::sph_forces::run(&mut without, &sim.grid, &raw, None);
        let change = field_error(&with.de_visc, &without.de_visc);
        eprintln!("reconstructed: de_visc moves by {change:e} of its scale");
        assert!(change > 1.0e-3, "the reconstruction changes nothing here");
        compare(&set, true);
    }
}
