//! `fem_stress` on the GPU (shaders/fem_stress.wgsl with the flow laws in
//! shaders/johnson_cook.wgsl, the steel EOS in shaders/steel_eos.wgsl and the deviatoric
//! helpers in shaders/deviator.wgsl); CPU twin `cpu::fem_stress::run`.

use super::shader::Program;
use super::state::{GpuElements, GpuNodes};
use super::timestep::DtSlots;
use super::{Gpu, GpuError, Kernel};

/// `fem_stress` advances every element over the clock's Δt and writes its nodal forces, stable
/// step and plastic work (adding the work to `plastic_total`), and folds the stable steps into
/// a slot of the clock's running minima (a bind group for each); an inverted element puts its
/// index into the status word `STATUS_INVERTED_ELEMENT` (the smallest one wins).
pub struct FemStressPass {
    kernel: Kernel,
    binds: [wgpu::BindGroup; 2],
    n_cells: u32,
}

impl FemStressPass {
    /// `fem_uniform` holds a `params::FemUniform`, `clock` the step's `Clock` (`slots` its
    /// slots' uniforms), `status` the
    /// step's status words, `plastic_total` one f32 per element; `damage`: the material has
    /// Johnson–Cook damage (the update is compiled out otherwise); `n_cells`: the pressure
    /// cells in `elements.cells`.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        gpu: &Gpu,
        nodes: &GpuNodes,
        elements: &GpuElements,
        fem_uniform: &wgpu::Buffer,
        damage: bool,
        n_cells: usize,
        clock: &wgpu::Buffer,
        slots: &DtSlots,
        status: &wgpu::Buffer,
        plastic_total: &wgpu::Buffer,
    ) -> Result<FemStressPass, GpuError> {
        let kernel = gpu.kernel(
            Program::FemStress,
            "main",
            &[("DAMAGE", f64::from(u8::from(damage)))],
        )?;
        let (n, e) = (nodes, elements);
        let bind = |slot: u32| {
            kernel.bind(
                gpu,
                &[
                    ("fold_slot", slots.get(slot)),
                    ("u", fem_uniform),
                    ("clock", clock),
                    ("status", status),
                    ("r", &n.r),
                    ("z", &n.z),
                    ("vr", &n.vr),
                    ("vz", &n.vz),
                    ("nodes", &e.nodes),
                    ("volume0", &e.volume0),
                    ("s_rr", &e.s_rr),
                    ("s_zz", &e.s_zz),
                    ("s_rz", &e.s_rz),
                    ("s_tt", &e.s_tt),
                    ("p", &e.p),
                    ("energy", &e.energy),
                    ("eps_p", &e.eps_p),
                    ("temperature", &e.temperature),
                    ("damage", &e.damage),
                    ("failed", &e.failed),
                    ("force", &e.force),
                    ("dt", &e.dt),
                    ("plastic_work", &e.plastic_work),
                    ("plastic_total", plastic_total),
                    ("cells", &e.cells),
                ],
            )
        };
        let binds = [bind(0)?, bind(1)?];
        Ok(FemStressPass {
            kernel,
            binds,
            n_cells: n_cells as u32,
        })
    }

    /// Record `fem_stress`, one thread per pressure cell, folding into the clock's `slot`.
    pub fn record(&self, pass: &mut wgpu::ComputePass, slot: u32) {
        self.kernel
            .dispatch(pass, &self.binds[slot as usize], self.n_cells);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::concrete::tests::{field_error, increment_error};
    use crate::gpu::integrate::{STATUS_CLEAR, STATUS_INVERTED_ELEMENT, STATUS_WORDS};
    use crate::gpu::params::FemUniform;
    use crate::gpu::shader::{self, fem_stress_parts, Part};
    use crate::gpu::{run_once, test_gpu};
    use crate::materials::flow::{FlowLaw, Strength};
    use crate::materials::zerilli_armstrong::ZaFcc;
    use crate::solver::{Model, Simulation};
    use crate::state::{Elements, FemParams, Nodes};

    /// CPU steps of the coarse Taylor bar before a comparison: the bar touches the wall after
    /// 1 µm of travel, and after 66 steps (t ≈ 2.3 µs) 126 of the 400 elements yield in the
    /// next stress pass, 7 of them for the first time (the return's bracket at ε_p = 0).
    const TAYLOR_STEPS: usize = 66;

    /// The Taylor bar (4340 Rc 30 onto a rigid wall, damage on) at radius/4 elements (400
    /// triangles, so the CPU steps take well under a second), after `steps` steps.
    fn taylor(steps: usize) -> Model {
        let scene = crate::scene::load(
            std::path::Path::new("cases/taylor-4340-208.toml"),
            &[
                "projectile.element_size=0.001".into(),
                "projectile.cell_pressure=true".into(),
            ],
        )
        .expect("taylor case");
        let mut sim = Simulation::new(&scene).expect("taylor builds");
        for _ in 0..steps {
            sim.step().expect("taylor steps");
        }
        sim.into_model().expect("taylor's state")
    }

    /// Evaluates the laws of johnson_cook.wgsl and steel_eos.wgsl on a list of cases, 8 inputs
    /// and 12 outputs each: (ε_p, ε̇, T, σ_trial, σ*, Δε_p, μ, E) → (T*, σ_y, H, the return's
    /// Δε_p, scale and σ_y, ε_f, ΔD, spall at mean stress σ_trial, p, dp/dμ, 0).
    const LAW_KERNEL: Part = Part {
        file: "(gpu::fem_stress tests' law kernel)",
        text: r#"
@group(0) @binding(0) var<uniform> u: FemUniform;
@group(0) @binding(1) var<storage, read> cases: array<f32>;
@group(0) @binding(2) var<storage, read_write> out: array<f32>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i >= u.n_elements) { return; }
    let a = 8u * i;
    let o = 12u * i;
    let eps_p = cases[a];
    let rate = cases[a + 1u];
    let temp = cases[a + 2u];
    let sigma = cases[a + 3u];
    let triax = cases[a + 4u];
    let t_star = jc_homologous_temperature(u, temp);
    out[o] = t_star;
    out[o + 1u] = jc_flow_stress(u, eps_p, rate, temp);
    out[o + 2u] = jc_hardening_modulus(u, eps_p, rate, temp);
    let ret = jc_radial_return(u, u.shear_modulus, sigma, eps_p, rate, temp, u.return_iterations);
    out[o + 3u] = ret.d_eps_p;
    out[o + 4u] = ret.scale;
    out[o + 5u] = ret.flow_stress;
    out[o + 6u] = jc_failure_strain(u, triax, rate, u.eps_rate_ref, t_star);
    out[o + 7u] = jc_damage_increment(u, cases[a + 5u], triax, rate, u.eps_rate_ref, t_star);
    out[o + 8u] = select(0.0, 1.0, jc_spalls(u, sigma));
    out[o + 9u] = steel_eos_pressure(u, cases[a + 6u], cases[a + 7u]);
    out[o + 10u] = steel_eos_bulk_tangent(u, cases[a + 6u]);
    out[o + 11u] = 0.0;
}
"#,
    };

    /// The law kernel is valid WGSL (checked without an adapter).
    #[test]
    fn law_kernel_validates() {
        shader::validate(&fem_stress_parts(LAW_KERNEL)).unwrap();
    }

    /// The same outputs from materials::{flow, johnson_cook, steel_eos}.
    fn law_cpu(m: &FemParams, c: &[f32; 8]) -> [f32; 12] {
        use crate::materials::{flow, johnson_cook as jc, steel_eos};
        let [eps_p, rate, temp, sigma, triax, d_eps_p, mu, e_vol] = *c;
        let (s, d) = (&m.strength, &m.damage.expect("the law cases have damage"));
        let t_star = flow::homologous_temperature(s, temp);
        let ret = flow::radial_return(
            s,
            m.shear_modulus,
            sigma,
            eps_p,
            rate,
            temp,
            m.return_iterations,
        );
        [
            t_star,
            flow::flow_stress(s, eps_p, rate, temp),
            flow::hardening_modulus(s, eps_p, rate, temp),
            ret.d_eps_p,
            ret.scale,
            ret.flow_stress,
            jc::failure_strain(d, triax, rate, s.eps_rate_ref, t_star),
            jc::damage_increment(d, d_eps_p, triax, rate, s.eps_rate_ref, t_star),
            f32::from(u8::from(jc::spalls(d, sigma))),
            steel_eos::pressure(&m.eos, mu, e_vol),
            steel_eos::bulk_tangent(&m.eos, mu),
            0.0,
        ]
    }

    /// Hand-picked states: (ε_p, ε̇, T, σ_trial) elastic below A, first yield with a small and
    /// large overshoot (the bracket's bisection), hardened, above the melt (σ_y = 0), negative
    /// ε_p with T below room and σ_trial = 0, large strain and rate beyond the spall stress;
    /// (σ*, Δε_p) compressive, shear, tensile, at and beyond the σ* = 1.5 switch, extreme
    /// compression (the exp cap) and zero strain; (μ, E) in tension, compression, large
    /// compression and zero.
    /// Index i takes the i-th of each list cyclically (9 and 7 coprime: every strength case
    /// meets every damage case).
    fn law_cases() -> Vec<[f32; 8]> {
        let strength = [
            (0.0, 0.5, 293.0, 700.0e6),
            (0.0, 1.0e3, 500.0, 780.0e6),
            (0.0, 1.0e3, 500.0, 1.2e9),
            (0.0, 1.0e4, 300.0, 3.0e9),
            (0.05, 1.0e3, 500.0, 1.5e9),
            (0.05, 1.0e3, 500.0, 1.003944e9),
            (0.1, 1.0e3, 1800.0, 1.5e9),
            (-0.3, 0.5, 200.0, 0.0),
            (1.0, 1.0e6, 1000.0, 7.0e9),
        ];
        let damage = [
            (-0.5, 0.01),
            (0.33, 0.01),
            (1.0, 1.0e-4),
            (1.5, 0.01),
            (4.0, 0.01),
            (-1.0e6, 0.01),
            (0.0, 0.0),
        ];
        let eos = [
            (-0.01, 1.0e8),
            (0.02, 1.0e8),
            (0.1, 0.0),
            (0.3, 5.0e8),
            (0.0, 0.0),
            (-0.5, 1.0e9),
        ];
        (0..strength.len() * damage.len())
            .map(|i| {
                let (eps_p, rate, temp, sigma) = strength[i % strength.len()];
                let (triax, d_eps_p) = damage[i % damage.len()];
                let (mu, e_vol) = eos[i % eos.len()];
                [eps_p, rate, temp, sigma, triax, d_eps_p, mu, e_vol]
            })
            .collect()
    }

    /// The WGSL flow-law and EOS functions agree with materials::{flow, johnson_cook,
    /// steel_eos} on hand-picked states, for the 4340 set with the CPU's 30 return iterations,
    /// and for a set on the floors (single return step, a softening EOS under its tangent
    /// floor, a failure strain of zero under its floor).
    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn johnson_cook_law_matches_cpu() {
        let gpu = test_gpu();
        let steel = taylor(0).fem;
        let d = steel.damage.expect("4340 has damage");
        let floors = FemParams {
            return_iterations: 1,
            eos: crate::materials::steel_eos::PolyEos {
                k2: -1000.0e9,
                ..steel.eos
            },
            damage: Some(crate::materials::johnson_cook::JcDamage {
                d1: 0.0,
                d2: 0.0,
                eps_f_min: 0.0,
                ..d
            }),
            ..steel
        };
        // Zerilli & Armstrong's copper constants on the same states (the law's own branch), and
        // a rate-only set (C₃ = 0) whose exponent is held at 0 on every case, without hardening.
        let with_za = |z: ZaFcc| FemParams {
            strength: Strength {
                law: FlowLaw::ZerilliArmstrongFcc(z),
                ..steel.strength
            },
            ..steel
        };
        let copper = ZaFcc {
            c0: 46.5e6,
            c2: 890.0e6,
            c3: 0.0028,
            c4: 0.000115,
        };
        let za = with_za(copper);
        let za_held = with_za(ZaFcc {
            c2: 0.0,
            c3: 0.0,
            c4: 0.1,
            ..copper
        });
        let names = [
            "T*",
            "flow stress",
            "hardening",
            "return d_eps_p",
            "return scale",
            "return flow stress",
            "failure strain",
            "damage increment",
            "spall",
            "pressure",
            "bulk tangent",
            "padding",
        ];
        for (set, m) in [
            ("4340", steel),
            ("floors", floors),
            ("zerilli-armstrong", za),
            ("zerilli-armstrong held", za_held),
        ] {
            let cases = law_cases();
            let flat: Vec<f32> = cases.iter().flatten().copied().collect();
            let uniform = gpu.uniform("fem", &FemUniform::new(&m, cases.len(), 0, 0));
            let input = gpu.buffer("cases", &flat);
            let output = gpu.zeros::<f32>("out", 12 * cases.len());
            let src = shader::source(&fem_stress_parts(LAW_KERNEL));
            let k = gpu
                .kernel_from("johnson-cook law", &src, "main", &[])
                .unwrap();
            let bind = k
                .bind(
                    &gpu,
                    &[("u", &uniform), ("cases", &input), ("out", &output)],
                )
                .unwrap();
            run_once(&gpu, |p| k.dispatch(p, &bind, cases.len() as u32)).unwrap();
            let got: Vec<f32> = gpu.read(&output, 12 * cases.len()).unwrap();

            // Scales of the tolerance, 2e-6 of each (a few f32 ulps: fused multiply-adds, the
            // driver's pow/exp/log within ~2 ulp): T* and the return's scale live in [0, 1];
            // σ_y and H carry the absolute error of 1 − T*^m near the melt, so they are
            // measured against the law's stress at zero strain and its hardening coefficient
            // (A and nB; Zerilli–Armstrong's C₀ and C₂/2); the converged return may stop
            // anywhere within Newton's band |f| ≤ 1e-7 σ_trial, i.e. 1e-7 σ_trial/3G in Δε_p;
            // the pressure against the sum of its terms' sizes (they cancel in tension).
            let (yield_scale, slope_scale) = match m.strength.law {
                FlowLaw::JohnsonCook(j) => (j.a, j.n * j.b),
                FlowLaw::ZerilliArmstrongFcc(z) => (z.c0, 0.5 * z.c2),
            };
            let three_g = 3.0 * m.shear_modulus;
            let mut worst = [0.0f32; 12];
            for (c, g) in cases.iter().zip(got.chunks(12)) {
                let want = law_cpu(&m, c);
                let (sigma, mu, e_vol) = (c[3], c[6], c[7]);
                let band = if m.return_iterations > 1 {
                    1.0e-7 * sigma / three_g
                } else {
                    0.0
                };
                for q in 0..12 {
                    let scale = match q {
                        0 | 4 | 8 | 11 => 1.0,
                        1 | 5 => want[q].abs().max(yield_scale),
                        2 => want[q].abs().max(slope_scale),
                        9 => {
                            let e = &m.eos;
                            let mc = mu.max(0.0);
                            e.k1 * mu.abs()
                                + (e.k2.abs() + e.k3.abs() * mc) * mc * mc
                                + (e.gamma * e_vol * (1.0 + mu)).abs()
                        }
                        _ => want[q].abs(),
                    };
                    let allowed = 2.0e-6 * scale + if q == 3 { band } else { 0.0 };
                    let err = (g[q] - want[q]).abs();
                    worst[q] = worst[q].max(err / scale.max(f32::MIN_POSITIVE));
                    assert!(
                        err <= allowed,
                        "{set}: {} for case {c:?}: GPU {} CPU {} (error {err:e}, scale {scale:e})",
                        names[q],
                        g[q],
                        want[q]
                    );
                }
            }
            assert!(
                got.chunks(12).any(|g| g[8] == 1.0) && got.chunks(12).any(|g| g[3] > 0.0),
                "{set}: the cases neither spall nor yield"
            );
            eprintln!("johnson-cook law, {set}: worst relative errors");
            for (name, w) in names.iter().zip(worst).take(11) {
                eprintln!("  {name}: {w:e}");
            }
        }
    }

    /// What one GPU stress pass leaves behind.
    struct GpuResult {
        elements: Elements,
        nodes: Nodes,
        plastic_total: Vec<f32>,
        status: Vec<u32>,
    }

    /// Upload `nodes` and `elements`, record fem_stress (with Δt = `dt`), and read everything
    /// back; plastic_total starts at
    /// `plastic_start`. The stress pass's fold into the clock's slot 0 must be the least of
    /// the elements' stable steps it leaves, to the bit.
    #[allow(clippy::too_many_arguments)]
    fn run_gpu(
        gpu: &Gpu,
        nodes: &Nodes,
        elements: &Elements,
        params: &FemParams,
        dt: f32,
        plastic_start: &[f32],
    ) -> GpuResult {
        let gn = GpuNodes::upload(gpu, nodes);
        let ge = GpuElements::upload(gpu, elements);
        let clock = gpu.buffer("clock", &crate::gpu::timestep::clock_words(dt, false));
        let status = gpu.buffer("status", &[STATUS_CLEAR; STATUS_WORDS]);
        let plastic_total = gpu.buffer("plastic total", plastic_start);
        let uniform = gpu.uniform(
            "fem",
            &FemUniform::new(
                params,
                elements.len(),
                nodes.len(),
                elements.cells.len() - 1,
            ),
        );
        let damage = params.damage.is_some();
        let slots = crate::gpu::timestep::DtSlots::new(gpu);
        let stress_pass = FemStressPass::new(
            gpu,
            &gn,
            &ge,
            &uniform,
            damage,
            elements.cells.len() - 1,
            &clock,
            &slots,
            &status,
            &plastic_total,
        )
        .unwrap();
        run_once(gpu, |p| stress_pass.record(p, 0)).unwrap();
        let mut back = GpuResult {
            elements: elements.clone(),
            nodes: nodes.clone(),
            plastic_total: gpu.read(&plastic_total, elements.len()).unwrap(),
            status: gpu.read(&status, STATUS_WORDS).unwrap(),
        };
        ge.download(gpu, &mut back.elements).unwrap();
        gn.download(gpu, &mut back.nodes).unwrap();
        let candidate = |x: f32| {
            if (0.0..=f32::MAX).contains(&x) {
                x.to_bits()
            } else {
                f32::MAX.to_bits()
            }
        };
        let least = back.elements.dt.iter().map(|&x| candidate(x)).min();
        let words: Vec<u32> = gpu.read(&clock, 6).unwrap();
        assert_eq!(Some(words[3]), least, "the elements' fold");
        back
    }

    /// The Taylor state made to exercise every branch of the element update in one pass:
    /// the per-step outputs NaN-poisoned (anything the GPU does not write shows), and, chosen
    /// from a trial CPU pass, a few yielding elements put just below D = 1 (by half their
    /// damage increment, far beyond round-off) so they fail by damage, an elastic one under a
    /// mean tension of 1.5 σ_spall so it spalls, and two already failed.
    fn prepared_state(sim: &Model) -> Elements {
        let mut e = sim.projectile.elements.clone();
        let mut trial = e.clone();
        crate::cpu::fem_stress::run(&mut trial, &sim.projectile.nodes, &sim.fem, sim.dt)
            .expect("taylor state is not inverted");
        let spall = sim.fem.damage.expect("4340 has damage").spall_stress;
        let yielding: Vec<usize> = (0..e.len())
            .filter(|&k| trial.damage[k] - e.damage[k] > 1.0e-5)
            .collect();
        for &k in yielding.iter().step_by(7).take(4) {
            e.damage[k] = 1.0 - 0.5 * (trial.damage[k] - e.damage[k]);
        }
        let elastic: Vec<usize> = (0..e.len())
            .filter(|&k| trial.eps_p[k] == e.eps_p[k])
            .collect();
        if let Some(&k) = elastic.get(3) {
            e.p[k] = -1.5 * spall;
        }
        for &k in elastic.iter().skip(4).step_by(11).take(2) {
            e.failed[k] = 1;
            e.damage[k] = 1.0;
        }
        // Two failed and open (cpu::fem_stress::OPEN_RELATIVE_VOLUME): their reference
        // volume shrunk so that they stand at 1.4 times it.
        for &k in elastic.iter().skip(9).step_by(13).take(2) {
            e.failed[k] = 1;
            e.damage[k] = 1.0;
            e.volume0[k] /= 1.4;
        }
        e.force.iter_mut().for_each(|f| *f = [f32::NAN; 6]);
        e.dt.iter_mut().for_each(|x| *x = f32::NAN);
        e.plastic_work.iter_mut().for_each(|x| *x = f32::NAN);
        e
    }

    /// Elements on each branch of the update, from the state before and after a CPU pass:
    /// (yielded this step, damage grew, failed this step, failed before, yielded for the first
    /// time, open: no force).
    fn branches(before: &Elements, after: &Elements) -> [usize; 6] {
        let mut n = [0; 6];
        for k in 0..after.len() {
            n[5] += usize::from(after.force[k] == [0.0; 6]);
            n[0] += usize::from(after.eps_p[k] > before.eps_p[k]);
            n[4] += usize::from(after.eps_p[k] > 0.0 && before.eps_p[k] == 0.0);
            n[1] += usize::from(after.damage[k] > before.damage[k]);
            n[2] += usize::from(after.failed[k] != 0 && before.failed[k] == 0);
            n[3] += usize::from(before.failed[k] != 0);
        }
        n
    }

    /// One fem_stress pass agrees with cpu::fem_stress::run field by field on a Taylor-bar
    /// state with yielding, damaged, failing, spalling and failed elements, with the CPU's
    /// bracketed Newton (30 iterations) and with the single linearised return step.
    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn fem_stress_matches_cpu() {
        let gpu = test_gpu();
        let sim = taylor(TAYLOR_STEPS);
        let nodes = &sim.projectile.nodes;
        let before = prepared_state(&sim);
        let plastic_start: Vec<f32> = (0..before.len()).map(|k| k as f32 * 0.25).collect();
        for iterations in [sim.fem.return_iterations, 1] {
            let params = FemParams {
                return_iterations: iterations,
                ..sim.fem
            };
            let mut cpu = before.clone();
            crate::cpu::fem_stress::run(&mut cpu, nodes, &params, sim.dt).unwrap();
            let n = branches(&before, &cpu);
            eprintln!(
                "fem_stress, {iterations} return iterations, {} elements at t = {:.2e} s: \
                 yielded {} ({} for the first time), damage grew {}, failed now {}, \
                 failed before {}, open {}",
                before.len(),
                sim.time,
                n[0],
                n[4],
                n[1],
                n[2],
                n[3],
                n[5]
            );
            assert!(n.iter().all(|&c| c > 0), "Taylor state too tame: {n:?}");
            // Both kinds of pressure cell: shared, and back to the elements' own (a failed
            // element in it).
            let shared = before
                .cells
                .windows(2)
                .filter(|w| {
                    let range = w[0] as usize..w[1] as usize;
                    crate::cpu::fem_stress::cell_eos(&before, range, nodes, sim.dt).is_some()
                })
                .count();
            let cells = before.cells.len() - 1;
            eprintln!("fem_stress: {shared} of {cells} pressure cells share one pressure");
            assert!(
                shared > 0 && shared < cells,
                "{shared} of {cells} cells shared"
            );

            let gpu_out = run_gpu(&gpu, nodes, &before, &params, sim.dt, &plastic_start);
            let back = &gpu_out.elements;
            assert_eq!(gpu_out.status[STATUS_INVERTED_ELEMENT], STATUS_CLEAR);
            assert_eq!(back.failed, cpu.failed, "failed flags differ");

            // Tolerances, relative to each field's largest value (history fields: to the
            // largest increment of this step, or a wrong increment would hide under the
            // accumulated value). Every output is a chain of ~10–30 f32 operations which the
            // driver may fuse (fma) or divide as a·(1/b), with pow/exp/log within a few ulp.
            // - Deviator: the trial S + Δt(2G dev ε̇ + spin terms), then the return's factor
            //   from σ_y (pow, log): ~10 ulps of the field's scale, 2e-6.
            // - p (and with it the forces and the energy increment): μ = V/V₀ inverted, less 1,
            //   cancels, so each ulp of V/V₀ is K₁·2⁻²³ in p. V/V₀ takes ~4 roundings (2A, r̄,
            //   V, the division; lavapipe does them as the CPU does, other drivers may fuse or
            //   divide differently): 4 such ulps over the largest |p|, at least 1e-5. On this
            //   state one ulp is 1.5e-5 of the largest |p|, so the bound is ~6e-5.
            // - dt: L and c to a few ulps without cancellation, 1e-6.
            // - Δε_p, and with it ΔT, ΔD and the work: Newton stops at |f| ≤ 1e-7 σ_trial, so
            //   the two sides may stop on iterates 1e-7 σ_trial/3G apart (printed below over
            //   the largest Δε_p), 1e-5.
            let p_max = cpu.p.iter().fold(0.0f32, |m, x| m.max(x.abs()));
            let d_eps_max =
                (0..cpu.len()).fold(0.0f32, |m, k| m.max(cpu.eps_p[k] - before.eps_p[k]));
            let seq_max = (0..cpu.len()).fold(0.0f32, |m, k| {
                m.max(crate::cpu::deviator::von_mises(&[
                    cpu.s_rr[k],
                    cpu.s_zz[k],
                    cpu.s_rz[k],
                    cpu.s_tt[k],
                ]))
            });
            let volume_ulp = params.eos.k1 * f32::EPSILON / p_max;
            let tol_p = (4.0 * volume_ulp).max(1.0e-5);
            eprintln!(
                "fem_stress ({iterations}) scales: largest |p| {p_max:e} Pa (one ulp of V/V₀ is \
                 {volume_ulp:e} of it: p, force, energy to {tol_p:e}), largest Δε_p \
                 {d_eps_max:e} (Newton's stopping band is {:e} of it)",
                1.0e-7 * seq_max / (3.0 * params.shear_modulus) / d_eps_max
            );
            for (name, a, b, start, tol) in [
                ("energy", &back.energy, &cpu.energy, &before.energy, tol_p),
                ("eps_p", &back.eps_p, &cpu.eps_p, &before.eps_p, 1.0e-5),
                (
                    "temperature",
                    &back.temperature,
                    &cpu.temperature,
                    &before.temperature,
                    1.0e-5,
                ),
                ("damage", &back.damage, &cpu.damage, &before.damage, 1.0e-5),
            ] {
                let e = increment_error(a, b, start);
                eprintln!("fem_stress ({iterations}) {name} increment: relative error {e:e}");
                assert!(e <= tol, "{name} increment: relative error {e:e} > {tol:e}");
            }
            // An open element exerts nothing and its step is the time it would take to close
            // (f32::MAX when it is not closing), far beyond the others: compared one by one,
            // and left out of the others' comparison (it would set the scale).
            let open: Vec<usize> = (0..cpu.len())
                .filter(|&k| cpu.force[k] == [0.0; 6])
                .collect();
            for &k in &open {
                assert_eq!(back.force[k], [0.0; 6], "open element {k}: force");
                let e = (back.dt[k] - cpu.dt[k]).abs() / cpu.dt[k];
                assert!(
                    e <= 1.0e-5,
                    "open element {k}: step {:e} against {:e}",
                    back.dt[k],
                    cpu.dt[k]
                );
            }
            let closed_dt = |dt: &[f32]| -> Vec<f32> {
                (0..dt.len())
                    .map(|k| if open.contains(&k) { 0.0 } else { dt[k] })
                    .collect()
            };
            let (back_dt, cpu_dt) = (closed_dt(&back.dt), closed_dt(&cpu.dt));
            let flat = |f: &[[f32; 6]]| f.iter().flatten().copied().collect::<Vec<f32>>();
            let (back_force, cpu_force) = (flat(&back.force), flat(&cpu.force));
            for (name, a, b, tol) in [
                ("s_rr", &back.s_rr, &cpu.s_rr, 2.0e-6),
                ("s_zz", &back.s_zz, &cpu.s_zz, 2.0e-6),
                ("s_rz", &back.s_rz, &cpu.s_rz, 2.0e-6),
                ("s_tt", &back.s_tt, &cpu.s_tt, 2.0e-6),
                ("p", &back.p, &cpu.p, tol_p),
                ("force", &back_force, &cpu_force, tol_p),
                ("dt", &back_dt, &cpu_dt, 1.0e-6),
                (
                    "plastic_work",
                    &back.plastic_work,
                    &cpu.plastic_work,
                    1.0e-5,
                ),
            ] {
                let e = field_error(a, b);
                eprintln!("fem_stress ({iterations}) {name}: relative error {e:e}");
                assert!(e <= tol, "{name}: relative error {e:e} > {tol:e}");
            }
            // The accumulator got exactly this step's work on top of what it held.
            for (k, (total, start)) in gpu_out.plastic_total.iter().zip(&plastic_start).enumerate()
            {
                assert_eq!(
                    *total,
                    start + back.plastic_work[k],
                    "plastic_total of element {k}"
                );
            }
        }
    }

    /// An inverted element (nodes turned clockwise) and one with a NaN node each put the
    /// smallest bad index into the status word; forces of good elements are still written.
    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn inverted_element_sets_status() {
        let gpu = test_gpu();
        let sim = taylor(0);
        let elements = &sim.projectile.elements;
        let params = &sim.fem;
        let plastic = vec![0.0; elements.len()];

        // Swapping two nodes of element k reverses its orientation (2A < 0).
        let mut inverted = elements.clone();
        let k = elements.len() / 2;
        inverted.nodes[k].swap(1, 2);
        inverted.nodes[k + 5].swap(0, 1);
        inverted.force.iter_mut().for_each(|f| *f = [f32::NAN; 6]);
        let out = run_gpu(
            &gpu,
            &sim.projectile.nodes,
            &inverted,
            params,
            sim.dt,
            &plastic,
        );
        let mut cpu = inverted.clone();
        let err = crate::cpu::fem_stress::run(&mut cpu, &sim.projectile.nodes, params, sim.dt)
            .expect_err("the CPU sees it too");
        eprintln!(
            "inverted element {k}: status word {}, CPU reports {}",
            out.status[STATUS_INVERTED_ELEMENT], err.element
        );
        assert_eq!(out.status[STATUS_INVERTED_ELEMENT], k as u32);
        assert_eq!(err.element, k);
        assert!(
            out.elements.force[k][0].is_nan(),
            "no force from an inverted element"
        );
        assert!(out.elements.force[k - 1][0].is_finite());
        for w in 0..STATUS_WORDS {
            if w != STATUS_INVERTED_ELEMENT {
                assert_eq!(out.status[w], STATUS_CLEAR);
            }
        }

        // A NaN coordinate makes 2A NaN for every element around the node.
        let mut nodes = sim.projectile.nodes.clone();
        let node = elements.nodes[k][0] as usize;
        nodes.z[node] = f32::NAN;
        let first = (0..elements.len())
            .find(|&e| elements.nodes[e].contains(&(node as u32)))
            .unwrap();
        let out = run_gpu(&gpu, &nodes, elements, params, sim.dt, &plastic);
        eprintln!(
            "NaN node {node}: status word {}, first element on it {first}",
            out.status[STATUS_INVERTED_ELEMENT]
        );
        assert_eq!(out.status[STATUS_INVERTED_ELEMENT], first as u32);
        assert!(out.elements.s_rr.iter().all(|x| x.is_finite()));
    }
}
