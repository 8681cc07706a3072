//! Helpers shared by the integration tests.

use penetrate::solver::Simulation;

/// `err` names the entity of `sim` whose own stable step is the least, and where it is.
pub fn assert_smallest_step_named(sim: &Simulation, err: &str) {
    let e = &sim.projectile.elements;
    let p = &sim.particles;
    let sph = sim.sph.as_ref().unwrap();
    let element = (0..e.len())
        .min_by(|&a, &b| e.dt[a].total_cmp(&e.dt[b]))
        .unwrap();
    let step = |i| penetrate::cpu::integrate::particle_step(p, sph, i);
    let particle = (0..p.len())
        .min_by(|&a, &b| step(a).total_cmp(&step(b)))
        .unwrap();
    let named = if e.dt[element] <= step(particle) {
        format!("element {element} has the smallest stable step")
    } else {
        format!("particle {particle} has the smallest stable step")
    };
    assert!(
        err.contains(&named) && err.contains(" at (r "),
        "{err}: not {named}"
    );
}
