//! The step on the CPU reference path, and what both backends share of it: the λ correction
//! of the hits and the checks on the next Δt.

use super::{Account, Entity, Instability, Model, Pass, RunError, Stepper, Unstable, When};
use crate::contact::{self, ContactBodies, Hit};
use crate::cpu;
use crate::gpu::step::Sync;
use crate::scene::ContactSpec;
use crate::state::Projectile;

/// The model's z = 0 follows the projectile through a target in steps of this much (m): a power
/// of two, so that a shift moves the positions it keeps small without rounding them.
pub const RECENTRE_STEP: f32 = 0.03125;

/// The CPU reference path: every pass in plain Rust on the host's state, which is therefore
/// never stale.
pub struct CpuStepper;

impl Stepper for CpuStepper {
    fn step(&mut self, model: &mut Model) -> Result<(), RunError> {
        model.step_cpu()
    }

    fn sync(&mut self, _: &mut Model, _: Sync) -> Result<(), RunError> {
        Ok(())
    }

    fn backend(&self) -> &'static str {
        "cpu"
    }

    fn keeps_host_current(&self) -> bool {
        true
    }
}

impl Model {
    /// One explicit step on the CPU: the scene's passes in their order (velocities and
    /// positions, contact, then rates, stresses and forces at the new configuration), then the
    /// next Δt.
    pub(super) fn step_cpu(&mut self) -> Result<(), RunError> {
        let dt = self.dt;
        let mut hits = Vec::new();
        for k in 0..self.passes.len() {
            match self.passes[k] {
                Pass::Integrate => self.integrate(dt)?,
                Pass::ContactDetect => {
                    hits = self.detect();
                    self.last_hits = hits.len();
                }
                Pass::ContactCorrect => {
                    let p = &mut self.particles;
                    correct_contact(
                        &hits,
                        Slaves {
                            r: &mut p.r,
                            z: &mut p.z,
                            vr: &mut p.vr,
                            vz: &mut p.vz,
                            mass: &p.mass,
                        },
                        &mut self.projectile,
                        &self.on_nose,
                        &self.scene.contact,
                        dt,
                        &mut self.account,
                    );
                }
                // The second half, at the configuration the first reached.
                _ => {}
            }
        }
        if let Some(by) = self.recentre_by() {
            self.recentre(by);
        }
        self.forces(dt)?;
        self.time += dt as f64;
        self.step += 1;
        self.account.count_limit(self.fem_limited);
        self.account.min_dt = self.account.min_dt.min(dt as f64);
        self.account.max_dt = self.account.max_dt.max(dt as f64);
        self.dt = self.stable_dt()?;
        Ok(())
    }

    /// Velocities and positions of the particles and the nodes over `dt`, with what the fixed
    /// boundary and the wall exert booked in the account.
    fn integrate(&mut self, dt: f32) -> Result<(), RunError> {
        // The wall images' reaction acts on the nodes over this step: the concrete's push on
        // the projectile through its surface, booked with the contact's.
        for (m, s) in self.walls.sums.iter().enumerate() {
            let impulse = (-s[1] - s[3]) as f64 * dt as f64;
            self.account.contact_impulse += impulse;
            if self.on_nose[m] {
                self.account.nose_impulse += impulse;
            }
        }
        let origin = self.origin;
        let blowup = |b: cpu::integrate::Blowup, when: When| {
            RunError::from(Instability {
                what: Unstable::Entity {
                    entity: Entity::named(b.what, b.index),
                    reason: b.reason,
                    r: b.r as f64,
                    z: b.z as f64 + origin,
                },
                when,
            })
        };
        if let Some(sph) = &self.sph {
            // Impulse the fixed boundary exerts on the rest: minus what its particles would
            // have gained from their neighbours.
            let p = &self.particles;
            self.account.boundary_impulse -= (0..p.len())
                .filter(|&i| p.fixed[i] != 0)
                .map(|i| p.mass[i] as f64 * p.az[i] as f64 * dt as f64)
                .sum::<f64>();
            cpu::integrate::particles(&mut self.particles, sph, dt, self.escape)
                .map_err(|b| blowup(b, self.when()))?;
        }
        let p_before = self.projectile_momentum();
        let lost = cpu::integrate::nodes(&mut self.projectile.nodes, dt, self.wall_z, self.escape)
            .map_err(|b| blowup(b, self.when()))?;
        if self.wall_z.is_some() {
            self.account.wall_dissipated += lost;
            let forces: f64 = self.projectile.nodes.fz.iter().map(|&f| f as f64).sum();
            self.account.boundary_impulse +=
                self.projectile_momentum() - p_before - forces * dt as f64;
        }
        Ok(())
    }

    /// Rates, stresses and forces at the current configuration, advancing the material state by
    /// `dt` (0 at start-up).
    pub(super) fn forces(&mut self, dt: f32) -> Result<(), RunError> {
        let when = self.when();
        let origin = self.origin;
        for pass in self.passes.iter().filter(|p| p.is_force()) {
            let (p, n, sph) = (&mut self.particles, &mut self.projectile, self.sph.as_ref());
            let w = &mut self.walls;
            match (pass, sph) {
                (Pass::Neighbours, Some(sph)) => {
                    cpu::neighbours::run(&mut self.grid, &p.r, &p.z, &sph.kernel)
                }
                (Pass::Walls, Some(sph)) => {
                    let support = sph.kernel.support();
                    cpu::wall::find(
                        &mut w.walls,
                        &p.r,
                        &p.z,
                        &n.nodes,
                        &n.masters,
                        support,
                        w.offset,
                    )
                }
                (Pass::SphRates, Some(sph)) => cpu::sph_rates::run(p, &self.grid, sph, w.found()),
                (Pass::Concrete, Some(sph)) => cpu::concrete::run(p, sph, dt),
                (Pass::SphForces, Some(sph)) => {
                    w.reaction = cpu::sph_forces::run(p, &self.grid, sph, w.found())
                }
                (Pass::FemStress, _) => {
                    cpu::fem_stress::run(&mut n.elements, &n.nodes, &self.fem, dt).map_err(
                        |inv| {
                            RunError::from(Instability {
                                what: Unstable::Entity {
                                    entity: Entity::Element(inv.element),
                                    reason: "inverted",
                                    r: inv.r as f64,
                                    z: inv.z as f64 + origin,
                                },
                                when,
                            })
                        },
                    )?;
                    self.account.plastic_work += n
                        .elements
                        .plastic_work
                        .iter()
                        .map(|&w| w as f64)
                        .sum::<f64>();
                }
                (Pass::FemForces, _) => cpu::fem_forces::run(&mut n.nodes, &n.elements),
                (Pass::WallForces, _) => {
                    w.sums = cpu::wall::segment_sums(&w.walls, &w.reaction, n.masters.len());
                    cpu::wall::react(&mut n.nodes, &n.masters, &w.sums);
                }
                // The target's passes of a scene without one are never in its list.
                _ => {}
            }
        }
        Ok(())
    }

    /// How far to move every position along z, after a step's correction, to bring the
    /// projectile's tip back within `RECENTRE_STEP` of the model's z = 0: None while it is
    /// there, and in a scene without a target's contact (a Taylor bar's wall is the origin).
    /// Why: near z = 0 f32 positions resolve a step's motion finely (docs/physics.md §5).
    pub(super) fn recentre_by(&self) -> Option<f32> {
        if self.wall_z.is_some() || !self.has(Pass::ContactDetect) {
            return None;
        }
        let tip = self
            .projectile
            .nodes
            .z
            .iter()
            .copied()
            .fold(f32::MAX, f32::min);
        let steps = (tip / RECENTRE_STEP).trunc();
        (steps != 0.0 && steps.is_finite()).then_some(-steps * RECENTRE_STEP)
    }

    /// Move every particle and node by `by` along z and the model's origin the other way: the
    /// world's positions stay where they are. The neighbour lists are built again from the
    /// moved positions, as the GPU's are.
    pub(super) fn recentre(&mut self, by: f32) {
        self.grid.invalidate();
        self.particles.z.iter_mut().for_each(|z| *z += by);
        self.projectile.nodes.z.iter_mut().for_each(|z| *z += by);
        self.origin -= by as f64;
    }

    /// The next Δt, noting in `fem_limited` whether the elements set it.
    pub(super) fn stable_dt(&mut self) -> Result<f32, RunError> {
        let (sph, fem) = self.least_steps();
        let dt = sph.min(fem) * self.scene.run.cfl as f32;
        self.check_dt(dt)?;
        Ok(dt)
    }

    /// The particles' and the elements' least stable steps (f32::MAX for a side the scene does
    /// not have), noting in `fem_limited` whether the elements' sets Δt: no larger than the
    /// particles', as shaders/integrate.wgsl `step_dt` decides it.
    pub(super) fn least_steps(&mut self) -> (f32, f32) {
        let sph = match &self.sph {
            Some(sph) => cpu::timestep::particle_dt(&self.particles, sph),
            None => f32::MAX,
        };
        let fem = if self.has(Pass::FemStress) {
            cpu::timestep::element_dt(&self.projectile.elements)
        } else {
            f32::MAX
        };
        self.fem_limited = fem <= sph && fem != f32::MAX;
        (sph, fem)
    }

    /// The next step must be positive, finite and bounded: it collapses when the mesh or the
    /// lattice does, and nothing bounds it when every element has failed and opened
    /// (`cpu::fem_stress::OPEN_RELATIVE_VOLUME`) and there is no target, or when the
    /// projectile's waves are absurdly slow (a bar at rest with E = 1e-9 Pa).
    pub(super) fn check_dt(&self, dt: f32) -> Result<(), RunError> {
        if collapsed(dt) {
            return Err(RunError::from(Instability {
                what: Unstable::StepCollapsed {
                    dt,
                    cfl: self.scene.run.cfl,
                    site: self.smallest_step_site(),
                },
                when: self.when(),
            }));
        }
        if dt > 1.0 {
            let e = &self.projectile.elements;
            let why = if self.sph.is_none() && e.failed.iter().all(|&f| f != 0) {
                "every element of the projectile has failed and opened, and there is no target"
                    .to_string()
            } else {
                // Waves that slow: the site says which element, and its state.
                self.smallest_step_site()
            };
            return Err(RunError::from(Instability {
                what: Unstable::StepUnbounded { dt, why },
                when: self.when(),
            }));
        }
        Ok(())
    }

    pub(super) fn detect(&self) -> Vec<Hit> {
        cpu::contact_detect::run(
            &self.slaves,
            &self.particles,
            &self.projectile.nodes,
            &self.projectile.masters,
        )
    }
}

/// The slaves' kinematics the λ correction moves: the particles' own arrays on the CPU path,
/// the hits' slaves read back from the GPU on the GPU path (a hit's `slave` indexes them).
pub(super) struct Slaves<'a> {
    pub(super) r: &'a mut [f32],
    pub(super) z: &'a mut [f32],
    pub(super) vr: &'a mut [f32],
    pub(super) vz: &'a mut [f32],
    pub(super) mass: &'a [f32],
}

/// The smallest step a run goes on with (s): below it the run has collapsed.
pub const MIN_STEP: f32 = 1.0e-13;

/// A step too small to go on with (or not a number): the run has collapsed.
pub(super) fn collapsed(dt: f32) -> bool {
    !(dt.is_finite() && dt > MIN_STEP)
}

/// The λ correction of `hits` (physics.md §4), with `law`'s λ and friction, on `slaves` and the
/// projectile's nodes; its dissipation and deepest penetration are booked in `account`. Returns
/// the global shift it added to every node's v_z (`contact::correct`).
pub(super) fn correct_contact(
    hits: &[Hit],
    slaves: Slaves<'_>,
    projectile: &mut Projectile,
    on_nose: &[bool],
    law: &ContactSpec,
    dt: f32,
    account: &mut Account,
) -> f32 {
    let Projectile {
        nodes: n,
        masters,
        total_mass,
        ..
    } = projectile;
    let mut bodies = ContactBodies {
        slave_r: slaves.r,
        slave_z: slaves.z,
        slave_vr: slaves.vr,
        slave_vz: slaves.vz,
        slave_mass: slaves.mass,
        node_r: &mut n.r,
        node_z: &mut n.z,
        node_vr: &mut n.vr,
        node_vz: &mut n.vz,
        node_mass: &n.mass,
        node_on_axis: &n.on_axis,
        dt,
    };
    let stats = contact::correct(
        hits,
        masters,
        on_nose,
        &mut account.segment_impulse,
        &mut bodies,
        law.lambda as f32,
        law.friction as f32,
        *total_mass,
    );
    account.contact_dissipated += stats.dissipated;
    account.contact_impulse += stats.impulse_z;
    account.nose_impulse += stats.nose_impulse_z;
    account.max_penetration = account.max_penetration.max(stats.max_penetration);
    stats.global_shift
}
