//! `concrete` on the GPU (shaders/concrete.wgsl, with the HJC law in shaders/hjc.wgsl and the
//! deviatoric helpers in shaders/deviator.wgsl); CPU twin `cpu::concrete::run` with
//! `materials::hjc` and `cpu::deviator`.

use super::shader::Program;
use super::state::GpuParticles;
use super::{Gpu, GpuError, Kernel};
use crate::state::SphParams;

/// The HJC update of every particle over the clock's Δt: reads r, vr, the velocity gradient,
/// drho, de_visc and (with the conjugate gradient) hoop_weight; advances rho, energy, p, the
/// deviator, damage, mu_max, eps_p and sound; and writes what `sph_forces` reads of the new
/// state (`cpu::sph_forces::prologue`): stress_rho2, art_stress (when it is on), and `pairs`.
pub struct ConcretePass {
    kernel: Kernel,
    bind: wgpu::BindGroup,
    n: u32,
    /// What a neighbour contributes to the gather, packed for one load each:
    /// ((σ_rr, σ_zz, σ_rz)/ρ², m̃) and (c, ρ, factor on Π, 0).
    pub pairs: [wgpu::Buffer; 2],
}

impl ConcretePass {
    pub fn new(
        gpu: &Gpu,
        particles: &GpuParticles,
        sph_uniform: &wgpu::Buffer,
        clock: &wgpu::Buffer,
        params: &SphParams,
    ) -> Result<ConcretePass, GpuError> {
        let constants = [
            ("CONJUGATE", f64::from(u8::from(params.conjugate_gradient))),
            (
                "ART_STRESS",
                f64::from(u8::from(params.art_stress_eps > 0.0)),
            ),
        ];
        let kernel = gpu.kernel(Program::Concrete, "main", &constants)?;
        let p = particles;
        let pairs = ["pair_s", "pair_c"].map(|name| gpu.zeros::<[f32; 4]>(name, p.len));
        let bind = kernel.bind(
            gpu,
            &[
                ("u", sph_uniform),
                ("clock", clock),
                ("r", &p.r),
                ("vr", &p.vr),
                ("l_rr", &p.l_rr),
                ("l_rz", &p.l_rz),
                ("l_zr", &p.l_zr),
                ("l_zz", &p.l_zz),
                ("drho", &p.drho),
                ("de_visc", &p.de_visc),
                ("hoop_weight", &p.hoop_weight),
                ("rho", &p.rho),
                ("strain_energy", &p.strain_energy),
                ("p", &p.p),
                ("s_rr", &p.s_rr),
                ("s_zz", &p.s_zz),
                ("s_rz", &p.s_rz),
                ("s_tt", &p.s_tt),
                ("damage", &p.damage),
                ("mu_max", &p.mu_max),
                ("eps_p", &p.eps_p),
                ("sound", &p.sound),
                ("m_tilde", &p.m_tilde),
                ("visc_switch", &p.visc_switch),
                ("stress_rho2", &p.stress_rho2),
                ("art_stress", &p.art_stress),
                ("pair_s", &pairs[0]),
                ("pair_c", &pairs[1]),
            ],
        )?;
        Ok(ConcretePass {
            kernel,
            bind,
            n: p.len as u32,
            pairs,
        })
    }

    pub fn record(&self, pass: &mut wgpu::ComputePass) {
        self.kernel.dispatch(pass, &self.bind, self.n);
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::gpu::params::SphUniform;
    use crate::gpu::shader::{self, hjc_parts, Part};
    use crate::gpu::{run_once, test_gpu};
    use crate::materials::hjc::{self, Hjc};
    use crate::solver::{Model, Simulation};

    /// Steps of the smoke scene before a comparison: the nose reaches the first particles
    /// after ~150 steps, so at 400 (t ≈ 19 µs, 5 mm deep) particles are crushed, yielding and
    /// damaged, and the viscosity acts.
    pub(crate) const SMOKE_STEPS: usize = 400;

    /// The smoke scene with `overrides` on the CPU, after `steps` steps.
    pub(crate) fn smoke_run(steps: usize, overrides: &[String]) -> Simulation {
        let scene = crate::scene::load(std::path::Path::new("cases/smoke.toml"), overrides)
            .expect("smoke case");
        let mut sim = Simulation::new(&scene).expect("smoke builds");
        for _ in 0..steps {
            sim.step().expect("smoke steps");
        }
        sim
    }

    /// The state of [`smoke_run`].
    pub(crate) fn smoke(steps: usize, overrides: &[String]) -> Model {
        smoke_run(steps, overrides)
            .into_model()
            .expect("smoke's state")
    }

    /// Largest |a − b| relative to the largest |b| of the field; infinite where a value is
    /// NaN on one side only (f32::max would skip it).
    pub(crate) fn field_error(a: &[f32], b: &[f32]) -> f32 {
        assert_eq!(a.len(), b.len());
        let scale = b
            .iter()
            .fold(0.0f32, |m, x| m.max(x.abs()))
            .max(f32::MIN_POSITIVE);
        a.iter()
            .zip(b)
            .fold(0.0f32, |m, (x, y)| m.max(difference(*x, *y)))
            / scale
    }

    /// |x − y|, 0 for equal values (infinities included), infinite when only one is NaN.
    fn difference(x: f32, y: f32) -> f32 {
        if x == y || (x.is_nan() && y.is_nan()) {
            0.0
        } else {
            let d = (x - y).abs();
            if d.is_nan() {
                f32::INFINITY
            } else {
                d
            }
        }
    }

    /// Largest error of the increments `a − start` against `b − start`, relative to the largest
    /// |b − start|, less two ulps of the stored value: each side rounds `start + increment`
    /// once, so a one-ulp difference of the sum is no error of the increment.
    pub(crate) fn increment_error(a: &[f32], b: &[f32], start: &[f32]) -> f32 {
        let scale = b
            .iter()
            .zip(start)
            .fold(0.0f32, |m, (y, s)| m.max((y - s).abs()))
            .max(f32::MIN_POSITIVE);
        a.iter()
            .zip(b)
            .fold(0.0f32, |m, (x, y)| {
                m.max(difference(*x, *y) - 2.0 * f32::EPSILON * y.abs())
            })
            .max(0.0)
            / scale
    }

    /// Evaluates the law of hjc.wgsl on a list of cases, 8 inputs and 8 outputs each:
    /// (μ, μ_max, D, ε̇, p, Δε_p, Δμ_p, tangent) → (EOS p, μ_max, Δμ_p, tangent;
    /// σ_y(p, D, ε̇), ΔD(p, Δε_p, Δμ_p, opening Δμ_p), c(tangent), σ_y(EOS p, D, ε̇)), the
    /// tensile strength T_d(ε̇) throughout.
    const LAW_KERNEL: Part = Part {
        file: "(gpu::concrete tests' law kernel)",
        text: r#"
@group(0) @binding(0) var<uniform> u: SphUniform;
@group(0) @binding(1) var<storage, read> cases: array<f32>;
@group(0) @binding(2) var<storage, read_write> out: array<f32>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i >= u.n) { return; }
    let a = 8u * i;
    let t_d = hjc_tensile_strength(u, cases[a + 3u]);
    let eos = hjc_pressure(u, cases[a], cases[a + 1u], cases[a + 2u], t_d);
    out[a] = eos.p;
    out[a + 1u] = eos.mu_max;
    out[a + 2u] = eos.d_mu_p;
    out[a + 3u] = eos.tangent;
    out[a + 4u] = hjc_yield_stress(u, cases[a + 4u], cases[a + 2u], cases[a + 3u], t_d);
    out[a + 5u] = hjc_damage_increment(
        u, cases[a + 4u], t_d, cases[a + 5u], cases[a + 6u], cases[a + 6u],
    );
    out[a + 6u] = hjc_sound_speed(u, cases[a + 7u]);
    out[a + 7u] = hjc_yield_stress(u, eos.p, cases[a + 2u], cases[a + 3u], t_d);
}
"#,
    };

    /// The law kernel is valid WGSL (checked without an adapter).
    #[test]
    fn law_kernel_validates() {
        shader::validate(&hjc_parts(LAW_KERNEL)).unwrap();
    }

    /// The same outputs from materials::hjc.
    fn law_cpu(h: &Hjc, tension: hjc::Tension, c: &[f32; 8]) -> [f32; 8] {
        let [mu, mu_max, d, rate, p, d_eps_p, d_mu_p, tangent] = *c;
        let t_d = hjc::tensile_strength(h, tension, rate);
        let eos = hjc::pressure(h, hjc::lock_strain(h), mu, mu_max, d, t_d);
        [
            eos.p,
            eos.mu_max,
            eos.d_mu_p,
            eos.tangent,
            hjc::yield_stress(h, p, d, rate, t_d),
            hjc::damage_increment(h, tension, p, t_d, d_eps_p, d_mu_p, d_mu_p),
            hjc::sound_speed(h, tangent),
            hjc::yield_stress(h, eos.p, d, rate, t_d),
        ]
    }

    /// Hand-picked states: (μ, μ_max, D) covering the elastic line, tension above and at the
    /// cut-off (intact, half and fully damaged), crushing on loading, unloading and reloading
    /// below μ_max, unloading into the cut-off, the locked dense curve on loading and
    /// unloading, both sides of μ_plock, and extreme strains; paired with (ε̇, p, Δε_p, Δμ_p,
    /// tangent) covering both yield branches, the S_max cap, no rate effect, the tensile floor
    /// and the EF_min floor of the failure strain.
    fn law_cases(mu_plock: f32) -> Vec<[f32; 8]> {
        let eos = [
            (5.0e-4, 0.0, 0.0),
            (-2.0e-4, 0.0, 0.0),
            (-1.0e-3, 0.0, 0.0),
            (-1.0e-3, 0.0, 0.5),
            (-1.0e-3, 0.0, 1.0),
            (0.05, 0.03, 0.0),
            (0.02, 0.0, 0.3),
            (0.045, 0.05, 0.0),
            (0.049, 0.05, 0.7),
            (0.03, 0.05, 0.0),
            (0.03, 0.05, 0.5),
            (0.12, 0.0, 0.0),
            (0.12, 0.2, 0.0),
            (0.15, 0.12, 0.9),
            (mu_plock * 0.999, 0.0, 0.0),
            (mu_plock * 1.001, 0.0, 0.0),
            (-0.9, 0.05, 0.3),
            (3.0, 0.2, 0.3),
            (0.0, 0.0, 0.0),
        ];
        let strength = [
            (100.0, 96.0e6, 0.01, 0.002, 16.0e9),
            (100.0, 0.0, 0.0, 0.0, 85.0e9),
            (100.0, -2.0e6, 0.01, 0.0, 30.0e9),
            (100.0, -5.0e6, 0.01, 0.002, 16.0e9),
            (100.0, 2.4e9, 0.0, 0.001, 70.0e9),
            (0.1, 96.0e6, 0.001, 0.0, 40.0e9),
            (3.0e4, -3.0e6, 0.01, 0.002, 16.0e9),
            (5.0, -1.0e6, 0.0, 0.003, 16.0e9),
            (50.0, -8.0e6, 0.002, 0.0, 16.0e9),
        ];
        let mut cases = Vec::new();
        for (k, &(mu, mu_max, d)) in eos.iter().enumerate() {
            for (m, &(rate, p, dep, dmp, tangent)) in strength.iter().enumerate() {
                // Every strength case against a few EOS states, not the full product.
                if (k + m) % 3 == 0 || m == 0 {
                    cases.push([mu, mu_max, d, rate, p, dep, dmp, tangent]);
                }
            }
        }
        cases
    }

    /// The WGSL HJC functions agree with materials::hjc on hand-picked states, for the
    /// reference set and the f_c rule's 35 MPa set (the smoke target's), with the static
    /// tension and the crack band.
    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn hjc_law_matches_cpu() {
        let gpu = test_gpu();
        let sim = smoke(0, &[]);
        let base = sim.sph.expect("smoke has a target");
        let tensions = [
            hjc::Tension::Static,
            hjc::Tension::CrackBand { band: 0.004 },
        ];
        for (h, tension) in [Hjc::reference_48mpa(), base.concrete]
            .into_iter()
            .flat_map(|h| tensions.map(|t| (h, t)))
        {
            let mut params = base;
            params.concrete = h;
            params.tension = tension;
            let mu_plock = hjc::lock_strain(&h);
            let cases = law_cases(mu_plock);
            let flat: Vec<f32> = cases.iter().flatten().copied().collect();
            let uniform = gpu.uniform("sph", &SphUniform::new(&params, cases.len()));
            let input = gpu.buffer("cases", &flat);
            let output = gpu.zeros::<f32>("out", flat.len());
            let src = shader::source(&hjc_parts(LAW_KERNEL));
            let k = gpu.kernel_from("hjc law", &src, "main", &[]).unwrap();
            let bind = k
                .bind(
                    &gpu,
                    &[("u", &uniform), ("cases", &input), ("out", &output)],
                )
                .unwrap();
            run_once(&gpu, |p| k.dispatch(p, &bind, cases.len() as u32)).unwrap();
            let got: Vec<f32> = gpu.read(&output, flat.len()).unwrap();

            // Scales for the absolute part of the tolerance: pressures are differences of terms
            // of size K·μ (the unloading line p_env − K_unload(m − μ), the cubic), so their
            // round-off is relative to K₁·max(|μ|, μ_max), not to p; the tensile strength
            // branch A(1 + p/T_d)(1 − D) f_c is a difference near the cut-off, so its round-off
            // (T_d's pow within ~2 ulp) is relative to A f_c; the rest are relative.
            // 2e-6: a few f32 ulps (fused multiply-adds, log/pow of the driver within ~2 ulp).
            let names = [
                "p",
                "mu_max",
                "d_mu_p",
                "tangent",
                "yield",
                "d_damage",
                "sound",
                "yield(eos p)",
            ];
            let mut worst = [0.0f32; 8];
            for (c, g) in cases.iter().zip(got.chunks(8)) {
                let want = law_cpu(&h, tension, c);
                let p_scale = h.k1 * c[0].abs().max(c[1]).max(1.0e-4);
                for q in 0..8 {
                    let scale = match q {
                        0 | 7 => p_scale,
                        2 => c[0].abs().max(c[1]).max(mu_plock),
                        4 => want[q].abs().max(h.a * h.fc),
                        _ => want[q].abs(),
                    };
                    let err = (g[q] - want[q]).abs();
                    worst[q] = worst[q].max(err / scale.max(f32::MIN_POSITIVE));
                    assert!(
                        err <= 2.0e-6 * scale,
                        "{} for case {c:?}: GPU {} CPU {} (error {err:e}, scale {scale:e})",
                        names[q],
                        g[q],
                        want[q]
                    );
                }
            }
            eprintln!(
                "hjc law, f_c {:e}, {tension:?}: worst relative errors {names:?} {worst:?}",
                h.fc
            );
        }
    }

    /// Particles on each branch of the law in a CPU-updated state, to show the smoke state
    /// exercises them: (plastic, crushed, locked, in tension, damaged).
    fn branches(
        before: &crate::state::Particles,
        after: &crate::state::Particles,
        h: &Hjc,
    ) -> [usize; 5] {
        let mut n = [0; 5];
        let mu_plock = hjc::lock_strain(h);
        for i in 0..after.len() {
            n[0] += usize::from(after.eps_p[i] > before.eps_p[i]);
            n[1] += usize::from(after.mu_max[i] > h.mu_crush);
            n[2] += usize::from(after.mu_max[i] >= mu_plock);
            n[3] += usize::from(after.p[i] < 0.0);
            n[4] += usize::from(after.damage[i] > 0.0);
        }
        n
    }

    /// One concrete pass agrees with cpu::concrete::run field by field on the smoke state, one
    /// particle of which separates so fast that continuity alone would make its density
    /// negative: both hold it at the floor and fail it.
    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn concrete_matches_cpu() {
        compare(&[]);
    }

    /// With the corrected gradient, whose hoop rate is v_r/r (the default conjugate one's,
    /// which `concrete_matches_cpu` compares, is weighted by each particle's hoop weight).
    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn concrete_with_corrected_gradient_matches_cpu() {
        compare(&["target.velocity_gradient=\"corrected\"".into()]);
    }

    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn concrete_with_artificial_stress_matches_cpu() {
        compare(&["target.artificial_stress=true".into()]);
    }

    /// What the pass leaves for sph_forces is the CPU prologue's of the GPU's new state, and
    /// the packed pairs hold exactly the state's values.
    fn check_prologue(
        gpu: &Gpu,
        pass: &ConcretePass,
        back: &crate::state::Particles,
        sph: &SphParams,
    ) {
        let mut cpu = back.clone();
        crate::cpu::sph_forces::prologue(&mut cpu, sph);
        let art_on = sph.art_stress_eps > 0.0;
        let tensile = cpu
            .art_stress
            .iter()
            .filter(|a| a.iter().any(|&x| x != 0.0));
        assert!(!art_on || tensile.count() > 0, "no artificial stress here");
        let col = |v: &[[f32; 3]], k: usize| -> Vec<f32> { v.iter().map(|a| a[k]).collect() };
        // σ/ρ²: a division and a product; R: atan2, sin and cos besides, a few ulp each on
        // the GPU.
        for k in 0..3 {
            for (name, a, b, on, tol) in [
                (
                    "stress_rho2",
                    &back.stress_rho2,
                    &cpu.stress_rho2,
                    true,
                    1.0e-6,
                ),
                (
                    "art_stress",
                    &back.art_stress,
                    &cpu.art_stress,
                    art_on,
                    1.0e-5,
                ),
            ] {
                let e = field_error(&col(a, k), &col(b, k));
                assert!(!on || e <= tol, "{name}[{k}]: relative error {e:e}");
            }
        }
        let n = back.len();
        let pair_s: Vec<[f32; 4]> = gpu.read(&pass.pairs[0], n).unwrap();
        let pair_c: Vec<[f32; 4]> = gpu.read(&pass.pairs[1], n).unwrap();
        for j in 0..n {
            let [a, b, c] = back.stress_rho2[j];
            assert_eq!(
                pair_s[j].map(f32::to_bits),
                [a, b, c, back.m_tilde[j]].map(f32::to_bits)
            );
            let own = [back.sound[j], back.rho[j], back.visc_switch[j], 0.0];
            assert_eq!(pair_c[j].map(f32::to_bits), own.map(f32::to_bits));
        }
    }

    fn compare(overrides: &[String]) {
        let gpu = test_gpu();
        let mut sim = smoke(SMOKE_STEPS, overrides);
        let sph = sim.sph.expect("smoke has a target");
        let dt = sim.dt;
        let separating = sim.particles.len() / 3;
        sim.particles.drho[separating] = -3.0 * sim.particles.rho[separating] / dt;
        let mut cpu = sim.particles.clone();
        crate::cpu::concrete::run(&mut cpu, &sph, dt);
        if sph.conjugate_gradient {
            // The hoop weight must matter here, or the comparison would not test it.
            let mut unweighted = sim.particles.clone();
            unweighted.hoop_weight.fill(1.0);
            crate::cpu::concrete::run(&mut unweighted, &sph, dt);
            let change = field_error(&unweighted.s_tt, &cpu.s_tt);
            eprintln!("concrete: the hoop weight moves s_tt by {change:e} of its scale");
            assert!(change > 1.0e-3, "the hoop weight changes nothing here");
        }
        let n = branches(&sim.particles, &cpu, &sph.concrete);
        eprintln!("concrete smoke branches (plastic, crushed, locked, cut-off, damaged): {n:?}");
        assert!(
            n[0] > 0 && n[1] > 0 && n[4] > 0,
            "smoke state too tame: {n:?}"
        );

        let gp = GpuParticles::upload(&gpu, &sim.particles);
        let uniform = gpu.uniform("sph", &SphUniform::new(&sph, gp.len));
        let clock = gpu.buffer("clock", &crate::gpu::timestep::clock_words(dt, false));
        let pass = ConcretePass::new(&gpu, &gp, &uniform, &clock, &sph).unwrap();
        run_once(&gpu, |p| pass.record(p)).unwrap();
        let mut back = sim.particles.clone();
        gp.download(&gpu, &mut back).unwrap();
        check_prologue(&gpu, &pass, &back, &sph);
        let floor = crate::cpu::concrete::density_floor(&sph.concrete);
        assert_eq!(
            cpu.rho[separating], floor,
            "CPU density of the separating particle"
        );
        assert_eq!(
            back.rho[separating], floor,
            "GPU density of the separating particle"
        );

        // Relative to each field's largest value: a few roundings per operation, fused on the
        // GPU, pow/log within ~2 ulp; the pressure is a difference of terms of size K·μ, the
        // strength a function of it, so their errors scale with the field rather than the value.
        // The history fields (rho, energy, damage, mu_max, eps_p) are compared by their
        // increments in this step, or a wrong increment would hide under the accumulated value.
        let before = &sim.particles;
        for (name, a, b, start, tol) in [
            ("rho", &back.rho, &cpu.rho, &before.rho, 1.0e-6),
            (
                "strain_energy",
                &back.strain_energy,
                &cpu.strain_energy,
                &before.strain_energy,
                1.0e-5,
            ),
            ("damage", &back.damage, &cpu.damage, &before.damage, 1.0e-5),
            ("mu_max", &back.mu_max, &cpu.mu_max, &before.mu_max, 1.0e-6),
            ("eps_p", &back.eps_p, &cpu.eps_p, &before.eps_p, 1.0e-5),
        ] {
            let e = increment_error(a, b, start);
            eprintln!("concrete {name} increment: relative error {e:e}");
            assert!(e <= tol, "{name} increment: relative error {e:e} > {tol:e}");
        }
        for (name, a, b, tol) in [
            ("p", &back.p, &cpu.p, 1.0e-5),
            ("s_rr", &back.s_rr, &cpu.s_rr, 1.0e-5),
            ("s_zz", &back.s_zz, &cpu.s_zz, 1.0e-5),
            ("s_rz", &back.s_rz, &cpu.s_rz, 1.0e-5),
            ("s_tt", &back.s_tt, &cpu.s_tt, 1.0e-5),
            ("sound", &back.sound, &cpu.sound, 1.0e-6),
        ] {
            let e = field_error(a, b);
            eprintln!("concrete {name}: relative error {e:e}");
            assert!(e <= tol, "{name}: relative error {e:e} > {tol:e}");
        }
    }
}
