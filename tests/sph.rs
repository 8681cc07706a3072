//! SPH target without a projectile (physics.md §3): rest stays rest, linear velocity fields give
//! exact velocity gradients and simple stress fields the cylindrical divergence (axis ghosts
//! included), a crushing slug conserves energy and axial momentum (with the Balsara switch and
//! the reconstructed viscosity too), the switch takes the viscosity out of a shear and leaves
//! it in a compression, and the reconstruction takes it out of a smooth compression.

use penetrate::cpu::{concrete, integrate, neighbours, sph_forces, sph_rates, timestep};
use penetrate::materials::hjc::Hjc;
use penetrate::mesh::target::lattice;
use penetrate::scene::{
    TargetSpec, TensionModel, VelocityFilter, VelocityGradient, ViscosityJump, ViscositySwitch,
};
use penetrate::state::{Particles, SphParams};

fn spec(fix: bool) -> TargetSpec {
    TargetSpec {
        radius: 0.04,
        thickness: 0.04,
        spacing: 0.002,
        smoothing_ratio: 1.5,
        fix_rear: fix,
        fix_lateral: fix,
        artificial_stress: true,
        viscosity_alpha: 1.0,
        viscosity_beta: 2.0,
        viscosity_switch: ViscositySwitch::None,
        viscosity_jump: ViscosityJump::Raw,
        velocity_filter: VelocityFilter::None,
        velocity_gradient: VelocityGradient::Corrected,
        lead_hole_depth: 0.0,
        lead_hole_diameter: 0.02,
        tension: TensionModel::CrackBand,
        concrete: Hjc::from_fc(35e6, 2370.0),
    }
}

fn target(spec: &TargetSpec) -> (Particles, SphParams) {
    let l = lattice(
        spec.radius,
        spec.thickness,
        spec.spacing,
        spec.concrete.density as f64,
    )
    .unwrap();
    (Particles::from_lattice(&l, spec), SphParams::new(spec))
}

/// A target at rest with no projectile stays at rest: |v| < 1e-6 m/s after 1000 steps, the
/// particles next to the axis included.
/// The free target of `spec(false)` without artificial stress, its neighbour grid built and
/// `sph_rates` run on it (at rest: the areas and hoop weights `sph_forces` reads), and the
/// kernel's support.
fn free_target_with_rates() -> (TargetSpec, Particles, SphParams, neighbours::CellGrid, f32) {
    let mut s = spec(false);
    s.artificial_stress = false;
    let (mut p, params) = target(&s);
    let mut grid = neighbours::CellGrid::default();
    let support = integrate::support(&params);
    neighbours::run(&mut grid, &p.r, &p.z, &params.kernel);
    sph_rates::run(&mut p, &grid, &params, None);
    (s, p, params, grid, support)
}

#[test]
fn target_at_rest_stays_at_rest() {
    let s = spec(true);
    let (mut p, params) = target(&s);
    let mut grid = neighbours::CellGrid::default();
    let dt = 0.3 * timestep::particle_dt(&p, &params);
    for _ in 0..1000 {
        integrate::particles(&mut p, &params, dt, 10.0).unwrap();
        neighbours::run(&mut grid, &p.r, &p.z, &params.kernel);
        sph_rates::run(&mut p, &grid, &params, None);
        concrete::run(&mut p, &params, dt);
        sph_forces::run(&mut p, &grid, &params, None);
    }
    let vmax = (0..p.len())
        .map(|i| p.vr[i].hypot(p.vz[i]))
        .fold(0.0f32, f32::max);
    assert!(vmax < 1e-6, "max |v| = {vmax} m/s");
    let near_axis = (0..p.len()).filter(|&i| p.r[i] < params.h).count();
    assert!(near_axis > 10);
}

/// A uniform velocity along the axis gives zero velocity gradient and density rate everywhere;
/// the admissible linear field v_r = a r, v_z = b z gives L_rr = a, L_zz = b and
/// ρ̇ = −ρ (2a + b) at every interior particle, next to the axis too; with the velocity filter
/// as well (a linear field passes it unchanged).
#[test]
fn velocity_gradient_is_exact_for_uniform_and_linear_fields() {
    for filter in [false, true] {
        gradient_is_exact(filter);
    }
}

fn gradient_is_exact(filter: bool) {
    let s = spec(false);
    let (mut p, mut params) = target(&s);
    params.velocity_filter = filter;
    let mut grid = neighbours::CellGrid::default();
    neighbours::run(&mut grid, &p.r, &p.z, &params.kernel);

    for i in 0..p.len() {
        p.vz[i] = -250.0;
    }
    sph_rates::run(&mut p, &grid, &params, None);
    for i in 0..p.len() {
        assert_eq!(
            (p.l_rr[i], p.l_rz[i], p.l_zr[i], p.l_zz[i], p.drho[i]),
            (0.0, 0.0, 0.0, 0.0, 0.0),
            "particle {i}"
        );
    }

    let (a, b) = (300.0f32, -500.0f32);
    for i in 0..p.len() {
        p.vr[i] = a * p.r[i];
        p.vz[i] = b * p.z[i];
    }
    sph_rates::run(&mut p, &grid, &params, None);
    let support = integrate::support(&params) as f64;
    let mut checked = 0;
    for i in 0..p.len() {
        let (r, z) = (p.r[i] as f64, p.z[i] as f64);
        // Interior: a full support from the free faces (the axis is not a free face).
        if r + support > s.radius || z + support > 0.0 || z - support < -s.thickness {
            continue;
        }
        let tol = 1e-3 * a.abs().max(b.abs());
        assert!(
            (p.l_rr[i] - a).abs() < tol,
            "particle {i} at r {r}: L_rr {}",
            p.l_rr[i]
        );
        assert!(
            (p.l_zz[i] - b).abs() < tol,
            "particle {i}: L_zz {}",
            p.l_zz[i]
        );
        assert!(p.l_rz[i].abs() < tol && p.l_zr[i].abs() < tol);
        let expected = -p.rho[i] * (2.0 * a + b);
        assert!(
            (p.drho[i] - expected).abs() < 1e-3 * expected.abs(),
            "particle {i}: ρ̇ {} vs {expected}",
            p.drho[i]
        );
        checked += 1;
    }
    assert!(checked > 50);
}

/// The velocity filter takes particle-scale scatter out of the velocity gradient: on the linear
/// field above plus a scatter of up to ±5 m/s on each particle's velocity (the δv/Δ a
/// kernel-scale gradient reads as strain rate), the interior particles' largest and mean
/// errors in L fall below 0.7 of the unfiltered ones (measured: 0.59 and 0.54; white scatter
/// has power at every scale down to the kernel's, which one pass of a kernel-wide mean only
/// partly removes); the linear part stays exact (previous test).
#[test]
fn velocity_filter_takes_particle_scatter_out_of_the_gradient() {
    let s = spec(false);
    let (mut p, mut params) = target(&s);
    let mut grid = neighbours::CellGrid::default();
    neighbours::run(&mut grid, &p.r, &p.z, &params.kernel);
    let (a, b, dv) = (300.0f32, -500.0f32, 5.0f32);
    // A fixed pseudo-random scatter in [−dv, dv) on each component (a linear congruential
    // sequence, so the test is the same every run).
    let mut state = 12345u64;
    let mut scatter = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        dv * (2.0 * ((state >> 40) as f32 / (1u64 << 24) as f32) - 1.0)
    };
    for i in 0..p.len() {
        p.vr[i] = a * p.r[i] + scatter();
        p.vz[i] = b * p.z[i] + scatter();
    }
    let support = integrate::support(&params) as f64;
    let interior: Vec<usize> = (0..p.len())
        .filter(|&i| {
            let (r, z) = (p.r[i] as f64, p.z[i] as f64);
            r + support <= s.radius && z + support <= 0.0 && z - support >= -s.thickness
        })
        .collect();
    assert!(interior.len() > 50);
    let mut errors = |filter: bool| {
        params.velocity_filter = filter;
        sph_rates::run(&mut p, &grid, &params, None);
        let e: Vec<f32> = interior
            .iter()
            .map(|&i| {
                [p.l_rr[i] - a, p.l_rz[i], p.l_zr[i], p.l_zz[i] - b]
                    .iter()
                    .fold(0.0f32, |m, x| m.max(x.abs()))
            })
            .collect();
        let max = e.iter().copied().fold(0.0f32, f32::max);
        let mean = e.iter().sum::<f32>() / e.len() as f32;
        (max, mean)
    };
    let (raw_max, raw_mean) = errors(false);
    let (filtered_max, filtered_mean) = errors(true);
    eprintln!(
        "scatter ±{dv} m/s: largest error in L {raw_max:e} → {filtered_max:e} 1/s, \
         mean {raw_mean:e} → {filtered_mean:e} 1/s"
    );
    assert!(raw_max > 100.0, "the scatter must show in the raw gradient");
    assert!(filtered_max < 0.7 * raw_max);
    assert!(filtered_mean < 0.7 * raw_mean);
}

/// The conjugate gradient's stress power is the work the particle forces do: on the lattice
/// with its free faces, a density scattered by ±10 %, a stress (θθ included) and a velocity
/// that vary from particle to particle (no viscosity, no artificial stress, and the particles
/// within 4h of the axis at rest, so the axis ghosts do not enter), `Σ m_i σ_i : D_i / ρ_i =
/// −Σ m_i a_i · v_i` to f32 round-off, D_θθ the hoop rate the stress update takes
/// (`sph_rates::hoop_rate`: `n_i v_r/r`, the hoop source's weight on it; with `v_r/r` the
/// lateral face, where n_i ≈ ½, would break it). The corrected gradient misses it by more than
/// 10 % (measured: its stress power is 59 % larger without the hoop terms): the stress update
/// then books strain the forces do not pay for.
#[test]
fn conjugate_gradient_stress_power_is_the_forces_work() {
    let mut s = spec(false);
    s.artificial_stress = false;
    s.viscosity_alpha = 0.0;
    s.viscosity_beta = 0.0;
    let (mut p, mut params) = target(&s);
    let mut grid = neighbours::CellGrid::default();
    neighbours::run(&mut grid, &p.r, &p.z, &params.kernel);
    let mut state = 987654321u64;
    let mut unit = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        2.0 * ((state >> 40) as f32 / (1u64 << 24) as f32) - 1.0
    };
    for i in 0..p.len() {
        p.rho[i] *= 1.0 + 0.1 * unit();
        p.p[i] = 50e6 * (1.0 + 0.5 * unit());
        p.s_rr[i] = 20e6 * unit();
        p.s_zz[i] = 20e6 * unit();
        p.s_rz[i] = 10e6 * unit();
        p.s_tt[i] = p.p[i] + 20e6 * unit();
        let moving = p.r[i] > 4.0 * params.h;
        p.vr[i] = if moving { 30.0 * unit() } else { 0.0 };
        p.vz[i] = if moving { -200.0 + 30.0 * unit() } else { 0.0 };
    }
    let mut mismatch = |conjugate: bool| {
        params.conjugate_gradient = conjugate;
        sph_rates::run(&mut p, &grid, &params, None);
        sph_forces::run(&mut p, &grid, &params, None);
        let (mut stress, mut force) = (0.0f64, 0.0f64);
        for i in 0..p.len() {
            let m = p.mass[i] as f64 / p.rho[i] as f64;
            let power = (p.s_rr[i] - p.p[i]) as f64 * p.l_rr[i] as f64
                + (p.s_zz[i] - p.p[i]) as f64 * p.l_zz[i] as f64
                + p.s_rz[i] as f64 * (p.l_rz[i] + p.l_zr[i]) as f64
                + (p.s_tt[i] - p.p[i]) as f64
                    * sph_rates::hoop_rate(&params, p.hoop_weight[i], p.vr[i], p.r[i]) as f64;
            stress += m * power;
            let work = p.mass[i] as f64
                * (p.ar[i] as f64 * p.vr[i] as f64 + p.az[i] as f64 * p.vz[i] as f64);
            force += work;
        }
        eprintln!("conjugate {conjugate}: stress power {stress:e} W, force work {force:e} W");
        (stress + force).abs() / force.abs()
    };
    let conjugate = mismatch(true);
    let corrected = mismatch(false);
    eprintln!("relative mismatch: conjugate {conjugate:e}, corrected {corrected:e}");
    assert!(conjugate < 1e-5, "conjugate: {conjugate:e}");
    assert!(corrected > 0.1, "corrected: {corrected:e}");
}

/// The momentum equation against `∇·σ/ρ` in cylindrical coordinates at every particle with a
/// full support from the free faces, the rows next to the axis included (ρ uniform, v = 0):
/// - a uniform pressure exerts no force (the hoop source's weight balances the pair term on
///   any lattice);
/// - `σ_zz = k z` gives `a_z = k/ρ` to 1 %: 0.7 % is the cubic spline's normalisation on the
///   square lattice at h = 1.5 Δ, the same at every row;
/// - `σ_rz = k r` gives `a_z = 2k/ρ` to 1.5 % from the third row on, and within 25 % on the
///   first two rows: the price of the conservative ghost weights (`sph_forces`, measured
///   21 % and 15 %).
#[test]
fn stress_fields_give_the_cylindrical_divergence() {
    let (s, mut p, params, grid, support) = free_target_with_rates();
    let rho = p.rho[0];
    let interior: Vec<usize> = (0..p.len())
        .filter(|&i| {
            p.r[i] + support < s.radius as f32
                && p.z[i] + support < 0.0
                && p.z[i] - support > -s.thickness as f32
        })
        .collect();
    assert!(
        interior
            .iter()
            .filter(|&&i| p.r[i] < s.spacing as f32)
            .count()
            > 3
    );

    let pressure = 1.0e8f32;
    p.p.iter_mut().for_each(|x| *x = pressure);
    sph_forces::run(&mut p, &grid, &params, None);
    // A pressure gradient of 1 Pa/Δ would give p/(ρ Δ) · 1e-8 m/s².
    let scale = pressure / (rho * s.spacing as f32);
    for &i in &interior {
        assert!(
            p.ar[i].abs() < 1e-5 * scale && p.az[i].abs() < 1e-5 * scale,
            "uniform pressure: particle {i} at r {}: a = ({}, {})",
            p.r[i],
            p.ar[i],
            p.az[i]
        );
    }

    let k = 1.0e10f32; // Pa/m
    p.p.iter_mut().for_each(|x| *x = 0.0);
    for i in 0..p.len() {
        p.s_zz[i] = k * p.z[i];
    }
    sph_forces::run(&mut p, &grid, &params, None);
    for &i in &interior {
        let rel = p.az[i] * rho / k - 1.0;
        assert!(
            rel.abs() < 0.01,
            "σ_zz = kz: particle {i} at r {}: a_z off by {rel}",
            p.r[i]
        );
        assert!(p.ar[i].abs() < 1e-3 * k / rho, "σ_zz = kz: a_r {}", p.ar[i]);
    }

    for i in 0..p.len() {
        p.s_zz[i] = 0.0;
        p.s_rz[i] = k * p.r[i];
    }
    sph_forces::run(&mut p, &grid, &params, None);
    for &i in &interior {
        let rel = p.az[i] * rho / (2.0 * k) - 1.0;
        let row = (p.r[i] / s.spacing as f32).floor();
        let tol = if row < 2.0 { 0.25 } else { 0.015 };
        assert!(
            rel.abs() < tol,
            "σ_rz = kr: particle {i} in row {row}: a_z off by {rel}"
        );
    }
}

/// A free face pushes out under a uniform pressure the same whichever way it faces: the lateral
/// face (normal to r) as the front face (normal to z). On the square lattice the first and
/// second columns in from the lateral face see the same truncated support as the first and
/// second rows in from the front face, so a_r there must equal a_z there (to 1e-3 of it), and
/// point outward. And a surface particle at twice its neighbours' pressure is pushed outward,
/// not drawn in. (The hoop source once cancelled the lateral push, `sph_forces`: a_r was 0 and
/// the over-pressured particle was pulled inward at 8e6 m/s².)
#[test]
fn lateral_face_pushes_out_as_the_front_face() {
    let (s, mut p, params, grid, support) = free_target_with_rates();
    p.p.iter_mut().for_each(|x| *x = 1.0e8);
    sph_forces::run(&mut p, &grid, &params, None);
    let dx = s.spacing as f32;
    let (radius, depth) = (s.radius as f32, s.thickness as f32);
    let full_z = |i: usize| p.z[i] + support < 0.0 && p.z[i] - support > -depth;
    let full_r = |i: usize| p.r[i] > support && p.r[i] + support < radius;
    for layer in 0..2 {
        let inset = (layer as f32 + 0.5) * dx;
        let front: Vec<f32> = (0..p.len())
            .filter(|&i| (p.z[i] + inset).abs() < 0.1 * dx && full_r(i))
            .map(|i| p.az[i])
            .collect();
        let lateral: Vec<f32> = (0..p.len())
            .filter(|&i| (p.r[i] - (radius - inset)).abs() < 0.1 * dx && full_z(i))
            .map(|i| p.ar[i])
            .collect();
        assert!(front.len() > 5 && lateral.len() > 5);
        let push = front[0];
        assert!(push > 1.0e5, "front face, layer {layer}: a_z {push}");
        for a in front.iter().chain(&lateral) {
            assert!(
                (a / push - 1.0).abs() < 1e-3,
                "layer {layer}: a {a} against the front face's {push}"
            );
        }
    }
    let k = (0..p.len())
        .find(|&i| {
            (p.r[i] - (radius - 0.5 * dx)).abs() < 0.1 * dx && (p.z[i] + 0.5 * depth).abs() < dx
        })
        .unwrap();
    p.p[k] = 2.0e8;
    sph_forces::run(&mut p, &grid, &params, None);
    assert!(
        p.ar[k] > 1.0e6,
        "over-pressured surface particle: a_r {}",
        p.ar[k]
    );
}

/// A slug of particles next to the axis driven at 277 m/s into the rest of a free target (no
/// projectile, no fixed boundary): over 1500 steps of crushing, the kinetic energy lost is the
/// internal energy gained to 0.5 % of the impact energy. The energy is booked from the work of
/// the particle forces, split pairwise (`sph_forces`), so this checks that split, the hoop
/// sources' work, the leapfrog remainder and the axis constraint's loss. The strain-power
/// estimate of the same energy is printed beside it: it is not the dual of these forces. No
/// boundary acts, so the axial momentum is conserved to f32 round-off (1e-5 of the slug's).
#[test]
fn slug_impact_energy_closes() {
    slug_impact(spec(false));
}

/// The same with the Balsara switch: the scaled Π stays symmetric in the pair and its heating
/// is booked with it.
#[test]
fn slug_impact_energy_closes_with_the_balsara_switch() {
    slug_impact(TargetSpec {
        viscosity_switch: ViscositySwitch::Balsara,
        ..spec(false)
    });
}

/// The same with the reconstructed viscosity: Π from the reconstructed jump, still symmetric
/// in the pair, and its heating booked with it; the slug's front is a shock, so the
/// viscosity still acts there.
#[test]
fn slug_impact_energy_closes_with_the_reconstructed_viscosity() {
    slug_impact(TargetSpec {
        viscosity_jump: ViscosityJump::Reconstructed,
        ..spec(false)
    });
}

fn slug_impact(s: TargetSpec) {
    let (mut p, params) = target(&s);
    let slug = |p: &Particles, i: usize| p.r[i] < 0.012 && p.z[i] > -0.008;
    for i in 0..p.len() {
        if slug(&p, i) {
            p.vz[i] = -277.0;
        }
    }
    let ke = |p: &Particles| -> f64 {
        (0..p.len())
            .map(|i| 0.5 * p.mass[i] as f64 * (p.vr[i] as f64).hypot(p.vz[i] as f64).powi(2))
            .sum()
    };
    let sum = |p: &Particles, e: &[f32]| -> f64 {
        (0..p.len()).map(|i| p.mass[i] as f64 * e[i] as f64).sum()
    };
    let momentum = |p: &Particles| -> f64 {
        (0..p.len())
            .map(|i| p.mass[i] as f64 * p.vz[i] as f64)
            .sum()
    };
    let (e0, p0) = (ke(&p), momentum(&p));
    let mut grid = neighbours::CellGrid::default();
    let step = |p: &mut Particles, grid: &mut neighbours::CellGrid, dt: f32| {
        neighbours::run(grid, &p.r, &p.z, &params.kernel);
        sph_rates::run(p, grid, &params, None);
        concrete::run(p, &params, dt);
        sph_forces::run(p, grid, &params, None);
    };
    let mut dt = 0.3 * timestep::particle_dt(&p, &params);
    step(&mut p, &mut grid, dt);
    for _ in 0..1500 {
        integrate::particles(&mut p, &params, dt, 10.0).unwrap();
        step(&mut p, &mut grid, dt);
        dt = 0.3 * timestep::particle_dt(&p, &params);
    }
    let (k, e, strain) = (ke(&p), sum(&p, &p.energy), sum(&p, &p.strain_energy));
    let error = (k + e - e0) / e0;
    eprintln!(
        "slug: E0 {e0:.1} J, kinetic {k:.1}, internal {e:.1} (strain-power estimate {strain:.1}), error {error:.2e}"
    );
    assert!(
        e > 0.3 * e0,
        "too little crushing to test: internal {e} of {e0} J"
    );
    assert!(error.abs() < 5e-3, "energy error {error:e}");
    let drift = (momentum(&p) - p0) / p0;
    eprintln!("slug: axial momentum drift {drift:.2e}");
    assert!(drift.abs() < 1e-5, "axial momentum drift {drift:e}");
}

/// Whether particle i of the target `spec` lies two kernel supports inside its free faces and
/// off the axis, where the corrected gradient of a linear field is exact.
fn interior(spec: &TargetSpec, support: f64, p: &Particles, i: usize) -> bool {
    let (r, z) = (p.r[i] as f64, p.z[i] as f64);
    r > 2.0 * support
        && r + 2.0 * support < spec.radius
        && z + 2.0 * support < 0.0
        && z - 2.0 * support > -spec.thickness
}

/// The Balsara switch (`target.viscosity_switch = "balsara"`) on a free target at rest in
/// stress, with a prescribed velocity field, at the particles two supports inside the free faces
/// and off the axis (where the corrected gradient of a linear field is exact):
/// - a simple shear `v_z = γ r` (∇·v = 0, |∇×v| = γ) gets factors below 10⁻³ and viscous
///   heating below 10⁻³ of the unswitched one;
/// - a curl-free compression `v = (a r, b z)` gets Balsara's `|2a + b|/(|2a + b| + 10⁻⁴ c/h)`
///   (0.989 here) to 10⁻⁴, and the unswitched acceleration and heating times that factor to
///   10⁻³ of the largest.
#[test]
fn balsara_switch_removes_the_viscosity_from_shear_only() {
    let plain = spec(false);
    let switched = TargetSpec {
        viscosity_switch: ViscositySwitch::Balsara,
        ..spec(false)
    };
    let (p0, params_off) = target(&plain);
    let params_on = SphParams::new(&switched);
    assert!(params_on.balsara && !params_off.balsara);
    let mut grid = neighbours::CellGrid::default();
    neighbours::run(&mut grid, &p0.r, &p0.z, &params_off.kernel);
    let support = integrate::support(&params_off) as f64;
    let inner = |p: &Particles, i: usize| interior(&plain, support, p, i);
    let forces = |v: &dyn Fn(f32, f32) -> (f32, f32), params: &SphParams| {
        let mut p = p0.clone();
        for i in 0..p.len() {
            (p.vr[i], p.vz[i]) = v(p.r[i], p.z[i]);
        }
        sph_rates::run(&mut p, &grid, params, None);
        sph_forces::run(&mut p, &grid, params, None);
        p
    };
    let inside: Vec<usize> = (0..p0.len()).filter(|&i| inner(&p0, i)).collect();
    assert!(inside.len() > 20, "{} particles inside", inside.len());

    let gamma = 1.0e4f32;
    let shear = |r: f32, _z: f32| (0.0, gamma * r);
    let (off, on) = (forces(&shear, &params_off), forces(&shear, &params_on));
    let heat = |p: &Particles| inside.iter().map(|&i| p.de_visc[i] as f64).sum::<f64>();
    let largest = inside
        .iter()
        .map(|&i| on.visc_switch[i])
        .fold(0.0f32, f32::max);
    eprintln!(
        "shear: largest factor {largest:e}, heating {:e} switched vs {:e}",
        heat(&on),
        heat(&off)
    );
    assert!(largest < 1e-3, "largest factor in shear {largest}");
    assert!(
        heat(&off) > 0.0,
        "no viscous heating in the shear to remove"
    );
    assert!(heat(&on).abs() < 1e-3 * heat(&off), "heating left in shear");
    assert!(
        off.visc_switch.iter().all(|&f| f == 1.0),
        "switch off: factor 1"
    );

    let (a, b) = (-3.0e3f32, -5.0e3f32);
    let squeeze = |r: f32, z: f32| (a * r, b * z);
    let (off, on) = (forces(&squeeze, &params_off), forces(&squeeze, &params_on));
    let div = (2.0 * a + b).abs();
    let factor = div / (div + 1e-4 * p0.sound[0] / params_on.h);
    let spread = inside
        .iter()
        .map(|&i| (on.visc_switch[i] - factor).abs())
        .fold(0.0f32, f32::max);
    eprintln!("compression: factor {factor}, largest departure {spread:e}");
    // The axial pair terms of a uniform compression cancel to round-off in the interior, so
    // both components are measured against the largest acceleration.
    let largest = |v: &[f32]| inside.iter().map(|&i| v[i].abs()).fold(0.0f32, f32::max);
    let acc = largest(&off.ar).max(largest(&off.az));
    for (name, x, y, s) in [
        ("ar", &on.ar, &off.ar, acc),
        ("az", &on.az, &off.az, acc),
        ("de_visc", &on.de_visc, &off.de_visc, largest(&off.de_visc)),
    ] {
        assert!(s > 0.0, "{name} is zero in the compression");
        let e = inside
            .iter()
            .map(|&i| (x[i] - factor * y[i]).abs())
            .fold(0.0f32, f32::max)
            / s;
        eprintln!("compression: {name} differs from factor × unswitched by {e:e} of its largest");
        assert!(e < 1e-3, "{name} differs by {e} with the switch");
    }
}

/// The reconstructed viscosity (`target.viscosity_jump = "reconstructed"`) on the free target
/// at rest in stress, at the particles two supports inside the free faces and off the axis
/// (where the corrected gradient of a linear field is exact):
/// - a uniform compression `v = (a r, b z)`, smooth, gets viscous heating below 10⁻³ of the
///   raw jump's: each pair's approach is what both ends' gradients carry to the midpoint;
/// - a jump in `v_z` between two uniform states across a plane keeps more than half of the raw
///   jump's heating: the gradients the kernel smears over the jump carry the ends at most
///   about a spacing over the kernel's width (⅓ here) of the way to each other.
#[test]
fn reconstruction_takes_the_viscosity_out_of_a_smooth_compression_only() {
    let raw = spec(false);
    let reconstructed = TargetSpec {
        viscosity_jump: ViscosityJump::Reconstructed,
        ..spec(false)
    };
    let (p0, params_raw) = target(&raw);
    let params_rec = SphParams::new(&reconstructed);
    assert!(params_rec.reconstruct_viscosity && !params_raw.reconstruct_viscosity);
    let mut grid = neighbours::CellGrid::default();
    neighbours::run(&mut grid, &p0.r, &p0.z, &params_raw.kernel);
    let support = integrate::support(&params_raw) as f64;
    let inner = |p: &Particles, i: usize| interior(&raw, support, p, i);
    let heat = |v: &dyn Fn(f32, f32) -> (f32, f32), params: &SphParams| -> f64 {
        let mut p = p0.clone();
        for i in 0..p.len() {
            (p.vr[i], p.vz[i]) = v(p.r[i], p.z[i]);
        }
        sph_rates::run(&mut p, &grid, params, None);
        sph_forces::run(&mut p, &grid, params, None);
        (0..p.len())
            .filter(|&i| inner(&p0, i))
            .map(|i| p.mass[i] as f64 * p.de_visc[i] as f64)
            .sum()
    };

    let squeeze = |r: f32, z: f32| (-3.0e3 * r, -5.0e3 * z);
    let (off, on) = (heat(&squeeze, &params_raw), heat(&squeeze, &params_rec));
    eprintln!("smooth compression: heating {on:e} reconstructed vs {off:e} raw");
    assert!(off > 0.0, "no viscous heating in the compression");
    assert!(
        on.abs() < 1e-3 * off,
        "heating left in a smooth compression"
    );

    let middle = -0.5 * raw.thickness as f32;
    let jump = |_r: f32, z: f32| (0.0, if z > middle { -100.0 } else { 0.0 });
    let (off, on) = (heat(&jump, &params_raw), heat(&jump, &params_rec));
    eprintln!("jump: heating {on:e} reconstructed vs {off:e} raw");
    assert!(off > 0.0, "no viscous heating across the jump");
    assert!(
        on > 0.5 * off,
        "the jump lost its viscosity: {on:e} of {off:e}"
    );
    assert!(on <= off, "the reconstruction added heating");
}
