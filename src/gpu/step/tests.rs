use super::{profiled_slot, HitBound, Sync, PROFILED};
use crate::gpu::neighbours::NBR_MAX;
use crate::pass::{self, Pass};
use crate::scene::Backend;
use crate::solver::Simulation;

/// The smoke scene at 800 m/s: a contact of several hits within a few hundred steps.
fn fast_smoke() -> Simulation {
    let scene = crate::scene::load(
        std::path::Path::new("cases/smoke.toml"),
        &["projectile.velocity=800".into()],
    )
    .unwrap();
    crate::solver::build(&scene, Backend::Gpu, None).unwrap()
}

/// f32 values as their bits, so that equality is bit-identity.
fn bits(v: &[f32]) -> Vec<u32> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// The bound takes the most hits of a window with margin, rises at once past it, falls at the
/// window's end, and never exceeds the list's capacity.
#[test]
fn hit_bound_follows_the_hits() {
    let mut b = HitBound::new(1000);
    assert_eq!(b.bound, 32);
    b.saw(40);
    assert_eq!(b.bound, 40 + 10 + 32);
    for _ in 1..super::readback::HIT_WINDOW {
        b.saw(5);
    }
    assert_eq!(b.bound, 82, "the window held 40");
    for _ in 0..super::readback::HIT_WINDOW {
        b.saw(5);
    }
    assert_eq!(b.bound, 5 + 1 + 32);
    b.saw(999);
    assert_eq!(b.bound, 1000);
    let mut small = HitBound::new(10);
    assert_eq!(small.bound, 10);
    small.saw(10);
    assert_eq!(small.bound, 10);
}

/// A step with more hits than the read-back's bound reads every hit in a second round trip:
/// a run whose bound is held at one hit ends bit for bit where one with the bound free does.
#[test]
#[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
fn hits_beyond_the_bound_are_all_read() {
    let run = |held: Option<usize>| {
        let mut sim = fast_smoke();
        for _ in 0..300 {
            if let Some(b) = held {
                sim.gpu_step().unwrap().hit_bound.bound = b;
            }
            sim.step().unwrap();
        }
        let t = sim.gpu_step().unwrap().traffic.steps;
        let m = sim.into_model().unwrap();
        let p = &m.particles;
        let n = &m.projectile.nodes;
        let state: Vec<Vec<u32>> = [
            &p.r, &p.z, &p.vr, &p.vz, &p.energy, &n.r, &n.z, &n.vr, &n.vz,
        ]
        .into_iter()
        .map(|v| bits(v))
        .collect();
        (
            state,
            m.account.contact_impulse.to_bits(),
            t.waits - t.calls,
        )
    };
    let (free, free_impulse, _) = run(None);
    let (held, held_impulse, second_reads) = run(Some(1));
    assert!(
        second_reads > 10,
        "{second_reads} steps read past the bound"
    );
    assert!(free_impulse != 0, "the contact acted");
    assert_eq!(free_impulse, held_impulse);
    assert!(free == held, "the states differ");
}

/// The batched reads of a history row and of the whole state give, bit for bit, what reading
/// each buffer alone gives; a history row's particle sums, reduced on the GPU, are the host's
/// f64 sums of the whole state to f32 round-off, its fastest particle the host's, and the
/// slaves' positions it brings the state's.
#[test]
#[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
fn batched_reads_match_reads_one_by_one() {
    let mut sim = fast_smoke();
    for _ in 0..150 {
        sim.step().unwrap();
    }
    let model = sim.model().unwrap();
    let slaves = model.slaves.clone();
    let mut m = (model.particles.clone(), model.projectile.clone());
    // A step pending: the history read finishes it in the same submission.
    sim.step().unwrap();
    let g = sim.gpu_step().unwrap();
    let (mut history_p, mut history_proj) = (m.0.clone(), m.1.clone());
    let totals = g
        .download(&mut history_p, &mut history_proj, Sync::History)
        .unwrap();
    let full = g.download(&mut m.0, &mut m.1, Sync::Full).unwrap();
    assert!(
        full.particles.is_none(),
        "a full read leaves the host's particles current"
    );
    let gpu = &g.gpu;
    let one = |b: &wgpu::Buffer, n: usize| bits(&gpu.read::<f32>(b, n).unwrap());
    let sph = g.sph.as_ref().unwrap();
    let (p, np) = (&sph.particles, m.0.len());
    for (buffer, full) in [
        (&p.r, &m.0.r),
        (&p.z, &m.0.z),
        (&p.vr, &m.0.vr),
        (&p.vz, &m.0.vz),
        (&p.energy, &m.0.energy),
        (&p.rho, &m.0.rho),
        (&p.p, &m.0.p),
        (&p.damage, &m.0.damage),
        (&p.hoop_weight, &m.0.hoop_weight),
        (&p.mass, &m.0.mass),
    ] {
        assert_eq!(one(buffer, np), bits(full));
    }
    let flat = |v: &[[f32; 3]]| bits(bytemuck::cast_slice(v));
    assert_eq!(one(&p.art_stress, 3 * np), flat(&m.0.art_stress));
    assert_eq!(gpu.read::<u32>(&p.fixed, np).unwrap(), m.0.fixed);
    let (n, nn) = (&g.nodes, m.1.nodes.len());
    for (buffer, full, history) in [
        (&n.r, &m.1.nodes.r, &history_proj.nodes.r),
        (&n.vz, &m.1.nodes.vz, &history_proj.nodes.vz),
    ] {
        assert_eq!(one(buffer, nn), bits(full));
        assert_eq!(one(buffer, nn), bits(history));
    }

    let (e, ne) = (&g.elements, m.1.elements.len());
    assert_eq!(one(&e.p, ne), bits(&m.1.elements.p));
    assert_eq!(one(&e.damage, ne), bits(&history_proj.elements.damage));
    assert_eq!(
        one(&e.force, 6 * ne),
        bits(bytemuck::cast_slice(&m.1.elements.force))
    );
    let sum = |b: &wgpu::Buffer, n: usize| {
        gpu.read::<f32>(b, n)
            .unwrap()
            .iter()
            .map(|&x| x as f64)
            .sum::<f64>()
    };
    // A chunk's f32 sum of CHUNK terms is within (CHUNK − 1) ulp of the sum of their
    // magnitudes (each term itself to a few ulp); the host's f64 sums are exact by comparison.
    let bound = (crate::gpu::history::CHUNK + 2) as f64 * f32::EPSILON as f64;
    let near = |gpu: f64, terms: &[f64], what: &str| {
        let host: f64 = terms.iter().sum();
        let magnitude: f64 = terms.iter().map(|t| t.abs()).sum();
        assert!(
            (gpu - host).abs() <= bound * magnitude,
            "{what}: {gpu} reduced on the GPU, {host} on the host"
        );
    };
    assert!(!slaves.is_empty());
    for &s in &slaves {
        let s = s as usize;
        assert_eq!(history_p.r[s].to_bits(), m.0.r[s].to_bits());
        assert_eq!(history_p.z[s].to_bits(), m.0.z[s].to_bits());
    }
    let reduced = totals
        .particles
        .expect("a history row reduces the particles");
    let q = &m.0;
    let terms = |f: &dyn Fn(usize) -> f64| (0..np).map(f).collect::<Vec<f64>>();
    let kinetic =
        terms(&|i| 0.5 * q.mass[i] as f64 * ((q.vr[i] as f64).powi(2) + (q.vz[i] as f64).powi(2)));
    near(reduced.kinetic, &kinetic, "kinetic energy");
    assert!(reduced.kinetic > 0.0);
    let internal = terms(&|i| q.mass[i] as f64 * q.energy[i] as f64);
    near(reduced.internal, &internal, "internal energy");
    let momentum = terms(&|i| q.mass[i] as f64 * q.vz[i] as f64);
    near(reduced.momentum_z, &momentum, "z-momentum");
    let impulse: Vec<f64> = gpu
        .read::<f32>(&g.acc.particle_impulse, np)
        .unwrap()
        .iter()
        .map(|&x| x as f64)
        .collect();
    near(
        totals.boundary_impulse - sum(&g.acc.node_impulse, nn),
        &impulse,
        "the particles' wall impulse",
    );
    let (index, r, z, speed) = reduced.fastest.expect("the particles move");
    let fastest = (0..np).fold((0, 0.0f32), |(k, v), i| {
        let s = q.vr[i].hypot(q.vz[i]);
        if s > v {
            (i, s)
        } else {
            (k, v)
        }
    });
    assert_eq!(index, fastest.0);
    assert!((speed - fastest.1).abs() <= 1e-6 * fastest.1);
    assert_eq!(
        (r.to_bits(), z.to_bits()),
        (q.r[index].to_bits(), q.z[index].to_bits())
    );
    assert_eq!(
        totals.plastic_work.to_bits(),
        sum(&g.plastic_total, ne).to_bits()
    );
    // The Δt the reads report is, to the bit, the one the next step integrates with.
    let next = g.advance().unwrap();
    assert_eq!(totals.next_dt.to_bits(), next.dt.to_bits());
    // And the nodal forces both reads made of the element forces are, to the bit, the ones
    // that integration gathered.
    assert!(
        m.1.nodes.fz.iter().any(|&f| f != 0.0),
        "the projectile is loaded"
    );
    for (buffer, full, history) in [
        (&g.nodes.fr, &m.1.nodes.fr, &history_proj.nodes.fr),
        (&g.nodes.fz, &m.1.nodes.fz, &history_proj.nodes.fz),
    ] {
        let gathered = bits(&g.gpu.read::<f32>(buffer, nn).unwrap());
        assert_eq!(gathered, bits(full));
        assert_eq!(gathered, bits(history));
    }
}

/// Every pass the GPU records has a profiler slot, in the order the pass list runs them:
/// the second half, then the first half (the next step's).
#[test]
fn every_recorded_pass_has_its_profiler_slot_in_order() {
    let all = pass::for_scene(true, true, true);
    let slots: Vec<u32> = all
        .iter()
        .filter(|p| p.is_force())
        .map(|p| profiled_slot(p.name()))
        .chain(
            all.iter()
                .filter(|p| !p.is_force() && **p != Pass::ContactCorrect)
                .map(|p| profiled_slot(p.name())),
        )
        .collect();
    assert!(
        slots.iter().all(|&s| s < PROFILED.len() as u32 + 1),
        "{slots:?}"
    );
    assert!(slots.windows(2).all(|w| w[0] < w[1]), "{slots:?}");
    assert!(all.contains(&Pass::FemForces));
}

/// Over a coupled run with the lists' skin, every pair within the support at the moment
/// the gathers run is in the lists (or the list overflowed, and the gathers walk the grid).
#[test]
#[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
fn stale_lists_hold_every_neighbour() {
    let scene = crate::scene::load(
        std::path::Path::new("cases/smoke.toml"),
        &["projectile.velocity=800".into()],
    )
    .unwrap();
    let mut sim = crate::solver::build(&scene, crate::scene::Backend::Gpu, None).unwrap();
    let support = sim.model().unwrap().sph.unwrap().kernel.support();
    let mut checked = 0;
    for step in 0..400 {
        sim.step().unwrap();
        let g = sim.gpu_step().unwrap();
        // The next gathers' lists and positions: what the next step records first (its
        // slaves' fixes applied again and the lists built again change nothing).
        let build = g.lists_stale();
        super::super::run_once(&g.gpu, |p| {
            let sph = g.sph.as_ref().unwrap();
            if let Some(c) = &sph.contact {
                // The slaves only: the lists read no node, and the nodes' shift, unlike the
                // slaves' values, would not bear being applied twice.
                c.record_apply(p, g.pending_fixes, false);
            }
            sph.neighbours.record(p, build);
        })
        .unwrap();
        let sph = g.sph.as_ref().unwrap();
        let n = sph.particles.len;
        let kin: Vec<[f32; 4]> = g.gpu.read(&sph.grid.kin, n).unwrap();
        let nbr: Vec<u32> = g.gpu.read(&sph.grid.nbr, NBR_MAX * n).unwrap();
        let count: Vec<u32> = g.gpu.read(&sph.grid.nbr_count, n).unwrap();
        for i in 0..n {
            if count[i] as usize > NBR_MAX {
                continue;
            }
            let list: Vec<u32> = (0..count[i] as usize).map(|k| nbr[k * n + i]).collect();
            for j in 0..n {
                for mirror in [false, true] {
                    let dr = if mirror {
                        kin[i][0] + kin[j][0]
                    } else {
                        kin[i][0] - kin[j][0]
                    };
                    let dz = kin[i][1] - kin[j][1];
                    if (mirror || i != j) && dr * dr + dz * dz < support * support {
                        let e = j as u32 | if mirror { 0x8000_0000 } else { 0 };
                        assert!(
                            list.contains(&e),
                            "step {step}: particle {i} misses {j} (mirror {mirror}), built {}",
                            g.builds
                        );
                        checked += 1;
                    }
                }
            }
        }
        g.built(build);
    }
    eprintln!("{checked} pairs checked");
}
