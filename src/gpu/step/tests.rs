use super::{profiled_slot, PROFILED};
use crate::gpu::neighbours::NBR_MAX;
use crate::pass::{self, Pass};

/// Every pass the GPU records has a profiler slot, in the order the pass list runs them:
/// the second half before the time step's, then the first half (the next step's).
#[test]
fn every_recorded_pass_has_its_profiler_slot_in_order() {
    let all = pass::for_scene(true, true);
    let slots: Vec<u32> = all
        .iter()
        .filter(|p| p.is_force())
        .map(|p| profiled_slot(p.name()))
        .chain([profiled_slot("timestep")])
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
        // fixes applied again and the lists built again change nothing).
        let build = g.lists_stale();
        super::super::run_once(&g.gpu, |p| {
            let sph = g.sph.as_ref().unwrap();
            if let Some(c) = &sph.contact {
                c.record_apply(p, g.pending_fixes);
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
