//! The whole step on the GPU against the CPU reference path (on lavapipe in CI). Without an
//! adapter these tests fail and say how to install one.

use std::path::{Path, PathBuf};

use penetrate::gpu::Gpu;
use penetrate::scene::{self, Backend, Scene};
use penetrate::solver::{self, Model, RunOptions, Simulation};

mod common;

fn case(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("cases")
        .join(name)
}

fn smoke(set: &[&str]) -> Scene {
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    scene::load(&case("smoke.toml"), &set).unwrap()
}

fn on_gpu(scene: &Scene) -> Simulation {
    let mut sim = Simulation::new(scene).unwrap();
    sim.use_gpu(gpu()).unwrap();
    sim
}

/// The adapter the tests run on (`PENETRATE_ADAPTER`, or the best one).
fn gpu() -> Gpu {
    let adapter = std::env::var("PENETRATE_ADAPTER").ok();
    Gpu::new(adapter.as_deref()).unwrap_or_else(|e| {
        panic!(
            "GPU test needs an adapter: {e}. Install Mesa's software Vulkan adapter \
             (Debian: apt-get install mesa-vulkan-drivers) or run `bash scripts/test`, which does."
        )
    })
}

/// Largest |a − b| over the field.
fn max_difference(a: &[f32], b: &[f32]) -> f32 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .fold(0.0f32, |m, (x, y)| m.max((x - y).abs()))
}

/// Largest |b| over the field.
fn scale(b: &[f32]) -> f32 {
    b.iter().fold(0.0f32, |m, x| m.max(x.abs()))
}

/// The state of `sim` after `steps` more steps.
fn run_steps(mut sim: Simulation, steps: usize) -> Model {
    for _ in 0..steps {
        sim.step().unwrap();
    }
    sim.into_model().unwrap()
}

/// After 300 steps of the coupled smoke scene at 1500 m/s (the nose is in the target, slaves
/// are being corrected, elements yield) the two paths agree field by field as closely as round-off lets
/// them.
///
/// Tolerance: each pass agrees with its CPU twin to ~1e-7 of the field's scale (the pass
/// tests), but the step carries round-off forward and the contact and the element stresses
/// amplify it (a stress is a difference of nearly equal nodal velocities, and already in free
/// flight f32 positions give the steel MPa of pressure noise). How far round-off alone moves
/// this scene is measured, not guessed: the CPU is run again with one ulp added to one of the
/// initial state's fields (the nodes' axial velocities or radii, the particles' positions;
/// the particles start at rest), four runs, and the GPU may depart from the CPU by at most 4×
/// the largest of their departures (the margin covers the sampling of a chaotic quantity),
/// plus 1e-6 of the field's scale. One nudge alone is too small a sample: on this scene the
/// concrete's deviator moves by 0.5–4.6 kPa from nudge to nudge.
#[test]
#[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
fn gpu_and_cpu_agree_after_300_coupled_steps() {
    // At 1500 m/s the nose yields (and takes damage) within the 300 steps; at 800 m/s the
    // nose, meshed without slivers, stays elastic that long.
    let scene = smoke(&["projectile.velocity=1500"]);
    let nudged = |field: fn(&mut Model) -> &mut Vec<f32>| {
        let mut sim = Simulation::new(&scene).unwrap();
        for v in field(sim.model_mut().unwrap()).iter_mut() {
            *v = f32::from_bits(v.to_bits() + 1);
        }
        run_steps(sim, 300)
    };
    let nudges = [
        nudged(|m| &mut m.projectile.nodes.vz),
        nudged(|m| &mut m.projectile.nodes.r),
        nudged(|m| &mut m.particles.z),
        nudged(|m| &mut m.particles.r),
    ];
    let cpu = run_steps(Simulation::new(&scene).unwrap(), 300);
    let gpu = run_steps(on_gpu(&scene), 300);
    assert!(cpu.last_hits > 0, "the test must exercise the contact");
    assert!(
        cpu.max_plastic_strain() > 0.0,
        "the test must exercise the plasticity"
    );
    assert!(
        (cpu.time - gpu.time).abs() < 1e-4 * cpu.time,
        "time {} vs {}",
        gpu.time,
        cpu.time
    );
    let fields = |s: &Model| -> Vec<(&'static str, Vec<f32>)> {
        let (p, n, e) = (&s.particles, &s.projectile.nodes, &s.projectile.elements);
        vec![
            ("particle r", p.r.clone()),
            ("particle z", p.z.clone()),
            ("particle vr", p.vr.clone()),
            ("particle vz", p.vz.clone()),
            ("particle p", p.p.clone()),
            ("particle s_rr", p.s_rr.clone()),
            ("particle s_zz", p.s_zz.clone()),
            ("particle damage", p.damage.clone()),
            ("node r", n.r.clone()),
            ("node z", n.z.clone()),
            ("node vr", n.vr.clone()),
            ("node vz", n.vz.clone()),
            ("element s_rr", e.s_rr.clone()),
            ("element s_zz", e.s_zz.clone()),
            ("element p", e.p.clone()),
            ("element eps_p", e.eps_p.clone()),
            ("element damage", e.damage.clone()),
        ]
    };
    let (want, got) = (fields(&cpu), fields(&gpu));
    let ulp: Vec<_> = nudges.iter().map(fields).collect();
    let mut report = Vec::new();
    for k in 0..want.len() {
        let name = want[k].0;
        let err = max_difference(&got[k].1, &want[k].1);
        let round_off = ulp
            .iter()
            .map(|u| max_difference(&u[k].1, &want[k].1))
            .fold(0.0, f32::max);
        let tol = 4.0 * round_off + 1e-6 * scale(&want[k].1);
        report.push(format!(
            "{name}: GPU−CPU {err:.3e}, largest one-ulp nudge {round_off:.3e} (scale {:.3e})",
            scale(&want[k].1)
        ));
        assert!(
            err <= tol,
            "{name}: {err:e} > {tol:e}\n{}",
            report.join("\n")
        );
    }
    eprintln!("{}", report.join("\n"));
}

/// The same scene on the same adapter gives bit-identical state twice.
#[test]
#[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
fn gpu_runs_are_bit_identical() {
    let scene = smoke(&[]);
    let a = run_steps(on_gpu(&scene), 200);
    let b = run_steps(on_gpu(&scene), 200);
    assert_eq!(a.time.to_bits(), b.time.to_bits());
    for (x, y) in [
        (&a.particles.r, &b.particles.r),
        (&a.particles.vz, &b.particles.vz),
        (&a.particles.p, &b.particles.p),
        (&a.projectile.nodes.z, &b.projectile.nodes.z),
        (&a.projectile.elements.s_zz, &b.projectile.elements.s_zz),
    ] {
        let xb: Vec<u32> = x.iter().map(|v| v.to_bits()).collect();
        let yb: Vec<u32> = y.iter().map(|v| v.to_bits()).collect();
        assert_eq!(xb, yb);
    }
}

/// From 33 mm in front of the face the model's origin moves with the projectile twice
/// (`solver::RECENTRE_STEP`: at the start, and again as the nose enters), on the GPU in the
/// step's second half as on the host: the depth, measured in the world, is the CPU's.
#[test]
#[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
fn gpu_moves_the_origin_as_the_cpu_does() {
    let dir = std::env::temp_dir().join(format!("penetrate-test-{}-origin", std::process::id()));
    let (cpu, gpu) = short_penetration(&["projectile.nose_z=0.033", "run.end_time=2e-4"], &dir);
    assert!(cpu.summary.depth_m > 0.0 && gpu.summary.depth_m > 0.0);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A short penetration run ends at the CPU's depth within 0.5 %, writes a summary that names
/// the GPU and lists each pass with its side, and books the contact's impulse, in all and on
/// the nose, as the CPU does.
#[test]
#[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
fn gpu_depth_matches_cpu_on_a_short_penetration() {
    let dir = std::env::temp_dir().join(format!("penetrate-test-{}-gpu", std::process::id()));
    let (cpu, gpu) = short_penetration(&[], &dir);
    let s = &gpu.summary;
    assert_eq!(s.backend, "gpu");
    assert!(
        s.passes.contains(&"contact_correct:cpu".to_string()),
        "{:?}",
        s.passes
    );
    assert!(
        s.passes.contains(&"sph_forces:gpu".to_string()),
        "{:?}",
        s.passes
    );
    assert!(
        s.passes.contains(&"fem_stress:gpu".to_string()),
        "{:?}",
        s.passes
    );
    let json = std::fs::read_to_string(dir.join("gpu").join("summary.json")).unwrap();
    assert!(json.contains("\"backend\": \"gpu\""));
    books_the_cpu_account(&cpu, &gpu);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The same with the velocity filter and the Balsara switch on (and the corrected gradient,
/// which the filter takes): the GPU's filter pass and its second gradient dispatch give the
/// CPU's depth within 0.5 %, and the filter moves the depth (or this would not test it).
#[test]
#[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
fn gpu_depth_matches_cpu_with_the_velocity_filter() {
    let dir =
        std::env::temp_dir().join(format!("penetrate-test-{}-gpu-filter", std::process::id()));
    let corrected = "target.velocity_gradient=\"corrected\"";
    let (cpu, _) = short_penetration(
        &[
            corrected,
            "target.velocity_filter=\"linear\"",
            "target.viscosity_switch=\"balsara\"",
        ],
        &dir,
    );
    let unfiltered = short_run(
        &smoke(&[
            "run.end_time=1e-4",
            corrected,
            "target.viscosity_switch=\"balsara\"",
        ]),
        &dir.join("unfiltered"),
        Backend::Cpu,
    );
    let (d, d0) = (cpu.summary.depth_m, unfiltered.summary.depth_m);
    eprintln!("short penetration: {d} m filtered, {d0} m unfiltered");
    assert!(d != d0, "the filter changes nothing");
    let _ = std::fs::remove_dir_all(&dir);
}

/// With the reconstructed viscosity: the GPU's second, corrected gather in `sph_rates` and the
/// reconstruction in `sph_forces` give the CPU's depth within 0.5 % and its account, and the
/// reconstruction moves the depth (or this would not test it).
#[test]
#[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
fn gpu_depth_matches_cpu_with_the_reconstructed_viscosity() {
    let dir = std::env::temp_dir().join(format!(
        "penetrate-test-{}-gpu-reconstructed",
        std::process::id()
    ));
    let (cpu, gpu) = short_penetration(&["target.viscosity_jump=\"reconstructed\""], &dir);
    books_the_cpu_account(&cpu, &gpu);
    let raw = short_run(
        &smoke(&["run.end_time=1e-4"]),
        &dir.join("raw"),
        Backend::Cpu,
    );
    let (d, d0) = (cpu.summary.depth_m, raw.summary.depth_m);
    eprintln!("short penetration: {d} m reconstructed, {d0} m raw");
    assert!(d != d0, "the reconstruction changes nothing");
    let _ = std::fs::remove_dir_all(&dir);
}

/// With Coulomb friction (μ = 0.3) too: the host's correction changes the slaves' and the
/// nodes' tangential velocities, which the GPU must take back whole; the run ends at the CPU's
/// depth within 0.5 % and books its account, and friction moves the depth.
#[test]
#[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
fn gpu_depth_matches_cpu_with_friction() {
    let dir = std::env::temp_dir().join(format!(
        "penetrate-test-{}-gpu-friction",
        std::process::id()
    ));
    let (cpu, gpu) = short_penetration(&["contact.friction=0.3"], &dir);
    books_the_cpu_account(&cpu, &gpu);
    let smooth = short_run(
        &smoke(&["run.end_time=1e-4"]),
        &dir.join("frictionless"),
        Backend::Cpu,
    );
    let (d, d0) = (gpu.summary.depth_m, smooth.summary.depth_m);
    eprintln!("short penetration: {d} m with friction (GPU), {d0} m without (CPU)");
    assert!(d < d0, "friction did not slow the shot: {d} m vs {d0} m");
    let _ = std::fs::remove_dir_all(&dir);
}

/// With the wall images: the GPU's walls, image gathers and segment sums give the CPU's depth
/// within 0.5 % and its account (the images' reaction booked with the contact's impulse, which
/// stays the projectile's momentum change on both paths), and the images move the depth.
#[test]
#[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
fn gpu_depth_matches_cpu_with_wall_images() {
    let dir =
        std::env::temp_dir().join(format!("penetrate-test-{}-gpu-images", std::process::id()));
    let (cpu, gpu) = short_penetration(&["contact.kernel=\"images\""], &dir);
    books_the_cpu_account(&cpu, &gpu);
    assert!(
        gpu.summary.passes.contains(&"walls:gpu".to_string()),
        "{:?}",
        gpu.summary.passes
    );
    let cut = short_run(
        &smoke(&["run.end_time=1e-4"]),
        &dir.join("cut"),
        Backend::Cpu,
    );
    let (d, d0) = (cpu.summary.depth_m, cut.summary.depth_m);
    eprintln!("short penetration: {d} m with images, {d0} m cut");
    assert!(d != d0, "the images change nothing");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A GPU run with wall images brings the segments' sums of the images' reaction back with its
/// state (what a checkpoint carries for the next integration), as the CPU makes them: the
/// images' total axial push on the projectile after 150 steps within 1 % of the CPU's (the
/// sums of one segment jump as particles take or lose their walls; their total does not).
#[test]
#[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
fn gpu_wall_sums_come_back_with_the_state() {
    let scene = smoke(&["contact.kernel=\"images\""]);
    let cpu = run_steps(Simulation::new(&scene).unwrap(), 150);
    let gpu = run_steps(on_gpu(&scene), 150);
    let axial = |m: &Model| -> f64 {
        assert_eq!(m.walls.sums.len(), m.projectile.masters.len());
        m.walls.sums.iter().map(|s| (s[1] + s[3]) as f64).sum()
    };
    let (c, g) = (axial(&cpu), axial(&gpu));
    eprintln!("the images' axial push after 150 steps: CPU {c} N, GPU {g} N");
    assert!(c.abs() > 0.0, "no image pushed");
    assert!(
        (g - c).abs() <= 0.01 * c.abs(),
        "GPU {g} N against CPU {c} N"
    );
}

/// The GPU run's energy error, contact impulse and nose impulse are the CPU's, and its contact
/// impulse is its projectile's momentum change.
fn books_the_cpu_account(cpu: &solver::RunOutcome, gpu: &solver::RunOutcome) {
    let s = &gpu.summary;
    // Which side set Δt: every step booked once, and the GPU's reduction decides as the CPU
    // does (the counts within a step or two where a near tie falls the other way).
    for t in [s, &cpu.summary] {
        assert_eq!(t.fem_limited_steps + t.sph_limited_steps, t.steps, "{t:?}");
    }
    assert!(
        s.fem_limited_steps.abs_diff(cpu.summary.fem_limited_steps) <= 2 + s.steps / 100,
        "steps the elements set: gpu {} of {}, cpu {} of {}",
        s.fem_limited_steps,
        s.steps,
        cpu.summary.fem_limited_steps,
        cpu.summary.steps
    );
    // Energy and momentum accounts come from the GPU's accumulators: same as the CPU's.
    assert!(
        (s.energy_error - cpu.summary.energy_error).abs() < 0.01,
        "energy error gpu {} cpu {}",
        s.energy_error,
        cpu.summary.energy_error
    );
    // The contact's axial impulse is the projectile's momentum change here too (the
    // correction's global shift reaches every node the GPU holds), and the CPU's within 0.5 %.
    let v0 = smoke(&[]).projectile.velocity;
    let change = s.projectile_mass_kg * (v0 - s.projectile_velocity_m_s);
    assert!(
        change > 0.0 && (s.contact_impulse_n_s - change).abs() < 1e-4 * change,
        "gpu contact impulse {} N s against the momentum change {change} N s",
        s.contact_impulse_n_s
    );
    let cpu_impulse = cpu.summary.contact_impulse_n_s;
    assert!(
        ((s.contact_impulse_n_s - cpu_impulse) / cpu_impulse).abs() < 0.005,
        "contact impulse gpu {} N s, cpu {cpu_impulse} N s",
        s.contact_impulse_n_s
    );
    // So is its nose's share.
    let (nose, cpu_nose) = (s.nose_impulse_n_s, cpu.summary.nose_impulse_n_s);
    assert!(
        nose > 0.0 && ((nose - cpu_nose) / cpu_nose).abs() < 0.005,
        "nose impulse gpu {nose} N s, cpu {cpu_nose} N s"
    );
}

/// The smoke scene to 0.1 ms (with `set`) on the CPU and on the GPU: both complete, the
/// projectile penetrates, and the depths agree within 0.5 %.
fn short_penetration(set: &[&str], dir: &Path) -> (solver::RunOutcome, solver::RunOutcome) {
    let mut all = vec!["run.end_time=1e-4"];
    all.extend_from_slice(set);
    let scene = smoke(&all);
    let cpu = short_run(&scene, &dir.join("cpu"), Backend::Cpu);
    let gpu = short_run(&scene, &dir.join("gpu"), Backend::Gpu);
    assert!(
        cpu.ok && gpu.ok,
        "{} / {}",
        cpu.summary.status,
        gpu.summary.status
    );
    let (dc, dg) = (cpu.summary.depth_m, gpu.summary.depth_m);
    assert!(dc > 0.02, "the projectile penetrates ({dc} m)");
    assert!(
        ((dg - dc) / dc).abs() < 0.005,
        "depth gpu {dg} m, cpu {dc} m"
    );
    (cpu, gpu)
}

fn short_run(scene: &Scene, out: &Path, backend: Backend) -> solver::RunOutcome {
    let mut opts = RunOptions::new(out.to_path_buf());
    opts.quiet = true;
    opts.vtk = false;
    opts.backend = Some(backend);
    opts.adapter = std::env::var("PENETRATE_ADAPTER").ok();
    solver::run(scene, &opts).unwrap()
}

/// A step that collapses on the GPU stops the run naming where, as on the CPU: the state is
/// brought back and the element or particle whose own stable step is the least is named.
#[test]
#[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
fn a_collapsed_gpu_step_names_where() {
    let mut sim = Simulation::new(&smoke(&[])).unwrap();
    for _ in 0..5 {
        sim.step().unwrap();
    }
    // A Courant number of 1e-7 makes every step about 1e-14 s: below what the run accepts.
    sim.model_mut().unwrap().scene.run.cfl = 1.0e-7;
    sim.use_gpu(gpu()).unwrap();
    let err = (0..3)
        .find_map(|_| sim.step().err())
        .expect("the step did not collapse")
        .to_string();
    assert!(err.contains("time step collapsed"), "{err}");
    common::assert_smallest_step_named(sim.model().unwrap(), &err);
}

/// A rigid projectile (λ = 0) builds no FEM passes on the GPU either, and the Taylor bars (no
/// target: no SPH or contact passes; copper has no damage model, so its stress pass is built
/// without the damage update) end at the CPU's length.
#[test]
#[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
fn gpu_builds_only_the_passes_a_scene_needs() {
    let rigid = smoke(&["contact.lambda=0"]);
    let passes = run_steps(on_gpu(&rigid), 50).pass_names("gpu");
    assert!(!passes.iter().any(|p| p.starts_with("fem_")), "{passes:?}");

    let set = vec![
        "projectile.element_size=0.001".to_string(),
        "run.end_time=2e-5".to_string(),
    ];
    for case_name in ["taylor-4340-208.toml", "taylor-copper-190.toml"] {
        let taylor = scene::load(&case(case_name), &set).unwrap();
        let until = |mut sim: Simulation| {
            while sim.time() < 2e-5 {
                sim.step().unwrap();
            }
            sim.into_model().unwrap()
        };
        let cpu = until(Simulation::new(&taylor).unwrap());
        let gpu = until(on_gpu(&taylor));
        let (lc, _) = cpu.projectile_extent();
        let (lg, _) = gpu.projectile_extent();
        assert!(
            ((lg - lc) / lc).abs() < 1e-4,
            "{case_name}: length gpu {lg} cpu {lc}"
        );
        assert!(
            cpu.max_plastic_strain() > 0.01,
            "{case_name}: the bar yields"
        );
        assert!(!gpu
            .pass_names("gpu")
            .iter()
            .any(|p| p.starts_with("sph") || p.starts_with("contact")));
    }
}

/// `bench` on the GPU: the host's share of a step (record, submit, wait, rest) partitions the
/// timed wall time, and the step waits for the GPU; the CPU path has no such split.
#[test]
#[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
fn bench_splits_the_gpu_step_on_the_host() {
    use penetrate::studies::bench;
    let adapter = std::env::var("PENETRATE_ADAPTER").ok();
    gpu();
    let case = case("forrestal1994-277.toml");
    let rows = bench::run(
        &case,
        &[1700],
        &[Backend::Gpu, Backend::Cpu],
        adapter.as_deref(),
        3,
        |_| {},
    )
    .unwrap();
    assert_eq!(rows.len(), 2);
    let gpu_row = &rows[0];
    assert!(gpu_row.refused.is_none(), "{:?}", gpu_row.refused);
    let [record, submit, wait, rest] = gpu_row.host_us.expect("a GPU row has the host split");
    assert!(
        record > 0.0 && submit > 0.0 && wait > 0.0 && rest >= 0.0,
        "{:?}",
        gpu_row.host_us
    );
    let sum = record + submit + wait + rest;
    assert!(
        (sum - 1e3 * gpu_row.ms_per_step).abs() < 1e-6 * sum,
        "{sum} µs against {} ms",
        gpu_row.ms_per_step
    );
    assert!(rows[1].host_us.is_none());
    // Building the lists adds the grid's passes to the step's dispatches.
    let (plain, building) = gpu_row.dispatches.expect("a GPU row counts its dispatches");
    assert!(
        plain > 0 && building > plain as f64,
        "{plain} and {building}"
    );
    assert!(rows[1].dispatches.is_none());
    // Every step reads back at least its Δt and status words; the CPU moves nothing.
    let (read, written) = gpu_row.step_bytes.expect("a GPU row counts its bytes");
    assert!(read > 0.0 && written >= 0.0, "{read} and {written}");
    assert!(rows[1].step_bytes.is_none());
    assert!(bench::table(&rows).contains(" / "));
}

/// A sweep stepped as a batch on one GPU (`--batch`) gives each run exactly what it gives
/// alone: history.csv and every frame to the byte. The runs end at different steps (the swept
/// key is the end time), so members leave the batch while others go on; a batch larger than
/// the sweep is handled (a CPU batch: `smoke.rs::a_cpu_batch_changes_no_run`).
#[test]
#[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
fn batched_sweep_runs_equal_their_solo_runs() {
    use penetrate::studies::sweep::{self, RunSettings, Vary};
    let root = std::env::temp_dir().join(format!("penetrate-batch-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    let vary = Vary::parse("run.end_time=2e-5:5e-5:1e-5").unwrap();
    let set = vec!["projectile.velocity=600".to_string()];
    let adapter = std::env::var("PENETRATE_ADAPTER").ok();
    let _ = gpu();
    let run = |batch: usize, name: &str| {
        let settings = RunSettings {
            adapter: adapter.clone(),
            vtk: true,
            batch,
            checkpoint: false,
            restart: false,
        };
        let out = root.join(name);
        let planned = sweep::plan_sweep(
            &case("smoke.toml"),
            &vary,
            &set,
            Some(Backend::Gpu),
            &settings,
            &out,
        )
        .unwrap();
        sweep::sweep(planned, &vary, &settings, &out, |_| {}).map(|_| out)
    };
    let solo = run(1, "solo").unwrap();
    let batched = run(3, "batched").unwrap();
    let wide = run(8, "wide").unwrap();
    let mut compared = 0;
    let members: Vec<_> = std::fs::read_dir(&solo)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_dir())
        .collect();
    assert_eq!(members.len(), 4, "{members:?}");
    for member in members.iter().map(|p| p.file_name().unwrap()) {
        let files: Vec<_> = std::fs::read_dir(solo.join(member))
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .filter(|f| f != "summary.json")
            .collect();
        assert!(files.iter().any(|f| f == "history.csv"), "{files:?}");
        for f in &files {
            let want = std::fs::read(solo.join(member).join(f)).unwrap();
            for other in [&batched, &wide] {
                let got = std::fs::read(other.join(member).join(f)).unwrap();
                assert!(got == want, "{member:?}/{f:?} differs from the solo run's");
                compared += 1;
            }
        }
    }
    assert!(compared > 8, "{compared} files compared");
    let _ = std::fs::remove_dir_all(&root);
}
