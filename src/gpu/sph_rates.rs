//! `sph_rates` on the GPU (shaders/sph_rates.wgsl); CPU twin `cpu::sph_rates::run`.

use super::neighbours::GpuGrid;
use super::shader::Program;
use super::sph_filter::SphFilterPass;
use super::state::GpuParticles;
use super::walls::WallBuffers;
use super::{Gpu, GpuError, Kernel};
use crate::state::SphParams;

/// Velocity gradients and density rates: `gradient` gathers over the grid's neighbours and axis
/// ghosts (with what the neighbours pass packed of them this step) and writes l_rr, l_rz,
/// l_zr, l_zz, drho and hoop_weight, visc_switch when the Balsara switch is on and l_visc with
/// the reconstructed viscosity. With the velocity filter,
/// `gradient` runs twice: first on the particles' velocities, then, after `sph_filter` has
/// written the filtered velocities in kin's layout, on those.
pub struct SphRatesPass {
    gradient: Kernel,
    bind: wgpu::BindGroup,
    filter: Option<Filter>,
    n: u32,
}

/// The velocity filter, and the rates' bindings with the filtered kinematics in kin's place.
struct Filter {
    pass: SphFilterPass,
    rates_bind: wgpu::BindGroup,
}

impl SphRatesPass {
    pub fn new(
        gpu: &Gpu,
        particles: &GpuParticles,
        grid: &GpuGrid,
        sph_uniform: &wgpu::Buffer,
        params: &SphParams,
        walls: &WallBuffers,
    ) -> Result<SphRatesPass, GpuError> {
        let switch = [
            ("BALSARA", f64::from(u8::from(params.balsara))),
            ("CONJUGATE", f64::from(u8::from(params.conjugate_gradient))),
            (
                "RECONSTRUCT",
                f64::from(u8::from(params.reconstruct_viscosity)),
            ),
            ("IMAGES", f64::from(u8::from(walls.images))),
        ];
        let gradient = gpu.kernel(Program::SphRates, "gradient", &switch)?;
        let p = particles;
        let rates_bind = |kin: &wgpu::Buffer| {
            let own = [
                ("u", sph_uniform),
                ("rho", &p.rho),
                ("sound", &p.sound),
                ("rate_pair", &grid.rate_pair),
                ("l_rr", &p.l_rr),
                ("l_rz", &p.l_rz),
                ("l_zr", &p.l_zr),
                ("l_zz", &p.l_zz),
                ("drho", &p.drho),
                ("visc_switch", &p.visc_switch),
                ("hoop_weight", &p.hoop_weight),
                ("l_visc", &p.l_visc),
                ("walls", &walls.walls),
            ];
            gradient.bind(gpu, &[&grid.walk_bindings(kin)[..], &own].concat())
        };
        let bind = rates_bind(&grid.kin)?;
        let filter = if params.velocity_filter {
            let pass = SphFilterPass::new(gpu, particles, grid, sph_uniform)?;
            Some(Filter {
                rates_bind: rates_bind(pass.kin_filtered())?,
                pass,
            })
        } else {
            None
        };
        Ok(SphRatesPass {
            gradient,
            bind,
            filter,
            n: p.len as u32,
        })
    }

    pub fn record(&self, pass: &mut wgpu::ComputePass) {
        self.gradient.dispatch(pass, &self.bind, self.n);
        if let Some(f) = &self.filter {
            f.pass.record(pass);
            self.gradient.dispatch(pass, &f.rates_bind, self.n);
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::gpu::concrete::tests::{field_error, smoke, smoke_run, SMOKE_STEPS};
    use crate::gpu::neighbours::tests::upload_cpu_grid;
    use crate::gpu::params::SphUniform;
    use crate::gpu::{run_once, test_gpu};

    /// The placeholders of a scene without wall images.
    pub(crate) fn no_walls(gpu: &Gpu) -> WallBuffers {
        WallBuffers::new(gpu, 0, false).unwrap()
    }

    /// One sph_rates pass agrees with cpu::sph_rates::run on the smoke state (a crater, the
    /// axis, free surfaces where the correction is skipped), walking the neighbour lists or,
    /// where they overflowed, the grid; with the Balsara switch, its factors too.
    fn compare(overrides: &[String], lists: bool) {
        let gpu = test_gpu();
        let sim = smoke(SMOKE_STEPS, overrides);
        let sph = sim.sph.expect("smoke has a target");
        let mut cpu = sim.particles.clone();
        crate::cpu::sph_rates::run(&mut cpu, &sim.grid, &sph, None);

        // The GPU starts from poisoned outputs, so whatever it does not write shows; the areas
        // are the neighbours pass's (`pack`), here the CPU's at the same positions.
        let mut start = sim.particles.clone();
        start.m_tilde.clone_from(&cpu.m_tilde);
        start.area.clone_from(&cpu.area);
        for v in [
            &mut start.l_rr,
            &mut start.l_rz,
            &mut start.l_zr,
            &mut start.l_zz,
            &mut start.drho,
            &mut start.hoop_weight,
        ] {
            v.fill(f32::NAN);
        }
        if sph.balsara {
            start.visc_switch.fill(f32::NAN);
        }
        if sph.reconstruct_viscosity {
            start.l_visc.fill([f32::NAN; 4]);
        }
        let gp = GpuParticles::upload(&gpu, &start);
        let uniform = gpu.uniform("sph", &SphUniform::new(&sph, gp.len));
        let grid = upload_cpu_grid(&gpu, &start, &uniform, &sim.grid, sph.h, lists);
        let pass = SphRatesPass::new(&gpu, &gp, &grid, &uniform, &sph, &no_walls(&gpu)).unwrap();
        run_once(&gpu, |p| pass.record(p)).unwrap();
        let mut back = start.clone();
        gp.download(&gpu, &mut back).unwrap();

        let moving = cpu.drho.iter().filter(|&&x| x != 0.0).count();
        eprintln!("sph_rates: {moving} of {} particles compressing", cpu.len());
        assert!(moving > 0, "the smoke state is at rest");
        // Sums of ~30 products each rounded once, the same terms in the same order; the
        // driver may fuse multiply-adds (gpu-notes.md), so a few ulp of the field's scale.
        // drho is ρ times a sum of terms that cancel at rest: compared on the same scale.
        let e = field_error(&back.hoop_weight, &cpu.hoop_weight);
        eprintln!("sph_rates hoop_weight: relative error {e:e}");
        assert!(e <= 1.0e-5, "hoop_weight: relative error {e:e}");
        check_gradients(&format!("lists {lists}"), &back, &cpu);
        // A ratio of sums already compared; 1 exactly when the switch is off.
        let e = field_error(&back.visc_switch, &cpu.visc_switch);
        eprintln!("sph_rates visc_switch: relative error {e:e}");
        assert!(e <= 1.0e-4, "visc_switch: relative error {e:e}");
        if sph.balsara {
            let partial = cpu.visc_switch.iter().filter(|&&f| f > 0.05 && f < 0.95);
            assert!(partial.count() > 0, "no particle with a partial switch");
        } else {
            assert!(back.visc_switch.iter().all(|&f| f == 1.0));
        }
        if sph.reconstruct_viscosity {
            assert_eq!(cpu.l_visc.len(), cpu.len());
            for k in 0..4 {
                let column = |p: &crate::state::Particles| -> Vec<f32> {
                    p.l_visc.iter().map(|l| l[k]).collect()
                };
                let e = field_error(&column(&back), &column(&cpu));
                eprintln!("sph_rates l_visc[{k}]: relative error {e:e}");
                assert!(e <= 1.0e-5, "l_visc[{k}]: relative error {e:e}");
            }
        }
    }

    /// The velocity gradients and density rates of `gpu` against `cpu`, to 1e-5 of each
    /// field's scale.
    pub(crate) fn check_gradients(
        label: &str,
        gpu: &crate::state::Particles,
        cpu: &crate::state::Particles,
    ) {
        for (name, a, b) in [
            ("l_rr", &gpu.l_rr, &cpu.l_rr),
            ("l_rz", &gpu.l_rz, &cpu.l_rz),
            ("l_zr", &gpu.l_zr, &cpu.l_zr),
            ("l_zz", &gpu.l_zz, &cpu.l_zz),
            ("drho", &gpu.drho, &cpu.drho),
        ] {
            let e = field_error(a, b);
            eprintln!("sph_rates ({label}) {name}: relative error {e:e}");
            assert!(e <= 1.0e-5, "{label} {name}: relative error {e:e}");
        }
    }

    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn sph_rates_match_cpu() {
        compare(&[], true);
    }

    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn sph_rates_on_overflowed_lists_match_cpu() {
        compare(&[], false);
    }

    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn sph_rates_with_balsara_switch_match_cpu() {
        compare(&["target.viscosity_switch=\"balsara\"".into()], true);
    }

    /// With the reconstructed viscosity, l_visc: a second, corrected gather beside the
    /// conjugate gradient (the default), L itself beside the corrected one.
    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn sph_rates_with_reconstructed_viscosity_match_cpu() {
        let jump = "target.viscosity_jump=\"reconstructed\"".to_string();
        compare(std::slice::from_ref(&jump), true);
        compare(
            &[jump, "target.velocity_gradient=\"corrected\"".into()],
            false,
        );
    }

    /// With the option `set` (scene overrides), on the lists and on the grid; the option must
    /// change the CPU's gradients on the smoke state, or the comparison would not test it.
    /// `plain` turns it off again in the SphParams the scene gave, which must have it on.
    fn compare_option(set: &[&str], plain: impl Fn(&mut SphParams) -> bool) {
        let overrides: Vec<String> = set.iter().map(|s| s.to_string()).collect();
        let sim = smoke(SMOKE_STEPS, &overrides);
        let sph = sim.sph.expect("smoke has a target");
        let mut off = sph;
        assert!(plain(&mut off), "{set:?} is not on");
        let (mut without, mut with) = (sim.particles.clone(), sim.particles.clone());
        crate::cpu::sph_rates::run(&mut without, &sim.grid, &off, None);
        crate::cpu::sph_rates::run(&mut with, &sim.grid, &sph, None);
        let change = field_error(&with.l_zz, &without.l_zz);
        eprintln!("{set:?}: L_zz moves by {change:e} of its scale");
        assert!(change > 1.0e-3, "{set:?} changes nothing here");
        compare(&overrides, true);
        compare(&overrides, false);
    }

    /// With the velocity filter (which takes the corrected gradient): two `gradient`
    /// dispatches around `sph_filter`.
    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn sph_rates_with_velocity_filter_match_cpu() {
        compare_option(
            &[
                "target.velocity_gradient=\"corrected\"",
                "target.velocity_filter=\"linear\"",
            ],
            |p| std::mem::replace(&mut p.velocity_filter, false),
        );
    }

    /// With the corrected gradient: `gradient` without its CONJUGATE branch (the default,
    /// which `sph_rates_match_cpu` compares, takes it).
    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn sph_rates_with_corrected_gradient_match_cpu() {
        compare_option(&["target.velocity_gradient=\"corrected\""], |p| {
            !std::mem::replace(&mut p.conjugate_gradient, true)
        });
    }

    /// Lists built with a skin and then used after the particles have moved (less than half
    /// the skin) still give the CPU's rates at the new positions, and the displacement watch
    /// measures the move.
    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn sph_rates_on_stale_lists_match_cpu() {
        use crate::gpu::integrate::{
            Accumulators, IntegratePass, TargetBindings, STATUS_CLEAR, STATUS_WORDS,
        };
        use crate::gpu::neighbours::{capacity, NeighboursPass, MOVED2_OFFSET};
        use crate::gpu::params::StepUniform;
        use crate::gpu::state::{GpuElements, GpuNodes};
        use crate::gpu::timestep;
        let gpu = test_gpu();
        let mut run = smoke_run(SMOKE_STEPS, &[]);
        let sim = run.model().unwrap();
        let sph = sim.sph.expect("smoke has a target");
        let support = sph.kernel.support();
        let skin = 0.5;
        let built = sim.particles.clone();
        let gp = GpuParticles::upload(&gpu, &built);
        let uniform = gpu.uniform("sph", &SphUniform::new(&sph, gp.len));
        let cap = capacity(&built.r, &built.z, support);
        let (neighbours, grid) =
            NeighboursPass::new(&gpu, &gp, &uniform, cap, support * (1.0 + skin)).unwrap();
        run_once(&gpu, |p| neighbours.record(p, true)).unwrap();

        // Move on, on the CPU, while every particle stays within the lists' slack.
        let slack = 0.5 * skin * support;
        let moved = |p: &crate::state::Particles| {
            (0..p.len())
                .map(|i| (p.r[i] - built.r[i]).hypot(p.z[i] - built.z[i]))
                .fold(0.0f32, f32::max)
        };
        let mut steps = 0;
        while moved(&run.model().unwrap().particles) < 0.5 * slack && steps < 200 {
            run.step().unwrap();
            steps += 1;
        }
        let sim = run.into_model().unwrap();
        let now = sim.particles.clone();
        let d = moved(&now);
        eprintln!("stale lists: {steps} steps later, largest move {d:e} m, slack {slack:e} m");
        assert!(
            d > 0.0 && d < slack,
            "the test must move the particles, within the slack"
        );

        let mut cpu = now.clone();
        crate::cpu::sph_rates::run(&mut cpu, &sim.grid, &sph, None);
        gp.write(&gpu, &now);
        let pass = SphRatesPass::new(&gpu, &gp, &grid, &uniform, &sph, &no_walls(&gpu)).unwrap();
        // The displacement watch is the integration's: one of Δt = 0 leaves every particle
        // where it is.
        let step = gpu.uniform(
            "step",
            &StepUniform {
                n_particles: gp.len as u32,
                escape: f32::MAX,
                ..Default::default()
            },
        );
        let clock = gpu.buffer("clock", &timestep::clock_words(0.0, false));
        let status = gpu.buffer("status", &[STATUS_CLEAR; STATUS_WORDS]);
        let slots = timestep::DtSlots::new(&gpu);
        let nodes = GpuNodes::upload(&gpu, &sim.projectile.nodes);
        let elements = GpuElements::upload(&gpu, &sim.projectile.elements);
        let acc = Accumulators::new(&gpu, gp.len, nodes.len);
        let watch = IntegratePass::new(
            &gpu,
            &step,
            &clock,
            &status,
            &slots,
            Some(TargetBindings {
                particles: &gp,
                x_build: neighbours.x_build(),
                grid_info: &grid.info,
                contact: None,
            }),
            &nodes,
            &elements,
            &acc,
        )
        .unwrap();
        run_once(&gpu, |p| {
            neighbours.record(p, false);
            watch.record(p, timestep::DT_FROM_CLOCK);
            pass.record(p);
        })
        .unwrap();
        let mut back = now.clone();
        gp.download(&gpu, &mut back).unwrap();
        let info: Vec<u32> = gpu
            .read(&grid.info, (MOVED2_OFFSET / 4 + 1) as usize)
            .unwrap();
        let watched = f32::from_bits(info[(MOVED2_OFFSET / 4) as usize]).sqrt();
        assert!(
            (watched - d).abs() <= 1e-5 * d,
            "watch {watched:e} vs {d:e}"
        );
        // The same neighbours in another order (the lists keep the order of the build).
        check_gradients("stale lists", &back, &cpu);
    }
}
