//! Short end-to-end runs of the shipped smoke case, and the command line's handling of bad input.
//!
//! One file past 800 lines on purpose: every file in tests/ is a binary of its own, linked
//! against the whole solver, so splitting it would add a link per piece to the fast tier.

use std::path::{Path, PathBuf};
use std::process::Command;

use penetrate::solver::{Entity, Instability, Model, RunError, Simulation, Unstable};
use penetrate::{scene, solver};

mod common;

fn case(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("cases")
        .join(name)
}

/// `penetrate run CASE --backend cpu --quiet --out DIR`, for the caller to add to.
fn cpu_run(case_name: &str, dir: &Path) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_penetrate"));
    command
        .args(["run", &case(case_name).display().to_string()])
        .args(["--backend", "cpu", "--quiet", "--out"])
        .arg(dir);
    command
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("penetrate-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// The shipped perforation case at twice its spacing and element size: the projectile leaves
/// the free-backed slab (the run stops on it, before its end time), slower than it struck,
/// with concrete thrown off the rear face, and the energy account closes.
#[test]
fn a_projectile_perforates_a_free_backed_slab() {
    let coarse = ["target.spacing=0.008", "projectile.element_size=0.006"].map(String::from);
    let scene = scene::load(&case("slab-perforation.toml"), &coarse).unwrap();
    let out = scratch("perforation");
    let outcome = common::run_cpu(&scene, &out, false);
    let s = &outcome.summary;
    assert!(outcome.ok, "status: {}", s.status);
    assert_eq!(s.stop_reason, penetrate::output::summary::PERFORATED);
    assert!(s.time_s < scene.run.end_time, "stopped at {} s", s.time_s);
    let striking = scene.projectile.velocity;
    assert!(
        s.projectile_velocity_m_s > 0.0 && s.projectile_velocity_m_s < striking,
        "residual velocity {} m/s, striking {striking}",
        s.projectile_velocity_m_s
    );
    assert!(s.rear_ejecta_kg > 0.0, "nothing left the rear face");
    assert!(s.energy_error < 0.01, "energy error {}", s.energy_error);
    eprintln!(
        "perforation: residual {:.1} m/s, rear ejecta {:.3} kg, front {:.3} kg",
        s.projectile_velocity_m_s, s.rear_ejecta_kg, s.front_ejecta_kg
    );
}

/// A short coupled run completes with finite fields and writes its outputs.
#[test]
fn smoke_case_runs_with_finite_fields() {
    let scene = scene::load(&case("smoke.toml"), &[]).unwrap();
    let out = scratch("smoke");
    let outcome = common::run_cpu(&scene, &out, true);
    let s = &outcome.summary;
    assert!(outcome.ok, "status: {}", s.status);
    assert_eq!(s.status, "completed");
    assert!(s.steps > 10);
    // The smoke projectile's elements set its steps, and the summary says which one.
    assert_eq!(s.fem_limited_steps + s.sph_limited_steps, s.steps);
    assert!(
        s.fem_limited_steps > 0,
        "{} of {}",
        s.fem_limited_steps,
        s.steps
    );
    assert!(
        s.smallest_step_at_end.starts_with("element "),
        "{}",
        s.smallest_step_at_end
    );
    for (name, v) in [
        ("depth", s.depth_m),
        ("velocity", s.projectile_velocity_m_s),
        ("energy_error", s.energy_error),
        ("momentum_error", s.momentum_error),
        ("max_damage", s.max_damage),
    ] {
        assert!(v.is_finite(), "{name} = {v}");
    }
    assert!(s.depth_m > 0.0, "the projectile entered the target");
    assert!(
        s.projectile_velocity_m_s < scene.projectile.velocity,
        "and was slowed down"
    );
    for f in [
        "summary.json",
        "history.csv",
        "frames.pvd",
        "target_00000.vtu",
        "projectile_00000.vtu",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    for key in [
        "depth_m",
        "projectile_velocity_m_s",
        "max_damage",
        "max_plastic_strain",
        "final_length_m",
        "max_radius_m",
        "steps",
        "particles",
        "elements",
        "wall_s",
        "backend",
        "adapter",
        "energy_error",
        "momentum_error",
        "passes",
        "status",
    ] {
        assert!(json.get(key).is_some(), "summary.json lacks {key}");
    }
    // The last target frame's particle masses sum its specific energies to the summary's
    // target energies (f32 in the frame).
    let last = (0..)
        .map(|k| out.join(format!("target_{k:05}.vtu")))
        .take_while(|f| f.is_file())
        .last()
        .unwrap();
    let frame = penetrate::output::vtk::read_vtu(&last).unwrap();
    let field = |name: &str| -> Vec<f64> {
        let values = frame.point_field(name).unwrap();
        values.iter().map(|&v| v as f64).collect()
    };
    let mass = field("mass");
    assert_eq!(mass.len(), s.particles);
    let total = |name: &str| -> f64 { mass.iter().zip(field(name)).map(|(m, e)| m * e).sum() };
    for (name, expected) in [
        ("energy", s.energy.internal_target),
        ("strain_energy", s.energy.strain_energy_target),
    ] {
        let summed = total(name);
        assert!(
            (summed - expected).abs() <= 1e-5 * expected.abs(),
            "Σ mass·{name} = {summed} J against {expected} J"
        );
    }
    let _ = std::fs::remove_dir_all(&out);
}

/// `history.csv` carries the projectile's plastic work: it never falls (each element's increment
/// σ_y Δε_p V ≥ 0), and its last row, written after the final sync, is the summary's. At 800 m/s
/// the smoke scene's nose yields by 0.1 ms. The cells' pressure checkerboard is there too, and
/// its last row is the summary's. So is the contact's axial impulse, which is the projectile's
/// momentum change, and its mean force between rows, in all and on the nose, and the body's
/// extent, the summary's on the last row.
#[test]
fn history_carries_the_plastic_work_the_checkerboard_and_the_contact_load() {
    let set = [
        "projectile.velocity=800".to_string(),
        "run.end_time=1e-4".to_string(),
    ];
    let scene = scene::load(&case("smoke.toml"), &set).unwrap();
    let out = scratch("history-work");
    let outcome = common::run_cpu(&scene, &out, false);
    assert!(outcome.ok, "status: {}", outcome.summary.status);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let column_of = |name: &str| common::history_column(&out, name);
    let work = column_of("plastic_work_J");
    assert!(work.windows(2).all(|w| w[1] >= w[0]), "{work:?}");
    let last = *work.last().unwrap();
    assert!(last > 0.0, "the nose yields: {last} J");
    assert_eq!(
        last,
        json["energy"]["plastic_work_projectile"].as_f64().unwrap()
    );
    // The body's extent: the mesh's at rest on the first row, the summary's on the last.
    let (length, radius) = (
        column_of("projectile_length_m"),
        column_of("projectile_radius_m"),
    );
    assert!((length[0] - 0.06).abs() < 1e-7 && (radius[0] - 0.01).abs() < 1e-7);
    assert_eq!(
        *length.last().unwrap(),
        json["final_length_m"].as_f64().unwrap()
    );
    assert_eq!(
        *radius.last().unwrap(),
        json["max_radius_m"].as_f64().unwrap()
    );
    let checkerboard = column_of("checkerboard_Pa");
    assert!(checkerboard.iter().all(|&c| c.is_finite() && c >= 0.0));
    assert_eq!(
        *checkerboard.last().unwrap(),
        json["checkerboard_pa"].as_f64().unwrap()
    );
    // The contact is the only axial load on the projectile (its own forces sum to zero along
    // z), so the impulse it booked is the projectile's momentum change, M (v₀ − v), to
    // round-off, and the force column integrates back to that impulse.
    let impulse = column_of("contact_impulse_Ns");
    let total = json["contact_impulse_n_s"].as_f64().unwrap();
    assert_eq!(*impulse.last().unwrap(), total);
    let mass = json["projectile_mass_kg"].as_f64().unwrap();
    let change = mass * (800.0 - json["projectile_velocity_m_s"].as_f64().unwrap());
    assert!(change > 1.0, "the projectile slowed: {change} N s");
    assert!(
        (total - change).abs() < 1e-4 * change,
        "contact impulse {total} N s against the momentum change {change} N s"
    );
    let (time, force) = (column_of("time_s"), column_of("contact_force_N"));
    assert_eq!(force[0], 0.0);
    let integral: f64 = (1..time.len())
        .map(|k| force[k] * (time[k] - time[k - 1]))
        .sum();
    assert!(
        (integral - total).abs() < 1e-9 * total,
        "∫F dt {integral} against {total} N s"
    );
    // The nose's share: all of it until the shank reaches the target's face (no hit yet on
    // a segment behind the junction); it never falls (every point of the nose faces forward,
    // n_z < 0, so each of its hits adds −m_S δ n_z > 0; a shank's or tail's hit may push
    // either way), and its force column integrates back to it too.
    let nose = column_of("nose_impulse_Ns");
    let depth = column_of("depth_m");
    let nose_length = scene::ogive_nose_length(0.02, 2.0);
    let entered = depth
        .iter()
        .filter(|&&d| d > 0.0 && d < nose_length)
        .count();
    assert!(entered > 2, "rows with only the nose in: {entered}");
    for k in 0..nose.len() {
        if depth[k] < nose_length {
            assert_eq!(nose[k], impulse[k], "row {k}, depth {} m", depth[k]);
        }
        assert!(
            k == 0 || nose[k] >= nose[k - 1],
            "row {k}: the nose's impulse fell to {} N s",
            nose[k]
        );
    }
    assert_eq!(
        *nose.last().unwrap(),
        json["nose_impulse_n_s"].as_f64().unwrap()
    );
    let nose_force = column_of("nose_force_N");
    let nose_integral: f64 = (1..time.len())
        .map(|k| nose_force[k] * (time[k] - time[k - 1]))
        .sum();
    let nose_total = *nose.last().unwrap();
    assert!(
        (nose_integral - nose_total).abs() < 1e-9 * nose_total,
        "∫F_nose dt {nose_integral} against {nose_total} N s"
    );
    let _ = std::fs::remove_dir_all(&out);
}

/// λ = 0: the projectile moves rigidly (no stress pass, all nodes with one velocity, zero
/// strain) while the target is pushed.
#[test]
fn lambda_zero_projectile_is_rigid() {
    let scene = scene::load(&case("smoke.toml"), &["contact.lambda=0".to_string()]).unwrap();
    let mut sim = Simulation::new(&scene).unwrap();
    for _ in 0..300 {
        sim.step().unwrap();
    }
    let sim = sim.into_model().unwrap();
    assert!(sim.account.contact_dissipated > 0.0, "contact happened");
    let n = &sim.projectile.nodes;
    assert!(n.vr.iter().all(|&v| v == 0.0));
    assert!(
        n.vz.iter().all(|&v| v == n.vz[0]),
        "one velocity for every node"
    );
    assert!(n.vz[0] > -(scene.projectile.velocity as f32), "slowed down");
    assert_eq!(sim.max_plastic_strain(), 0.0);
    assert!(!sim
        .pass_names("cpu")
        .iter()
        .any(|p| p.starts_with("fem_stress")));
    // Without element stresses the particles set every step.
    assert_eq!(
        (sim.account.fem_limited_steps, sim.account.sph_limited_steps),
        (0, 300)
    );
}

/// Coulomb friction at the sliding surface (μ = 0.3) drags on the nose: the smoke shot ends
/// shallower and slower than the frictionless one, its contact takes a larger axial impulse,
/// which is still the projectile's momentum change, and the energy balance still closes (the
/// friction's loss is booked with the contact's).
#[test]
fn friction_slows_the_smoke_shot_and_keeps_the_energy_balance() {
    let run = |mu: &str| {
        let scene = scene::load(&case("smoke.toml"), &[format!("contact.friction={mu}")]).unwrap();
        let out = scratch(&format!("friction-{mu}"));
        let outcome = common::run_cpu(&scene, &out, false);
        let _ = std::fs::remove_dir_all(&out);
        assert!(outcome.ok, "μ {mu}: {}", outcome.summary.status);
        (scene, outcome.summary)
    };
    let (_, smooth) = run("0");
    let (scene, rough) = run("0.3");
    assert!(
        rough.depth_m < smooth.depth_m,
        "depth {} m with friction, {} m without",
        rough.depth_m,
        smooth.depth_m
    );
    assert!(rough.projectile_velocity_m_s < smooth.projectile_velocity_m_s);
    assert!(rough.contact_impulse_n_s > smooth.contact_impulse_n_s);
    assert!(rough.energy.contact_dissipated > smooth.energy.contact_dissipated);
    let change =
        rough.projectile_mass_kg * (scene.projectile.velocity - rough.projectile_velocity_m_s);
    assert!(
        (rough.contact_impulse_n_s - change).abs() < 1e-3 * change,
        "contact impulse {} N s against the momentum change {change} N s",
        rough.contact_impulse_n_s
    );
    for s in [&smooth, &rough] {
        assert!(s.energy_error.abs() < 0.01, "{}", s.energy_error);
    }
}

/// The wall images complete the lining's kernel and hand their reaction to the projectile: the
/// smoke shot with them ends at another depth, the contact's impulse (the images' reaction
/// booked with the correction's) is still the projectile's momentum change, the model's
/// momentum and energy still close, and the images take load off the correction.
#[test]
fn wall_images_push_on_the_projectile_and_keep_the_balances() {
    let run = |kernel: &str| {
        let set = [format!("contact.kernel=\"{kernel}\"")];
        let scene = scene::load(&case("smoke.toml"), &set).unwrap();
        let out = scratch(&format!("kernel-{kernel}"));
        let outcome = common::run_cpu(&scene, &out, false);
        let _ = std::fs::remove_dir_all(&out);
        assert!(outcome.ok, "{kernel}: {}", outcome.summary.status);
        (scene, outcome.summary)
    };
    let (_, cut) = run("cut");
    let (scene, images) = run("images");
    eprintln!(
        "depth {} m with images, {} m cut; contact dissipated {} J, {} J",
        images.depth_m,
        cut.depth_m,
        images.energy.contact_dissipated,
        cut.energy.contact_dissipated
    );
    assert!(images.depth_m != cut.depth_m, "the images change nothing");
    assert!(
        images.energy.contact_dissipated < cut.energy.contact_dissipated,
        "the images leave the correction as much to do"
    );
    let change =
        images.projectile_mass_kg * (scene.projectile.velocity - images.projectile_velocity_m_s);
    assert!(
        (images.contact_impulse_n_s - change).abs() < 1e-3 * change,
        "contact impulse {} N s against the momentum change {change} N s",
        images.contact_impulse_n_s
    );
    assert!(
        images.momentum_error.abs() < 1e-5,
        "{}",
        images.momentum_error
    );
    assert!(images.energy_error.abs() < 0.01, "{}", images.energy_error);
}

/// The projectile's yielding is set by its load, not by the step: the smoke scene at 1500 m/s
/// to 0.1 ms at CFL 0.25 and 0.125 puts the same plastic work into the projectile to well
/// within what a step-made share would change (halving the step would halve it): 1.33 and
/// 1.50 J. Before the contact carried its velocity change into the node positions, CFL 0.5 and
/// 0.25 gave 33.7 J and 13.5 J. The test struck at 800 m/s until the nose was meshed in layers,
/// whose nose stays elastic at that speed (no work to compare); the pair compared is the finer
/// one because the work converges as the step shrinks (docs/limitations.md, "The nose cell's
/// mode").
#[test]
#[ignore = "full tier: long run (bash scripts/test)"]
fn projectile_plastic_work_does_not_depend_on_the_step() {
    let plastic_work = |cfl: &str| {
        let set = [
            "projectile.velocity=1500".to_string(),
            "run.end_time=1e-4".to_string(),
            format!("run.cfl={cfl}"),
        ];
        let scene = scene::load(&case("smoke.toml"), &set).unwrap();
        let mut sim = Simulation::new(&scene).unwrap();
        while sim.time() < scene.run.end_time {
            sim.step().unwrap();
        }
        let sim = sim.into_model().unwrap();
        (sim.account.plastic_work, sim.max_plastic_strain())
    };
    let (coarse, coarse_strain) = plastic_work("0.25");
    let (fine, fine_strain) = plastic_work("0.125");
    assert!(fine > 0.0 && fine_strain > 0.0, "the nose yields: {fine} J");
    assert!(
        (coarse - fine).abs() < 0.15 * fine,
        "plastic work {coarse} J at CFL 0.25 against {fine} J at 0.125"
    );
    assert!(
        (coarse_strain - fine_strain).abs() < 0.15 * fine_strain,
        "largest plastic strain {coarse_strain} at CFL 0.25 against {fine_strain} at 0.125"
    );
}

/// A lead hole: the particles inside it are left out (and `check` counts them out), the nose
/// starts at its bottom, and the projectile meets the concrete there (no earlier); the depth is
/// still measured from z = 0.
#[test]
fn projectile_starts_down_a_lead_hole() {
    let hole = 0.02;
    let whole = Simulation::new(&scene::load(&case("smoke.toml"), &[]).unwrap())
        .unwrap()
        .into_model()
        .unwrap();
    let scene = scene::load(
        &case("smoke.toml"),
        &[format!("target.lead_hole_depth={hole}")],
    )
    .unwrap();
    let mut sim = Simulation::new(&scene).unwrap();
    let radius = 0.5 * scene.projectile.diameter as f32;
    let p = &sim.model().unwrap().particles;
    assert!((0..p.len()).all(|i| p.r[i] >= radius || p.z[i] <= -hole as f32));
    let removed = in_hole(&whole, radius, hole);
    assert!(removed > 0);
    assert_eq!(p.len(), whole.particles.len() - removed);
    // `penetrate check` counts the same particles before anything is built.
    assert_eq!(penetrate::estimate::footprint(&scene).particles, p.len());
    let spacing = scene.target.as_ref().unwrap().spacing;
    assert!((sim.model().unwrap().depth() - (hole - 0.25 * spacing)).abs() < 1e-6);
    let mut first_hit_depth = None;
    for _ in 0..300 {
        sim.step().unwrap();
        let m = sim.model().unwrap();
        if first_hit_depth.is_none() && m.last_hits > 0 {
            first_hit_depth = Some(m.depth());
        }
    }
    let sim = sim.into_model().unwrap();
    let first = first_hit_depth.expect("the nose meets the concrete at the bottom");
    // The first row left is at hole + Δ/2 (no hit before the nose passes the hole's bottom);
    // the sharp tip must pass it by about 1.4 mm more before a particle centre lies inside it.
    assert!(first > hole && first < hole + 2.0 * spacing, "{first}");
    assert!(
        sim.projectile_velocity() < scene.projectile.velocity,
        "slowed down"
    );
    assert!(sim.energy_error().abs() < 0.01, "{}", sim.energy_error());
}

/// Particles of an undrilled target whose centres lie in a hole `radius` wide and `hole` deep.
fn in_hole(whole: &Model, radius: f32, hole: f64) -> usize {
    let p = &whole.particles;
    (0..p.len())
        .filter(|&i| p.r[i] < radius && p.z[i] > -hole as f32)
        .count()
}

/// A pilot hole narrower than the projectile: its particles are left out (and `check` counts
/// them out), and the nose starts at the face and meets the concrete round the hole.
#[test]
fn a_pilot_hole_leaves_the_nose_at_the_face() {
    let hole = 0.02;
    let diameter = 0.01;
    let whole = Simulation::new(&scene::load(&case("smoke.toml"), &[]).unwrap())
        .unwrap()
        .into_model()
        .unwrap();
    let scene = scene::load(
        &case("smoke.toml"),
        &[
            format!("target.lead_hole_depth={hole}"),
            format!("target.lead_hole_diameter={diameter}"),
        ],
    )
    .unwrap();
    let mut sim = Simulation::new(&scene).unwrap();
    let radius = 0.5 * diameter as f32;
    let removed = in_hole(&whole, radius, hole);
    assert!(removed > 0);
    let m = sim.model().unwrap();
    assert_eq!(m.particles.len(), whole.particles.len() - removed);
    assert_eq!(
        penetrate::estimate::footprint(&scene).particles,
        m.particles.len()
    );
    assert_eq!(m.depth(), whole.depth());
    let mut first_hit_depth = None;
    for _ in 0..1500 {
        sim.step().unwrap();
        let m = sim.model().unwrap();
        if m.last_hits > 0 {
            first_hit_depth = Some(m.depth());
            break;
        }
    }
    // The ogive's flank meets the hole's wall before the tip reaches the hole's bottom: it
    // reaches the first column outside the hole (r = 6.25 mm) 9.6 mm behind the tip (CRH 2,
    // 20 mm), so the tip goes about that far down the hole first (10.8 mm measured).
    let first = first_hit_depth.expect("the nose meets the concrete round the hole");
    assert!(first > 0.4 * hole && first < hole, "{first}");
}

/// `max_damage_shank` and `max_plastic_strain_shank` read the elements that started behind the
/// nose only: a failed, strained nose element leaves them at 0, a damaged, strained shank
/// element sets them.
#[test]
fn shank_damage_leaves_the_nose_out() {
    let scene = scene::load(&case("smoke.toml"), &[]).unwrap();
    let mut sim = Simulation::new(&scene).unwrap().into_model().unwrap();
    let spec = &scene.projectile;
    let scene::ProjectileShape::Ogive { crh } = spec.shape else {
        panic!("the smoke projectile is an ogive")
    };
    let join = (spec.nose_z + scene::ogive_nose_length(spec.diameter, crh)) as f32;
    let (n, e) = (&sim.projectile.nodes, &sim.projectile.elements);
    let centroid = |k: usize| e.nodes[k].iter().map(|&i| n.z[i as usize]).sum::<f32>() / 3.0;
    let nose = (0..e.len()).find(|&k| centroid(k) < join).unwrap();
    let shank = (0..e.len()).find(|&k| centroid(k) > join).unwrap();
    // (whole projectile, behind the nose) for damage, then plastic strain.
    let maxima = |sim: &Model| {
        [
            (sim.max_damage(), sim.max_damage_shank()),
            (sim.max_plastic_strain(), sim.max_plastic_strain_shank()),
        ]
    };
    sim.projectile.elements.damage[nose] = 1.0;
    sim.projectile.elements.eps_p[nose] = 2.0;
    assert_eq!(maxima(&sim), [(1.0, 0.0), (2.0, 0.0)]);
    sim.projectile.elements.damage[shank] = 0.5;
    sim.projectile.elements.eps_p[shank] = 0.25;
    assert_eq!(maxima(&sim), [(1.0, 0.5), (2.0, 0.25)]);
}

/// f32 positions far from the model's z = 0 round a step's motion coarsely, and a node's
/// rounding, different from its neighbours', strains the elements without any force. The
/// model's origin therefore follows the projectile (`solver::RECENTRE_STEP`): flying free from
/// 1 m in front of the face, the projectile is brought near z = 0 and its elements' pressure
/// stays what it is from 20 mm, where without the re-centring the rounding of z ≈ 1 m
/// (1.2e-7 m, a strain of 5e-5 in a 2.5 mm element each step) raised it tenfold.
#[test]
fn the_origin_follows_the_projectile_so_distance_adds_no_strain() {
    let flight = |standoff: f64| {
        let set = [format!("projectile.nose_z={standoff}")];
        let scene = scene::load(&case("smoke.toml"), &set).unwrap();
        let mut sim = Simulation::new(&scene).unwrap();
        for _ in 0..300 {
            sim.step().unwrap();
        }
        let m = sim.into_model().unwrap();
        let e = &m.projectile.elements;
        let p_max = e.p.iter().fold(0.0f32, |a, p| a.max(p.abs()));
        let z_far = m
            .projectile
            .nodes
            .z
            .iter()
            .fold(0.0f32, |a, z| a.max(z.abs()));
        let tip = standoff - m.time * 300.0;
        (p_max, z_far, m.depth(), tip, m.last_hits)
    };
    let (near, _, _, near_tip, near_hits) = flight(0.02);
    let (far, z_far, depth, tip, hits) = flight(1.0);
    assert!(hits == 0 && near_hits == 0 && near_tip > 0.0, "free flight");
    assert_eq!(depth, 0.0, "{tip} m in front of the face");
    assert!(
        z_far < 0.06 + 0.0313,
        "the model keeps the projectile near z = 0: {z_far} m"
    );
    assert!(
        far < 2.0 * near + 1.0e5,
        "pressure from 1 m {far} Pa, from 1 mm {near} Pa"
    );
}

/// The smoke scene 50 steps in, and its deepest projectile node.
fn smoke_after_50_steps() -> (scene::Scene, Model, usize) {
    let scene = scene::load(&case("smoke.toml"), &[]).unwrap();
    let mut sim = Simulation::new(&scene).unwrap();
    for _ in 0..50 {
        sim.step().unwrap();
    }
    let sim = sim.into_model().unwrap();
    let n = &sim.projectile.nodes;
    let tip = (0..n.len())
        .min_by(|&a, &b| n.z[a].total_cmp(&n.z[b]))
        .unwrap();
    (scene, sim, tip)
}

/// Depth and extent follow the body, not its debris: a nose node whose elements have all failed
/// and which has run 0.3 m ahead (as a light nose node did in a 800 m/s shot) moves neither;
/// the same node still held by one element that has not failed moves both.
#[test]
fn depth_ignores_nodes_of_failed_elements_only() {
    let (scene, mut sim, tip) = smoke_after_50_steps();
    let (depth, extent) = (sim.depth(), sim.projectile_extent());
    let n = &sim.projectile.nodes;
    let refs: Vec<usize> = n.elem_refs
        [n.elem_offsets[tip] as usize..n.elem_offsets[tip + 1] as usize]
        .iter()
        .map(|&e| e as usize / 3)
        .collect();
    assert!(!refs.is_empty());
    sim.projectile.nodes.z[tip] -= 0.3;
    for &e in &refs {
        sim.projectile.elements.failed[e] = 1;
    }
    // The next deepest node is at most one element behind the old tip.
    let element = scene.projectile.element_size;
    assert!(sim.depth() <= depth && sim.depth() > depth - 2.0 * element);
    assert!(sim.projectile_extent().0 <= extent.0);
    sim.projectile.elements.failed[refs[0]] = 0;
    assert!((sim.depth() - (depth + 0.3)).abs() < 1e-6);
    assert!((sim.projectile_extent().0 - (extent.0 + 0.3)).abs() < 1e-6);
}

/// A failed element stretched open (beyond `OPEN_RELATIVE_VOLUME` of its reference volume)
/// exerts no force, not even the bulk viscosity of a compression, and limits the step only by
/// the time it would take to close: not at all at rest, and under a compression by more than
/// the step of a closed element. A failed element less open, and an intact one as open, keep
/// their forces and the usual step.
#[test]
fn an_open_failed_element_exerts_nothing_and_sets_no_step() {
    use penetrate::cpu::fem_stress::{self, OPEN_RELATIVE_VOLUME};
    use penetrate::mesh::geometry::Geometry;
    let scene = scene::load(&case("smoke.toml"), &[]).unwrap();
    let sim = Simulation::new(&scene).unwrap().into_model().unwrap();
    let at_rest = sim.projectile.nodes.clone();
    let mut squeezed = at_rest.clone();
    let z_mid = squeezed.z.iter().sum::<f32>() / squeezed.len() as f32;
    // A uniform compression at 10⁴ s⁻¹: every element's volume shrinks.
    for i in 0..squeezed.len() {
        squeezed.vr[i] = -1.0e4 * squeezed.r[i];
        squeezed.vz[i] = -1.0e4 * (squeezed.z[i] - z_mid);
    }
    let (open, ajar, intact) = (0, 1, 2);
    let mut before = sim.projectile.elements.clone();
    for (k, factor) in [
        (open, OPEN_RELATIVE_VOLUME + 0.1),
        (ajar, 0.5 * (1.0 + OPEN_RELATIVE_VOLUME)),
        (intact, OPEN_RELATIVE_VOLUME + 0.1),
    ] {
        let g = Geometry::new(&before.nodes[k], &at_rest.r, &at_rest.z);
        before.volume0[k] = g.volume() / factor;
    }
    for k in [open, ajar] {
        before.failed[k] = 1;
        before.damage[k] = 1.0;
    }
    let mut rest = before.clone();
    fem_stress::run(&mut rest, &at_rest, &sim.fem, sim.dt).unwrap();
    assert_eq!(rest.force[open], [0.0; 6]);
    assert_eq!(rest.dt[open], f32::MAX);

    let mut e = before.clone();
    fem_stress::run(&mut e, &squeezed, &sim.fem, sim.dt).unwrap();
    assert_eq!(e.force[open], [0.0; 6]);
    assert_eq!(e.p[open], 0.0);
    for k in [ajar, intact] {
        assert!(
            e.dt[k] > 0.0 && e.dt[k] < 1.0e-5,
            "element {k}: step {:e}",
            e.dt[k]
        );
        assert!(
            e.force[k].iter().any(|&f| f != 0.0),
            "element {k}: no force"
        );
    }
    assert!(
        e.dt[open] > e.dt[ajar] && e.dt[open] < 1.0e-3,
        "open: step {:e}",
        e.dt[open]
    );
    // The ajar element's force is its bulk viscosity alone: the pressure is cut off.
    assert_eq!(e.p[ajar], 0.0);
}

/// A bar with no target, at rest, whose every element has failed and opened has nothing left
/// to limit its step: the run stops and says so, rather than take a step of 10³⁸ s.
#[test]
fn nothing_left_to_limit_the_step_stops_the_run() {
    use penetrate::cpu::fem_stress::OPEN_RELATIVE_VOLUME;
    use penetrate::mesh::geometry::Geometry;
    let scene = scene::load(&case("taylor-4340-208.toml"), &[]).unwrap();
    let mut sim = Simulation::new(&scene).unwrap();
    sim.step().unwrap();
    let m = sim.model_mut().unwrap();
    // At rest and unloaded, so that no element is closing.
    let nodes = &mut m.projectile.nodes;
    for field in [&mut nodes.vr, &mut nodes.vz, &mut nodes.fr, &mut nodes.fz] {
        field.iter_mut().for_each(|v| *v = 0.0);
    }
    let n = m.projectile.nodes.clone();
    let e = &mut m.projectile.elements;
    for k in 0..e.len() {
        let v = Geometry::new(&e.nodes[k], &n.r, &n.z).volume();
        e.volume0[k] = v / (OPEN_RELATIVE_VOLUME + 0.5);
        e.failed[k] = 1;
    }
    let mut stopped = None;
    for _ in 0..3 {
        if let Err(err) = sim.step() {
            stopped = Some(err.to_string());
            break;
        }
    }
    let message = stopped.expect("the run went on");
    assert!(
        message.contains("nothing limits the time step")
            && message.contains("every element of the projectile has failed and opened"),
        "{message}"
    );
}

/// A step over 1 s with the elements whole (a bar at rest whose waves crawl: E = 1e-9 Pa) is
/// not blamed on failed elements: the message names the element with the least stable step.
#[test]
fn an_unbounded_step_of_whole_elements_names_where() {
    let dir = scratch("slow-waves");
    let out = cpu_run("taylor-copper-190.toml", &dir)
        .arg("--no-vtk")
        .args(["--set", "projectile.velocity=0"])
        .args(["--set", "projectile.material.youngs_modulus=1e-9"])
        // Its strength below that modulus, as the scene checks ask.
        .args(["--set", "projectile.material.za_c0=1e-10"])
        .args(["--set", "projectile.material.za_c2=0"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("nothing limits the time step")
            && err.contains("more than 1 s: element")
            && err.contains("has the smallest stable step")
            && !err.contains("failed and opened"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A piece of the nose still intact but held to the body only by failed elements (a tip
/// broken off, as in a 1000 m/s shot at the ×0.75 mesh) is debris: running 0.3 m ahead it
/// moves neither the depth nor the extent.
#[test]
fn depth_ignores_an_intact_piece_broken_off() {
    let (scene, mut sim, tip) = smoke_after_50_steps();
    let (depth, extent) = (sim.depth(), sim.projectile_extent());
    let n = &sim.projectile.nodes;
    let piece = n.elem_refs[n.elem_offsets[tip] as usize] as usize / 3;
    let corners = sim.projectile.elements.nodes[piece];
    // Fail every other element touching the piece's corners.
    for k in 0..sim.projectile.elements.len() {
        let touches = sim.projectile.elements.nodes[k]
            .iter()
            .any(|c| corners.contains(c));
        if k != piece && touches {
            sim.projectile.elements.failed[k] = 1;
        }
    }
    for &c in &corners {
        sim.projectile.nodes.z[c as usize] -= 0.3;
    }
    let element = scene.projectile.element_size;
    assert!(sim.depth() <= depth && sim.depth() > depth - 3.0 * element);
    assert!(sim.projectile_extent().0 <= extent.0);
}

/// Bad input on the command line: exit code 2, a one-line message naming the file, no panic.
#[test]
fn cli_rejects_bad_input_without_panicking() {
    let bin = env!("CARGO_BIN_EXE_penetrate");
    let dir = scratch("cli");
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.toml");
    let text = std::fs::read_to_string(case("smoke.toml"))
        .unwrap()
        .replace("velocity = 300", "velocity = -300");
    assert!(
        text.contains("velocity = -300"),
        "smoke.toml changed shape: update this test"
    );
    std::fs::write(&bad, text).unwrap();
    for args in [
        vec!["run".to_string(), bad.display().to_string()],
        vec!["check".to_string(), bad.display().to_string()],
        vec![
            "run".to_string(),
            case("smoke.toml").display().to_string(),
            "--set".into(),
            "target.fcc=3".into(),
        ],
        vec![
            "run".to_string(),
            dir.join("missing.toml").display().to_string(),
        ],
        // Valid, but far beyond any machine: refused up front with the estimate.
        vec![
            "run".to_string(),
            case("smoke.toml").display().to_string(),
            "--set".into(),
            "target.spacing=1e-6".into(),
        ],
        vec![
            "check".to_string(),
            case("smoke.toml").display().to_string(),
            "--set".into(),
            "projectile.element_size=1e-7".into(),
        ],
    ] {
        let out = Command::new(bin).args(&args).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    let out = Command::new(bin)
        .args(["check", &case("smoke.toml").display().to_string()])
        .output()
        .unwrap();
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("projectile.velocity") && text.contains("particles"),
        "{text}"
    );
    assert!(!text.contains("which would stop the run"), "{text}");
    // A concrete whose elastic modulus is 10⁷ times K₁ needs 1.6·10⁶ steps of 1.2e-11 s; the
    // estimate says so, and that the run will stop at max_steps first.
    let out = Command::new(bin)
        .args(["check", &case("smoke.toml").display().to_string()])
        .args(["--set", "target.concrete.mu_crush=1e-12"])
        .args(["--set", "run.max_steps=100000"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("more than run.max_steps = 100000, which would stop the run"),
        "{text}"
    );
    assert!(
        !text.contains("under which a run takes its step as collapsed"),
        "{text}"
    );
    // A Courant number of 1e-9 asks for steps of 1e-16 s: the estimate says the run would
    // take them as collapsed.
    let out = Command::new(bin)
        .args(["check", &case("smoke.toml").display().to_string()])
        .args(["--set", "run.cfl=1e-9"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("; not above 1e-13 s, under which a run takes its step as collapsed"),
        "{text}"
    );
    // `check` on a shipped case with `sets`: its report.
    let report = |case_name: &str, sets: &[&str]| {
        let mut cmd = Command::new(bin);
        cmd.args(["check", &case(case_name).display().to_string()]);
        for s in sets {
            cmd.args(["--set", s]);
        }
        let out = cmd.output().unwrap();
        assert!(out.status.success());
        String::from_utf8_lossy(&out.stdout).to_string()
    };
    // The lattice column nearest the shank: at 3 mm spacing the one at 13.5 mm grazes the
    // 13.45 mm shank, which a rigid projectile's run is warned about; at 3.1 mm it is 0.5 mm off.
    let column_line = |sets: &[&str]| {
        let text = report("forrestal1994-277.toml", sets);
        text.lines()
            .find(|l| l.starts_with("# lattice: "))
            .unwrap_or_else(|| panic!("no lattice line: {text}"))
            .to_string()
    };
    // A mesh finer than ¾ of the lattice's spacing is warned about; the shipped ¾ is not.
    assert!(!report("forrestal1994-642.toml", &[]).contains("# contact: "));
    let fine = report(
        "forrestal1994-642.toml",
        &["projectile.element_size=0.0015"],
    );
    assert!(
        fine.contains("# contact: elements of 1.50 mm against particles 4.00 mm apart"),
        "{fine}"
    );
    let grazing = column_line(&["contact.lambda=0", "target.spacing=0.003"]);
    assert!(
        grazing.contains("r = 13.500 mm, 0.050 mm outside") && grazing.contains("amplifies"),
        "{grazing}"
    );
    for sets in [
        &["contact.lambda=0", "target.spacing=0.0031"][..],
        &["target.spacing=0.003"][..],
    ] {
        let line = column_line(sets);
        assert!(!line.contains("amplifies"), "{sets:?}: {line}");
    }
    // A Taylor bar has no target and so no SPH step; its step does not depend on where its
    // wall is (the mesh is built at the model's origin, as the run builds it).
    let step_line = |wall_z: &str| {
        let text = report("taylor-4340-208.toml", &[&format!("wall.z={wall_z}")]);
        assert!(
            text.contains(&format!("# target: none, a rigid wall at z = {wall_z} m")),
            "{text}"
        );
        let line = text.lines().find(|l| l.contains("stable step")).unwrap();
        assert!(!line.contains("SPH"), "{line}");
        line.to_string()
    };
    assert_eq!(step_line("0"), step_line("100"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// A reader that goes away (`penetrate run … | head -1`) does not make `run` panic: with its
/// stdout closed before it prints, the run still completes, exits 0 and writes its summary.
#[test]
fn run_survives_a_closed_stdout() {
    let dir = scratch("closed-stdout");
    let mut child = cpu_run("smoke.toml", &dir)
        .arg("--no-vtk")
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Closed before the run has loaded its scene, let alone printed its result.
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{err}");
    assert!(out.status.success(), "{err}");
    assert!(dir.join("summary.json").is_file());
    let _ = std::fs::remove_dir_all(&dir);
}

/// The smoke scene on the CPU after five steps: a run under way, for the failure tests.
fn smoke_after_five_steps() -> Simulation {
    let scene = scene::load(&case("smoke.toml"), &[]).unwrap();
    let mut sim = Simulation::new(&scene).unwrap();
    for _ in 0..5 {
        sim.step().unwrap();
    }
    sim
}

/// A non-finite value halts the step with the entity, its position, the step and the time named.
#[test]
fn instability_is_reported_with_what_where_and_when() {
    let scene = scene::load(&case("smoke.toml"), &[]).unwrap();
    let mut sim = smoke_after_five_steps();
    sim.model_mut().unwrap().particles.az[7] = f32::NAN;
    let err = sim.step().unwrap_err();
    // The error is typed: which entity, what, where and when, as data.
    let RunError::Unstable(Instability {
        what:
            Unstable::Entity {
                entity,
                reason,
                r,
                z,
            },
        when,
    }) = &err
    else {
        panic!("not an unstable entity: {err:?}");
    };
    assert_eq!(*entity, Entity::Particle(7));
    assert!(reason.starts_with("non-finite"), "{reason}");
    assert_eq!(when.step, 5);
    // Its z went non-finite with its acceleration; its r is where it was.
    assert!(
        when.time > 0.0 && r.is_finite() && !z.is_finite(),
        "{err:?}"
    );
    // And printed as the run's status says it.
    let err = err.to_string();
    assert!(err.starts_with("unstable: particle 7 non-finite"), "{err}");
    assert!(err.contains("step 5") && err.contains(" t "), "{err}");

    let mut sim = Simulation::new(&scene).unwrap();
    // Fold one element inside out: the stress pass must refuse it.
    let m = sim.model_mut().unwrap();
    let el = m.projectile.elements.nodes[3];
    let (a, b) = (el[0] as usize, el[1] as usize);
    let n = &mut m.projectile.nodes;
    (n.r[a], n.r[b], n.z[a], n.z[b]) = (n.r[b], n.r[a], n.z[b], n.z[a]);
    // The swap folds element 3 and may fold others that share its nodes (at the nose's tip
    // the kite's first triangle); the pass names the first it meets.
    let (n, elements) = (&m.projectile.nodes, &m.projectile.elements.nodes);
    let folded: Vec<usize> = (0..elements.len())
        .filter(|&e| {
            let el = elements[e].map(|k| k as usize);
            let twice_area: f32 = (0..3)
                .map(|k| n.r[el[k]] * (n.z[el[(k + 1) % 3]] - n.z[el[(k + 2) % 3]]))
                .sum();
            twice_area <= 0.0
        })
        .collect();
    assert!(folded.contains(&3), "{folded:?}");
    let err = sim.step().unwrap_err();
    assert!(
        matches!(
            &err,
            RunError::Unstable(Instability {
                what: Unstable::Entity {
                    entity: Entity::Element(e),
                    reason: "inverted",
                    ..
                },
                ..
            }) if *e == folded[0]
        ),
        "{err:?}, folded {folded:?}"
    );
    assert!(
        err.to_string()
            .contains(&format!("element {} inverted", folded[0])),
        "{err}"
    );
}

/// A projectile far wider than it is long (a disc 1 m across and 20 mm thick, struck onto the
/// wall) runs: the bound beyond which a node counts as escaped takes in its radius, not only
/// its length (it stopped at step 0 with its rim "escaped" when it did not).
#[test]
fn a_disc_is_not_taken_for_an_escape() {
    let dir = scratch("disc");
    let out = cpu_run("taylor-copper-190.toml", &dir)
        .arg("--no-vtk")
        .args(["--set", "projectile.diameter=1.0"])
        .args(["--set", "projectile.length=0.02"])
        .args(["--set", "projectile.element_size=0.005"])
        .args(["--set", "run.end_time=2e-7"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A step that collapses stops the run naming where: the element or particle whose own stable
/// step is the least, with its position and state.
#[test]
fn a_collapsed_step_names_where() {
    let mut sim = smoke_after_five_steps();
    // A Courant number of 1e-7 makes every step about 1e-14 s: below what the run accepts.
    sim.model_mut().unwrap().scene.run.cfl = 1.0e-7;
    let err = sim.step().unwrap_err().to_string();
    assert!(
        err.contains("time step collapsed") && err.contains("step 6"),
        "{err}"
    );
    assert!(err.contains("× run.cfl = 1e-7;"), "{err}");
    common::assert_smallest_step_named(sim.model().unwrap(), &err);
}

/// The CPU path gives the same bits whatever the thread count: every parallel loop writes only
/// its own slots and the only reductions (the time step) are minima.
#[test]
fn same_bits_on_one_and_two_threads() {
    let scene = scene::load(&case("smoke.toml"), &[]).unwrap();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut sim = Simulation::new(&scene).unwrap();
            for _ in 0..300 {
                sim.step().unwrap();
            }
            let sim = sim.into_model().unwrap();
            let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<u32>>();
            (
                bits(&sim.particles.z),
                bits(&sim.particles.vz),
                bits(&sim.projectile.nodes.z),
                bits(&sim.projectile.elements.s_zz),
            )
        })
    };
    assert!(run(1) == run(2), "results differ between 1 and 2 threads");
}

/// `sweep --batch` on the CPU makes its runs at once, sharing the thread pool, and every run's
/// history.csv and frames are its solo run's to the byte. The runs end at different steps (the
/// swept key is the end time), so the pool is shared by three runs, then two, then one.
#[test]
fn a_cpu_batch_changes_no_run() {
    let sweep = |batch: &str| {
        let out = common::scratch("cpu-batch", batch);
        let o = Command::new(env!("CARGO_BIN_EXE_penetrate"))
            .args([
                "sweep",
                "cases/smoke.toml",
                "--vary",
                "run.end_time=2e-5:5e-5:1e-5",
            ])
            .args(["--set", "projectile.velocity=600", "--backend", "cpu"])
            .args(["--batch", batch, "--out", out.to_str().unwrap()])
            .env("RAYON_NUM_THREADS", "4")
            .current_dir(common::root())
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", common::stderr(&o));
        if batch == "3" {
            let said = common::stderr(&o);
            assert!(said.contains("3 at a time, sharing 4 threads"), "{said}");
        }
        out
    };
    let (solo, batched) = (sweep("1"), sweep("3"));
    let mut compared = 0;
    for member in std::fs::read_dir(&solo).unwrap().map(|e| e.unwrap().path()) {
        if !member.is_dir() {
            continue;
        }
        let name = member.file_name().unwrap();
        for file in std::fs::read_dir(&member)
            .unwrap()
            .map(|e| e.unwrap().file_name())
        {
            if file == "summary.json" {
                continue;
            }
            let got = std::fs::read(batched.join(name).join(&file)).unwrap();
            assert!(
                got == std::fs::read(member.join(&file)).unwrap(),
                "{name:?}/{file:?} differs from the solo run's"
            );
            compared += 1;
        }
        let depth = |dir: &Path| {
            let text = std::fs::read_to_string(dir.join(name).join("summary.json")).unwrap();
            let summary: serde_json::Value = serde_json::from_str(&text).unwrap();
            (summary["depth_m"].as_f64(), summary["steps"].as_u64())
        };
        assert_eq!(depth(&solo), depth(&batched), "{name:?}");
    }
    assert!(compared >= 4 * 3, "{compared} files compared");
    let _ = std::fs::remove_dir_all(&solo);
    let _ = std::fs::remove_dir_all(&batched);
}

/// Every scene of the stability suite loads: the scene file's bounds on real materials must not
/// refuse the suite's own scenes (a steel 10 or 100 times stiffer is scaled on the loaded
/// scene), and the stiff ones' elastic wave speed is √10 and 10 times the base's, so their
/// step is that much shorter.
#[test]
fn every_stability_scene_loads() {
    use penetrate::studies::stability;
    let base_path = case("stability.toml");
    let base = scene::load(&base_path, &[]).unwrap();
    let cases = stability::cases(&base, true);
    assert!(cases.iter().filter(|c| c.moduli_factor.is_some()).count() == 2);
    for c in &cases {
        let s = stability::scene_of(&base_path, c).unwrap_or_else(|e| panic!("{}: {e}", c.name));
        let f = c.moduli_factor.unwrap_or(1.0);
        let speed = |s: &scene::Scene| s.projectile.material.wave_speed();
        let ratio = speed(&s) / speed(&base);
        if c.name != "nu0499" {
            assert!(
                (ratio / f.sqrt() - 1.0).abs() < 1e-6,
                "{}: wave speed ×{ratio} for moduli ×{f}",
                c.name
            );
        }
        let (t, t0) = (s.target.as_ref().unwrap(), base.target.as_ref().unwrap());
        assert!(
            (t.concrete.shear_modulus as f64 / t0.concrete.shear_modulus as f64 / f - 1.0).abs()
                < 1e-6,
            "{}: concrete G",
            c.name
        );
    }
}

/// `check-stability` on two of its hardest scenes, CPU path: each completes with the energy
/// account closed to 1 % of the impact energy, no slave left inside the projectile and no
/// non-finite value, and the table names them. The 2500 m/s shot, and the target no wider
/// than the shank, which made energy and stopped at 84 µs until the hoop-weight fix
/// (docs/notes/2026-11-stability-suite.md). The suite's λ = 1 row (each slave's whole momentum
/// change on two nodes) is checked below at half the step: its account's error grows with the
/// step (docs/limitations.md, "Numerics and model").
#[test]
#[ignore = "full tier: long run (bash scripts/test)"]
fn stability_suite_runs_and_closes_the_energy() {
    let bin = env!("CARGO_BIN_EXE_penetrate");
    let dir = scratch("stability");
    let out = std::process::Command::new(bin)
        .args(["check-stability", "--backend", "cpu", "--quick", "--only"])
        .arg("v2500,grazing")
        .arg("--case")
        .arg(case("stability.toml"))
        .arg("--out")
        .arg(&dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let table = std::fs::read_to_string(dir.join("stability.md")).unwrap();
    for name in ["v2500", "grazing"] {
        assert!(table.contains(&format!("| {name} | cpu |")), "{table}");
        assert_closed(name, &dir.join(format!("{name}-cpu")));
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The run in `dir` completed with its energy account closed to 1 % of the impact energy, no
/// slave left inside the projectile and no non-finite value.
fn assert_closed(name: &str, dir: &std::path::Path) {
    let text = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    let s: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(s["status"], "completed", "{name}: {text}");
    let energy = s["energy_error"].as_f64().unwrap();
    assert!(energy.abs() < 0.01, "{name}: energy error {energy}");
    assert_eq!(s["slaves_inside"], 0, "{name}");
    assert_eq!(s["nonfinite_values"], 0, "{name}");
    assert!(s["particles_at_density_floor"].is_u64(), "{name}: {text}");
}

/// λ = 1 on the stability scene: the account of a correction that puts each slave's whole
/// momentum change on two nodes closes to 1 % at CFL 0.25 (0.62 %). At the shipped CFL 0.5 it
/// ends 1.26 % over (0.70 % at CFL 0.28; 0.82 % with the nose meshed as one block, whose
/// slivers held the step near CFL 0.28's): the error is the step's, first order.
#[test]
#[ignore = "full tier: long run (bash scripts/test)"]
fn lambda_one_closes_its_energy_at_half_the_step() {
    let dir = scratch("lambda1");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_penetrate"))
        .arg("run")
        .arg(case("stability.toml"))
        .args(["--backend", "cpu", "--quiet", "--no-vtk", "--out"])
        .arg(&dir)
        .args(["--set", "contact.lambda=1", "--set", "run.cfl=0.25"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_closed("lambda1", &dir);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A suite row that does not pass makes `check-stability` exit 1 and name it, with the table
/// written: here a Taylor bar as the base, whose `grazing` scene (a narrower target) the
/// scene check refuses. Before, the table had no folder to go into when no run had made one
/// (exit 3, a bare "No such file or directory"), and a failing row still exited 0.
#[test]
fn a_failing_stability_row_fails_the_command_and_output_errors_exit_3() {
    let bin = env!("CARGO_BIN_EXE_penetrate");
    let dir = scratch("stability-refused");
    let out = std::process::Command::new(bin)
        .args(["check-stability", "--backend", "cpu", "--quick", "--only"])
        .arg("grazing")
        .arg("--case")
        .arg(case("taylor-4340-208.toml"))
        .arg("--out")
        .arg(&dir)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("1 of 1 runs did not pass (grazing on cpu)"),
        "{stderr}"
    );
    let table = std::fs::read_to_string(dir.join("stability.md")).unwrap();
    assert!(
        table.contains("| grazing | cpu |") && table.contains("refused"),
        "{table}"
    );
    // A run folder that cannot be made is an output error, exit 3 as for `run` (it was 2).
    std::fs::write(dir.join("v100-cpu"), "a file where the run's folder goes").unwrap();
    let out = std::process::Command::new(bin)
        .args([
            "check-stability",
            "--backend",
            "cpu",
            "--quick",
            "--only",
            "v100",
        ])
        .arg("--case")
        .arg(case("stability.toml"))
        .arg("--out")
        .arg(&dir)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(3), "{stderr}");
    assert!(stderr.contains("v100-cpu"), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The smoke scene after 20 steps, its energy guard passed, and its impact energy (J).
fn smoke_after_20_steps() -> (Model, f64) {
    let scene = scene::load(&case("smoke.toml"), &[]).unwrap();
    let mut sim = Simulation::new(&scene).unwrap();
    for _ in 0..20 {
        sim.step().unwrap();
    }
    let sim = sim.into_model().unwrap();
    assert!(sim.check_energy().is_ok(), "{}", sim.energy_error());
    let e0 = 0.5 * (scene.projectile.velocity as f64).powi(2) * sim.projectile.total_mass;
    (sim, e0)
}

/// The energy guard: a run whose energy account comes apart is stopped as unstable, with the
/// step, the time and the fastest particle named; an account that closes passes, and one that
/// is not a number fails.
#[test]
fn a_run_whose_energy_account_comes_apart_is_unstable() {
    let (mut sim, e0) = smoke_after_20_steps();
    // One particle kicked to a speed that carries about a tenth of the impact energy.
    let p = &mut sim.particles;
    let i = p.len() / 2;
    p.vz[i] = (2.0 * 0.1 * e0 / p.mass[i] as f64).sqrt() as f32;
    let err = sim.check_energy().unwrap_err().to_string();
    assert!(err.contains("energy balance lost"), "{err}");
    assert!(err.contains(&format!("particle {i} ")), "{err}");
    assert!(err.contains("step 20"), "{err}");
    sim.particles.vz[i] = f32::NAN;
    assert!(sim.check_energy().is_err());
}

/// The other guard: a target whose forces have made energy, booked by the account as a
/// negative internal energy so that the balance still closes, is stopped as unstable.
#[test]
fn a_target_that_makes_energy_is_unstable() {
    let (mut sim, e0) = smoke_after_20_steps();
    // One particle given a tenth of the impact energy as speed, its internal energy lowered by
    // as much: the account still closes, but the target has returned more than was done on it.
    let before = sim.energy_error();
    let p = &mut sim.particles;
    let i = p.len() / 2;
    let kinetic = |p: &penetrate::state::Particles| {
        0.5 * p.mass[i] as f64 * ((p.vr[i] as f64).powi(2) + (p.vz[i] as f64).powi(2))
    };
    let k0 = kinetic(p);
    p.vz[i] = (2.0 * 0.1 * e0 / p.mass[i] as f64).sqrt() as f32;
    let gained = kinetic(p) - k0;
    p.energy[i] -= (gained / p.mass[i] as f64) as f32;
    assert!(
        (sim.energy_error() - before).abs() < 1.0e-3,
        "{}",
        sim.energy_error()
    );
    let err = sim.check_energy().unwrap_err().to_string();
    assert!(err.contains("energy made in the target"), "{err}");
    assert!(err.contains(&format!("particle {i} ")), "{err}");
}

/// `bench` refuses a step count or a size it cannot time with a message, never a panic (a CPU
/// row's step count used to be clamped into 3..=steps, which panicked below 3), and times a
/// single step at the smallest size the case allows.
#[test]
fn bench_refuses_what_it_cannot_time() {
    use penetrate::scene::Backend;
    use penetrate::studies::bench;
    let case = case("forrestal1994-277.toml");
    let run =
        |sizes: &[usize], steps| bench::run(&case, sizes, &[Backend::Cpu], None, steps, |_| {});
    let err = run(&[2000], 0).unwrap_err();
    assert!(err.contains("--steps 0"), "{err}");
    // 0.4 m × 0.76 m at a spacing of at most the 13.45 mm radius: 1681 particles or more.
    let err = run(&[1680], 10).unwrap_err();
    assert!(
        err.contains("bench size 1680") && err.contains("1681"),
        "{err}"
    );
    let rows = run(&[1681], 1).unwrap();
    assert_eq!(rows.len(), 1);
    let row = &rows[0];
    assert!(row.refused.is_none(), "{:?}", row.refused);
    assert_eq!(row.steps, 1);
    assert!(row.ms_per_step > 0.0 && row.particles > 1000);
    // One timed step from five at rest builds no lists; the cost of one that does is timed.
    assert_eq!(row.list_builds, Some(0));
    assert!(row.build_ms.is_some_and(f64::is_finite));
}

/// Ctrl-C (SIGINT) ends a run at the end of its step with what a finished run writes: the
/// summary says `interrupted`, the history keeps its rows, and the exit code is 130.
#[cfg(unix)]
#[test]
fn an_interrupted_run_keeps_its_outputs() {
    let dir = scratch("interrupted");
    // The smoke scene for 0.2 s of simulated time: ~4·10⁶ steps, far longer than the wait below.
    let child = cpu_run("smoke.toml", &dir)
        .arg("--no-vtk")
        .args([
            "--set",
            "run.end_time=0.2",
            "--set",
            "run.stop_at_rest=false",
        ])
        .args(["--set", "run.history_interval=1e-6"])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Wait for a few history rows, so the run is under way.
    let history = dir.join("history.csv");
    let started = std::time::Instant::now();
    let rows = || csv::Reader::from_path(&history).map_or(0, |mut r| r.records().count());
    while rows() < 2 {
        assert!(started.elapsed().as_secs() < 120, "no history rows");
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    // SAFETY: a signal to our own child process.
    assert_eq!(unsafe { libc::kill(child.id() as i32, libc::SIGINT) }, 0);
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{err}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let status = summary["status"].as_str().unwrap();
    assert!(status.starts_with("interrupted"), "{status}");
    assert!(summary["time_s"].as_f64().unwrap() < 0.2);
    assert!(common::csv_file(&history).1.len() >= 2);
    let _ = std::fs::remove_dir_all(&dir);
}

/// An output folder that cannot be made (here a file stands in its way) is named, with exit
/// code 3, before anything runs.
#[test]
fn an_output_folder_that_cannot_be_made_is_named() {
    let file = scratch("out-is-a-file");
    std::fs::write(&file, "not a folder").unwrap();
    let out = cpu_run("smoke.toml", &file)
        .arg("--no-vtk")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(3), "{err}");
    assert!(
        err.contains("cannot create the output folder") && err.contains("out-is-a-file"),
        "{err}"
    );
    let _ = std::fs::remove_file(&file);
}

/// A scene that cannot take its first step (a concrete whose shear modulus is overridden to
/// 1e30 Pa: its particles' stable step is 7e-17 s, below the 1e-13 s taken as a collapse)
/// stops as any unstable run does: exit code 1, and `summary.json` and the history's row at
/// rest written beside `scene.toml`, the status naming what and where.
#[test]
fn a_run_that_cannot_take_its_first_step_keeps_its_outputs() {
    let dir = scratch("first-step");
    let out = cpu_run("smoke.toml", &dir)
        .arg("--no-vtk")
        .args(["--set", "target.concrete.shear_modulus=1e30"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let status = summary["status"].as_str().unwrap();
    assert!(
        status.contains("time step collapsed") && status.contains("before the first step"),
        "{status}"
    );
    assert!(
        status.contains("particle") && status.contains("(r "),
        "{status}"
    );
    assert_eq!(summary["steps"].as_u64(), Some(0));
    let (_, rows) = common::csv_file(&dir.join("history.csv"));
    assert_eq!(rows.len(), 1, "{rows:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A Taylor bar's run does not depend on where its wall is: the model is built with the wall at
/// z = 0 and `wall.z` added back in what it writes. f32 positions near z = 100 m are 7.6 µm
/// apart, more than the bar's motion in a step, and the bar used not to move at all.
#[test]
fn a_taylor_run_does_not_depend_on_where_the_wall_is() {
    let run = |wall_z: &str| {
        let dir = scratch(&format!("wall-{wall_z}"));
        let out = cpu_run("taylor-4340-208.toml", &dir)
            .args(["--set", &format!("wall.z={wall_z}")])
            .args([
                "--set",
                "run.end_time=2e-6",
                "--set",
                "run.history_interval=2e-7",
            ])
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let history = std::fs::read_to_string(dir.join("history.csv")).unwrap();
        let frame = penetrate::output::vtk::read_vtu(&dir.join("projectile_00001.vtu")).unwrap();
        let _ = std::fs::remove_dir_all(&dir);
        (history, frame.z[0] as f64)
    };
    let (at_zero, z0) = run("0");
    let (far, z100) = run("100");
    assert!(at_zero.lines().count() > 5);
    assert_eq!(at_zero, far, "the history must not depend on wall.z");
    // The frames are written where the scene put the bar (f32 at 100 m: 7.6e-6 m apart).
    assert!((z100 - 100.0 - z0).abs() < 1e-5, "{z0} {z100}");
}

/// A run into a folder an earlier run wrote clears that run's summary, frames and plots
/// first, so that a shorter run, or one without frames, is not read together with the last
/// one's; other files are left alone.
#[test]
fn a_run_clears_the_frames_an_earlier_run_left() {
    let bin = env!("CARGO_BIN_EXE_penetrate");
    let dir = scratch("rerun");
    let run = |extra: &[&str]| {
        let out = cpu_run("smoke.toml", &dir)
            .args(["--set", "run.end_time=4e-6"])
            .args(extra)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    };
    let frames = || {
        std::fs::read_dir(&dir)
            .unwrap()
            .filter(|e| {
                let name = e.as_ref().unwrap().file_name();
                let name = name.to_str().unwrap();
                name.ends_with(".vtu") || name.ends_with(".pvd")
            })
            .count()
    };
    run(&["--set", "run.output_interval=1e-6"]);
    // At t = 0, every µs and at the end, of the target and of the projectile, and the
    // collection.
    assert!(frames() >= 11, "{}", frames());
    std::fs::write(dir.join("notes.txt"), "mine").unwrap();
    // A picture `penetrate plot` drew of the last run goes with it.
    std::fs::write(dir.join("damage.png"), "stale").unwrap();
    run(&["--no-vtk"]);
    assert_eq!(frames(), 0);
    assert!(!dir.join("damage.png").exists());
    assert!(dir.join("summary.json").is_file() && dir.join("notes.txt").is_file());
    // A run refused before its first step leaves no history or summary of the last one.
    let out = Command::new(bin)
        .args(["run", &case("smoke.toml").display().to_string()])
        .args(["--backend", "gpu", "--adapter", "no-such-adapter", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(!dir.join("summary.json").exists() && !dir.join("history.csv").exists());
    assert!(dir.join("scene.toml").is_file() && dir.join("notes.txt").is_file());
    let _ = std::fs::remove_dir_all(&dir);
}

/// A run whose disk stops taking its outputs (here the file a frame is first written to is
/// /dev/full, which takes nothing: "No space left on device") stops there with exit code 3,
/// naming the file, the step and the time, and leaves whole files: the frames before it, a
/// collection naming only frames that exist, the history's rows, and `summary.json` with the
/// status.
#[test]
fn a_run_the_disk_refuses_stops_and_keeps_whole_outputs() {
    assert!(
        Path::new("/dev/full").exists(),
        "this test needs /dev/full, a device that is always full"
    );
    let dir = scratch("disk-full");
    std::fs::create_dir_all(&dir).unwrap();
    std::os::unix::fs::symlink("/dev/full", dir.join("projectile_00002.vtu.partial")).unwrap();
    let out = cpu_run("smoke.toml", &dir)
        .args(["--set", "run.end_time=4e-6"])
        .args(["--set", "run.output_interval=1e-6"])
        .args(["--set", "run.history_interval=2e-7"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(3), "{err}");
    assert!(
        err.contains("output failed at step")
            && err.contains("projectile_00002.vtu: No space left on device")
            && err.contains("with summary.json"),
        "{err}"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let status = summary["status"].as_str().unwrap();
    assert!(status.starts_with("output failed at step"), "{status}");
    // Frames are written off the stepping thread: the run learns of the refusal a step or so
    // after it handed the frame over (the status names the frame's step and time).
    let t = summary["time_s"].as_f64().unwrap();
    assert!(t >= 2e-6, "stopped at t = {t}");
    let history = std::fs::read_to_string(dir.join("history.csv")).unwrap();
    assert!(
        history.ends_with('\n') && history.lines().count() > 5,
        "{history}"
    );
    let (header, rows) = common::csv_file(&dir.join("history.csv"));
    let expected = penetrate::output::history::header().unwrap();
    assert_eq!(header, expected.split(',').collect::<Vec<_>>());
    for row in rows {
        assert_eq!(row.len(), header.len(), "{row:?}");
        row.iter()
            .for_each(|v| assert!(v.parse::<f64>().is_ok(), "{row:?}"));
    }
    let pvd = std::fs::read_to_string(dir.join("frames.pvd")).unwrap();
    let listed: Vec<&str> = pvd
        .split("file=\"")
        .skip(1)
        .map(|s| s.split('"').next().unwrap())
        .collect();
    assert!(listed.contains(&"projectile_00001.vtu"), "{pvd}");
    assert!(!listed.contains(&"projectile_00002.vtu"), "{pvd}");
    for file in listed {
        let frame = std::fs::read(dir.join(file)).unwrap();
        assert!(frame.ends_with(b"</VTKFile>\n"), "{file} is not whole");
        penetrate::output::vtk::read_vtu(&dir.join(file)).unwrap();
    }
    let partial = std::fs::read_dir(&dir)
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .file_name()
                .to_string_lossy()
                .ends_with(".partial")
        })
        .count();
    assert_eq!(partial, 0);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The same refusal, as data: which output, its reason, the step and time, and what was kept.
#[test]
fn a_refused_output_is_typed() {
    use penetrate::solver::{Kept, Output, OutputError, OutputFailure, RunOptions};
    let dir = scratch("disk-full-typed");
    std::fs::create_dir_all(&dir).unwrap();
    std::os::unix::fs::symlink("/dev/full", dir.join("projectile_00002.vtu.partial")).unwrap();
    let set = [
        "run.end_time=4e-6".to_string(),
        "run.output_interval=1e-6".to_string(),
        "run.history_interval=2e-7".to_string(),
    ];
    let scene = scene::load(&case("smoke.toml"), &set).unwrap();
    let mut opts = RunOptions::new(dir.clone());
    opts.quiet = true;
    let err = match solver::run(&scene, &opts) {
        Err(RunError::Output(e)) => *e,
        Err(e) => panic!("not an output error: {e:?}"),
        Ok(_) => panic!("the run went through a full disk"),
    };
    let OutputError {
        failure:
            OutputFailure {
                what,
                kind,
                reason,
                when: Some(when),
            },
        kept: Some(Kept {
            status,
            folder,
            summary,
        }),
    } = &err
    else {
        panic!("no step or nothing kept: {err:?}");
    };
    assert_eq!(*what, Output::Frame(2));
    assert_eq!(*kind, std::io::ErrorKind::StorageFull);
    assert!(reason.contains("projectile_00002.vtu"), "{reason}");
    assert!(
        (2e-6..3e-6).contains(&when.time) && when.step > 0,
        "{when:?}"
    );
    assert!(status.starts_with("output failed at step"), "{status}");
    assert_eq!(folder, &dir);
    assert_eq!(summary, &Ok(()));
    let _ = std::fs::remove_dir_all(&dir);
}

/// The first line a run of the smoke scene for 1000 s with `args` says on stderr, or "" when
/// it says nothing within 60 s (a run that cannot fit writes for ever: don't wait for it).
fn first_warning_of_a_long_run(name: &str, args: &[&str]) -> String {
    use std::io::BufRead as _;
    let dir = scratch(name);
    let mut child = cpu_run("smoke.toml", &dir)
        .args([
            "--set",
            "run.end_time=1000",
            "--set",
            "run.stop_at_rest=false",
        ])
        .args(["--set", "run.max_steps=1000000000000"])
        .args(args)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let stderr = child.stderr.take().unwrap();
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let first = std::io::BufReader::new(stderr).lines().next();
        let _ = tx.send(first.and_then(|l| l.ok()).unwrap_or_default());
    });
    let first = rx
        .recv_timeout(std::time::Duration::from_secs(60))
        .unwrap_or_default();
    child.kill().unwrap();
    child.wait().unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    first
}

/// A run whose frames, by `check`'s estimate, need more than the disk has free says so on
/// stderr before it writes them (here a frame every step for 1000 s: petabytes).
#[test]
fn a_run_whose_frames_cannot_fit_is_warned_about() {
    let first = first_warning_of_a_long_run("overfill", &["--set", "run.output_interval=1e-12"]);
    assert!(
        first.starts_with("penetrate: warning: this run may write") && first.contains("MiB free"),
        "{first}"
    );
}

/// So does a run without frames whose history rows cannot fit (a row every step for 1000 s).
#[test]
fn a_run_whose_history_cannot_fit_is_warned_about() {
    let first = first_warning_of_a_long_run(
        "overfill-history",
        &["--no-vtk", "--set", "run.history_interval=1e-12"],
    );
    assert!(
        first.starts_with("penetrate: warning: this run may write")
            && first.contains("history rows")
            && first.contains("MiB free")
            && first.ends_with("raise run.history_interval"),
        "{first}"
    );
}

/// A run that by `check`'s estimate cannot reach its end time within `run.max_steps` says so
/// before it starts, naming the cap and what sets the step; one that can says nothing.
#[test]
fn a_run_that_will_reach_max_steps_is_warned_about() {
    let stderr_of = |max_steps: &str| {
        let dir = scratch(&format!("max-steps-{max_steps}"));
        let out = cpu_run("smoke.toml", &dir)
            .args(["--no-vtk", "--set", &format!("run.max_steps={max_steps}")])
            .output()
            .unwrap();
        let _ = std::fs::remove_dir_all(&dir);
        String::from_utf8(out.stderr).unwrap()
    };
    // The smoke scene takes about 220 steps to its end time.
    let capped = stderr_of("100");
    let first = capped.lines().next().unwrap_or_default();
    assert!(
        first.starts_with("penetrate: warning: this run needs ≈")
            && first.contains("run.max_steps = 100 would stop it")
            && first.contains("the projectile mesh's smallest element"),
        "{capped}"
    );
    let free = stderr_of("1000");
    assert!(!free.contains("warning"), "{free}");
    // `check`'s step line names the height of the element that sets the projectile's step.
    let out = Command::new(env!("CARGO_BIN_EXE_penetrate"))
        .args(["check", &case("smoke.toml").display().to_string()])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    let line = text.lines().find(|l| l.contains("stable step")).unwrap();
    assert!(
        line.contains("its smallest element 1.098e-3 m high"),
        "{line}"
    );
}
